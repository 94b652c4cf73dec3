"""The HTML renderer of a :class:`~comparisons.report.data.ReportData`: ``report.html``.

One self-contained file beside ``report.md`` (:mod:`pim.io.html` builds the blocks): the
results first (within the first screen), then the coefficients, inputs, the design sheet's
plots inlined as PNG, the animation playable in the page (base64 MP4), the appendices and PIM's
assumptions, whose 20-column table is split into groups of columns that fit a screen (one
row per assumption in each). Every number is in the report's units; the figures and the
video are read from the report's folder, nothing else is touched.
"""

from __future__ import annotations

import shlex
from pathlib import Path

from pim.io import html as h
from pim.io.inertia_data import estimate_notes
from pim.io.units import convert, display_units

from comparisons.report.assumptions import assumption_tables, ladder_intro, verdicts
from comparisons.report.data import ReportData, monte_carlo_note
from comparisons.report.tables import Table, fmt_value

__all__ = ["render_html", "html_table", "HTML_NAME"]

#: File name of the HTML report.
HTML_NAME = h.HTML_REPORT_NAME

def html_table(table: Table, *, columns=None, title: str | None = None, note: str = "",
               cls: str = "", part: int | None = None) -> str:
    """``table`` (or its ``columns`` only: ``part`` numbers the part) as HTML, cells
    formatted as in the Markdown; its id is ``table-NAME`` (``table-NAME-PART``)."""
    columns = list(table.columns if columns is None else columns)
    index = [table.columns.index(c) for c in columns]
    rows = [[table.formats.get(table.columns[i], fmt_value)(row[i]) for i in index]
            for row in table.rows]
    return h.table(columns, rows, title=table.title if title is None else title, note=note,
                   id=f"table-{table.name}" + ("" if part is None else f"-{part}"), cls=cls)


def _command(data: ReportData, name: str) -> str:
    return f"pim {name} {shlex.quote(data.case_path)}"


def _csv(table: Table) -> str:
    return f"CSV: `{table.name}.csv`"


def _facts(data: ReportData) -> str:
    r, s = data.result, data.sources
    items = [("epsilon", f"{data.eps:.4g}", s["eps"]), ("beta", f"{data.beta:.4g}", s["beta"]),
             ("impulse ratio mu", f"{float(r.mu):.4g}", f"mu0 = {float(r.mu0):.4g}")]
    if data.simulated is not None:
        items.append(("pymunk against PIM", f"{data.error:.1e}", "relative error"))
    shown = display_units(data.units)
    items.append(("units", f"{shown.system.upper()}, speeds in {shown.speed}",
                  "--units and --speed-unit change them"))
    return h.facts(items)


def _results(data: ReportData) -> str:
    notes = []
    table = data.case.uncertainty
    if table is not None:
        notes.append(monte_carlo_note(data.case))
    if bool(data.case.vehicle2.fixed):
        notes.append("Vehicle 2 is a fixed obstacle: it has no delta-V and no PDOF.")
    body = [_facts(data), html_table(data.tables["results"],
                                     note=_csv(data.tables["results"]))]
    if data.errors:
        body.insert(0, '<div class="warn"><strong>Inadmissible answer</strong> (the numbers '
                    'below are not physically possible)' + h.bullets(data.errors) + "</div>")
    if "pre_impact" in data.tables:
        body.append(html_table(data.tables["pre_impact"], note=_csv(data.tables["pre_impact"])))
    if notes:
        body.append(h.bullets(notes))
    if data.warnings:
        body.append('<div class="warn"><strong>Warnings</strong>'
                    + h.bullets(data.warnings) + "</div>")
    return h.section("Results", body, id="results", cls="keep")


def _coefficients(data: ReportData) -> str:
    fit = data.fit
    if fit is None:
        return h.section("Coefficients", h.paragraph(
            f"epsilon from the {data.sources['eps']}, beta from the {data.sources['beta']} "
            "(no fit)."), id="coefficients", cls="keep")
    rms, unit = convert(fit.rms, "velocity", data.units)
    return h.section("Coefficients", [h.paragraph(
        f"Fitted to the measured post-impact velocities (least squares, `pim fit`): "
        f"epsilon = {fit.eps:.6g}, beta = {fit.beta:.6g} (rms residual {float(rms):.4g} "
        f"{unit})."), html_table(data.tables["fit"], note=_csv(data.tables["fit"]))],
        id="coefficients", cls="keep")


def _inputs(data: ReportData) -> str:
    body = [html_table(data.tables["inputs"], note=_csv(data.tables["inputs"]))]
    notes = estimate_notes(data.case, data.units)
    if notes:
        body.append(h.bullets(notes))
    return h.section("Case inputs", body, id="inputs")


def _plots(data: ReportData, folder: Path) -> str:
    figures = [h.figure(folder / rel, alt=Path(rel).stem.replace("_", " "),
                        caption=f"`{rel}`") for rel in data.plot_files]
    return h.section("The design sheet's plots", '<div class="grid">' + "".join(figures)
                     + "</div>", id="plots")


