"""The HTML renderer of a :class:`~comparisons.report.document.Document`: one self-contained
page (``report.html``) beside the Markdown.

Built on the blocks of :mod:`pim.io.html`: figures inlined as PNG, videos playable in the page
(base64 MP4, a still frame for print), every text escaped. A table with column groups
(:attr:`comparisons.report.tables.Table.groups`) is shown as one table per group, each one
screen wide and led by the first column; figures that follow each other sit side by side
where the page has room for them at their own width. The figures and videos are read from
the report's folder; nothing else is touched.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.document import (
    Bullets,
    Callout,
    Cards,
    Code,
    Document,
    Figure,
    FileList,
    Paragraph,
    Section,
    Video,
)
from comparisons.report.tables import Table, cell_text
from pim.io import html as h

__all__ = ["render_html", "html_table", "HTML_NAME"]

#: File name of the HTML report.
HTML_NAME = h.HTML_REPORT_NAME


def _note(table: Table) -> str:
    csv = f"CSV: `{table.name}.csv`" if table.csv else ""
    return "; ".join(t for t in (csv, table.note) if t)


def html_table(table: Table) -> str:
    """``table`` as HTML (cells as in the Markdown), its id ``table-NAME``; with column
    groups, one table per group with ids ``table-NAME-1``, ``table-NAME-2`` ..."""
    numeric = table.numeric()
    if not table.groups:
        return h.table(table.columns, table.cells(), title=table.title, note=_note(table),
                       numeric=numeric, id=f"table-{table.name}")
    parts = []
    for i, (caption, cols) in enumerate(h.split_columns(table.columns, table.groups,
                                                        table.columns[0]), start=1):
        index = [table.columns.index(c) for c in cols]
        rows = [[cell_text(table, table.columns[j], row[j]) for j in index]
                for row in table.rows]
        parts.append(h.table(cols, rows, title=caption, note=_note(table) if i == 1 else "",
                             numeric=[numeric[j] for j in index],
                             id=f"table-{table.name}-{i}", cls="split"))
    return "\n".join(parts)


def _block(block, folder: Path) -> str:
    """The HTML of one block (figures and videos read from ``folder``)."""
    if isinstance(block, Table):
        return html_table(block) if block.show else ""
    if isinstance(block, Paragraph):
        return h.paragraph(block.text)
    if isinstance(block, Bullets):
        return h.bullets(block.items)
    if isinstance(block, Callout):
        return h.callout(block.title, block.items)
    if isinstance(block, Cards):
        return h.facts((c.label, c.value, c.note) for c in block.cards)
    if isinstance(block, Figure):
        return h.figure(folder / block.path, alt=block.alt, caption=block.caption)
    if isinstance(block, Video):
        mp4 = folder / block.path
        return h.video(mp4, caption=f"{block.caption} File: `{block.path}`.",
                       frames=block.frames, fps=block.fps, size=block.size,
                       still=h.still_frame(mp4, block.still_at))
    if isinstance(block, Code):
        return h.code(block.text)
    if isinstance(block, FileList):
        return h.links(block.paths)
    raise TypeError(f"not a report block: {block!r}")


def _section(section: Section, folder: Path) -> str:
    """A section; figures that follow each other share one grid."""
    pieces, figures = [], []
    for block in (*section.blocks, None):
        if isinstance(block, Figure):
            figures.append(_block(block, folder))
            continue
        if figures:
            pieces.append(h.grid(figures))
            figures = []
        if block is not None and (piece := _block(block, folder)):
            pieces.append(piece)
    return h.section(section.title, pieces, id=section.id, cls="keep" if section.keep else "")


def render_html(doc: Document, folder) -> str:
    """The text of ``NAME.html``: ``doc`` rendered, its figures and videos read from
    ``folder`` (the report's folder) and inlined."""
    folder = Path(folder)
    return h.page(doc.title, [_section(s, folder) for s in doc.sections],
                  subtitle=doc.subtitle,
                  contents=[(s.id, s.toc or s.title) for s in doc.sections],
                  generator=doc.generator)


