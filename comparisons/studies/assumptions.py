"""``pim assumptions``: PIM's assumptions relaxed one at a time, on a ladder of crush scenes.

The configurations and their ranges are :mod:`comparisons.studies.assumption_configs`;
this module simulates them and measures the effects; :mod:`comparisons.report.assumptions`
puts them in words, tables, a plot and documents.

Every configuration at contact time T has the stiffness that gives T for its own contact
point, k = (pi (1 + eps) / (2 T))^2 / K_nn; the "centroid" and outline configurations take
K_nn at the impulse centroid of an outline probe (the outline scene at C's stiffness) at
the same T. If the outline probe fails (e.g. a pole crossed by the car's outline) the
ladder goes on at C without the outline rung and says why.

Effects, each in two measures:

* the project's one error, :func:`sim.error_measure.impact_error` (largest difference in
  the velocity changes, yaw rates times the radius of gyration, relative to the largest
  change of the reference) [-];
* in physical terms (:class:`Change`): per vehicle, how far the delta-V vector moves [m/s]
  and the post-impact yaw rate [rad/s] (presented in the case's units).

The *marginal* effect of an assumption is between its rung and the rung's baseline at the
same contact time; the *cumulative* one is PIM's error against the rung, PIM evaluated at
the rung's own impact configuration (so the cumulative effect holds PIM's assumptions only,
never the input uncertainty of where C is). "Where C is" (:class:`InputShift`): PIM and the
scene at the sheet's C against both moved to where the illustrative outlines' impulse acts;
the uncertainty of an input, reported beside the ladder. :attr:`AssumptionStudy.sweeps`
keeps the former per-assumption view (:mod:`comparisons.studies.assumption_legacy`) for
``comparisons.regression.sections``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

import pim
import sim
from comparisons.studies.assumption_configs import (
    CONTACT_RANGE,
    STICKING,
    STIFF_LIMIT,
    TYPICAL,
    RungConfig,
    baseline_of,
    ladder_configs,
    plan,
)
from comparisons.studies.assumption_legacy import legacy_sweeps
from comparisons.studies.coefficients import coefficients
from comparisons.studies.one_impact import OneImpactRung, one_impact_rung
from pim.model.numbers import InputError
from sim.compliant_batch import STATUS_MESSAGES
from sim.compliant_setup import build_problem, rotate
from sim.contact_law import stiffness_for_duration, tangential_recovery_default
from sim.error_measure import impact_error
from sim.sweep import sweep

__all__ = ["ConfigRun", "Change", "Rung", "Ladder", "InputShift", "EffectRange",
           "FrictionPoint", "AssumptionStudy", "ENGINES", "run_assumptions", "change",
           "contact_case", "simulate_config", "pim_friction"]

#: The integrators a study runs on: the compiled crush scene, or pymunk (the cross-check).
ENGINES = ("numba", "pymunk")


@dataclass(frozen=True)
class ConfigRun:
    """One simulated configuration: post-impact motion (SI) and what the contact did.

    Attributes
    ----------
    config : RungConfig
        The configuration simulated.
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
    failure : str or None
        Why the simulation failed (then the numbers are NaN); None when it ran.
    """

    config: RungConfig
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
    failure: str | None = None

    @classmethod
    def failed(cls, config: RungConfig, why: str) -> ConfigRun:
        """A run that failed for the reason ``why`` (its numbers NaN)."""
        nan2 = np.full(2, math.nan)
        return cls(config, nan2, nan2, math.nan, math.nan, failure=why)

    @classmethod
    def of_result(cls, config: RungConfig, r, index=()) -> ConfigRun:
        """From a :class:`sim.CompliantResult`, or scene ``index`` of a
        :class:`sim.CompliantBatch` (whose point contacts start at t = 0)."""
        def at(name, default=None):
            value = getattr(r, name, default)
            return np.asarray(value, float)[index] if np.ndim(value) else float(value)
        e0 = float(at("energy_before"))
        return cls(config, at("velocity1"), at("velocity2"), float(at("yaw_rate1")),
                   float(at("yaw_rate2")), float(at("contact_duration")), at("impact_point"),
                   at("impulse_normal"), float(at("contact_start", 0.0)),
                   at("impact_point_body1"), at("impulse_normal_body2"),
                   (e0 - float(at("energy_after"))) / e0 if e0 > 0 else math.nan,
                   float(at("stick_fraction")), bool(np.asarray(r.slip_reversed)[index]))

    @classmethod
    def of_pim(cls, case: pim.Case, result: pim.Result) -> ConfigRun:
        """PIM's own outcome, as the ladder's foot."""
        def vec(x):
            return np.asarray(x, float).reshape(2)
        return cls(RungConfig(), vec(result.velocity1), vec(result.velocity2),
                   float(np.asarray(result.yaw_rate1)), float(np.asarray(result.yaw_rate2)),
                   0.0, vec(case.impact.point))


@dataclass(frozen=True)
class Change:
    """How far one outcome is from another, per vehicle [SI] (NaN for a fixed barrier).

    Attributes
    ----------
    delta_v1, delta_v2 : float
        Length of the difference of the delta-V vectors (= of the post-impact velocities)
        of vehicles 1 and 2 [m/s].
    yaw_rate1, yaw_rate2 : float
        Absolute difference of the post-impact yaw rates [rad/s].
    """

    delta_v1: float
    delta_v2: float
    yaw_rate1: float
    yaw_rate2: float

    @property
    def delta_v(self) -> float:
        """The larger of the two vehicles' delta-V differences [m/s] (NaN if none)."""
        return _largest(self.delta_v1, self.delta_v2)

    @property
    def yaw_rate(self) -> float:
        """The larger of the two yaw-rate differences [rad/s] (NaN if none)."""
        return _largest(self.yaw_rate1, self.yaw_rate2)


