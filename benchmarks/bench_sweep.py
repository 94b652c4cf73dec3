"""Simulation sweep: 1000 pymunk scenes serial vs. a local process pool (sim.sweep).

    python benchmarks/bench_sweep.py [--scenes 1000] [--workers 2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import pim
from sim import simulate_many


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=1000)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    base = pim.load_case("ricsac9")
    rng = np.random.default_rng(0)
    cases = [base.transformed(rotation=r) for r in rng.uniform(-np.pi, np.pi, args.scenes)]
    eps = rng.uniform(0.1, 0.6, args.scenes)
    t0 = time.perf_counter()
    serial = simulate_many(cases, eps, 1.0, executor="serial").results
    t_serial = time.perf_counter() - t0
    t0 = time.perf_counter()
    pool = simulate_many(cases, eps, 1.0, executor="process", max_workers=args.workers).results
    t_pool = time.perf_counter() - t0
    same = all(np.array_equal(a.velocity1, b.velocity1) for a, b in zip(serial, pool,
                                                                        strict=True))
    print(f"sim sweep of {args.scenes} scenes (pymunk, ricsac9 rotated, random eps)")
    print(f"  serial        {t_serial:6.2f} s  ({args.scenes / t_serial:7.0f} scenes/s)")
    print(f"  process pool  {t_pool:6.2f} s  ({args.scenes / t_pool:7.0f} scenes/s)  "
          f"speed-up {t_serial / t_pool:.2f}x, results identical: {same}")


if __name__ == "__main__":
    main()
