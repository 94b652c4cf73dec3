"""The analytic event: approach, the first impact, every further impact, run-out to rest.

:func:`event` (``pim.event``) builds one :class:`pim.model.event.Event` of a case:

1. **the approach**: the case's pre-impact motion held back ``approach`` seconds: free
   motion (constant CG velocity and yaw rate), or, where the case's evidence has tyre marks
   before the impact (``[evidence.vehicleN.pre_impact]``), the straight slide at the
   marks' constant deceleration over their length (:mod:`pim.model.pre_impact`, eq. 1);
2. **the first impact** by PIM under the case's law, as :func:`pim.solve` gives it;
3. **the run-out of both vehicles** with the case's tyres (``[evidence.vehicleN]``: wheelbase,
   track, friction, braking, the field tyre), else the Coulomb tyre at
   :data:`pim.model.event.DEFAULT_TYRE_FRICTION` on all four wheels locked, with the
   wheelbase and track from the outline (:func:`event_vehicle`), stepped by the compiled
   event kernel (:mod:`pim.model.event_kernel`) that watches the outlines;
4. **every further impact**: at a new contact that closes, PIM at the C and Gamma of the
   outlines' contact geometry (:mod:`pim.model.event_formula`: C the penetrating corner,
   Gamma the normal of the penetrated edge), under the law and coefficients of the case's
   ``[[impacts]]`` entry for it (:class:`pim.model.case.ImpactSpec`) or the stated
   defaults (the friction-capped Brach law, restitution
   :data:`~pim.model.event_formula.SECONDARY_RESTITUTION`, beta 1, cap
   :data:`~pim.model.event_formula.SECONDARY_CONTACT_FRICTION`), solved in the kernel by
   :func:`pim.model.event_formula.further_impact` (any of :func:`pim.solve`'s laws, the
   same formula) and recorded from its states before and after;
5. **on to rest**: every vehicle's ``|v| + |omega| r_max`` below
   :data:`pim.model.event.REST_SPEED`, or ``max_time``.

Steps 3-5 are one call of the compiled kernel; the scene's arrays are built once per case
and tyre friction (the last 8 kept: a case is frozen).

:func:`event_rest_many` runs step 3-5 for N samples of post-impact motion at once (the
same kernel, the same further impacts under every law): the rest states and an impact
summary, for the Monte Carlo and the reconstruction through the event.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
from types import SimpleNamespace

import numpy as np

from ..model.case import Case, Impact, ImpactSpec, Vehicle
from ..model.event import (
    DEFAULT_APPROACH,
    DEFAULT_TYRE_FRICTION,
    REST_SPEED,
    Event,
    ImpactRecord,
    Track,
    phase_labels,
)
from ..model.event_formula import (
    CONTACT_TOLERANCE,
    EVENT_STEP,
    MAX_IMPACTS,
    SECONDARY_BETA,
    SECONDARY_CONTACT_FRICTION,
    SECONDARY_LAW,
    SECONDARY_RESTITUTION,
    energy_loss,
    slip_speed,
)
from ..model.geometry import vehicle_outline
from ..model.impact_laws import LAW_CODES
from ..model.law import resolve_law, solve
from ..model.numbers import InputError, checked_number, real_array
from ..model.pdof import pdof
from ..model.pre_impact import mark_deceleration
from ..model.runout import MAX_TIME, RhsData, RunoutVehicle
from ..model.tyres import DEFAULT_REGULARISATION, STANDARD_GRAVITY

__all__ = ["event", "event_after", "event_rest_many", "EventRest", "event_vehicle", "impact_spec",
           "single_scene", "SingleScene",
           "kernel_impact_records",
           "WHEELBASE_PER_LENGTH", "TRACK_PER_WIDTH", "FREE_MOTION_TIME", "SLIDE_SPEED",
           "APPROACH_SAMPLE"]

#: Wheelbase of a vehicle without run-out evidence, per outline length [-]: passenger cars'
#: wheelbase is 0.57-0.63 of their length (NHTSA's 2010s sedans: 2.70-2.85 m of 4.6-4.9 m).
WHEELBASE_PER_LENGTH = 0.6
#: Track of a vehicle without run-out evidence, per outline width [-] (1.55-1.60 m of
#: 1.80-1.85 m).
TRACK_PER_WIDTH = 0.85
#: The time limit [s] of an event without tyres (free motion never comes to rest).
FREE_MOTION_TIME = 3.0
#: A wheel slides (leaves marks) where the slip speed its tyre resists exceeds this [m/s]:
#: ten times the tyre law's regularisation, where the force is within 0.5 % of mu N.
SLIDE_SPEED = 10 * DEFAULT_REGULARISATION
#: Interval of the approach's samples [s].
APPROACH_SAMPLE = 0.02


def event_vehicle(vehicle: Vehicle, evidence, tyre_friction, where: str) -> RunoutVehicle:
    """The run-out vehicle of one of the event's vehicles.

    With run-out evidence (``[evidence.vehicleN]``), its wheelbase, track, axle position,
    friction, braking, steer and tyre; ``tyre_friction`` [-], when given, replaces its
    friction. Without, the Coulomb tyre at ``tyre_friction`` (default
    :data:`~pim.model.event.DEFAULT_TYRE_FRICTION`) on four locked wheels, a wheelbase of
    :data:`WHEELBASE_PER_LENGTH` and a track of :data:`TRACK_PER_WIDTH` of the outline,
    the axles centred on the outline (the front axle ``(length - wheelbase) / 2`` behind
    the front). ``tyre_friction`` 0 (free motion) returns the vehicle at friction 1; the
    caller zeroes it (:func:`scene_data`).
    """
    free = tyre_friction is not None and float(tyre_friction) == 0.0
    mu = 1.0 if free else tyre_friction
    if evidence is not None:
        rv = evidence.runout_vehicle(float(vehicle.mass), float(vehicle.yaw_inertia))
        return rv if mu is None else replace(rv, friction=float(mu))
    if vehicle.length is None or vehicle.width is None:
        raise InputError(f"{where}.length and width are needed for the event (its outline, "
                         f"and its wheelbase and track without [evidence.{where}])")
    length = float(vehicle.length)
    front = length / 2 if vehicle.cg_to_front is None else float(vehicle.cg_to_front)
    base = WHEELBASE_PER_LENGTH * length
    axle = min(max(front - (length - base) / 2, 0.0), base)
    return RunoutVehicle(float(vehicle.mass), float(vehicle.yaw_inertia), base,
                         TRACK_PER_WIDTH * float(vehicle.width), axle,
                         DEFAULT_TYRE_FRICTION if mu is None else float(mu))


def impact_spec(case: Case, k: int) -> ImpactSpec:
    """The law and coefficients of the event's impact number ``k`` (2, 3, ...): the case's
    ``[[impacts]]`` entry k - 2, else its last entry, else the stated defaults (law
    :data:`~pim.model.event_formula.SECONDARY_LAW`); an entry's missing coefficients take
    the defaults too (restitution :data:`~pim.model.event_formula.SECONDARY_RESTITUTION`,
    beta :data:`~pim.model.event_formula.SECONDARY_BETA`, contact friction
    :data:`~pim.model.event_formula.SECONDARY_CONTACT_FRICTION` for the laws that take
    one)."""
    specs = tuple(getattr(case, "impacts", ()) or ())
    spec = specs[min(k - 2, len(specs) - 1)] if specs else ImpactSpec(law=SECONDARY_LAW)
    ks = spec.law == "kudlich-slibar"
    return replace(
        spec, restitution=SECONDARY_RESTITUTION if spec.restitution is None
        else spec.restitution,
        beta=None if ks else SECONDARY_BETA if spec.beta is None else spec.beta,
        contact_friction=None if spec.law == "brach" else SECONDARY_CONTACT_FRICTION
        if spec.contact_friction is None else spec.contact_friction)


def _outline_row(vehicle: Vehicle, where: str) -> tuple:
    if vehicle.length is None or vehicle.width is None:
        raise InputError(f"{where}.length and width are needed for the event's outline watch")
    length = float(vehicle.length)
    front = length / 2 if vehicle.cg_to_front is None else float(vehicle.cg_to_front)
    return front, length, float(vehicle.width)


def scene_data(case: Case, tyre_friction, n: int = 1, *, generic: bool = False) -> tuple:
    """``(data1, data2 or None, outlines (2, 3), inverse (4,), runout vehicles)`` of the
    case's two vehicles for n samples (friction 0 where ``tyre_friction`` is 0).

    One sample (a single event's scene) takes :meth:`pim.model.runout.RhsData.one`, the
    arrays of :meth:`~pim.model.runout.RhsData.of` without its broadcasting; ``generic``
    True takes ``of`` even then (the reference the one-sample path is tested against).
    """
    build = RhsData.one if n == 1 and not generic else (lambda v: RhsData.of(v, n))
    ev = case.evidence
    vehicles, data = [], []
    for i in (1, 2):
        vehicle = getattr(case, f"vehicle{i}")
        if i == 2 and bool(vehicle.fixed):
            vehicles.append(None)
            data.append(None)
            continue
        rv = event_vehicle(vehicle, None if ev is None else getattr(ev, f"vehicle{i}"),
                           tyre_friction, f"vehicle{i}")
        d = build(rv)
        if tyre_friction is not None and float(tyre_friction) == 0.0:
            d = replace(d, friction=np.zeros(n))
        vehicles.append(rv)
        data.append(d)
    outlines = np.array([_outline_row(case.vehicle1, "vehicle1"),
                         _outline_row(case.vehicle2, "vehicle2")])
    inverse = np.array([1 / float(case.vehicle1.mass), 1 / float(case.vehicle1.yaw_inertia),
                        1 / float(case.vehicle2.mass), 1 / float(case.vehicle2.yaw_inertia)])
    return data[0], data[1], outlines, inverse, vehicles


def _further_specs(case: Case) -> tuple:
    """:func:`impact_spec` of the impacts 2 to MAX_IMPACTS + 1, each distinct one built
    once (the last ``[[impacts]]`` entry, or the defaults, stands for all after it)."""
    given = len(tuple(getattr(case, "impacts", ()) or ()))
    if not given:
        return _default_specs()
    distinct = [impact_spec(case, k) for k in range(2, min(given, MAX_IMPACTS) + 2)]
    return tuple(distinct[min(k, len(distinct) - 1)] for k in range(MAX_IMPACTS))


@lru_cache(maxsize=1)
def _default_specs() -> tuple:
    """:func:`_further_specs` of a case without ``[[impacts]]``: the stated defaults
    (:func:`impact_spec`) for every further impact (one frozen constant)."""
    return (impact_spec(None, 2),) * MAX_IMPACTS


def _further_coefficients(specs: tuple) -> np.ndarray:
    """:func:`_coefficients` of ``specs``; the defaults' (:func:`_default_specs`) are one
    read-only constant (:func:`_default_coefficients`)."""
    return _default_coefficients() if specs is _default_specs() else _coefficients(specs)


@lru_cache(maxsize=1)
def _default_coefficients() -> np.ndarray:
    """:func:`_coefficients` of :func:`_default_specs` (read-only)."""
    out = _coefficients(_default_specs())
    out.setflags(write=False)
    return out


def _coefficients(specs: tuple) -> np.ndarray:
    """(MAX_IMPACTS, 7): the further impacts' laws (``specs``, :func:`_further_specs`) for
    the kernel (:data:`pim.model.event_kernel.COEFFICIENT_COLUMNS`: restitution, beta, cap,
    law code, C and Gamma where the case's ``[[impacts]]`` give them, else NaN)."""
    rows = []
    for spec in specs:
        cap = np.inf if spec.law == "brach" else float(spec.contact_friction)
        point = ((np.nan, np.nan) if spec.point is None
                 else np.asarray(spec.point, float).reshape(2))
        rows.append((float(spec.restitution), 1.0 if spec.beta is None else float(spec.beta),
                     cap, LAW_CODES[spec.law], *point,
                     np.nan if spec.normal_angle is None else float(spec.normal_angle)))
    return np.array(rows)


def _state(case: Case, result, fixed: bool) -> np.ndarray:
    """Both vehicles' (x, y, psi, v_x, v_y, omega) just after the first impact (..., 2, 6)
    (the leading axes of the result's samples; ``fixed``: vehicle 2 is a fixed obstacle,
    its motion 0)."""
    out = np.empty(np.shape(result.yaw_rate1) + (2, 6))
    for i, v in enumerate((case.vehicle1, case.vehicle2)):
        out[..., i, :2] = np.asarray(v.cg, float).reshape(2)
        out[..., i, 2] = float(v.heading)
        if i == 1 and fixed:
            out[..., i, 3:] = 0.0
        else:
            out[..., i, 3:5] = getattr(result, f"velocity{i + 1}")
            out[..., i, 5] = getattr(result, f"yaw_rate{i + 1}")
    return out


def approach_motion(vehicles, marks, times, out=None) -> np.ndarray:
    """The vehicles' approach at ``times`` [s] <= 0 (before the impact at 0): their states
    (V, n, 6) (x, y, psi, v_x, v_y, omega), written into ``out`` when given.

    ``vehicles`` (V :class:`pim.Vehicle`) and ``marks`` (V, each
    :class:`pim.model.pre_impact.PreImpactMarks` or None). Free motion at the case's
    velocity and yaw rate; with tyre marks before the impact the CG slides straight along
    its impact velocity at the marks' constant deceleration ``a`` over their length ``L``
    (:func:`pim.model.pre_impact.mark_deceleration`, eq. 1), and moves freely at the speed
    at the marks' start before them: at ``tau = -t``, ``v = v_0 + a tau`` and the distance
    to the impact ``v_0 tau + a tau^2 / 2`` up to ``tau_L`` where it reaches ``L``. The
    heading turns at the yaw rate either way (``psi_0 - omega tau``).
    """
    tau = -np.asarray(times, float)
    out = np.empty((len(vehicles), len(tau), 6)) if out is None else out
    cg_vel = np.array([(v.cg, v.velocity) for v in vehicles], float).reshape(-1, 2, 2)
    cg, vel = cg_vel[:, 0], cg_vel[:, 1]
    turn = np.array([(float(np.asarray(v.yaw_rate)), float(v.heading)) for v in vehicles])
    w, heading = turn[:, 0], turn[:, 1]
    np.multiply(w[:, None], tau, out=out[:, :, 2])
    np.subtract(heading[:, None], out[:, :, 2], out=out[:, :, 2])    # heading - w tau
    out[:, :, 5] = w[:, None]
    np.multiply(tau[:, None], vel[:, None], out=out[:, :, :2])
    np.subtract(cg[:, None], out[:, :, :2], out=out[:, :, :2])       # cg - tau v
    out[:, :, 3:5] = vel[:, None]
    for i, m in enumerate(marks):
        if m is not None:
            _marks_approach(m, cg[i], vel[i], tau, out[i])
    return out


def _marks_approach(marks, cg: np.ndarray, vel: np.ndarray, tau: np.ndarray,
                    out: np.ndarray) -> None:
    """The CG's position and velocity in ``out`` (n, 6) of a vehicle that slid along its
    marks before the impact (:func:`approach_motion`), at ``tau`` [s] before it."""
    speed = float(np.hypot(*vel))
    if speed == 0.0 or marks.skid_length == 0.0:
        return
    a = float(mark_deceleration(marks.friction, marks.drag, marks.grade, STANDARD_GRAVITY))
    length = float(marks.skid_length)
    tau_l = (np.sqrt(speed ** 2 + 2 * a * length) - speed) / a if a > 0 else length / speed
    within = np.minimum(tau, tau_l)
    along = speed * within + 0.5 * a * within ** 2 + (speed + a * tau_l) * np.maximum(
        tau - tau_l, 0.0)
    unit = vel / speed
    now = speed + a * within
    out[:, :2] = cg - along[:, None] * unit
    out[:, 3:5] = now[:, None] * unit


def sliding_flags(states: np.ndarray, vehicle: RunoutVehicle | None,
                  friction: float = 1.0) -> np.ndarray:
    """Which wheels slide (N, 4) along states (N, 6): the slip speed the tyre resists
    (``f |s| + (1 - f) |s . e_t|``, :func:`pim.model.tyres.wheel_force`'s weights) above
    :data:`SLIDE_SPEED`; none without tyres (``vehicle`` None or ``friction`` 0)."""
    n = states.shape[0]
    if vehicle is None or friction == 0.0:
        return np.zeros((n, 4), bool)
    return _sliding(np.asarray(states, float)[None], *(w[None] for w in _wheels(vehicle)))[0]


def _wheels(vehicle: RunoutVehicle) -> tuple:
    """``(positions (4, 2) [m], braking (4,) [-], steer (4,) [rad])`` of a run-out vehicle,
    read-only (shared by the events of a scene)."""
    out = (np.array(vehicle.positions, float), np.array(vehicle.braking, float),
           np.array(np.broadcast_to(np.asarray(vehicle.steer, float), (4,))))
    for a in out:
        a.setflags(write=False)
    return out


def _sliding(states: np.ndarray, pos: np.ndarray, braking: np.ndarray,
             steer: np.ndarray) -> np.ndarray:
    """:func:`sliding_flags` of V vehicles at once: states (V, N, 6), their wheels'
    positions (V, 4, 2), braking (V, 4) and steer (V, 4); (V, N, 4)
    (:func:`pim.model.event_formula.slip_speed` on arrays)."""
    psi = states[..., 2:3]
    heading = psi + steer[:, None]
    f = braking[:, None]
    speed = slip_speed(np.cos(psi), np.sin(psi), states[..., 3:4], states[..., 4:5],
                       states[..., 5:6], pos[:, None, :, 0], pos[:, None, :, 1],
                       np.cos(heading), np.sin(heading), f)
    return speed > SLIDE_SPEED


def _coefficients_of(spec: ImpactSpec, result) -> dict:
    if spec.law == "kudlich-slibar":
        return {"k": float(np.asarray(result.eps)), "mu_c": float(spec.contact_friction)}
    out = {"eps": float(np.asarray(result.eps)), "beta": float(np.asarray(result.beta))}
    if spec.law == "brach-capped":
        out["mu_c"] = float(spec.contact_friction)
    return out


def impact_record(impact_case: Case, result, time: float, spec: ImpactSpec,
                  source: str) -> ImpactRecord:
    """The :class:`pim.model.event.ImpactRecord` of an impact solved by :func:`pim.solve`
    (its energy lost by :func:`pim.model.event_formula.energy_loss`, the formula of
    ``result.energy_loss``, on numbers)."""
    v1, v2 = impact_case.vehicle1, impact_case.vehicle2
    fixed = bool(v2.fixed)
    numbers = np.empty(15)          # impulse, CGs, velocities and yaw rates before, after
    numbers[0:2], numbers[2:4], numbers[4:6] = result.impulse, v1.cg, v2.cg
    numbers[6:8], numbers[8:10] = v1.velocity, v2.velocity
    numbers[10:12] = v1.yaw_rate, v2.yaw_rate
    numbers[12:14], numbers[14] = result.velocity1, result.yaw_rate1
    px, py, x1, y1, x2, y2, u1, w1, u2, w2, r1, r2, a1, b1, s1 = numbers.tolist()
    a2, b2, s2 = (0.0, 0.0, 0.0) if fixed else (*np.asarray(result.velocity2, float).reshape(
        2).tolist(), float(result.yaw_rate2))
    point = np.asarray(impact_case.impact.point, float).reshape(2)
    cx, cy = point.tolist()
    headings = np.array([float(v1.heading), float(v2.heading)])
    pd = pdof(np.array([[px, py], [-px, -py]]), headings)
    if fixed:
        pd[1] = np.nan
    loss = energy_loss(cx, cy, (x1, y1, 0.0, u1, w1, r1), (x2, y2, 0.0, u2, w2, r2),
                       (px, py, a1, b1, s1, a2, b2, s2))
    return ImpactRecord(
        time=float(time), point=point, normal_angle=float(impact_case.impact.normal_angle),
        law=spec.law, coefficients=_coefficients_of(spec, result),
        impulse=numbers[0:2].copy(), velocity_before=numbers[6:10].reshape(2, 2),
        velocity_after=np.array([[a1, b1], [a2, b2]]), yaw_rate_before=numbers[10:12],
        yaw_rate_after=np.array([s1, s2]), energy_loss=float(loss), pdof=pd, source=source)


def kernel_impact_records(rows: np.ndarray, specs, fixed: bool,
                          source: str = "outlines") -> list:
    """The :class:`pim.model.event.ImpactRecord` of each impact the event kernel solved,
    from its rows (k, :data:`pim.model.event_kernel.IMPACT_COLUMNS`: the states before and
    after, the impulse, C and n) and the laws they were solved under (``specs``, k
    :func:`impact_spec`'s at least); ``fixed``: vehicle 2 is a fixed obstacle (no PDOF).
    Each column is taken out of the rows once for all of them (each record's arrays are
    its own rows of those)."""
    if not len(rows):
        return []
    k = len(rows)
    g = rows[:, _RECORD_GATHER]            # (one gather: each record's arrays are views)
    impulse, both = g[:, 2:4], g[:, 2:6].reshape(k, 2, 2)
    np.negative(both[:, 1], out=both[:, 1])
    pd = pdof(both, rows[:, 21:23])
    if fixed:
        pd[:, 1] = np.nan
    columns = (g[:, 0:2], impulse, g[:, 6:10].reshape(k, 2, 2), g[:, 10:14].reshape(k, 2, 2),
               g[:, 14:16], g[:, 16:18], pd)
    normal = np.arctan2(rows[:, 4], rows[:, 3]).tolist()
    numbers = g[:, 18:21].tolist()
    return [_kernel_record(numbers[i], normal[i], [c[i] for c in columns], spec, source)
            for i, spec in zip(range(k), specs)]


#: The columns of the kernel's impact rows (:data:`pim.model.event_kernel.IMPACT_COLUMNS`)
#: an :class:`ImpactRecord` takes, in :func:`kernel_impact_records`' order: C, the impulse,
#: minus the impulse (vehicle 2's, for its PDOF), the velocities before and after, the yaw
#: rates before and after, then time, energy lost and the law's ratio.
_RECORD_GATHER = np.array([1, 2, 5, 6, 5, 6, 15, 16, 18, 19, 8, 9, 11, 12, 17, 20, 10, 13,
                           0, 14, 23])


def _kernel_record(numbers: list, normal: float, arrays: list, spec: ImpactSpec,
                   source: str) -> ImpactRecord:
    """One record of :func:`kernel_impact_records`: its time, energy lost and ratio
    (``numbers``), the normal's angle from its row, and its C, impulse, velocities and yaw
    rates before and after and PDOFs (``arrays``)."""
    time, loss, ratio = numbers
    if spec.law == "kudlich-slibar":
        coefficients = {"k": float(spec.restitution), "mu_c": float(spec.contact_friction)}
    else:
        coefficients = {"eps": float(spec.restitution), "beta": ratio}
        if spec.law == "brach-capped":
            coefficients["mu_c"] = float(spec.contact_friction)
    point, impulse, v_before, v_after, w_before, w_after, pd = arrays
    return ImpactRecord(
        time=time, point=point,
        normal_angle=normal if spec.normal_angle is None else float(spec.normal_angle),
        law=spec.law, coefficients=coefficients, impulse=impulse, velocity_before=v_before,
        velocity_after=v_after, yaw_rate_before=w_before, yaw_rate_after=w_after,
        energy_loss=loss, pdof=pd, source=source)


@dataclass(frozen=True)
class _Run:
    """The run-out part of a single event: its rows (time + states), impacts, last state."""

    rows: np.ndarray
    impacts: list
    stopped: tuple
    status: str


@dataclass(frozen=True)
class _Watch:
    """How a single event's run-out is stepped and watched (SI)."""

    step: float
    max_time: float
    tolerance: float


@dataclass(frozen=True)
class SingleScene:
    """A case's scene for its single events (:func:`single_scene`).

    Attributes
    ----------
    kernel : pim.model.event_kernel.KernelScene
        The event kernel's arrays (one sample).
    tyred : tuple of int
        The vehicles with tyres (indices: not a fixed obstacle).
    wheels : tuple
        Their wheels' positions (V, 4, 2) [m], braking (V, 4) [-] and steer (V, 4) [rad]
        (stacked on a first axis for the kernel).
    positions : tuple
        Each tyred vehicle's wheel positions (4, 2) [m] (read-only, the tracks').
    specs : tuple
        The further impacts' laws (:func:`impact_spec`).
    fixed : bool
        Vehicle 2 is a fixed obstacle.
    outlines : tuple
        Each vehicle's outline corners in its body frame (4, 2) [m]
        (:func:`pim.model.geometry.vehicle_outline`; read-only, the tracks').
    """

    kernel: object
    tyred: tuple
    wheels: tuple
    positions: tuple
    specs: tuple
    fixed: bool
    outlines: tuple


def _scene(case: Case, tyre_friction) -> SingleScene:
    """The case's :class:`SingleScene` at ``tyre_friction``, built once for the last 8 (case,
    tyre friction) pairs (:func:`_kept_scene`; a case is frozen and hashes by identity)."""
    return _kept_scene(case, None if tyre_friction is None else float(tyre_friction))


@lru_cache(maxsize=8)
def _kept_scene(case: Case, tyre_friction) -> SingleScene:
    return single_scene(case, tyre_friction)


def single_scene(case: Case, tyre_friction=None, *, generic: bool = False) -> SingleScene:
    """The :class:`SingleScene` of a case's single events at ``tyre_friction`` (as
    :func:`event`), built anew (:func:`event` keeps the last 8). ``generic`` True: by
    the n-sample path (:func:`scene_data`'s ``generic``, the wheels' positions computed
    again), the reference the one-sample path is tested against (the same arrays)."""
    from ..model.event_kernel import EventScene, kernel_scene  # compiled: numba

    data1, data2, outlines, inverse, vehicles = scene_data(case, tyre_friction,
                                                           generic=generic)
    specs = _further_specs(case)
    scene = EventScene(data1, data2, outlines[None], inverse[None],
                       _further_coefficients(specs)[None])
    tyred = tuple(i for i, v in enumerate(vehicles) if v is not None)
    tyres = [vehicles[i] for i in tyred]
    if generic or not all(v.plain for v in tyres):
        wheels = [_wheels(v) for v in tyres]
        stacked = tuple(np.stack([w[j] for w in wheels]) for j in range(3))   # (the kernel's)
    else:
        stacked = _stacked_wheels(tyres, [(data1, data2)[i] for i in tyred])
    positions = tuple(p.view() for p in stacked[0])
    outlines = tuple(vehicle_outline(v) for v in (case.vehicle1, case.vehicle2))
    for p in positions + outlines:
        p.setflags(write=False)
    return SingleScene(kernel_scene(scene, 1), tyred, stacked, positions, specs,
                       bool(case.vehicle2.fixed), outlines)


def _stacked_wheels(vehicles: list, data: list) -> tuple:
    """:func:`_wheels` of V vehicles with :attr:`~pim.model.runout.RunoutVehicle.plain`
    fields stacked on a first axis as the kernel takes them (positions (V, 4, 2), braking
    (V, 4), steer (V, 4)), the positions from their one-sample ``data``, without a stack
    per array."""
    positions, steer = np.empty((len(vehicles), 4, 2)), np.empty((len(vehicles), 4))
    for i, (v, d) in enumerate(zip(vehicles, data)):
        positions[i, :, 0], positions[i, :, 1] = d.wheel_x[0], d.wheel_y[0]
        steer[i] = v.steer
    return positions, np.array([v.braking for v in vehicles], float), steer


def _run_out(scene: SingleScene, state: np.ndarray, watch: _Watch) -> _Run:
    """Steps 3-5 of one event (module notes) in one call of the compiled kernel, which
    solves every further impact; the records from its rows."""
    from ..model.event_kernel import run_event  # compiled event: numba on first use

    size = int(watch.max_time / watch.step) + 64 + 2 * MAX_IMPACTS
    while True:
        run = run_event(scene.kernel, state[None], solve=True, record=size, step=watch.step,
                        max_time=watch.max_time, stop_speed=REST_SPEED,
                        tolerance=watch.tolerance)
        if run.status[0] != "record":       # (steps shrunk near contact: more rows)
            break
        size *= 4
    status, count = run.status[0], int(run.count[0])
    if status == "impacts":
        raise InputError(f"event: more than {MAX_IMPACTS} impacts after the first (the "
                         f"vehicles stay in contact: a contact without end is refused)")
    impacts = kernel_impact_records(run.impacts[0, :count], scene.specs, scene.fixed)
    if status == "energy":
        raise InputError(f"event: the impact at t = {impacts[-1].time:.4g} s gains energy "
                         f"under law {impacts[-1].law} (refused)")
    return _Run(run.record, impacts, tuple(~run.moving[0]), status)


def event(case: Case, *, tyre_friction=None, approach: float = DEFAULT_APPROACH,
          single_impact: bool = False, max_time=None, eps=None, beta=None,
          step: float = EVENT_STEP, tolerance: float = CONTACT_TOLERANCE) -> Event:
    """The analytic event of a case: approach, every impact, run-out to rest (module notes).

    Parameters
    ----------
    case : Case
        One case (scalar fields) with both outlines (``length``, ``width``); its
        ``impacts`` (the ``[[impacts]]`` list) set the further impacts' laws.
    tyre_friction : float, optional
        Tyre-road friction [-] of both run-outs, replacing the evidence's; 0: free motion
        (no tyres, the event ends at ``max_time``). Default: the case's evidence, else
        :data:`pim.model.event.DEFAULT_TYRE_FRICTION`.
    approach : float
        How long before the first impact the event starts [s] (>= 0).
    single_impact : bool
        PIM's single impact: no outline watch after it (today's run-out).
    max_time : float, optional
        Time limit after the first impact [s]; default 60 s with tyres,
        :data:`FREE_MOTION_TIME` without.
    eps, beta : float, optional
        The first impact's coefficients (default the case's), as :func:`pim.solve`.
    step : float
        Fixed step of the run-out [s] (shrunk near contact, :mod:`pim.model.event_kernel`).
    tolerance : float
        Overlap growth [m] that makes a new contact.

    Returns
    -------
    Event
        ``source`` "analytic"; ``impacts`` every impact in time order (the first from the
        case, ``source`` "case"; the further ones ``source`` "outlines").

    Examples
    --------
    >>> import pim
    >>> ev = pim.event(pim.load_case("ricsac9"), tyre_friction=0.0)
    >>> [round(i.time, 2) for i in ev.impacts]
    [0.0, 0.42]
    """
    approach = checked_number(approach, "approach", low=0.0, unit="s")
    tyre_friction, free, limit = _run_options(tyre_friction, max_time)
    scene = _scene(case, tyre_friction)
    result = solve(case, eps, beta)
    choice = resolve_law(case, eps, beta)
    first_spec = ImpactSpec(law=choice.law, contact_friction=choice.contact_friction)
    first = impact_record(case, result, 0.0, first_spec, "case")
    run = _run_out(scene, _state(case, result, scene.fixed),
                   _Watch(step, limit, np.inf if single_impact else tolerance))
    return _assemble(case, (first, *run.impacts), run, approach, scene, free)


def _assemble(case: Case, impacts: tuple, run: _Run, approach: float, scene: SingleScene,
              free: bool) -> Event:
    """The event's samples: the approach, the state just before the first impact, and the
    run-out's rows (the first is the state just after it)."""
    before = np.arange(-approach, 0.0, APPROACH_SAMPLE) if approach > 0 else np.zeros(0)
    start = len(before) + 1
    rows = run.rows
    time = np.empty(start + len(rows))
    time[:start - 1], time[start - 1], time[start:] = before, 0.0, rows[:, 0]
    states = np.empty((2, len(time), 6))
    states[:, start:] = rows[:, 1:].reshape(-1, 2, 6).transpose(1, 0, 2)
    ev = case.evidence
    evidence = (None, None) if ev is None else (ev.vehicle1, ev.vehicle2)
    approach_motion((case.vehicle1, case.vehicle2),
                    [None if e is None else e.pre_impact for e in evidence], time[:start],
                    out=states[:, :start])
    return _event_of(time, states, run, scene, start=start, free=free,
                     impact_times=[i.time for i in impacts], impacts=tuple(impacts))


def _event_of(time: np.ndarray, states: np.ndarray, run: _Run, scene: SingleScene, *,
              start: int, free: bool, impact_times: list, impacts: tuple) -> Event:
    """The Event of both vehicles' ``states`` (2, N, 6) (C-contiguous) at ``time``: the
    wheels that slide from sample ``start`` on (the run-out; of the vehicles with tyres,
    all at once)."""
    if scene.tyred and not free:
        from ..model.event_kernel import sliding_rows  # compiled event: numba

        sliding = sliding_rows(states, *scene.wheels, SLIDE_SPEED, vehicles=scene.tyred,
                               first=start)
    else:
        sliding = np.zeros((2, len(time), 4), bool)
    tracks = [Track(states[i, :, :2], states[i, :, 2], states[i, :, 3:5], states[i, :, 5],
                    sliding=sliding[i], outline=scene.outlines[i],
                    fixed=i == 1 and scene.fixed,
                    wheels=scene.positions[scene.tyred.index(i)] if i in scene.tyred
                    else None)
              for i in (0, 1)]
    stopped = tuple(bool(s) for s in run.stopped)
    rest = float(time[-1]) if all(stopped) else None
    notes = []
    if not all(stopped):
        notes.append(f"still moving at the time limit ({time[-1]:.3g} s after the impact)")
    return Event(time, tracks[0], tracks[1], phase_labels(time, impact_times, rest),
                 impacts=impacts, source="analytic", stopped=stopped, notes=tuple(notes))


def _run_options(tyre_friction, max_time) -> tuple:
    """``(tyre_friction, free, limit)``: the checked friction (None: the case's), whether
    the run-out is free motion (friction 0), and its time limit [s] (``max_time``, else
    :data:`FREE_MOTION_TIME` without tyres and :data:`MAX_TIME` with them)."""
    if tyre_friction is not None:
        tyre_friction = checked_number(tyre_friction, "tyre_friction", low=0.0)
    free = tyre_friction == 0.0
    limit = (FREE_MOTION_TIME if free else MAX_TIME) if max_time is None else checked_number(
        max_time, "max_time", low=0.0, low_open=True, unit="s")
    return tyre_friction, free, limit


def event_after(case: Case, velocity, yaw_rate, *, first: ImpactRecord | None = None,
                tyre_friction=None, max_time=None, step: float = EVENT_STEP,
                tolerance: float = CONTACT_TOLERANCE) -> Event:
    """The event from the first impact (t = 0) on, its post-impact motion given: the
    run-out with the outline watch and every further impact, to rest (steps 3-5 of the
    module notes), as :func:`event_rest_many` computes its ends.

    What a reconstruction through the event animates: its fitted post-impact motion
    (:func:`pim.analysis.event_fit.fit_through_event`) carried through the further impacts
    that fit assumed.

    Parameters
    ----------
    case : Case
        One case with both outlines; its poses are the vehicles' at the impact, its
        ``impacts`` set the further impacts' laws, its evidence the tyres.
    velocity : array_like (2, 2)
        Each vehicle's velocity just after the first impact [m/s] (vehicle 2's ignored when
        it is a fixed obstacle).
    yaw_rate : array_like (2,)
        Each vehicle's yaw rate just after the first impact [rad/s].
    first : ImpactRecord, optional
        The first impact's record (the motion was given, not solved here: the caller's
        answer, e.g. a reconstruction's); without it ``impacts`` holds the further impacts
        only, and :meth:`Event.at` cannot place the first.
    tyre_friction, max_time, step, tolerance
        As :func:`event`.

    Returns
    -------
    Event
        ``source`` "analytic", from t = 0 (the state just after the first impact, phase
        "impact 1") to rest; ``impacts`` ``first`` (when given) and every further impact.
    """
    tyre_friction, free, limit = _run_options(tyre_friction, max_time)
    velocity = real_array(velocity, "velocity", "m/s")
    yaw_rate = real_array(yaw_rate, "yaw_rate", "rad/s")
    if velocity.shape != (2, 2) or yaw_rate.shape != (2,):
        raise InputError(f"event_after: velocity must be (2, 2) [m/s] and yaw_rate (2,) "
                         f"[rad/s], got {velocity.shape} and {yaw_rate.shape}")
    scene = _scene(case, tyre_friction)
    motion = SimpleNamespace(velocity1=velocity[0], velocity2=velocity[1],
                             yaw_rate1=yaw_rate[0], yaw_rate2=yaw_rate[1])
    run = _run_out(scene, _state(case, motion, scene.fixed), _Watch(step, limit, tolerance))
    states = np.ascontiguousarray(run.rows[:, 1:].reshape(-1, 2, 6).transpose(1, 0, 2))
    return _event_of(run.rows[:, 0].copy(), states, run, scene, start=0, free=free,
                     impact_times=[0.0, *(i.time for i in run.impacts)],
                     impacts=run.impacts if first is None else (first, *run.impacts))


@dataclass(frozen=True)
class EventRest:
    """The ends of N events (SI): what :func:`event_rest_many` computes.

    Attributes
    ----------
    rest_position : ndarray (n, 2, 2)
        Each vehicle's CG at rest (or at the time limit) [m] (axis 1: vehicle).
    rest_heading : ndarray (n, 2)
        Each vehicle's heading then [rad].
    stopped : ndarray of bool (n, 2)
        Which vehicles came to rest.
    impacts : ndarray of int (n,)
        Further impacts after the first.
    first_time : ndarray (n,)
        Time of the first further impact [s] (NaN without).
    time : ndarray (n,)
        Time of the end [s].
    ok : ndarray of bool (n,)
        The run ended at rest or at the time limit (not refused: too many impacts, energy
        gained).
    """

    rest_position: np.ndarray
    rest_heading: np.ndarray
    stopped: np.ndarray
    impacts: np.ndarray
    first_time: np.ndarray
    time: np.ndarray
    ok: np.ndarray


def event_rest_many(case: Case, velocity, yaw_rate, *, tyre_friction=None, max_time=None,
                    single_impact: bool = False, step: float = EVENT_STEP,
                    tolerance: float = CONTACT_TOLERANCE, vehicles=None,
                    poses=None) -> EventRest:
    """The rest states of N events from N post-impact motions of one case (compiled, parallel).

    The run-out, the outline watch and every further impact of :func:`event` (the same
    kernel: :func:`pim.model.event_formula.further_impact` under the case's ``[[impacts]]``
    laws or the defaults, every law :func:`pim.solve` takes), no timeline kept.

    Parameters
    ----------
    case : Case
        The impact configuration (positions, headings, outlines, masses), scalar.
    velocity : array_like (n, 2, 2)
        Both vehicles' CG velocities just after the first impact [m/s] (axis 1: vehicle).
    yaw_rate : array_like (n, 2)
        Their yaw rates [rad/s].
    tyre_friction : float or array_like (n,), optional
        As :func:`event` (per sample when an array; 0 not allowed per sample).
    max_time, single_impact, step, tolerance
        As :func:`event`.
    vehicles : (RunoutVehicle, RunoutVehicle or None), optional
        Per-sample run-out vehicles (arrays of n: masses, yaw inertias, friction) in place
        of the case's (None for a fixed obstacle): the Monte Carlo's sampled inputs
        (``tyre_friction`` then unused).
    poses : array_like (n, 2, 3), optional
        Each sample's CGs [m] and headings [rad] at the impact in place of the case's.
    """
    from ..model.event_kernel import EventScene, run_event  # compiled: numba on first use

    velocity = np.asarray(velocity, float).reshape(-1, 2, 2)
    n = velocity.shape[0]
    per_sample = tyre_friction is not None and np.ndim(tyre_friction) > 0
    data1, data2, outlines, inverse, _ = scene_data(
        case, 1.0 if per_sample else tyre_friction, n)
    if per_sample:
        mu = np.broadcast_to(np.asarray(tyre_friction, float), (n,)).copy()
        data1 = replace(data1, friction=mu)
        data2 = None if data2 is None else replace(data2, friction=mu)
    free = not per_sample and tyre_friction is not None and float(tyre_friction) == 0.0
    if vehicles is not None:
        data1, data2, inverse = _sampled_vehicles(vehicles, n)
    start = np.broadcast_to(_state(case, _Motion(velocity, yaw_rate),
                                   bool(case.vehicle2.fixed)), (n, 2, 6)).copy()
    if poses is not None:
        start[:, :, :3] = poses
    scene = EventScene(data1, data2, outlines[None], np.reshape(inverse, (-1, 4)),
                       _coefficients(_further_specs(case))[None])
    run = run_event(scene, start, solve=True,
                    max_time=(FREE_MOTION_TIME if free else MAX_TIME) if max_time is None
                    else float(max_time), step=step, stop_speed=REST_SPEED,
                    tolerance=np.inf if single_impact else tolerance)
    first = np.where(run.count > 0, run.impacts[:, 0, 0], np.nan)
    return EventRest(rest_position=run.final[:, :, :2].copy(),
                     rest_heading=run.final[:, :, 2].copy(), stopped=~run.moving,
                     impacts=run.count, first_time=first, time=run.time,
                     ok=np.isin(run.status, ("rest", "time")))


def _sampled_vehicles(vehicles, n: int) -> tuple:
    """``(data1, data2 or None, inverse (n, 4))`` of n samples' run-out vehicles (vehicle 2
    None: a fixed obstacle, its inverse mass and inertia 0)."""
    data = [None if v is None else RhsData.of(v, n) for v in vehicles]
    inverse = np.zeros((n, 4))
    for k, d in enumerate(data):
        if d is not None:
            inverse[:, 2 * k], inverse[:, 2 * k + 1] = 1.0 / d.mass, 1.0 / d.yaw_inertia
    return data[0], data[1], inverse


@dataclass(frozen=True)
class _Motion:
    """Post-impact motion of n samples in :func:`_state`'s reading (velocity (n, 2, 2),
    yaw rate (n, 2))."""

    velocity: np.ndarray
    yaw_rate: np.ndarray

    @property
    def velocity1(self):
        return self.velocity[:, 0]

    @property
    def velocity2(self):
        return self.velocity[:, 1]

    @property
    def yaw_rate1(self):
        return np.asarray(self.yaw_rate, float).reshape(-1, 2)[:, 0]

    @property
    def yaw_rate2(self):
        return np.asarray(self.yaw_rate, float).reshape(-1, 2)[:, 1]
