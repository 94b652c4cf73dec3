"""The speeds before the impact (:mod:`pim.analysis.pre_impact_speeds`) as the commands show
them: rows in the user's units, text lines, JSON, a Markdown section and an HTML section.

Used by ``pim solve`` (from the case's impact velocities) and ``pim reconstruct`` (from the
reconstructed impact speeds, with the Monte Carlo's 5/50/95 %).
"""

from __future__ import annotations

from pim.analysis.pre_impact_speeds import PreImpactSpeed
from pim.io import html
from pim.io.units import convert

__all__ = ["pre_impact_rows", "pre_impact_lines", "pre_impact_json", "pre_impact_markdown",
           "pre_impact_html", "TITLE"]

TITLE = "Speeds before the impact"


def _what(s: PreImpactSpeed, units: str) -> str:
    """Where the speed holds and from what, in ``units``."""
    if s.source == "marks":
        m = s.marks
        length, unit = convert(m.skid_length, "length", units)
        grade = f", grade {100 * m.grade:+.3g} %" if m.grade else ""
        return (f"start of {float(length):.4g} {unit} of marks before the impact (friction "
                f"{m.friction:.3g}, drag fraction {m.drag:.3g}{grade})")
    return (f"t = {s.start_time:g} s of [driver.vehicle{s.vehicle}] (driven to the impact on "
            f"the vehicle's run-out tyre)")


def pre_impact_rows(speeds, units: str) -> list[dict]:
    """One row per :class:`PreImpactSpeed`: name, unit, value, p5, p50, p95, impact speed
    (``impact``) in ``units`` (impact speeds: mph in US units), and ``what`` (where the
    speed holds, from what evidence)."""
    rows = []
    for s in speeds:
        values, unit = convert([s.start_speed, s.p5, s.p50, s.p95, s.impact_speed],
                               "impact_speed", units)
        v = [float(x) for x in values]
        rows.append({"name": s.name, "unit": unit, "value": v[0], "p5": v[1], "p50": v[2],
                     "p95": v[3], "impact": v[4], "what": _what(s, units),
                     "source": s.source, "varied": list(s.varied),
                     "drivers": [[k, x] for k, x in s.drivers]})
    return rows


def _spread(row) -> str:
    if row["p5"] != row["p5"]:
        return ""
    return f"  [{row['p5']:.4g}, {row['p50']:.4g}, {row['p95']:.4g}]"


def _main_driver(row) -> str:
    top = [(k, x) for k, x in row["drivers"][:1] if x > 0.005]
    return "".join(f"; main driver of the spread {k} ({x:.2f})" for k, x in top)


def pre_impact_lines(rows) -> list[str]:
    """Text lines: each speed with its 5/50/95 % (when computed), where it holds and the
    main driver of its spread."""
    return [f"{r['name']:32s} {r['value']:10.4g} {r['unit']}{_spread(r)}  ({r['what']}; "
            f"impact speed {r['impact']:.4g} {r['unit']}{_main_driver(r)})" for r in rows]


def pre_impact_json(rows) -> dict:
    """``--json``'s ``pre_impact`` entry: name -> value, percentiles, unit, impact speed and
    where it holds (NaN percentiles become null in :func:`pim_cli.main.echo_json`)."""
    return {r["name"]: {k: r[k] for k in ("unit", "value", "p5", "p50", "p95", "impact",
                                           "source", "what", "varied", "drivers")}
            for r in rows}


def _cells(r) -> tuple:
    def g(x):
        return "" if x != x else f"{x:.4g}"

    drivers = ", ".join(f"{k} {x:.2f}" for k, x in r["drivers"][:3] if x > 0.005)
    return (r["name"], g(r["value"]), g(r["p5"]), g(r["p50"]), g(r["p95"]), r["unit"],
            g(r["impact"]), r["what"], drivers)


_COLUMNS = ("speed", "value", "5 %", "50 %", "95 %", "unit", "impact speed", "where, from what",
            "drivers of the spread")
_NOTE = ("Marks: v_start = sqrt(v_impact^2 + 2 g L (f mu cos(theta) + sin(theta))) "
         "(Fricke 1990; Brach & Brach 2011); the 5/50/95 % carry each Monte Carlo sample's "
         "impact speed with the marks' friction and length drawn from [uncertainty]; their "
         "drivers are first-order variance indices (correlation ratio). Driver table: the "
         "start speed whose motion under the table reaches the impact speed.")


def pre_impact_markdown(rows) -> list[str]:
    """report.md's section (no lines without rows)."""
    if not rows:
        return []
    lines = [f"## {TITLE}", "", _NOTE, "", "| " + " | ".join(_COLUMNS) + " |",
             "|" + "---|" * len(_COLUMNS)]
    lines += ["| " + " | ".join(c or "-" for c in _cells(r)) + " |" for r in rows]
    return lines + [""]


def pre_impact_html(rows) -> list[str]:
    """report.html's section (an empty list without rows)."""
    if not rows:
        return []
    return [html.section(TITLE, [html.paragraph(_NOTE), html.table(
        _COLUMNS, [_cells(r) for r in rows], title=TITLE, id="table-pre-impact")],
        id="pre-impact")]
