"""`pim event CASE --out DIR --json` (issue 32 item 7): the folder's files, the JSON's fields in
the case's units (RICSAC 9: ft and mph), timeline.csv's units header, the folder written
whole, bad input refused before anything is written."""

import csv
import json

import numpy as np
import pytest

import pim
from pim_cli.event import event
from pim_cli.main import main


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("event") / "r9"
    import io
    from contextlib import redirect_stdout

    buf = io.StringIO()
    with redirect_stdout(buf):
        assert main(["event", "ricsac9", "--out", str(out), "--json", "--no-progress",
                     "--before", "0.3"]) == 0
    return out, json.loads(buf.getvalue())


def test_the_folder_holds_the_video_plan_timeline_and_report(run):
    out, _ = run
    names = {p.name for p in out.iterdir()}
    assert {"event.mp4", "plan.png", "timeline.csv", "report.html", "report.md"} <= names
    html = (out / "report.html").read_text()
    assert html.index("Answer") < html.index("The event") < html.index("<video")  # answer first


def test_json_fields_in_the_case_units(run):
    _, data = run
    assert data["units"]["system"] == "us" and data["units"]["speed"] == "mph"
    assert data["approach_duration"] == pytest.approx(0.3, abs=2e-3)
    first = data["impacts"][0]
    assert first["time"] == pytest.approx(0.0, abs=1e-9) and first["units"]["speed"] == "mph"
    case = pim.load_case("ricsac9")
    c_ft = np.asarray(case.impact.point) / 0.3048
    np.testing.assert_allclose(first["C"], c_ft, atol=1e-6)
    assert first["Gamma"] == pytest.approx(np.degrees(float(case.impact.normal_angle)))
    assert len(first["delta_v"]) == 2 and len(first["pdof"]) == 2
    assert first["energy_loss"] > 0 and first["units"]["energy"] == "ft lbf"
    assert first["law"] and first["coefficients"]
    assert [r["vehicle"] for r in data["rest"]] == [1, 2]
    assert data["rest"][0]["units"] == {"length": "ft", "angle": "deg"}
    check = data["crosscheck"]                   # the analytic event against pymunk's
    assert (check["units"]["length"], check["units"]["speed"]) == ("ft", "mph")
    assert check["sources"] == ["analytic", "simulated"]
    assert len(check["rest_position"]) == 2 and check["same_impacts"]
    assert max(check["rest_position"]) < 3.0      # ft: the two producers agree at rest
    # each impact compared (issue 32 item 3: the difference at each impact), in ft and mph
    assert len(check["impacts"]) == check["impact_count"][0] >= 1
    first = check["impacts"][0]
    assert first["index"] == 1 and first["times"] == pytest.approx([0.0, 0.0], abs=1e-9)
    for key in ("C", "Gamma", "delta_v", "pdof", "position", "heading", "speed_before",
                "speed_after"):
        assert key in first
    assert first["C"] == pytest.approx(0.0, abs=1e-9)   # both solve the case's own C
    assert max(first["speed_before"]) < 0.5              # mph: the same approach


def test_timeline_csv_speaks_the_case_units(run):
    out, data = run
    with open(out / "timeline.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert header[:3] == ["time [s]", "phase", "x1 [ft]"] and "vx1 [mph]" in header
    last = dict(zip(header, rows[-1], strict=True))
    assert float(last["x1 [ft]"]) == pytest.approx(data["rest"][0]["position"][0], rel=1e-9)
    assert rows[1][1] == "approach"


def test_bad_input_writes_nothing(tmp_path, capsys):
    out = tmp_path / "x"
    assert main(["event", "ricsac9", "--out", str(out), "--tyre-friction", "-1"]) == 2
    assert not out.exists()
    assert main(["event", "no-such-case", "--out", str(out)]) == 2
    assert not out.exists()


def test_the_command_says_what_it_writes():
    for name in ("event.mp4", "plan.png", "timeline.csv", "report.html", "--json"):
        assert name in event.help


def test_compare_json_holds_the_event_crosscheck_at_each_impact(tmp_path):
    """`pim compare --json` shows the whole event: its cross-check at each impact and at
    rest, in the case's units (RICSAC 9: ft, mph), as `pim event --json` does."""
    import io
    from contextlib import redirect_stdout

    buf = io.StringIO()
    with redirect_stdout(buf):
        assert main(["compare", "ricsac9", "--out", str(tmp_path / "c"), "--json",
                     "--no-speed-error", "--no-assumptions", "--no-progress"]) == 0
    check = json.loads(buf.getvalue())["event_crosscheck"]
    assert (check["units"]["length"], check["units"]["speed"]) == ("ft", "mph")
    assert check["sources"] == ["analytic", "simulated"] and check["same_impacts"]
    assert len(check["impacts"]) == check["impact_count"][0] >= 1
    assert check["impacts"][0]["index"] == 1 and len(check["impacts"][0]["position"]) == 2
    assert max(check["rest_position"]) < 3.0                   # ft
