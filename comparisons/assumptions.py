"""``pim assumptions``: which of PIM's assumptions holds for a case, and by how much.

For each assumption of PIM the finite-duration scene of :func:`sim.simulate_compliant`
relaxes it alone, a physical parameter is swept, and PIM's error against the simulation is
measured:

========================  =========================================  ======================
assumption                scene (only this differs from PIM)          swept parameter
========================  =========================================  ======================
instantaneous impulse     point contact, frictionless, no tyres       contact time 10-200 ms
no external forces        the same at 100 ms, tyres during contact    tyre friction 0-1
one impact point          outlines crush into each other, no friction contact time 10-200 ms
Newton restitution and    point contact at 5 ms (nearly instant),     friction mu_c 0-1.5
mu = beta mu0             Coulomb friction with a friction spring
========================  =========================================  ======================

PIM is evaluated with the same physical restitution epsilon (the crush hysteresis' own)
and, for the frictionless scenes, beta = 0; for the friction scene with the beta a user who
knows mu_c would give it, beta = min(1, mu_c / |mu0|) (mu0 from PIM, on PIM's side only).

Errors (simulation = truth), per vehicle i:

* delta-V: | |dV_PIM,i| - |dV_sim,i| | / |dV_sim,i|;
* speed: |speed_PIM,i - speed_sim,i| / |dV_sim,i| (relative to the change, so that a
  vehicle nearly at rest after the impact does not blow it up);
* yaw: k_i |Omega_PIM,i - Omega_sim,i| / |dV_sim,i| (the yaw-rate error as a velocity at the
  radius of gyration k_i, on the same scale).

The effective (epsilon, beta) are :func:`pim.fit` applied to the simulated post-impact
motion (velocities and yaw rates): what PIM would need to reproduce it; the effective C is
the impulse centroid of the simulation. At typical values (100 ms, mu_tyre 0.7, the case's
outlines, mu_c 0.5) a table gives all of it and one sentence per assumption says whether it
holds (within 5 %, within 15 %, or not).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

import pim
import sim
from pim.io import html as h
from pim.io.files import save_figure, write_text
from pim.io.units import convert
from sim.compliant_setup import build_problem
from sim.contact_law import stiffness_for_duration
from sim.sweep import sweep

from .animation import build_renderer, write_animation
from .coefficients import coefficients
from .report_html import assumption_tables
from .tables import Table, fmt_error

__all__ = ["ASSUMPTIONS", "Outcome", "AssumptionSweep", "AssumptionStudy", "run_assumptions",
           "assumption_table", "plot_assumption", "plot_overview", "write_assumptions",
           "outcome_errors", "TYPICAL", "HOLDS", "ROUGHLY"]

#: Relative error below which an assumption "holds", and below which it holds "roughly".
HOLDS, ROUGHLY = 0.05, 0.15
#: Typical values of the swept parameters.
TYPICAL = {"duration": 0.1, "tyre_friction": 0.7, "friction": 0.5}
#: Contact duration [s] of the friction scene (short: the impulse is nearly instantaneous).
FRICTION_SCENE_DURATION = 0.005

#: key -> (title, parameter, unit, swept values, geometry)
ASSUMPTIONS = {
    "instantaneous": ("instantaneous impulse (no motion during the contact)", "contact time",
                      "ms", (10, 20, 35, 50, 75, 100, 150, 200)),
    "no_external_forces": ("no external forces (tyres) during the contact", "tyre friction",
                           "-", (0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)),
    "one_point": ("one impact point (outlines crush instead)", "contact time", "ms",
                  (10, 20, 35, 50, 75, 100, 150, 200)),
    "restitution_friction": ("Newton restitution and mu = beta mu0 (Coulomb friction, "
                             "stick-slip)", "friction mu_c", "-",
                             (0.0, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5)),
}
ERROR_NAMES = ("delta_v1", "delta_v2", "speed1", "speed2", "yaw1", "yaw2")


@dataclass(frozen=True)
class Outcome:
    """One simulated scene against PIM.

    Attributes
    ----------
    key : str
        The assumption (a key of :data:`ASSUMPTIONS`).
    value : float
        The swept parameter (contact time in ms, or a coefficient).
    errors : dict
        Name in :data:`ERROR_NAMES` -> relative error [-] (NaN for a fixed vehicle 2).
    yaw_error_deg : (float, float)
        |Omega_PIM - Omega_sim| per vehicle [deg/s].
    eps_eff, beta_eff : float
        Effective (epsilon, beta): :func:`pim.fit` to the simulated motion.
    fit_rms : float
        Its rms residual [m/s] (how well any PIM answer reproduces the simulation).
    point_eff : ndarray (2,)
        Impulse centroid [m] (effective C).
    contact_duration : float
        [s].
    stick_fraction : float
    slip_reversed : bool
    energy_loss : float
        Share of the kinetic energy lost [-] (simulation).
    pim_energy_loss : float
        PIM's share [-] (negative: PIM gains energy).
    secondary_impact : float or None
        Time [s] of a secondary impact after separation, if one was looked for and found.
    point_distance : float
        |C_eff - C| [m].
    failure : str or None
        Why the simulation failed (then the numbers are NaN).
    """

    key: str
    value: float
    errors: dict
    yaw_error_deg: tuple
    eps_eff: float
    beta_eff: float
    fit_rms: float
    point_eff: np.ndarray
    contact_duration: float
    stick_fraction: float
    slip_reversed: bool
    energy_loss: float
    pim_energy_loss: float
    secondary_impact: float | None = None
    point_distance: float = math.nan
    failure: str | None = None

    @property
    def worst(self) -> tuple[str, float]:
        """The largest relative error and its name."""
        finite = {k: v for k, v in self.errors.items() if math.isfinite(v)}
        if not finite:
            return "", math.nan
        name = max(finite, key=finite.get)
        return name, finite[name]


@dataclass(frozen=True)
class AssumptionSweep:
    """One assumption: the swept outcomes and the one at the typical value."""

    key: str
    title: str
    parameter: str
    unit: str
    outcomes: tuple
    typical: Outcome

    @property
    def values(self) -> np.ndarray:
        return np.array([o.value for o in self.outcomes])

    def error(self, name: str) -> np.ndarray:
        return np.array([o.errors.get(name, math.nan) for o in self.outcomes])

    def verdict(self) -> str:
        """One sentence: does the assumption hold for this case at the typical value?"""
        o = self.typical
        if o.failure is not None:
            return f"{self.title}: not assessed (simulation failed: {o.failure})."
        name, worst = o.worst
        where = f"{_label(name)} off by {100 * worst:.1f} %"
        typical = f"{_fmt(o.value)} {self.unit}".replace(" -", "")
        extra = ""
        if self.key == "one_point":
            extra = f"; the impulse centroid lies {o.point_distance:.2f} m from C"
        if self.key == "restitution_friction" and o.slip_reversed:
            extra = "; the tangential slip reverses, which mu = beta mu0 cannot represent"
        if worst < HOLDS:
            text = f"holds within 5 % ({where} at {self.parameter} {typical})"
        elif worst < ROUGHLY:
            text = f"holds roughly, within 15 % ({where} at {self.parameter} {typical})"
        else:
            text = f"does not hold ({where} at {self.parameter} {typical})"
        return f"{self.title[0].upper()}{self.title[1:]}: {text}{extra}."


@dataclass(frozen=True, eq=False)
class AssumptionStudy:
    """Outcome of :func:`run_assumptions`."""

    case: pim.Case
    eps: float
    beta: float
    stiffness_typical: float
    sweeps: tuple
    seconds: float
    animation_result: object = field(default=None, repr=False)

    def sweep(self, key: str) -> AssumptionSweep:
        return next(s for s in self.sweeps if s.key == key)

    def verdicts(self) -> list[str]:
        return [s.verdict() for s in self.sweeps]


def _label(name: str) -> str:
    return {"delta_v1": "|delta-V| of vehicle 1", "delta_v2": "|delta-V| of vehicle 2",
            "speed1": "speed of vehicle 1", "speed2": "speed of vehicle 2",
            "yaw1": "yaw rate of vehicle 1", "yaw2": "yaw rate of vehicle 2"}.get(name, name)


def _fmt(x: float) -> str:
    return f"{x:g}"


def _gyration(vehicle) -> float:
    return float(np.sqrt(vehicle.yaw_inertia / vehicle.mass))


def outcome_errors(case: pim.Case, result: pim.Result, velocity1, velocity2, yaw_rate1,
                   yaw_rate2) -> tuple[dict, tuple]:
    """PIM's relative errors against a simulated outcome (module notes), and the yaw-rate
    errors [deg/s]."""
    out = {}
    yaw_deg = []
    sims = ((case.vehicle1, velocity1, yaw_rate1, result.velocity1, result.yaw_rate1),
            (case.vehicle2, velocity2, yaw_rate2, result.velocity2, result.yaw_rate2))
    for i, (vehicle, v_sim, w_sim, v_pim, w_pim) in enumerate(sims, start=1):
        if bool(vehicle.fixed):
            for n in ("delta_v", "speed", "yaw"):
                out[f"{n}{i}"] = math.nan
            yaw_deg.append(math.nan)
            continue
        v0 = np.asarray(vehicle.velocity, float).reshape(2)
        v_sim = np.asarray(v_sim, float)
        v_pim = np.asarray(v_pim, float).reshape(2)
        dv_sim = max(float(np.hypot(*(v_sim - v0))), 1e-12)
        out[f"delta_v{i}"] = abs(float(np.hypot(*(v_pim - v0))) - dv_sim) / dv_sim
        out[f"speed{i}"] = abs(float(np.hypot(*v_pim)) - float(np.hypot(*v_sim))) / dv_sim
        dw = abs(float(np.asarray(w_pim)) - float(w_sim))
        out[f"yaw{i}"] = _gyration(vehicle) * dw / dv_sim
        yaw_deg.append(math.degrees(dw))
    return {k: out[k] for k in ERROR_NAMES}, tuple(yaw_deg)


def _job(job: tuple) -> Outcome:
    """One scene of the study (module-level, so that it runs on a process pool)."""
    case, key, value, eps, beta_pim, stiffness, settings, kwargs = job
    try:
        r = sim.simulate_compliant(case, eps, stiffness, settings=settings, **kwargs)
    except sim.SimulationError as exc:
        nan = math.nan
        return Outcome(key, value, {n: nan for n in ERROR_NAMES}, (nan, nan), nan, nan, nan,
                       np.full(2, nan), nan, nan, False, nan, nan, None, nan,
                       f"{exc.kind}: {exc}")
    return _outcome(case, key, value, eps, beta_pim, r)


def _outcome(case, key, value, eps, beta_pim, r) -> Outcome:
    result = pim.solve(case, eps, beta_pim)
    errors, yaw_deg = outcome_errors(case, result, r.velocity1, r.velocity2, r.yaw_rate1,
                                     r.yaw_rate2)
    fixed2 = bool(case.vehicle2.fixed)
    measured = pim.Measured(r.velocity1, None if fixed2 else r.velocity2, r.yaw_rate1,
                            None if fixed2 else r.yaw_rate2)
    try:
        fitted = pim.fit(replace(case, measured=measured), include_yaw=True)
        eps_eff, beta_eff, rms = fitted.eps, fitted.beta, fitted.rms
    except ValueError:
        eps_eff = beta_eff = rms = math.nan
    e0 = r.energy_before
    pim_loss = float(np.asarray(result.energy_loss)) / e0 if e0 > 0 else math.nan
    point = np.asarray(case.impact.point, float).reshape(2)
    centroid = np.asarray(r.impact_point, float)
    return Outcome(key, float(value), errors, yaw_deg, float(eps_eff), float(beta_eff),
                   float(rms), centroid, r.contact_duration, r.stick_fraction,
                   bool(r.slip_reversed), r.energy_loss / e0 if e0 > 0 else math.nan, pim_loss,
                   r.secondary_impact, float(np.hypot(*(centroid - point))))


def run_assumptions(case: pim.Case, eps: float | None = None, beta: float | None = None, *,
                    executor=None, progress: bool | None = None, stiffness: float | None = None,
                    animation_after: float | None = 2.0, settings=None,
                    sweeps: bool = True) -> AssumptionStudy:
    """Sweep every assumption of PIM for ``case`` (module notes).

    Parameters
    ----------
    case : pim.Case
        A single case.
    eps : float, optional
        Physical restitution [-] of the crush (default: the fit to the case's measured motion,
        else ``case.impact.restitution``).
    beta : float, optional
        PIM's beta as the case uses it (reported; the frictionless scenes compare with
        beta = 0, the friction scene with min(1, mu_c / |mu0|)).
    executor : None, "process", "serial", dask Client or Executor
        Where the scenes run (:func:`sim.sweep.sweep`).
    progress : bool or None
        Progress bar.
    stiffness : float, optional
        Not used for the sweeps (they set k from the contact time); the stiffness [N/m] of
        the animated scene (default: the one giving 100 ms).
    animation_after : float or None
        Seconds after separation to simulate for the animation (None: no animation run).
    settings : sim.CompliantSettings, optional
        Numerics of every run.
    sweeps : bool
        Sweep the parameters; False: only the typical values (the summary of
        ``pim compare``).
    """

    start = time.perf_counter()
    eps, beta, _ = coefficients(case, eps, beta)
    if not 0.0 <= eps <= 1.0:
        raise ValueError(f"eps must be in [0, 1], got {eps}")
    settings = replace(settings or sim.CompliantSettings(), record=False, duration=0.0)
    k_nn = build_problem(case, eps, sim.DEFAULT_STIFFNESS).k_nn
    mu0 = abs(float(np.asarray(pim.solve(case, eps, 1.0).mu0)))

    def k_for(ms: float) -> float:
        return float(stiffness_for_duration(ms / 1e3, k_nn, eps))

    k100 = k_for(1e3 * TYPICAL["duration"])
    k_short = k_for(1e3 * FRICTION_SCENE_DURATION)
    jobs = []
    has_outline = (case.vehicle1.length is not None and
                   (case.vehicle2.length is not None or bool(case.vehicle2.fixed)))
    for key, (_, _, _, values) in ASSUMPTIONS.items():
        typical = {"instantaneous": 1e3 * TYPICAL["duration"], "one_point": 1e3 *
                   TYPICAL["duration"], "no_external_forces": TYPICAL["tyre_friction"],
                   "restitution_friction": TYPICAL["friction"]}[key]
        for value in sorted(set(values) | {typical}) if sweeps else [typical]:
            if key in ("instantaneous", "one_point"):
                if key == "one_point" and not has_outline:
                    continue
                geometry = "outline" if key == "one_point" else "point"
                jobs.append((case, key, value, eps, 0.0, k_for(value), settings,
                             dict(geometry=geometry)))
            elif key == "no_external_forces":
                jobs.append((case, key, value, eps, 0.0, k100, settings,
                             dict(tyre_friction=value)))
            else:
                beta_pim = min(1.0, value / mu0) if mu0 > 0 else 1.0
                jobs.append((case, key, value, eps, beta_pim, k_short, settings,
                             dict(friction=value)))
    outcomes = sweep(_job, jobs, executor=executor, progress=progress is not False,
                     desc="assumptions")
    sweeps = []
    for key, (title, parameter, unit, values) in ASSUMPTIONS.items():
        mine = [o for o in outcomes if o.key == key]
        if not mine:
            continue
        typical_value = {"instantaneous": 100.0, "one_point": 100.0,
                         "no_external_forces": TYPICAL["tyre_friction"],
                         "restitution_friction": TYPICAL["friction"]}[key]
        typical = min(mine, key=lambda o: abs(o.value - typical_value))
        swept = tuple(o for o in mine if o.value in values) or (typical,)
        sweeps.append(AssumptionSweep(key, title, parameter, unit, swept, typical))
    anim = None
    if animation_after is not None:
        geometry = "outline" if has_outline else "point"
        try:
            anim = sim.simulate_compliant(
                case, eps, stiffness or k100, geometry=geometry,
                settings=replace(settings, record=True, duration=float(animation_after)))
        except sim.SimulationError:
            anim = None
    return AssumptionStudy(case, eps, beta, k100, tuple(sweeps), time.perf_counter() - start,
                           anim)


def assumption_table(study: AssumptionStudy, name: str = "assumptions",
                     units: str = "si") -> Table:
    """PIM's errors at the typical values, the effective (epsilon, beta) and C; the fit's
    rms and C in the ``units`` system ("si" or "us"; the rest is dimensionless, deg/s or
    ms in both)."""
    (speed,), v_unit = convert([1.0], "velocity", units)
    (length,), l_unit = convert([1.0], "length", units)
    rows = []
    for s in study.sweeps:
        o = s.typical
        e = o.errors
        rows.append((s.title, f"{s.parameter} {_fmt(o.value)} {s.unit}".replace(" -", ""),
                     e["delta_v1"], e["delta_v2"], e["speed1"], e["speed2"], e["yaw1"],
                     e["yaw2"], o.yaw_error_deg[0], o.yaw_error_deg[1], o.eps_eff, o.beta_eff,
                     o.fit_rms * speed, float(o.point_eff[0]) * length,
                     float(o.point_eff[1]) * length, o.point_distance * length,
                     1e3 * o.contact_duration, o.stick_fraction, o.slip_reversed,
                     o.energy_loss, o.pim_energy_loss, o.failure or ""))
    columns = ("assumption", "at", "err |dV1| [-]", "err |dV2| [-]", "err speed1 [-]",
               "err speed2 [-]", "err yaw1 [-]", "err yaw2 [-]", "err yaw1 [deg/s]",
               "err yaw2 [deg/s]", "eps_eff [-]", "beta_eff [-]", f"fit rms [{v_unit}]",
               f"C_eff x [{l_unit}]", f"C_eff y [{l_unit}]", f"|C_eff - C| [{l_unit}]",
               "contact [ms]", "stick fraction [-]", "slip reversed", "energy loss sim [-]",
               "energy loss PIM [-]", "failure")
    fmts = {c: fmt_error for c in columns if c.startswith("err ") and "deg" not in c}
    return Table(name, "PIM's error at typical values, effective coefficients and C",
                 columns, tuple(rows), fmts)


def sweep_table(study: AssumptionStudy, name: str = "assumption_sweeps") -> Table:
    """Every swept scene."""
    rows = []
    for s in study.sweeps:
        for o in s.outcomes:
            rows.append((s.key, o.value, *(o.errors[n] for n in ERROR_NAMES), o.eps_eff,
                         o.beta_eff, 1e3 * o.contact_duration, o.stick_fraction,
                         o.slip_reversed, o.failure or ""))
    columns = ("assumption", "value", *(f"err {n} [-]" for n in ERROR_NAMES), "eps_eff [-]",
               "beta_eff [-]", "contact [ms]", "stick fraction [-]", "slip reversed",
               "failure")
    return Table(name, "Every scene of the assumption sweeps", columns, tuple(rows),
                 {c: fmt_error for c in columns if c.startswith("err ")})


def plot_assumption(sweep_: AssumptionSweep):
    """PIM's error in delta-V, speed and yaw rate against the swept parameter (a Figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 3.4), layout="constrained")
    axes = fig.subplots(1, 3, sharex=True)
    x = sweep_.values
    for ax, (label, names) in zip(axes, (("|delta-V|", ("delta_v1", "delta_v2")),
                                         ("post-impact speed", ("speed1", "speed2")),
                                         ("yaw rate (x k / |dV|)", ("yaw1", "yaw2"))),
                                  strict=True):
        for n, style in zip(names, ("o-", "s--"), strict=True):
            y = sweep_.error(n)
            if np.isfinite(y).any():
                ax.plot(x, 100 * y, style, label=f"vehicle {n[-1]}")
        ax.axhline(100 * HOLDS, color="0.6", lw=0.8, ls=":")
        ax.set_title(f"PIM's error in {label}", fontsize=10)
        ax.set_xlabel(f"{sweep_.parameter} [{sweep_.unit}]")
        ax.set_ylabel("error [%]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(sweep_.title, fontsize=11)
    return fig


def plot_overview(study: AssumptionStudy):
    """The largest of PIM's six errors against each assumption's parameter (a Figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 6.5), layout="constrained")
    axes = fig.subplots(2, 2).ravel()
    for ax, s in zip(axes, study.sweeps, strict=False):
        for names, label in ((("delta_v1", "delta_v2"), "|delta-V|"),
                             (("speed1", "speed2"), "speed"), (("yaw1", "yaw2"), "yaw rate")):
            y = np.nanmax(np.stack([s.error(n) for n in names]), axis=0) \
                if any(np.isfinite(s.error(n)).any() for n in names) else None
            if y is not None:
                ax.plot(s.values, 100 * y, "o-", ms=3, label=label)
        ax.axhline(100 * HOLDS, color="0.5", lw=0.8, ls=":", label="5 %")
        ax.set_title(s.title, fontsize=9)
        ax.set_xlabel(f"{s.parameter} [{s.unit}]")
        ax.set_ylabel("PIM's error, worse vehicle [%]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes[len(study.sweeps):]:
        ax.set_visible(False)
    fig.suptitle(f"{study.case.name or 'case'}: PIM against the finite-duration crush scene "
                 f"(epsilon = {study.eps:.3g})", fontsize=11)
    return fig


def write_assumptions(study: AssumptionStudy, out_dir, *, animation: bool = True,
                      progress: bool | None = None, command: str = "") -> list[Path]:
    """Write assumptions.md, the tables (CSV), plots (PNG) and the MP4 to ``out_dir``."""

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = []
    table, every = assumption_table(study), sweep_table(study)
    files += [table.write_csv(out), every.write_csv(out)]
    files.append(save_figure(plot_overview(study), out / "assumptions.png"))
    for s in study.sweeps:
        files.append(save_figure(plot_assumption(s), out / f"assumption-{s.key}.png"))
    info = None
    if animation and study.animation_result is not None:
        r = study.animation_result
        ghost = pim.solve(study.case, study.eps, 0.0)
        renderer = build_renderer(
            study.case, study.eps, 0.0, result=ghost, simulated=r,
            after=max(0.1, float(r.trajectory.time[-1]) - 0.05),
            title=f"{study.case.name or 'case'}: finite-duration crush ({r.geometry}, "
                  f"{1e3 * r.contact_duration:.0f} ms), PIM ghost eps = {study.eps:.3g}, "
                  f"beta = 0")
        info = write_animation(renderer, out / "assumptions.mp4", progress=progress)
        files.append(info.path)
    files.append(write_text(out / "assumptions.html",
                            assumptions_html(study, table, out, info, command)))
    files.append(write_text(out / "assumptions.md",
                            assumptions_markdown(study, table, info, command)))
    return files


def assumptions_html(study: AssumptionStudy, table: Table, out_dir, info=None,
                     command: str = "") -> str:
    """The study as one self-contained HTML page: the verdicts, the table at typical values
    split into parts one screen wide, the plots and the animation inline (read from
    ``out_dir``, where :func:`write_assumptions` wrote them)."""
    out = Path(out_dir)
    parts = assumption_tables(table)
    sections = [h.section("Verdicts", [h.bullets(study.verdicts()), h.paragraph(
        f"epsilon = {study.eps:.4g} is the crush hysteresis' restitution; the stiffness is set "
        f"from the contact time (k = {study.stiffness_typical:.3g} N/m for 100 ms). Errors are "
        f"relative to the simulated |delta-V| of each vehicle.")], id="verdicts", cls="keep"),
        h.section("At typical values", [*parts, h.paragraph(
            "eps_eff, beta_eff: what `pim fit` needs to reproduce the simulated motion; C_eff: "
            "the impulse centroid. Every scene: `assumption_sweeps.csv`.")], id="typical"),
        h.section("Sweeps", h.figure(out / "assumptions.png", alt="overview") + '<div class="'
                  'grid">' + "".join(h.figure(out / f"assumption-{s.key}.png", alt=s.key)
                                     for s in study.sweeps) + "</div>", id="sweeps")]
    if info is not None:
        mp4 = out / "assumptions.mp4"
        sections.append(h.section("Animation", h.video(
            mp4, frames=info.frames, fps=info.fps, size=info.size,
            still=h.still_frame(mp4, 0.5), caption="The finite-duration scene (filled) with "
            "PIM's answer as a dashed ghost: `assumptions.mp4`.")
            + ("" if info.secondary_impact is None else h.paragraph(
                f"**Warning:** {info.secondary_impact.message()}.")), id="animation"))
    return h.page(f"{study.case.name or 'case'}: which of PIM's assumptions hold", sections,
                  subtitle=(f"Regenerate with `{command}`. " if command else "")
                  + "The same as text: `assumptions.md`.",
                  contents=[("verdicts", "Verdicts"), ("typical", "At typical values"),
                            ("sweeps", "Sweeps"), ("animation", "Animation")][:len(sections)],
                  generator="pim assumptions")


def assumptions_markdown(study: AssumptionStudy, table: Table, info=None,
                         command: str = "") -> str:
    """The study as Markdown."""
    name = study.case.name or "case"
    lines = [f"# {name}: which of PIM's assumptions hold", ""]
    if command:
        lines += [f"Regenerate with `{command}`.", ""]
    lines += [f"Each scene of the finite-duration crush model (docs/contact-model.md) relaxes "
              f"one assumption of PIM; epsilon = {study.eps:.4g} is the crush hysteresis' "
              f"restitution, the stiffness is set from the contact time "
              f"(k = {study.stiffness_typical:.3g} N/m for 100 ms). Errors are relative to "
              f"the simulated |delta-V| of each vehicle (comparisons/assumptions.py).", ""]
    lines += ["## Verdicts", ""] + [f"- {v}" for v in study.verdicts()] + [""]
    lines += ["## At typical values", "", table.to_markdown(), "",
              "eps_eff, beta_eff: what `pim fit` (velocities and yaw rates) needs to reproduce "
              "the simulated motion; C_eff: the impulse centroid.", ""]
    lines += ["![assumptions](assumptions.png)", ""]
    for s in study.sweeps:
        lines += [f"![{s.key}](assumption-{s.key}.png)", ""]
    if info is not None:
        lines += [f"[assumptions.mp4](assumptions.mp4): the finite-duration scene (filled) "
                  f"with PIM's answer as a dashed ghost ({info.frames} frames)."]
        if info.secondary_impact is not None:
            lines += ["", f"**Warning:** {info.secondary_impact.message()}."]
        lines += [""]
    lines += [f"Every scene: [assumption_sweeps.csv](assumption_sweeps.csv). Run time "
              f"{study.seconds:.1f} s.", ""]
    return "\n".join(lines)
