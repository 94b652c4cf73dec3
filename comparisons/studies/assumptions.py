"""``pim assumptions``: PIM's assumptions relaxed one at a time, on a ladder of scenes.

Each scene of the ladder differs from the one below it in exactly one assumption of PIM
(:class:`Scene` is the typed configuration; :func:`changed_assumptions` says which
assumptions two scenes differ in, and a test checks every rung):

======  ==========================================  ===========================================
rung    assumption relaxed (against the rung below)  scene
======  ==========================================  ===========================================
pim     --                                          ``pim.solve`` at (epsilon, beta_pim)
law     Newton's restitution, mu = beta mu0         crush hysteresis (epsilon) and PIM's
                                                    tangential law (frictionless for beta 0, a
                                                    sticking plastic friction spring for
                                                    beta 1), point at C, nearly instantaneous
duration  instantaneous impulse                     the same at contact time T
point   PIM's impact configuration (C, Gamma)       one point where the outlines' impulse
                                                    acts: bodies where the outlines first
                                                    touch, C at their impulse centroid, Gamma
                                                    along their mean contact normal (same T)
outline concentrated contact                        the outlines crush into each other (same T)
tyres   no external forces                          tyre friction during the contact (same T)
friction  PIM's tangential law                      Coulomb friction mu_c between the vehicles
                                                    with tangential recovery r (same T)
======  ==========================================  ===========================================

beta_pim is 0 or 1, whichever is nearer the case's beta: PIM with that beta is what the
"law" rung emulates. "Nearly instantaneous" is the stiff limit, a contact of
:data:`STIFF_LIMIT` (the scene converges to the instantaneous one at first order in the
contact time, docs/contact-model.md). Every scene at contact time T has the stiffness that
gives T for its own contact point: k = (pi (1 + eps) / (2 T))^2 / K_nn; the outline scenes
take K_nn at the impulse centroid of an outline probe at the same T. If the outline scene
fails (e.g. a pole crossed by the car's outline) the ladder goes on at C without the outline
rungs and says why. :attr:`AssumptionStudy.sweeps` keeps the former per-assumption view
(PIM's per-vehicle errors, :func:`outcome_errors`) for ``comparisons.regression.sections``.

The measure is the project's one error, :func:`sim.error_measure.impact_error`: the largest
difference in the velocity changes (yaw rates times the radius of gyration), relative to the
largest change of the reference. The *marginal* effect of an assumption is that error
between its rung and the rung below at the same contact time; the *cumulative* one is the
error of PIM against the rung. The study repeats the ladder at several contact times
(:data:`DURATIONS`), the tyre rung at several tyre frictions (the tyre effect as a function
of the contact time: never tyres plus duration blamed on tyres) and the friction rung at
several mu_c and tangential recoveries r (0: plastic; eps^2: the default; 1: elastic).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, fields, replace

import numpy as np

import pim
import sim
from pim.io.units import convert
from pim.model.numbers import InputError
from sim.compliant_setup import build_problem, rotate
from sim.contact_law import stiffness_for_duration, tangential_recovery_default
from sim.error_measure import ERROR_DEFINITION, impact_error
from sim.sweep import sweep

from comparisons.studies.coefficients import coefficients
from comparisons.report.tables import Table, fmt_error

__all__ = ["Scene", "SceneRun", "Rung", "Ladder", "AssumptionStudy", "RUNGS", "TYPICAL",
           "DURATIONS", "STIFF_LIMIT", "HOLDS", "ROUGHLY", "ASSUMPTION_FIELDS",
           "changed_assumptions", "ladder_scenes", "run_assumptions", "assumption_table",
           "sweep_table", "plot_overview", "outcome_errors", "LEGACY_KEYS", "legacy_sweeps", "ladder_intro"]

#: Marginal effect below which an assumption is negligible, and below which it is moderate.
HOLDS, ROUGHLY = 0.05, 0.15
#: Typical values of the physical parameters, written once: contact time [s], tyre friction
#: [-], friction between the vehicles [-]. The verdicts are stated at these.
TYPICAL = {"duration": 0.1, "tyre_friction": 0.7, "friction": 0.5}
#: Contact times of the ladder [s] (the typical one included).
DURATIONS = (0.01, 0.025, 0.05, 0.1, 0.2)
#: The nearly instantaneous contact of the "law" rung [s].
STIFF_LIMIT = 0.002
#: PIM's sticking (beta = 1) as a contact law: a friction coefficient no impact exhausts,
#: a friction spring this many times stiffer than the crush, and no tangential rebound.
STICKING = {"friction": 10.0, "stiffness_ratio": 1000.0, "recovery": 0.0}
#: Tyre frictions [-] of the tyre-effect curves, and mu_c [-] of the friction map.
TYRE_FRICTIONS = (0.35, 0.7, 1.0)
FRICTIONS = (0.2, 0.5, 1.0)


@dataclass(frozen=True)
class Scene:
    """Which of PIM's assumptions a scene keeps (the typed configuration of one rung).

    Attributes
    ----------
    law : {"pim", "crush"}
        Newton's restitution and mu = beta mu0 (PIM itself), or the crush hysteresis with
        the same epsilon and a tangential law (``friction``).
    duration : float or None
        Contact time [s]; None: instantaneous (PIM; the crush law at :data:`STIFF_LIMIT`).
    point : {"C", "centroid"}
        Where the point contact acts: the case's C and normal Gamma, or the impulse centroid
        and the mean contact normal of the outlines (the line the outlines' impulse acts on).
    distributed : bool
        The outlines crush into each other (the force acts where they overlap).
    tyre_friction : float
        Tyre/ground friction during the contact [-] (0: no external forces).
    friction : {"pim", "coulomb"}
        PIM's tangential law (frictionless for beta 0, sticking for beta 1), or Coulomb
        friction ``mu_c`` with tangential recovery ``recovery``.
    mu_c : float
        Friction between the vehicles [-] (Coulomb only).
    recovery : float or None
        Tangential recovery r [-] (Coulomb only; None: eps^2).
    """

    law: str = "pim"
    duration: float | None = None
    point: str = "C"
    distributed: bool = False
    tyre_friction: float = 0.0
    friction: str = "pim"
    mu_c: float = 0.0
    recovery: float | None = None


#: Assumption -> the fields of :class:`Scene` that say whether a scene keeps it.
ASSUMPTION_FIELDS = {
    "law": ("law",),
    "duration": ("duration",),
    "point": ("point",),
    "outline": ("distributed",),
    "tyres": ("tyre_friction",),
    "friction": ("friction", "mu_c", "recovery"),
}
assert {f for v in ASSUMPTION_FIELDS.values() for f in v} == {f.name for f in fields(Scene)}

#: Rung key -> (the assumption it relaxes, in a user's words).
RUNGS = {
    "pim": "PIM",
    "law": "Newton's restitution and mu = beta mu0 (replaced by the crush hysteresis)",
    "duration": "instantaneous impulse (finite contact time)",
    "point": "impulse at C along Gamma (moved to the line the outlines' impulse acts on)",
    "outline": "one contact point (the outlines crush: a distributed contact)",
    "tyres": "no external forces (tyre friction during the contact)",
    "friction": "PIM's tangential law (Coulomb friction between the vehicles)",
}


def changed_assumptions(scene: Scene, baseline: Scene) -> set[str]:
    """The assumptions (keys of :data:`ASSUMPTION_FIELDS`) ``scene`` differs in."""
    return {name for name, names in ASSUMPTION_FIELDS.items()
            if any(getattr(scene, f) != getattr(baseline, f) for f in names)}


def ladder_scenes(duration: float, has_outline: bool, tyre_friction: float | None = None,
                  mu_c: float | None = None, recovery: float | None = None) -> dict:
    """Rung key -> :class:`Scene` of the ladder at contact time ``duration`` [s], each
    built from the one below by changing one assumption."""
    tyre = TYPICAL["tyre_friction"] if tyre_friction is None else tyre_friction
    mu = TYPICAL["friction"] if mu_c is None else mu_c
    out = {"pim": Scene()}
    out["law"] = replace(out["pim"], law="crush")
    out["duration"] = replace(out["law"], duration=duration)
    below = out["duration"]
    if has_outline:
        out["point"] = replace(below, point="centroid")
        out["outline"] = replace(out["point"], distributed=True)
        below = out["outline"]
    out["tyres"] = replace(below, tyre_friction=tyre)
    out["friction"] = replace(out["tyres"], friction="coulomb", mu_c=mu, recovery=recovery)
    return out


@dataclass(frozen=True)
class SceneRun:
    """One simulated scene: post-impact motion (SI) and what the contact did.

    Attributes
    ----------
    scene : Scene
        The scene simulated.
    velocity1, velocity2 : numpy.ndarray
        Post-impact CG velocities of vehicles 1 and 2, shape (2,) [m/s].
    yaw_rate1, yaw_rate2 : float
        Post-impact yaw rates, CCW positive [rad/s].
    contact_duration : float
        Contact time [s].
    impact_point : numpy.ndarray
        Impulse centroid, shape (2,) [m] (global frame).
    normal : numpy.ndarray
        Mean contact (impulse) normal, unit, shape (2,) [-].
    contact_start : float
        Time of first contact [s].
    point_body1 : numpy.ndarray
        Impulse centroid relative to vehicle 1's CG in its body frame, shape (2,) [m].
    normal_body2 : numpy.ndarray
        Mean contact normal in vehicle 2's body frame, unit, shape (2,) [-].
    energy_loss : float
        Kinetic energy lost, as a share of the energy before [-].
    stick_fraction : float
        Share of the contact time the contact stuck [-].
    slip_reversed : bool
        Whether the tangential slip reversed during contact.
    tangential_recovery : float
        Share r of the stored tangential energy the contact gives back [-].
    failure : str or None
        Why the simulation failed (then the numbers are NaN); None when it ran.
    """

    scene: Scene
    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: float
    yaw_rate2: float
    contact_duration: float = math.nan
    impact_point: np.ndarray = field(default_factory=lambda: np.full(2, math.nan))
    normal: np.ndarray = field(default_factory=lambda: np.full(2, math.nan))
    contact_start: float = 0.0
    point_body1: np.ndarray = field(default_factory=lambda: np.full(2, math.nan))
    normal_body2: np.ndarray = field(default_factory=lambda: np.full(2, math.nan))
    energy_loss: float = math.nan
    stick_fraction: float = math.nan
    slip_reversed: bool = False
    tangential_recovery: float = math.nan
    failure: str | None = None

    @classmethod
    def failed(cls, scene: Scene, why: str) -> SceneRun:
        nan2 = np.full(2, math.nan)
        return cls(scene, nan2, nan2, math.nan, math.nan, failure=why)


@dataclass(frozen=True)
class Rung:
    """One rung of the ladder: the scene, its baseline and the effects measured.

    Attributes
    ----------
    key : str
        A key of :data:`RUNGS`.
    baseline : str or None
        The rung below (None for PIM).
    run : SceneRun
    marginal : float
        impact_error of this scene against the rung below [-] (same contact time).
    cumulative : float
        impact_error of PIM against this scene [-].
    eps_eff, beta_eff : float
        :func:`pim.fit` to the simulated motion (what PIM would need); NaN if not fitted.
    fit_rms : float
        RMS residual of that fit [m/s]; NaN if not fitted.
    """

    key: str
    baseline: str | None
    run: SceneRun
    marginal: float
    cumulative: float
    eps_eff: float = math.nan
    beta_eff: float = math.nan
    fit_rms: float = math.nan

    @property
    def scene(self) -> Scene:
        return self.run.scene

    @property
    def title(self) -> str:
        return RUNGS[self.key]


@dataclass(frozen=True)
class Ladder:
    """The rungs at one contact time, bottom (PIM) first.

    Attributes
    ----------
    duration : float
        Contact time of the ladder's scenes [s].
    rungs : tuple of Rung
        The rungs, bottom (PIM) first.
    """

    duration: float
    rungs: tuple

    def rung(self, key: str) -> Rung | None:
        return next((r for r in self.rungs if r.key == key), None)


@dataclass(frozen=True, eq=False)
class AssumptionStudy:
    """Outcome of :func:`run_assumptions`.

    Attributes
    ----------
    case : pim.Case
    eps, beta : float
        The case's coefficients (beta as the case uses it).
    beta_pim : float
        0 or 1: the beta PIM is evaluated at and the "law" rung emulates.
    ladders : tuple of Ladder
        One per contact time, shortest first.
    tyre_curves : dict
        Tyre friction -> array of the tyre rung's marginal effect at each of ``durations``.
    recovery_map : tuple of (mu_c, r, marginal, cumulative)
        The friction rung at the typical contact time.
    centroid_distance : float
        |impulse centroid - C| [m] of the outlines at the typical contact time.
    normal_turn : float
        Angle [deg] from the case's normal Gamma to the outlines' mean contact normal there.
    stiffness_typical : float
        Contact stiffness k giving the typical contact time [N/m].
    seconds : float
        Wall time of the study [s].
    animation_result : sim.CompliantResult or None
        The recorded run for the animation (None when not asked for or the run failed).
    outline_note : str
        Why the outline rungs are missing ("" when they ran).
    """

    case: pim.Case
    eps: float
    beta: float
    beta_pim: float
    ladders: tuple
    tyre_curves: dict
    recovery_map: tuple
    centroid_distance: float
    normal_turn: float
    stiffness_typical: float
    seconds: float
    animation_result: object = field(default=None, repr=False)
    outline_note: str = ""

    @property
    def durations(self) -> np.ndarray:
        return np.array([ladder.duration for ladder in self.ladders])

    @property
    def typical(self) -> Ladder:
        """The ladder at :data:`TYPICAL` contact time."""
        return min(self.ladders, key=lambda lad: abs(lad.duration - TYPICAL["duration"]))

    def effect(self, key: str, kind: str = "marginal") -> np.ndarray:
        """The marginal or cumulative effect of rung ``key`` at each contact time [-]."""
        return np.array([getattr(lad.rung(key), kind) if lad.rung(key) else math.nan
                         for lad in self.ladders])

    def verdicts(self) -> list[str]:
        """One sentence per relaxed assumption, naming it and the effect measured."""
        return verdicts(self)

    def intro(self, command: str) -> str:
        """The sentence a report puts before the verdicts (:func:`ladder_intro`)."""
        return ladder_intro(command)

    @property
    def sweeps(self) -> tuple:
        """The typical ladder in the shape of the former study, for callers written for it
        (``comparisons.regression.sections``): :data:`LEGACY_KEYS` rung -> ``LegacySweep``."""
        return legacy_sweeps(self)


#: The former study's assumption keys of the rungs that relax the same assumption.
LEGACY_KEYS = {"duration": "instantaneous", "tyres": "no_external_forces",
               "outline": "one_point", "friction": "restitution_friction"}


@dataclass(frozen=True)
class LegacyOutcome:
    """PIM's per-vehicle errors against one rung's scene (:func:`outcome_errors`) and the
    rung's effective coefficients, named as the former study named them.

    Attributes
    ----------
    value : float
        The swept value: the contact time of the typical ladder [s].
    errors : dict
        Per-vehicle relative errors of PIM (:func:`outcome_errors`) [-].
    eps_eff, beta_eff : float
        Coefficients :func:`pim.fit` finds for the simulated motion [-].
    fit_rms : float
        RMS residual of that fit [m/s].
    energy_loss : float
        Simulated kinetic energy lost, as a share of the energy before [-].
    pim_energy_loss : float
        PIM's kinetic energy lost, as a share of the energy before [-].
    stick_fraction : float
        Share of the contact time the contact stuck [-].
    point_distance : float
        Distance from the impulse centroid to the case's impact point C [m].
    failure : str or None
        Why the simulation failed; None when it ran.
    """

    value: float
    errors: dict
    eps_eff: float
    beta_eff: float
    fit_rms: float
    energy_loss: float
    pim_energy_loss: float
    stick_fraction: float
    point_distance: float
    failure: str | None


@dataclass(frozen=True)
class LegacySweep:
    """One rung under the former study's name.

    Attributes
    ----------
    key : str
        The former study's name of the rung.
    typical : LegacyOutcome
        Its outcome at the typical contact time.
    """

    key: str
    typical: LegacyOutcome


def legacy_sweeps(study: AssumptionStudy) -> tuple:
    """:attr:`AssumptionStudy.sweeps` (see there)."""
    case = study.case
    result = pim.solve(case, study.eps, study.beta_pim)
    e0 = float(np.asarray(result.kinetic_energy_before))
    pim_loss = float(np.asarray(result.energy_loss)) / e0 if e0 > 0 else math.nan
    point = np.asarray(case.impact.point, float).reshape(2)
    out = []
    for rung in study.typical.rungs:
        if rung.key not in LEGACY_KEYS:
            continue
        run = rung.run
        errors, _ = outcome_errors(case, result, run.velocity1, run.velocity2, run.yaw_rate1,
                                   run.yaw_rate2)
        out.append(LegacySweep(LEGACY_KEYS[rung.key], LegacyOutcome(
            study.typical.duration, errors, rung.eps_eff, rung.beta_eff, rung.fit_rms,
            run.energy_loss, pim_loss, run.stick_fraction,
            float(np.hypot(*(run.impact_point - point))), run.failure)))
    return tuple(out)


def outcome_errors(case: pim.Case, result: pim.Result, velocity1, velocity2, yaw_rate1,
                   yaw_rate2) -> tuple[dict, tuple]:
    """Per-vehicle relative errors of PIM against a simulated outcome (benchmarks only; the
    study uses :func:`sim.error_measure.impact_error`) and the yaw-rate errors [deg/s]."""
    out, yaw_deg = {}, []
    sims = ((case.vehicle1, velocity1, yaw_rate1, result.velocity1, result.yaw_rate1),
            (case.vehicle2, velocity2, yaw_rate2, result.velocity2, result.yaw_rate2))
    for i, (vehicle, v_sim, w_sim, v_pim, w_pim) in enumerate(sims, start=1):
        if bool(vehicle.fixed):
            out.update({f"delta_v{i}": math.nan, f"speed{i}": math.nan, f"yaw{i}": math.nan})
            yaw_deg.append(math.nan)
            continue
        v0 = np.asarray(vehicle.velocity, float).reshape(2)
        v_sim, v_pim = np.asarray(v_sim, float), np.asarray(v_pim, float).reshape(2)
        dv_sim = max(float(np.hypot(*(v_sim - v0))), 1e-12)
        out[f"delta_v{i}"] = abs(float(np.hypot(*(v_pim - v0))) - dv_sim) / dv_sim
        out[f"speed{i}"] = abs(float(np.hypot(*v_pim)) - float(np.hypot(*v_sim))) / dv_sim
        dw = abs(float(np.asarray(w_pim)) - float(w_sim))
        out[f"yaw{i}"] = float(np.sqrt(vehicle.yaw_inertia / vehicle.mass)) * dw / dv_sim
        yaw_deg.append(math.degrees(dw))
    names = ("delta_v1", "delta_v2", "speed1", "speed2", "yaw1", "yaw2")
    return {k: out[k] for k in names}, tuple(yaw_deg)


# -- simulating one scene ---------------------------------------------------------------------

def _contact_case(case: pim.Case, scene: Scene, probe: SceneRun | None) -> pim.Case:
    """The case placed where the outlines of ``probe`` touch, if the scene says so.

    The bodies are moved along their free pre-impact paths to the instant the outlines first
    touch (``probe.contact_start``), C to the outlines' impulse centroid (fixed in vehicle
    1's frame) and Gamma to their mean contact normal (fixed in vehicle 2's frame): the
    point contact then acts on the line the distributed contact's impulse acts on. The
    outline scenes take the stiffness for that point.
    """
    if scene.point == "C":
        return case
    t = probe.contact_start

    def moved(vehicle):
        if bool(vehicle.fixed):
            return vehicle
        return replace(vehicle, cg=np.asarray(vehicle.cg, float) + np.asarray(
            vehicle.velocity, float) * t, heading=float(vehicle.heading)
            + float(vehicle.yaw_rate) * t)

    v1, v2 = moved(case.vehicle1), moved(case.vehicle2)
    point = np.asarray(v1.cg, float) + rotate(probe.point_body1, float(v1.heading))
    n = rotate(probe.normal_body2, float(v2.heading))
    return replace(case, vehicle1=v1, vehicle2=v2, impact=replace(
        case.impact, point=point, normal_angle=math.atan2(n[1], n[0])))


def _simulate(job: tuple) -> SceneRun:
    """Simulate one scene (module level, so that it runs on a process pool)."""
    case, eps, beta_pim, scene, line, settings = job
    if scene.point == "centroid" and (line is None or line.failure is not None
                                      or not np.isfinite(line.point_body1).all()):
        why = "no outline probe" if line is None else line.failure or "no impulse centroid"
        return SceneRun.failed(scene, f"the outline probe failed ({why})")
    try:
        where = _contact_case(case, scene, line)
        k_nn = build_problem(where, eps, sim.DEFAULT_STIFFNESS).k_nn
        duration = STIFF_LIMIT if scene.duration is None else scene.duration
        k = float(stiffness_for_duration(duration, k_nn, eps))
        mu = scene.mu_c
        if scene.friction == "coulomb":
            settings = replace(settings, tangential_recovery=scene.recovery)
        elif beta_pim > 0:
            mu = STICKING["friction"]
            settings = replace(settings, tangential_recovery=STICKING["recovery"],
                               tangential_stiffness=STICKING["stiffness_ratio"] * k)
        r = sim.simulate_compliant(case if scene.distributed else where, eps, k, friction=mu,
                                   geometry="outline" if scene.distributed else "point",
                                   tyre_friction=scene.tyre_friction, settings=settings)
    except sim.SimulationError as exc:
        return SceneRun.failed(scene, f"{exc.kind}: {exc}")
    e0 = r.energy_before
    return SceneRun(scene, r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2,
                    r.contact_duration, np.asarray(r.impact_point, float),
                    np.asarray(r.impulse_normal, float), r.contact_start,
                    np.asarray(r.impact_point_body1, float),
                    np.asarray(r.impulse_normal_body2, float),
                    r.energy_loss / e0 if e0 > 0 else math.nan, r.stick_fraction,
                    bool(r.slip_reversed), r.tangential_recovery)


def _pim_run(case: pim.Case, result: pim.Result) -> SceneRun:
    return SceneRun(Scene(), np.asarray(result.velocity1, float).reshape(2),
                    np.asarray(result.velocity2, float).reshape(2),
                    float(np.asarray(result.yaw_rate1)), float(np.asarray(result.yaw_rate2)),
                    0.0, np.asarray(case.impact.point, float).reshape(2))


def _error(case: pim.Case, reference: SceneRun, run: SceneRun) -> float:
    """impact_error of ``run`` against ``reference`` (NaN if either failed)."""
    if reference.failure is not None or run.failure is not None:
        return math.nan
    return float(impact_error(case, reference, run.velocity1, run.velocity2, run.yaw_rate1,
                              run.yaw_rate2))


def _fit(case: pim.Case, run: SceneRun) -> tuple[float, float, float]:
    """(eps_eff, beta_eff, rms [m/s]): what PIM needs to reproduce the simulated motion."""
    if run.failure is not None:
        return math.nan, math.nan, math.nan
    fixed2 = bool(case.vehicle2.fixed)
    measured = pim.Measured(run.velocity1, None if fixed2 else run.velocity2, run.yaw_rate1,
                            None if fixed2 else run.yaw_rate2)
    try:
        fitted = pim.fit(replace(case, measured=measured), include_yaw=True)
    except ValueError:
        return math.nan, math.nan, math.nan
    return float(fitted.eps), float(fitted.beta), float(fitted.rms)


# -- the study ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Plan:
    """What the study simulates: the contact times and the variants of the top rungs."""

    durations: tuple
    tyre_frictions: tuple
    frictions: tuple
    recoveries: tuple


def _plan(eps: float, sweeps: bool) -> _Plan:
    r_default = float(tangential_recovery_default(eps))
    recoveries = tuple(sorted({0.0, r_default, 1.0}))
    if not sweeps:
        return _Plan((TYPICAL["duration"],), (TYPICAL["tyre_friction"],),
                     (TYPICAL["friction"],), recoveries)
    return _Plan(tuple(sorted(set(DURATIONS) | {TYPICAL["duration"]})),
                 tuple(sorted(set(TYRE_FRICTIONS) | {TYPICAL["tyre_friction"]})),
                 tuple(sorted(set(FRICTIONS) | {TYPICAL["friction"]})), recoveries)


def _variants(plan: _Plan, duration: float, has_outline: bool) -> list[Scene]:
    """Every scene simulated at ``duration``: the ladder and the top rungs' variants."""
    scenes = [s for k, s in ladder_scenes(duration, has_outline).items() if k != "pim"]
    tyres = ladder_scenes(duration, has_outline)["tyres"]
    scenes += [replace(tyres, tyre_friction=mu) for mu in plan.tyre_frictions]
    if duration == TYPICAL["duration"]:
        scenes += [replace(tyres, friction="coulomb", mu_c=mu, recovery=r)
                   for mu in plan.frictions for r in plan.recoveries]
    return list(dict.fromkeys(scenes))          # unique, in order


