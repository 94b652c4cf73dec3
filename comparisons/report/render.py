"""The Markdown and CSV renderers of a :class:`~comparisons.report.document.Document`.

Pure functions of the document (no simulation, no file system): :func:`render_markdown`
writes ``report.md``, :func:`render_csv` one CSV per table (full precision; None and NaN as
empty cells). This module is the only place a Markdown table is built
(:func:`markdown_table`; tests/meta/test_report_pipeline.py fails on one built anywhere
else). The HTML renderer is :mod:`comparisons.report.html`; :mod:`comparisons.report.write`
writes all three.
"""

from __future__ import annotations

import csv
import io
import math

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
from comparisons.report.tables import Table, raw_value

__all__ = ["render_markdown", "render_csv", "markdown_table", "table_csv", "video_line"]


def _escape(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def markdown_table(table: Table) -> str:
    """A GitHub-flavoured Markdown table of ``table``'s cells (numbers right-aligned)."""
    align = ["---:" if n else ":---" for n in table.numeric()]
    lines = ["| " + " | ".join(_escape(c) for c in table.columns) + " |",
             "|" + "|".join(align) + "|"]
    lines += ["| " + " | ".join(_escape(c) for c in row) + " |" for row in table.cells()]
    return "\n".join(lines)


def _csv_cell(v):
    """A raw value as a CSV cell: floats at full precision, yes/no, None and NaN empty."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    if isinstance(v, bool):
        return "yes" if v else "no"
    return repr(float(v)) if isinstance(v, float) else v


def table_csv(table: Table) -> str:
    """CSV text of ``table`` (full precision; None and NaN as empty cells)."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(table.columns)
    for row in table.rows:
        writer.writerow([_csv_cell(raw_value(v)) for v in row])
    return buf.getvalue()


def render_csv(doc: Document) -> dict[str, str]:
    """The CSV files of the document's tables: file name -> text."""
    return {f"{t.name}.csv": table_csv(t) for t in doc.tables() if t.csv}


def video_line(video: Video) -> str:
    """The video's frames, rate, duration and size in words ("video" when not stated)."""
    if not video.frames or not video.fps:
        return "video"
    size = f", {video.size[0]} x {video.size[1]} px" if video.size else ""
    return f"{video.frames} frames at {video.fps:g} fps, {video.frames / video.fps:.2f} s{size}"


def _table(table: Table) -> list[str]:
    if not table.show:
        return []
    head = f"**{table.title}**" + (f" ([{table.name}.csv]({table.name}.csv))"
                                   if table.csv else "")
    lines = [head, ""]
    if table.note:
        lines += [table.note, ""]
    return lines + [markdown_table(table), ""]


def _block(block) -> list[str]:
    """The Markdown lines of one block (blank line after)."""
    if isinstance(block, Table):
        return _table(block)
    if isinstance(block, Paragraph):
        return [block.text, ""]
    if isinstance(block, Bullets):
        return [f"- {item}" for item in block.items] + [""]
    if isinstance(block, Callout):
        return [f"**{block.title}:**", ""] + [f"- {item}" for item in block.items] + [""]
    if isinstance(block, Cards):
        return [f"- **{c.label}: {c.value}**" + (f" ({c.note})" if c.note else "")
                for c in block.cards] + [""]
    if isinstance(block, Figure):
        return [f"![{block.alt}]({block.path})", ""] + (
            [f"*{block.caption}*", ""] if block.caption else [])
    if isinstance(block, Video):
        return [f"[{block.path}]({block.path}) ({video_line(block)}). {block.caption}", ""]
    if isinstance(block, Code):
        return ["```", block.text, "```", ""]
    if isinstance(block, FileList):
        return [f"- [{p}]({p})" for p in block.paths] + [""]
    raise TypeError(f"not a report block: {block!r}")


def _section(section: Section) -> list[str]:
    lines = [f"## {section.title}", ""]
    for block in section.blocks:
        lines += _block(block)
    return lines


def render_markdown(doc: Document) -> str:
    """The text of ``NAME.md``: the title, the subtitle, each section with its blocks."""
    lines = [f"# {doc.title}", ""]
    if doc.subtitle:
        lines += [doc.subtitle, ""]
    for section in doc.sections:
        lines += _section(section)
    return "\n".join(lines).rstrip("\n") + "\n"