def _largest(a: float, b: float) -> float:
    values = [x for x in (a, b) if math.isfinite(x)]
    return max(values) if values else math.nan


NAN_CHANGE = Change(math.nan, math.nan, math.nan, math.nan)


def change(case: pim.Case, a, b) -> Change:
    """:class:`Change` from outcome ``a`` to outcome ``b`` (anything with the post-impact
    ``velocity1``, ``velocity2``, ``yaw_rate1``, ``yaw_rate2``, SI)."""
    if getattr(a, "failure", None) is not None or getattr(b, "failure", None) is not None:
        return NAN_CHANGE
    fixed2 = bool(case.vehicle2.fixed)

    def dv(x, y):
        return float(np.hypot(*(np.asarray(y, float).reshape(2)
                                - np.asarray(x, float).reshape(2))))

    def dw(x, y):
        return abs(float(np.asarray(y)) - float(np.asarray(x)))

    return Change(dv(a.velocity1, b.velocity1),
                  math.nan if fixed2 else dv(a.velocity2, b.velocity2),
                  dw(a.yaw_rate1, b.yaw_rate1),
                  math.nan if fixed2 else dw(a.yaw_rate2, b.yaw_rate2))


def _error(case: pim.Case, reference, run) -> float:
    """impact_error of ``run`` against ``reference`` (NaN if either failed)."""
    if getattr(reference, "failure", None) is not None or run.failure is not None:
        return math.nan
    return float(impact_error(case, reference, run.velocity1, run.velocity2, run.yaw_rate1,
                              run.yaw_rate2))


# -- one configuration ------------------------------------------------------------------------

def contact_case(case: pim.Case, probe: ConfigRun) -> pim.Case:
    """The case placed where the outlines of ``probe`` touch.

    The bodies are moved along their free pre-impact paths to the instant the outlines first
    touch (``probe.contact_start``), C to the outlines' impulse centroid (fixed in vehicle
    1's frame) and Gamma to their mean contact normal (fixed in vehicle 2's frame): a point
    contact there acts on the line the distributed contact's impulse acts on.
    """
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


@dataclass(frozen=True)
class Context:
    """What every configuration of one study shares.

    Attributes
    ----------
    case : pim.Case
        The case at the sheet's C.
    eps : float
        Restitution of the crush [-].
    beta_pim : float
        The case's own beta (given, fitted or the case file's): PIM's tangential law the
        "pim" friction emulates (:func:`pim_friction`).
    settings : sim.CompliantSettings
        Numerics of every run.
    """

    case: pim.Case
    eps: float
    beta_pim: float
    settings: object


def _probe_usable(probe: ConfigRun | None) -> str | None:
    """Why ``probe`` cannot place a centroid configuration (None: it can)."""
    if probe is None:
        return "no outline probe"
    if probe.failure is not None:
        return probe.failure
    return None if np.isfinite(probe.point_body1).all() else "no impulse centroid"


@dataclass(frozen=True)
class SimulationInputs:
    """What one configuration's simulation takes.

    Attributes
    ----------
    case : pim.Case
        The case (moved where the outlines' impulse acts for a point at the centroid).
    stiffness : float
        Loading stiffness k giving the configuration's contact time [N/m].
    friction : float
        mu_c between the vehicles [-].
    settings : sim.CompliantSettings
        Numerics, tyre mode, tangential stiffness and recovery.
    """

    case: pim.Case
    stiffness: float
    friction: float
    settings: object


