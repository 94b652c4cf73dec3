"""Tables of the reports as data: raw values, written at full precision in the CSV and
formatted for reading by the renderers (:mod:`comparisons.report.render`,
:mod:`comparisons.report.html`) in the one number format
(:mod:`pim.model.number_format`).

A cell is a float, an int, a bool, a string, None (empty) or a :class:`Num` (a number that
states how many digits it shows, e.g. those its interval allows).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from pim.model.number_format import SIGNIFICANT, format_number

__all__ = ["Table", "Num", "fmt_value", "fmt_error", "cell_text", "raw_value", "is_numeric"]


@dataclass(frozen=True)
class Num:
    """A table cell holding a number and how many digits it shows.

    Attributes
    ----------
    value : float
        The value, at full precision (what the CSV holds).
    decimals : int or None
        Decimal places shown (:func:`pim.model.number_format.interval_decimals`),
        or None for ``sig`` significant digits.
    sig : int
        Significant digits when ``decimals`` is None.
    """

    value: float
    decimals: int | None = None
    sig: int = SIGNIFICANT

    def __str__(self) -> str:
        return format_number(self.value, sig=self.sig, decimals=self.decimals)


def fmt_value(x) -> str:
    """A cell as text: a number in the one format (4 significant digits); None/NaN as an
    empty cell; yes/no; text unchanged."""
    if isinstance(x, Num):
        return str(x)
    return format_number(x)


def fmt_error(x) -> str:
    """An error with two significant digits (0 as 0; None/NaN as an em dash: not
    defined)."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    if isinstance(x, str):
        return x
    return format_number(x, sig=2)


def raw_value(x):
    """A cell's value at full precision (a :class:`Num`'s value)."""
    return x.value if isinstance(x, Num) else x


def is_numeric(x) -> bool:
    """Whether a cell holds a number (right-aligned)."""
    x = raw_value(x)
    return isinstance(x, int | float) and not isinstance(x, bool)


@dataclass(frozen=True)
class Table:
    """A titled table: column names, rows of values, and per-column formatters.

    Attributes
    ----------
    name : str
        File stem of the CSV (``name.csv``) and the table's id.
    title : str
        Caption in the report.
    columns : tuple of str
        Column headers (units in brackets).
    rows : tuple of tuple
        Cells (float, int, bool, str, None or :class:`Num`).
    formats : dict
        Column name -> function formatting a cell (default :func:`fmt_value`).
    note : str
        A line under the caption (inline marks allowed).
    groups : tuple
        (caption, column names) pairs: on a screen the table is shown as one table per
        group, each led by the first column (:func:`pim.io.html.split_columns`); empty: one
        table.
    csv : bool
        Written as ``name.csv`` too.
    show : bool
        Shown in the page (False: only written as ``name.csv``, which the page links).
    """

    name: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple, ...]
    formats: dict[str, Callable] = field(default_factory=dict)
    note: str = ""
    groups: tuple = ()
    csv: bool = True
    show: bool = True

    def __post_init__(self) -> None:
        for row in self.rows:
            if len(row) != len(self.columns):
                raise ValueError(f"table {self.name}: a row has {len(row)} cells for "
                                 f"{len(self.columns)} columns")

    def column(self, name: str) -> list:
        """The raw values of one column."""
        i = self.columns.index(name)
        return [raw_value(row[i]) for row in self.rows]

    def cells(self) -> list[list[str]]:
        """Every cell as text, formatted by its column's formatter."""
        return [[cell_text(self, c, v) for c, v in zip(self.columns, row, strict=True)]
                for row in self.rows]

    def numeric(self) -> list[bool]:
        """Per column: whether it holds numbers (right-aligned)."""
        return [any(is_numeric(r[i]) for r in self.rows) for i in range(len(self.columns))]

    def records(self) -> list[dict]:
        """Every row as a dict of column -> raw value (for JSON)."""
        return [{c: raw_value(v) for c, v in zip(self.columns, row, strict=True)}
                for row in self.rows]


def cell_text(table: Table, column: str, value) -> str:
    """One cell of ``table`` as text."""
    if isinstance(value, Num) and column not in table.formats:
        return str(value)
    return table.formats.get(column, fmt_value)(raw_value(value)
                                                if column in table.formats else value)
