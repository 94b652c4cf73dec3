"""Run-out forward model: the batched fixed-step RK4 over many samples against a Python
loop of single solve_ivp runs (measured on a subset and scaled), on the synthetic case's
vehicle 1 with spread post-impact motion; then the compiled run-out's speed (samples/s) with
the field tyre (brush, load transfer) against the Coulomb tyre, same samples, same run.

    python benchmarks/bench_runout.py [--samples 10000] [--loop 20]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np

from pim.model.runout import RunoutVehicle, runout, runout_many
from pim.model.runout_kernel import integrate_many
from pim.model.tyres import TyreData


def compiled_speeds(car: RunoutVehicle, heading, velocity, yaw_rate) -> dict:
    """Samples per second of the compiled run-out for each tyre law (after a warm-up)."""
    n = len(heading)
    speeds = {}
    for name, tyre in (("coulomb", None), ("brush", TyreData())):
        vehicle = RunoutVehicle(car.mass, car.yaw_inertia, car.wheelbase, car.track,
                                car.cg_to_front_axle, car.friction, braking=car.braking, tyre=tyre)
        warm = replace(vehicle, friction=np.asarray(car.friction)[:2])
        integrate_many(warm, np.zeros((2, 2)), heading[:2], velocity[:2], yaw_rate[:2])
        t0 = time.perf_counter()
        integrate_many(vehicle, np.zeros((n, 2)), heading, velocity, yaw_rate)
        speeds[name] = n / (time.perf_counter() - t0)
    return speeds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--loop", type=int, default=20)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    n = args.samples
    speed = rng.uniform(3, 12, n)
    direction = rng.uniform(-np.pi, np.pi, n)
    velocity = speed[:, None] * np.column_stack([np.cos(direction), np.sin(direction)])
    yaw_rate = rng.uniform(-4, 4, n)
    heading = rng.uniform(-np.pi, np.pi, n)
    friction = rng.uniform(0.6, 0.8, n)
    car = RunoutVehicle(1023.0, 1323.0, 2.6, 1.45, 1.2, friction,
                        braking=(1.0, 1.0, 0.3, 0.3))
    runout(RunoutVehicle(1023.0, 1323.0, 2.6, 1.45, 1.2, 0.7), [0, 0], 0.0, [5.0, 0.0], 1.0)
    t0 = time.perf_counter()
    batch = runout_many(car, np.zeros((n, 2)), heading, velocity, yaw_rate)
    t_batch = time.perf_counter() - t0
    t0 = time.perf_counter()
    for i in range(args.loop):
        one = RunoutVehicle(1023.0, 1323.0, 2.6, 1.45, 1.2, friction[i],
                            braking=(1.0, 1.0, 0.3, 0.3))
        runout(one, [0, 0], heading[i], velocity[i], yaw_rate[i], rtol=1e-8, atol=1e-10)
    t_loop = (time.perf_counter() - t0) / args.loop * n
    print(f"run-out of {n:,} samples: batched RK4 {t_batch:.2f} s "
          f"({batch.stopped.mean():.0%} stopped); a loop of solve_ivp would take "
          f"~{t_loop:.1f} s (from {args.loop} runs): ratio {t_loop / t_batch:.1f}x")
    speeds = compiled_speeds(car, heading, velocity, yaw_rate)
    print(f"compiled run-out, {n:,} samples: Coulomb tyre {speeds['coulomb']:,.0f} samples/s, "
          f"brush tyre (load transfer) {speeds['brush']:,.0f} samples/s "
          f"({speeds['coulomb'] / speeds['brush']:.1f}x slower)")


if __name__ == "__main__":
    main()
