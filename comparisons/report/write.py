"""Write a :class:`~comparisons.report.document.Document`: the one way every command's report
reaches the disk.

:func:`write_document` writes one CSV per table, ``NAME.html`` (one self-contained page,
:mod:`comparisons.report.html`) and ``NAME.md`` (:mod:`comparisons.report.render`), each
atomically, into a folder the caller owns (usually the temporary folder of
:func:`pim.io.output.output_folder`, swapped in whole at the end). The figures and videos the
document shows must already be in that folder.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.document import Document
from comparisons.report.html import render_html
from comparisons.report.render import render_csv, render_markdown, table_csv
from pim.io.files import write_text

__all__ = ["write_document", "document_files", "write_table_csv"]


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