def _animation(data: ReportData, folder: Path) -> str:
    info = data.animation
    if info is None:
        text = ("not written (--no-animation)." if data.animation_error is None else
                f"the simulation failed ({data.animation_error.kind}): {data.animation_error}")
        return h.section("Animation", h.paragraph("No animation: " + text), id="animation")
    mp4 = folder / "animation.mp4"
    caption = ("Filled outlines: the pymunk simulation; dashed magenta outlines: PIM's "
               "post-impact motion (free rigid motion from the impact configuration with PIM's "
               "velocities and yaw rates); red: the impulse on vehicle 1 at C; green: C, the "
               "contact plane and the normal n. Largest offset between ghost and simulation "
               f"after the impact: {info.max_ghost_offset_px:.2g} px. File: `animation.mp4`.")
    body = [h.video(mp4, caption=caption, frames=info.frames, fps=info.fps, size=info.size,
                    still=h.still_frame(mp4, 0.6))]
    if info.secondary_impact is not None:
        body.append(f'<div class="warn"><strong>Plausibility:</strong> '
                    f"{h.esc(info.secondary_impact.message(data.units))}; the animation marks "
                    f"it.</div>")
    return h.section("Animation", body, id="animation")


def _crosscheck(data: ReportData) -> str:
    s, body = data.simulated, []
    if s is not None:
        body += [h.paragraph(
            f"pymunk settings: dt = {s.settings.dt:g} s, {s.iterations} solver iterations "
            f"(automatic), {s.settings.contact} contact, {s.settings.start} start; wall time "
            f"{s.wall_time * 1e3:.3g} ms. Largest error in the impact's velocity changes: "
            f"**{data.error:.2e}** (relative to the largest change; docs/comparisons.md)."),
            html_table(data.tables["crosscheck"], note=_csv(data.tables["crosscheck"]))]
    else:
        body.append(h.paragraph(f"The simulation failed ({data.sim_error.kind}): "
                                f"{data.sim_error}"))
    if data.limits:
        body += [h.paragraph("Where the simulator cannot reproduce PIM here:"),
                 h.bullets(data.limits)]
    return h.section("Appendix A: PIM against a pymunk simulation", body, id="crosscheck")


def _speed_error(data: ReportData, folder: Path) -> str:
    study = data.study
    if study is None:
        return ""
    rec = study.recommended()
    if rec is None:
        verdict = f"No run reached the target error {study.target:g}."
    else:
        its = "automatic" if rec.iterations is None else rec.iterations
        verdict = (f"Recommended: dt = {rec.dt:g} s, {its} iterations ({rec.iterations_used} "
                   f"sweeps), {rec.start} start, {rec.contact} contact: error {rec.error:.2e} "
                   f"in {rec.wall_time * 1e3:.3g} ms per impact, against PIM's "
                   f"{study.analytic_time * 1e3:.3g} ms per call.")
    pareto = data.tables["speed_error_pareto"]
    return h.section("Appendix B: simulator speed against error (coarse)", [
        h.paragraph(f"{len(study.points)} simulator runs over dt, solver iterations, contact "
                    f"start and contact geometry; the full study is "
                    f"`{_command(data, 'speed-error')}`. {verdict}"),
        h.figure(folder / "speed_error.png", alt="speed against error",
                 caption="Error against wall time per impact."),
        html_table(pareto, note=f"{_csv(pareto)}; every run: `speed_error.csv`")],
        id="speed-error")


def _assumptions(data: ReportData) -> str:
    if data.assumptions is None or "assumptions" not in data.tables:
        return ""
    table = data.tables["assumptions"]
    parts = assumption_tables(table)
    return h.section("PIM's assumptions (finite-duration crush scene)", [
        h.paragraph(ladder_intro(_command(data, "assumptions"))),
        h.bullets(verdicts(data.assumptions, data.units)),
        h.paragraph(f"The table at typical values, in {len(parts)} parts (one row per "
                    f"assumption in each; all columns: `{table.name}.csv`)."),
        *parts], id="assumptions")


def _files(data: ReportData) -> str:
    names = sorted(set(data.files) | {HTML_NAME, "report.md"})
    links = "<ul class=\"files\">" + "".join(
        f'<li><a href="{h.esc(n)}">{h.esc(n)}</a></li>' for n in names) + "</ul>"
    timing = h.table(("step", "time [s]"), [(k, f"{v:.2f}") for k, v in data.seconds.items()],
                     title="Timings")
    return h.section("Files and timings", [h.paragraph(
        "The folder holds, beside this self-contained page, the Markdown report and every "
        "table as CSV, figure as PNG and the animation as MP4:"), links, timing], id="files")


def render_html(data: ReportData, folder) -> str:
    """The text of ``report.html``: ``data`` rendered, the figures and the animation read
    from ``folder`` (the report's folder) and inlined."""
    folder = Path(folder)
    sections = [_results(data), _coefficients(data), _inputs(data), _plots(data, folder),
                _animation(data, folder), _crosscheck(data), _speed_error(data, folder),
                _assumptions(data), _files(data)]
    contents = [("results", "Results"), ("coefficients", "Coefficients"),
                ("inputs", "Inputs"), ("plots", "Plots"), ("animation", "Animation"),
                ("crosscheck", "A: pymunk cross-check")]
    if data.study is not None:
        contents.append(("speed-error", "B: speed against error"))
    if data.assumptions is not None:
        contents.append(("assumptions", "Assumptions"))
    contents.append(("files", "Files"))
    description = getattr(data.case, "description", None) or ""
    subtitle = (description.rstrip(".") + ". " if description else "") + (
        f"Written by `pim compare` in {display_units(data.units)}: Brach's "
        "Planar Impact Mechanics (PIM) with a pymunk (Chipmunk2D) cross-check.")
    return h.page(f"{data.case.name or 'case'}: reconstruction report", sections,
                  subtitle=subtitle, contents=contents, generator="pim compare")
