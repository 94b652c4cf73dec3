"""Every command that writes an output folder checks its input before it takes the folder's
lock (issue 33 point 10): with the folder busy, bad input is still refused as bad input, so
two runs that both fail on their input never fail on each other."""

from __future__ import annotations

from pathlib import Path

import pytest

from pim.io.output import output_folder
from pim_cli.main import main

ROOT = Path(__file__).resolve().parents[2]

#: Each command that writes a folder and takes a case, with the options that keep it short.
COMMANDS = {"compare": ["--no-animation", "--no-speed-error", "--no-assumptions"],
            "assumptions": ["--no-animation"], "speed-error": ["--coarse"], "plot": [],
            "reconstruct": ["--samples", "0"]}


def capped_case(tmp_path) -> str:
    """ricsac9 under the friction-capped law, which ``pim speed-error`` refuses."""
    text = (ROOT / "pim/io/cases/ricsac9.toml").read_text()
    path = tmp_path / "capped.toml"
    path.write_text(text.replace("[impact]\n", '[impact]\nlaw = "brach-capped"\n'
                                               'contact_friction = 0.9\n'))
    return str(path)


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_a_missing_case_is_refused_as_such_while_the_folder_is_busy(command, tmp_path, capsys):
    out = tmp_path / "out"
    missing = str(tmp_path / "no-such-case.toml")
    with output_folder(out):                      # another run holds the lock
        code = main([command, missing, "--out", str(out), *COMMANDS[command]])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "another pim run" not in err and "no-such-case" in err, err


def test_speed_error_refuses_a_law_before_the_lock_and_before_any_sweep(tmp_path, capsys):
    out = tmp_path / "out"
    with output_folder(out):
        code = main(["speed-error", capped_case(tmp_path), "ricsac9", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and "cannot use impact law 'brach-capped'" in err, err
    assert "another pim run" not in err


def test_speed_error_checks_every_case_before_sweeping_the_first(tmp_path, capsys,
                                                                   monkeypatch):
    def sweep(*args, **kwargs):
        raise AssertionError("a case was swept before every case was read")

    monkeypatch.setattr("comparisons.studies.speed_error.sweep", sweep)
    out = tmp_path / "out"
    code = main(["speed-error", "ricsac9", str(tmp_path / "missing.toml"), "--out", str(out),
                 "--coarse", "--no-compliant"])
    err = capsys.readouterr().err
    assert code == 2 and "missing.toml" in err, err
    assert not out.exists()
