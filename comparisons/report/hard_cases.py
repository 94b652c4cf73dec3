"""The report of ``pim hard-cases`` (:mod:`comparisons.studies.hard_cases`): every bundled
hard case through PIM and the simulator, as a :class:`~comparisons.report.document.Document`
(``hard-cases.md``, ``.html`` and the two CSVs) written through the one pipeline.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.document import Bullets, Code, Document, Paragraph, Section
from comparisons.report.write import write_document
from comparisons.studies.hard_cases import TARGET, HardCaseStudy

__all__ = ["hard_cases_document", "write_hard_cases", "COMMAND"]

#: The command that regenerates docs/hard-cases.md.
COMMAND = "pim hard-cases --out docs"


def hard_cases_document(study: HardCaseStudy, units: str = "si") -> Document:
    """The study as a report (results in ``units``)."""
    intro = Section("method", "Method", (
        Paragraph("Regenerate with:"), Code(COMMAND),
        Paragraph("Each bundled hard case (`pim cases`, `pim/io/cases/hard-*.toml`) at its "
                  "own (epsilon, beta), solved by PIM and simulated by pymunk at the default "
                  "settings (point contact at C, exact start, dt = 1e-3 s, automatic "
                  "iterations). `sim error` is the largest error in the impact's velocity "
                  "changes relative to the largest change (docs/comparisons.md). Times are "
                  "wall times on the machine that ran the command.")), keep=True)
    needs = Section("needs", f"What the simulator needs to reach {TARGET:g}", (
        Paragraph("From the full speed-error sweep of each case (dt 1e-2 ... 1e-5 s, "
                  "iterations 1 ... 100 and automatic, exact or detected start, point or "
                  "outline contact). `exact start: iterations` is the fewest fixed iteration "
                  "count that reaches the target at every dt of the sweep; `detected start: "
                  "largest dt` is empty where no dt of the sweep reaches it."),
        study.needs_table(),
        Bullets(tuple(f"**{c.name}** ({c.description}): {c.needs_text()}; outline contact "
                      f"{c.outline_text()}." for c in study.cases))))
    return Document("Hard cases: PIM against the pymunk simulation", "pim hard-cases", (
        intro, Section("results", "Results", (study.results_table(units),), keep=True), needs),
        name="hard-cases")


def write_hard_cases(study: HardCaseStudy, out_dir, units: str = "si") -> list[Path]:
    """Write hard-cases.md (first in the list), hard-cases.html and the two CSVs to
    ``out_dir`` (atomically), in ``units``."""
    written = write_document(hard_cases_document(study, units), Path(out_dir))
    return [written[-1], *written[:-1]]
