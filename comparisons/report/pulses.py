"""The report of ``pim pulses``: each figure named fitted or predicted, as a
:class:`~comparisons.report.document.Document` (``pulses.md``, ``.html`` and the CSV)
written with its plot through the one pipeline.

The table (:func:`pulse_table`) says per row whether the contact law's figure agrees by
construction (fitted to the same test: :func:`comparisons.studies.pulses.roles`) or is a
prediction; the report (:func:`pulses_document`) leads with the predicted figures' errors
and says the same in words, written from the table.
"""

from __future__ import annotations

import math
from pathlib import Path

from comparisons.report.document import Card, Cards, Document, Figure, Paragraph, Section
from comparisons.report.tables import Table
from comparisons.report.write import write_document
from comparisons.studies.pulses import PulseComparison, roles
from pim.io.files import save_figure
from pim.io.units import convert

__all__ = ["pulse_table", "plot_pulses", "pulses_document", "write_pulses"]

_ROWS = (("contact duration (force > 5 % of peak)", "duration", 1e3, "ms"),
         ("peak force", "peak_force", 1e-3, "kN"),
         ("time of peak force", "peak_force_time", 1e3, "ms"),
         ("crush at peak force", "crush_at_peak_force", 1.0, "m"),
         ("maximum crush", "max_crush", 1.0, "m"),
         ("time of maximum crush", "max_crush_time", 1e3, "ms"),
         ("rebound speed", "rebound_speed", 1.0, "m/s"),
         ("delta-V", "delta_v", 1.0, "m/s"))


def _values(c: PulseComparison, attr: str, factor: float, unit: str, units) -> tuple:
    a, b = getattr(c.measured_metrics, attr), getattr(c.model_metrics, attr)
    if unit in ("m", "m/s"):
        (a, b), unit = convert([a, b], "length" if unit == "m" else "speed", units)
    else:
        a, b = a * factor, b * factor
    return float(a), float(b), unit


def pulse_table(c: PulseComparison, units="si") -> Table:
    """Measured against modelled metrics, each named fitted or predicted, with the error
    and the relative error."""
    role = roles(c)
    rows = []
    for label, attr, factor, unit in _ROWS:
        a, b, unit = _values(c, attr, factor, unit, units)
        rows.append((label, role[attr], unit, a, b, b - a,
                     100.0 * (b - a) / a if a else math.nan))
    return Table("pulses-nhtsa10146", "NHTSA 10146 against the contact law",
                 ("quantity", "fitted or predicted", "unit", "measured", "contact law",
                  "error", "error [%]"),
                 tuple(rows), {"measured": lambda x: f"{x:.3g}",
                               "contact law": lambda x: f"{x:.3g}",
                               "error": lambda x: f"{x:+.3g}",
                               "error [%]": lambda x: "" if x != x else f"{x:+.1f}"})


