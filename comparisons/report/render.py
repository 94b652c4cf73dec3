"""Renderers of a :class:`~comparisons.report.data.ReportData`: Markdown and CSV.

Each renderer is a pure function of the report data (no simulation, no file system): the
Markdown text of ``report.md`` (:func:`render_markdown`, one function per section) and the
CSV files of the tables (:func:`render_csv`). An HTML renderer would be one more function of
the same object.
"""

from __future__ import annotations

import shlex

import numpy as np

from pim.io.inertia_data import estimate_notes
from pim.io.units import convert, display_units

from comparisons.report.assumptions import ladder_intro, verdicts
from comparisons.report.data import ReportData, monte_carlo_note
from comparisons.report.tables import Table

__all__ = ["render_markdown", "render_csv", "md_table", "REPORT_NAME"]

#: File name of the Markdown report.
REPORT_NAME = "report.md"


def md_table(table: Table) -> str:
    """A table under its title with a link to its CSV."""
    return f"**{table.title}** ([{table.name}.csv]({table.name}.csv))\n\n{table.to_markdown()}\n"


def render_csv(data: ReportData) -> dict[str, str]:
    """The CSV files of the report: file name -> text."""
    return {f"{t.name}.csv": t.to_csv() for t in data.tables.values()}


def render_markdown(data: ReportData) -> str:
    """The text of ``report.md``."""
    lines = []
    for section in (_head, _results, _coefficients, _inputs, _plots, _animation, _crosscheck,
                    _speed_error, _assumptions, _files):
        lines += section(data)
    return "\n".join(lines)


def _command(data: ReportData, name: str) -> str:
    """A command runnable as printed: the case as the user gave it, quoted for a shell."""
    return f"pim {name} {shlex.quote(data.case_path)}"


def _describe(dist, kind: str, units: str) -> str:
    """A distribution of the [uncertainty] table in words, in display units."""
    def v(x):
        return f"{float(convert(x, kind, units)[0]):.4g}" if kind != "dimensionless" \
            else f"{x:.4g}"

    if dist.kind == "uniform":
        return f"uniform on [{v(dist.a)}, {v(dist.b)}]"
    if dist.kind == "plusminus":
        return f"nominal +- {v(dist.b)} (uniform)"
    if dist.kind == "normal":
        return "normal, sd " + v(dist.b) + ("" if dist.a is None else f", mean {v(dist.a)}")
    return f"fixed at {v(dist.a)}"


def _head(data: ReportData) -> list[str]:
    lines = [f"# {data.case.name or 'case'}: reconstruction report", ""]
    if getattr(data.case, "description", None):
        lines += [data.case.description, ""]
    return lines + [
        f"Written by `pim compare` in {display_units(data.units)} (`--units` and "
        "`--speed-unit` change them). "
        "Brach's Planar Impact Mechanics (PIM) gives the post-impact motion in closed "
        "form from the case's inputs and two coefficients, epsilon (restitution) and "
        "beta (the fraction of the impulse ratio that stops the sliding at C). The "
        "appendix checks PIM against a pymunk (Chipmunk2D) simulation of the same "
        "impact.", ""]


def _results(data: ReportData) -> list[str]:
    r, s = data.result, data.sources
    lines = ["## Results", ""]
    if data.errors:
        lines += ["**Inadmissible answer** (the numbers below are not physically possible):",
                  ""] + [f"- {p}" for p in data.errors] + [""]
    lines += [f"- **epsilon = {data.eps:.6g}** ({s['eps']}), **beta = {data.beta:.6g}** "
             f"({s['beta']}); impulse ratio mu = {float(r.mu):.4g} "
             f"(mu0 = {float(r.mu0):.4g})."]
    table = data.case.uncertainty
    if table is not None:
        for key, label in (("impact.restitution", "epsilon"), ("impact.beta", "beta")):
            if key in table.inputs:
                lines.append(f"- {label} in the `[uncertainty]` table: "
                             f"{_describe(table.inputs[key], 'dimensionless', data.units)}.")
        lines.append(f"- {monte_carlo_note(data.case)}")
    if bool(np.asarray(data.case.vehicle2.fixed)):
        lines.append("- Vehicle 2 is a fixed obstacle: it has no delta-V and no PDOF.")
    lines += ["", md_table(data.tables["results"])]
    if "pre_impact" in data.tables:
        lines += [md_table(data.tables["pre_impact"])]
    if data.warnings:
        lines += ["Warnings:", ""] + [f"- {p}" for p in data.warnings] + [""]
    return lines


def _coefficients(data: ReportData) -> list[str]:
    lines = ["## Coefficients", ""]
    fit = data.fit
    if fit is None:
        return lines + [f"epsilon from the {data.sources['eps']}, beta from the "
                        f"{data.sources['beta']} (no fit).", ""]
    rms, unit = convert(fit.rms, "velocity", data.units)
    return lines + [f"Fitted to the measured post-impact velocities (least squares, "
                    f"`pim fit`): epsilon = {fit.eps:.6g}, beta = {fit.beta:.6g} "
                    f"(rms residual {float(rms):.4g} {unit}).", "",
                    md_table(data.tables["fit"])]