def simulation_inputs(context: Context, config: RungConfig,
                      probe: ConfigRun | None) -> SimulationInputs:
    """The simulation inputs of ``config`` (``probe`` places a centroid configuration)."""
    case, eps = context.case, context.eps
    where = case if config.point == "C" else contact_case(case, probe)
    k_nn = build_problem(where, eps, sim.DEFAULT_STIFFNESS).k_nn
    duration = STIFF_LIMIT if config.duration is None else config.duration
    k = float(stiffness_for_duration(duration, k_nn, eps))
    settings, mu = replace(context.settings, tyre_mode=config.tyre_mode), config.mu_c
    if config.friction == "coulomb":
        settings = replace(settings, tangential_recovery=config.recovery)
    elif context.beta_pim > 0:
        mu = pim_friction(where, eps, context.beta_pim)
        settings = replace(settings, tangential_recovery=STICKING["recovery"],
                           tangential_stiffness=STICKING["stiffness_ratio"] * k)
    return SimulationInputs(case if config.distributed else where, k, mu, settings)


def pim_friction(case: pim.Case, eps: float, beta: float) -> float:
    """The friction between the vehicles [-] of PIM's tangential law as a contact law: a
    stiff, plastic friction spring that sticks (beta >= 1: :data:`STICKING`'s friction, which
    no impact exhausts) or slides at PIM's impulse ratio |mu| = beta |mu0| (0 < beta < 1: the
    case's own beta, not the nearer of 0 and 1)."""
    if beta >= 1.0:
        return STICKING["friction"]
    return float(beta * abs(float(pim.solve(case, eps, 1.0).mu0)))


def _unplaced(config: RungConfig, probe: ConfigRun | None) -> ConfigRun | None:
    """The failed run of a centroid configuration without a usable probe (else None)."""
    why = _probe_usable(probe) if config.point == "centroid" else None
    return None if why is None else ConfigRun.failed(
        config, f"the outline probe failed ({why})")


def simulate_config(job: tuple) -> ConfigRun:
    """Simulate one configuration on pymunk: ``job`` = (Context, RungConfig, probe or None)
    (module level, so that it runs on a process pool)."""
    context, config, probe = job
    unplaced = _unplaced(config, probe)
    if unplaced is not None:
        return unplaced
    try:
        s = simulation_inputs(context, config, probe)
        r = sim.simulate_compliant(s.case, context.eps, s.stiffness, friction=s.friction,
                                   geometry="outline" if config.distributed else "point",
                                   tyre_friction=config.tyre_friction, settings=s.settings,
                                   engine="pymunk")
    except sim.SimulationError as exc:
        return ConfigRun.failed(config, f"{exc.kind}: {exc}")
    return ConfigRun.of_result(config, r)


def probe_config(duration: float) -> RungConfig:
    """The outline probe at contact time ``duration``: the outline scene at C's stiffness,
    whose impulse centroid, normal and first touch place the centroid configuration."""
    return RungConfig(law="crush", duration=duration, distributed=True)


def _batch_group(context: Context, configs: list, probes: dict) -> dict:
    """{(geometry, where, contact time, tangential stiffness): [(config, SimulationInputs)]}:
    the configurations one compiled call can take (one case, one set of numerics)."""
    groups = {}
    for c in configs:
        s = simulation_inputs(context, c, probes.get(c.duration))
        moved = c.point == "centroid" and not c.distributed
        key = (c.distributed, c.duration if moved else None, s.settings.tangential_stiffness)
        groups.setdefault(key, []).append((c, s))
    return groups


def _run_batch(context: Context, members: list) -> dict:
    """One compiled call over ``members`` [(config, SimulationInputs)] sharing a case."""
    eps, (config, first) = context.eps, members[0]
    recovery = [tangential_recovery_default(eps) if s.settings.tangential_recovery is None
                else s.settings.tangential_recovery for _, s in members]
    b = sim.simulate_compliant(
        first.case, eps, np.array([s.stiffness for _, s in members]),
        friction=np.array([s.friction for _, s in members]),
        tyre_friction=np.array([c.tyre_friction for c, _ in members]),
        settings=first.settings, engine="numba",
        geometry="outline" if config.distributed else "point",
        tyre_mode=np.array([c.tyre_mode for c, _ in members]),
        tangential_recovery=np.array(recovery, float))
    names = b.status_name
    return {c: ConfigRun.of_result(c, b, i) if names[i] == "ok" else
            ConfigRun.failed(c, _failure(names[i], first.settings))
            for i, (c, _) in enumerate(members)}


