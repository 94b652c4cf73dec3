"""``pim compare``: the whole story of one case in a folder -- report.md, CSVs, PNGs, MP4.

The report opens with what a reconstruction hands on (results.csv): each vehicle's delta-V
(magnitude, components, PDOF and clock position), post-impact speeds and yaw rates, the
energy loss and its normal/tangential crush split, epsilon and beta with their source (fit,
case file, command line) and, where the case has an ``[uncertainty]`` table, 5-95 %
intervals. Then the coefficients (fit.csv), the inputs (inputs.csv), the design sheet's plots
(plots/*.png) and the animation (animation.mp4, optionally .gif); the appendix holds the
PIM-against-pymunk cross-check (crosscheck.csv) and a coarse speed-against-error sweep
(speed_error*.csv, speed_error.png; the full study is ``pim speed-error``). Every number is
in the case file's unit system unless ``units`` says otherwise.

Each file is written atomically and report.md last, so it only exists when every file it
links does. A rerun into the same folder removes the files of the earlier run that this run
does not write (the folder's ``.pim-compare-files`` lists them) and temporary files left by
killed runs, so the folder never mixes runs. The plots render in a forked worker process
while the animation and the sweep run in this one (``parallel=False`` for one process).

The appendix also summarises PIM's assumptions at typical values (the finite-duration crush
scene, :mod:`comparisons.assumptions`; assumptions.csv); the full study is
``pim assumptions``. The animation and the report say so when the outlines run into each
other again after the impact (a secondary impact PIM does not model,
:func:`sim.find_secondary_impact`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import pim
import sim
from pim.analysis.residuals import has_measured_terms
from pim.io.files import save_figure, write_text
from pim.io.units import convert
from pim.model.plausibility import warnings_of
from pim.model.quantities import OUTPUTS as QUANTITIES
from pim.plotting.sheet import write_plots
from pim.plotting.tables import summarize
from sim.error_measure import KIND_OF_UNIT, compare_results, impact_error

from .animation import build_renderer, write_animation
from .assumptions import assumption_table, run_assumptions
from .coefficients import coefficients
from .speed_error import COARSE, pareto_table, plot_speed_error, study_table, sweep
from .tables import Table, fmt_error

__all__ = ["Report", "compare_case", "inputs_table", "fit_table", "crosscheck_table",
           "results_table", "MANIFEST"]

#: File in the report folder listing the files the last run wrote (relative paths).
MANIFEST = ".pim-compare-files"


def _f(x) -> float:
    return float(np.asarray(x, float).reshape(()))


@dataclass
class Report:
    """What :func:`compare_case` wrote and measured."""

    out_dir: Path
    files: list[Path] = field(default_factory=list)
    eps: float = math.nan
    beta: float = math.nan
    error: float = math.nan
    seconds: dict = field(default_factory=dict)
    animation: object = None
    study: object = None
    assumptions: object = None

    @property
    def report(self) -> Path:
        return self.out_dir / "report.md"


def inputs_table(case: pim.Case, units: str = "si") -> Table:
    """The case's inputs in the ``units`` system ("si" or "us")."""
    def val(x, kind):
        value, unit = convert(np.asarray(x, float), kind, units)
        return value, unit

    def pair(x, kind):
        (a, b), unit = val(np.asarray(x, float).reshape(2), kind)
        return f"{a:.6g}, {b:.6g}", unit

    rows = []
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        fixed = bool(v.fixed)
        mass, mass_unit = val(_f(v.mass), "mass")
        inertia, inertia_unit = val(_f(v.yaw_inertia), "inertia")
        cg, length_unit = pair(v.cg, "length")
        vel, vel_unit = pair(v.velocity, "velocity")
        yaw, yaw_unit = val(_f(v.yaw_rate), "angular_velocity")
        size = "" if v.length is None else \
            f"{float(val(v.length, 'length')[0]):.4g} x {float(val(v.width, 'length')[0]):.4g}"
        rows += [
            (f"vehicle {i}", "mass", "fixed obstacle" if fixed else float(mass), mass_unit),
            (f"vehicle {i}", "yaw inertia", "" if fixed else float(inertia), inertia_unit),
            (f"vehicle {i}", "CG x, y", cg, length_unit),
            (f"vehicle {i}", "heading", math.degrees(_f(v.heading)), "deg"),
            (f"vehicle {i}", "velocity x, y", vel, vel_unit),
            (f"vehicle {i}", "yaw rate", float(yaw), yaw_unit),
            (f"vehicle {i}", "length x width", size, length_unit),
        ]
    point, length_unit = pair(case.impact.point, "length")
    rows += [("impact", "point C x, y", point, length_unit),
             ("impact", "normal angle Gamma", math.degrees(_f(case.impact.normal_angle)), "deg"),
             ("impact", "restitution in the case", case.impact.restitution, "-"),
             ("impact", "beta in the case", case.impact.beta, "-")]
    m = case.measured
    if m is not None:
        for i, vel, w in ((1, m.velocity1, m.yaw_rate1), (2, m.velocity2, m.yaw_rate2)):
            if vel is not None:
                text, unit = pair(vel, "velocity")
                rows.append((f"measured {i}", "post-impact velocity x, y", text, unit))
            if w is not None:
                value, unit = val(w, "angular_velocity")
                rows.append((f"measured {i}", "post-impact yaw rate", float(value), unit))
    return Table("inputs", f"Case inputs ({units.upper()} units)",
                 ("item", "quantity", "value", "unit"), tuple(rows))


