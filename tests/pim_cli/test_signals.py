"""SIGINT and SIGTERM at any moment of a run end it with 130/143 and one line, leaving the
earlier output (issue 28's fault harness: 4 of 28 signal trials exited 0, and one SIGTERM
printed pymunk's "Exception ignored from callback for ffi.gc" with a traceback). Each test
runs the command line in a process of its own with one phase slowed down
(tests/pim_cli/signal_driver.py) and signals it within that phase."""

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DRIVER = Path(__file__).with_name("signal_driver.py")


def signalled(phase: str, args: list, signum: int, cwd: Path):
    """Run ``pim ARGS`` with ``phase`` slowed; send ``signum`` at its mark; return the exit
    code, stdout and stderr."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT),
                                                        os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.Popen([sys.executable, str(DRIVER), phase, *args], cwd=cwd, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first = proc.stderr.readline()
    assert first == "MARK\n", f"the phase never came: {first!r} {proc.communicate()}"
    proc.send_signal(signum)
    out, err = proc.communicate(timeout=300)
    # click writes an empty line on stderr when Ctrl-C ends a command (for a terminal's ^C)
    return proc.returncode, out, first + err.lstrip("\n")


def test_a_signal_in_a_pymunk_callback_ends_the_run_at_once_without_a_traceback(tmp_path):
    """Before: the exception raised inside the collision callback was printed ("From cffi
    callback") and dropped; the simulation went on to print its table."""
    code, out, err = signalled("callback", ["sim", "ricsac9"], signal.SIGTERM, tmp_path)
    assert (code, out, err) == (143, "", "MARK\nterminated\n")


def test_a_signal_in_a_pymunk_destructor_ends_the_run_without_a_traceback(tmp_path):
    """Before: "Exception ignored from callback for ffi.gc" with a traceback."""
    code, out, err = signalled("destructor", ["sim", "ricsac9"], signal.SIGINT, tmp_path)
    assert (code, err) == (130, "MARK\naborted\n"), err


def test_a_signal_during_the_shutdown_is_not_an_exit_0(tmp_path):
    """Before: ignored once the run's code was known (worker joins at the interpreter's
    shutdown take a while): the run exited 0. Now 143; the finished folder stays."""
    out = tmp_path / "out"
    code, _, err = signalled("shutdown", ["reconstruct", "ricsac9-reconstruct", "--out",
                                          str(out), "--samples", "0"], signal.SIGTERM, tmp_path)
    assert (code, err) == (143, "MARK\nterminated\n")
    assert {"report.md", "report.html", "reconstruction.csv"} <= {p.name for p in
                                                                  out.iterdir()}


@pytest.mark.parametrize("frame", [0, pytest.param(40, marks=pytest.mark.slow)])
def test_a_signal_while_the_animation_is_written_leaves_no_file(tmp_path, frame):
    code, _, err = signalled(f"frame:{frame}", ["animate", "ricsac9", "--out",
                                                str(tmp_path / "a.mp4"), "--no-progress"],
                             signal.SIGINT, tmp_path)
    assert (code, err) == (130, "MARK\naborted\n")
    assert list(tmp_path.iterdir()) == []                 # no MP4, no temporary file


@pytest.mark.slow
@pytest.mark.parametrize("signum, k", [(signal.SIGTERM, 3), (signal.SIGINT, 20)])
def test_a_signal_during_the_speed_error_sweep_keeps_the_earlier_output(tmp_path, signum, k):
    out = tmp_path / "docs"
    out.mkdir()
    (out / "speed-error-hard-pole.md").write_text("the earlier run")
    code, _, err = signalled(f"simulation:{k}", [
        "speed-error", "hard-pole", "--coarse", "--no-compliant", "--repeats", "1",
        "--no-progress", "--out", str(out)], signum, tmp_path)
    assert code == (143 if signum == signal.SIGTERM else 130), err
    assert err == "MARK\n" + ("terminated\n" if signum == signal.SIGTERM else "aborted\n")
    assert [p.name for p in out.iterdir()] == ["speed-error-hard-pole.md"]
    assert (out / "speed-error-hard-pole.md").read_text() == "the earlier run"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["docs"]     # no temporary litter


def test_the_driver_runs_the_command_as_pim_does(tmp_path):
    """Without a signal the slowed phase only delays the run."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, str(DRIVER), "callback", "sim", "ricsac9",
                           "--json"], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0 and done.stderr == "MARK\n"
    assert json.loads(done.stdout)["error"] < 1e-9
