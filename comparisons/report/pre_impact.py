"""The speeds before the impact (:mod:`pim.analysis.pre_impact_speeds`) as the commands show
them: typed rows in the user's units, text lines, JSON and a report section.

Used by ``pim solve`` (from the case's impact velocities), ``pim compare`` and ``pim
reconstruct`` (from the reconstructed impact speeds, with the Monte Carlo's 5/50/95 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from comparisons.report.document import Paragraph, Section
from pim.model.number_format import interval_decimals
from comparisons.report.tables import Num, Table
from pim.analysis.pre_impact_speeds import PreImpactSpeed
from pim.io.units import convert
from pim.model.quantities import label_of

__all__ = ["PreImpactRow", "driver_label", "pre_impact_rows", "pre_impact_lines", "pre_impact_json",
           "pre_impact_section", "pre_impact_spread_table", "TITLE", "NOTE"]

TITLE = "Speeds before the impact"


@dataclass(frozen=True)
class PreImpactRow:
    """One speed before the impact in the user's units.

    Attributes
    ----------
    name : str
        Its dotted name (``vehicle1.speed_at_marks_start``).
    unit : str
        Display unit of the speeds.
    value : float
        The speed where the evidence starts.
    p5, p50, p95 : float
        Its Monte Carlo percentiles (NaN when not computed).
    impact : float
        The impact speed it was carried back from.
    what : str
        Where the speed holds and from what evidence.
    source : str
        "marks" or "driver".
    varied : list of str
        The inputs the Monte Carlo varied for it.
    drivers : list of [str, float]
        Inputs driving its spread with their first-order indices, largest first.
    """

    name: str
    unit: str
    value: float
    p5: float
    p50: float
    p95: float
    impact: float
    what: str
    source: str
    varied: list
    drivers: list

    @property
    def has_spread(self) -> bool:
        """Whether the percentiles were computed."""
        return not math.isnan(self.p5)

    @property
    def label(self) -> str:
        """Its plain-language name ("speed of vehicle 1 where its marks start")."""
        vehicle = self.name.split(".")[0].replace("vehicle", "vehicle ")
        return (f"speed of {vehicle} where its marks start" if self.source == "marks"
                else f"speed of {vehicle} where its driver table starts")


def driver_label(key: str) -> str:
    """An input driving a spread, named as a reader says it ("vehicle1.speed (impact)" ->
    "impact speed of vehicle 1")."""
    return label_of(key.removesuffix(" (impact)"))


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


def pre_impact_rows(speeds, units: str) -> list[PreImpactRow]:
    """One :class:`PreImpactRow` per :class:`PreImpactSpeed`, in ``units`` (impact speeds:
    the system's impact-speed unit)."""
    rows = []
    for s in speeds:
        values, unit = convert([s.start_speed, s.p5, s.p50, s.p95, s.impact_speed],
                               "impact_speed", units)
        v = [float(x) for x in values]
        rows.append(PreImpactRow(name=s.name, unit=unit, value=v[0], p5=v[1], p50=v[2],
                                 p95=v[3], impact=v[4], what=_what(s, units),
                                 source=s.source, varied=list(s.varied),
                                 drivers=[[k, x] for k, x in s.drivers]))
    return rows


def _spread(row: PreImpactRow) -> str:
    if not row.has_spread:
        return ""
    return f"  [{row.p5:.4g}, {row.p50:.4g}, {row.p95:.4g}]"


def _main_driver(row: PreImpactRow) -> str:
    top = [(k, x) for k, x in row.drivers[:1] if x > 0.005]
    return "".join(f"; main driver of the spread {driver_label(k)} ({x:.2f})" for k, x in top)


def pre_impact_lines(rows) -> list[str]:
    """Text lines: each speed with its 5/50/95 % (when computed), where it holds and the
    main driver of its spread."""
    return [f"{r.label:32s} {r.value:10.4g} {r.unit}{_spread(r)}  ({r.what}; "
            f"impact speed {r.impact:.4g} {r.unit}{_main_driver(r)})" for r in rows]


def pre_impact_json(rows) -> dict:
    """``--json``'s ``pre_impact`` entry: name -> value, percentiles, unit, impact speed and
    where it holds (NaN percentiles become null in :func:`pim_cli.main.echo_json`)."""
    return {r.name: {k: getattr(r, k) for k in ("unit", "value", "p5", "p50", "p95", "impact",
                                                 "source", "what", "varied", "drivers")}
            for r in rows}


NOTE = ("Marks: v_start = sqrt(v_impact^2 + 2 g L (f mu cos(theta) + sin(theta))) "
        "(Fricke 1990; Brach & Brach 2011); the 5/50/95 % carry each Monte Carlo sample's "
        "impact speed with the marks' friction and length drawn from [uncertainty]; their "
        "drivers are first-order variance indices (correlation ratio). Driver table: the "
        "start speed whose motion under the table reaches the impact speed.")


def _cells(r: PreImpactRow) -> tuple:
    digits = interval_decimals(r.p5, r.p95)
    drivers = ", ".join(f"{driver_label(k)} {x:.2f}" for k, x in r.drivers[:3] if x > 0.005)

    def cell(x):
        return None if math.isnan(x) else Num(x, digits)

    return (r.label, cell(r.value), cell(r.p5), cell(r.p50), cell(r.p95), r.unit,
            Num(r.impact), r.what, drivers)


def pre_impact_spread_table(rows) -> Table:
    """The speeds with their 5/50/95 % (``reconstruction_pre_impact.csv``)."""
    return Table("pre_impact", TITLE, ("speed", "value", "5 %", "50 %", "95 %", "unit",
                                       "impact speed", "where, from what",
                                       "drivers of the spread"),
                 tuple(_cells(r) for r in rows))


def pre_impact_section(rows) -> Section | None:
    """The report section of the speeds before the impact (None without rows)."""
    if not rows:
        return None
    return Section("pre-impact", TITLE, (Paragraph(NOTE), pre_impact_spread_table(rows)),
                   toc="Before the impact")

