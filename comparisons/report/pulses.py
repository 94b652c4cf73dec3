"""The report of ``pim pulses`` (:mod:`comparisons.studies.pulses`): the contact law's crash
pulse against NHTSA test 10146, as a :class:`~comparisons.report.document.Document`
(``pulses.md``, ``.html``, the CSV and the figure) written through the one pipeline.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.document import Document, Figure, Paragraph, Section
from comparisons.report.number_format import format_number
from comparisons.report.write import write_document
from comparisons.studies.pulses import PulseComparison, plot_pulses, pulse_table
from pim.io.files import save_figure
from pim.io.units import convert

__all__ = ["pulses_document", "write_pulses"]


def pulses_document(c: PulseComparison, units: str = "si", command: str = "") -> Document:
    """The comparison as a report (numbers in ``units``)."""
    speed, su = convert(c.speed, "speed", units)
    mass, mu = convert(c.mass, "mass", units)
    dv = convert(c.delta_v_rms, "speed", units)[0]
    blocks = ([Paragraph(f"Regenerate with `{command}`.")] if command else []) + [
        Paragraph(f"Source: {c.source}"),
        Paragraph(f"Contact law at the test's speed ({format_number(float(speed))} {su}, "
                  f"{format_number(float(mass))} {mu}): linear loading stiffness "
                  f"{c.stiffness / 1e3:.0f} kN/m, restitution {c.eps:.3f}. RMS difference "
                  f"over the record: force {c.force_rms / 1e3:.0f} kN, delta-V "
                  f"{format_number(float(dv), sig=3)} {su}."),
        pulse_table(c, units), Figure("pulses.png", alt="pulses")]
    return Document("Crash pulse: NHTSA 10146 against the contact law", "pim pulses",
                    (Section("pulses", "The pulse", tuple(blocks), keep=True),),
                    name="pulses")


def write_pulses(c: PulseComparison, out_dir, units: str = "si",
                 command: str = "") -> list[Path]:
    """Write pulses.md (first in the list), pulses.html, the CSV and pulses.png."""
    out = Path(out_dir)
    png = save_figure(plot_pulses(c, units), out / "pulses.png")
    written = write_document(pulses_document(c, units, command), out)
    return [written[-1], *written[:-1], png]