def _probes(case, eps, beta_pim, plan, settings, executor, progress):
    """The outline scene per contact time (its impulse centroid, normal and first-touch
    instant place the "point" rung): ({duration: run}, None), or (None, why) if one failed."""
    jobs = [(case, eps, beta_pim, Scene(law="crush", duration=d, distributed=True), None,
             settings) for d in plan.durations]
    runs = sweep(_simulate, jobs, executor=executor, progress=progress, desc="outline probes")
    failed = next((r.failure for r in runs if r.failure is not None), None)
    return (None, failed) if failed else (dict(zip(plan.durations, runs, strict=True)), None)


def _simulate_all(case, eps, beta_pim, plan, has_outline, probes, settings, executor,
                  progress) -> dict:
    """Every scene of the study: {scene: run}."""
    scenes = list(dict.fromkeys(s for d in plan.durations
                                for s in _variants(plan, d, has_outline)))
    jobs = [(case, eps, beta_pim, s, probes.get(s.duration), settings) for s in scenes]
    runs = sweep(_simulate, jobs, executor=executor, progress=progress, desc="assumptions")
    return dict(zip(scenes, runs, strict=True))


def _ladder(case, duration, scenes: dict, runs: dict, pim_run: SceneRun, fit: bool) -> Ladder:
    """The rungs at ``duration``: each run against the rung below and against PIM."""
    rungs, below = [], None
    for key, scene in scenes.items():
        run = pim_run if key == "pim" else runs[scene]
        marginal = 0.0 if below is None else _error(case, below.run, run)
        fitted = _fit(case, run) if fit and key != "pim" else (math.nan,) * 3
        rung = Rung(key, None if below is None else below.key, run, marginal,
                    _error(case, pim_run, run), *fitted)
        rungs.append(rung)
        below = rung
    return Ladder(duration, tuple(rungs))


