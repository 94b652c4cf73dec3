"""Scenes per second of the finite-duration crush scene: pymunk against the compiled engine.

Run:  python benchmarks/bench_compliant_compiled.py [--pymunk 60] [--batch 20000]

The same random scenes (RICSAC 9 and the hard barrier case with random restitution, contact
time 50-200 ms, Coulomb friction, tyre friction, tyre mode and tangential recovery) run on
``engine="pymunk"`` one call each, and on ``engine="numba"`` as one batch (the scenes tiled
to ``--batch``), on all cores and on one thread; a warm call of one scene is timed too (the
cost a least-squares loop pays per evaluation). Two step settings: validate-models' 20 steps
per contact time and the default 400. Prints scenes per second, the ratio compiled / pymunk
measured in this run (goal: >= 1000; the machine is shared, compare ratios), and the largest
difference between the engines on the timed scenes (they step alike: 0 expected).
"""

from __future__ import annotations

import argparse
import time

import numba
import numpy as np

import pim
import sim
from sim.batch import case_element


def scenes(n: int, seed: int = 0) -> tuple[pim.Case, dict]:
    """n scenes: RICSAC 9 and the hard barrier alternately, random contact inputs."""
    rng = np.random.default_rng(seed)
    cases = [pim.load_case("ricsac9"), pim.load_case("hard-barrier")]
    picks = [cases[i % 2] for i in range(n)]
    fields = {}
    for name in ("mass", "yaw_inertia", "cg", "velocity", "yaw_rate", "heading"):
        for k in (1, 2):
            fields[f"{name}{k}"] = np.stack(
                [np.broadcast_to(getattr(getattr(c, f"vehicle{k}"), name), np.shape(
                    getattr(cases[0].vehicle1, name))) for c in picks])
    v = [pim.Vehicle(fields[f"mass{k}"], fields[f"yaw_inertia{k}"], fields[f"cg{k}"],
                     fields[f"velocity{k}"], fields[f"yaw_rate{k}"], fields[f"heading{k}"])
         for k in (1, 2)]
    impact = pim.Impact(point=np.stack([c.impact.point for c in picks]),
                        normal_angle=np.array([c.impact.normal_angle for c in picks]))
    case = pim.Case(v[0], v[1], impact)
    inputs = dict(eps=rng.uniform(0.05, 0.6, n), contact_time=rng.uniform(0.05, 0.2, n),
                  friction=rng.uniform(0.0, 1.5, n),
                  tyre_friction=np.where(rng.random(n) < 0.5, 0.0, rng.uniform(0.3, 1.0, n)),
                  tyre_mode=rng.choice(["rolling", "locked"], n),
                  tangential_recovery=rng.uniform(0.0, 1.0, n))
    return case, inputs


def pymunk_rate(case, inputs, settings) -> tuple[float, np.ndarray]:
    """Scenes per second of engine="pymunk" and the post-impact velocities (n, 6)."""
    n = len(inputs["eps"])
    out = np.full((n, 6), np.nan)
    start = time.perf_counter()
    for i in range(n):
        one = {k: v[i] for k, v in inputs.items()}
        try:
            r = sim.simulate_compliant(case_element(case, i), one.pop("eps"), settings=settings,
                                       engine="pymunk", **one)
        except sim.SimulationError:
            continue
        out[i] = np.r_[r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2]
    return n / (time.perf_counter() - start), out


def compiled_rate(case, inputs, settings, size: int, repeat: int = 3) -> float:
    """Scenes per second of engine="numba" on ``size`` scenes (best of ``repeat``)."""
    n = len(inputs["eps"])
    index = np.arange(size) % n
    tiled = {k: np.asarray(v)[index] for k, v in inputs.items()}
    big = pim.Case(*(pim.Vehicle(v.mass[index], v.yaw_inertia[index], v.cg[index],
                                 v.velocity[index], v.yaw_rate[index], v.heading[index])
                     for v in (case.vehicle1, case.vehicle2)),
                   pim.Impact(point=case.impact.point[index],
                              normal_angle=case.impact.normal_angle[index]))
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        sim.simulate_compliant(big, settings=settings, **tiled)
        best = min(best, time.perf_counter() - start)
    return size / best


def warm_call(settings, repeat: int = 200) -> float:
    """Seconds per call of one RICSAC 9 scene on engine="numba" (best of 5 rounds)."""
    case = pim.load_case("ricsac9")
    sim.simulate_compliant(case, 0.355, contact_time=0.1, settings=settings)
    best = np.inf
    for _ in range(5):
        start = time.perf_counter()
        for k in range(repeat):
            sim.simulate_compliant(case, 0.3 + 1e-4 * k, contact_time=0.1, friction=0.4,
                                   tyre_friction=0.7, settings=settings)
        best = min(best, (time.perf_counter() - start) / repeat)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pymunk", type=int, default=60, help="scenes run on pymunk")
    parser.add_argument("--batch", type=int, default=20000, help="scenes of the batch")
    args = parser.parse_args()
    case, inputs = scenes(args.pymunk)
    start = time.perf_counter()
    sim.simulate_compliant(case, settings=sim.CompliantSettings(), **inputs)
    print(f"first compiled call (compile or load from numba's cache): "
          f"{time.perf_counter() - start:.2f} s")
    threads = numba.get_num_threads()
    for steps in (20, 400):
        settings = sim.CompliantSettings(record=False, steps_per_contact=steps,
                                         min_steps=min(10, steps))
        batch = sim.simulate_compliant(case, settings=settings, **inputs)
        rate_p, post = pymunk_rate(case, inputs, settings)
        got = np.c_[batch.velocity1, batch.velocity2, batch.yaw_rate1, batch.yaw_rate2]
        diff = np.nanmax(np.abs(got - post))
        rate_c = compiled_rate(case, inputs, settings, args.batch)
        numba.set_num_threads(1)
        rate_1 = compiled_rate(case, inputs, settings, args.batch)
        numba.set_num_threads(threads)
        warm = warm_call(settings)
        print(f"{steps:4d} steps per contact ({int(np.mean(batch.steps))} steps on average, "
              f"{batch.ok.sum()}/{batch.ok.size} scenes ok):")
        print(f"  pymunk             {rate_p:12.1f} scenes/s")
        print(f"  compiled, {threads} threads {rate_c:12.1f} scenes/s   ratio "
              f"{rate_c / rate_p:8.0f}")
        print(f"  compiled, 1 thread {rate_1:12.1f} scenes/s   ratio {rate_1 / rate_p:8.0f}")
        print(f"  warm call of 1 scene {1e6 * warm:8.1f} us ({1e6 / rate_p:.0f} us on pymunk)")
        print(f"  largest difference compiled - pymunk: {diff:.3g} (m/s, rad/s)")


if __name__ == "__main__":
    main()