def _failure(status: str, settings) -> str:
    """Why a compiled scene failed, in words: with the step set from the contact time
    (``settings.dt`` None) the step resolves every contact, so "tunnelled" is the outlines
    passing through each other."""
    if status == "tunnelled" and settings.dt is None:
        return ("tunnelled: the outlines passed through each other (the crush is deeper than "
                "the vehicles)")
    return f"{status}: {STATUS_MESSAGES[status]}"


def _run_compiled(context: Context, configs: list, probes: dict) -> dict:
    """{config: ConfigRun} of every configuration on the compiled scene, in batches."""
    out = {}
    placed = []
    for c in configs:
        unplaced = _unplaced(c, probes.get(c.duration))
        if unplaced is None:
            placed.append(c)
        else:
            out[c] = unplaced
    for members in _batch_group(context, placed, probes).values():
        out.update(_run_batch(context, members))
    return out


def run_configs(context: Context, configs: list, probes: dict, *, engine: str = "numba",
                executor=None, progress=False) -> dict:
    """{config: ConfigRun} of every configuration (``probes``: {contact time: probe run}):
    on ``engine`` "numba", compiled in batches; on "pymunk", one scene at a time on
    ``executor`` (:func:`sim.sweep.sweep`), the cross-check."""
    if engine not in ENGINES:
        raise InputError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    if engine == "numba":
        return _run_compiled(context, configs, probes) if configs else {}
    jobs = [(context, c, probes.get(c.duration)) for c in configs]
    runs = sweep(simulate_config, jobs, executor=executor, progress=progress,
                 desc="assumptions") if jobs else []
    return dict(zip(configs, runs, strict=True))


# -- the study -------------------------------------------------------------------------------

@dataclass(frozen=True)
class Rung:
    """One rung of the ladder: its configuration, its baseline and the effects measured.

    Attributes
    ----------
    key : str
        A key of :data:`comparisons.studies.assumption_configs.RUNGS`.
    baseline : str or None
        The configuration it is measured against (None for PIM).
    run : ConfigRun
    marginal : float
        impact_error of this scene against its baseline [-] (same contact time).
    cumulative : float
        impact_error of PIM (at the scene's impact configuration) against this scene [-].
    change : Change
        The marginal effect in physical terms (baseline to scene).
    pim_change : Change
        The cumulative effect in physical terms (PIM to scene).
    eps_eff, beta_eff : float
        :func:`pim.fit` to the simulated motion (what PIM would need); NaN if not fitted.
    fit_rms : float
        RMS residual of that fit [m/s]; NaN if not fitted.
    """

    key: str
    baseline: str | None
    run: ConfigRun
    marginal: float
    cumulative: float
    change: Change = NAN_CHANGE
    pim_change: Change = NAN_CHANGE
    eps_eff: float = math.nan
    beta_eff: float = math.nan
    fit_rms: float = math.nan

    @property
    def config(self) -> RungConfig:
        """The rung's configuration."""
        return self.run.config


@dataclass(frozen=True)
class Shift:
    """The scene at the sheet's C against the scene where the outlines' impulse acts, at
    one contact time (the input-uncertainty block "where C is").

    Attributes
    ----------
    at_c, at_centroid : ConfigRun
        The "duration" and "centroid" configurations' runs.
    error : float
        impact_error of the moved scene against the one at C [-].
    change : Change
        The same in physical terms.
    """

    at_c: ConfigRun
    at_centroid: ConfigRun
    error: float
    change: Change


@dataclass(frozen=True)
class Ladder:
    """The rungs at one contact time, bottom (PIM) first.

    Attributes
    ----------
    duration : float
        Contact time of the ladder's scenes [s].
    rungs : tuple of Rung
        The rungs, bottom (PIM) first.
    shift : Shift or None
        Where C is, at this contact time (None without outlines).
    """

    duration: float
    rungs: tuple
    shift: Shift | None = None

    def rung(self, key: str) -> Rung | None:
        """The rung ``key`` (None when the ladder has none)."""
        return next((r for r in self.rungs if r.key == key), None)


@dataclass(frozen=True)
class InputShift:
    """Where C is: the sheet's C and Gamma against where the illustrative outlines' impulse
    acts, reported as input uncertainty beside the ladder (not a rung).

    Attributes
    ----------
    distance : float
        How far the outlines' impulse centroid lies from the sheet's C on vehicle 1 (in its
        body frame) at the typical contact time [m].
    turn : float
        Angle [deg] from the case's Gamma to the outlines' mean contact normal there, on
        vehicle 2 (in its body frame).
    pim_error : float
        impact_error of PIM at the moved configuration against PIM at C [-].
    pim_change : Change
        The same in physical terms.
    """

    distance: float
    turn: float
    pim_error: float
    pim_change: Change


