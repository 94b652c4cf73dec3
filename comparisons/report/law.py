"""``pim compare`` for the impact laws other than Brach's: "kudlich-slibar" (PC-Crash,
Virtual CRASH) and "brach-capped" (docs/impact-laws.md).

The report (report.html, report.md, their CSVs and the animation, written whole or not at
all by :func:`pim.io.output.output_folder` as :mod:`comparisons.report.compare` is, through
the one report pipeline) opens with the answer a reconstruction hands on
(:func:`pim.model.law`'s answer: the cards, the warnings, the results table) and the law
with its parameters, then how well the answer fits the measurements, the coefficients, the
inputs and the animation (the law's pymunk run solid, the analytic post-impact motion as the
ghost), and the appendix compares the analytic answer with that run
(:func:`comparisons.studies.law_runs.simulate_law`).

*What is fitted.* The one fitting engine (:func:`pim.fit`) fits the law's own parameters:
(k, mu_c) under "kudlich-slibar" (mu_c stated as a lower bound where the contact sticks),
(eps, beta) under the cap mu_c for "brach-capped". When the case has measured motion, the
report gives that fit and names the law it was done under; the results stay at the law's
parameters from the case file or the command line. The design sheet's plots, the
speed-error sweep, the uncertainty intervals and the assumptions study are Brach's (eps,
beta) studies: the report says they are not run for this law.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import pim
import sim
from comparisons.animation.collision import animation_plan, build_renderer
from comparisons.animation.render import write_animation
from comparisons.report.compare import Report, crosscheck_table
from comparisons.report.compare_tables import (
    answer_cards,
    fit_table,
    inputs_table,
    misfit_sentence,
    misfit_table,
    results_table,
)
from comparisons.report.document import (
    Bullets,
    Callout,
    Document,
    FileList,
    Paragraph,
    Section,
    Video,
)
from pim.model.number_format import format_number
from comparisons.report.tables import Table
from comparisons.report.write import document_files, write_document
from comparisons.studies.law_runs import LawSetup, simulate_law
from pim.analysis.misfit import misfit
from pim.analysis.residuals import has_measured_terms
from pim.io.output import output_folder, rebase
from pim.io.units import display_units, quantity_text
from pim.model.plausibility import findings
from sim.error_measure import compare_results, impact_error

__all__ = ["compare_law_case", "law_table", "law_document", "LawReport", "NOT_RUN"]

#: The parts of Brach's report not run under another law, and why.
NOT_RUN = ("the design sheet's plots, the coarse speed-error sweep, the 5-95 % uncertainty "
           "intervals and PIM's assumptions study vary Brach's (epsilon, beta); they are not "
           "run for this law (set impact.law = \"brach\" for them)")


def law_table(setup: LawSetup) -> Table:
    """The impact law and its parameters (law.csv)."""
    rows = [("impact law", setup.law, ""), ("restitution (k or epsilon)", setup.restitution, "-")]
    if setup.contact_friction is not None:
        rows.append(("contact friction mu_c", setup.contact_friction, "-"))
    label = "effective beta" if setup.law == "brach-capped" else "equivalent PIM beta"
    rows.append((label, setup.beta, "-"))
    return Table("law", "Impact law and its parameters", ("quantity", "value", "unit"),
                 tuple(rows))


@dataclass
class LawReport:
    """What the law's report shows.

    Attributes
    ----------
    case : pim.Case
        The case.
    setup : LawSetup
        The law, its parameters and its answer.
    units : str
        Unit system of every number shown.
    fit : pim.analysis.fitting.FitResult or None
        The fit of the law's parameters to the measured motion.
    run : sim.SimResult or sim.SimulationError
        The law's pymunk run, or why it failed.
    error : float
        Largest relative error of the impact's velocity changes, the run against the
        analytic answer (NaN when the run failed).
    animation : comparisons.animation.render.AnimationInfo, sim.SimulationError or None
        The animation written, why it could not be simulated, or None (not asked for).
    tables : dict of str to Table
        The tables by name.
    """

    case: pim.Case
    setup: LawSetup
    units: str
    fit: object = None
    run: object = None
    error: float = math.nan
    animation: object = None
    tables: dict = field(default_factory=dict)


def _fit(case: pim.Case, setup: LawSetup):
    """The fit of the law's parameters to the measured motion under the law (or None):
    (k, mu_c) for "kudlich-slibar", (eps, beta) under the cap for "brach-capped"."""
    if not has_measured_terms(case):
        return None
    return pim.fit(case, law=setup.law,
                   mu_c=setup.contact_friction if setup.law == "brach-capped" else None)


def _crosscheck(case, setup, units):
    """The law's pymunk run against the analytic answer: (run or error, table, error)."""
    try:
        run = simulate_law(case, setup)
    except sim.SimulationError as exc:
        return exc, None, math.nan
    error = float(impact_error(case, setup.result, run.velocity1, run.velocity2,
                               run.yaw_rate1, run.yaw_rate2))
    return run, crosscheck_table(compare_results(case, setup.result, run), units), error


