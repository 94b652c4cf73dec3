"""Benchmark: the inverse PIM and the reconstruction Monte Carlo (issue 11's figures).

Prints, measured in the same run:

* the median wall time of one inverse PIM (``pim.analysis.inverse_pim.inverse_pim``: both
  speeds, eps and beta of RICSAC 9 turned around, ``ricsac9-reconstruct``), goal < 10 ms;
* as its baseline, one local ``scipy.optimize.least_squares`` from the case's bounds' middle
  with finite-difference derivatives on the same residuals (no global search): the ratio
  says what the global search and the exact derivatives cost or save;
* the wall time of ``pim.analysis.reconstruction.reconstruct`` of the same case with 10 000
  Monte Carlo samples, and the samples per second of the batched inverse;
* the same with rest evidence (``synthetic-runout``: RICSAC 9's scene, every sample's
  run-outs refitted): goal < 60 s on 2 cores.

Run: ``python benchmarks/bench_reconstruct.py [--repeats N] [--samples N]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from bench_fit import median_time  # a sibling script: benchmarks run from their folder
from scipy.optimize import least_squares

import pim
from pim.analysis.free_fit import free_residuals, residual_terms
from pim.analysis.free_inputs import case_state
from pim.analysis.inverse_pim import inverse_pim
from pim.analysis.reconstruction import reconstruct
from pim.analysis.residuals import measured_terms


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=50)
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--no-evidence", dest="evidence", action="store_false",
                        help="skip the synthetic evidence case (about a minute)")
    args = parser.parse_args(argv)
    case = pim.load_case("ricsac9-reconstruct")
    unknown = case.unknown
    keys = ("impact.restitution", "impact.beta", "vehicle1.speed", "vehicle2.speed")
    names = measured_terms(case, True)
    rows, target, factor = residual_terms(case, names)
    base = case_state(case, 0.5, 0.5)
    lo = np.array([unknown[k][0] for k in keys])
    hi = np.array([unknown[k][1] for k in keys])

    def local():
        return least_squares(lambda x: free_residuals(base, keys, x[None], rows, target, factor,
                                                      jacobian=False)[0][0],
                             0.5 * (lo + hi), bounds=(lo, hi), jac="2-point", method="trf")

    inverse_pim(case)                      # warm caches (scipy imports)
    local()
    t_inv = median_time(lambda: inverse_pim(case), args.repeats)
    t_loc = median_time(local, args.repeats)
    f = inverse_pim(case)
    loc = local()
    print(f"inverse PIM (Sobol search + batched LM, exact derivatives): {t_inv * 1e3:.2f} ms "
          f"per solve (goal < 10 ms)")
    print(f"  baseline, one local least_squares with finite differences: {t_loc * 1e3:.2f} ms "
          f"-> ratio {t_inv / t_loc:.2f}")
    print(f"  same optimum: max |x - x_local| = "
          f"{np.max(np.abs(np.array([f.values[k] for k in keys]) - loc.x)):.2e}")
    t = time.perf_counter()
    rec = reconstruct(case, samples=args.samples, seed=0)
    t_mc = time.perf_counter() - t
    print(f"reconstruct ricsac9-reconstruct with {args.samples} Monte Carlo samples: "
          f"{t_mc:.2f} s (goal < 60 s), {rec.samples.n_used} used, "
          f"{args.samples / t_mc:.0f} samples/s")
    show(rec)
    if args.evidence:
        case = pim.load_case("synthetic-runout")
        t = time.perf_counter()
        rec = reconstruct(case, samples=0)
        t_nom = time.perf_counter() - t
        t = time.perf_counter()
        rec = reconstruct(case, samples=args.samples, seed=0)
        t_all = time.perf_counter() - t
        print(f"reconstruct synthetic-runout (RICSAC 9's scene, rest evidence, run-out in "
              f"every sample) with {args.samples} samples: {t_all:.1f} s (goal < 60 s); of "
              f"which the nominal solve_ivp run-out fits {t_nom:.1f} s and the batched "
              f"Monte Carlo {t_all - t_nom:.1f} s ({args.samples / (t_all - t_nom):.0f} "
              f"samples/s), {rec.samples.n_used} used")
        show(rec)


def show(rec):
    for row in rec.table():
        if row["name"].endswith("speed"):
            print(f"  {row['name']}: {row['value'] / 0.44704:.2f} mph, 5/50/95 % = "
                  f"{row['p5'] / 0.44704:.2f} / {row['p50'] / 0.44704:.2f} / "
                  f"{row['p95'] / 0.44704:.2f} mph (staged / true 21.2 mph)")


if __name__ == "__main__":
    main()
