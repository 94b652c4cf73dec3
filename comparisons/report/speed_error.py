"""The reports of ``pim speed-error``: the rigid scene's sweep
(:mod:`comparisons.studies.speed_error`, ``speed-error-STEM.md``) and the finite-duration
contact's (:mod:`comparisons.studies.speed_error_compliant`,
``speed-error-compliant-STEM.md``), each a :class:`~comparisons.report.document.Document`
written with its figure and CSVs through the one pipeline.
"""

from __future__ import annotations

from pathlib import Path

from comparisons.report.document import Bullets, Code, Document, Figure, Paragraph, Section
from pim.model.number_format import format_number
from comparisons.report.write import write_document
from comparisons.studies.event_speed_error import (
    REFERENCE,
    EventSpeedStudy,
    event_pareto_table,
    event_study_table,
    plot_event_speed_error,
)
from comparisons.studies.speed_error import (
    SpeedErrorStudy,
    pareto_table,
    plot_speed_error,
    study_table,
)
from comparisons.studies.speed_error_compliant import (
    FIXED_STEP,
    REFERENCE_STEPS,
    CompliantSpeedStudy,
    compliant_table,
    fixed_step_label,
    plot_compliant_speed_error,
)
from pim.io.files import save_figure

__all__ = ["speed_error_document", "write_speed_error", "compliant_document",
           "write_compliant", "speed_error_json", "speed_error_line", "compliant_json",
           "compliant_summary", "event_speed_document", "write_event_speed",
           "event_speed_json", "event_speed_line"]


def _method(study: SpeedErrorStudy) -> str:
    return (f"epsilon = {study.eps:.6g}, beta = {study.beta:.6g}. {len(study.points)} runs of "
            f"the pymunk scene over dt {sorted({p.dt for p in study.points})}, iterations "
            f"(1 ... 100 and automatic), exact or detected contact start, point or outline "
            f"contact. Error: the largest error in the impact's velocity changes (V1, V2, "
            f"and k1 W1, k2 W2 with k the radius of gyration), relative to the largest "
            f"change. Wall time: building the pymunk Space and stepping it through the "
            f"impact, best of the repeats, on the machine that ran the command. "
            f"{len(study.succeeded)} runs succeeded.")


def _findings(study: SpeedErrorStudy) -> list[str]:
    lines = []
    for where, text in ((dict(start="exact", contact="point"), "point contact, exact start"),
                        (dict(start="detected", contact="point"),
                         "point contact, detected start"),
                        (dict(contact="outline"), "outline contact")):
        best = study.best(**where)
        if best is not None:
            lines.append(f"best {text}: error {best.error:.2e} ({best.label})")
    fails = {}
    for p in study.points:
        if not p.ok:
            fails[p.failure] = fails.get(p.failure, 0) + 1
    if fails:
        lines.append("failed runs: " + ", ".join(f"{k} x {v}" for k, v in fails.items()))
    return lines


def _write_study(document: Document, figure, out_dir) -> list[Path]:
    """Write a study's ``document`` through the pipeline and its ``figure`` as
    ``NAME.png`` (NAME the document's): the Markdown first, then the other files, the PNG
    last."""
    out = Path(out_dir)
    png = save_figure(figure, out / f"{document.name}.png")
    written = write_document(document, out)
    return [written[-1], *written[:-1], png]


def speed_error_document(study: SpeedErrorStudy, stem: str, command: str = "") -> Document:
    """The sweep as a report: method, recommendation, plot, Pareto front, every run."""
    rec = study.recommended()
    if rec is not None:
        its = "automatic" if rec.iterations is None else str(rec.iterations)
        verdict = (f"**Recommended: dt = {rec.dt:g} s, {its} iterations "
                   f"({rec.iterations_used} sweeps), {rec.start} start, {rec.contact} "
                   f"contact** -- error {rec.error:.2e} in "
                   f"{format_number(rec.wall_time * 1e3, sig=3)} ms per impact (the fastest "
                   f"run reaching {study.target:g}: on the Pareto front).")
    else:
        verdict = f"**No run reaches {study.target:g}.**"
    blocks = ([Paragraph("Regenerate with:"), Code(command)] if command else []) + [
        Paragraph(_method(study)), Paragraph(verdict),
        Paragraph(f"PIM itself: {format_number(study.analytic_time * 1e3, sig=3)} ms per "
                  f"single call, {format_number(study.analytic_batch_time * 1e6, sig=3)} us "
                  f"per case in a batch of 10 000, error (residual of its own equations) "
                  f"{study.analytic_error:.2e}."),
        Bullets(tuple(_findings(study))),
        Figure(f"speed-error-{stem}.png", alt="speed against error")]
    front = pareto_table(study, f"speed-error-{stem}-pareto")
    every = study_table(study, f"speed-error-{stem}")
    return Document(f"Speed against error: {study.case_name}", "pim speed-error", (
        Section("study", "The study", tuple(blocks), keep=True),
        Section("pareto", "Pareto front", (front,)),
        Section("every-run", "Every run", (every,))), name=f"speed-error-{stem}")


