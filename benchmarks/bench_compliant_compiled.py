"""Scenes per second of the finite-duration crush scene: pymunk against the compiled engine.

Run:  python benchmarks/bench_compliant_compiled.py [--pymunk 60] [--batch 20000] [--rounds 3]

The same random scenes (RICSAC 9 and the hard barrier case with random restitution, contact
time 50-200 ms, Coulomb friction, tyre friction, tyre mode and tangential recovery) run on
``engine="pymunk"`` one call each, and on ``engine="numba"`` as one batch (the scenes tiled
to ``--batch``), on 2 threads and on 1; a warm call of one scene is timed too (the cost a
least-squares loop pays per evaluation). Two step settings: validate-models' 20 steps per
contact time and the default 400. Each round times every engine (interleaved: the load of
the shared machine changes from second to second) and the best of the rounds is kept.
Prints scenes per second by wall time and by CPU time, the ratio compiled / pymunk
measured in this run (goal: >= 1000 on 2 cores, by wall time; the CPU-time ratio of one
thread is the figure least disturbed by other jobs), the load average, and the largest
difference between the engines on the timed scenes (they run the same functions: 0).
"""

from __future__ import annotations

import argparse
import os
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


GOAL = 1000.0


def _clock():
    return time.perf_counter(), time.process_time()


def _since(start) -> tuple[float, float]:
    """(wall, CPU) seconds since ``start`` (:func:`_clock`)."""
    return time.perf_counter() - start[0], time.process_time() - start[1]


def pymunk_run(case, inputs, settings) -> tuple[tuple[float, float], np.ndarray]:
    """(wall, CPU) seconds per scene of engine="pymunk" and the post-impact velocities (n, 6)."""
    n = len(inputs["eps"])
    out = np.full((n, 6), np.nan)
    start = _clock()
    for i in range(n):
        one = {k: v[i] for k, v in inputs.items()}
        try:
            r = sim.simulate_compliant(case_element(case, i), one.pop("eps"), settings=settings,
                                       engine="pymunk", **one)
        except sim.SimulationError:
            continue
        out[i] = np.r_[r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2]
    wall, cpu = _since(start)
    return (wall / n, cpu / n), out


def tiled(case, inputs, size: int):
    """The scenes tiled to ``size``: (case, inputs)."""
    n = len(inputs["eps"])
    index = np.arange(size) % n
    big = pim.Case(*(pim.Vehicle(v.mass[index], v.yaw_inertia[index], v.cg[index],
                                 v.velocity[index], v.yaw_rate[index], v.heading[index])
                     for v in (case.vehicle1, case.vehicle2)),
                   pim.Impact(point=case.impact.point[index],
                              normal_angle=case.impact.normal_angle[index]))
    return big, {k: np.asarray(v)[index] for k, v in inputs.items()}


def compiled_run(big, inputs, settings, threads: int) -> tuple[float, float]:
    """(wall, CPU) seconds per scene of engine="numba" on the batch, on ``threads`` threads."""
    before = numba.get_num_threads()
    numba.set_num_threads(threads)
    try:
        start = _clock()
        sim.simulate_compliant(big, settings=settings, **inputs)
        wall, cpu = _since(start)
    finally:
        numba.set_num_threads(before)
    size = len(inputs["eps"])
    return wall / size, cpu / size


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


def measure(case, inputs, settings, size: int, rounds: int) -> dict:
    """Best (wall, CPU) per scene of each engine over ``rounds`` interleaved rounds (the load
    of a shared machine changes from second to second: each round times every engine)."""
    big, many = tiled(case, inputs, size)
    threads = numba.config.NUMBA_NUM_THREADS
    best = {k: [np.inf, np.inf] for k in ("pymunk", "2 threads", "1 thread")}
    post = None
    for _ in range(rounds):
        runs = {"2 threads": compiled_run(big, many, settings, min(2, threads)),
                "1 thread": compiled_run(big, many, settings, 1)}
        runs["pymunk"], post = pymunk_run(case, inputs, settings)
        for key, (wall, cpu) in runs.items():
            best[key] = [min(best[key][0], wall), min(best[key][1], cpu)]
    return {"best": best, "post": post}


def report(steps: int, settings, batch, found: dict) -> None:
    """Print one setting's figures: scenes/s, the ratios to pymunk and the goal."""
    best, post = found["best"], found["post"]
    got = np.c_[batch.velocity1, batch.velocity2, batch.yaw_rate1, batch.yaw_rate2]
    wall_p, cpu_p = best["pymunk"]
    print(f"{steps:4d} steps per contact ({int(np.mean(batch.steps))} steps on average, "
          f"{batch.ok.sum()}/{batch.ok.size} scenes ok), best of the rounds:")
    print(f"  {'engine':<22}{'scenes/s (wall)':>16}{'ratio':>8}{'scenes/s (CPU)':>16}"
          f"{'ratio':>8}")
    print(f"  {'pymunk':<22}{1 / wall_p:>16,.1f}{'':>8}{1 / cpu_p:>16,.1f}")
    for key in ("2 threads", "1 thread"):
        wall, cpu = best[key]
        print(f"  {'compiled, ' + key:<22}{1 / wall:>16,.0f}{wall_p / wall:>8.0f}"
              f"{1 / cpu:>16,.0f}{cpu_p / cpu:>8.0f}")
    ratio = wall_p / best["2 threads"][0]
    print(f"  goal: compiled >= {GOAL:.0f} x pymunk on 2 cores (wall): {ratio:.0f} x, "
          f"{'met' if ratio >= GOAL else 'NOT met'}; 2 threads / 1 thread "
          f"{best['1 thread'][0] / best['2 threads'][0]:.2f} x")
    warm = warm_call(settings)
    print(f"  warm call of 1 scene {1e6 * warm:8.1f} us ({1e6 * wall_p:.0f} us on pymunk)")
    print(f"  largest difference compiled - pymunk: {np.nanmax(np.abs(got - post)):.3g} "
          f"(m/s, rad/s)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pymunk", type=int, default=60, help="scenes run on pymunk")
    parser.add_argument("--batch", type=int, default=20000, help="scenes of the batch")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved timing rounds")
    args = parser.parse_args()
    case, inputs = scenes(args.pymunk)
    start = time.perf_counter()
    sim.simulate_compliant(case, settings=sim.CompliantSettings(), **inputs)
    print(f"first compiled call (compile or load from numba's cache): "
          f"{time.perf_counter() - start:.2f} s; load average {os.getloadavg()[0]:.1f} on "
          f"{os.cpu_count()} cores, numba threads {numba.config.NUMBA_NUM_THREADS}")
    for steps in (20, 400):
        settings = sim.CompliantSettings(record=False, steps_per_contact=steps,
                                         min_steps=min(10, steps))
        batch = sim.simulate_compliant(case, settings=settings, **inputs)
        report(steps, settings, batch, measure(case, inputs, settings, args.batch,
                                               args.rounds))
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
