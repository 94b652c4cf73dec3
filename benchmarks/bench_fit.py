"""Benchmark: global (epsilon, beta) fit of RICSAC 9 against a single local minimize.

Prints the median wall time of

* ``pim.fit`` (a Sobol sample of the box in one vectorised evaluation + batched bounded
  Levenberg-Marquardt refinement of the best samples on exact dual-number derivatives: the
  one fitting engine, of which (eps, beta) is the two-key case), and
* one local ``scipy.optimize.minimize`` (L-BFGS-B, bounds eps in [0, 1], beta in [0, 1])
  started from the design sheet's guess (eps = 0.1, beta = 1), the way the sheet's Mathcad
  Minimize() works, once with finite-difference gradients (what a direct translation of the
  sheet does) and once with the exact gradient (dual numbers through the one formula),

all measured in the same run, interleaved, and their ratios (goal: global <= 3x local).
Then it shows, on a case with two basins (beta widened past the q singularity), where the
local minimize stops and where the global fit goes.

Run: ``python benchmarks/bench_fit.py [--repeats N]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.optimize import minimize

import pim
from pim.analysis.fitting import fit
from pim.analysis.residuals import residuals
from pim.model.dual import MOTION_OUTPUTS, motion_jacobian

NAMES = ("velocity1_x", "velocity1_y", "velocity2_x", "velocity2_y")
ROWS = [MOTION_OUTPUTS.index(n) for n in NAMES]


def local_fit(case, x0=(0.1, 1.0), bounds=((0.0, 1.0), (0.0, 1.0)), gradient=False):
    """One local bounded minimize of the sheet's velocity error from ``x0``."""
    target = np.concatenate([case.measured.velocity1, case.measured.velocity2])
    if gradient:
        def fun(x):
            values, jac = motion_jacobian(case, x[0], x[1])
            r = values[ROWS] - target
            return float(r @ r), 2.0 * (r @ jac[ROWS][:, :2])
    else:
        def fun(x):
            r = residuals(pim.solve(case, x[0], x[1]), NAMES)
            return float(r @ r)
    return minimize(fun, x0, jac=gradient or None, method="L-BFGS-B", bounds=bounds)


def median_time(func, repeats):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        func()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=200)
    args = parser.parse_args(argv)
    case = pim.load_case("ricsac9")

    # warm up (imports, caches), then interleave the three timings in rounds
    g, a, b = fit(case), local_fit(case), local_fit(case, gradient=True)
    rounds = 5
    t_global, t_num, t_grad = [], [], []
    for _ in range(rounds):
        t_global.append(median_time(lambda: fit(case), args.repeats // rounds))
        t_num.append(median_time(lambda: local_fit(case), args.repeats // rounds))
        t_grad.append(median_time(lambda: local_fit(case, gradient=True), args.repeats // rounds))
    tg, tn, tc = (float(np.median(t)) for t in (t_global, t_num, t_grad))

    print("RICSAC 9: least-squares fit of the post-impact velocities (bounds eps in [0, 1], "
          "beta in [0, 1])")
    print(f"{'method':<52} {'time [ms]':>9} {'eps':>8} {'beta':>7} {'cost':>9} {'nfev':>5}")
    rows = [("global pim.fit (Sobol 256 + batched LM refine)", tg, g.eps, g.beta, g.cost,
             g.nfev),
            ("local minimize from (0.1, 1), finite-diff gradient", tn, a.x[0], a.x[1], a.fun,
             a.nfev),
            ("local minimize from (0.1, 1), exact gradient", tc, b.x[0], b.x[1], b.fun,
             b.nfev)]
    for label, t, e, be, c, n in rows:
        print(f"{label:<52} {1e3 * t:9.3f} {e:8.5f} {be:7.4f} {c:9.5f} {n:5d}")
    print(f"ratio global / local (finite-diff gradient): {tg / tn:.2f}  (goal <= 3)")
    print(f"ratio global / local (exact gradient): {tg / tc:.2f}  (goal <= 3)")

    # two basins: widen beta past the singular beta (A - mu B = 0, here near beta = 9) and
    # generate measurements on the far branch
    bounds = ((0.0, 1.0), (0.0, 12.0))
    truth = pim.solve(case, 0.3, 10.5)
    two = pim.Case(case.vehicle1, case.vehicle2, case.impact,
                   pim.Measured(truth.velocity1, truth.velocity2), name="two-basin")
    g2 = fit(two, bounds=bounds)
    l2 = local_fit(two, bounds=bounds)
    print("\ntwo-basin case (measured values from eps = 0.3, beta = 10.5; beta bounds [0, 12]):")
    print(f"  global fit: eps = {g2.eps:.6f}, beta = {g2.beta:.6f}, cost = {g2.cost:.3g}; "
          f"{len(g2.minima)} minima refined: "
          + ", ".join(f"({e:.3f}, {b:.3f}, {c:.3g})" for e, b, c in g2.minima))
    print(f"  local from (0.1, 1): eps = {l2.x[0]:.6f}, beta = {l2.x[1]:.6f}, cost = {l2.fun:.3g}")


if __name__ == "__main__":
    main()
