"""The report of ``pim compare`` (Brach's law) as a :class:`~comparisons.report.document.Document`.

It leads with what a reconstruction hands on: the answer as cards (each vehicle's delta-V,
PDOF and post-impact speed, the energy lost, each with its 5-95 % interval), the warnings (a
poor fit among them, said in a sentence), the results table and the speeds before the
impact. Then how well the answer fits the measurements (each measured quantity in sigmas),
the coefficients and where they come from, the inputs, the design sheet's plots, the
animation; the appendices hold the simulator's agreement with PIM, the coarse
speed-against-error sweep and PIM's assumptions at typical values; last the files and
timings.
"""

from __future__ import annotations

import shlex
from dataclasses import replace

import numpy as np

from comparisons.report.assumptions import ASSUMPTION_GROUPS, ladder_intro, verdicts
from comparisons.report.compare_tables import answer_cards, misfit_sentence
from comparisons.report.data import ReportData, monte_carlo_note
from comparisons.report.document import (
    Bullets,
    Callout,
    Document,
    Figure,
    FileList,
    Paragraph,
    Section,
    Video,
)
from pim.model.number_format import format_number
from comparisons.report.write import document_files
from pim.io.inertia_data import estimate_notes
from pim.io.units import convert, display_units

__all__ = ["compare_document", "ASSUMPTION_GROUPS", "REPORT_NAME", "ANIMATION_CAPTION"]

#: File name of the Markdown report.
REPORT_NAME = "report.md"

#: What the animation shows.
ANIMATION_CAPTION = (
    "The whole event, from the approach to rest (pim event): filled outlines, the pymunk "
    "event; dashed magenta outlines, the analytic event (PIM's impacts and the run-out with "
    "the tyres); grey: tyre marks where the wheels slide; red: the impulse on vehicle 1 at "
    "C; green: each impact's C, contact plane and normal n. The tyre friction and its "
    "source are in the caption.")


def _command(data: ReportData, name: str) -> str:
    """A command runnable as printed: the case as the user gave it, quoted for a shell."""
    return f"pim {name} {shlex.quote(data.case_path)}"


def _describe(dist, kind: str, units: str) -> str:
    """A distribution of the [uncertainty] table in words, in display units."""
    def v(x):
        return format_number(float(convert(x, kind, units)[0])) if kind != "dimensionless" \
            else format_number(x)

    if dist.kind == "uniform":
        return f"uniform on [{v(dist.a)}, {v(dist.b)}]"
    if dist.kind == "plusminus":
        return f"nominal +- {v(dist.b)} (uniform)"
    if dist.kind == "normal":
        return "normal, sd " + v(dist.b) + ("" if dist.a is None else f", mean {v(dist.a)}")
    return f"fixed at {v(dist.a)}"


def _subtitle(data: ReportData) -> str:
    description = getattr(data.case, "description", None) or ""
    return ((description.rstrip(".") + ". " if description else "")
            + f"Written by `pim compare` in {display_units(data.units)} (`--units` and "
            "`--speed-unit` change them). Brach's Planar Impact Mechanics (PIM) gives the "
            "post-impact motion in "
            "closed form from the case's inputs and two coefficients, epsilon (restitution) "
            "and beta (the fraction of the impulse ratio that stops the sliding at C); the "
            "appendix checks PIM against a pymunk (Chipmunk2D) simulation of the same impact.")


def _warnings(data: ReportData) -> list[str]:
    """Everything the reader must see beside the answer: plausibility, a poor fit, a
    secondary impact."""
    out = list(data.warnings)
    if data.misfit is not None:
        sentence = misfit_sentence(data.misfit, data.units, data.fit, data.spread is not None)
        if sentence:
            out.append(sentence)
    info = data.animation
    if info is not None and info.secondary_impact is not None:
        out.append(f"{info.secondary_impact.message(data.units)}; the animation marks it.")
    return out


