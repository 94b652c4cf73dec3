"""The command line on a case without a yaw inertia (issue 28, point 5): one note on stderr
in the case's units, and the estimate in the JSON of ``pim uncertainty`` and ``pim
reconstruct`` and in the reconstruction's reports."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pim_cli.main import main
from tests.published_cg import car_estimate

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "tests" / "data" / "no-yaw-inertia.toml"


def _case(tmp_path, units: str) -> Path:
    text = CASE.read_text()
    if units == "us":
        text = text.replace('"1500 kg"', '"3307 lb"').replace('"2.7 m"', '"106.3 inch"')
    path = tmp_path / f"case-{units}.toml"
    path.write_text(text)
    return path


def _pim(*args):
    """The console script in a fresh process: the note goes to stderr through logging,
    which pytest's capture would otherwise take over."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "pim_cli", *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=300, cwd=ROOT)


@pytest.mark.parametrize("units, value, unit", [("si", "2848 kg m^2", "2.7 m"),
                                               ("us", "slug ft^2", "8.858 ft")])
def test_command_line_notes_the_estimate_once_in_the_case_units(tmp_path, units, value, unit):
    run = _pim("solve", _case(tmp_path, units))
    assert run.returncode == 0, run.stderr
    notes = [line for line in run.stderr.splitlines() if line.startswith("note:")]
    assert len(notes) == 1, run.stderr
    (note,) = notes
    assert "vehicle1.yaw_inertia not given: estimated" in note and value in note
    assert f"wheelbase L {unit}" in note and "±7.4 % (1 sd)" in note
    assert "Heydinger et al. 1999" in note and "a = 0.397 L ± 0.026 L (1 sd" in note
    assert "NHTSA's NCAP 2004 measurements) assumed" in note


def test_uncertainty_json_carries_the_estimate(capsys):
    assert main(["uncertainty", str(CASE), "--samples", "2000", "--json"]) == 0
    (estimate,) = json.loads(capsys.readouterr().out)["estimates"]
    assert estimate["input"] == "vehicle1.yaw_inertia" and estimate["unit"] == "kg m^2"
    assert estimate["value"] == pytest.approx(car_estimate(), rel=5e-4)
    assert estimate["sd"] / estimate["value"] == pytest.approx(0.074, abs=0.003)


def test_reconstruct_json_and_report_list_the_estimate(tmp_path, capsys):
    path = tmp_path / "rec.toml"
    path.write_text(CASE.read_text().replace('velocity = ["15 m/s", "0 m/s"]',
                                             'velocity = ["0 m/s", "0 m/s"]') + """
[measured]
vehicle1.velocity = ["9.8 m/s", "2.3 m/s"]
vehicle1.yaw_rate = "135 deg/s"
vehicle2.velocity = ["4.6 m/s", "2.9 m/s"]
vehicle2.yaw_rate = "-237 deg/s"
[unknown]
vehicle1.speed = {bounds = ["0 m/s", "40 m/s"]}
""")
    assert main(["reconstruct", str(path), "--samples", "20", "--json"]) == 0
    (estimate,) = json.loads(capsys.readouterr().out)["estimates"]
    assert estimate["input"] == "vehicle1.yaw_inertia"
    assert [a[:12] for a in estimate["assumed"]] == ["a = 0.397 L "]
    out = tmp_path / "out"
    assert main(["reconstruct", str(path), "--samples", "20", "--out", str(out),
                 "--no-video"]) == 0
    for name in ("report.md", "report.html"):
        assert "vehicle1.yaw_inertia not given: estimated 2848 kg m^2" in (out / name).read_text()
