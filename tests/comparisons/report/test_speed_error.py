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
