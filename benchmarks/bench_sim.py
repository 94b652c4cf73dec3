"""Speed and accuracy of the pymunk cross-check (sim/): the figures behind its defaults.

Run:  python benchmarks/bench_sim.py [--scenes N]

Prints
1. wall time per simulated impact at default settings (RICSAC 9 and random scenes), with
   pim.solve on the same scene as the baseline measured in the same run;
2. accuracy against pim.solve for fixed solver iteration counts and for the automatic
   count (default), over random admissible scenes without a stated limitation;
3. the error of the "detected" start (engine finds the contact) against dt.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import pim
import sim
from sim.sampling import random_scenes


def rel_error(r, a) -> float:
    speed = max(np.abs(a.velocity1).max(), np.abs(a.velocity2).max())
    spin = max(abs(float(a.yaw_rate1)), abs(float(a.yaw_rate2)), 1e-300)
    return max(np.abs(np.r_[r.velocity1 - a.velocity1, r.velocity2 - a.velocity2]).max() / speed,
               abs(r.yaw_rate1 - float(a.yaw_rate1)) / spin,
               abs(r.yaw_rate2 - float(a.yaw_rate2)) / spin)


def per_call(fn, repeat: int) -> float:
    fn()
    start = time.perf_counter()
    for _ in range(repeat):
        fn()
    return (time.perf_counter() - start) / repeat


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--scenes", type=int, default=500)
    args = parser.parse_args()
    case = pim.load_case("ricsac9")

    print("1. wall time per impact, default settings")
    t_sim = per_call(lambda: sim.simulate(case, 0.355, 1.0), 400)
    t_pim = per_call(lambda: pim.solve(case, 0.355, 1.0), 400)
    walls = [sim.simulate(case, 0.355, 1.0).wall_time for _ in range(400)]
    print(f"   RICSAC 9: sim.simulate {1e3 * t_sim:.3f} ms per call "
          f"(SimResult.wall_time median {1e3 * np.median(walls):.3f} ms: build + step), "
          f"pim.solve {1e3 * t_pim:.3f} ms; ratio {t_sim / t_pim:.1f}x")
    scenes = random_scenes(args.scenes, seed=1)
    usable = [s for s in scenes if not sim.limitations(*s)]
    analytic = [pim.solve(*s) for s in usable]
    start = time.perf_counter()
    results = [sim.simulate(*s) for s in usable]
    elapsed = time.perf_counter() - start
    iters = np.array([r.iterations for r in results])
    print(f"   {len(usable)} random scenes: {1e3 * elapsed / len(usable):.3f} ms per impact "
          f"(automatic iterations: median {np.median(iters):.0f}, max {iters.max()}); "
          f"{len(scenes) - len(usable)} of {len(scenes)} scenes have a stated limitation")

    print("2. accuracy vs solver iterations (max relative error of velocities/yaw rates)")
    print(f"   {'iterations':>10} {'max error':>10} {'99th pct':>10} {'> 1e-6':>7} "
          f"{'ms/impact':>10}")
    for its in (5, 10, 20, 40, 80, 160, 320, None):
        settings = sim.Settings(iterations=its, convergence_tolerance=None,
                                energy_tolerance=1.0)
        errs = []
        start = time.perf_counter()
        for s, a in zip(usable, analytic, strict=True):
            errs.append(rel_error(sim.simulate(*s, settings), a))
        ms = 1e3 * (time.perf_counter() - start) / len(usable)
        errs = np.array(errs)
        print(f"   {'auto' if its is None else its:>10} {errs.max():>10.2e} "
              f"{np.percentile(errs, 99):>10.2e} {(errs > 1e-6).sum():>7d} {ms:>10.3f}")

    print("3. detected start (engine finds the contact): RICSAC 9 error vs dt")
    a = pim.solve(case, 0.355, 1.0)
    for dt in (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4):
        r = sim.simulate(case, 0.355, 1.0, sim.Settings(start="detected", dt=dt))
        print(f"   dt = {dt:.3e} s: max relative error {rel_error(r, a):.3e}, "
              f"{r.steps} steps, {1e3 * r.wall_time:.3f} ms")
    r = sim.simulate(case, 0.355, 1.0, sim.Settings(contact="outline", start="detected"))
    print(f"   outline contact (patch), detected: max relative error {rel_error(r, a):.3e}, "
          f"{r.contact_points} points")


if __name__ == "__main__":
    main()
