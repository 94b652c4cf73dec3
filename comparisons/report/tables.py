"""Tables of the comparisons as data, written as CSV and rendered as Markdown.

A :class:`Table` holds raw values (floats stay floats in the CSV, at full precision); the
Markdown rendering formats them for reading (6 significant digits, errors as 1.2e-07).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from pim.io.files import write_text

__all__ = ["Table", "fmt_value", "fmt_error"]


def fmt_value(x) -> str:
    """A number to 6 significant digits; None/NaN as an empty cell; text unchanged."""
    if x is None:
        return ""
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if math.isnan(x):
            return ""
        return f"{x:.6g}"
    return str(x)


def fmt_error(x) -> str:
    """An error as 1.23e-07 (0 as 0; None/NaN as an em dash: not defined)."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    if isinstance(x, str):
        return x
    if x == 0:
        return "0"
    return f"{x:.2e}"


@dataclass(frozen=True)
class Table:
    """A titled table: column names, rows of values, and per-column Markdown formatters.

    Attributes
    ----------
    name : str
        File stem of the CSV (``name.csv``).
    title : str
        Caption in the report.
    columns : tuple of str
        Column headers (units in brackets).
    rows : tuple of tuple
        Raw values (float, int, str or None).
    formats : dict
        Column name -> function formatting a value for Markdown (default :func:`fmt_value`).
    """

    name: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple, ...]
    formats: dict[str, Callable] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for row in self.rows:
            if len(row) != len(self.columns):
                raise ValueError(f"table {self.name}: a row has {len(row)} cells for "
                                 f"{len(self.columns)} columns")

    def column(self, name: str) -> list:
        """The raw values of one column."""
        i = self.columns.index(name)
        return [row[i] for row in self.rows]

    def to_csv(self) -> str:
        """CSV text (full precision; None and NaN as empty cells)."""
        buf = io.StringIO()
        writer = csv.writer(buf, lineterminator="\n")
        writer.writerow(self.columns)
        for row in self.rows:
            writer.writerow(["" if v is None or (isinstance(v, float) and math.isnan(v))
                             else repr(v) if isinstance(v, float) else v for v in row])
        return buf.getvalue()

    def write_csv(self, out_dir) -> Path:
        """Write ``out_dir/name.csv`` atomically."""
        return write_text(Path(out_dir) / f"{self.name}.csv", self.to_csv())

    def to_markdown(self, align: Sequence[str] | None = None) -> str:
        """A GitHub-flavoured Markdown table (numbers right-aligned)."""
        cells = [[self.formats.get(c, fmt_value)(v) for c, v in zip(self.columns, row,
                                                                     strict=True)]
                 for row in self.rows]
        if align is None:
            align = ["---:" if any(isinstance(r[i], int | float) and not isinstance(r[i], bool)
                                   for r in self.rows) else ":---"
                     for i in range(len(self.columns))]
        header = (c.replace("|", "\\|") for c in self.columns)
        lines = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
        lines += ["| " + " | ".join(c.replace("|", "\\|") for c in row) + " |" for row in cells]
        return "\n".join(lines)
