"""``pim compare``: the whole story of one case in a folder -- report.html, report.md, CSVs,
PNGs, MP4.

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
:class:`~comparisons.report.data.ReportData`), stating it as the report's document
(:func:`comparisons.report.compare_document.compare_document`: the answer first) and writing
that through the one pipeline (:func:`comparisons.report.write.write_document`: the CSVs,
report.html, the self-contained page, and report.md).

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
from dataclasses import fields as dataclass_fields
from pathlib import Path

import numpy as np

import pim
import sim
from comparisons.animation.collision import build_renderer, event_renderer, measured_rest
from comparisons.animation.plan import plan_view
from comparisons.animation.render import write_animation
from comparisons.report.assumptions import assumption_table
from comparisons.report.compare_document import REPORT_NAME, compare_document
from comparisons.report.compare_tables import (
    fit_table,
    inputs_table,
    misfit_table,
    pre_impact_table,
    results_table,
)
from comparisons.report.data import ReportData
from comparisons.report.event import crosscheck_table as event_crosscheck_table
from comparisons.report.html import HTML_NAME
from comparisons.report.tables import Num, Table, fmt_error
from comparisons.report.write import write_document
from comparisons.studies.assumptions import run_assumptions
from comparisons.studies.coefficients import coefficients
from comparisons.studies.speed_error import (
    COARSE,
    pareto_table,
    plot_speed_error,
    study_table,
    sweep,
)
from pim.analysis.misfit import misfit
from pim.analysis.residuals import has_measured_terms
from pim.io.files import save_figure
from pim.io.output import output_folder, rebase
from pim.io.process import started_pool, stop_workers
from pim.io.units import convert, display_units, quantity_text
from pim.model.numbers import InputError
from pim.model.plausibility import findings
from pim.plotting.sheet import write_plots
from sim.error_measure import KIND_OF_UNIT, compare_results, impact_error

__all__ = ["Report", "CompareOptions", "compare_case", "gather_report", "write_report",
           "crosscheck_table"]


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
        The Markdown report, ``out_dir / "report.md"`` (property).
    html : Path
        The deliverable, the self-contained ``out_dir / "report.html"`` (property).
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

    @property
    def html(self) -> Path:
        return self.out_dir / HTML_NAME


def crosscheck_table(errors, units: str = "si") -> Table:
    """Analytic against simulated, every post-impact quantity, in the ``units`` system."""
    rows = []
    for q in errors:
        (a, s_, e), unit = convert(np.array([q.analytic, q.simulated, q.absolute]),
                                   KIND_OF_UNIT[q.unit], units)
        rows.append((q.label, unit, Num(float(a), sig=6), Num(float(s_), sig=6), float(e),
                     q.relative))
    return Table("crosscheck", "PIM (analytic) against pymunk (simulated), post-impact",
                 ("quantity", "unit", "PIM", "pymunk", "absolute error", "relative error"),
                 tuple(rows), formats={"absolute error": fmt_error, "relative error": fmt_error})


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
    """What :func:`compare_case` includes and how (each field also a keyword of it).

    Attributes
    ----------
    eps, beta : float or None
        Restitution and friction coefficients [-] to use instead of fitting (None: fit);
        both given: no fit even when the case has measurements (one given: the other is
        fitted when the case has measurements).
    gif : bool
        Also write animation.gif.
    animation, speed_error : bool
        Include the animation and the coarse speed-error sweep.
    tyre : float or None
        Tyre friction coefficient [-] after the impact in the animation (0: none; None:
        the case's [evidence] friction, else :data:`pim.model.event.DEFAULT_TYRE_FRICTION`).
    assumptions : bool
        Include PIM's assumptions at typical values (the full study: ``pim assumptions``).
    progress : bool or None
        tqdm bars on stderr (None: only on a terminal).
    units : str, pim.io.units.DisplayUnits or None
        Units of every number in the report: "si", "us" (speeds in km/h, mph) or a
        DisplayUnits (None: the case file's, ``case.units`` with its ``case.speed_unit``,
        :func:`pim.io.units.display_units`).
    parallel : bool
        Render the plots in a forked worker process while the animation and the sweep run.
    uncertainty_samples : int
        Monte Carlo samples for the 5-95 % intervals when the case has an
        ``[uncertainty]`` table.
    friction_limit : float or None
        Warn in the report when |mu| [-] exceeds it (None: no warning).
    case_path : str or None
        The case as the user named it (bundled name or file path), used in the commands the
        report suggests (None: ``case.name``).
    """

    eps: float | None = None
    beta: float | None = None
    gif: bool = False
    animation: bool = True
    speed_error: bool = True
    tyre: float | None = None
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
                self.pool = started_pool(1, multiprocessing.get_context("forkserver"),
                                         _warm_up)
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
                      animation_requested=options.animation, spread=spread,
                      misfit=misfit(result))
    data.add_table(results_table(result, units, spread))
    pre_impact = pre_impact_table(case, units)
    if pre_impact is not None:
        data.add_table(pre_impact)
    if data.misfit.rows:
        data.add_table(misfit_table(data.misfit, units))
    data.add_table(inputs_table(case, units))
    if fit is not None:
        data.add_table(fit_table(fit, units))
    return data


def _gather_crosscheck(data: ReportData) -> None:
    """The pymunk simulation of the same impact and its errors against PIM."""
    case, eps, beta = data.case, data.eps, data.beta
    data.limits = sim.limitations(case, eps, beta)
    try:
        data.simulated = sim.simulate(case, eps, beta,
                                      analytic=pim.solve(case, eps, 1.0, law="brach"))
    except sim.SimulationError as exc:
        data.sim_error = exc
        return
    s = data.simulated
    data.add_table(crosscheck_table(compare_results(case, data.result, s), data.units))
    data.error = float(impact_error(case, data.result, s.velocity1, s.velocity2, s.yaw_rate1,
                                    s.yaw_rate2))


def _gather_animation(data: ReportData, folder: Path, options: CompareOptions) -> None:
    """animation.mp4 (and .gif) and plan.png: the whole event (the pymunk event with the
    analytic event as a ghost, :func:`comparisons.animation.collision.event_renderer`) and
    the analytic event against the pymunk event at each impact and at rest
    (:func:`sim.event_crosscheck`), or, for a case the event cannot run (no outlines), the
    single impact's simulation with PIM's ghost."""
    case = data.case
    try:
        try:
            renderer, analytic, simulated = event_renderer(
                case, tyre=options.tyre, units=data.units, eps=data.eps, beta=data.beta,
                strict=False)
            analytic = simulated if analytic is None else analytic
        except InputError:
            simulated = None
            renderer, analytic = build_renderer(case, data.eps, data.beta, result=data.result,
                                                tyre=options.tyre, units=data.units), None
        data.animation = write_animation(renderer, folder / "animation.mp4",
                                         gif=folder / "animation.gif" if options.gif else None,
                                         progress=options.progress)
    except sim.SimulationError as exc:
        data.animation_error = exc
        return
    data.files += ["animation.mp4"] + (["animation.gif"] if options.gif else [])
    if analytic is not None and analytic is not simulated:
        data.event_check = sim.event_crosscheck(analytic, simulated)
        data.add_table(event_crosscheck_table(data.event_check, data.units))
    if analytic is not None:
        save_figure(plan_view(analytic, units=data.units, measured_rest=measured_rest(case),
                              title=f"{case.name or 'case'}: the {analytic.source} event"),
                    folder / "plan.png")
        data.plan = "plan.png"
        data.files.append("plan.png")


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


def _with_fields(options: CompareOptions | None, fields: dict) -> CompareOptions:
    """``options`` (default ``CompareOptions()``) with the fields named in ``fields``."""
    names = [f.name for f in dataclass_fields(CompareOptions)]
    unknown = sorted(set(fields) - set(names))
    if unknown:
        raise InputError(f"compare_case got unknown option(s) {', '.join(unknown)}; "
                         f"allowed: options, {', '.join(names)}")
    return replace(options or CompareOptions(), **fields)


def write_report(data: ReportData, folder) -> list[Path]:
    """Write the report's CSVs, report.html and report.md (last) into ``folder`` through the
    one report pipeline (:func:`comparisons.report.write.write_document`); return every file
    of the run (figures and animation included), report.html and report.md last."""
    folder = Path(folder)
    written = write_document(compare_document(data), folder)
    media = [folder / rel for rel in data.files]
    return media + written


def compare_case(case: pim.Case, out_dir, options: CompareOptions | None = None,
                 **fields) -> Report:
    """Write the report of ``case`` into folder ``out_dir`` (report.md, CSVs, PNGs, MP4).

    Parameters
    ----------
    case : pim.Case
        A single case.
    out_dir : path
        Folder to write: replaced whole by this run when it is complete
        (:func:`pim.io.output.output_folder`; an error or interrupt leaves it as it was).
    options : CompareOptions, optional
        What the report includes and how (default ``CompareOptions()``).
    **fields
        Any field of :class:`CompareOptions` by name (``eps=0.4``, ``animation=False``,
        ``units="us"`` ...), overriding ``options``'s.
    """
    options = _with_fields(options, fields)
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
