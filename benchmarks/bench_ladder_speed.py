"""Wall and CPU time of ``pim assumptions`` and ``pim speed-error`` on RICSAC 9: the compiled
crush scene against the pymunk path, measured in the same run.

Run:  python benchmarks/bench_ladder_speed.py [--case ricsac9] [--repeats 1]
                                              [--only assumptions|speed-error]

Each command runs as the user runs it (``python -m pim_cli ...`` in a fresh process, its
output into a temporary folder; ``pim assumptions`` without the MP4), once with
``--engine numba`` (the default) and once with ``--engine pymunk``. Prints per command and
engine the wall time, the CPU time of the command and its worker processes, and the ratio
pymunk / compiled. The goal (issue 26): each command under 10 s on 2 cores with the
compiled scene. The machine is shared: the load average is printed beside the figures; on
a loaded machine compare the CPU times and the ratio.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COMMANDS = {
    "assumptions": ["assumptions", "{case}", "--no-animation", "--no-progress"],
    "speed-error": ["speed-error", "{case}", "--no-progress"],
}


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(command: str, case: str, engine: str) -> tuple[float, float]:
    """(wall [s], CPU [s] of the process and its workers) of one command."""
    args = [a.format(case=case) for a in COMMANDS[command]] + ["--engine", engine]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    with tempfile.TemporaryDirectory() as tmp:
        cpu0, wall0 = _children_cpu(), time.perf_counter()
        subprocess.run([sys.executable, "-m", "pim_cli", *args, "--out", str(Path(tmp) / "o")],
                       check=True, env=env, cwd=ROOT, stdout=subprocess.DEVNULL)
        return time.perf_counter() - wall0, _children_cpu() - cpu0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--case", default="ricsac9")
    parser.add_argument("--repeats", type=int, default=1, help="runs per command (best kept)")
    parser.add_argument("--only", choices=sorted(COMMANDS), default=None)
    args = parser.parse_args()
    print(f"{args.case}: load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'command':<14}{'engine':<9}{'wall [s]':>10}{'CPU [s]':>10}")
    for command in [args.only] if args.only else list(COMMANDS):
        best = {}
        for engine in ("numba", "pymunk"):
            times = [run(command, args.case, engine) for _ in range(max(1, args.repeats))]
            best[engine] = min(times)
            print(f"{command:<14}{engine:<9}{best[engine][0]:>10.1f}{best[engine][1]:>10.1f}")
        wall = best["pymunk"][0] / best["numba"][0]
        cpu = best["pymunk"][1] / best["numba"][1]
        print(f"{command:<14}{'ratio':<9}{wall:>9.1f}x{cpu:>9.1f}x   (pymunk / compiled; "
              f"goal: compiled under 10 s wall)")
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