@dataclass(frozen=True)
class FrictionPoint:
    """The friction rung at one (contact time, mu_c, r).

    Attributes
    ----------
    duration : float
        Contact time [s].
    mu_c : float
        Friction between the vehicles [-].
    recovery : float
        Tangential recovery r [-].
    marginal, cumulative : float
        As :class:`Rung` [-].
    change : Change
        The marginal effect in physical terms.
    """

    duration: float
    mu_c: float
    recovery: float
    marginal: float
    cumulative: float
    change: Change


@dataclass(frozen=True)
class EffectRange:
    """One effect over the unmeasured parameters (contact times, recoveries).

    Attributes
    ----------
    settings : tuple of str
        What each value was measured at, e.g. ("50 ms", ...) or ("75 ms, r 0.5", ...).
    marginal : numpy.ndarray
        impact_error of each [-].
    delta_v : numpy.ndarray
        The larger vehicle's delta-V difference of each [m/s].
    yaw_rate : numpy.ndarray
        The larger yaw-rate difference of each [rad/s].
    missing : tuple of str
        Contact times of the range left out: their ladder lacks the typical one's outline
        rung (its outline scene failed there, :attr:`AssumptionStudy.outline_note`), so
        the rung's baseline differs.
    """

    settings: tuple
    marginal: np.ndarray
    delta_v: np.ndarray
    yaw_rate: np.ndarray
    missing: tuple = ()

    def extremes(self, name: str) -> tuple:
        """(smallest, largest) of ``name`` ("marginal", "delta_v", "yaw_rate"), NaN
        ignored."""
        values = np.asarray(getattr(self, name), float)
        if not np.isfinite(values).any():
            return math.nan, math.nan
        return float(np.nanmin(values)), float(np.nanmax(values))

    def setting_of(self, name: str, which: str = "max") -> str:
        """The setting at the largest (``"max"``) or smallest value of ``name``."""
        values = np.asarray(getattr(self, name), float)
        if not np.isfinite(values).any():
            return ""
        return self.settings[int(np.nanargmax(values) if which == "max"
                                 else np.nanargmin(values))]


