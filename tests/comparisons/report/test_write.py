"""The one writer of the reports (comparisons.report.write): the CSVs, the page and the
Markdown, all or an error before any file when a figure is missing."""

import pytest

from comparisons.report.document import Document, Figure, Section
from comparisons.report.tables import Table
from comparisons.report.write import document_files, write_document

DOC = Document("t", "pim test", (Section("s", "S", (
    Table("a", "A", ("x",), ((1.5,),)), Table("b", "B", ("x",), ((2.0,),), csv=False))),),
    name="study")


def test_the_files_of_a_document():
    assert document_files(DOC) == ["a.csv", "study.html", "study.md"]
    assert document_files(DOC, html=False) == ["a.csv", "study.md"]


def test_written_in_order_markdown_last(tmp_path):
    written = write_document(DOC, tmp_path)
    assert [p.name for p in written] == document_files(DOC)
    assert (tmp_path / "a.csv").read_text() == "x\n1.5\n"
    assert "**B**" in (tmp_path / "study.md").read_text()
    assert not (tmp_path / "b.csv").exists()


def test_a_missing_figure_writes_nothing(tmp_path):
    doc = Document("t", "pim test", (Section("s", "S", (Figure("f.png", alt="f"),)),))
    with pytest.raises(FileNotFoundError, match="f.png"):
        write_document(doc, tmp_path)
    assert list(tmp_path.iterdir()) == []
