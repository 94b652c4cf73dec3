"""Speed against error of the finite-duration contact: pymunk over dt, solve_ivp over rtol.

For one case, two point-contact scenes at the default car stiffness
(:data:`sim.DEFAULT_STIFFNESS`): frictionless, and with friction mu_c = 0.5 between the
vehicles (stick-slip). Each is integrated

* by pymunk (:func:`sim.simulate_compliant`) with dt = (estimated contact time) / n for n in
  :data:`STEPS` (10 ... 2560 steps per contact), and
* by ``solve_ivp`` (:func:`sim.reference_compliant`) with DOP853 (explicit) and Radau
  (implicit) at rtol in :data:`RTOLS`,

against the reference: DOP853 at rtol 1e-13. The error is
:func:`sim.error_measure.impact_error` (largest error in the impact's velocity changes,
relative to the largest change); the wall time per impact is the best of ``repeats`` runs.
The Pareto front is :func:`comparisons.speed_error.pareto_front`; the recommended setting is
the fastest run on the front that reaches :data:`TARGET` (1e-3, the issue's goal), and the
fastest reaching 1e-6 is reported per integrator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import pim
import sim
from pim.io.files import save_figure, write_text
from sim.error_measure import impact_error

from .speed_error import ERROR_FLOOR, pareto_front
from .tables import Table, fmt_error

__all__ = ["CompliantPoint", "CompliantSpeedStudy", "compliant_sweep", "STEPS", "RTOLS",
           "TARGET", "SCENES", "plot_compliant_speed_error", "write_compliant_study"]

STEPS = (10, 20, 40, 80, 160, 320, 640, 1280, 2560)
RTOLS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-8, 1e-10, 1e-12)
METHODS = ("DOP853", "Radau")
TARGET = 1e-3
#: scene name -> friction mu_c between the vehicles
SCENES = {"frictionless": 0.0, "friction 0.5": 0.5}
REFERENCE_RTOL = 1e-13


@dataclass(frozen=True)
class CompliantPoint:
    """One integrator setting and how it did on one scene."""

    scene: str
    integrator: str          # "pymunk", "DOP853", "Radau"
    setting: float           # dt [s] for pymunk, rtol for solve_ivp
    steps: int
    error: float
    wall_time: float
    failure: str | None = None

    @property
    def ok(self) -> bool:
        return self.failure is None and math.isfinite(self.error)

    @property
    def label(self) -> str:
        name = "dt" if self.integrator == "pymunk" else "rtol"
        return f"{self.integrator} {name}={self.setting:.3g}"


@dataclass(frozen=True, eq=False)
class CompliantSpeedStudy:
    """Outcome of :func:`compliant_sweep`."""

    case_name: str
    eps: float
    stiffness: float
    points: tuple
    reference_spread: float   # |DOP853 - Radau| at the tightest rtol, on the error scale
    target: float = TARGET

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
    best, out = math.inf, None
    for _ in range(max(1, repeats)):
        out = func()
        best = min(best, out.wall_time)
    return out, best


def compliant_sweep(case: pim.Case, eps: float | None = None, *, steps=STEPS, rtols=RTOLS,
                    methods=METHODS, scenes=None, repeats: int = 3,
                    progress: bool | None = None) -> CompliantSpeedStudy:
    """Run the study (module notes) for ``case`` at restitution ``eps`` (default: the case's,
    else 0.3)."""
    from tqdm.auto import tqdm

    if eps is None:
        eps = case.impact.restitution if case.impact.restitution is not None else 0.3
    eps = sim.contact_law.check_fraction(eps, "eps")
    k = sim.DEFAULT_STIFFNESS
    scenes = dict(SCENES if scenes is None else scenes)
    total = len(scenes) * (len(steps) + len(rtols) * len(methods))
    bar = tqdm(total=total, desc=f"compliant {case.name}", unit="run", leave=False,
               disable=None if progress is None else not progress)
    points = []
    spread = 0.0
    try:
        for scene, mu in scenes.items():
            ref = sim.reference_compliant(case, eps, k, friction=mu, settings=sim.CompliantSettings(
                record=False, rtol=REFERENCE_RTOL))
            alt = sim.reference_compliant(case, eps, k, friction=mu, settings=sim.CompliantSettings(
                record=False, rtol=1e-12, method="Radau"))
            spread = max(spread, float(impact_error(case, ref, alt.velocity1, alt.velocity2,
                                                    alt.yaw_rate1, alt.yaw_rate2)))

            def record(integrator, setting, run, scene=scene, ref=ref):
                try:
                    out, wall = _timed(run, repeats)
                    err = float(impact_error(case, ref, out.velocity1, out.velocity2,
                                             out.yaw_rate1, out.yaw_rate2))
                    points.append(CompliantPoint(scene, integrator, setting, out.steps, err,
                                                 wall))
                except sim.SimulationError as exc:
                    points.append(CompliantPoint(scene, integrator, setting, 0, math.nan,
                                                 math.nan, exc.kind))
                bar.update(1)

            for n in steps:
                settings = sim.CompliantSettings(record=False, steps_per_contact=int(n),
                                                 min_steps=min(10, int(n)))
                dt = sim.compliant.step_size(sim.compliant_setup.build_problem(
                    case, eps, k, mu, settings=settings))
                record("pymunk", dt, lambda s=settings, mu=mu: sim.simulate_compliant(
                    case, eps, k, friction=mu, settings=s))
            for method in methods:
                for rtol in rtols:
                    settings = sim.CompliantSettings(record=False, rtol=rtol, method=method)
                    record(method, rtol, lambda s=settings, mu=mu: sim.reference_compliant(
                        case, eps, k, friction=mu, settings=s))
    finally:
        bar.close()
    return CompliantSpeedStudy(case.name, float(eps), k, tuple(points), spread)


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
    style = {"pymunk": ("o", "C0"), "DOP853": ("s", "C1"), "Radau": ("^", "C2")}
    for ax, scene in zip(axes, scenes, strict=True):
        for name, (marker, color) in style.items():
            pts = [p for p in study.scene_points(scene) if p.integrator == name]
            if pts:
                ax.plot([p.wall_time for p in pts], [max(p.error, ERROR_FLOOR) for p in pts],
                        marker=marker, color=color, ls=":", lw=0.8,
                        label="pymunk over dt" if name == "pymunk" else f"solve_ivp {name}")
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
    axes[0].set_ylabel("error against solve_ivp at rtol 1e-13 [-]")
    return fig


def write_compliant_study(study: CompliantSpeedStudy, out_dir, stem: str,
                          command: str = "") -> list[Path]:
    """Write ``speed-error-compliant-STEM.md``, ``.csv`` and ``.png``."""

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    table = compliant_table(study, f"speed-error-compliant-{stem}")
    png = save_figure(plot_compliant_speed_error(study), out / f"speed-error-compliant-{stem}.png")
    lines = [f"# Speed against error of the finite-duration contact: {study.case_name}", ""]
    if command:
        lines += [f"Regenerate with `{command}`.", ""]
    lines += [f"Point contact, epsilon = {study.eps:.4g}, k = {study.stiffness:.3g} N/m; "
              f"pymunk over dt (10 ... 2560 steps per estimated contact time), solve_ivp "
              f"DOP853 and Radau over rtol, against DOP853 at rtol 1e-13 (which Radau at "
              f"1e-12 matches to {study.reference_spread:.1e}). Error: the largest error in "
              f"the impact's velocity changes, relative to the largest change.", ""]
    for scene in dict.fromkeys(p.scene for p in study.points):
        rec = study.recommended(scene)
        text = (f"**recommended {rec.label}**: error {rec.error:.1e} in "
                f"{rec.wall_time * 1e3:.3g} ms" if rec else "no run reaches the target")
        lines.append(f"- {scene}: {text}.")
        for integrator in ("pymunk", "DOP853", "Radau"):
            for target in (1e-3, 1e-6):
                p = study.fastest(scene, integrator, target)
                if p is not None:
                    lines.append(f"  - {integrator} reaches {target:g} at {p.label}: "
                                 f"{p.wall_time * 1e3:.3g} ms per impact")
    lines += ["", f"![speed against error](speed-error-compliant-{stem}.png)", "",
              table.to_markdown(), ""]
    md = write_text(out / f"speed-error-compliant-{stem}.md", "\n".join(lines))
    return [md, table.write_csv(out), png]