#: Rows of the results table: (key of pim.plotting.tables.summarize, key of the Monte
#: Carlo output per vehicle or None).
RESULT_ROWS = (("delta_v", ("delta_v1_magnitude", "delta_v2_magnitude")), ("delta_v_x", None),
               ("delta_v_y", None),
               ("pdof", ("pdof1", "pdof2")), ("clock", None), ("speed", ("speed1", "speed2")),
               ("velocity_x", None), ("velocity_y", None),
               ("yaw_rate", ("yaw_rate1", "yaw_rate2")), ("energy_loss", ("energy_loss",)),
               ("crush_normal", None), ("crush_tangential", None), ("tangential_share", None))


def results_table(result: pim.Result, units: str = "si", spread=None) -> Table:
    """What a reconstruction hands on, per vehicle, in the ``units`` system.

    ``spread`` (a :class:`pim.analysis.montecarlo.UncertaintyResult`) adds 5-95 % intervals.
    """

    rows_by_key = {r.key: r for r in summarize(result, units)}

    def interval(name):
        if spread is None or name is None:
            return ""
        stats = spread.stats[name]
        (low, high), _ = convert(np.array([stats.p5, stats.p95]), QUANTITIES[name].kind,
                                 units)
        return f"{low:.4g} to {high:.4g}"

    rows = []
    for key, mc in RESULT_ROWS:
        r = rows_by_key[key]
        mc = mc or (None, None)
        row = (r.label, r.vehicle1, "" if r.single else (r.vehicle2 if r.vehicle2 is not None
                                                          else "-"), r.unit)
        if spread is not None:
            row += (interval(mc[0]), "" if r.single else interval(mc[1] if len(mc) > 1 else None))
        rows.append(row)
    columns = ("quantity", "vehicle 1", "vehicle 2", "unit")
    if spread is not None:
        columns += ("vehicle 1, 5-95 %", "vehicle 2, 5-95 %")
    return Table("results", "Reconstruction results", columns, tuple(rows))


def _cost_rows(fit, f: float, unit: str) -> list[tuple]:
    """The fit's cost: with measured sigmas the chi-square [-] (unit-free), its degrees of
    freedom, p-value and verdict; else the sum of squares in the user's unit squared."""
    g = fit.goodness
    if g is None:
        return [("cost (sum of squared velocity errors)", fit.cost * f * f, f"({unit})^2")]
    return [("chi-square", g.chi_square, "-"), ("degrees of freedom", g.dof, "-"),
            ("p-value", g.p_value, "-"), ("verdict", g.verdict(), "")]