def write_speed_error(study: SpeedErrorStudy, out_dir, stem: str,
                      command: str = "") -> list[Path]:
    """Write ``speed-error-STEM.md`` (first in the list), ``.html``, ``.csv`` (every run),
    ``-pareto.csv`` and ``.png`` into ``out_dir``."""
    return _write_study(speed_error_document(study, stem, command), plot_speed_error(study),
                        out_dir)


def _compliant_lines(study: CompliantSpeedStudy) -> tuple[list[str], list[str]]:
    """(per configuration: the recommended setting; per configuration, integrator and
    target: the fastest run reaching it)."""
    recommended, fastest = [], []
    for name in dict.fromkeys(p.scene for p in study.points):
        rec = study.recommended(name)
        recommended.append(f"{name}: " + (
            f"**recommended {rec.label}**: error {rec.error:.1e} in "
            f"{format_number(rec.wall_time * 1e3, sig=3)} ms per impact." if rec
            else "no run reaches the target."))
        for integrator in (FIXED_STEP[study.engine], "DOP853", "Radau"):
            for target in (1e-3, 1e-6):
                p = study.fastest(name, integrator, target)
                if p is not None:
                    fastest.append(f"{name}, {integrator} reaches {target:g} at {p.label}: "
                                   f"{format_number(p.wall_time * 1e3, sig=3)} ms per impact")
    return recommended, fastest


def compliant_document(study: CompliantSpeedStudy, stem: str, command: str = "") -> Document:
    """The finite-duration contact's sweep as a report: the recommended setting of each
    friction configuration first, then the fastest run per integrator, the method, the
    plot and every run."""
    recommended, fastest = _compliant_lines(study)
    intro = (f"Point contact, epsilon = {study.eps:.4g}, k = {study.stiffness:.3g} N/m (the "
             f"stiffness of a {1e3 * study.contact_time:g} ms contact); the "
             f"{fixed_step_label(FIXED_STEP[study.engine])} (10 ... 2560 steps per "
             f"estimated contact time), solve_ivp DOP853 and Radau over rtol, against DOP853 "
             f"at rtol {study.reference_rtol:g} (the tightest within {REFERENCE_STEPS} steps "
             f"per configuration; it differs from the rung before by "
             f"{study.reference_spread:.1e}). Whole study: {study.wall_time:.1f} s. Error: "
             f"the largest error in the impact's velocity changes, relative to the largest "
             f"change.")
    blocks = [Bullets(tuple(recommended)), Bullets(tuple(fastest)),
              *([Paragraph(f"Regenerate with `{command}`.")] if command else []),
              Paragraph(intro),
              Figure(f"speed-error-compliant-{stem}.png", alt="speed against error"),
              compliant_table(study, f"speed-error-compliant-{stem}")]
    return Document(f"Speed against error of the finite-duration contact: "
                    f"{study.case_name}", "pim speed-error",
                    (Section("study", "The study", tuple(blocks), keep=True),),
                    name=f"speed-error-compliant-{stem}")


def write_compliant(study: CompliantSpeedStudy, out_dir, stem: str,
                    command: str = "") -> list[Path]:
    """Write ``speed-error-compliant-STEM.md`` (first), ``.html``, ``.csv`` and ``.png``."""
    return _write_study(compliant_document(study, stem, command),
                        plot_compliant_speed_error(study), out_dir)


def speed_error_json(study: SpeedErrorStudy, stem: str) -> dict:
    """The rigid sweep of one case as ``pim speed-error --json`` gives it: the case, its
    files (filled in by the writer), the recommended setting (None when no run reaches the
    target) and PIM's own time per call and per batched case [s]."""
    rec = study.recommended()
    return {"case": stem, "files": [],
            "recommended": None if rec is None else
            {"dt": rec.dt, "iterations": rec.iterations,
             "iterations_used": rec.iterations_used, "start": rec.start,
             "contact": rec.contact, "error": rec.error, "wall_time": rec.wall_time},
            "analytic_time": study.analytic_time,
            "analytic_batch_time": study.analytic_batch_time}


def speed_error_line(study: SpeedErrorStudy, stem: str) -> str:
    """One line: the recommended setting with its error and time per impact beside PIM's
    time per call, or that no run reaches the target."""
    rec = study.recommended()
    text = ("no run reaches the target" if rec is None else
            f"recommended dt = {rec.dt:g} s, iterations = "
            f"{'auto' if rec.iterations is None else rec.iterations}, {rec.start} "
            f"start, {rec.contact} contact: error {rec.error:.2e}, "
            f"{rec.wall_time * 1e3:.3g} ms/impact (PIM {study.analytic_time * 1e3:.3g} "
            f"ms/call)")
    return f"{stem}: {text}"


def _recommended(study: CompliantSpeedStudy) -> dict:
    """Friction configuration -> its recommended run (None: none reaches the target)."""
    return {scene: study.recommended(scene)
            for scene in dict.fromkeys(p.scene for p in study.points)}


