"""One whole event (approach, every impact, run-out to rest): the pymunk event
(sim.simulate_event, default step 1 ms) against the compiled analytic event (pim.event),
on RICSAC 9 (one impact) and a generated side slap (three impacts), best of --repeats
runs each, both in this run; the goal: the analytic event at least 100 times faster.

The ratio is of wall times, and of CPU times (process time: steadier on a shared machine).
pim.event builds a case's kernel arrays on its first event and keeps them for the case
object; the event of a new case object (its arrays built: the first event of a case) is
timed and judged against the goal too.

    python benchmarks/bench_event.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import pim
import sim
from sim.event_check import side_slap_case

GOAL = 100.0


def best_time(run, repeats: int) -> tuple[float, float, object]:
    """Best wall and CPU times [s] of ``repeats`` calls of ``run`` and its last result."""
    wall, cpu, out = float("inf"), float("inf"), None
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        out = run()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu, out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    cases = (pim.load_case("ricsac9"), side_slap_case(1.6))
    t0 = time.perf_counter()
    pim.event(cases[0])                        # compiles (or loads) the event kernel
    print(f"analytic event: first call (compile or cache load) "
          f"{time.perf_counter() - t0:.2f} s, not counted")
    for case in cases:
        t_sim, c_sim, simulated = best_time(lambda c=case: sim.simulate_event(c), args.repeats)
        t_pim, c_pim, analytic = best_time(lambda c=case: pim.event(c), args.repeats)
        t_new, c_new, _ = best_time(lambda c=case: pim.event(replace(c)), args.repeats)
        ratio, cpu_ratio = t_sim / t_pim, c_sim / max(c_pim, 1e-9)
        new_ratio, new_cpu = t_sim / t_new, c_sim / max(c_new, 1e-9)
        print(f"{case.name}: pymunk event {1e3 * t_sim:.1f} ms "
              f"({len(simulated.impacts)} impacts, {len(simulated)} samples, to "
              f"{simulated.end_time:.2f} s); analytic event {1e3 * t_pim:.2f} ms "
              f"({len(analytic.impacts)} impacts); analytic / pymunk speed ratio "
              f"{ratio:.1f}x, CPU {cpu_ratio:.1f}x ({verdict(ratio, cpu_ratio)})")
        print(f"{case.name}, a new case object (its scene built): analytic event "
              f"{1e3 * t_new:.2f} ms; analytic / pymunk speed ratio {new_ratio:.1f}x, "
              f"CPU {new_cpu:.1f}x ({verdict(new_ratio, new_cpu)})")


def verdict(ratio: float, cpu_ratio: float) -> str:
    """Whether the wall and CPU ratios both meet :data:`GOAL`."""
    return f"goal {GOAL:g}x: {'met' if min(ratio, cpu_ratio) >= GOAL else 'NOT met'}"


if __name__ == "__main__":
    main()
