"""Stress `pim compare`'s interrupts: the check of test_compare's
test_a_killed_run_keeps_the_old_run_whole, many times, two runs at a time, beside one busy
process; prints each failure and the count per moment (issue 33 item 10).

    PYTHONPATH=$PWD python tests/comparisons/report/interrupt_stress.py N WHEN...

WHEN is SIGNAL-MOMENT: SIGNAL is INT or TERM; MOMENT is seconds after the start, "writing"
(the test's: once a file is written), "rand" (0.3-5 s), "win" (1.8-3.2 s: the plot worker's
start on 2 cores loaded about 15), "pool" (0-0.4 s after the run's forkserver appears: the
plot worker's start at any load), "anim" (0-1.5 s after ffmpeg's temporary MP4 appears); a leading
"P" (TERM-Pwin) signals the parent alone instead of the process group. Each run also fails
when a process still names its folder 0.2 s after the parent ended (an orphaned ffmpeg or
worker). Not a test: it takes minutes (about 7 s a run on 2 busy cores).
"""

import collections
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pim
from comparisons.report.compare import compare_case
from tests.comparisons.report.test_compare import copy_run, new_files, pim_command, snapshot

MOMENTS = {"rand": (0.3, 5.0), "win": (1.8, 3.2), "pool": (0.0, 0.4), "anim": (0.0, 1.5)}


def _forkserver_started(pid):
    """Whether process ``pid`` has a forkserver child (the plot worker's pool starts)."""
    try:
        children = Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
        return any(b"forkserver" in Path(f"/proc/{c}/cmdline").read_bytes() for c in children)
    except OSError:
        return False


def _ready(parent, start, moment, pid):
    """Whether the run reached the moment's event (a file written, a forkserver started,
    ffmpeg's MP4 begun)."""
    if moment == "pool":
        return _forkserver_started(pid)
    if moment == "writing":
        return bool(new_files(parent, start))
    if moment == "anim":
        return any(p.name.endswith(".mp4") for p in parent.rglob("*"))
    return True


def interrupt(parent, signum, when, k):
    """Start `pim compare` into parent/r, signal it at ``when``; return code and stderr."""
    group, moment = not when.startswith("P"), when.lstrip("P")
    start = time.time()
    proc = subprocess.Popen(pim_command() + ["compare", "ricsac9", "--out", str(parent / "r"),
                                             "--no-progress", "--no-speed-error"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    while not _ready(parent, start, moment, proc.pid) and proc.poll() is None \
            and time.time() < start + 200:
        time.sleep(0.02)
    low, high = MOMENTS.get(moment, (0.0, 0.0))
    wait = random.Random(k).uniform(low, high)
    time.sleep(wait if moment in MOMENTS else 0.0 if moment == "writing" else float(moment))
    running = proc.poll() is None
    (os.killpg if group else os.kill)(proc.pid, signum)
    _, err = proc.communicate(timeout=120)
    return (proc.returncode, err) if running else (None, "ended before the signal")


def one(old, base, k, signum, when):
    """One run: the problems found ("" when none) and stderr."""
    tmp = base / f"t{k}"
    tmp.mkdir()
    out, before = copy_run(old, tmp)
    try:
        code, err = interrupt(tmp, signum, when, k)
    except subprocess.TimeoutExpired:
        return "no end within 120 s (a child holds stderr)", ""
    problems = []
    if code != (130 if signum == signal.SIGINT else 143):
        problems.append(f"code {code}")
    if err.strip() not in ("aborted", "terminated"):
        problems.append("stderr")
    if snapshot(out) != before:
        problems.append("old run changed")
    time.sleep(0.2)
    left = subprocess.run(["pgrep", "-f", f"{tmp}/"], capture_output=True,
                          text=True).stdout.split()
    if left:
        problems.append(f"left running {left}")
    if [p.name for p in tmp.iterdir()] != ["r"]:
        problems.append("litter")
    shutil.rmtree(tmp, ignore_errors=True)
    return ", ".join(problems), err


def main(n, whens):
    base = Path(tempfile.mkdtemp(prefix="interrupt-stress-"))
    old = base / "old" / "r"
    compare_case(pim.load_case("ricsac9"), old, eps=0.4, beta=0.8, animation=False,
                 speed_error=False, progress=False, assumptions=False, parallel=False)
    tasks = [(k * 100 + j, getattr(signal, "SIG" + w.split("-")[0]), w.split("-")[1])
             for k in range(n) for j, w in enumerate(whens)]
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    counts = collections.Counter()
    try:
        with ThreadPoolExecutor(2) as pool:
            for (k, signum, when), (problem, err) in zip(
                    tasks, pool.map(lambda task: one(old, base, *task), tasks)):
                key = f"{signal.Signals(signum).name} {when}"
                counts[key, not problem] += 1
                if problem:
                    print(f"FAIL {key} run {k}: {problem}: {err[-400:]!r}", flush=True)
    finally:
        busy.kill()
        shutil.rmtree(base, ignore_errors=True)
    for key in dict.fromkeys(k for k, _ in counts):
        print(f"{key}: {counts[key, False]} failed of {counts[key, True] + counts[key, False]}")


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2:])
