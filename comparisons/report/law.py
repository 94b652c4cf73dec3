"""``pim compare`` for the impact laws other than Brach's: "kudlich-slibar" (PC-Crash,
Virtual CRASH) and "brach-capped" (docs/impact-laws.md).

The report (report.md with its CSVs and the animation, written whole or not at all by
:func:`pim.io.output.output_folder` as :mod:`comparisons.report.compare` is; no report.html yet)
opens with the law, its parameters and the results a reconstruction hands on
(:func:`pim.solve`'s answer), then the coefficients, the inputs and the animation (the
law's pymunk run solid, the analytic post-impact motion as the ghost), and the appendix
compares the analytic answer with that run (:func:`comparisons.studies.law_runs.simulate_law`).

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
from dataclasses import replace
from pathlib import Path

import pim
import sim
from pim.analysis.residuals import has_measured_terms
from pim.io.files import write_text
from pim.io.output import output_folder, rebase
from pim.io.units import display_units, quantity_text
from pim.model.plausibility import findings
from sim.error_measure import compare_results, impact_error

from comparisons.animation.render import animation_settings, build_renderer, write_animation
from comparisons.studies.law_runs import LawSetup, simulate_law
from comparisons.report.compare import Report, crosscheck_table, fit_table, inputs_table, results_table
from comparisons.report.render import md_table
from comparisons.report.tables import Table

__all__ = ["compare_law_case", "law_table", "NOT_RUN"]

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


def _animation(case, setup, out, gif, tyre, units, progress):
    """The animation (AnimationInfo) or the simulation error that prevented it."""
    try:
        simulated = simulate_law(case, setup, animation_settings(2.0, tyre))
        renderer = build_renderer(case, setup.restitution, setup.beta, result=setup.result,
                                  simulated=simulated, tyre=tyre, units=units,
                                  title=f"{case.name or 'case'}: {setup.describe()}")
        return write_animation(renderer, out / "animation.mp4",
                               gif=out / "animation.gif" if gif else None, progress=progress)
    except sim.SimulationError as exc:
        return exc


def compare_law_case(case: pim.Case, out_dir, setup: LawSetup, *, gif: bool = False,
                     animation: bool = True, tyre: float = 0.0, progress: bool | None = None,
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
    tyre : float
        Tyre friction coefficient after the impact in the animation (0: none).
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
        rep = _write(case, tmp, setup, gif, animation, tyre, progress, units)
    info = rep.animation
    if info is not None:
        info = replace(info, path=out / "animation.mp4",
                       gif=out / "animation.gif" if info.gif else None)
    return replace(rep, out_dir=out, files=rebase(rep.files, tmp, out), animation=info)


def _write(case, folder: Path, setup, gif, animation, tyre, progress, units) -> Report:
    """Gather and write the report into ``folder`` (the temporary output folder)."""
    started = time.perf_counter()
    rep = Report(out_dir=folder, eps=setup.restitution, beta=setup.beta)
    fit = _fit(case, setup)
    tables = [results_table(setup.result, units), law_table(setup), inputs_table(case, units)]
    if fit is not None:
        tables.append(fit_table(fit, units))
    run, table, rep.error = _crosscheck(case, setup, units)
    if table is not None:
        tables.append(table)
    info = None
    if animation:
        info = _animation(case, setup, folder, gif, tyre, units, progress)
        if not isinstance(info, sim.SimulationError):
            rep.files += [p for p in (info.path, info.gif) if p is not None]
            rep.animation = info
    for t in tables:
        rep.files.append(t.write_csv(folder))
    rep.seconds["report"] = time.perf_counter() - started
    text = _markdown(case, setup, fit, run, info, tables, rep, units)
    rep.files.append(write_text(folder / "report.md", text))
    return rep


def _fit_lines(setup, fit) -> list[str]:
    if fit is None:
        return [f"No measured motion in the case: {setup.parameters()} from the case file or "
                "the command line (no fit).", ""]
    if fit.law == "kudlich-slibar":
        lower = fit.lower_bounds.get("impact.mu_c")
        mu_c = (f"mu_c >= {lower:.6g} (only a lower bound: the fitted contact sticks, and any "
                f"mu_c above it gives the same answer)" if lower is not None
                else f"mu_c = {fit.contact_friction:.6g}")
        lines = [f"The fit is done under the **Kudlich-Slibar law** (the one fitting engine, "
                 f"`pim fit`, exact derivatives): k = {fit.eps:.6g}, {mu_c}; `pim compare "
                 f"CASE --k {fit.eps:.4g} --mu-c {fit.contact_friction:.4g}` reports the law "
                 "there."]
    else:
        lines = [f"The fit is done under the **friction-capped Brach law** (cap mu_c = "
                 f"{fit.contact_friction:.6g}; the one fitting engine, `pim fit`): epsilon = "
                 f"{fit.eps:.6g}, beta = {fit.beta:.6g}."]
    lines.append(f"The results above stay at the law's parameters ({setup.parameters()}).")
    return [" ".join(lines), ""]


def _markdown(case, setup, fit, run, info, tables, rep, units) -> str:
    by_name = {t.name: t for t in tables}
    name = case.name or "case"
    lines = [f"# {name}: reconstruction report", ""]
    if getattr(case, "description", None):
        lines += [case.description, ""]
    lines += [f"Written by `pim compare` in {units}. Impact law: "
              f"**{setup.describe()}** (docs/impact-laws.md).", "", "## Results", ""]
    r = setup.result
    found = findings(case, r, show=quantity_text(units))
    if found.errors:
        lines += ["**Inadmissible answer** (the numbers below are not physically possible):",
                  ""] + [f"- {p}" for p in found.errors] + [""]
    lines += [f"- **{setup.parameters()}**; impulse ratio Pt / Pn = {float(r.mu):.4g}.", "",
              md_table(by_name["results"]), md_table(by_name["law"])]
    if found.warnings:
        lines += ["Warnings:", ""] + [f"- {p}" for p in found.warnings] + [""]
    lines += ["## Coefficients", ""] + _fit_lines(setup, fit)
    if "fit" in by_name:
        lines += [md_table(by_name["fit"])]
    lines += ["## Case inputs", "", md_table(by_name["inputs"]), "## Animation", ""]
    if isinstance(info, sim.SimulationError):
        lines += [f"No animation: the simulation failed ({info.kind}): {info}", ""]
    elif info is not None:
        lines += [f"[animation.mp4](animation.mp4) ({info.frames} frames at {info.fps} fps). "
                  f"Filled outlines: the law's pymunk run; dashed magenta outlines: the "
                  f"analytic post-impact motion. Largest offset between them after the "
                  f"impact: {info.max_ghost_offset_px:.2g} px.", ""]
        if info.secondary_impact is not None:
            lines += [f"**Plausibility:** {info.secondary_impact.message(units)}; the "
                      f"animation marks it.", ""]
    else:
        lines += ["(not written: --no-animation)", ""]
    lines += ["## Appendix A: the analytic answer against the law's pymunk run", ""]
    if isinstance(run, sim.SimulationError):
        lines += [f"The simulation failed ({run.kind}): {run}", ""]
    else:
        how = ("two phases: compression by the engine at restitution 0 and Coulomb "
               "coefficient mu_c, then k times its impulse" if setup.law == "kudlich-slibar"
               else "the rigid Brach scene at the effective beta")
        lines += [f"pymunk run ({how}). Largest error in the impact's velocity changes: "
                  f"**{rep.error:.2e}** (relative to the largest change).", "",
                  md_table(by_name["crosscheck"])]
    lines += ["## Not run for this law", "", f"- {NOT_RUN}.", "", "## Files", ""]
    for path in sorted({p.relative_to(rep.out_dir).as_posix() for p in rep.files}
                       | {"report.md"}):
        lines.append(f"- [{path}]({path})")
    lines.append("")
    return "\n".join(lines)