def _extras(case, plan, runs, has_outline, pim_run):
    """The tyre effect over the contact times, and the friction rung over (mu_c, r)."""
    curves = {}
    for mu in plan.tyre_frictions:
        values = []
        for d in plan.durations:
            scenes = ladder_scenes(d, has_outline, tyre_friction=mu)
            below = runs[scenes["outline" if has_outline else "duration"]]
            values.append(_error(case, below, runs[scenes["tyres"]]))
        curves[mu] = np.array(values)
    d = TYPICAL["duration"]
    tyres = runs[ladder_scenes(d, has_outline)["tyres"]]
    recovery_map = []
    for mu in plan.frictions:
        for r in plan.recoveries:
            run = runs[ladder_scenes(d, has_outline, mu_c=mu, recovery=r)["friction"]]
            recovery_map.append((mu, r, _error(case, tyres, run), _error(case, pim_run, run)))
    return curves, tuple(recovery_map)


def run_assumptions(case: pim.Case, eps: float | None = None, beta: float | None = None, *,
                    executor=None, progress: bool | None = None, stiffness: float | None = None,
                    animation_after: float | None = 2.0, settings=None,
                    sweeps: bool = True) -> AssumptionStudy:
    """PIM's assumptions relaxed one at a time on the ladder of scenes (module notes).

    Parameters
    ----------
    case : pim.Case
        A single case.
    eps : float, optional
        Physical restitution [-] of the crush (default: the fit to the case's measured
        motion, else ``case.impact.restitution``).
    beta : float, optional
        PIM's beta as the case uses it; PIM is compared at 0 or 1, whichever is nearer.
    executor : None, "process", "serial", dask Client or Executor
        Where the scenes run (:func:`sim.sweep.sweep`).
    progress : bool or None
        Progress bars.
    stiffness : float, optional
        Stiffness [N/m] of the animated scene (default: the one giving the typical time).
    animation_after : float or None
        Seconds after separation to simulate for the animation (None: no animation run).
    settings : sim.CompliantSettings, optional
        Numerics of every run.
    sweeps : bool
        All contact times and variants; False: the ladder at the typical values only (and
        the three tangential recoveries), the summary of ``pim compare``.
    """
    start = time.perf_counter()
    eps, beta, _ = coefficients(case, eps, beta)
    if not 0.0 <= eps <= 1.0:
        raise InputError(f"eps must be in [0, 1], got {eps}")
    beta_pim = 0.0 if beta < 0.5 else 1.0
    settings = replace(settings or sim.CompliantSettings(), record=False, duration=0.0)
    has_outline = (case.vehicle1.length is not None and
                   (case.vehicle2.length is not None or bool(case.vehicle2.fixed)))
    plan = _plan(eps, sweeps)
    probes, note = {}, "the case gives no outlines: vehicle length and width"
    if has_outline:
        found, failure = _probes(case, eps, beta_pim, plan, settings, executor,
                                 progress is not False)
        has_outline, probes = found is not None, found or {}
        note = f"the outline scene failed: {failure}"
    runs = _simulate_all(case, eps, beta_pim, plan, has_outline, probes, settings, executor,
                         progress is not False)
    pim_run = _pim_run(case, pim.solve(case, eps, beta_pim))
    ladders = tuple(_ladder(case, d, ladder_scenes(d, has_outline), runs, pim_run,
                            fit=d == TYPICAL["duration"]) for d in plan.durations)
    curves, recovery_map = _extras(case, plan, runs, has_outline, pim_run)
    k_nn = build_problem(case, eps, sim.DEFAULT_STIFFNESS).k_nn
    k_typical = float(stiffness_for_duration(TYPICAL["duration"], k_nn, eps))
    point = np.asarray(case.impact.point, float).reshape(2)
    probe = probes.get(TYPICAL["duration"])
    distance = turn = math.nan
    if probe is not None:
        distance = float(np.hypot(*(probe.impact_point - point)))
        gamma = float(case.impact.normal_angle)
        turn = math.degrees(math.remainder(math.atan2(probe.normal[1], probe.normal[0])
                                           - gamma, math.tau))
    anim = _animation(case, eps, stiffness or k_typical, has_outline, settings,
                      animation_after)
    return AssumptionStudy(case, eps, beta, beta_pim, ladders, curves, recovery_map, distance,
                           turn, k_typical, time.perf_counter() - start, anim,
                           "" if has_outline else note)