@dataclass(frozen=True, eq=False)
class AssumptionStudy:
    """Outcome of :func:`run_assumptions`.

    Attributes
    ----------
    case : pim.Case
    eps, beta : float
        The case's coefficients (beta as the case uses it).
    beta_pim : float
        The beta PIM is evaluated at and the "law" rung emulates: the case's own (``beta``,
        given, fitted to the measured motion or the case file's; :func:`pim_friction`).
    ladders : tuple of Ladder
        One per contact time, shortest first.
    range_durations : tuple of float
        The contact times the verdicts span [s].
    tyre_curves : dict
        (wheels' state, tyre friction) -> array of the tyre rung's marginal effect at each
        of ``durations`` [-].
    friction_points : tuple of FrictionPoint
        The friction rung over (contact time, mu_c, r).
    input_shift : InputShift or None
        Where C is (None without outlines).
    stiffness_typical : float
        Contact stiffness k giving the typical contact time at C [N/m].
    engine : str
        The integrator (:data:`ENGINES`).
    seconds : float
        Wall time of the study [s].
    animation_result : sim.CompliantResult or None
        The recorded run for the animation (None when not asked for or the run failed).
    outline_note : str
        Why the outline rung is missing at some or all contact times ("" when it ran at
        every one).
    one_impact : OneImpactRung or None
        The "one impact" rung: the whole event against PIM's single impact
        (:mod:`comparisons.studies.one_impact`; None without both outlines).
    """

    case: pim.Case
    eps: float
    beta: float
    beta_pim: float
    ladders: tuple
    range_durations: tuple
    tyre_curves: dict
    friction_points: tuple
    input_shift: InputShift | None
    stiffness_typical: float
    engine: str
    seconds: float
    animation_result: object = field(default=None, repr=False)
    outline_note: str = ""
    one_impact: OneImpactRung | None = None

    @property
    def durations(self) -> np.ndarray:
        """Contact times of the ladders [s]."""
        return np.array([ladder.duration for ladder in self.ladders])

    @property
    def typical(self) -> Ladder:
        """The ladder at the typical contact time (:data:`TYPICAL`)."""
        return min(self.ladders, key=lambda lad: abs(lad.duration - TYPICAL["duration"]))

    @property
    def contact_range(self) -> tuple:
        """(shortest, longest) contact time of the verdicts [s]."""
        return min(self.range_durations), max(self.range_durations)

    def in_range(self, key: str = "friction") -> list:
        """The ladders whose contact time the verdicts span and in which rung ``key`` has
        the typical ladder's baseline (with or without the outline rung below it alike)."""
        def same(lad):
            rung, typical = lad.rung(key), self.typical.rung(key)
            if rung is None or typical is None or rung.baseline != typical.baseline:
                return False
            return key in ("law", "duration") or (
                (lad.rung("outline") is None) == (self.typical.rung("outline") is None))
        return [lad for lad in self.ladders if lad.duration in self.range_durations
                and same(lad)]

    def missing(self, key: str = "friction") -> tuple:
        """The range's contact times :meth:`in_range` leaves out, as "150 ms"."""
        kept = {lad.duration for lad in self.in_range(key)}
        return tuple(f"{1e3 * d:g} ms" for d in self.range_durations if d not in kept)

    def effect(self, key: str, kind: str = "marginal") -> np.ndarray:
        """The marginal or cumulative effect of rung ``key`` at each contact time [-]."""
        return np.array([getattr(lad.rung(key), kind) if lad.rung(key) else math.nan
                         for lad in self.ladders])

    def over_range(self, key: str) -> EffectRange | None:
        """Rung ``key``'s marginal effect over the verdicts' contact times (None if the
        ladder has no such rung)."""
        rungs = [(lad.duration, lad.rung(key)) for lad in self.in_range(key)]
        if not rungs:
            return None
        return EffectRange(tuple(f"{1e3 * d:g} ms" for d, _ in rungs),
                           np.array([r.marginal for _, r in rungs]),
                           np.array([r.change.delta_v for _, r in rungs]),
                           np.array([r.change.yaw_rate for _, r in rungs]), self.missing(key))

    def shift_over_range(self) -> EffectRange | None:
        """Where C is, for the scene over the verdicts' contact times (None without
        outlines)."""
        shifts = [(lad.duration, lad.shift) for lad in self.in_range("outline")]
        if not shifts:
            return None
        return EffectRange(tuple(f"{1e3 * d:g} ms" for d, _ in shifts),
                           np.array([s.error for _, s in shifts]),
                           np.array([s.change.delta_v for _, s in shifts]),
                           np.array([s.change.yaw_rate for _, s in shifts]),
                           self.missing("outline"))

    def friction_over(self, mu_c: float | None = None) -> EffectRange | None:
        """The friction rung at ``mu_c`` (default the typical) over the verdicts' contact
        times and every tangential recovery r (None if not simulated)."""
        mu = TYPICAL["friction"] if mu_c is None else mu_c
        kept = {lad.duration for lad in self.in_range()}
        pts = [p for p in self.friction_points if p.mu_c == mu and p.duration in kept]
        if not pts:
            return None
        return EffectRange(tuple(f"{1e3 * p.duration:g} ms, r {p.recovery:.3g}" for p in pts),
                           np.array([p.marginal for p in pts]),
                           np.array([p.change.delta_v for p in pts]),
                           np.array([p.change.yaw_rate for p in pts]), self.missing())

    @property
    def sweeps(self) -> tuple:
        """The typical ladder in the shape of the former study, for callers written for it
        (``comparisons.regression.sections``; :func:`assumption_legacy.legacy_sweeps`)."""
        return legacy_sweeps(self)


def _fit(case: pim.Case, run: ConfigRun) -> tuple[float, float, float]:
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


@dataclass(frozen=True)
class _Outcomes:
    """What the ladders read: every run, PIM at C and PIM at each centroid configuration."""

    context: Context
    runs: dict
    pim_at_c: ConfigRun
    pim_moved: dict          # contact time -> (moved case, PIM's ConfigRun there)

    def has_outline(self, duration: float) -> bool:
        """Whether the outline scene ran at ``duration`` (its probe placed the centroid)."""
        return duration in self.pim_moved

    def pim_for(self, config: RungConfig) -> tuple:
        """(case, PIM's run) at ``config``'s impact configuration."""
        if config.point == "C":
            return self.context.case, self.pim_at_c
        return self.pim_moved[config.duration]

    def run(self, config: RungConfig) -> ConfigRun:
        """The run of ``config`` (PIM for the ladder's foot)."""
        return self.pim_at_c if config.law == "pim" else self.runs[config]


