"""How far the detected contact start errs, over random scenes (issue 12, defect 11).

    python benchmarks/bench_detected_start.py [--n 200] [--dt 1e-4] [--seed 0]

Random approaching scenes (masses 100-40 000 kg, radii of gyration 0.3-3 m, speeds up to
40 m/s per axis, yaw rates up to 6 rad/s, any Gamma), epsilon 0.3, beta 1 (sticking, which
the engine reproduces), simulated with the engine finding the contact itself
(``start="detected"``) at one dt. Prints the spread of the error
(:func:`sim.error_measure.impact_error`) per unit dt and of the ratio of the simulated to
PIM's impulse magnitude, so that the documentation can state a measured spread instead of a
figure that holds for one case only.
"""

from __future__ import annotations

import argparse

import numpy as np

import pim
import sim
from sim.error_measure import impact_error


def random_scene(rng) -> pim.Case:
    def vehicle():
        m = rng.uniform(100, 40000)
        return pim.Vehicle(m, m * rng.uniform(0.3, 3) ** 2, rng.uniform(-4, 4, 2),
                           rng.uniform(-40, 40, 2), rng.uniform(-6, 6), rng.uniform(-np.pi, np.pi))

    return pim.Case(vehicle(), vehicle(), pim.Impact(rng.uniform(-3, 3, 2),
                                                     rng.uniform(-np.pi, np.pi)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=200)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    per_dt, ratio, failures = [], [], {}
    while len(per_dt) + sum(failures.values()) < args.n:
        case = random_scene(rng)
        result = pim.solve(case, 0.3, 1.0)
        if not bool(result.approaching) or not bool(result.admissible):
            continue
        try:
            s = sim.simulate(case, 0.3, 1.0, sim.Settings(start="detected", dt=args.dt))
        except sim.SimulationError as exc:
            failures[exc.kind] = failures.get(exc.kind, 0) + 1
            continue
        err = float(impact_error(case, result, s.velocity1, s.velocity2, s.yaw_rate1,
                                 s.yaw_rate2))
        per_dt.append(err / args.dt)
        ratio.append(np.hypot(*s.impulse) / float(np.hypot(*result.impulse)))
    q = [5, 50, 95, 100]
    e, r = np.percentile(per_dt, q), np.percentile(ratio, q)
    print(f"{len(per_dt)} random scenes simulated at dt = {args.dt:g} s, detected start "
          f"(failed: {failures or 'none'})")
    print("error / dt [1/s]:      "
          + ", ".join(f"{p}%: {v:.3g}" for p, v in zip(q, e, strict=True)))
    print("|P_sim| / |P_PIM| [-]: "
          + ", ".join(f"{p}%: {v:.3g}" for p, v in zip(q, r, strict=True)))
    print(f"smallest |P_sim| / |P_PIM|: {min(ratio):.3g}")


if __name__ == "__main__":
    main()