def _animation(case, eps, k, has_outline, settings, after):
    if after is None:
        return None
    try:
        return sim.simulate_compliant(
            case, eps, k, geometry="outline" if has_outline else "point",
            settings=replace(settings, record=True, duration=float(after)))
    except sim.SimulationError:
        return None


# -- words ------------------------------------------------------------------------------------

def _pct(x: float) -> str:
    return "n/a" if not math.isfinite(x) else f"{100 * x:.1f} %"


def _size(x: float) -> str:
    if not math.isfinite(x):
        return "not assessed (a simulation failed)"
    if x < HOLDS:
        return "negligible"
    return "moderate" if x < ROUGHLY else "large"


def _tangential(study: AssumptionStudy) -> str:
    return ("no friction between the vehicles (PIM's beta = 0)" if study.beta_pim == 0 else
            "a sticking, plastic friction spring (PIM's beta = 1)")


def _over_durations(study: AssumptionStudy, key: str) -> str:
    ms = [f"{_pct(e)} at {1e3 * d:g} ms" for d, e in zip(study.durations,
                                                          study.effect(key), strict=True)]
    return f" (over the contact times: {', '.join(ms)})" if len(ms) > 1 else ""


def _recovery_words(study: AssumptionStudy) -> str:
    """How the friction effect depends on the tangential recovery r, per mu_c."""
    rs = sorted({r for _, r, _, _ in study.recovery_map})
    parts = []
    for mu in sorted({m for m, _, _, _ in study.recovery_map}):
        values = [m for m_c, _, m, _ in study.recovery_map if m_c == mu]
        spread = np.nanmax(values) - np.nanmin(values) if np.isfinite(values).any() else 0
        how = ("does not depend on r: the contact slides" if spread < 0.005 else
               "depends on r: the contact sticks part of the time")
        parts.append(f"{' / '.join(_pct(v) for v in values)} at mu_c {mu:g} ({how})")
    return (f"; with tangential recovery r = {' / '.join(f'{r:.3g}' for r in rs)} the "
            f"friction effect is {'; '.join(parts)}")


