"""The tables of docs/inertia-estimate.md, written by ``python -m comparisons.docs
inertia-estimate``: each body class's yaw dynamic index, its scatter and the held-out check
(NHTSA's measured yaw inertias, :mod:`pim.io.inertia_data`), the mass-only line of each
group with the same checks, each class's CG position a / L with the same checks
(NHTSA's NCAP 2004 measurements, :mod:`pim.io.axle_data`), and each class's line of the
wheelbase on the overall length (Lock's 1993 cars, :mod:`pim.io.length_data`).

Each table sits between its markers in docs/inertia-estimate.md (:data:`BEGIN` / :data:`END`,
:data:`MASS_BEGIN` / :data:`MASS_END`, :data:`LENGTH_BEGIN` / :data:`LENGTH_END` and
:data:`AXLE_BEGIN` / :data:`AXLE_END`; the rest
of the page is prose); each is a
:class:`~comparisons.report.tables.Table` rendered by the one Markdown renderer and written
by :func:`comparisons.report.write.write_block`. A test fails when the page differs from
what the code gives.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.render import markdown_table
from comparisons.report.tables import Num, Table
from comparisons.report.write import write_block
from pim.io.axle_data import axle_fractions
from pim.io.axle_data import held_out as axle_held_out
from pim.io.inertia_data import (
    REGRESSION_GROUPS,
    dynamic_indices,
    held_out,
    mass_held_out,
    mass_regressions,
)
from pim.io.length_data import held_out as length_held_out
from pim.io.length_data import slope_p_value, usable_lines, wheelbase_lines

__all__ = ["COMMAND", "BEGIN", "END", "AXLE_BEGIN", "AXLE_END", "MASS_BEGIN", "MASS_END",
           "LENGTH_BEGIN", "LENGTH_END", "PAGE", "index_table", "axle_table", "mass_table",
           "length_table", "block", "axle_block", "mass_block", "length_block", "regenerate"]

COMMAND = "python -m comparisons.docs inertia-estimate"
BEGIN = (f"<!-- inertia-estimate: begin (written by `{COMMAND}`; edit "
         "comparisons/docs/inertia_estimate.py, not this table) -->")
END = "<!-- inertia-estimate: end -->"
AXLE_BEGIN = (f"<!-- cg-position: begin (written by `{COMMAND}`; edit "
              "comparisons/docs/inertia_estimate.py, not this table) -->")
AXLE_END = "<!-- cg-position: end -->"
MASS_BEGIN = (f"<!-- mass-line: begin (written by `{COMMAND}`; edit "
              "comparisons/docs/inertia_estimate.py, not this table) -->")
MASS_END = "<!-- mass-line: end -->"
LENGTH_BEGIN = (f"<!-- wheelbase-line: begin (written by `{COMMAND}`; edit "
                "comparisons/docs/inertia_estimate.py, not this table) -->")
LENGTH_END = "<!-- wheelbase-line: end -->"
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


def axle_table() -> Table:
    """Per body class: vehicles, which a / L it uses (its own, or all pooled below
    :data:`pim.io.axle_data.MIN_COUNT`), the mean a / L, its sd and predictive sd, and how
    many held-out vehicles lie within 1.96 predictive sd (:func:`pim.io.axle_data.held_out`)
    with the sd of their standardised errors."""
    rows = []
    for body, f in axle_fractions().items():
        inside, n, z_sd = axle_held_out(body)
        rows.append((body, n, "its own" if f.body == body else "all pooled", f.count,
                     Num(f.mean, 4), Num(f.sd, 4), Num(f.predictive_sd, 4), inside,
                     Num(100 * inside / n, 0), Num(z_sd, 2)))
    return Table("cg-position", "The CG's axle position a / L per body class",
                 ("body", "vehicles", "a / L used", "its vehicles", "mean a / L [-]",
                  "sd [-]", "predictive sd [-]", "held out: within 1.96 sd",
                  "held out: within [%]", "sd of held-out z [-]"), tuple(rows), csv=False)


def mass_table() -> Table:
    """Per group of the mass-only line (:data:`pim.io.inertia_data.REGRESSION_GROUPS`): its
    bodies, vehicles, slope, intercept, R^2, relative residual sd, measured masses, and how
    many held-out vehicles lie within 1.96 predictive sd
    (:func:`pim.io.inertia_data.mass_held_out`) with the sd of their standardised errors."""
    rows = []
    for group, line in mass_regressions().items():
        inside, n, z_sd = mass_held_out(group)
        low, high = line.mass_range
        rows.append((group, ", ".join(REGRESSION_GROUPS[group]), n, Num(line.slope, 3),
                     Num(line.intercept, 1), Num(line.r_squared, 3),
                     Num(100 * line.relative_sd, 1), f"{low:.0f}-{high:.0f}", inside,
                     Num(100 * inside / n, 0), Num(z_sd, 2)))
    return Table("mass-line", "The yaw inertia's least-squares line on mass per group",
                 ("group", "body", "vehicles", "slope [m^2]", "intercept [kg m^2]", "R^2 [-]",
                  "relative residual sd [%]", "masses [kg]", "held out: within 1.96 sd",
                  "held out: within [%]", "sd of held-out z [-]"), tuple(rows), csv=False)


def length_table() -> Table:
    """Per body class of the Cars93 data (:mod:`pim.io.length_data`): vehicles, the line of
    wheelbase on overall length (slope, intercept, R^2, residual sd), its lengths, the
    slope's p-value and whether the line is used, and how many held-out vehicles lie within
    1.96 predictive sd (:func:`pim.io.length_data.held_out`) with the sd of their
    standardised errors."""
    rows = []
    for body, line in wheelbase_lines().items():
        inside, n, z_sd = length_held_out(body)
        low, high = line.length_range
        rows.append((body, n, Num(line.slope, 4), Num(line.intercept, 4),
                     Num(line.r_squared, 3), Num(100 * line.sd, 2), f"{low:.2f}-{high:.2f}",
                     f"{slope_p_value(line):.2g}", "yes" if body in usable_lines() else "no",
                     inside, Num(100 * inside / n, 0), Num(z_sd, 2)))
    return Table("wheelbase-line", "The wheelbase's least-squares line on overall length",
                 ("body", "vehicles", "slope [-]", "intercept [m]", "R^2 [-]",
                  "residual sd [cm]", "lengths [m]", "p of the slope", "used",
                  "held out: within 1.96 sd", "held out: within [%]", "sd of held-out z [-]"),
                 tuple(rows), csv=False)


def length_block() -> str:
    """The generated wheelbase-line block of docs/inertia-estimate.md, markers included."""
    return "\n".join([LENGTH_BEGIN, "", markdown_table(length_table()), "", LENGTH_END])


def mass_block() -> str:
    """The generated mass-line block of docs/inertia-estimate.md, markers included."""
    return "\n".join([MASS_BEGIN, "", markdown_table(mass_table()), "", MASS_END])


def axle_block() -> str:
    """The generated CG-position block of docs/inertia-estimate.md, markers included."""
    return "\n".join([AXLE_BEGIN, "", markdown_table(axle_table()), "", AXLE_END])


def block() -> str:
    """The generated block of docs/inertia-estimate.md, markers included."""
    return "\n".join([BEGIN, "", markdown_table(index_table()), "", END])


def regenerate(docs_dir) -> list[Path]:
    """Rewrite the tables of ``docs_dir/inertia-estimate.md`` (each between its markers)."""
    page = Path(docs_dir) / PAGE
    write_block(page, BEGIN, END, block())
    write_block(page, MASS_BEGIN, MASS_END, mass_block())
    write_block(page, LENGTH_BEGIN, LENGTH_END, length_block())
    return [write_block(page, AXLE_BEGIN, AXLE_END, axle_block())]
