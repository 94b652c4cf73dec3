"""The renderers of comparisons.report.render: pure functions of a hand-built ReportData
(no simulation, no files). A failed simulation and a skipped animation are said in words,
every table becomes its CSV. The renderers on a gathered report (and the quoted case path
of the suggested commands) are in tests/comparisons/report/test_compare.py."""

import pytest

import pim
import sim
from comparisons.report.data import ReportData
from comparisons.report.render import REPORT_NAME, md_table, render_csv, render_markdown
from comparisons.report.tables import Table


@pytest.fixture
def data():
    case = pim.load_case("ricsac9")
    d = ReportData(case, "cases/my case.toml", "si", 0.2, 0.9,
                   {"eps": "case file", "beta": "case file"}, pim.solve(case, 0.2, 0.9),
                   sim_error=sim.SimulationError("no_contact", "the bodies never touched"),
                   animation_requested=False, files=["results.csv", "inputs.csv"],
                   seconds={"fit": 0.5})
    d.add_table(Table("results", "Post-impact motion", ("quantity", "value [m/s]"),
                      (("speed 1", 3.25),)))
    d.add_table(Table("inputs", "Case inputs", ("field", "value"), (("mass 1", 1000.0),)))
    return d


def test_markdown_has_every_section_in_order(data):
    text = render_markdown(data)
    heads = [line for line in text.splitlines() if line.startswith("#")]
    assert heads == ["# ricsac9: reconstruction report", "## Results", "## Coefficients",
                     "## Case inputs", "## The design sheet's plots", "## Animation",
                     "## Appendix A: PIM against a pymunk simulation", "## Files"]


def test_failures_and_skips_are_said_in_words(data):
    text = render_markdown(data)
    assert "The simulation failed (no_contact): the bodies never touched" in text
    assert "(not written: --no-animation)" in text
    assert "epsilon from the case file, beta from the case file (no fit)." in text
    assert "Timings: fit 0.50 s" in text


def test_files_list_the_report_itself_and_link_each_csv(data):
    text = render_markdown(data)
    for rel in ("inputs.csv", "results.csv", REPORT_NAME):
        assert f"- [{rel}]({rel})" in text
    assert md_table(data.tables["results"]).startswith(
        "**Post-impact motion** ([results.csv](results.csv))")


def test_csv_is_one_file_per_table(data):
    files = render_csv(data)
    assert list(files) == ["results.csv", "inputs.csv"]
    assert files["results.csv"].splitlines() == ["quantity,value [m/s]", "speed 1,3.25"]

