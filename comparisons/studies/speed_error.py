"""What the simulator's accuracy costs: error against the analytic answer versus wall time.

For one case at (epsilon, beta) :func:`sweep` runs the pymunk scene over a grid of

* time step dt (1e-2 ... 1e-5 s),
* solver iterations per step (1 ... 100, and the automatic count of :mod:`sim.convergence`),
* contact start: "exact" (the bodies reach PIM's impact configuration exactly when the
  contact is processed) or "detected" (the engine finds the contact itself, a fraction of a
  step late, so the lever arms are off by O(dt)),
* contact geometry: "point" (PIM's single point C and normal n) or "outline" (the
  vehicles' rectangles collide, a contact patch),

and records the error of each run (:func:`sim.error_measure.impact_error`, relative to the
velocity changes of the impact) and its wall time per impact (building the pymunk Space and
stepping it, best of ``repeats`` runs: the machine is shared and noisy). Failed runs keep
their :class:`sim.SimulationError` kind. The analytic solver goes on the same axes: its time
per impact (one call, and per case in a vectorised batch of 10 000) and its error, the
residual of its own equations (:func:`sim.error_measure.analytic_residual`).

The Pareto front holds the runs that no other run beats on both time and error; the
recommended setting is taken from the front (so no run is both faster and more accurate):
the largest dt, then the fewest iterations, among the front's runs that reach the target
error (1e-6) within 2x the fastest such run's time.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from itertools import product

import numpy as np

import pim
import sim
from comparisons.report.tables import Table, fmt_error
from sim.error_measure import analytic_residual, impact_error
from sim.scene import resolve_coefficients

__all__ = ["SweepPoint", "SpeedErrorStudy", "sweep", "DTS", "ITERATIONS", "STARTS",
           "CONTACTS", "TARGET", "COARSE", "plot_speed_error", "study_table",
           "pareto_table", "analytic_timing", "pareto_front", "ERROR_FLOOR"]

#: Time steps [s] of the full study.
DTS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5)
#: Solver iterations per step of the full study; None is the automatic count.
ITERATIONS = (1, 2, 3, 5, 10, 20, 30, 50, 100, None)
STARTS = ("exact", "detected")
CONTACTS = ("point", "outline")
#: Error the recommended setting must reach [-].
TARGET = 1e-6
#: The coarse grid of the report (``pim compare``): seconds, not minutes.
COARSE = dict(dts=(1e-2, 1e-3, 1e-4, 1e-5), iterations=(1, 3, 10, 30, None),
              starts=STARTS, contacts=CONTACTS, repeats=1)


@dataclass(frozen=True)
class SweepPoint:
    """One simulator setting and how it did.

    Attributes
    ----------
    dt : float
        Time step [s].
    iterations : int or None
        Iterations asked for (None: automatic).
    iterations_used : int
        Iterations the engine ran (the automatic count resolved), 0 if the run failed early.
    start, contact : str
        Contact start and geometry.
    error : float
        :func:`sim.error_measure.impact_error` [-]; NaN when the run failed.
    wall_time : float
        Best wall time per impact [s]; NaN when the run failed.
    failure : str or None
        The :class:`sim.SimulationError` kind (or "unavailable" for a setting the case
        cannot take, e.g. outlines of a vehicle without dimensions).
    message : str
        The failure message.
    """

    dt: float
    iterations: int | None
    iterations_used: int
    start: str
    contact: str
    error: float
    wall_time: float
    failure: str | None = None
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.failure is None

    @property
    def label(self) -> str:
        its = "auto" if self.iterations is None else str(self.iterations)
        return f"dt={self.dt:g} it={its} {self.start}/{self.contact}"


@dataclass(frozen=True, eq=False)
class SpeedErrorStudy:
    """The outcome of :func:`sweep`.

    Attributes
    ----------
    case_name : str
    eps, beta : float
        The coefficients simulated [-].
    points : tuple of SweepPoint
    analytic_time : float
        Wall time of one ``pim.solve`` call on the single case [s] (best of several).
    analytic_batch_time : float
        Wall time per case of ``pim.solve`` on a batch of 10 000 copies [s].
    analytic_error : float
        Residual of PIM's own equations (:func:`sim.error_measure.analytic_residual`) [-].
    target : float
        Error the recommendation must reach [-].
    """

    case_name: str
    eps: float
    beta: float
    points: tuple[SweepPoint, ...]
    analytic_time: float
    analytic_batch_time: float
    analytic_error: float
    target: float = TARGET

    @property
    def succeeded(self) -> list[SweepPoint]:
        return [p for p in self.points if p.ok]

    def pareto(self) -> list[SweepPoint]:
        """Runs not beaten on both wall time and error, fastest first."""
        return pareto_front(self.succeeded)

    def recommended(self) -> SweepPoint | None:
        """The setting to use, a run on the Pareto front (module docstring), or None if no
        run reaches the target."""
        good = [p for p in self.pareto() if p.error <= self.target]
        if not good:
            return None
        fastest = min(p.wall_time for p in good)
        near = [p for p in good if p.wall_time <= 2.0 * fastest]
        return sorted(near, key=lambda p: (-p.dt, p.iterations_used, p.start != "exact",
                                           p.contact != "point", p.wall_time))[0]

    def best(self, **where) -> SweepPoint | None:
        """The most accurate successful run among those matching ``where`` (e.g. start=...)."""
        pts = [p for p in self.succeeded if all(getattr(p, k) == v for k, v in where.items())]
        return min(pts, key=lambda p: (p.error, p.wall_time)) if pts else None

    def cheapest_reaching(self, target: float | None = None, **where) -> SweepPoint | None:
        """Largest dt, then fewest iterations, reaching ``target`` among matching runs."""
        target = self.target if target is None else target
        pts = [p for p in self.succeeded if p.error <= target
               and all(getattr(p, k) == v for k, v in where.items())]
        if not pts:
            return None
        return sorted(pts, key=lambda p: (-p.dt, p.iterations_used, p.wall_time))[0]


def pareto_front(points) -> list:
    """Points (with ``wall_time`` and ``error``) not beaten on both, fastest first."""
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p.wall_time, p.error)):
        if p.error < best:
            front.append(p)
            best = p.error
    return front


def analytic_timing(case: pim.Case, eps: float, beta: float, repeats: int = 20):
    """(seconds per single call, seconds per case in a batch of 10 000) of ``pim.solve``."""
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        pim.solve(case, eps, beta)
        best = min(best, time.perf_counter() - t0)
    batch = np.full(10_000, float(eps))
    pim.solve(case, batch, beta, backend="numpy")
    best_batch = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        pim.solve(case, batch, beta, backend="numpy")
        best_batch = min(best_batch, time.perf_counter() - t0)
    return best, best_batch / len(batch)


def _run(case, eps, beta, settings, analytic, result, repeats):

    best = math.inf
    out = None
    for _ in range(max(1, repeats)):
        out = sim.simulate(case, eps, beta, settings, analytic=analytic)
        best = min(best, out.wall_time)
    err = float(impact_error(case, result, out.velocity1, out.velocity2, out.yaw_rate1,
                             out.yaw_rate2))
    return out, err, best


def sweep(case: pim.Case, eps: float | None = None, beta: float | None = None, *,
          dts=DTS, iterations=ITERATIONS, starts=STARTS, contacts=CONTACTS, repeats: int = 3,
          target: float = TARGET, progress: bool | None = None) -> SpeedErrorStudy:
    """Run the simulator over every combination of the settings and measure error and time.

    Parameters
    ----------
    case : pim.Case
        A single case.
    eps, beta : float, optional
        Coefficients [-]; default the case's (beta 1 if unset).
    dts, iterations, starts, contacts : sequences
        The settings swept (module docstring); iterations None = automatic.
    repeats : int
        Runs per setting; the best wall time is kept.
    target : float
        Error the recommendation must reach [-].
    progress : bool or None
        tqdm bar on stderr (None: only on a terminal).
    """
    from tqdm import tqdm


    eps, beta = resolve_coefficients(case, eps, beta)
    result = pim.solve(case, eps, beta)
    analytic = pim.solve(case, eps, 1.0)
    combos = list(product(contacts, starts, dts, iterations))
    points = []
    for contact, start, dt, its in tqdm(combos, desc=f"speed-error {case.name or ''}".strip(),
                                        unit="run", leave=False,
                                        disable=None if progress is None else not progress):
        settings = sim.Settings(dt=dt, iterations=its, start=start, contact=contact,
                                convergence_tolerance=None)
        try:
            out, err, wall = _run(case, eps, beta, settings, analytic, result, repeats)
        except sim.SimulationError as exc:
            points.append(SweepPoint(dt, its, 0, start, contact, math.nan, math.nan,
                                     failure=exc.kind, message=str(exc)))
            continue
        except ValueError as exc:       # e.g. outlines without vehicle dimensions
            points.append(SweepPoint(dt, its, 0, start, contact, math.nan, math.nan,
                                     failure="unavailable", message=str(exc)))
            continue
        points.append(SweepPoint(dt, its, out.iterations, start, contact, err, wall))
    t_one, t_batch = analytic_timing(case, eps, beta)
    return SpeedErrorStudy(case.name or "case", eps, beta, tuple(points), t_one, t_batch,
                           analytic_residual(case, result), target)


# ---------------------------------------------------------------------------------------------
# tables and plot
# ---------------------------------------------------------------------------------------------

def _its(p: SweepPoint) -> str:
    return f"auto ({p.iterations_used})" if p.iterations is None else str(p.iterations)


def study_table(study: SpeedErrorStudy, name: str = "speed_error") -> Table:
    """Every run: settings, error, wall time per impact [ms], failure."""
    pareto = {id(p) for p in study.pareto()}
    rec = study.recommended()
    rows = []
    for p in study.points:
        rows.append((p.contact, p.start, p.dt, _its(p), p.iterations_used,
                     p.error, p.wall_time * 1e3 if p.ok else math.nan,
                     "yes" if id(p) in pareto else "", "yes" if p is rec else "",
                     p.failure or ""))
    return Table(name, f"{study.case_name}: simulator error against PIM and wall time per impact",
                 ("contact", "start", "dt [s]", "iterations", "sweeps used", "error [-]",
                  "wall time [ms]", "Pareto", "recommended", "failure"),
                 tuple(rows), formats={"error [-]": fmt_error})


def pareto_table(study: SpeedErrorStudy, name: str = "speed_error_pareto") -> Table:
    """The Pareto front, the recommendation and the analytic solver, for reports."""
    rec = study.recommended()
    rows = [("PIM analytic, one call", "", "", "", study.analytic_error,
             study.analytic_time * 1e3, ""),
            ("PIM analytic, batch of 10 000 (per case)", "", "", "", study.analytic_error,
             study.analytic_batch_time * 1e3, "")]
    for p in study.pareto():
        rows.append((f"pymunk {p.contact}, {p.start} start", p.dt, _its(p), p.iterations_used,
                     p.error, p.wall_time * 1e3, "yes" if p is rec else ""))
    return Table(name, f"{study.case_name}: Pareto front (no faster run is more accurate)",
                 ("solver", "dt [s]", "iterations", "sweeps used", "error [-]",
                  "wall time per impact [ms]", "recommended"), tuple(rows),
                 formats={"error [-]": fmt_error})


#: Errors below this are drawn at it (a log axis has no zero).
ERROR_FLOOR = 1e-17


def plot_speed_error(study: SpeedErrorStudy):
    """Log-log error against wall time per impact: every run, the Pareto front, the
    analytic solver, the target and the recommended setting. Returns a matplotlib Figure."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    fig = Figure(figsize=(8.6, 5.8), layout="constrained")
    ax = fig.subplots()
    markers = {("point", "exact"): "o", ("point", "detected"): "s",
               ("outline", "exact"): "^", ("outline", "detected"): "v"}
    ok = study.succeeded
    dts = sorted({p.dt for p in study.points})
    import matplotlib as mpl

    cmap = mpl.colormaps["viridis"]
    norm = mpl.colors.LogNorm(vmin=min(dts), vmax=max(dts) * (1.0001 if len(dts) == 1 else 1))
    for (contact, start), marker in markers.items():
        pts = [p for p in ok if p.contact == contact and p.start == start]
        if not pts:
            continue
        ax.scatter([p.wall_time for p in pts], [max(p.error, ERROR_FLOOR) for p in pts],
                   c=[p.dt for p in pts], cmap=cmap, norm=norm, marker=marker, s=34,
                   edgecolors="k", linewidths=0.3, alpha=0.85, zorder=3)
    front = study.pareto()
    if front:
        xs = [p.wall_time for p in front]
        ys = [max(p.error, ERROR_FLOOR) for p in front]
        ax.step(xs, ys, where="post", color="C3", lw=1.6, zorder=4, label="Pareto front")
    ax.scatter([study.analytic_time], [max(study.analytic_error, ERROR_FLOOR)], marker="*",
               s=260, color="gold", edgecolors="k", zorder=5, label="PIM analytic, one call")
    ax.scatter([study.analytic_batch_time], [max(study.analytic_error, ERROR_FLOOR)],
               marker="D", s=120, color="orange", edgecolors="k", zorder=5,
               label="PIM analytic, per case in a batch of 10 000")
    ax.axhline(study.target, color="0.4", ls="--", lw=1, label=f"target {study.target:g}")
    rec = study.recommended()
    if rec is not None:
        ax.scatter([rec.wall_time], [max(rec.error, ERROR_FLOOR)], s=300, facecolors="none",
                   edgecolors="C3", linewidths=2.2, zorder=6)
        ax.annotate(f"recommended:\ndt = {rec.dt:g} s, {_its(rec)} iterations,\n"
                    f"{rec.start} start, {rec.contact} contact",
                    xy=(rec.wall_time, max(rec.error, ERROR_FLOOR)), xytext=(18, 28),
                    textcoords="offset points", fontsize=8.5, color="C3",
                    arrowprops=dict(arrowstyle="-", color="C3"),
                    bbox=dict(boxstyle="round", fc="white", ec="C3", alpha=0.9))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time per impact [s]")
    ax.set_ylabel("error against PIM (relative to the velocity changes) [-]")
    failed = len(study.points) - len(ok)
    ax.set_title(f"{study.case_name}: speed against error  (ε = {study.eps:.4g}, "
                 f"β = {study.beta:.4g}; {len(ok)} runs"
                 + (f", {failed} failed and not shown)" if failed else ")"), fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    for (contact, start), marker in markers.items():
        handles.append(Line2D([], [], marker=marker, ls="", color="0.5", mec="k", mew=0.3))
        labels.append(f"pymunk, {contact} contact, {start} start")
    ax.legend(handles, labels, fontsize=7.5, loc="center left")
    sm = mpl.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=ax, label="time step dt [s]")
    ax.text(0.01, 0.01, f"errors below {ERROR_FLOOR:g} drawn at {ERROR_FLOOR:g}",
            transform=ax.transAxes, fontsize=7, color="0.4")
    return fig
