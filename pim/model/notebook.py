"""How results read in a notebook: an HTML table in the case's units, a dict, a DataFrame.

Each result type (:class:`pim.Result`, :class:`pim.analysis.fitting.FitResult`,
:class:`pim.analysis.montecarlo.UncertaintyResult`,
:class:`pim.analysis.reconstruction.Reconstruction`) says what it shows as a :class:`Table`
(its ``display_table(units=None)``: numbers in the display units, the case's by default); the
:class:`Notebook` mixin turns that one table into Jupyter's ``_repr_html_`` (numbers in the
reports' format, :mod:`pim.model.number_format`) and into ``to_frame()``, a pandas DataFrame
of the same numbers unrounded (pandas is optional: imported there, and only there).
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass

import numpy as np

from .number_format import format_number

__all__ = ["Table", "html_table", "frame", "Notebook", "short"]


@dataclass(frozen=True)
class Table:
    """What a result shows: a title, column names, rows of cells, notes under it.

    Attributes
    ----------
    title : str
    columns : tuple of str
        The first column names the rows (the DataFrame's index).
    rows : tuple of tuple
        Cells: text, or numbers in the display units (None or NaN: blank).
    notes : tuple of str
        Lines under the table (the units, what was left out).
    """

    title: str
    columns: tuple
    rows: tuple
    notes: tuple = ()


def _cell(value) -> str:
    if isinstance(value, float | np.floating) and not math.isfinite(value):
        return "" if math.isnan(value) else str(float(value))
    return html.escape(format_number(value) if not isinstance(value, str) else value)


def html_table(table: Table) -> str:
    """``table`` as an HTML table (caption, header, one row per row, notes below): what
    Jupyter shows of a result."""
    head = "".join(f"<th>{html.escape(c)}</th>" for c in table.columns)
    body = "".join("<tr>" + "".join(f"<td>{_cell(v)}</td>" for v in row) + "</tr>"
                   for row in table.rows)
    notes = "".join(f"<p>{html.escape(n)}</p>" for n in table.notes)
    return (f"<div><table><caption>{html.escape(table.title)}</caption>"
            f"<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{notes}</div>")


def frame(table: Table):
    """``table`` as a pandas DataFrame indexed by its first column (numbers unrounded).

    Raises
    ------
    ImportError
        pandas is not installed (``to_dict()`` gives the same numbers).
    """
    try:
        import pandas as pd
    except ImportError:
        raise ImportError("to_frame() needs pandas (pip install pandas); to_dict() gives "
                          "the same numbers without it") from None
    rows = [[None if isinstance(v, float) and math.isnan(v) else v for v in row]
            for row in table.rows]
    return pd.DataFrame(rows, columns=list(table.columns)).set_index(table.columns[0])


class Notebook:
    """Mixin: ``_repr_html_`` and ``to_frame()`` of the class's ``display_table(units=None)``."""

    def display_table(self, units=None) -> Table:       # pragma: no cover - each class has its own
        raise NotImplementedError

    def _repr_html_(self) -> str:
        return html_table(self.display_table())

    def to_frame(self, units=None):
        """The numbers of the result's table (:meth:`display_table`) as a pandas DataFrame, in
        ``units`` (a :class:`pim.model.display.DisplayUnits` or "si"/"us"; default the
        case's). Needs pandas."""
        return frame(self.display_table(units))


def short(value, unit: str = "") -> str:
    """A number as a repr shows it: 4 significant digits, then its unit."""
    return f"{format_number(float(value))}{' ' + unit if unit else ''}"