def _write_animation(case, setup, out, gif, tyre, units, progress):
    """The animation (AnimationInfo) or the simulation error that prevented it."""
    try:
        simulated = simulate_law(case, setup, animation_plan(case, setup.result, tyre))
        renderer = build_renderer(case, setup.restitution, setup.beta, result=setup.result,
                                  simulated=simulated, tyre=tyre, units=units,
                                  title=f"{case.name or 'case'}: {setup.describe()}")
        return write_animation(renderer, out / "animation.mp4",
                               gif=out / "animation.gif" if gif else None, progress=progress)
    except sim.SimulationError as exc:
        return exc


def compare_law_case(case: pim.Case, out_dir, setup: LawSetup, *, gif: bool = False,
                     animation: bool = True, tyre: float | None = None, progress: bool | None = None,
                     units: str | None = None) -> Report:
    """Write the comparison report of ``case`` under ``setup``'s law to ``out_dir``.

    Parameters
    ----------
    case : pim.Case
        A single case.
    out_dir : path
        Folder to write (created; the earlier run's files are replaced or removed).
    setup : LawSetup
        The law, its parameters and its answer (:func:`comparisons.studies.law_runs.law_setup`).
    gif, animation : bool
        Also write animation.gif; write the animation at all.
    tyre : float or None
        Tyre friction coefficient after the impact in the animation (0: none; None: the
        case's [evidence] friction, else :data:`pim.model.event.DEFAULT_TYRE_FRICTION`).
    progress : bool or None
        tqdm bar of the animation (None: only on a terminal).
    units : {"si", "us"} or pim.io.units.DisplayUnits, optional
        Units of every number (default: the case file's).

    Returns
    -------
    Report
        ``eps`` is the law's restitution, ``beta`` its (effective or equivalent) PIM beta.
    """
    units = display_units(units, case=case)
    out = Path(out_dir)
    with output_folder(out, command="pim compare") as tmp:
        rep = _write(case, tmp, setup, (gif, animation, tyre, progress), units)
    info = rep.animation
    if info is not None:
        info = replace(info, path=out / "animation.mp4",
                       gif=out / "animation.gif" if info.gif else None)
    return replace(rep, out_dir=out, files=rebase(rep.files, tmp, out), animation=info)


def _gather(case, folder: Path, setup, media, units) -> LawReport:
    """Fit, cross-check and animation of the law's report (media: gif, animation, tyre,
    progress)."""
    gif, animation, tyre, progress = media
    data = LawReport(case, setup, units, fit=_fit(case, setup))
    for table in (results_table(setup.result, units), law_table(setup)):
        data.tables[table.name] = table
    found = misfit(setup.result)
    if found.rows:
        data.tables["misfit"] = misfit_table(found, units)
    data.tables["inputs"] = inputs_table(case, units)
    if data.fit is not None:
        data.tables["fit"] = fit_table(data.fit, units)
    data.run, table, data.error = _crosscheck(case, setup, units)
    if table is not None:
        data.tables["crosscheck"] = table
    if animation:
        data.animation = _write_animation(case, setup, folder, gif, tyre, units, progress)
    return data


def _write(case, folder: Path, setup, media, units) -> Report:
    """Gather and write the report into ``folder`` (the temporary output folder)."""
    started = time.perf_counter()
    data = _gather(case, folder, setup, media, units)
    rep = Report(out_dir=folder, eps=setup.restitution, beta=setup.beta, error=data.error)
    info = data.animation
    if info is not None and not isinstance(info, sim.SimulationError):
        rep.files += [p for p in (info.path, info.gif) if p is not None]
        rep.animation = info
    rep.files += write_document(law_document(data), folder)
    rep.seconds["report"] = time.perf_counter() - started
    return rep


def _fit_lines(setup, fit) -> str:
    if fit is None:
        return (f"No measured motion in the case: {setup.parameters()} from the case file or "
                "the command line (no fit).")
    if fit.law == "kudlich-slibar":
        lower = fit.lower_bounds.get("impact.mu_c")
        mu_c = (f"mu_c >= {lower:.6g} (only a lower bound: the fitted contact sticks, and any "
                f"mu_c above it gives the same answer)" if lower is not None
                else f"mu_c = {fit.contact_friction:.6g}")
        text = (f"The fit is done under the **Kudlich-Slibar law** (the one fitting engine, "
                f"`pim fit`, exact derivatives): k = {fit.eps:.6g}, {mu_c}; `pim compare "
                f"CASE --k {fit.eps:.4g} --mu-c {fit.contact_friction:.4g}` reports the law "
                "there.")
    else:
        text = (f"The fit is done under the **friction-capped Brach law** (cap mu_c = "
                f"{fit.contact_friction:.6g}; the one fitting engine, `pim fit`): epsilon = "
                f"{fit.eps:.6g}, beta = {fit.beta:.6g}.")
    return f"{text} The results above stay at the law's parameters ({setup.parameters()})."