def _rung(out: _Outcomes, key: str, configs: dict, fit: bool) -> Rung:
    """Rung ``key`` of the ladder ``configs``, against its baseline and against PIM."""
    case = out.context.case
    run = out.run(configs[key])
    if key == "pim":
        return Rung("pim", None, run, 0.0, 0.0, change(case, run, run), change(case, run, run))
    base = baseline_of(key, out.has_outline(configs["duration"].duration))
    below = out.run(configs[base])
    where, pim_run = out.pim_for(configs[key])
    fitted = _fit(case, run) if fit else (math.nan,) * 3
    return Rung(key, base, run, _error(case, below, run), _error(where, pim_run, run),
                change(case, below, run), change(case, pim_run, run), *fitted)


def _ladder(out: _Outcomes, duration: float) -> Ladder:
    """The rungs at ``duration``; the input shift there."""
    configs = ladder_configs(duration, out.has_outline(duration))
    keys = [k for k in configs if k != "centroid"]
    fit = duration == TYPICAL["duration"]
    rungs = tuple(_rung(out, k, configs, fit) for k in keys)
    shift = None
    if out.has_outline(duration):
        at_c, moved = out.runs[configs["duration"]], out.runs[configs["centroid"]]
        shift = Shift(at_c, moved, _error(out.context.case, at_c, moved),
                      change(out.context.case, at_c, moved))
    return Ladder(duration, rungs, shift)


def _tyre_curves(out: _Outcomes, the_plan) -> dict:
    """(wheels' state, tyre friction) -> the tyre rung's marginal effect over the contact
    times, always against the tyre-free scene at the same time."""
    curves = {}
    for key, mode in (("tyres", "rolling"), ("tyres_locked", "locked")):
        for mu in the_plan.tyre_frictions:
            values = []
            for d in the_plan.durations:
                configs = ladder_configs(d, out.has_outline(d), tyre_friction=mu)
                below = out.runs[configs[baseline_of(key, out.has_outline(d))]]
                values.append(_error(out.context.case, below, out.runs[configs[key]]))
            curves[(mode, mu)] = np.array(values)
    return curves


def _friction_points(out: _Outcomes, the_plan) -> tuple:
    """The friction rung at every (contact time, mu_c, r) simulated."""
    case, points = out.context.case, []
    for d in the_plan.durations:
        configs = ladder_configs(d, out.has_outline(d))
        tyres = out.runs[configs["tyres"]]
        where, pim_run = out.pim_for(configs["friction"])
        for mu in the_plan.frictions:
            for r in the_plan.recoveries:
                config = replace(configs["friction"], mu_c=mu,
                                 recovery=the_plan.recovery(r))
                if config in out.runs:
                    run = out.runs[config]
                    points.append(FrictionPoint(d, mu, r, _error(case, tyres, run),
                                                _error(where, pim_run, run),
                                                change(case, tyres, run)))
    return tuple(points)


def _input_shift(out: _Outcomes) -> InputShift | None:
    """Where C is: the typical contact time's outline probe against the sheet's C, both on
    the vehicles (C relative to vehicle 1, Gamma relative to vehicle 2)."""
    if not out.pim_moved:
        return None
    case, d = out.context.case, TYPICAL["duration"]
    where, moved = out.pim_moved[d] if d in out.pim_moved else next(
        iter(out.pim_moved.values()))
    v1, w1, v2, w2 = case.vehicle1, where.vehicle1, case.vehicle2, where.vehicle2

    def on(vehicle, point):
        return rotate(np.asarray(point, float).reshape(2) - np.asarray(vehicle.cg, float)
                      .reshape(2), -float(vehicle.heading))

    distance = float(np.hypot(*(on(w1, where.impact.point) - on(v1, case.impact.point))))
    turn = math.degrees(math.remainder(
        (float(where.impact.normal_angle) - float(w2.heading))
        - (float(case.impact.normal_angle) - float(v2.heading)), math.tau))
    return InputShift(distance, turn, _error(case, out.pim_at_c, moved),
                      change(case, out.pim_at_c, moved))


def _probes(context: Context, durations, run) -> tuple:
    """({contact time: probe run} of the probes that ran, {contact time: why} of those
    that failed); ``run``: :func:`run_configs` with the study's engine and executor."""
    runs = run(context, [probe_config(d) for d in durations], {})
    ran = {c.duration: r for c, r in runs.items() if r.failure is None}
    return ran, {c.duration: r.failure for c, r in runs.items() if r.failure is not None}


def outline_note(failed: dict, has_outline: bool) -> str:
    """Why the outline rung is missing at some contact times of the verdicts' range
    (:data:`CONTACT_RANGE`; "" when it ran at every one: a failure beyond the range, which
    only the plots over contact time show, is not the verdicts' business)."""
    if not has_outline:
        return "the case gives no outlines: vehicle length and width"
    low, high = CONTACT_RANGE
    failed = {d: why for d, why in failed.items() if low <= d <= high}
    if not failed:
        return ""
    at = ", ".join(f"{1e3 * d:g}" for d in sorted(failed))
    return f"the outline scene failed at {at} ms: {failed[max(failed)]}"