def ladder_intro(command: str) -> str:
    """The sentence a report puts before the verdicts: what the ladder is, at which typical
    values (from :data:`TYPICAL`), and the command of the whole study."""
    return (f"A ladder of crush scenes relaxes PIM's assumptions one at a time, each scene "
            f"differing from the one below in one assumption; the marginal effect is against "
            f"the scene below at the same contact time, the cumulative one is PIM's error "
            f"against the scene (typical values: {1e3 * TYPICAL['duration']:g} ms contact, "
            f"tyre friction {TYPICAL['tyre_friction']:g}, friction "
            f"{TYPICAL['friction']:g} between the vehicles); docs/contact-model.md has the "
            f"model. The study over contact times, its plots and an animation are "
            f"`{command}`.")


def verdicts(study: AssumptionStudy) -> list[str]:
    """One sentence per rung above PIM; each names the assumption it measured."""
    lad = study.typical
    ms = f"{1e3 * lad.duration:g} ms"
    length, label = convert(1.0, "length", study.case.units)
    text = {
        "law": f"Newton's restitution with mu = beta mu0, replaced by the crush hysteresis "
               f"(epsilon = {study.eps:.3g}) with {_tangential(study)} at a nearly "
               f"instantaneous {1e3 * STIFF_LIMIT:g} ms contact",
        "duration": f"The instantaneous impulse, replaced by a {ms} contact (same contact law "
                    f"at C)",
        "point": f"PIM's impact configuration (the impulse at C along Gamma), replaced by "
                 f"where the outlines' impulse acts: the bodies where the outlines first "
                 f"touch, the point at their impulse centroid "
                 f"({length * study.centroid_distance:.2f} {label} from C) along their mean "
                 f"contact normal ({study.normal_turn:+.0f} deg from Gamma), still one point "
                 f"({ms})",
        "outline": f"One contact point, replaced by the outlines crushing into each other "
                   f"(a distributed contact with the same impulse centroid, {ms})",
        "tyres": f"No external forces, replaced by tyre friction {TYPICAL['tyre_friction']:g} "
                 f"during the {ms} contact",
        "friction": f"PIM's tangential law, replaced by Coulomb friction "
                    f"{TYPICAL['friction']:g} between the vehicles with tangential recovery "
                    f"r = eps^2 = {float(tangential_recovery_default(study.eps)):.3g} ({ms})",
    }
    out = []
    for rung in lad.rungs[1:]:
        if rung.run.failure:
            out.append(f"{text[rung.key]}: not assessed ({rung.run.failure}).")
            continue
        sentence = (f"{text[rung.key]}: {_size(rung.marginal)} marginal effect, "
                    f"{_pct(rung.marginal)} against the scene below; PIM is "
                    f"{_pct(rung.cumulative)} off this scene (cumulative)")
        if rung.key in ("duration", "tyres"):
            sentence += _over_durations(study, rung.key)
        if rung.key == "friction" and study.recovery_map:
            sentence += _recovery_words(study)
        out.append(sentence + ".")
    if lad.rung("outline") is None:
        out.insert(2, f"PIM's impact configuration and one contact point: not assessed "
                      f"({study.outline_note}).")
    return out