def _results(data: LawReport) -> Section:
    setup, r = data.setup, data.setup.result
    found = findings(data.case, r, show=quantity_text(data.units))
    warnings = list(found.warnings)
    sentence = misfit_sentence(misfit(r), data.units, data.fit)
    if sentence:
        warnings.append(sentence)
    blocks = [answer_cards(r, data.units)]
    if found.errors:
        blocks.insert(0, Callout("Inadmissible answer (the numbers below are not physically "
                                 "possible)", tuple(found.errors)))
    if warnings:
        blocks.append(Callout("Warnings", tuple(warnings)))
    blocks += [data.tables["results"], Bullets((
        f"**{setup.parameters()}**; impulse ratio Pt / Pn = {format_number(float(r.mu))}.",
        "No intervals under this law (4 significant digits).")), data.tables["law"]]
    return Section("results", "Results", tuple(blocks), keep=True)


def _animation_section(data: LawReport) -> Section:
    info = data.animation
    if isinstance(info, sim.SimulationError):
        text = f"No animation: the simulation failed ({info.kind}): {info}"
    elif info is None:
        text = "(not written: --no-animation)"
    else:
        caption = ("Filled outlines: the law's pymunk run; dashed magenta outlines: the "
                   "analytic post-impact motion. Largest offset between them after the "
                   f"impact: {format_number(info.max_ghost_offset_px, sig=2)} px.")
        return Section("animation", "Animation", (
            Video("animation.mp4", caption, info.frames, info.fps, tuple(info.size), 0.6),))
    return Section("animation", "Animation", (Paragraph(text),))


def _appendix(data: LawReport) -> Section:
    run = data.run
    if isinstance(run, sim.SimulationError):
        blocks = (Paragraph(f"The simulation failed ({run.kind}): {run}"),)
    else:
        how = ("two phases: compression by the engine at restitution 0 and Coulomb "
               "coefficient mu_c, then k times its impulse"
               if data.setup.law == "kudlich-slibar"
               else "the rigid Brach scene at the effective beta")
        blocks = (Paragraph(f"pymunk run ({how}). Largest error in the impact's velocity "
                            f"changes: **{format_number(data.error, sig=2)}** (relative to "
                            f"the largest change)."), data.tables["crosscheck"])
    return Section("crosscheck", "Appendix A: the analytic answer against the law's pymunk run",
                   blocks, toc="A: pymunk cross-check")


def law_document(data: LawReport) -> Document:
    """The report of ``pim compare`` under the law of ``data.setup`` (module notes)."""
    coefficients = [Paragraph(_fit_lines(data.setup, data.fit))]
    if "fit" in data.tables:
        coefficients.append(data.tables["fit"])
    sections = [_results(data)]
    if "misfit" in data.tables:
        sections.append(Section("misfit", "How well the answer fits the measurements", (
            Paragraph(misfit_sentence(misfit(data.setup.result), data.units, data.fit)
                      or "Every measured quantity lies within 3 sigma of the model at the "
                         "answer."), data.tables["misfit"]), toc="Fit", keep=True))
    sections += [Section("coefficients", "Coefficients", tuple(coefficients), keep=True),
                 Section("inputs", "Case inputs", (data.tables["inputs"],), toc="Inputs"),
                 _animation_section(data), _appendix(data),
                 Section("not-run", "Not run for this law", (Bullets((f"{NOT_RUN}.",)),),
                         toc="Not run")]
    name = data.case.name or "case"
    doc = Document(f"{name}: reconstruction report", "pim compare", tuple(sections),
                   subtitle=((data.case.description or "").rstrip(".") + ". "
                             if getattr(data.case, "description", None) else "")
                   + f"Written by `pim compare` in {display_units(data.units)}. Impact law: "
                   f"**{data.setup.describe()}** (docs/impact-laws.md).")
    info = data.animation
    media = [] if info is None or isinstance(info, sim.SimulationError) else \
        ["animation.mp4"] + (["animation.gif"] if info.gif else [])
    files = sorted(set(media) | set(document_files(doc)))
    return replace(doc, sections=doc.sections + (
        Section("files", "Files", (FileList(tuple(files)),)),))
