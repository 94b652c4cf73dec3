"""End-to-end time of ``pim compare ricsac9`` and its split, against a reference workload.

    python benchmarks/bench_compare.py [--repeat 3] [--case ricsac9]

Prints, for each run: the wall time of the whole command (a fresh ``pim`` process, imports
included) and its CPU time (user + system, the plot worker included), then the split that
the report records (fit with the Monte Carlo intervals, simulation, animation, speed-error
sweep, plots -- rendered in a worker process in parallel with the animation and sweep -- and
the report), and the plots rendered serially in this process. The machine is shared, so
every time is also given as a ratio to a fixed CPU-bound reference workload (``pim solve``
of a 200 000-case batch on the numpy path) timed in the same run: divide the ratio by the
reference's idle-machine time to estimate the idle time. The best of ``--repeat`` runs is
kept.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

import pim


def reference() -> float:
    """Seconds for a fixed numpy workload: solve a 200 000-case batch (backend numpy)."""
    rng = np.random.default_rng(0)
    n = 200_000
    case = pim.Case(pim.Vehicle(rng.uniform(800, 2000, n), 2000.0, rng.uniform(-2, 2, (n, 2)),
                                rng.uniform(-20, 20, (n, 2))),
                    pim.Vehicle(1500.0, 2500.0, [0.0, -2.0], [0.0, 10.0]),
                    pim.Impact([0.0, 0.0], rng.uniform(-1, 1, n)))
    t0 = time.perf_counter()
    pim.solve(case, 0.3, 0.8, backend="numpy").kinetic_energy_after  # noqa: B018
    return time.perf_counter() - t0


def run_command(case: str, out: str) -> tuple[float, float, dict]:
    """Wall and CPU seconds of ``pim compare CASE`` in a fresh process, and its split."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "pim_cli", "compare", case, "--out", out,
                           "--json", "--no-progress"], capture_output=True, text=True,
                          check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, json.loads(done.stdout)["seconds"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--case", default="ricsac9")
    args = parser.parse_args()
    from pim.plotting.sheet import write_plots

    case = pim.load_case(args.case)
    fit = pim.fit(case) if case.measured is not None else None
    best = None
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.repeat):
            ref = reference()
            wall, cpu, split = run_command(args.case, os.path.join(tmp, f"run{k}"))
            t0 = time.perf_counter()
            write_plots(case, fit, os.path.join(tmp, "plots"), formats=("png",))
            serial_plots = time.perf_counter() - t0
            ref = min(ref, reference())
            print(f"run {k + 1}: pim compare {args.case}: {wall:.2f} s wall "
                  f"({wall / ref:.1f} x reference), {cpu:.2f} s CPU; reference {ref:.3f} s; "
                  f"plots serially in-process {serial_plots:.2f} s "
                  f"({serial_plots / ref:.1f} x reference)")
            print("  split: " + ", ".join(f"{k_} {v:.2f} s" for k_, v in split.items()))
            if best is None or wall / ref < best[0]:
                best = (wall / ref, wall, ref)
    print(f"best: {best[1]:.2f} s wall = {best[0]:.1f} x the reference workload "
          f"({best[2]:.3f} s in this run)")


if __name__ == "__main__":
    main()
