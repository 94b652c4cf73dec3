"""The report of ``pim assumptions`` (:mod:`comparisons.studies.assumptions`): the verdicts,
the ladder at the typical contact time (its 14-column table split into parts one screen
wide on the page), the plots and the animation of the finite-duration scene with PIM's
ghost, as a :class:`~comparisons.report.document.Document` (``assumptions.md``, ``.html``,
the CSVs) written through the one pipeline.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pim
from comparisons.animation.render import build_renderer, write_animation
from comparisons.report.compare_document import ASSUMPTION_GROUPS
from comparisons.report.document import (
    Bullets,
    Callout,
    Document,
    Figure,
    Paragraph,
    Section,
    Video,
)
from comparisons.report.write import write_document
from comparisons.studies.assumptions import (
    AssumptionStudy,
    assumption_table,
    plot_overview,
    sweep_table,
)
from pim.io.files import save_figure
from sim.error_measure import ERROR_DEFINITION

__all__ = ["assumptions_document", "write_assumptions"]


def assumptions_document(study: AssumptionStudy, info=None, command: str = "") -> Document:
    """The study as a report; ``info`` is the animation written beside it (or None)."""
    name = study.case.name or "case"
    intro = (f"A ladder of finite-duration crush scenes (docs/contact-model.md), each "
             f"differing from the one below in one assumption of PIM; epsilon = "
             f"{study.eps:.4g}, PIM at beta = {study.beta_pim:g}. The marginal effect of an "
             f"assumption is the impact error between its scene and the scene below at the "
             f"same contact time; the cumulative one is PIM's error against the scene. "
             f"Impact error: {ERROR_DEFINITION} (sim.error_measure.impact_error).")
    table = replace(assumption_table(study), groups=ASSUMPTION_GROUPS)
    every = replace(sweep_table(study), show=False)
    sections = [
        Section("verdicts", "Verdicts", (
            *([Paragraph(f"Regenerate with `{command}`.")] if command else []),
            Paragraph(intro), Bullets(tuple(study.verdicts()))), keep=True),
        Section("typical", f"The ladder at {1e3 * study.typical.duration:g} ms", (
            table, every, Paragraph(
                "eps_eff, beta_eff: what `pim fit` (velocities and yaw rates) needs to "
                "reproduce the simulated motion; C_eff: the impulse centroid. Every scene: "
                f"[{every.name}.csv]({every.name}.csv). Run time {study.seconds:.1f} s.")),
            toc="The ladder"),
        Section("sweeps", "Over contact times, tyre friction and the tangential recovery",
                (Figure("assumptions.png", alt="the ladder's effects"),), toc="Plots")]
    if info is not None:
        blocks = [Video("assumptions.mp4", "The finite-duration scene (filled) with PIM's "
                        "answer as a dashed ghost.", info.frames, info.fps, tuple(info.size))]
        if info.secondary_impact is not None:
            blocks.append(Callout("Warning", (f"{info.secondary_impact.message()}.",)))
        sections.append(Section("animation", "Animation", tuple(blocks)))
    return Document(f"{name}: PIM's assumptions one at a time", "pim assumptions",
                    tuple(sections), name="assumptions",
                    subtitle="Which of PIM's assumptions hold for this case.")


def _animation(study: AssumptionStudy, out: Path, progress):
    """The finite-duration scene's MP4 with PIM's ghost (AnimationInfo)."""
    r = study.animation_result
    ghost = pim.solve(study.case, study.eps, study.beta_pim)
    renderer = build_renderer(
        study.case, study.eps, study.beta_pim, result=ghost, simulated=r,
        after=max(0.1, float(r.trajectory.time[-1]) - 0.05),
        title=f"{study.case.name or 'case'}: finite-duration crush ({r.geometry}, "
              f"{1e3 * r.contact_duration:.0f} ms), PIM ghost eps = {study.eps:.3g}, "
              f"beta = {study.beta_pim:g}")
    return write_animation(renderer, out / "assumptions.mp4", progress=progress)


def write_assumptions(study: AssumptionStudy, out_dir, *, animation: bool = True,
                      progress: bool | None = None, command: str = "") -> list[Path]:
    """Write assumptions.md, assumptions.html, the tables (CSV), the plot (PNG) and the MP4
    to ``out_dir``; return the paths."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = [save_figure(plot_overview(study), out / "assumptions.png")]
    info = None
    if animation and study.animation_result is not None:
        info = _animation(study, out, progress)
        files.append(info.path)
    return files + write_document(assumptions_document(study, info, command), out)
