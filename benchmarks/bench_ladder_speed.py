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
a loaded machine read the last column, the wall time the run would take on 2 idle cores:
the CPU time of the command's own process plus half its workers' (``pim speed-error`` times
its two finite-duration scenes on two workers; ``pim assumptions`` on the compiled scene
runs in one process).
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
GOAL = 10.0
COMMANDS = {
    "assumptions": ["assumptions", "{case}", "--no-animation", "--no-progress"],
    "speed-error": ["speed-error", "{case}", "--no-progress"],
}


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


#: A child's own CPU time, reported by the wrapper :func:`run` starts the command in.
_WRAPPER = ("import resource, runpy, sys; sys.argv = ['pim'] + sys.argv[1:]\n"
            "try:\n    runpy.run_module('pim_cli', run_name='__main__')\n"
            "finally:\n    u = resource.getrusage(resource.RUSAGE_SELF)\n"
            "    sys.stderr.write(f'OWN-CPU {u.ru_utime + u.ru_stime}\\n')\n")


def run(command: str, case: str, engine: str) -> tuple[float, float, float]:
    """(wall [s], CPU [s] of the process and its workers, idle 2-core estimate [s]) of one
    command."""
    args = [a.format(case=case) for a in COMMANDS[command]] + ["--engine", engine]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
    with tempfile.TemporaryDirectory() as tmp:
        cpu0, wall0 = _children_cpu(), time.perf_counter()
        done = subprocess.run([sys.executable, "-c", _WRAPPER, *args, "--out",
                               str(Path(tmp) / "o")], check=False, env=env, cwd=ROOT,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        wall, cpu = time.perf_counter() - wall0, _children_cpu() - cpu0
    own = [float(line.split()[1]) for line in done.stderr.splitlines()
           if line.startswith("OWN-CPU")]
    if done.returncode not in (0, None) or not own:
        raise RuntimeError(f"{command} failed: {done.stderr[-2000:]}")
    return wall, cpu, own[0] + (cpu - own[0]) / 2.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--case", default="ricsac9")
    parser.add_argument("--repeats", type=int, default=1, help="runs per command (best kept)")
    parser.add_argument("--only", choices=sorted(COMMANDS), default=None)
    args = parser.parse_args()
    print(f"{args.case}: load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'command':<14}{'engine':<9}{'wall [s]':>10}{'CPU [s]':>10}"
          f"{'idle 2-core estimate [s]':>26}")
    for command in [args.only] if args.only else list(COMMANDS):
        best = {}
        for engine in ("numba", "pymunk"):
            times = [run(command, args.case, engine) for _ in range(max(1, args.repeats))]
            best[engine] = min(times)
            wall, cpu, idle = best[engine]
            print(f"{command:<14}{engine:<9}{wall:>10.1f}{cpu:>10.1f}{idle:>26.1f}")
        ratios = [best["pymunk"][i] / best["numba"][i] for i in range(3)]
        print(f"{command:<14}{'ratio':<9}{ratios[0]:>9.1f}x{ratios[1]:>9.1f}x"
              f"{ratios[2]:>25.1f}x   (pymunk / compiled)")
        wall, _, idle = best["numba"]
        print(f"{command:<14}goal: compiled under {GOAL:.0f} s on 2 cores: "
              f"{'met' if idle < GOAL else 'NOT met'} by the idle 2-core estimate "
              f"({idle:.1f} s), {'met' if wall < GOAL else 'not met'} by this run's wall "
              f"time ({wall:.1f} s at load {os.getloadavg()[0]:.1f})")
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
