"""The table of docs/inertia-estimate.md: each body class's yaw dynamic index, its scatter
and the held-out check, written from NHTSA's measured vehicles
(:mod:`pim.io.inertia_data`) by ``python -m comparisons.docs inertia-estimate``.

The table sits between :data:`BEGIN` and :data:`END` in docs/inertia-estimate.md (the rest
of the page is prose); it is a :class:`~comparisons.report.tables.Table` rendered by the
one Markdown renderer and written by :func:`comparisons.report.write.write_block`. A test
fails when the page differs from what the code gives.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.render import markdown_table
from comparisons.report.tables import Num, Table
from comparisons.report.write import write_block
from pim.io.inertia_data import dynamic_indices, held_out

__all__ = ["COMMAND", "BEGIN", "END", "PAGE", "index_table", "block", "regenerate"]

COMMAND = "python -m comparisons.docs inertia-estimate"
BEGIN = (f"<!-- inertia-estimate: begin (written by `{COMMAND}`; edit "
         "comparisons/docs/inertia_estimate.py, not this table) -->")
END = "<!-- inertia-estimate: end -->"
#: The page of docs/ that holds the table.
PAGE = "inertia-estimate.md"


def index_table() -> Table:
    """Per body class: vehicles, the mean yaw dynamic index D, its sd, the predictive sd,
    the relative sd, and how many held-out vehicles lie within 1.96 predictive sd
    (:func:`pim.io.inertia_data.held_out`) with the sd of their standardised errors."""
    rows = []
    for body, d in dynamic_indices().items():
        inside, n, z_sd = held_out(body)
        rows.append((body, d.count, Num(d.mean, 4), Num(d.sd, 4), Num(d.predictive_sd, 4),
                     Num(100 * d.relative_sd, 1), inside, Num(100 * inside / n, 0),
                     Num(z_sd, 2)))
    return Table("inertia-estimate", "The yaw dynamic index per body class",
                 ("body", "vehicles", "mean D [-]", "sd of D [-]", "predictive sd [-]",
                  "relative (1 sd) [%]", "held out: within 1.96 sd", "held out: within [%]",
                  "sd of held-out z [-]"), tuple(rows), csv=False)


def block() -> str:
    """The generated block of docs/inertia-estimate.md, markers included."""
    return "\n".join([BEGIN, "", markdown_table(index_table()), "", END])


def regenerate(docs_dir) -> list[Path]:
    """Rewrite the table of ``docs_dir/inertia-estimate.md`` (between the markers)."""
    return [write_block(Path(docs_dir) / PAGE, BEGIN, END, block())]
