"""The speeds before the impact in pim solve and pim reconstruct (comparisons.report.pre_impact):
text, JSON and the report files, in the user's units."""

import json
import re
from dataclasses import replace

import pytest

from comparisons.report.pre_impact import pre_impact_lines, pre_impact_rows
from pim.analysis.pre_impact_speeds import PreImpactSpeed
from pim.io.output import MARKER
from pim.model.distributions import Distribution, UncertaintyTable
from pim.model.evidence import Evidence
from pim.model.pre_impact import PreImpactMarks, speed_at_mark_start
from pim_cli import reconstruct as reconstruct_command
from pim_cli.main import main
from tests.pim.analysis.test_pre_impact_speeds import (
    FT,
    MPH,
    V_CASE,
    G,
    bundled,
    by_hand_mph,
    vehicle_evidence,
)


def test_pim_solve_prints_the_speed_at_the_start_of_the_marks(capsys):
    assert main(["solve", "pre-impact-skids"]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines()
                if x.startswith("speed of vehicle 1 where its marks start"))
    assert f"{by_hand_mph(31.09, 30, 1.0):.4g} mph" in line and "30 ft of marks" in line
    assert main(["solve", "pre-impact-skids", "--json", "--units", "si"]) == 0
    data = json.loads(capsys.readouterr().out)["pre_impact"]
    row = data["vehicle2.speed_at_marks_start"]
    assert row["unit"] == "km/h" and row["p5"] is None        # 1 km/h = 1/3.6 m/s
    assert row["value"] == pytest.approx(by_hand_mph(31.09, 20, 1.6 / 3, -0.02) * MPH * 3.6,
                                         rel=1e-6)
    assert row["impact"] == pytest.approx(V_CASE * 3.6)


def test_pim_solve_with_a_driver_table_from_before_the_impact(tmp_path, capsys):
    case = tmp_path / "braking.toml"
    case.write_text(bundled("synthetic-runout") + '\n[driver.vehicle1]\n'
                    'time = ["-1.5 s", "0 s"]\nbrake = [1, 1]\n')
    assert main(["solve", str(case), "--json"]) == 0
    row = json.loads(capsys.readouterr().out)["pre_impact"]["vehicle1.speed_at_driver_start"]
    # locked from -1.5 s on the Coulomb tyre (friction 0.7): v0 = v + 0.7 g 1.5
    assert row["unit"] == "mph" and row["source"] == "driver"
    assert row["value"] * MPH == pytest.approx(V_CASE + 0.7 * G * 1.5, rel=1e-4)