def fit_table(fit, units: str = "si") -> Table:
    """The fitted (epsilon, beta) and the quality of the fit, in the ``units`` system."""
    f, unit = convert(1.0, "velocity", units)
    f = float(f)
    rows = [("epsilon", fit.eps, "-"), ("beta", fit.beta, "-"),
            *_cost_rows(fit, f, unit),
            ("rms residual", fit.rms * f, unit),
            ("on a bound", ", ".join(f"{k} {v}" for k, v in fit.on_bound.items()) or "no", ""),
            ("local minima found", len(fit.minima), "")]
    rows += [(f"residual {name}", float(r) * f, unit)
             for name, r in zip(fit.residual_names, fit.residuals, strict=True)]
    return Table("fit", "Least-squares fit of (epsilon, beta) to the measured motion",
                 ("quantity", "value", "unit"), tuple(rows))




def crosscheck_table(errors, units: str = "si") -> Table:
    """Analytic against simulated, every post-impact quantity, in the ``units`` system."""
    rows = []
    for q in errors:
        (a, s_, e), unit = convert(np.array([q.analytic, q.simulated, q.absolute]),
                                   KIND_OF_UNIT[q.unit], units)
        rows.append((q.label, unit, float(a), float(s_), float(e), q.relative))
    rows = tuple(rows)
    return Table("crosscheck", "PIM (analytic) against pymunk (simulated), post-impact",
                 ("quantity", "unit", "PIM", "pymunk", "absolute error", "relative error"),
                 rows, formats={"absolute error": fmt_error, "relative error": fmt_error})


def _md_table(table: Table) -> str:
    return f"**{table.title}** ([{table.name}.csv]({table.name}.csv))\n\n{table.to_markdown()}\n"


def _coefficient_sources(case, eps, beta) -> tuple[float, float, dict, object]:
    """epsilon, beta, where each comes from ("command line", "fit to the measured motion",
    "case file", "default (1)") and the fit (or None), by :func:`coefficients`."""
    sources = {"eps": "command line" if eps is not None else None,
               "beta": "command line" if beta is not None else None}
    eps, beta, fit = coefficients(case, eps, beta)
    for name in ("eps", "beta"):
        if sources[name] is None:
            sources[name] = "fit to the measured motion" if fit is not None else "case file"
    if sources["beta"] == "case file" and case.impact.beta is None:
        sources["beta"] = "default (1)"
    return eps, beta, sources, fit


def _stale_files(out: Path) -> None:
    """Remove temporary files that killed runs left in ``out`` (atomic_path's names)."""
    for folder in (out, out / "plots"):
        if folder.is_dir():
            for path in folder.glob(".*-*.tmp*"):
                if path.is_file():
                    path.unlink(missing_ok=True)


def _replace_manifest(out: Path, files: list[Path]) -> None:
    """Delete the earlier run's files this run did not write; record this run's files."""
    manifest = out / MANIFEST
    new = {p.relative_to(out).as_posix() for p in files}
    if manifest.is_file():
        for rel in manifest.read_text(encoding="utf-8").split("\n"):
            rel = rel.strip()
            if rel and rel not in new and ".." not in Path(rel).parts:
                (out / rel).unlink(missing_ok=True)
    write_text(manifest, "\n".join(sorted(new)) + "\n")


def _warm_up() -> None:
    """Import what the plot worker needs (runs while the parent fits)."""
    import matplotlib.backends.backend_agg  # noqa: F401  (pim.plotting.sheet is imported)


def _render_plots(case, fit, folder, units):
    """Write the sheet's plots; return the files and the CPU seconds it took."""
    cpu = time.process_time()
    files = write_plots(case, fit, folder, formats=("png",), units=units)
    return files, time.process_time() - cpu