def plot_pulses(c: PulseComparison, units="si"):
    """Force-time, delta-V-time and force-crush, measured against the law (a Figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.5, 4.2), layout="constrained")
    axes = fig.subplots(1, 3)
    su = convert(1.0, "speed", units)[1]
    lu = convert(1.0, "length", units)[1]
    for p, label, style in ((c.measured, "NHTSA 10146 (measured)", dict(color="k", lw=1.4)),
                            (c.model, f"contact law, k = {c.stiffness / 1e3:.0f} kN/m, "
                                      f"eps = {c.eps:.3f}", dict(color="C3", lw=1.6,
                                                                  ls="--"))):
        axes[0].plot(p.time * 1e3, p.force / 1e3, label=label, **style)
        axes[1].plot(p.time * 1e3, convert(c.speed - p.velocity, "speed", units)[0],
                     label=label, **style)
        axes[2].plot(convert(p.crush, "length", units)[0], p.force / 1e3, label=label,
                     **style)
    axes[0].set(xlabel="time [ms]", ylabel="barrier force [kN]",
                title=f"force: RMS difference {c.force_rms / 1e3:.0f} kN")
    axes[1].set(xlabel="time [ms]", ylabel=f"delta-V [{su}]",
                title=f"delta-V: RMS difference "
                      f"{float(convert(c.delta_v_rms, 'speed', units)[0]):.2f} {su}")
    axes[2].set(xlabel=f"crush [{lu}]", ylabel="barrier force [kN]", title="force-crush")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return fig


def _roles_words(c: PulseComparison, table: Table) -> str:
    """What is fitted, what is predicted, and by how much the predictions miss."""
    fitted = [r[0] for r in table.rows if r[1].startswith("fitted")]
    missed = ", ".join(f"{r[0]} {r[6]:+.0f} %" for r in table.rows if r[1] == "predicted")
    k_words = (f"fitted to this test ({c.stiffness_source})" if c.stiffness_fitted
               else f"{c.stiffness_source}, not fitted to this test")
    e_words = ("this test's rebound over its impact speed" if c.eps_fitted
               else "given, not fitted to this test")
    agree = (f"The rows marked fitted ({', '.join(fitted)}) agree by construction: they "
             f"follow from parameters taken from this test and check nothing. "
             if fitted else "No row is fitted to this test. ")
    return (f"**Fitted and predicted.** The stiffness k = {c.stiffness / 1e3:.0f} kN/m is "
            f"{k_words}; the restitution {c.eps:.3f} is {e_words}. {agree}The predicted "
            f"rows are the linear law's independent figures and miss: {missed}. A linear "
            f"spring peaks in force at its maximum crush; the car's structure peaks earlier "
            f"and softens.")


def _answer(c: PulseComparison, table: Table, units) -> Cards:
    """The key figures: the predicted rows' errors, then the curves' RMS differences."""
    su = convert(1.0, "speed", units)[1]
    rms = float(convert(c.delta_v_rms, "speed", units)[0])
    cards = [Card(f"error in {r[0]}", f"{r[6]:+.0f} %",
                  f"contact law {r[4]:.3g} {r[2]} against measured {r[3]:.3g} {r[2]}")
             for r in table.rows if r[1] == "predicted"]
    return Cards((*cards, Card("RMS difference in force", f"{c.force_rms / 1e3:.0f} kN",
                               "over the record"),
                  Card("RMS difference in delta-V", f"{rms:.2f} {su}", "over the record")))


def pulses_document(c: PulseComparison, units="si", command: str = "") -> Document:
    """The comparison as a report (``pulses.md``, ``.html`` and the CSV): the predicted
    figures' errors first, the table naming each row fitted or predicted, the plot, the
    source and the law's parameters."""
    table = pulse_table(c, units)
    speed, su = convert(c.speed, "speed", units)
    rms, _ = convert(c.delta_v_rms, "speed", units)
    answer = Section("answer", "The contact law against the test", (
        _answer(c, table, units), Paragraph(_roles_words(c, table)), table), keep=True)
    plot = Section("plots", "Force, delta-V and crush", (
        Figure("pulses.png", alt="force-time, delta-V-time and force-crush, measured "
                                 "against the contact law"),))
    about = Section("source", "Source and parameters", (
        Paragraph(f"Source: {c.source}"),
        Paragraph(f"Contact law at the test's speed ({float(speed):.2f} {su}, "
                  f"{c.mass:.0f} kg): linear loading stiffness {c.stiffness / 1e3:.0f} kN/m, "
                  f"restitution {c.eps:.3f}. RMS difference over the record: force "
                  f"{c.force_rms / 1e3:.0f} kN, delta-V {float(rms):.2f} {su}.")))
    return Document("Crash pulse: NHTSA 10146 against the contact law", "pim pulses",
                    (answer, plot, about), name="pulses",
                    subtitle=f"Regenerate with `{command}`." if command else "")


def write_pulses(c: PulseComparison, folder, units="si", command: str = "",
                 html: bool = True) -> list[Path]:
    """Write pulses.md (first in the list), pulses.html (with ``html``),
    pulses-nhtsa10146.csv and pulses.png to ``folder``."""
    folder = Path(folder)
    png = save_figure(plot_pulses(c, units), folder / "pulses.png")
    written = write_document(pulses_document(c, units, command), folder, html=html)
    return [written[-1], *written[:-1], png]
