"""Speed against error of the finite-duration contact: the fixed-step scene over dt, solve_ivp
over rtol.

For one case, two point-contact scenes at the stiffness that gives the typical contact time
(:data:`CONTACT_TIME`, 100 ms: :func:`sim.contact_law.stiffness_for_duration`, defined for
any contact type, where a measured stiffness exists for a full-width frontal barrier
only, :func:`sim.crash_data.default_stiffness`): frictionless, and with friction
mu_c = 0.5 between the vehicles (stick-slip). Each is integrated

* by the fixed-step crush scene (:func:`sim.simulate_compliant`) with dt = (estimated
  contact time) / n for n in :data:`STEPS` (10 ... 2560 steps per contact): compiled
  (``engine="numba"``, the default) or stepped by pymunk (``engine="pymunk"``, the
  cross-check; both step the same functions and agree to round-off), and
* by ``solve_ivp`` (:func:`sim.reference_compliant`) with DOP853 (explicit) and Radau
  (implicit) at rtol in :data:`RTOLS`,

against the reference: DOP853 at the tightest rtol of :data:`REFERENCE_RTOLS` (1e-8, 1e-9,
1e-10) that fits the budget :data:`REFERENCE_STEPS` (each tighter rung is tried only when
the last one took under a quarter of the budget's steps, and is stopped at the budget
(``CompliantSettings.max_steps``), the rung before it then being the reference: a step
count, so the choice does not depend on the machine's load; tighter tolerances approach
round-off and can cost 10^4-10^5 steps: the pickup-into-sedan case took 262 s and 63 359
steps at rtol 1e-12). The tolerance reached and the reference's spread (its difference from
the rung before) are reported. Swept rtols tighter than 10x the reference's are dropped
(they would measure the reference), and a method's tighter rtols (or the fixed step's finer steps)
are skipped as "over_budget" once the last run took more than a third of :data:`RUN_BUDGET`.
The error is :func:`sim.error_measure.impact_error` (largest error in the impact's velocity
changes, relative to the largest change); the wall time per impact is the best of
``repeats`` runs (the repeats stop once the runs took :data:`REPEAT_BELOW` together: a long
run's timing noise is a small share of it). The Pareto front is
:func:`comparisons.studies.speed_error.pareto_front`; the
recommended setting is the fastest run on the front that reaches :data:`TARGET` (1e-3, the
issue's goal), and the fastest reaching 1e-6 is reported per integrator.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, replace

import numpy as np

import pim
import sim
from comparisons.report.tables import Table, fmt_error
from comparisons.studies.speed_error import ERROR_FLOOR, pareto_front
from pim.model.numbers import InputError
from sim.error_measure import impact_error
from sim.sweep import sweep

__all__ = ["CompliantPoint", "CompliantSpeedStudy", "compliant_sweep", "STEPS", "RTOLS",
           "TARGET", "SCENES", "COARSE", "REFERENCE_RTOLS", "REFERENCE_STEPS", "RUN_BUDGET",
           "REPEAT_BELOW", "CONTACT_TIME", "ENGINES", "Grid", "SweepJob", "sweep_points",
           "scene_stiffness", "reference_within_budget", "Reference",
           "plot_compliant_speed_error", "fixed_step_label", "FIXED_STEP"]

STEPS = (10, 20, 40, 80, 160, 320, 640, 1280, 2560)
RTOLS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)
METHODS = ("DOP853", "Radau")
TARGET = 1e-3
#: scene name -> friction mu_c between the vehicles
SCENES = {"frictionless": 0.0, "friction 0.5": 0.5}
#: Tolerances tried for the reference, loosest first [-].
REFERENCE_RTOLS = (1e-8, 1e-9, 1e-10)
#: Integration steps one reference scene may cost (the next rung runs only if the last took
#: under a quarter of them; 46-172 steps at rtol 1e-10 on the bundled cases).
REFERENCE_STEPS = 2000
#: Wall time of one swept run above which the next finer setting is not tried [s] (x 3).
RUN_BUDGET = 1.5
#: The repeats of a setting stop once its runs took this long together [s] (a long run's
#: timing noise is a small share of it; repeats would only cost time).
REPEAT_BELOW = 0.06
#: Contact time [s] the scenes' stiffness is chosen for (the typical one of
#: ``comparisons.studies.assumption_configs.TYPICAL``).
CONTACT_TIME = 0.1
#: The fixed-step integrators: the compiled crush scene, or pymunk (the cross-check).
ENGINES = ("numba", "pymunk")


@dataclass(frozen=True)
class CompliantPoint:
    """One integrator setting and how it did on one scene.

    Attributes
    ----------
    scene : str
        Scene name, a key of :data:`SCENES` ("frictionless", "friction 0.5").
    integrator : str
        "compiled" or "pymunk" (the fixed-step scene), "DOP853" or "Radau".
    setting : float
        Time step dt [s] of the fixed-step scene, relative tolerance rtol [-] for solve_ivp.
    steps : int
        Integration steps the run took [-] (0 when it failed or was skipped).
    error : float
        :func:`sim.error_measure.impact_error` against the scene's reference [-] (NaN when
        the run failed or was skipped).
    wall_time : float
        Best wall time of the ``repeats`` runs [s] (NaN when failed or skipped).
    failure : str or None
        Why there is no result: a :class:`sim.SimulationError` kind, or "over_budget".
    ok : bool
        A finite error and no failure (property).
    label : str
        "INTEGRATOR dt=..." or "INTEGRATOR rtol=..." (property).
    """

    scene: str
    integrator: str          # "compiled", "pymunk", "DOP853", "Radau"
    setting: float           # dt [s] of the fixed-step scene, rtol for solve_ivp
    steps: int
    error: float
    wall_time: float
    failure: str | None = None

    @property
    def ok(self) -> bool:
        return self.failure is None and math.isfinite(self.error)

    @property
    def label(self) -> str:
        name = "dt" if self.integrator in FIXED_STEP.values() else "rtol"
        return f"{self.integrator} {name}={self.setting:.3g}"


@dataclass(frozen=True, eq=False)
class CompliantSpeedStudy:
    """Outcome of :func:`compliant_sweep`.

    Attributes
    ----------
    case_name : str
        The case's name.
    eps : float
        Restitution used [-].
    stiffness : float
        Linear contact stiffness of the scenes [N/m] (the one giving ``contact_time``).
    points : tuple of CompliantPoint
        Every run, all scenes and integrators.
    reference_spread : float
        Largest over the scenes of the reference's spread: its
        :func:`sim.error_measure.impact_error` against the rung before it [-] (0 with one
        rung).
    target : float
        Error the recommended setting must reach [-] (:data:`TARGET`).
    reference_rtol : float
        Loosest over the scenes of the rtol their reference reached [-] (the tightest all
        reached).
    wall_time : float
        Wall time of the whole study [s].
    contact_time : float
        The contact time the stiffness was chosen for [s].
    engine : str
        The fixed-step integrator (:data:`ENGINES`).
    """

    case_name: str
    eps: float
    stiffness: float
    points: tuple
    reference_spread: float   # reference against the rung before it, on the error scale
    target: float = TARGET
    reference_rtol: float = math.nan   # tightest rtol the reference reached (all scenes)
    wall_time: float = math.nan        # wall time of the whole study [s]
    contact_time: float = CONTACT_TIME
    engine: str = "numba"

    def scene_points(self, scene: str) -> list:
        return [p for p in self.points if p.scene == scene and p.ok]

    def pareto(self, scene: str) -> list:
        return pareto_front(self.scene_points(scene))

    def recommended(self, scene: str) -> CompliantPoint | None:
        """The fastest Pareto run reaching the target, or None."""
        good = [p for p in self.pareto(scene) if p.error <= self.target]
        return good[0] if good else None

    def fastest(self, scene: str, integrator: str, target: float) -> CompliantPoint | None:
        pts = [p for p in self.scene_points(scene) if p.integrator == integrator
               and p.error <= target]
        return min(pts, key=lambda p: p.wall_time) if pts else None


def _timed(func, repeats: int):
    """Best wall time of up to ``repeats`` runs, the repeats stopping once the runs took
    :data:`REPEAT_BELOW` together (a long run is timed once, a short one that a busy
    machine delayed is timed again)."""
    best, out, spent = math.inf, None, 0.0
    for _ in range(max(1, repeats)):
        out = func()
        best, spent = min(best, out.wall_time), spent + out.wall_time
        if spent > REPEAT_BELOW:
            break
    return out, best


@dataclass(frozen=True, eq=False)
class Reference:
    """The reference of one scene: the result, the rtol it reached, its spread and cost.

    Attributes
    ----------
    result : sim.CompliantResult
        The DOP853 run at the tightest tolerance reached.
    rtol : float
        Its relative tolerance [-].
    spread : float
        :func:`sim.error_measure.impact_error` against the rung before [-] (NaN with one).
    wall_time : float
        Wall time of all the rungs run [s].
    """

    result: object
    rtol: float
    spread: float
    wall_time: float


def reference_within_budget(case: pim.Case, eps: float, stiffness: float, friction: float,
                            rtols=REFERENCE_RTOLS, budget: int = REFERENCE_STEPS
                            ) -> Reference:
    """DOP853 at the tightest of ``rtols`` (loosest first) that fits ``budget`` steps.

    The next rung runs only if the last took under budget / 4 steps (module notes), and
    stops at ``budget`` steps (``CompliantSettings.max_steps``): a rung that would take more
    is abandoned and the one before it is the reference. ``spread`` is
    :func:`sim.error_measure.impact_error` of the last rung against the one before (NaN
    with a single rung): an upper estimate of the reference's own error.
    """
    results, spent = [], 0.0
    for rtol in rtols:
        if results and results[-1][1].steps > budget / 4.0:
            break
        settings = sim.CompliantSettings(record=False, rtol=rtol)
        if results:                       # the first rung runs whatever it costs
            settings = replace(settings, max_steps=budget)
        start = time.perf_counter()
        try:
            out = sim.reference_compliant(case, eps, stiffness, friction=friction,
                                          settings=settings)
        except sim.SimulationError as exc:
            if not results or exc.kind != "not_converged":
                raise
            spent += time.perf_counter() - start
            break
        spent += out.wall_time
        results.append((rtol, out))
    rtol, ref = results[-1]
    spread = math.nan
    if len(results) > 1:
        prev = results[-2][1]
        spread = float(impact_error(case, ref, prev.velocity1, prev.velocity2,
                                    prev.yaw_rate1, prev.yaw_rate2))
    return Reference(ref, rtol, spread, spent)


#: The fixed-step integrator's name in the study, per engine.
FIXED_STEP = {"numba": "compiled", "pymunk": "pymunk"}


def fixed_step_label(integrator: str) -> str:
    """How a plot or a table names an integrator."""
    return {"compiled": "compiled scene over dt", "pymunk": "pymunk over dt"}.get(
        integrator, f"solve_ivp {integrator}")


class _Batch:
    """A compiled run of one scene seen as a :class:`sim.CompliantResult` (its failure
    raised as the :class:`sim.SimulationError` it stands for)."""

    def __init__(self, batch):
        if not bool(batch.ok):
            batch.result()                       # raises the scene's SimulationError
        self.velocity1, self.velocity2 = batch.velocity1, batch.velocity2
        self.yaw_rate1, self.yaw_rate2 = float(batch.yaw_rate1), float(batch.yaw_rate2)
        self.steps, self.wall_time = int(batch.steps), batch.wall_time


def _fixed_step(case, eps, k, mu, settings, engine):
    if engine == "numba":
        return _Batch(sim.simulate_compliant(case, eps, k, friction=mu, settings=settings,
                                             engine="numba"))
    return sim.simulate_compliant(case, eps, k, friction=mu, settings=settings,
                                  engine="pymunk")


def _ladders(case, eps, k, mu, grid: Grid, engine: str):
    """(integrator, [(setting, run), ...]) from the cheapest setting to the dearest."""
    fixed = []
    for n in grid.steps:
        settings = sim.CompliantSettings(record=False, steps_per_contact=int(n),
                                         min_steps=min(10, int(n)))
        dt = sim.compliant.step_size(sim.compliant_setup.build_problem(
            case, eps, k, mu, settings=settings))
        fixed.append((dt, lambda s=settings: _fixed_step(case, eps, k, mu, s, engine)))
    out = [(FIXED_STEP[engine], fixed)]
    for method in grid.methods:
        ladder = []
        for rtol in sorted(grid.rtols, reverse=True):
            settings = sim.CompliantSettings(record=False, rtol=rtol, method=method)
            ladder.append((rtol, lambda s=settings: sim.reference_compliant(
                case, eps, k, friction=mu, settings=s)))
        out.append((method, ladder))
    return out


def _run_ladder(case, scene, ref, integrator, ladder, repeats, run_budget):
    points, last = [], 0.0
    for setting, run in ladder:
        if last > run_budget / 3.0:
            points.append(CompliantPoint(scene, integrator, setting, 0, math.nan, math.nan,
                                         "over_budget"))
            continue
        try:
            out, wall = _timed(run, repeats)
            last = out.wall_time
            err = float(impact_error(case, ref, out.velocity1, out.velocity2,
                                     out.yaw_rate1, out.yaw_rate2))
            points.append(CompliantPoint(scene, integrator, setting, out.steps, err, wall))
        except sim.SimulationError as exc:
            points.append(CompliantPoint(scene, integrator, setting, 0, math.nan,
                                         math.nan, exc.kind))
    return points


def scene_stiffness(case: pim.Case, eps: float, contact_time: float = CONTACT_TIME) -> float:
    """The stiffness [N/m] that gives the point contact at C the contact time
    ``contact_time`` [s] (:func:`sim.contact_law.stiffness_for_duration`)."""
    k_nn = sim.compliant_setup.build_problem(case, eps, sim.DEFAULT_STIFFNESS).k_nn
    return float(sim.contact_law.stiffness_for_duration(contact_time, k_nn, eps))


@dataclass(frozen=True)
class Grid:
    """The settings a study sweeps and the budgets that bound it.

    Attributes
    ----------
    steps : tuple of int
        Steps per estimated contact time of the fixed-step scene (:data:`STEPS`).
    rtols : tuple of float
        Relative tolerances of the solve_ivp methods (:data:`RTOLS`).
    methods : tuple of str
        solve_ivp methods (:data:`METHODS`).
    repeats : int
        Runs per setting at most (the best wall time kept; :func:`_timed`).
    run_budget : float
        A run longer than a third of it ends its ladder [s] (:data:`RUN_BUDGET`).
    reference_rtols : tuple of float
        Tolerances tried for the reference, loosest first (:data:`REFERENCE_RTOLS`).
    reference_budget : int
        Steps one reference scene may cost (:data:`REFERENCE_STEPS`).
    """

    steps: tuple = STEPS
    rtols: tuple = RTOLS
    methods: tuple = METHODS
    repeats: int = 3
    run_budget: float = RUN_BUDGET
    reference_rtols: tuple = REFERENCE_RTOLS
    reference_budget: int = REFERENCE_STEPS


#: The coarse grid (``pim speed-error --coarse``): seconds, not a minute.
COARSE = Grid(steps=(10, 40, 160, 640), rtols=(1e-3, 1e-6, 1e-9), repeats=1)


@dataclass(frozen=True)
class SweepJob:
    """One friction configuration of the crush scene swept over the grid: its inputs and
    the grid (a job for one worker).

    Attributes
    ----------
    case : pim.Case
    eps : float
        Restitution [-].
    stiffness : float
        Contact stiffness [N/m].
    scene : str
        Its name (a key of :data:`SCENES`).
    friction : float
        mu_c between the vehicles [-].
    grid : Grid
        The settings swept and the budgets.
    engine : str
        The fixed-step integrator (:data:`ENGINES`).
    """

    case: pim.Case
    eps: float
    stiffness: float
    scene: str
    friction: float
    grid: Grid
    engine: str


def sweep_points(job: SweepJob) -> tuple:
    """(points, reference) of one scene: its reference, then every integrator's ladder
    (module level, so that the scenes run on a process pool)."""
    g, case = job.grid, job.case
    if job.engine == "numba":      # load (or compile) the kernel outside the timed runs
        _fixed_step(case, job.eps, job.stiffness, 0.0, sim.CompliantSettings(record=False),
                    job.engine)
    ref = reference_within_budget(case, job.eps, job.stiffness, job.friction,
                                  g.reference_rtols, g.reference_budget)
    usable = replace(g, rtols=tuple(r for r in g.rtols if r >= 10.0 * ref.rtol))
    points = []
    for integrator, ladder in _ladders(case, job.eps, job.stiffness, job.friction, usable,
                                       job.engine):
        points += _run_ladder(case, job.scene, ref.result, integrator, ladder, g.repeats,
                              g.run_budget)
    return points, ref


def compliant_sweep(case: pim.Case, eps: float | None = None, *, grid: Grid = Grid(),
                    scenes=None, progress: bool | None = None, engine: str = "numba",
                    contact_time: float = CONTACT_TIME, executor="serial"
                    ) -> CompliantSpeedStudy:
    """Run the study (module notes) for ``case`` at restitution ``eps`` (default: the case's,
    else 0.3) over ``grid`` (its settings and budgets; :data:`COARSE` for a quick look);
    ``scenes``: name -> mu_c (default :data:`SCENES`); ``engine`` ("numba" or "pymunk",
    :data:`ENGINES`) steps the fixed-step scene; ``contact_time`` [s] sets the stiffness
    (:func:`scene_stiffness`); the scenes run one per worker of ``executor``
    (:func:`sim.sweep.sweep`; default "serial"), each timing its own runs."""
    if engine not in ENGINES:
        raise InputError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    wall0 = time.perf_counter()
    if eps is None:
        eps = case.impact.restitution if case.impact.restitution is not None else 0.3
    eps = sim.contact_law.check_fraction(eps, "eps")
    k = scene_stiffness(case, eps, contact_time)
    jobs = [SweepJob(case, float(eps), k, scene, mu, grid, engine)
            for scene, mu in dict(SCENES if scenes is None else scenes).items()]
    done = sweep(sweep_points, jobs, executor=executor, chunksize=1,
                 progress=sys.stderr.isatty() if progress is None else bool(progress),
                 desc=f"compliant {case.name}")
    points = tuple(p for pts, _ in done for p in pts)
    spread = max((0.0 if math.isnan(ref.spread) else ref.spread) for _, ref in done)
    return CompliantSpeedStudy(case.name, float(eps), k, points, spread,
                               reference_rtol=max(ref.rtol for _, ref in done),
                               wall_time=time.perf_counter() - wall0,
                               contact_time=float(contact_time), engine=engine)


def compliant_table(study: CompliantSpeedStudy, name: str) -> Table:
    """Every run."""
    fronts = {id(p) for scene in {p.scene for p in study.points} for p in study.pareto(scene)}
    recs = {id(study.recommended(s)) for s in {p.scene for p in study.points}}
    rows = tuple((p.scene, p.integrator, p.setting, p.steps, p.error, p.wall_time * 1e3,
                  "yes" if id(p) in fronts else "", "yes" if id(p) in recs else "",
                  p.failure or "") for p in study.points)
    columns = ("scene", "integrator", "dt [s] or rtol", "steps", "error [-]",
               "wall time [ms]", "Pareto", "recommended", "failure")
    return Table(name, "Finite-duration contact: error against wall time", columns, rows,
                 {"error [-]": fmt_error})


def plot_compliant_speed_error(study: CompliantSpeedStudy):
    """Log-log error against wall time per impact, one panel per scene (a Figure)."""
    from matplotlib.figure import Figure

    scenes = list(dict.fromkeys(p.scene for p in study.points))
    fig = Figure(figsize=(6.0 * len(scenes), 4.8), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(scenes), sharey=True))
    style = {"compiled": ("D", "C4"), "pymunk": ("o", "C0"), "DOP853": ("s", "C1"),
             "Radau": ("^", "C2")}
    for ax, scene in zip(axes, scenes, strict=True):
        for name, (marker, color) in style.items():
            pts = [p for p in study.scene_points(scene) if p.integrator == name]
            if pts:
                ax.plot([p.wall_time for p in pts], [max(p.error, ERROR_FLOOR) for p in pts],
                        marker=marker, color=color, ls=":", lw=0.8,
                        label=fixed_step_label(name))
        front = study.pareto(scene)
        if front:
            ax.step([p.wall_time for p in front], [max(p.error, ERROR_FLOOR) for p in front],
                    where="post", color="C3", lw=1.5, label="Pareto front")
        rec = study.recommended(scene)
        if rec is not None:
            ax.scatter([rec.wall_time], [max(rec.error, ERROR_FLOOR)], s=260,
                       facecolors="none", edgecolors="C3", linewidths=2, zorder=5,
                       label=f"recommended: {rec.label}")
        ax.axhline(study.target, color="0.4", ls="--", lw=1, label=f"target {study.target:g}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time per impact [s]")
        ax.set_title(f"{study.case_name}, {scene}", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5)
    axes[0].set_ylabel(f"error against solve_ivp at rtol {study.reference_rtol:g} [-]")
    return fig