def compliant_json(study: CompliantSpeedStudy) -> dict:
    """The finite-duration sweep's recommendation per friction configuration (integrator,
    setting, error, wall time per impact [s]) and the study's wall time [s]."""
    return {"compliant": {
        scene: None if rec is None else
        {"integrator": rec.integrator, "setting": rec.setting, "error": rec.error,
         "wall_time": rec.wall_time} for scene, rec in _recommended(study).items()},
        "compliant_seconds": study.wall_time}


def compliant_summary(study: CompliantSpeedStudy, stem: str) -> list[str]:
    """One line per friction configuration: its recommended run with its error and time per
    impact, or that no run reaches 1e-3."""
    return [f"{stem} finite-duration ({scene}): " + (
        "no run reaches 1e-3" if rec is None else
        f"recommended {rec.label}: error {rec.error:.1e}, {rec.wall_time * 1e3:.3g} ms/impact")
        for scene, rec in _recommended(study).items()]


def _event_verdict(study: EventSpeedStudy) -> str:
    """The fastest run of each engine reaching the target, in words."""
    parts = []
    for engine in ("pymunk", "analytic"):
        rec = study.recommended(engine)
        parts.append(f"{engine}: " + ("no run reaches it" if rec is None else
                                      f"**{rec.label}**, error {rec.error:.2e} in "
                                      f"{format_number(rec.wall_time * 1e3, sig=3)} ms"))
    return (f"Fastest run reaching the target error {study.target:g}, per engine: "
            + "; ".join(parts) + ".")


def event_speed_document(study: EventSpeedStudy, stem: str, command: str = "") -> Document:
    """The whole event's sweep as a report: method, verdict, plot, Pareto front, every run."""
    fails = {}
    for p in study.points:
        if not p.ok:
            fails[p.failure] = fails.get(p.failure, 0) + 1
    method = (f"The reference: the pymunk event at dt = {REFERENCE['dt']:g} s and "
              f"{REFERENCE['iterations']} solver iterations "
              f"({len(study.reference.impacts)} impacts, "
              f"{format_number(study.reference_time, sig=3)} s). Against it: the pymunk event "
              f"over its step (also its contact test's step) and iterations, and the analytic "
              f"event (pim.event) over its run-out step (its contact test's step; it bisects "
              f"a contact to 1 us). Error: the largest of each impact's delta-V difference "
              f"relative to its largest |delta-V| and each vehicle's rest-position distance "
              f"relative to its run-out travel; infinite when the impact count differs. Wall "
              f"time: one event, best of the repeats, on the machine that ran the command.")
    blocks = ([Paragraph("Regenerate with:"), Code(command)] if command else []) + [
        Paragraph(method), Paragraph(_event_verdict(study)),
        Bullets(tuple(f"failed runs: {k} x {v}" for k, v in fails.items())),
        Figure(f"speed-error-event-{stem}.png", alt="the event's speed against error")]
    return Document(f"Speed against error of the whole event: {study.case_name}",
                    "pim speed-error --event", (
                        Section("study", "The study", tuple(blocks), keep=True),
                        Section("pareto", "Pareto front",
                                (event_pareto_table(study, f"speed-error-event-{stem}-pareto"),)),
                        Section("every-run", "Every run",
                                (event_study_table(study, f"speed-error-event-{stem}"),))),
                    name=f"speed-error-event-{stem}")


def write_event_speed(study: EventSpeedStudy, out_dir, stem: str,
                      command: str = "") -> list[Path]:
    """Write ``speed-error-event-STEM.md`` (first in the list), ``.html``, ``.csv``,
    ``-pareto.csv`` and ``.png`` into ``out_dir``."""
    return _write_study(event_speed_document(study, stem, command),
                        plot_event_speed_error(study), out_dir)


def event_speed_json(study: EventSpeedStudy) -> dict:
    """The event study's part of ``pim speed-error --json``: per engine the fastest run
    reaching the target (None: none), and the reference's impacts and time [s]."""
    def run(p):
        return None if p is None else {"step": p.step, "iterations": p.iterations,
                                       "error": p.error, "rest_error": p.rest_error,
                                       "wall_time": p.wall_time, "impacts": p.impacts}

    return {"event": {"target": study.target, "reference": dict(REFERENCE),
                      "reference_impacts": len(study.reference.impacts),
                      "reference_time": study.reference_time,
                      "recommended": {e: run(study.recommended(e))
                                      for e in ("pymunk", "analytic")}}}


def event_speed_line(study: EventSpeedStudy, stem: str) -> str:
    """One line: each engine's fastest run reaching the target."""
    parts = []
    for engine in ("pymunk", "analytic"):
        rec = study.recommended(engine)
        parts.append(f"{engine} none reaches {study.target:g}" if rec is None else
                     f"{rec.label}: error {rec.error:.2e}, {rec.wall_time * 1e3:.3g} ms/event")
    return f"{stem} (whole event): " + "; ".join(parts)
