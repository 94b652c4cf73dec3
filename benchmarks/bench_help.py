"""How fast ``pim --help`` answers, against a bare interpreter measured in the same run.

    python benchmarks/bench_help.py [--repeat 15]

Each sample starts a fresh interpreter in a subprocess: ``python -c pass`` (the floor no
command can go below) and the console script's own entry (``pim_cli.run``) with ``--help``,
and, for scale, ``pim solve --help`` (which imports its command module and so pim). The runs
are interleaved, because the machine is shared; the best and the median of ``--repeat`` runs
are printed, with the help's own cost (its time minus the bare interpreter's) and the ratio.
The goal (issue 27): ``pim --help`` under 0.3 s, which a table of the commands
(``pim_cli/commands.py``) meets by importing no command module, no numpy and no pim.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ENTRY = "from pim_cli import run; run()"
RUNS = {"python -c pass": [sys.executable, "-c", "pass"],
        "pim --help": [sys.executable, "-c", ENTRY, "--help"],
        "pim solve --help": [sys.executable, "-c", ENTRY, "solve", "--help"]}
GOAL = 0.3


def wall_time(command: list[str]) -> float:
    """Seconds from start to exit of ``command`` (its output discarded; it must succeed)."""
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, cwd=ROOT)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    times = {name: [] for name in RUNS}
    for command in RUNS.values():              # warm the file cache once
        wall_time(command)
    for _ in range(args.repeat):
        for name, command in RUNS.items():
            times[name].append(wall_time(command))
    floor = min(times["python -c pass"])
    print(f"{'':18s} {'best':>8s} {'median':>8s} {'minus python':>13s} {'ratio':>6s}")
    for name, samples in times.items():
        best, median = min(samples), statistics.median(samples)
        print(f"{name:18s} {best:7.3f}s {median:7.3f}s {best - floor:12.3f}s "
              f"{best / floor:5.1f}x")
    best = min(times["pim --help"])
    print(f"pim --help: {best:.3f} s (goal < {GOAL} s: "
          f"{'met' if best < GOAL else 'NOT met'}), {args.repeat} runs each, interleaved")


if __name__ == "__main__":
    main()
