"""Time of ``pim speed-error CASE`` per case (issue 17 item 5): wall time, CPU time of the
process and the load average, for every bundled case and the user-written US-unit side
impact (tests/data/pickup-into-sedan-side.toml).

On a machine shared with other jobs the wall time is inflated by waiting for a core; the
command is single-threaded, so its CPU time (user + sys) estimates the wall time on an idle
machine.

    python benchmarks/bench_speed_error.py [CASE ...]
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

from click.testing import CliRunner

from pim.io.casefile import list_cases
from pim_cli.compare import speed_error

USER_CASE = str(Path(__file__).resolve().parent.parent / "tests" / "data"
                / "pickup-into-sedan-side.toml")


def time_case(name: str, out: str) -> tuple[float, float, int]:
    """(wall [s], CPU [s], exit code) of ``pim speed-error NAME``."""
    cpu0 = os.times()
    wall0 = time.perf_counter()
    res = CliRunner().invoke(speed_error, [name, "--out", out, "--no-progress"])
    wall = time.perf_counter() - wall0
    cpu1 = os.times()
    cpu = (cpu1.user - cpu0.user) + (cpu1.system - cpu0.system)
    return wall, cpu, res.exit_code


def main(names) -> None:
    names = list(names) or [c for c, _ in list_cases()] + [USER_CASE]
    print(f"{'case':<28} {'wall [s]':>9} {'CPU [s]':>8} {'load (1 min)':>12} exit")
    with tempfile.TemporaryDirectory() as out:
        for name in names:
            wall, cpu, code = time_case(name, out)
            print(f"{Path(name).stem:<28} {wall:9.1f} {cpu:8.1f} {os.getloadavg()[0]:12.2f} "
                  f"{code}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
