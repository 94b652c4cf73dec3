"""``pim pulses`` in a table, a plot and Markdown: each figure named fitted or predicted.

The table (:func:`pulse_table`) says per row whether the contact law's figure agrees by
construction (fitted to the same test: :func:`comparisons.studies.pulses.roles`) or is a
prediction; the Markdown (:func:`pulses_markdown`) says the same in words, with the
predicted figures' errors written from the table.
"""

from __future__ import annotations

import math
from pathlib import Path

from comparisons.report.render import markdown_table
from comparisons.report.tables import Table
from comparisons.report.write import write_table_csv
from comparisons.studies.pulses import PulseComparison, roles
from pim.io.files import save_figure, write_text
from pim.io.units import convert

__all__ = ["pulse_table", "plot_pulses", "pulses_markdown", "write_pulses"]

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


def pulses_markdown(c: PulseComparison, table: Table, command: str = "",
                    units="si") -> str:
    """The comparison as Markdown (``docs/pulses.md``)."""
    speed, su = convert(c.speed, "speed", units)
    rms, _ = convert(c.delta_v_rms, "speed", units)
    lines = ["# Crash pulse: NHTSA 10146 against the contact law", ""]
    if command:
        lines += [f"Regenerate with `{command}`.", ""]
    lines += [f"Source: {c.source}", "",
              f"Contact law at the test's speed ({float(speed):.2f} {su}, {c.mass:.0f} kg): "
              f"linear loading stiffness {c.stiffness / 1e3:.0f} kN/m, restitution "
              f"{c.eps:.3f}. RMS difference over the record: force {c.force_rms / 1e3:.0f} "
              f"kN, delta-V {float(rms):.2f} {su}.", "", _roles_words(c, table), "",
              markdown_table(table), "", "![pulses](pulses.png)", ""]
    return "\n".join(lines)


def write_pulses(c: PulseComparison, folder, units="si", command: str = "") -> list[Path]:
    """Write pulses.md, pulses-nhtsa10146.csv and pulses.png to ``folder``."""
    folder = Path(folder)
    table = pulse_table(c, units)
    png = save_figure(plot_pulses(c, units), folder / "pulses.png")
    md = write_text(folder / "pulses.md", pulses_markdown(c, table, command, units))
    return [md, write_table_csv(table, folder), png]