def _notes(data: ReportData) -> list[str]:
    r, s = data.result, data.sources
    notes = [f"**epsilon = {format_number(data.eps)}** ({s['eps']}), **beta = "
             f"{format_number(data.beta)}** ({s['beta']}); impulse ratio mu = "
             f"{format_number(float(r.mu))} (mu0 = {format_number(float(r.mu0))}); the "
             "coefficients and the fit follow below."]
    table = data.case.uncertainty
    if table is not None:
        for key, label in (("impact.restitution", "epsilon"), ("impact.beta", "beta")):
            if key in table.inputs:
                notes.append(f"{label} in the `[uncertainty]` table: "
                             f"{_describe(table.inputs[key], 'dimensionless', data.units)}.")
        notes.append(monte_carlo_note(data.case).rstrip(".")
                     + "; each value shows the digits its interval allows.")
    else:
        notes.append("The case has no `[uncertainty]` table: no intervals (4 significant "
                     "digits).")
    if bool(np.asarray(data.case.vehicle2.fixed)):
        notes.append("Vehicle 2 is a fixed obstacle: it has no delta-V and no PDOF.")
    return notes


def _results(data: ReportData) -> Section:
    blocks = [answer_cards(data.result, data.units, data.spread)]
    if data.errors:
        blocks.insert(0, Callout("Inadmissible answer (the numbers below are not physically "
                                 "possible)", tuple(data.errors)))
    reason = data.fit.contradiction if data.fit is not None else None
    if reason:
        blocks.insert(0, Callout("The evidence contradicts itself (the answer below is the "
                                 "best fit to measurements that cannot all be right)",
                                 (reason,)))
    warnings = _warnings(data)
    if warnings:
        blocks.append(Callout("Warnings", tuple(warnings)))
    blocks.append(data.tables["results"])
    if "pre_impact" in data.tables:
        blocks.append(data.tables["pre_impact"])
    blocks.append(Bullets(tuple(_notes(data))))
    return Section("results", "Results", tuple(blocks), keep=True)


def _misfit(data: ReportData) -> Section | None:
    if "misfit" not in data.tables:
        return None
    sentence = misfit_sentence(data.misfit, data.units, data.fit, data.spread is not None)
    text = sentence or ("Every measured quantity lies within 3 sigma of the model at the "
                        "answer.")
    return Section("misfit", "How well the answer fits the measurements",
                   (Paragraph(text), data.tables["misfit"]), toc="Fit", keep=True)


def _coefficients(data: ReportData) -> Section:
    fit = data.fit
    if fit is None:
        return Section("coefficients", "Coefficients", (Paragraph(
            f"epsilon from the {data.sources['eps']}, beta from the {data.sources['beta']} "
            "(no fit)."),), keep=True)
    rms, unit = convert(fit.rms, "velocity", data.units)
    return Section("coefficients", "Coefficients", (Paragraph(
        f"Fitted to the measured post-impact velocities (least squares, `pim fit`): epsilon = "
        f"{format_number(fit.eps)}, beta = {format_number(fit.beta)} (rms residual "
        f"{format_number(float(rms), sig=3)} {unit})."), data.tables["fit"]), keep=True)


def _inputs(data: ReportData) -> Section:
    notes = estimate_notes(data.case, data.units)
    blocks = (data.tables["inputs"],) + ((Bullets(tuple(notes)),) if notes else ())
    return Section("inputs", "Case inputs", blocks, toc="Inputs")


def _plots(data: ReportData) -> Section:
    figures = tuple(Figure(rel, alt=rel.rsplit("/", 1)[-1].rsplit(".", 1)[0].replace("_", " "))
                    for rel in data.plot_files)
    return Section("plots", "The design sheet's plots", figures, toc="Plots")


def _animation(data: ReportData) -> Section:
    info = data.animation
    if info is None:
        e = data.animation_error
        text = ("(not written: --no-animation)" if e is None
                else f"No animation: the simulation failed ({e.kind}): {e}")
        return Section("animation", "Animation", (Paragraph(text),))
    caption = (f"{ANIMATION_CAPTION} Largest offset between ghost and simulation after the "
               f"impact: {format_number(info.max_ghost_offset_px, sig=2)} px.")
    blocks = [Video("animation.mp4", caption, info.frames, info.fps, tuple(info.size), 0.6)]
    if data.plan:
        blocks.append(Figure(data.plan, "plan view of the event",
                             "The analytic event in plan view: outlines at the stated "
                             "interval with their times, the CG paths, the tyre marks, each "
                             "impact, the rest positions."))
    if info.gif:
        blocks.append(Paragraph("Also as a GIF: [animation.gif](animation.gif)."))
    if info.secondary_impact is not None:
        blocks.append(Callout("Plausibility", (
            f"{info.secondary_impact.message(data.units)}; the animation marks it.",)))
    return Section("animation", "Animation", tuple(blocks))


