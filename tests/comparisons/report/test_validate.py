"""The report of `pim validate` (comparisons.report.validate) on a hand-made Validation: typed
tables in the user's units, the summary first, the method and sources last, the figures
inline. The command's run on the bundled data is in tests/pim_cli/test_validate.py."""

from matplotlib.figure import Figure

from comparisons.report.render import render_markdown
from comparisons.report.tables import Num, Table
from comparisons.report.validate import (
    METHOD,
    Validation,
    consistency_table,
    validation_document,
    write_validation,
)


def test_the_document_and_its_files(tmp_path):
    fig = Figure(figsize=(2, 1))
    fig.subplots()
    v = Validation("ricsac", "us", summary=["ricsac: 11 tests checked"],
                   tables=[Table("consistency", "RICSAC momentum consistency", ("test", "x"),
                                 (("RICSAC 1", Num(1.234, 1)),))],
                   figures={"coefficients": fig})
    doc = validation_document(v)
    assert [s.id for s in doc.sections] == ["summary", "consistency", "figures", "method",
                                            "sources"]
    text = render_markdown(doc)
    assert "- ricsac: 11 tests checked" in text and "| RICSAC 1 | 1.2 |" in text
    assert METHOD["Sources"][0] in text
    files = write_validation(v, tmp_path)
    assert [f.name for f in files] == ["report.md", "consistency.csv", "report.html",
                                       "coefficients.png"]
    assert (tmp_path / "consistency.csv").read_text() == "test,x\nRICSAC 1,1.234\n"


def test_consistency_flags_are_yes_or_no_in_the_csv():
    from types import SimpleNamespace

    check = SimpleNamespace(test="RICSAC 4", impulse_ratio=0.1234, linear_imbalance=None,
                            arm1=1.0, arm2=2.0, flagged=True, reasons=["imbalance"])
    table = consistency_table([check])
    assert table.cells()[0] == ["RICSAC 4", "12.3", "", "1.00", "2.00", "yes", "imbalance"]