def compare_case(case: pim.Case, out_dir, *, eps: float | None = None,
                 beta: float | None = None, gif: bool = False, animation: bool = True,
                 speed_error: bool = True, tyre: float = 0.0, assumptions: bool = True,
                 progress: bool | None = None, units: str | None = None,
                 parallel: bool = True, uncertainty_samples: int = 20_000,
                 friction_limit: float | None = None) -> Report:
    """Write the comparison report of one case to ``out_dir`` (see the module docstring).

    Parameters
    ----------
    case : pim.Case
        A single case.
    out_dir : path
        Folder to write (created; the earlier run's files are replaced or removed).
    eps, beta : float, optional
        Use these instead of fitting; both given: no fit even when the case has
        measurements (one given: the other is fitted when the case has measurements).
    gif : bool
        Also write animation.gif.
    animation, speed_error : bool
        Include the animation and the coarse speed-error sweep.
    assumptions : bool
        Include PIM's assumptions at typical values (the full study: ``pim assumptions``).
    tyre : float
        Tyre friction coefficient after the impact in the animation (0: none).
    progress : bool or None
        tqdm bars on stderr (None: only on a terminal).
    units : {"si", "us"}, optional
        Units of every number in the report (default: the case file's, ``case.units``).
    parallel : bool
        Render the plots in a forked worker process while the animation and the sweep run.
    uncertainty_samples : int
        Monte Carlo samples for the 5-95 % intervals when the case has an
        ``[uncertainty]`` table.
    friction_limit : float, optional
        Warn in the report when |mu| exceeds it.
    """
    from dataclasses import replace

    from tqdm import tqdm


    cpu0 = time.process_time()
    units = units or case.units
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    _stale_files(out)
    rep = Report(out_dir=out)
    steps = ["fit", "simulate", "plots"] + (["animation"] if animation else []) \
        + (["speed-error"] if speed_error else []) \
        + (["assumptions"] if assumptions else []) + ["report"]
    bar = tqdm(total=len(steps), desc=f"compare {case.name or ''}".strip(), unit="step",
               disable=None if progress is None else not progress)

    def tick(name, t0):
        rep.seconds[name] = time.perf_counter() - t0
        bar.update(1)

    # The plot worker: a fresh process (forkserver, safe after OpenMP threads ran), started
    # now so that its imports overlap with the fit.
    pool = None
    if parallel:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        try:
            pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("forkserver"))
            pool.submit(_warm_up)
        except (ValueError, OSError):
            pool = None

    # Results and coefficients ------------------------------------------------------------
    t0 = time.perf_counter()
    has_measured = has_measured_terms(case)
    eps, beta, sources, fit = _coefficient_sources(case, eps, beta)
    rep.eps, rep.beta = eps, beta
    result = pim.solve(case, eps, beta)
    spread = None
    if case.uncertainty is not None:
        spread = pim.uncertainty(case, n=uncertainty_samples, seed=0, eps=eps, beta=beta)
    tables = [results_table(result, units, spread), inputs_table(case, units)]
    if fit is not None:
        tables.append(fit_table(fit, units))
    tick("fit", t0)

    # Plots: in the worker while this process simulates and animates ---------------------
    t0 = time.perf_counter()
    plot_case = case if fit is not None or not has_measured else replace(case, measured=None)
    plots_future = None
    if pool is not None:
        from concurrent.futures.process import BrokenProcessPool

        try:
            plots_future = pool.submit(_render_plots, plot_case, fit, out / "plots", units)
        except BrokenProcessPool:          # the worker died while warming up
            plots_future = None
    try:
        # Cross-check ---------------------------------------------------------------------
        t1 = time.perf_counter()
        limits = sim.limitations(case, eps, beta)
        sim_error = None
        simulated = None
        try:
            simulated = sim.simulate(case, eps, beta, analytic=pim.solve(case, eps, 1.0))
        except sim.SimulationError as exc:
            sim_error = exc
        if simulated is not None:
            errors = compare_results(case, result, simulated)
            tables.append(crosscheck_table(errors, units))
            rep.error = float(impact_error(case, result, simulated.velocity1,
                                           simulated.velocity2, simulated.yaw_rate1,
                                           simulated.yaw_rate2))
        tick("simulate", t1)

        # Animation -----------------------------------------------------------------------
        info = None
        anim_error = None
        if animation:
            t1 = time.perf_counter()
            try:
                renderer = build_renderer(case, eps, beta, result=result, tyre=tyre,
                                          units=units)
                info = write_animation(renderer, out / "animation.mp4",
                                       gif=out / "animation.gif" if gif else None,
                                       progress=progress)
                rep.files.append(info.path)
                if info.gif:
                    rep.files.append(info.gif)
            except sim.SimulationError as exc:
                anim_error = exc
            rep.animation = info
            tick("animation", t1)

        # Speed against error -------------------------------------------------------------
        study = None
        if speed_error:
            t1 = time.perf_counter()
            study = sweep(case, eps, beta, progress=progress, **COARSE)
            rep.study = study
            tables += [pareto_table(study), study_table(study)]
            rep.files.append(save_figure(plot_speed_error(study), out / "speed_error.png"))
            tick("speed-error", t1)

        plot_files = None
        if plots_future is not None:
            from concurrent.futures.process import BrokenProcessPool

            try:
                plot_files, plot_cpu = plots_future.result()
            except BrokenProcessPool:      # the worker died: render here instead
                plot_files = None
        if plot_files is None:
            plot_files, plot_cpu = _render_plots(plot_case, fit, out / "plots", units)
    finally:
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
    rep.files += plot_files
    rep.seconds["plots (parallel: wall time of simulate to plots)" if pool is not None
                else "plots"] = time.perf_counter() - t0
    rep.seconds["plots CPU"] = plot_cpu
    bar.update(1)

    # Assumptions at typical values ---------------------------------------------------------
    if assumptions:
        t0 = time.perf_counter()
        rep.assumptions = run_assumptions(case, eps, beta, executor="serial", progress=False,
                                          animation_after=None, sweeps=False)
        tables.append(assumption_table(rep.assumptions))
        tick("assumptions", t0)

    # CSVs and report.md --------------------------------------------------------------------
    t0 = time.perf_counter()
    for table in tables:
        rep.files.append(table.write_csv(out))
    text = _markdown(case, fit, eps, beta, sources, result, simulated, sim_error, limits,
                     tables, plot_files, out, info, anim_error, study, rep, units,
                     friction_limit)
    rep.files.append(write_text(out / "report.md", text))
    _replace_manifest(out, rep.files)
    tick("report", t0)
    rep.seconds["CPU of this process"] = time.process_time() - cpu0
    bar.close()
    return rep


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