def _crosscheck(data: ReportData) -> Section:
    s, blocks = data.simulated, []
    if s is not None:
        blocks += [Paragraph(
            f"pymunk settings: dt = {s.settings.dt:g} s, {s.iterations} solver iterations "
            f"(automatic), {s.settings.contact} contact, {s.settings.start} start; wall time "
            f"{format_number(s.wall_time * 1e3, sig=3)} ms. Largest error in the impact's "
            f"velocity changes: **{format_number(data.error, sig=2)}** (relative to the "
            f"largest change; see docs/comparisons.md)."), data.tables["crosscheck"]]
    else:
        e = data.sim_error
        blocks.append(Paragraph(f"The simulation failed ({e.kind}): {e}"))
    if data.event_check is not None:
        blocks += [Paragraph(
            f"The whole event (`pim event`), the analytic event against the pymunk event at "
            f"each impact and at rest: {data.event_check.count_text()}."),
            data.tables["event_crosscheck"]]
    if data.limits:
        blocks += [Paragraph("Where the simulator cannot reproduce PIM here:"),
                   Bullets(tuple(data.limits))]
    return Section("crosscheck", "Appendix A: PIM against a pymunk simulation",
                   tuple(blocks), toc="A: pymunk cross-check")


def _speed_error(data: ReportData) -> Section | None:
    study = data.study
    if study is None:
        return None
    rec = study.recommended()
    if rec is not None:
        its = "automatic" if rec.iterations is None else rec.iterations
        verdict = (f"Recommended: dt = {rec.dt:g} s, {its} iterations ({rec.iterations_used} "
                   f"sweeps), {rec.start} start, {rec.contact} contact: error "
                   f"{format_number(rec.error, sig=2)} in "
                   f"{format_number(rec.wall_time * 1e3, sig=3)} ms per impact, against PIM's "
                   f"{format_number(study.analytic_time * 1e3, sig=3)} ms per call "
                   f"({format_number(study.analytic_batch_time * 1e6, sig=3)} us per case in "
                   f"a batch).")
    else:
        verdict = f"No run reached the target error {study.target:g}."
    every = replace(data.tables["speed_error"], show=False)
    return Section("speed-error", "Appendix B: simulator speed against error (coarse)", (
        Paragraph(f"{len(study.points)} simulator runs over dt, solver iterations, contact "
                  f"start and contact geometry; the full study is "
                  f"`{_command(data, 'speed-error')}`. {verdict}"),
        Figure("speed_error.png", alt="speed against error",
               caption="Error against wall time per impact."),
        data.tables["speed_error_pareto"], every,
        Paragraph(f"Every run: [{every.name}.csv]({every.name}.csv).")),
        toc="B: speed against error")


def _assumptions(data: ReportData) -> Section | None:
    if data.assumptions is None or "assumptions" not in data.tables:
        return None
    table = replace(data.tables["assumptions"], groups=ASSUMPTION_GROUPS)
    return Section("assumptions", "PIM's assumptions (finite-duration crush scene)", (
        Paragraph(ladder_intro(_command(data, "assumptions"))),
        Bullets(tuple(verdicts(data.assumptions, data.units))), table), toc="Assumptions")


def _files(data: ReportData, files: list[str]) -> Section:
    timings = ", ".join(f"{k} {v:.2f} s" for k, v in data.seconds.items())
    return Section("files", "Files", (
        Paragraph("The folder holds, beside the self-contained report.html, this report as "
                  "Markdown (report.md), every table as CSV, every figure as PNG and the "
                  "animation as MP4:"),
        FileList(tuple(files)), Paragraph(f"Timings: {timings}")))


def compare_document(data: ReportData) -> Document:
    """The report of ``data`` (module notes)."""
    sections = [_results(data), _misfit(data), _coefficients(data),
                _inputs(data),
                _plots(data), _animation(data), _crosscheck(data), _speed_error(data),
                _assumptions(data)]
    doc = Document(f"{data.case.name or 'case'}: reconstruction report", "pim compare",
                   tuple(s for s in sections if s is not None), subtitle=_subtitle(data))
    files = sorted(set(data.files) | set(document_files(doc)))
    return replace(doc, sections=doc.sections + (_files(data, files),))