# -- tables and plots -----------------------------------------------------------------------

def _scene_words(scene: Scene) -> str:
    if scene.law == "pim":
        return "PIM"
    parts = ["crush", "instant" if scene.duration is None else f"{1e3 * scene.duration:g} ms",
             "outline" if scene.distributed else f"point at {scene.point}"]
    if scene.tyre_friction:
        parts.append(f"tyres {scene.tyre_friction:g}")
    parts.append("PIM's tangential law" if scene.friction == "pim" else
                 f"mu_c {scene.mu_c:g}, r {'eps^2' if scene.recovery is None else scene.recovery}")
    return ", ".join(parts)


def assumption_table(study: AssumptionStudy, name: str = "assumptions",
                     units: str | None = None) -> Table:
    """The ladder at the typical contact time: marginal and cumulative effects per rung.

    Lengths in ``units`` ("si" or "us"; default: the case's own).
    """
    length, label = convert(1.0, "length", units or study.case.units)
    rows = []
    for rung in study.typical.rungs[1:]:
        r = rung.run
        rows.append((rung.title, rung.baseline, _scene_words(rung.scene), rung.marginal,
                     rung.cumulative, 1e3 * r.contact_duration,
                     float(length * r.impact_point[0]), float(length * r.impact_point[1]),
                     rung.eps_eff, rung.beta_eff, r.energy_loss,
                     r.stick_fraction, r.slip_reversed, r.failure or ""))
    columns = ("assumption relaxed", "against", "scene", "marginal effect [-]",
               "cumulative (PIM's error) [-]", "contact [ms]", f"C_eff x [{label}]",
               f"C_eff y [{label}]",
               "eps_eff [-]", "beta_eff [-]", "energy loss [-]", "stick fraction [-]",
               "slip reversed", "failure")
    return Table(name, f"PIM's assumptions one at a time at {1e3 * study.typical.duration:g} "
                 f"ms ({ERROR_DEFINITION})", columns, tuple(rows),
                 {c: fmt_error for c in columns[3:5]})


