"""One whole event (approach, every impact, run-out to rest): the pymunk event
(sim.simulate_event, default step 1 ms) against the compiled analytic event (pim.event),
on RICSAC 9 (one impact) and a generated side slap (three impacts), best of --repeats
runs each, both in this run; the goal: the analytic event at least 100 times faster.

    python benchmarks/bench_event.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import time

import pim
import sim
from sim.event_check import side_slap_case

GOAL = 100.0


def best_time(run, repeats: int) -> tuple[float, object]:
    """Best wall time [s] of ``repeats`` calls of ``run`` and its last result."""
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - t0)
    return best, out


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
        t_sim, simulated = best_time(lambda c=case: sim.simulate_event(c), args.repeats)
        t_pim, analytic = best_time(lambda c=case: pim.event(c), args.repeats)
        ratio = t_sim / t_pim
        print(f"{case.name}: pymunk event {1e3 * t_sim:.1f} ms "
              f"({len(simulated.impacts)} impacts, {len(simulated)} samples, to "
              f"{simulated.end_time:.2f} s); analytic event {1e3 * t_pim:.2f} ms "
              f"({len(analytic.impacts)} impacts); analytic / pymunk speed ratio "
              f"{ratio:.1f}x (goal {GOAL:g}x: {'met' if ratio >= GOAL else 'NOT met'})")


if __name__ == "__main__":
    main()
