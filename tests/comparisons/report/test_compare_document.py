"""The report of `pim compare` as a typed document (comparisons.report.compare_document), built
from a hand-made ReportData (no simulation): the answer first, the sections in order, failures
and skips said in words, the files listed. The gathered report is in test_compare.py and the
RICSAC 9 defects of issue 28 in test_compare_tables.py."""

import pytest

import pim
import sim
from comparisons.report.compare_document import REPORT_NAME, compare_document
from comparisons.report.compare_tables import results_table
from comparisons.report.data import ReportData
from comparisons.report.document import Callout, Cards, FileList
from comparisons.report.render import render_markdown
from comparisons.report.tables import Table
from pim.analysis.misfit import misfit


@pytest.fixture
def data():
    case = pim.load_case("ricsac9")
    result = pim.solve(case, 0.2, 0.9)
    d = ReportData(case, "cases/my case.toml", "si", 0.2, 0.9,
                   {"eps": "case file", "beta": "case file"}, result, misfit=misfit(result),
                   sim_error=sim.SimulationError("no_contact", "the bodies never touched"),
                   animation_requested=False, files=["plots/a.png"], plot_files=["plots/a.png"],
                   seconds={"fit": 0.5})
    d.add_table(results_table(result, "si"))
    d.add_table(Table("inputs", "Case inputs", ("field", "value"), (("mass 1", 1000.0),)))
    return d


def test_the_answer_comes_first_then_the_fit_and_the_coefficients(data):
    doc = compare_document(data)
    assert [s.id for s in doc.sections] == ["results", "coefficients", "inputs", "plots",
                                            "animation", "crosscheck", "files"]
    first = doc.sections[0].blocks
    assert isinstance(first[0], Cards) and first[0].cards[0].label == "delta-V, vehicle 1"
    assert isinstance(first[1], Callout) and "The fit is poor" in first[1].items[-1]


def test_the_misfit_section_appears_with_its_table(data):
    from comparisons.report.compare_tables import misfit_table

    data.add_table(misfit_table(data.misfit, "si"))
    ids = [s.id for s in compare_document(data).sections]
    assert ids[:3] == ["results", "misfit", "coefficients"]


def test_failures_and_skips_are_said_in_words(data):
    text = render_markdown(compare_document(data))
    assert "The simulation failed (no_contact): the bodies never touched" in text
    assert "(not written: --no-animation)" in text
    assert "epsilon from the case file, beta from the case file (no fit)." in text
    assert "Timings: fit 0.50 s" in text
    assert "The case has no `[uncertainty]` table: no intervals" not in text   # it has one


def test_files_list_the_figures_the_tables_and_both_reports(data):
    doc = compare_document(data)
    (files,) = [b for b in doc.sections[-1].blocks if isinstance(b, FileList)]
    assert files.paths == ("inputs.csv", "plots/a.png", "report.html", REPORT_NAME,
                           "results.csv")
