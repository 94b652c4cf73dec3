"""What the whole event's accuracy costs: each event's error against a tight reference
versus its wall time (``pim speed-error --event``), as :mod:`comparisons.studies.speed_error`
does for one impact.

The reference is the pymunk event (:func:`sim.simulate_event`) at a tight setting
(:data:`REFERENCE`: dt = 1e-4 s, 100 solver iterations). Against it run

* the pymunk event over its step dt (which is also its contact test's step: Chipmunk tests
  the outlines every step) and its solver iterations per step;
* the analytic event (:func:`pim.event`) over its step (the run-out's fixed step, which is
  its contact test's step; near a contact it bisects to 1 us).

Error of an event (one number, so that runs can be ranked; [-]): the largest of each paired
impact's delta-V difference relative to the impact's largest |delta-V| (both vehicles;
:class:`sim.event_check.ImpactDifference`), and each vehicle's rest-position distance
relative to its travel from the first impact to rest in the reference; infinite when the
number of impacts differs from the reference's (a missed or extra impact is no small error).
The first impact's convergence check is off in the sweep (few iterations show their error
instead of a refusal), as in :mod:`comparisons.studies.speed_error`. Wall time: one event,
best of ``repeats`` runs (the analytic event after a first call that
compiles or loads its kernel). Failed runs keep their :class:`sim.SimulationError` kind.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

import pim
import sim
from comparisons.report.tables import Table, fmt_error
from comparisons.studies.speed_error import pareto_front
from sim.event_check import event_crosscheck

__all__ = ["EventPoint", "EventSpeedStudy", "event_sweep", "event_error", "REFERENCE",
           "EVENT_DTS", "EVENT_ITERATIONS", "ANALYTIC_STEPS", "EVENT_COARSE", "EVENT_TARGET",
           "event_study_table", "event_pareto_table", "plot_event_speed_error"]

#: The reference's pymunk setting.
REFERENCE = {"dt": 1e-4, "iterations": 100}
#: pymunk steps [s] and solver iterations per step of the full study (None: automatic).
EVENT_DTS = (1e-2, 3e-3, 1e-3, 3e-4)
EVENT_ITERATIONS = (3, 10, 30, None)
#: The analytic event's steps [s] of the full study.
ANALYTIC_STEPS = (0.02, 0.01, 0.004, 0.001)
#: The coarse grid (seconds, not minutes).
EVENT_COARSE = {"dts": (1e-2, 1e-3), "iterations": (10, None), "analytic_steps": (0.01, 0.004)}
#: Error the recommended setting must reach [-] (1 %: a centimetre in a metre of run-out).
EVENT_TARGET = 1e-2


@dataclass(frozen=True)
class EventPoint:
    """One run of the study.

    Attributes
    ----------
    engine : str
        "pymunk" or "analytic".
    step : float
        Its step [s] (pymunk's dt, or the analytic event's run-out step).
    iterations : int or None
        pymunk's solver iterations asked for (None: automatic; None for the analytic event).
    impacts : int
        Number of impacts found (0 when the run failed).
    error : float
        :func:`event_error` [-]; NaN when the run failed.
    rest_error : float
        Largest rest-position distance from the reference [m]; NaN when failed.
    wall_time : float
        Best wall time of one event [s]; NaN when failed.
    failure : str or None
        The :class:`sim.SimulationError` kind, or "refused" for the analytic event's refusal.
    message : str
    """

    engine: str
    step: float
    iterations: int | None
    impacts: int
    error: float
    rest_error: float
    wall_time: float
    failure: str | None = None
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.failure is None

    @property
    def label(self) -> str:
        if self.engine == "analytic":
            return f"analytic step={self.step:g}"
        its = "auto" if self.iterations is None else str(self.iterations)
        return f"pymunk dt={self.step:g} it={its}"


@dataclass(frozen=True, eq=False)
class EventSpeedStudy:
    """The outcome of :func:`event_sweep`.

    Attributes
    ----------
    case_name : str
    reference : pim.model.event.Event
        The tight pymunk event.
    reference_time : float
        Its wall time [s].
    points : tuple of EventPoint
    target : float
        Error the recommendation must reach [-].
    """

    case_name: str
    reference: object
    reference_time: float
    points: tuple
    target: float = EVENT_TARGET

    @property
    def succeeded(self) -> list:
        return [p for p in self.points if p.ok and math.isfinite(p.error)]

    def pareto(self) -> list:
        """Runs not beaten on both wall time and error, fastest first."""
        return pareto_front(self.succeeded)

    def recommended(self, engine: str | None = None):
        """The fastest run reaching the target (of ``engine`` when given), or None."""
        good = [p for p in self.succeeded if p.error <= self.target
                and (engine is None or p.engine == engine)]
        return min(good, key=lambda p: p.wall_time) if good else None


def event_error(event, reference) -> tuple[float, float]:
    """(the study's error [-] of ``event`` against ``reference``, module notes; the largest
    rest-position distance [m])."""
    check = event_crosscheck(event, reference)
    rest = float(np.max(check.rest_position))
    if not check.same_impacts:
        return math.inf, rest
    travel = [np.hypot(*(t.position[-1] - t.position[np.searchsorted(reference.time, 0.0)]))
              for t in reference.tracks]
    errors = [d.delta_v_relative for d in check.impacts]
    errors += [float(d) / max(float(s), 1e-3) for d, s in zip(check.rest_position, travel,
                                                              strict=True)]
    return float(max(errors)), rest


def _timed(run, repeats: int):
    best, out = math.inf, None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - t0)
    return out, best


def _point(engine, step, its, run, reference, repeats) -> EventPoint:
    failed = {"impacts": 0, "error": math.nan, "rest_error": math.nan,
              "wall_time": math.nan}
    try:
        event, wall = _timed(run, repeats)
    except sim.SimulationError as exc:
        return EventPoint(engine, step, its, **failed, failure=exc.kind, message=str(exc))
    except pim.InputError as exc:        # the analytic event's refusals
        return EventPoint(engine, step, its, **failed, failure="refused", message=str(exc))
    error, rest = event_error(event, reference)
    return EventPoint(engine, step, its, len(event.impacts), error, rest, wall)


def event_sweep(case: pim.Case, *, tyre_friction=None, dts=EVENT_DTS,
                iterations=EVENT_ITERATIONS, analytic_steps=ANALYTIC_STEPS,
                repeats: int = 1, progress: bool | None = None,
                reference: dict | None = None) -> EventSpeedStudy:
    """Run both events over their settings and measure error and time (module notes).

    Parameters
    ----------
    case : pim.Case
        A single case with both outlines.
    tyre_friction : float, optional
        As :func:`sim.simulate_event` and :func:`pim.event`.
    dts, iterations, analytic_steps : sequences
        pymunk's steps [s] and iterations (None: automatic), the analytic event's steps [s].
    repeats : int
        Runs per setting (the best wall time is kept).
    progress : bool or None
        tqdm bar on stderr (None: only on a terminal).
    reference : dict, optional
        The reference's ``sim.Settings`` fields (default :data:`REFERENCE`).

    Raises
    ------
    sim.SimulationError
        The reference itself failed.
    """
    from tqdm import tqdm

    kw = {} if tyre_friction is None else {"tyre_friction": tyre_friction}
    t0 = time.perf_counter()
    reference = sim.simulate_event(case, settings=sim.Settings(**(reference or REFERENCE)),
                                   **kw)
    reference_time = time.perf_counter() - t0
    pim.event(case, **kw)               # compiles or loads the analytic kernel: not timed
    runs = [("pymunk", dt, its) for dt in dts for its in iterations]
    runs += [("analytic", step, None) for step in analytic_steps]
    points = []
    for engine, step, its in tqdm(runs, desc=f"event speed-error {case.name or ''}".strip(),
                                  unit="run", leave=False,
                                  disable=None if progress is None else not progress):
        if engine == "pymunk":
            def run(step=step, its=its):
                return sim.simulate_event(case, settings=sim.Settings(
                    dt=step, iterations=its, convergence_tolerance=None), **kw)
        else:
            def run(step=step):
                return pim.event(case, step=step, **kw)
        points.append(_point(engine, step, its, run, reference, repeats))
    return EventSpeedStudy(case.name or "case", reference, reference_time, tuple(points))


def _its(p: EventPoint) -> str:
    return "" if p.engine == "analytic" else ("auto" if p.iterations is None
                                              else str(p.iterations))


def event_study_table(study: EventSpeedStudy, name: str = "speed_error_event") -> Table:
    """Every run: engine, step, iterations, impacts, errors, wall time [ms], failure."""
    pareto = {id(p) for p in study.pareto()}
    rows = tuple((p.engine, p.step, _its(p), p.impacts, p.error, p.rest_error,
                  p.wall_time * 1e3, "yes" if id(p) in pareto else "", p.failure or "")
                 for p in study.points)
    return Table(name, f"{study.case_name}: each event against the reference (pymunk, dt = "
                       f"{REFERENCE['dt']:g} s, {REFERENCE['iterations']} iterations, "
                       f"{len(study.reference.impacts)} impacts)",
                 ("engine", "step [s]", "iterations", "impacts", "error [-]",
                  "rest position error [m]", "wall time [ms]", "Pareto", "failure"), rows,
                 formats={"error [-]": fmt_error})


def event_pareto_table(study: EventSpeedStudy, name: str = "speed_error_event_pareto") -> Table:
    """The Pareto front and the reference, for reports."""
    rows = [("reference: " + f"pymunk dt={REFERENCE['dt']:g} it={REFERENCE['iterations']}",
             len(study.reference.impacts), 0.0, study.reference_time * 1e3)]
    rows += [(p.label, p.impacts, p.error, p.wall_time * 1e3) for p in study.pareto()]
    return Table(name, f"{study.case_name}: Pareto front of the whole event",
                 ("run", "impacts", "error [-]", "wall time per event [ms]"), tuple(rows),
                 formats={"error [-]": fmt_error})


def plot_event_speed_error(study: EventSpeedStudy):
    """Log-log error against wall time per event: pymunk's runs by step, the analytic
    event's, the Pareto front and the target. Returns a matplotlib Figure."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 5.4), layout="constrained")
    ax = fig.subplots()
    for engine, marker in (("pymunk", "o"), ("analytic", "*")):
        pts = [p for p in study.succeeded if p.engine == engine]
        if pts:
            ax.scatter([p.wall_time for p in pts], [max(p.error, 1e-12) for p in pts],
                       marker=marker, s=60 if engine == "pymunk" else 160, label=engine,
                       edgecolors="k", linewidths=0.4, zorder=3)
            for p in pts:
                ax.annotate(p.label.split(" ", 1)[1], (p.wall_time, max(p.error, 1e-12)),
                            fontsize=6, xytext=(3, 3), textcoords="offset points")
    front = study.pareto()
    if front:
        ax.step([p.wall_time for p in front], [max(p.error, 1e-12) for p in front],
                where="post", color="C3", lw=1.4, label="Pareto front")
    ax.axhline(study.target, color="0.4", ls="--", lw=1, label=f"target {study.target:g}")
    ax.set(xscale="log", yscale="log", xlabel="wall time per event [s]",
           ylabel="error against the reference [-]",
           title=f"{study.case_name}: the whole event, speed against error")
    ax.legend(fontsize=8)
    return fig
