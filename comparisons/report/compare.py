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

The folder is a transaction (:func:`pim.io.output.output_folder`): the run is written into a
temporary sibling folder and swapped in whole at the end, so the folder holds one complete
run, the earlier one until the new one is complete; a second run into the same folder at
the same time fails at once. The plots render in a forked worker process while the
animation and the sweep run in this one (``parallel=False`` for one process).

The work is split into gathering (:func:`gather_report` fills a
:class:`~comparisons.report.data.ReportData`) and rendering it
(:mod:`comparisons.report.render`: Markdown and CSV; :mod:`comparisons.report.html`:
report.html, the same report as one self-contained page).

The appendix also summarises PIM's assumptions at typical values (the finite-duration crush
scene, :mod:`comparisons.studies.assumptions`; assumptions.csv); the full study is
``pim assumptions``. The animation and the report say so when the outlines run into each
other again after the impact (a secondary impact PIM does not model,
:func:`sim.find_secondary_impact`).
"""

from __future__ import annotations

import math
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

import pim
import sim
from pim.analysis.pre_impact_speeds import case_pre_impact
from pim.analysis.residuals import has_measured_terms
from comparisons.report.pre_impact import TITLE as PRE_IMPACT_TITLE
from comparisons.report.pre_impact import pre_impact_rows
from pim.io.files import save_figure, write_text
from pim.io.output import ignore_interrupts, output_folder, rebase, stop_workers
from pim.io.units import convert, display_units, quantity_text
from pim.model.plausibility import findings
from pim.model.quantities import OUTPUTS as QUANTITIES
from pim.plotting.sheet import write_plots
from pim.plotting.tables import summarize
from sim.error_measure import KIND_OF_UNIT, compare_results, impact_error

from comparisons.animation.render import build_renderer, write_animation
from comparisons.report.assumptions import assumption_table
from comparisons.studies.assumptions import run_assumptions
from comparisons.studies.coefficients import coefficients
from comparisons.report.data import ReportData
from comparisons.report.html import HTML_NAME, render_html
from comparisons.report.render import REPORT_NAME, render_csv, render_markdown
from comparisons.studies.speed_error import COARSE, pareto_table, plot_speed_error, study_table, sweep
from comparisons.report.tables import Table, fmt_error

__all__ = ["Report", "CompareOptions", "compare_case", "gather_report", "write_report",
           "inputs_table", "fit_table", "crosscheck_table", "results_table",
           "pre_impact_table"]


def _f(x) -> float:
    return float(np.asarray(x, float).reshape(()))


@dataclass
class Report:
    """What :func:`compare_case` wrote and measured.

    Attributes
    ----------
    out_dir : Path
        The report folder.
    files : list of Path
        Every file written, in ``out_dir`` (report.md last).
    eps, beta : float
        Restitution and impulse ratio used [-] (fitted or given).
    error : float
        Largest relative error of the impact's velocity changes, pymunk against PIM [-]
        (NaN when the cross-check failed).
    seconds : dict of str to float
        Wall and CPU time per step [s].
    animation : comparisons.animation.render.AnimationInfo or None
        The animation written (paths in ``out_dir``), if any.
    study : comparisons.studies.speed_error.SpeedErrorStudy or None
        The coarse speed-against-error sweep, if run.
    assumptions : comparisons.studies.assumptions.AssumptionStudy or None
        PIM's assumptions at typical values, if run.
    data : ReportData or None
        Everything the report shows (paths relative to the report folder).
    report : Path
        The report itself, ``out_dir / "report.md"`` (property).
    """

    out_dir: Path
    files: list[Path] = field(default_factory=list)
    eps: float = math.nan
    beta: float = math.nan
    error: float = math.nan
    seconds: dict = field(default_factory=dict)
    animation: object = None
    study: object = None
    assumptions: object = None
    data: ReportData | None = None

    @property
    def report(self) -> Path:
        return self.out_dir / REPORT_NAME


def inputs_table(case: pim.Case, units: str = "si") -> Table:
    """The case's inputs in the ``units`` system ("si" or "us")."""
    def val(x, kind):
        value, unit = convert(np.asarray(x, float), kind, units)
        return value, unit

    def pair(x, kind):
        (a, b), unit = val(np.asarray(x, float).reshape(2), kind)
        return f"{a:.6g}, {b:.6g}", unit

    rows = []
    estimated = {e.name: e for e in case.estimates}
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        fixed = bool(v.fixed)
        estimate = estimated.get(f"vehicle{i}.yaw_inertia")
        mass, mass_unit = val(_f(v.mass), "mass")
        inertia, inertia_unit = val(_f(v.yaw_inertia), "inertia")
        cg, length_unit = pair(v.cg, "length")
        vel, vel_unit = pair(v.velocity, "velocity")
        yaw, yaw_unit = val(_f(v.yaw_rate), "angular_velocity")
        size = "" if v.length is None else \
            f"{float(val(v.length, 'length')[0]):.4g} x {float(val(v.width, 'length')[0]):.4g}"
        rows += [
            (f"vehicle {i}", "mass", "fixed obstacle" if fixed else float(mass), mass_unit),
            (f"vehicle {i}", "yaw inertia" + (f" ({estimate.short})" if estimate else ""),
             "" if fixed else float(inertia), inertia_unit),
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
    return Table("inputs", f"Case inputs ({display_units(units)})",
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


def pre_impact_table(case: pim.Case, units: str = "si") -> Table | None:
    """The speed at the start of each vehicle's pre-impact marks (or driver table) from the
    case's impact velocities (:mod:`pim.analysis.pre_impact_speeds`); None without such
    evidence."""
    rows = pre_impact_rows(case_pre_impact(case), units)
    if not rows:
        return None
    unit = rows[0]["unit"]
    return Table("pre_impact", PRE_IMPACT_TITLE, ("speed", f"value [{unit}]",
                                                  f"impact speed [{unit}]", "where, from what"),
                 tuple((r["name"], r["value"], r["impact"], r["what"]) for r in rows))


def _cost_rows(fit, f: float, unit: str) -> list[tuple]:
    """The fit's cost: with measured sigmas the chi-square [-] (unit-free), its degrees of
    freedom, p-value and verdict; else the sum of squares in the user's unit squared."""
    g = fit.goodness
    if g is None:
        return [("cost (sum of squared velocity errors)", fit.cost * f * f, f"({unit})^2")]
    return [("chi-square", g.chi_square, "-"), ("degrees of freedom", g.dof, "-"),
            ("p-value", g.p_value, "-"), ("verdict", g.verdict(), "")]


def fit_table(fit, units: str = "si") -> Table:
    """The fitted law parameters ((epsilon, beta), or (k, mu_c) under the Kudlich-Slibar
    law) and the quality of the fit, in the ``units`` system."""
    f, unit = convert(1.0, "velocity", units)
    f = float(f)
    law = getattr(fit, "law", "brach")
    coefficients = [("epsilon", fit.eps, "-"), ("beta", fit.beta, "-")]
    title = "(epsilon, beta)"
    if law == "kudlich-slibar":
        lower = "impact.mu_c" in fit.lower_bounds
        coefficients = [("impact law", law, ""), ("k", fit.eps, "-"),
                        ("mu_c (lower bound: the contact sticks)" if lower else "mu_c",
                         fit.contact_friction, "-"), ("equivalent PIM beta", fit.beta, "-")]
        title = "(k, mu_c) under the Kudlich-Slibar law"
    elif law == "brach-capped":
        coefficients = [("impact law", law, ""), *coefficients,
                        ("cap mu_c", fit.contact_friction, "-")]
        title = "(epsilon, beta) under the friction cap"
    rows = [*coefficients,
            *_cost_rows(fit, f, unit),
            ("rms residual", fit.rms * f, unit),
            ("on a bound", ", ".join(f"{k} {v}" for k, v in fit.on_bound.items()) or "no", ""),
            ("local minima found", len(fit.minima), "")]
    rows += [(f"residual {name}", float(r) * f, unit)
             for name, r in zip(fit.residual_names, fit.residuals, strict=True)]
    return Table("fit", f"Least-squares fit of {title} to the measured motion",
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



@dataclass(frozen=True)
class CompareOptions:
    """What :func:`compare_case` includes and how (its keyword arguments, detailed there).

    Attributes
    ----------
    eps, beta : float or None
        Restitution and friction coefficients [-] to use instead of fitting (None: fit).
    gif : bool
        Also write animation.gif.
    animation, speed_error : bool
        Include the animation and the coarse speed-error sweep.
    tyre : float
        Tyre friction coefficient [-] after the impact in the animation (0: none).
    assumptions : bool
        Include PIM's assumptions at typical values.
    progress : bool or None
        tqdm bars on stderr (None: only on a terminal).
    units : str, pim.io.units.DisplayUnits or None
        Units of the report: "si", "us" (speeds in km/h, mph) or a DisplayUnits (None: the
        case file's, :func:`pim.io.units.display_units`).
    parallel : bool
        Render the plots in a forked worker process.
    uncertainty_samples : int
        Monte Carlo samples for the 5-95 % intervals.
    friction_limit : float or None
        Warn when |mu| [-] exceeds it (None: no warning).
    case_path : str or None
        The case as the user named it, for the commands the report suggests.
    """

    eps: float | None = None
    beta: float | None = None
    gif: bool = False
    animation: bool = True
    speed_error: bool = True
    tyre: float = 0.0
    assumptions: bool = True
    progress: bool | None = None
    units: str | None = None
    parallel: bool = True
    uncertainty_samples: int = 2000
    friction_limit: float | None = None
    case_path: str | None = None


class _Steps:
    """The progress bar over a report's steps and the wall time of each."""

    def __init__(self, case, options: CompareOptions):
        from tqdm import tqdm

        steps = ["fit", "simulate", "plots"] + (["animation"] if options.animation else []) \
            + (["speed-error"] if options.speed_error else []) \
            + (["assumptions"] if options.assumptions else []) + ["report"]
        self.seconds: dict = {}
        self.bar = tqdm(total=len(steps), desc=f"compare {case.name or ''}".strip(),
                        unit="step", disable=None if options.progress is None
                        else not options.progress)

    def done(self, name: str | None, t0: float) -> None:
        if name is not None:
            self.seconds[name] = time.perf_counter() - t0
        self.bar.update(1)


def _warm_up() -> None:
    """Import what the plot worker needs (runs while the parent fits)."""
    import matplotlib.backends.backend_agg  # noqa: F401  (pim.plotting.sheet is imported)


def _render_plots(case, fit, folder, units):
    """Write the sheet's plots; return the files and the CPU seconds it took."""
    cpu = time.process_time()
    files = write_plots(case, fit, folder, formats=("png",), units=units)
    return files, time.process_time() - cpu


class _PlotWorker:
    """The sheet's plots in a worker process (forkserver: safe after OpenMP threads ran),
    started at once so that its imports overlap with the fit; in this process when
    ``parallel`` is False or the worker dies. The worker ignores Ctrl-C (this process
    handles it) and is killed when this process leaves the block with an error or an
    interrupt, before the run's temporary folder is removed."""

    def __init__(self, parallel: bool):
        self.pool, self.future, self.args = None, None, None
        if parallel:
            try:
                self.pool = ProcessPoolExecutor(
                    1, mp_context=multiprocessing.get_context("forkserver"),
                    initializer=ignore_interrupts)
                self.pool.submit(_warm_up)
            except (ValueError, OSError):
                self.pool = None

    def __enter__(self):
        return self

    def submit(self, *args) -> None:
        self.args = args
        if self.pool is not None:
            try:
                self.future = self.pool.submit(_render_plots, *args)
            except BrokenProcessPool:          # the worker died while warming up
                self.future = None

    def result(self):
        """The plot files and their CPU seconds (rendered here if the worker died)."""
        if self.future is not None:
            try:
                return self.future.result()
            except BrokenProcessPool:
                pass
        return _render_plots(*self.args)

    def __exit__(self, exc_type, exc, tb):
        if self.pool is None:
            return
        if exc_type is not None:
            stop_workers(self.pool)
        self.pool.shutdown(wait=True, cancel_futures=True)


def _gather_results(case, options: CompareOptions, units: str) -> ReportData:
    """Coefficients (fitted or given), PIM's answer, the Monte Carlo spread, the tables."""
    eps, beta, sources, fit = _coefficient_sources(case, options.eps, options.beta)
    result = pim.solve(case, eps, beta)
    spread = None
    if case.uncertainty is not None:
        spread = pim.uncertainty(case, n=options.uncertainty_samples, seed=0, eps=eps,
                                 beta=beta)
    found = findings(case, result, options.friction_limit, quantity_text(units))
    data = ReportData(case=case, case_path=options.case_path or case.name or "CASE",
                      units=units, eps=eps, beta=beta, sources=sources, result=result, fit=fit,
                      warnings=found.warnings, errors=found.errors,
                      animation_requested=options.animation)
    data.add_table(results_table(result, units, spread))
    pre_impact = pre_impact_table(case, units)
    if pre_impact is not None:
        data.add_table(pre_impact)
    data.add_table(inputs_table(case, units))
    if fit is not None:
        data.add_table(fit_table(fit, units))
    return data


def _gather_crosscheck(data: ReportData) -> None:
    """The pymunk simulation of the same impact and its errors against PIM."""
    case, eps, beta = data.case, data.eps, data.beta
    data.limits = sim.limitations(case, eps, beta)
    try:
        data.simulated = sim.simulate(case, eps, beta, analytic=pim.solve(case, eps, 1.0, law="brach"))
    except sim.SimulationError as exc:
        data.sim_error = exc
        return
    s = data.simulated
    data.add_table(crosscheck_table(compare_results(case, data.result, s), data.units))
    data.error = float(impact_error(case, data.result, s.velocity1, s.velocity2, s.yaw_rate1,
                                    s.yaw_rate2))


def _gather_animation(data: ReportData, folder: Path, options: CompareOptions) -> None:
    """animation.mp4 (and .gif): the simulation with PIM's ghost."""
    try:
        renderer = build_renderer(data.case, data.eps, data.beta, result=data.result,
                                  tyre=options.tyre, units=data.units)
        data.animation = write_animation(renderer, folder / "animation.mp4",
                                         gif=folder / "animation.gif" if options.gif else None,
                                         progress=options.progress)
    except sim.SimulationError as exc:
        data.animation_error = exc
        return
    data.files += ["animation.mp4"] + (["animation.gif"] if options.gif else [])


def _gather_speed_error(data: ReportData, folder: Path, options: CompareOptions) -> None:
    """The coarse sweep of the simulator's speed against its error (speed_error.png)."""
    data.study = sweep(data.case, data.eps, data.beta, progress=options.progress, **COARSE)
    data.add_table(pareto_table(data.study))
    data.add_table(study_table(data.study))
    save_figure(plot_speed_error(data.study), folder / "speed_error.png")
    data.files.append("speed_error.png")


def gather_report(case: pim.Case, folder, options: CompareOptions,
                  steps: _Steps | None = None) -> ReportData:
    """Compute everything the report of ``case`` shows; write its figures and animation
    into ``folder`` (the tables and the text are the renderers' part: :func:`write_report`).
    ``steps`` (progress bar and timings) is made here unless given.
    """
    cpu0 = time.process_time()
    folder = Path(folder)
    units = display_units(options.units, case=case)
    steps = steps or _Steps(case, options)
    seconds = steps.seconds
    with _PlotWorker(options.parallel) as worker:
        t0 = time.perf_counter()
        data = _gather_results(case, options, units)
        data.seconds = seconds
        steps.done("fit", t0)
        t0 = time.perf_counter()
        plot_case = case if data.fit is not None or not has_measured_terms(case) \
            else replace(case, measured=None)
        worker.submit(plot_case, data.fit, folder / "plots", units)
        t1 = time.perf_counter()
        _gather_crosscheck(data)
        steps.done("simulate", t1)
        if options.animation:
            t1 = time.perf_counter()
            _gather_animation(data, folder, options)
            steps.done("animation", t1)
        if options.speed_error:
            t1 = time.perf_counter()
            _gather_speed_error(data, folder, options)
            steps.done("speed-error", t1)
        plot_files, plot_cpu = worker.result()
        parallel = worker.pool is not None
    data.plot_files = [Path(p).relative_to(folder).as_posix() for p in plot_files]
    data.files += data.plot_files
    seconds["plots (parallel: wall time of simulate to plots)" if parallel
            else "plots"] = time.perf_counter() - t0
    seconds["plots CPU"] = plot_cpu
    steps.done(None, t0)
    if options.assumptions:
        t0 = time.perf_counter()
        data.assumptions = run_assumptions(case, data.eps, data.beta, executor="serial",
                                           progress=False, animation_after=None, sweeps=False)
        data.add_table(assumption_table(data.assumptions, units=units))
        steps.done("assumptions", t0)
    data.seconds["CPU of this process"] = time.process_time() - cpu0
    return data


def write_report(data: ReportData, folder) -> list[Path]:
    """Write the report's CSVs, report.html and report.md (last) into ``folder``; return
    every file of the run (figures and animation included)."""
    folder = Path(folder)
    csvs = render_csv(data)
    data.files += list(csvs) + [HTML_NAME]
    for name, text in csvs.items():
        write_text(folder / name, text)
    write_text(folder / HTML_NAME, render_html(data, folder))
    write_text(folder / REPORT_NAME, render_markdown(data))
    return [folder / rel for rel in data.files] + [folder / REPORT_NAME]


def compare_case(case: pim.Case, out_dir, *, eps: float | None = None,
                 beta: float | None = None, gif: bool = False, animation: bool = True,
                 speed_error: bool = True, tyre: float = 0.0, assumptions: bool = True,
                 progress: bool | None = None, units: str | None = None,
                 parallel: bool = True, uncertainty_samples: int = 2000,
                 friction_limit: float | None = None, case_path: str | None = None) -> Report:
    """Write the report of ``case`` into folder ``out_dir`` (report.md, CSVs, PNGs, MP4).

    Parameters
    ----------
    case : pim.Case
        A single case.
    out_dir : path
        Folder to write: replaced whole by this run when it is complete
        (:func:`pim.io.output.output_folder`; an error or interrupt leaves it as it was).
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
    units : {"si", "us"} or pim.io.units.DisplayUnits, optional
        Units of every number in the report (default: the case file's, ``case.units`` with
        its ``case.speed_unit``).
    parallel : bool
        Render the plots in a forked worker process while the animation and the sweep run.
    uncertainty_samples : int
        Monte Carlo samples for the 5-95 % intervals when the case has an
        ``[uncertainty]`` table.
    friction_limit : float, optional
        Warn in the report when |mu| exceeds it.
    case_path : str, optional
        The case as the user named it (bundled name or file path), used in the commands the
        report suggests (default: ``case.name``).
    """
    options = CompareOptions(eps=eps, beta=beta, gif=gif, animation=animation,
                             speed_error=speed_error, tyre=tyre, assumptions=assumptions,
                             progress=progress, units=units, parallel=parallel,
                             uncertainty_samples=uncertainty_samples,
                             friction_limit=friction_limit, case_path=case_path)
    out = Path(out_dir)
    steps = _Steps(case, options)
    try:
        with output_folder(out, command="pim compare") as tmp:
            data = gather_report(case, tmp, options, steps)
            t0 = time.perf_counter()
            files = write_report(data, tmp)
            steps.done("report", t0)
    finally:
        steps.bar.close()
    info = data.animation
    if info is not None:
        info = replace(info, path=out / "animation.mp4",
                       gif=out / "animation.gif" if info.gif else None)
    return Report(out_dir=out, files=rebase(files, tmp, out),
                  eps=data.eps, beta=data.beta, error=data.error, seconds=data.seconds,
                  animation=info, study=data.study, assumptions=data.assumptions, data=data)
