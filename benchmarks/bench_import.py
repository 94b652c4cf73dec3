"""How fast ``import pim`` and ``pim solve CASE`` start, against a bare interpreter and numpy.

    python benchmarks/bench_import.py [--repeat 15] [--case ricsac9]

Each sample starts a fresh interpreter in a subprocess: ``python -c pass`` (the floor),
``python -c "import numpy"`` (what pim cannot avoid), ``python -c "import pim"``, the console
script's entry (``pim_cli.run``) with ``solve CASE``, and, for scale, ``import pint`` (which
neither of pim's two needs: the common units are read without it, pim/model/unit_table.py).
The runs are interleaved, because the machine is shared; the best and the median of
``--repeat`` runs are printed, with each one's cost above the bare interpreter and above
numpy, and the best CPU time (user + system) of each, which a busy machine inflates far less
than the wall time. The goals (issue 33 point 9, on an idle machine): ``import pim`` under 0.3 s and
``pim solve CASE`` under 0.5 s.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ENTRY = "from pim_cli import run; run()"
GOALS = {"import pim": 0.3, "pim solve": 0.5}


def runs(case: str) -> dict[str, list[str]]:
    """The commands timed, by name."""
    return {"python -c pass": [sys.executable, "-c", "pass"],
            "import numpy": [sys.executable, "-c", "import numpy"],
            "import pint": [sys.executable, "-c", "import pint"],
            "import pim": [sys.executable, "-c", "import pim"],
            "pim solve": [sys.executable, "-c", ENTRY, "solve", case]}


def cpu() -> float:
    """CPU seconds (user + system) of the finished children so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def wall_time(command: list[str]) -> tuple[float, float]:
    """Seconds from start to exit of ``command`` (its output discarded; it must succeed),
    wall and CPU."""
    start, used = time.perf_counter(), cpu()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, cwd=ROOT)
    return time.perf_counter() - start, cpu() - used


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--case", default="ricsac9")
    args = parser.parse_args()
    commands = runs(args.case)
    times = {name: [] for name in commands}
    cpus = {name: [] for name in commands}
    for command in commands.values():              # warm the file cache once
        wall_time(command)
    for _ in range(args.repeat):
        for name, command in commands.items():
            wall, used = wall_time(command)
            times[name].append(wall)
            cpus[name].append(used)
    floor, numpy = min(times["python -c pass"]), min(times["import numpy"])
    print(f"{'':15s} {'best':>8s} {'median':>8s} {'minus python':>13s} {'minus numpy':>12s} "
          f"{'best CPU':>9s}")
    for name, samples in times.items():
        best, median = min(samples), statistics.median(samples)
        print(f"{name:15s} {best:7.3f}s {median:7.3f}s {best - floor:12.3f}s "
              f"{best - numpy:11.3f}s {min(cpus[name]):8.3f}s")
    for name, goal in GOALS.items():
        best = min(times[name])
        print(f"{name}{' ' + args.case if name == 'pim solve' else ''}: {best:.3f} s "
              f"(goal < {goal} s on an idle machine: {'met' if best < goal else 'NOT met'} "
              f"here; python -c pass {floor:.3f} s), {args.repeat} runs each, interleaved")


if __name__ == "__main__":
    main()
