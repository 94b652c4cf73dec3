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
   :data:`~pim.model.event_formula.SECONDARY_CONTACT_FRICTION`), solved by :func:`pim.solve`;
5. **on to rest**: every vehicle's ``|v| + |omega| r_max`` below
   :data:`pim.model.event.REST_SPEED`, or ``max_time``.

:func:`event_rest_many` runs step 3-5 for N samples of post-impact motion at once (the
kernel solves the further impacts itself, Brach's laws): the rest states and an impact
summary, for the Monte Carlo and the reconstruction through the event.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

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
)
from ..model.geometry import kinetic_energy, vehicle_outline
from ..model.law import resolve_law, solve
from ..model.numbers import InputError
from ..model.pdof import pdof
from ..model.pre_impact import mark_deceleration
from ..model.runout import MAX_TIME, RhsData, RunoutVehicle
from ..model.tyres import DEFAULT_REGULARISATION, STANDARD_GRAVITY

__all__ = ["event", "event_rest_many", "EventRest", "event_vehicle", "impact_spec",
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


def scene_data(case: Case, tyre_friction, n: int = 1) -> tuple:
    """``(data1, data2 or None, outlines (2, 3), inverse (4,), runout vehicles)`` of the
    case's two vehicles for n samples (friction 0 where ``tyre_friction`` is 0)."""
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
        d = RhsData.of(rv, n)
        if tyre_friction is not None and float(tyre_friction) == 0.0:
            d = replace(d, friction=np.zeros(n))
        vehicles.append(rv)
        data.append(d)
    outlines = np.array([_outline_row(case.vehicle1, "vehicle1"),
                         _outline_row(case.vehicle2, "vehicle2")])
    inverse = np.array([1 / float(case.vehicle1.mass), 1 / float(case.vehicle1.yaw_inertia),
                        1 / float(case.vehicle2.mass), 1 / float(case.vehicle2.yaw_inertia)])
    return data[0], data[1], outlines, inverse, vehicles


def _coefficients(case: Case) -> np.ndarray:
    """(MAX_IMPACTS, 3): each further impact's eps, beta and cap for the kernel."""
    rows = []
    for k in range(2, MAX_IMPACTS + 2):
        spec = impact_spec(case, k)
        if spec.law == "kudlich-slibar":
            raise InputError(f"impacts[{k - 2}].law: the Monte Carlo's event solves further "
                             f"impacts under Brach's laws only (brach, brach-capped)")
        cap = np.inf if spec.law == "brach" else float(spec.contact_friction)
        rows.append((float(spec.restitution), float(spec.beta), cap))
    return np.array(rows)


def _state(case: Case, result) -> np.ndarray:
    """Both vehicles' (x, y, psi, v_x, v_y, omega) just after the first impact (..., 2, 6)
    (the leading axes of the result's samples)."""
    rows = []
    for i in (1, 2):
        v = getattr(case, f"vehicle{i}")
        w = np.asarray(getattr(result, f"yaw_rate{i}"), float)
        vel = np.broadcast_to(np.asarray(getattr(result, f"velocity{i}"), float), w.shape + (2,))
        if bool(v.fixed):
            vel, w = np.zeros_like(vel), np.zeros_like(w)
        pose = np.broadcast_to(np.append(np.asarray(v.cg, float).reshape(2), float(v.heading)),
                               w.shape + (3,))
        rows.append(np.concatenate([pose, vel, w[..., None]], axis=-1))
    return np.stack(rows, axis=-2)


def approach_motion(vehicle: Vehicle, marks, times) -> tuple:
    """One vehicle's approach at ``times`` [s] < 0 (before the impact at 0): ``(position
    (n, 2), heading (n,), velocity (n, 2), yaw rate (n,))``.

    Free motion at the case's velocity and yaw rate; with tyre marks before the impact
    (:class:`pim.model.pre_impact.PreImpactMarks`) the CG slides straight along its
    impact velocity at the marks' constant deceleration ``a`` over their length ``L``
    (:func:`pim.model.pre_impact.mark_deceleration`, eq. 1), and moves freely at the speed
    at the marks' start before them: at ``tau = -t``, ``v = v_0 + a tau`` and the distance
    to the impact ``v_0 tau + a tau^2 / 2`` up to ``tau_L`` where it reaches ``L``.
    """
    tau = -np.asarray(times, float)
    cg = np.asarray(vehicle.cg, float).reshape(2)
    vel = np.asarray(vehicle.velocity, float).reshape(2)
    w, heading = float(np.asarray(vehicle.yaw_rate)), float(vehicle.heading)
    n = len(tau)
    speed = float(np.hypot(*vel))
    if marks is None or speed == 0.0 or marks.skid_length == 0.0:
        return (cg - tau[:, None] * vel, heading - w * tau, np.broadcast_to(vel, (n, 2)).copy(),
                np.full(n, w))
    a = float(mark_deceleration(marks.friction, marks.drag, marks.grade, STANDARD_GRAVITY))
    length = float(marks.skid_length)
    tau_l = (np.sqrt(speed ** 2 + 2 * a * length) - speed) / a if a > 0 else length / speed
    within = np.minimum(tau, tau_l)
    along = speed * within + 0.5 * a * within ** 2 + (speed + a * tau_l) * np.maximum(
        tau - tau_l, 0.0)
    unit = vel / speed
    now = speed + a * within
    return (cg - along[:, None] * unit, heading - w * tau, now[:, None] * unit, np.full(n, w))


def sliding_flags(states: np.ndarray, vehicle: RunoutVehicle | None,
                  friction: float = 1.0) -> np.ndarray:
    """Which wheels slide (N, 4) along states (N, 6): the slip speed the tyre resists
    (``f |s| + (1 - f) |s . e_t|``, :func:`pim.model.tyres.wheel_force`'s weights) above
    :data:`SLIDE_SPEED`; none without tyres (``vehicle`` None or ``friction`` 0)."""
    n = states.shape[0]
    if vehicle is None or friction == 0.0:
        return np.zeros((n, 4), bool)
    pos = np.asarray(vehicle.positions, float)
    braking = np.asarray(vehicle.braking, float)
    steer = np.broadcast_to(np.asarray(vehicle.steer, float), (4,))
    psi = states[:, 2:3]
    c, s = np.cos(psi), np.sin(psi)
    ax, ay = c * pos[:, 0] - s * pos[:, 1], s * pos[:, 0] + c * pos[:, 1]
    sx, sy = states[:, 3:4] - states[:, 5:6] * ay, states[:, 4:5] + states[:, 5:6] * ax
    lat = -np.sin(psi + steer) * sx + np.cos(psi + steer) * sy
    speed = braking * np.hypot(sx, sy) + (1 - braking) * np.abs(lat)
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
    """The :class:`pim.model.event.ImpactRecord` of an impact solved by :func:`pim.solve`."""
    v1, v2 = impact_case.vehicle1, impact_case.vehicle2
    impulse = np.asarray(result.impulse, float).reshape(2)
    before = np.array([np.asarray(v.velocity, float).reshape(2) for v in (v1, v2)])
    after = np.array([np.asarray(result.velocity1, float).reshape(2),
                      np.zeros(2) if bool(v2.fixed)
                      else np.asarray(result.velocity2, float).reshape(2)])
    w_after = np.array([float(np.asarray(result.yaw_rate1)),
                        0.0 if bool(v2.fixed) else float(np.asarray(result.yaw_rate2))])
    pd = np.array([float(pdof(impulse, float(v1.heading))),
                   np.nan if bool(v2.fixed) else float(pdof(-impulse, float(v2.heading)))])
    return ImpactRecord(
        time=float(time), point=np.asarray(impact_case.impact.point, float).reshape(2),
        normal_angle=float(impact_case.impact.normal_angle), law=spec.law,
        coefficients=_coefficients_of(spec, result), impulse=impulse, velocity_before=before,
        velocity_after=after,
        yaw_rate_before=np.array([float(np.asarray(v.yaw_rate)) for v in (v1, v2)]),
        yaw_rate_after=w_after, energy_loss=float(np.asarray(result.energy_loss)),
        pdof=pd, source=source)


def _contact_case(case: Case, state: np.ndarray, contact: np.ndarray,
                  spec: ImpactSpec) -> Case:
    """The impact case of a further contact: both vehicles at ``state`` (2, 6), C and
    Gamma from the outlines (``contact``: depth, C, n) unless ``spec`` states them."""
    vehicles = []
    for i in (1, 2):
        v = getattr(case, f"vehicle{i}")
        if not bool(v.fixed):
            row = state[i - 1]
            v = replace(v, cg=row[:2].copy(), heading=float(row[2]), velocity=row[3:5].copy(),
                        yaw_rate=float(row[5]))
        vehicles.append(v)
    point = contact[1:3] if spec.point is None else np.asarray(spec.point, float)
    gamma = (float(np.arctan2(contact[4], contact[3])) if spec.normal_angle is None
             else float(spec.normal_angle))
    impact = Impact(point.copy(), gamma, restitution=spec.restitution,
                    beta=None if spec.law == "kudlich-slibar" else spec.beta, law=spec.law,
                    contact_friction=None if spec.law == "brach" else spec.contact_friction)
    return Case(vehicles[0], vehicles[1], impact, name=case.name)


def _post_state(state: np.ndarray, impact_case: Case, result) -> np.ndarray:
    """``state`` (2, 6) with the impact's post-impact velocities and yaw rates."""
    out = state.copy()
    out[0, 3:5] = np.asarray(result.velocity1, float).reshape(2)
    out[0, 5] = float(np.asarray(result.yaw_rate1))
    if not bool(impact_case.vehicle2.fixed):
        out[1, 3:5] = np.asarray(result.velocity2, float).reshape(2)
        out[1, 5] = float(np.asarray(result.yaw_rate2))
    return out


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


def _run_out(case: Case, scene, state: np.ndarray, watch: _Watch) -> _Run:
    """Steps 3-5 of one event (module notes): the kernel runs to a contact, :func:`pim.solve`
    solves it, the kernel goes on, until rest or the time limit."""
    from ..model.event_kernel import run_event  # compiled event: numba on first use

    t, allowed, rows, impacts = 0.0, None, [], []
    while True:
        size = int((watch.max_time - t) / watch.step) + 64
        run = run_event(scene, state[None], start_time=t, allowed=allowed, solve=False,
                        record=size, step=watch.step, max_time=watch.max_time,
                        stop_speed=REST_SPEED, tolerance=watch.tolerance)
        rows.append(run.record)
        status, t, state = run.status[0], float(run.time[0]), run.final[0]
        allowed = run.allowed
        if status == "record":
            rows[-1] = rows[-1][:-1]            # the next part starts with this state
            continue
        if status != "contact":
            return _Run(np.concatenate(rows), impacts, tuple(~run.moving[0]), status)
        if len(impacts) == MAX_IMPACTS:
            raise InputError(f"event: more than {MAX_IMPACTS} impacts after the first (the "
                             f"vehicles stay in contact: a contact without end is refused)")
        spec = impact_spec(case, len(impacts) + 2)
        impact_case = _contact_case(case, state, run.contact[0], spec)
        impact_case, result = _solved(impact_case)
        if not bool(np.asarray(result.approaching)):
            rows[-1] = rows[-1][:-1]            # C does not close under the law's test
            continue
        if float(np.asarray(result.energy_loss)) < -1e-9 * (1 + _energy(impact_case)):
            raise InputError(f"event: the impact at t = {t:.4g} s gains energy under law "
                             f"{spec.law} (refused)")
        impacts.append(impact_record(impact_case, result, t, spec, "outlines"))
        state = _post_state(state, impact_case, result)
        allowed = np.array([max(float(run.contact[0, 0]), 0.0)])


def _solved(impact_case: Case) -> tuple:
    """``(case, pim.solve(case))`` of a further impact; under Brach's laws an answer that
    gains energy is solved again frictionless (beta 0), the rule of
    :func:`pim.model.event_formula.capped_impact` (Kane and Levinson's paradox)."""
    result = solve(impact_case)
    if impact_case.impact.law != "kudlich-slibar" and float(
            np.asarray(result.energy_loss)) < 0.0:
        impact_case = replace(impact_case, impact=replace(impact_case.impact, beta=0.0))
        result = solve(impact_case)
    return impact_case, result


def _energy(case: Case) -> float:
    return float(sum(kinetic_energy(v.mass, v.yaw_inertia, v.velocity, v.yaw_rate)
                     for v in (case.vehicle1, case.vehicle2)))


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
    if not (np.isfinite(approach) and approach >= 0):
        raise InputError(f"approach must be a finite time >= 0 [s], got {approach!r}")
    free = tyre_friction is not None and float(tyre_friction) == 0.0
    if tyre_friction is not None and not (np.isfinite(tyre_friction) and tyre_friction >= 0):
        raise InputError(f"tyre_friction must be a finite number >= 0, got {tyre_friction!r}")
    limit = (FREE_MOTION_TIME if free else MAX_TIME) if max_time is None else float(max_time)
    if not limit > 0:
        raise InputError(f"max_time must be > 0 [s], got {max_time!r}")
    data1, data2, outlines, inverse, vehicles = scene_data(case, tyre_friction)
    from ..model.event_kernel import EventScene  # compiled event: numba on first use

    scene = EventScene(data1, data2, outlines[None], inverse[None], np.zeros((1, 1, 3)))
    result = solve(case, eps, beta)
    choice = resolve_law(case, eps, beta)
    first_spec = ImpactSpec(law=choice.law, contact_friction=choice.contact_friction)
    first = impact_record(case, result, 0.0, first_spec, "case")
    run = _run_out(case, scene, _state(case, result),
                   _Watch(step, limit, np.inf if single_impact else tolerance))
    return _assemble(case, (first, *run.impacts), run, approach,
                     (vehicles, 0.0 if free else 1.0))


def _assemble(case: Case, impacts: tuple, run: _Run, approach: float, tyres: tuple) -> Event:
    """The event's samples: the approach, the state just before the first impact, and the
    run-out's rows (the first is the state just after it)."""
    before = np.arange(-approach, 0.0, APPROACH_SAMPLE) if approach > 0 else np.zeros(0)
    ev = case.evidence
    tracks = []
    for i in (1, 2):
        vehicle = getattr(case, f"vehicle{i}")
        marks = None if ev is None or getattr(ev, f"vehicle{i}") is None else getattr(
            ev, f"vehicle{i}").pre_impact
        pre = approach_motion(vehicle, marks, np.append(before, 0.0))
        cols = run.rows[:, 1 + 6 * (i - 1):7 + 6 * (i - 1)]
        states = np.concatenate([np.column_stack([pre[0], pre[1], pre[2], pre[3]]), cols])
        sliding = sliding_flags(states, tyres[0][i - 1], tyres[1])
        sliding[:len(before) + 1] = False
        wheels = None if tyres[0][i - 1] is None else tyres[0][i - 1].positions
        tracks.append(Track(states[:, :2], states[:, 2], states[:, 3:5], states[:, 5],
                            sliding=sliding, outline=vehicle_outline(vehicle),
                            fixed=bool(vehicle.fixed), wheels=wheels))
    time = np.concatenate([before, [0.0], run.rows[:, 0]])
    stopped = tuple(bool(s) for s in run.stopped)
    rest = float(time[-1]) if all(stopped) else None
    notes = []
    if not all(stopped):
        notes.append(f"still moving at the time limit ({time[-1]:.3g} s after the impact)")
    return Event(time, tracks[0], tracks[1], phase_labels(time, [i.time for i in impacts],
                                                           rest),
                 impacts=tuple(impacts), source="analytic", stopped=stopped,
                 notes=tuple(notes))


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

    The run-out, the outline watch and every further impact of :func:`event`, the further
    impacts solved in the kernel (:func:`pim.model.event_formula.capped_impact`: Brach's
    laws, the case's ``[[impacts]]`` or the defaults), no timeline kept.

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
    start = np.broadcast_to(_state(case, _Motion(velocity, yaw_rate)), (n, 2, 6)).copy()
    if poses is not None:
        start[:, :, :3] = poses
    if bool(case.vehicle2.fixed):
        start[:, 1, 3:] = 0.0
    scene = EventScene(data1, data2, outlines[None], np.reshape(inverse, (-1, 4)),
                       _coefficients(case)[None])
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