def _pim_moved(context: Context, probes: dict, beta_pim: float) -> dict:
    """Contact time -> (the case moved where the outlines' impulse acts, PIM there)."""
    out = {}
    for d, probe in probes.items():
        where = contact_case(context.case, probe)
        out[d] = (where, ConfigRun.of_pim(where, pim.solve(where, context.eps, beta_pim)))
    return out


def has_outlines(case: pim.Case) -> bool:
    """Whether the case gives the vehicles' outlines (length and width)."""
    return (case.vehicle1.length is not None and
            (case.vehicle2.length is not None or bool(case.vehicle2.fixed)))


def run_assumptions(case: pim.Case, eps: float | None = None, beta: float | None = None, *,
                    executor=None, progress: bool | None = None, stiffness: float | None = None,
                    animation_after: float | None = 2.0, settings=None,
                    sweeps: bool = True, engine: str = "numba") -> AssumptionStudy:
    """PIM's assumptions relaxed one at a time on the ladder of crush scenes (module notes).

    Parameters
    ----------
    case : pim.Case
        A single case.
    eps : float, optional
        Physical restitution [-] of the crush (default: the fit to the case's measured
        motion, else ``case.impact.restitution``).
    beta : float, optional
        PIM's beta (default: the fit to the case's measured motion, else
        ``case.impact.beta``, else 1); PIM is compared at it, and the "law" rung emulates it
        (:func:`pim_friction`).
    executor : None, "process", "serial", dask Client or Executor
        Where the pymunk scenes run (:func:`sim.sweep.sweep`).
    progress : bool or None
        Progress bars.
    stiffness : float, optional
        Stiffness [N/m] of the animated scene (default: the one giving the typical time).
    animation_after : float or None
        Seconds after separation to simulate for the animation (None: no animation run).
    settings : sim.CompliantSettings, optional
        Numerics of every run.
    sweeps : bool
        Every contact time and variant (:func:`assumption_configs.plan`); False: the
        verdicts only (the range's ends and middle), the summary of ``pim compare``.
    engine : {"numba", "pymunk"}
        The compiled crush scene, or pymunk for every scene (the cross-check,
        :func:`run_configs`).
    """
    start = time.perf_counter()
    eps, beta, _ = coefficients(case, eps, beta)
    if not 0.0 <= eps <= 1.0:
        raise InputError(f"eps must be in [0, 1], got {eps}")
    beta_pim = beta                     # the case's own, never rounded to 0 or 1
    settings = replace(settings or sim.CompliantSettings(), record=False, duration=0.0)
    context, the_plan = Context(case, eps, beta_pim, settings), plan(eps, sweeps)
    def run(ctx, configs, probes):
        return run_configs(ctx, configs, probes, engine=engine, executor=executor,
                           progress=progress is not False)

    probes, failed = _probes(context, the_plan.durations, run) if has_outlines(case) \
        else ({}, {})
    runs = run(context, the_plan.configs(set(probes)), probes)
    out = _Outcomes(context, runs, ConfigRun.of_pim(case, pim.solve(case, eps, beta_pim)),
                    _pim_moved(context, probes, beta_pim))
    k_nn = build_problem(case, eps, sim.DEFAULT_STIFFNESS).k_nn
    k_typical = float(stiffness_for_duration(TYPICAL["duration"], k_nn, eps))
    anim = _animation(case, eps, stiffness or k_typical, bool(probes), settings,
                      animation_after)
    return AssumptionStudy(
        case=case, eps=eps, beta=beta, beta_pim=beta_pim,
        ladders=tuple(_ladder(out, d) for d in the_plan.durations),
        range_durations=the_plan.range_durations, tyre_curves=_tyre_curves(out, the_plan),
        friction_points=_friction_points(out, the_plan), input_shift=_input_shift(out),
        stiffness_typical=k_typical, engine=engine, seconds=time.perf_counter() - start,
        animation_result=anim, outline_note=outline_note(failed, has_outlines(case)),
        one_impact=one_impact_rung(case, eps, beta_pim) if has_outlines(case) else None)


def _animation(case, eps, k, has_outline, settings, after):
    if after is None:
        return None
    try:
        return sim.simulate_compliant(
            case, eps, k, geometry="outline" if has_outline else "point",
            settings=replace(settings, record=True, duration=float(after)), engine="pymunk")
    except sim.SimulationError:
        return None