def _markdown(case, fit, eps, beta, sources, result, simulated, sim_error, limits, tables,
              plot_files, out, info, anim_error, study, rep, units,
              friction_limit=None) -> str:
    by_name = {t.name: t for t in tables}
    name = case.name or "case"
    lines = [f"# {name}: reconstruction report", ""]
    if getattr(case, "description", None):
        lines += [case.description, ""]
    lines += [f"Written by `pim compare` in {units.upper()} units (`--units` changes them). "
              "Brach's Planar Impact Mechanics (PIM) gives the post-impact motion in closed "
              "form from the case's inputs and two coefficients, epsilon (restitution) and "
              "beta (the fraction of the impulse ratio that stops the sliding at C). The "
              "appendix checks PIM against a pymunk (Chipmunk2D) simulation of the same "
              "impact.", ""]
    lines += ["## Results", ""]
    lines += [f"- **epsilon = {eps:.6g}** ({sources['eps']}), "
              f"**beta = {beta:.6g}** ({sources['beta']}); impulse ratio mu = "
              f"{float(result.mu):.4g} (mu0 = {float(result.mu0):.4g})."]
    table = case.uncertainty
    if table is not None:
        dists = table.inputs
        for key, label in (("impact.restitution", "epsilon"), ("impact.beta", "beta")):
            if key in dists:
                lines.append(f"- {label} in the `[uncertainty]` table: "
                             f"{_describe(dists[key], 'dimensionless', units)}.")
        lines.append("- 5-95 % intervals: Monte Carlo of the case's `[uncertainty]` table "
                     "(`pim uncertainty`), at the coefficients above unless the table varies "
                     "them.")
    if bool(np.asarray(case.vehicle2.fixed)):
        lines.append("- Vehicle 2 is a fixed obstacle: it has no delta-V and no PDOF.")
    lines += ["", _md_table(by_name["results"])]
    warnings = warnings_of(case, result, friction_limit)
    if warnings:
        lines += ["Warnings:", ""] + [f"- {p}" for p in warnings] + [""]
    lines += ["## Coefficients", ""]
    if fit is not None:
        rms, unit = convert(fit.rms, "velocity", units)
        lines += [f"Fitted to the measured post-impact velocities (least squares, "
                  f"`pim fit`): epsilon = {fit.eps:.6g}, beta = {fit.beta:.6g} "
                  f"(rms residual {float(rms):.4g} {unit}).", "", _md_table(by_name["fit"])]
    else:
        lines += [f"epsilon from the {sources['eps']}, beta from the {sources['beta']} "
                  f"(no fit).", ""]
    lines += ["## Case inputs", "", _md_table(by_name["inputs"])]
    lines += ["## The design sheet's plots", ""]
    for path in plot_files:
        rel = path.relative_to(out).as_posix()
        lines += [f"![{path.stem}]({rel})", ""]
    lines += ["## Animation", ""]
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
            lines += [f"**Plausibility:** {info.secondary_impact.message()}; the animation "
                      f"marks it.", ""]
    elif anim_error is not None:
        lines += [f"No animation: the simulation failed ({anim_error.kind}): {anim_error}", ""]
    else:
        lines += ["(not written: --no-animation)", ""]
    lines += ["## Appendix A: PIM against a pymunk simulation", ""]
    if simulated is not None:
        s = simulated
        lines += [f"pymunk settings: dt = {s.settings.dt:g} s, {s.iterations} solver iterations "
                  f"(automatic), {s.settings.contact} contact, {s.settings.start} start; "
                  f"wall time {s.wall_time * 1e3:.3g} ms. Largest error in the impact's "
                  f"velocity changes: **{rep.error:.2e}** (relative to the largest change; "
                  f"see docs/comparisons.md).", "", _md_table(by_name["crosscheck"])]
    else:
        lines += [f"The simulation failed ({sim_error.kind}): {sim_error}", ""]
    if limits:
        lines += ["Where the simulator cannot reproduce PIM here:", ""]
        lines += [f"- {t}" for t in limits] + [""]
    if study is not None:
        rec = study.recommended()
        lines += ["## Appendix B: simulator speed against error (coarse)", ""]
        lines += [f"{len(study.points)} simulator runs over dt, solver iterations, contact "
                  f"start and contact geometry; the full study is `pim speed-error {name}`.", ""]
        if rec is not None:
            its = "automatic" if rec.iterations is None else rec.iterations
            lines += [f"Recommended: dt = {rec.dt:g} s, {its} iterations "
                      f"({rec.iterations_used} sweeps), {rec.start} start, {rec.contact} "
                      f"contact: error {rec.error:.2e} in {rec.wall_time * 1e3:.3g} ms per "
                      f"impact, against PIM's {study.analytic_time * 1e3:.3g} ms per call "
                      f"({study.analytic_batch_time * 1e6:.3g} us per case in a batch).", ""]
        else:
            lines += [f"No run reached the target error {study.target:g}.", ""]
        lines += ["![speed against error](speed_error.png)", "",
                  _md_table(by_name["speed_error_pareto"]),
                  "Every run: [speed_error.csv](speed_error.csv).", ""]
    if rep.assumptions is not None:
        lines += ["## PIM's assumptions (finite-duration crush scene)", ""]
        lines += ["Each scene relaxes one of PIM's assumptions at a typical value (100 ms "
                  "contact, tyre friction 0.7, the case's outlines, friction 0.5 between the "
                  "vehicles); docs/contact-model.md has the model. The sweeps, plots and an "
                  f"animation are `pim assumptions {name}`.", ""]
        lines += [f"- {v}" for v in rep.assumptions.verdicts()] + [""]
        lines += [_md_table(by_name["assumptions"])]
    lines += ["## Files", ""]
    for path in sorted({p.relative_to(out).as_posix() for p in rep.files} | {"report.md"}):
        lines.append(f"- [{path}]({path})")
    lines += ["", "Timings: " + ", ".join(f"{k} {v:.2f} s" for k, v in rep.seconds.items()), ""]
    return "\n".join(lines)


#: Public names of the folder helpers, for the reports of the other impact laws
#: (:mod:`comparisons.law_report`).
stale_files, replace_manifest, md_table = _stale_files, _replace_manifest, _md_table
