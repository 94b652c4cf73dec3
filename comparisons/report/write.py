"""Write a :class:`~comparisons.report.document.Document`: the one way every command's report
reaches the disk.

:func:`write_document` writes one CSV per table, ``NAME.html`` (one self-contained page,
:mod:`comparisons.report.html`) and ``NAME.md`` (:mod:`comparisons.report.render`), each
atomically, into a folder the caller owns (usually the temporary folder of
:func:`pim.io.output.output_folder`, swapped in whole at the end). The figures and videos the
document shows must already be in that folder.

The generated parts of hand-written pages of docs/ (a block between two markers, its tables
rendered by :func:`comparisons.report.render.markdown_table`) reach the disk through
:func:`write_block`.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.document import Document
from comparisons.report.html import render_html
from comparisons.report.render import render_csv, render_markdown, table_csv
from pim.io.files import write_text

__all__ = ["write_document", "document_files", "write_table_csv", "replace_block",
           "write_block"]


def document_files(doc: Document, html: bool = True) -> list[str]:
    """The names of the files :func:`write_document` writes for ``doc``: its CSVs, then
    ``NAME.html`` (with ``html``) and ``NAME.md``."""
    return ([f"{t.name}.csv" for t in doc.tables() if t.csv]
            + ([f"{doc.name}.html"] if html else []) + [f"{doc.name}.md"])


def write_document(doc: Document, folder, html: bool = True) -> list[Path]:
    """Write ``doc``'s CSVs, ``NAME.html`` (unless ``html`` is False) and ``NAME.md`` (last)
    into ``folder``; return their paths in that order.

    Raises
    ------
    FileNotFoundError
        A figure or video the document shows is not in ``folder``.
    """
    folder = Path(folder)
    missing = [p for p in doc.media() if not (folder / p).is_file()]
    if missing:
        raise FileNotFoundError(f"{doc.generator}: the report shows {', '.join(missing)}, "
                                f"which {folder} does not hold")
    written = [write_text(folder / name, text) for name, text in render_csv(doc).items()]
    if html:
        written.append(write_text(folder / f"{doc.name}.html", render_html(doc, folder)))
    written.append(write_text(folder / f"{doc.name}.md", render_markdown(doc)))
    return written


def write_table_csv(table, folder) -> Path:
    """Write ``folder/NAME.csv``, the table's CSV (:func:`render.table_csv`), atomically."""
    return write_text(Path(folder) / f"{table.name}.csv", table_csv(table))


def replace_block(text: str, begin: str, end: str, block: str, where: str = "the text") -> str:
    """``text`` with its part from the marker ``begin`` to the marker ``end`` (both
    included) replaced by ``block`` (which holds the markers again).

    Raises
    ------
    ValueError
        ``text`` does not hold each marker exactly once, ``end`` after ``begin``.
    """
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(end) < text.index(begin):
        raise ValueError(f"{where} must hold the generated block's markers once each, "
                         f"{begin!r} before {end!r}")
    head, rest = text.split(begin)
    return head + block + rest.split(end, 1)[1]


def write_block(path, begin: str, end: str, block: str, source=None) -> Path:
    """Write ``path``: the page ``source`` (default ``path`` itself) with its generated
    block replaced (:func:`replace_block`), atomically. The rest of the page is kept as
    written."""
    source = Path(path if source is None else source)
    text = source.read_text(encoding="utf-8")
    return write_text(Path(path), replace_block(text, begin, end, block, str(source)))
