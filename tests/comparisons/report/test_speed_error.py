"""The report of `pim speed-error` (comparisons.report.speed_error) on a small sweep: the
recommendation line the committed docs/speed-error-ricsac9.md is read by, the Pareto front
and every run as tables (every run in full precision in the CSV), the figure beside it."""

import re

import pytest

import pim
from comparisons.report.render import render_markdown
from comparisons.report.speed_error import speed_error_document, write_speed_error
from comparisons.studies.speed_error import sweep


@pytest.fixture(scope="module")
def study():
    return sweep(pim.load_case("hard-pole"), dts=(1e-3, 1e-4), iterations=(None,),
                 repeats=1, progress=False)


def test_the_document_states_the_recommendation_as_the_docs_test_reads_it(study):
    text = render_markdown(speed_error_document(study, "hard-pole", "pim speed-error x"))
    assert "```\npim speed-error x\n```" in text
    rec = study.recommended()
    assert rec is not None
    m = re.search(r"\*\*Recommended: dt = ([0-9.e-]+) s, (\w+) iterations.*?(exact|detected) "
                  r"start, (point|outline) contact\*\* -- error ([0-9.e+-]+)", text)
    assert m and float(m.group(1)) == rec.dt and m.group(2) == "automatic"
    assert "## Pareto front" in text and "## Every run" in text
    assert not re.search(r"(?<![\d.])0\.0000", text)          # no 0.0000 ms


def test_the_files_are_written_through_the_pipeline(study, tmp_path):
    files = write_speed_error(study, tmp_path, "hard-pole")
    assert [f.name for f in files] == ["speed-error-hard-pole.md",
                                       "speed-error-hard-pole-pareto.csv",
                                       "speed-error-hard-pole.csv",
                                       "speed-error-hard-pole.html",
                                       "speed-error-hard-pole.png"]
    rows = (tmp_path / "speed-error-hard-pole.csv").read_text().splitlines()
    assert len(rows) == 1 + len(study.points)
    page = (tmp_path / "speed-error-hard-pole.html").read_text()
    assert page.count("data:image/png;base64,") == 1 and 'id="table-speed-error-hard-pole"' \
        in page


def test_the_json_and_the_line_of_the_rigid_sweep(study):
    from comparisons.report.speed_error import speed_error_json, speed_error_line

    rec = study.recommended()
    data = speed_error_json(study, "hard-pole")
    assert list(data) == ["case", "files", "recommended", "analytic_time",
                          "analytic_batch_time"]
    assert data["recommended"]["dt"] == rec.dt and data["recommended"]["iterations"] is None
    line = speed_error_line(study, "hard-pole")
    assert line.startswith(f"hard-pole: recommended dt = {rec.dt:g} s, iterations = auto, ")
    assert f"{rec.wall_time * 1e3:.3g} ms/impact (PIM " in line


def test_the_json_and_lines_of_the_finite_duration_sweep():
    from comparisons.report.speed_error import compliant_json, compliant_summary
    from comparisons.studies import speed_error_compliant as S

    cstudy = S.compliant_sweep(pim.load_case("ricsac9"), 0.355, grid=S.Grid(
        steps=(10, 40), rtols=(1e-3,), methods=("DOP853",), repeats=1),
        scenes={"frictionless": 0.0}, progress=False)
    data = compliant_json(cstudy)
    assert set(data) == {"compliant", "compliant_seconds"}
    assert list(data["compliant"]) == ["frictionless"]
    (line,) = compliant_summary(cstudy, "ricsac9")
    rec = cstudy.recommended("frictionless")
    assert line == ("ricsac9 finite-duration (frictionless): no run reaches 1e-3" if rec is None
                    else f"ricsac9 finite-duration (frictionless): recommended {rec.label}: "
                         f"error {rec.error:.1e}, {rec.wall_time * 1e3:.3g} ms/impact")


def test_the_whole_events_study_is_written_through_the_pipeline(tmp_path):
    from comparisons.report.speed_error import (
        event_speed_document,
        event_speed_json,
        event_speed_line,
        write_event_speed,
    )
    from comparisons.studies.event_speed_error import event_sweep
    from sim.event_check import side_slap_case

    study = event_sweep(side_slap_case(1.6, eps=0.3, beta=0.5), dts=(1e-3,),
                        iterations=(30,), analytic_steps=(0.004,), progress=False,
                        reference={"dt": 5e-4, "iterations": 30})
    text = render_markdown(event_speed_document(study, "slap", "pim speed-error x --event"))
    assert "Fastest run reaching the target error" in text and "## Every run" in text
    files = write_event_speed(study, tmp_path, "slap")
    assert [f.name for f in files] == ["speed-error-event-slap.md",
                                       "speed-error-event-slap-pareto.csv",
                                       "speed-error-event-slap.csv",
                                       "speed-error-event-slap.html",
                                       "speed-error-event-slap.png"]
    data = event_speed_json(study)["event"]
    assert data["recommended"]["analytic"]["step"] == 0.004
    assert "analytic step=0.004" in event_speed_line(study, "slap")