def _inputs(data: ReportData) -> list[str]:
    notes = [f"- {line}" for line in estimate_notes(data.case, data.units)]
    return ["## Case inputs", "", md_table(data.tables["inputs"])] + (notes + [""] if notes
                                                                      else [])


def _plots(data: ReportData) -> list[str]:
    lines = ["## The design sheet's plots", ""]
    for rel in data.plot_files:
        stem = rel.rsplit("/", 1)[-1].rsplit(".", 1)[0]
        lines += [f"![{stem}]({rel})", ""]
    return lines


def _animation(data: ReportData) -> list[str]:
    lines = ["## Animation", ""]
    info = data.animation
    if info is not None:
        lines += [f"[animation.mp4](animation.mp4) ({info.frames} frames at {info.fps} fps, "
                  f"{info.size[0]} x {info.size[1]} px"
                  + (", also [animation.gif](animation.gif)" if info.gif else "") + "). "
                  "Filled outlines: the pymunk simulation; dashed magenta outlines: PIM's "
                  "post-impact motion (free rigid motion from the impact configuration with "
                  "PIM's velocities and yaw rates); red: the impulse on vehicle 1 at C; green: "
                  "C, the contact plane and the normal n. "
                  f"Largest offset between ghost and simulation after the impact: "
                  f"{info.max_ghost_offset_px:.2g} px.", ""]
        if info.secondary_impact is not None:
            lines += [f"**Plausibility:** {info.secondary_impact.message(data.units)}; the animation "
                      f"marks it.", ""]
    elif data.animation_error is not None:
        e = data.animation_error
        lines += [f"No animation: the simulation failed ({e.kind}): {e}", ""]
    else:
        lines += ["(not written: --no-animation)", ""]
    return lines


def _crosscheck(data: ReportData) -> list[str]:
    lines = ["## Appendix A: PIM against a pymunk simulation", ""]
    s = data.simulated
    if s is not None:
        lines += [f"pymunk settings: dt = {s.settings.dt:g} s, {s.iterations} solver iterations "
                  f"(automatic), {s.settings.contact} contact, {s.settings.start} start; "
                  f"wall time {s.wall_time * 1e3:.3g} ms. Largest error in the impact's "
                  f"velocity changes: **{data.error:.2e}** (relative to the largest change; "
                  f"see docs/comparisons.md).", "", md_table(data.tables["crosscheck"])]
    else:
        e = data.sim_error
        lines += [f"The simulation failed ({e.kind}): {e}", ""]
    if data.limits:
        lines += ["Where the simulator cannot reproduce PIM here:", ""]
        lines += [f"- {t}" for t in data.limits] + [""]
    return lines


def _speed_error(data: ReportData) -> list[str]:
    study = data.study
    if study is None:
        return []
    lines = ["## Appendix B: simulator speed against error (coarse)", "",
             f"{len(study.points)} simulator runs over dt, solver iterations, contact "
             f"start and contact geometry; the full study is "
             f"`{_command(data, 'speed-error')}`.", ""]
    rec = study.recommended()
    if rec is not None:
        its = "automatic" if rec.iterations is None else rec.iterations
        lines += [f"Recommended: dt = {rec.dt:g} s, {its} iterations "
                  f"({rec.iterations_used} sweeps), {rec.start} start, {rec.contact} "
                  f"contact: error {rec.error:.2e} in {rec.wall_time * 1e3:.3g} ms per "
                  f"impact, against PIM's {study.analytic_time * 1e3:.3g} ms per call "
                  f"({study.analytic_batch_time * 1e6:.3g} us per case in a batch).", ""]
    else:
        lines += [f"No run reached the target error {study.target:g}.", ""]
    return lines + ["![speed against error](speed_error.png)", "",
                    md_table(data.tables["speed_error_pareto"]),
                    "Every run: [speed_error.csv](speed_error.csv).", ""]


def _assumptions(data: ReportData) -> list[str]:
    if data.assumptions is None:
        return []
    return (["## PIM's assumptions (finite-duration crush scene)", "",
             ladder_intro(_command(data, "assumptions")), ""]
            + [f"- {v}" for v in verdicts(data.assumptions, data.units)] + [""]
            + [md_table(data.tables["assumptions"])])


def _files(data: ReportData) -> list[str]:
    lines = ["## Files", ""]
    for rel in sorted(set(data.files) | {REPORT_NAME}):
        lines.append(f"- [{rel}]({rel})")
    return lines + ["", "Timings: " + ", ".join(f"{k} {v:.2f} s"
                                                for k, v in data.seconds.items()), ""]
