"""The report of `pim hard-cases` (comparisons.report.hard_cases), on a stand-in study (the
real one sweeps every hard case: tests/comparisons/studies/test_hard_cases.py)."""

from types import SimpleNamespace

from comparisons.report.hard_cases import COMMAND, hard_cases_document, write_hard_cases
from comparisons.report.render import render_markdown
from comparisons.report.tables import Table


def study():
    case = SimpleNamespace(name="hard-x", description="a hard case",
                           needs_text=lambda: "30 iterations", outline_text=lambda: "1e-3")
    return SimpleNamespace(
        cases=(case,),
        results_table=lambda units="si": Table("hard-cases", "Results", ("case", "t [ms]"),
                                               (("hard-x", 4.2e-05),)),
        needs_table=lambda: Table("hard-cases-needs", "Needs", ("case",), (("hard-x",),)))


def test_the_document_and_its_files(tmp_path):
    text = render_markdown(hard_cases_document(study()))
    assert f"```\n{COMMAND}\n```" in text and "| hard-x | 4.2e-05 |" in text
    assert "- **hard-x** (a hard case): 30 iterations; outline contact 1e-3." in text
    files = write_hard_cases(study(), tmp_path)
    assert [f.name for f in files] == ["hard-cases.md", "hard-cases.csv",
                                       "hard-cases-needs.csv", "hard-cases.html"]