def test_pim_solve_refuses_bad_marks_in_one_line(tmp_path, capsys):
    case = tmp_path / "bad.toml"
    case.write_text(bundled("synthetic-runout") + '\n[evidence.vehicle1.pre_impact]\n'
                    'skid_length = "30 ft"\nfriction = 0.7\nbraking = 2\n')
    assert main(["solve", str(case)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "evidence.vehicle1.pre_impact.braking" in err[0]


@pytest.fixture
def fast_reconstruction(monkeypatch):
    """pim reconstruct on RICSAC 9 turned around (measured motion: seconds, not the minutes
    of run-out fits) with vehicle 1's marks attached to the reconstruction's case."""
    marks = PreImpactMarks(30 * FT, 0.7, where="evidence.vehicle1.pre_impact")
    table = UncertaintyTable({"evidence.vehicle1.pre_impact.friction":
                              Distribution("plusminus", None, 0.05)})
    real = reconstruct_command.run_reconstruction

    def with_marks(case, **kwargs):
        rec = real(case, **kwargs)
        solved = replace(rec.case, evidence=Evidence(vehicle1=vehicle_evidence(pre_impact=marks)),
                         uncertainty=UncertaintyTable({**rec.case.uncertainty.inputs,
                                                       **table.inputs}))
        return replace(rec, case=solved)

    monkeypatch.setattr(reconstruct_command, "run_reconstruction", with_marks)
    return marks


def test_pim_reconstruct_shows_the_speeds_before_the_impact(fast_reconstruction, tmp_path,
                                                            capsys):
    assert main(["reconstruct", "ricsac9-reconstruct", "--samples", "400", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    row = data["pre_impact"]["vehicle1.speed_at_marks_start"]
    impact = data["unknowns"]["vehicle1.speed"]
    assert row["unit"] == "mph" and row["impact"] == pytest.approx(impact["value"])
    v = speed_at_mark_start(impact["value"] * MPH, 30 * FT, 0.7) / MPH
    assert row["value"] == pytest.approx(v, rel=1e-9)
    assert row["p5"] < row["p50"] < row["p95"] and row["p5"] < row["value"] < row["p95"]
    assert row["varied"] == ["evidence.vehicle1.pre_impact.friction"]
    assert {name for name, _ in row["drivers"]} == {"vehicle1.speed (impact)",
                                                     "evidence.vehicle1.pre_impact.friction"}
    out = tmp_path / "out"
    assert main(["reconstruct", "ricsac9-reconstruct", "--samples", "400", "--out",
                 str(out)]) == 0
    text = capsys.readouterr().out
    assert "speed of vehicle 1 where its marks start" in text and "nan" not in text.lower()
    # issue 33, point 6: readable names, no dotted keys, in the text
    assert "main driver of the spread impact speed of vehicle 1" in text
    assert not re.search(r"\b(vehicle\d|evidence|impact|measured)\.\w", text), text
    assert {p.name for p in out.iterdir()} == {"report.md", "report.html",
                                               "reconstruction.csv", "pre_impact.csv", MARKER}
    md = (out / "report.md").read_text()
    assert "## Speeds before the impact" in md
    assert "speed of vehicle 1 where its marks start" in md and ".speed_at" not in md
    page = (out / "report.html").read_text()
    table = page.split('id="table-pre_impact"')[1].split("</table>")[0]
    assert "<td>speed of vehicle 1 where its marks start</td>" in table
    assert "<td>mph</td>" in table
    assert 'href="#pre-impact"' in page
    assert (out / "pre_impact.csv").read_text().splitlines()[1].startswith(
        "speed of vehicle 1 where its marks start,")


def test_without_samples_no_interval_is_printed(fast_reconstruction, capsys):
    assert main(["reconstruct", "ricsac9-reconstruct", "--samples", "0"]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines()
                if x.startswith("speed of vehicle 1 where its marks start"))
    assert "[" not in line.split("mph")[1].split("(")[0] and "nan" not in out.lower()


def test_rows_speak_the_users_units():
    s = PreImpactSpeed(1, "marks", 10.0, 20.0, marks=PreImpactMarks(
        12.192, 0.7, grade=0.02))
    (si,) = pre_impact_rows([s], "si")
    (us,) = pre_impact_rows([s], "us")
    assert si.unit == "km/h" and si.value == pytest.approx(20.0 * 3.6)
    assert "12.19 m of marks" in si.what
    assert us.unit == "mph" and us.value == pytest.approx(20.0 / MPH)
    assert "40 ft of marks" in us.what and "grade +2 %" in us.what
    assert "nan" not in pre_impact_lines([us])[0]


@pytest.mark.slow
def test_pim_reconstruct_on_the_bundled_case(tmp_path, capsys):
    """The bundled case end to end (run-out fits: minutes): the known 21.2 mph impact
    speeds come back, so the marks' start speeds are the hand values."""
    assert main(["reconstruct", "pre-impact-skids", "--samples", "200", "--no-video",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)["pre_impact"]
    assert data["vehicle1.speed_at_marks_start"]["value"] == pytest.approx(
        by_hand_mph(31.09, 30, 1.0), rel=1e-5)
    row = data["vehicle2.speed_at_marks_start"]
    assert row["p5"] < by_hand_mph(31.09, 20, 1.6 / 3, -0.02) < row["p95"]