def sweep_table(study: AssumptionStudy, name: str = "assumption_sweeps") -> Table:
    """Every rung at every contact time, the tyre curves and the friction map."""
    rows = []
    for lad in study.ladders:
        for rung in lad.rungs[1:]:
            rows.append(("ladder", rung.key, 1e3 * lad.duration, _scene_words(rung.scene),
                         rung.marginal, rung.cumulative, rung.run.failure or ""))
    for mu, values in study.tyre_curves.items():
        for d, v in zip(study.durations, values, strict=True):
            rows.append(("tyre effect", f"tyre friction {mu:g}", 1e3 * d, "", v, math.nan, ""))
    for mu, r, marginal, _ in study.recovery_map:
        rows.append(("friction effect", f"mu_c {mu:g}, r {r:.3g}",
                     1e3 * TYPICAL["duration"], "", marginal, math.nan, ""))
    columns = ("part", "rung", "contact time [ms]", "scene", "marginal effect [-]",
               "cumulative (PIM's error) [-]", "failure")
    return Table(name, "Every scene of the study", columns, tuple(rows),
                 {c: fmt_error for c in columns[4:6]})


def plot_overview(study: AssumptionStudy):
    """The ladder (bars), effects over the contact time, tyres, friction (a Figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12, 8), layout="constrained")
    (a, b), (c, d) = fig.subplots(2, 2)
    rungs = study.typical.rungs[1:]
    x = np.arange(len(rungs))
    a.bar(x - 0.2, [100 * r.marginal for r in rungs], 0.4, label="marginal (vs rung below)")
    a.bar(x + 0.2, [100 * r.cumulative for r in rungs], 0.4, label="cumulative (PIM's error)")
    a.set_xticks(x, [r.key for r in rungs])
    a.set_title(f"ladder at {1e3 * study.typical.duration:g} ms", fontsize=10)
    for key in [r.key for r in rungs if r.key != "law"]:
        b.plot(1e3 * study.durations, 100 * study.effect(key), "o-", ms=3, label=key)
    b.plot(1e3 * study.durations, 100 * study.effect(rungs[-1].key, "cumulative"), "k--",
           label="cumulative (all)")
    b.set_xlabel("contact time [ms]")
    b.set_title("marginal effect of each assumption over the contact time", fontsize=10)
    for mu, values in study.tyre_curves.items():
        c.plot(1e3 * study.durations, 100 * values, "o-", ms=3, label=f"tyre friction {mu:g}")
    c.set_xlabel("contact time [ms]")
    c.set_title("tyre effect (tyres vs no tyres at the same contact time)", fontsize=10)
    for r in sorted({row[1] for row in study.recovery_map}):
        pts = [(mu, m) for mu, rr, m, _ in study.recovery_map if rr == r]
        d.plot([p[0] for p in pts], [100 * p[1] for p in pts], "o-", ms=3,
               label=f"tangential recovery r = {r:.3g}")
    d.set_xlabel("friction between the vehicles mu_c [-]")
    d.set_title("friction effect (Coulomb vs PIM's tangential law)", fontsize=10)
    for ax in (a, b, c, d):
        ax.axhline(100 * HOLDS, color="0.6", lw=0.8, ls=":")
        ax.set_ylabel("impact error [%]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{study.case.name or 'case'}: PIM's assumptions one at a time "
                 f"(epsilon = {study.eps:.3g}, PIM at beta = {study.beta_pim:g})", fontsize=11)
    return fig
