"""The finite-duration contact stepped by pymunk: PIM's assumptions relaxed, not emulated.

:func:`simulate_compliant` integrates the two bodies with pymunk (Chipmunk2D) while the
project computes the contact force (:mod:`sim.contact_law`) from the bodies' state in
every step: the bodies carry no collision shapes, so Chipmunk's own rigid contact response
never acts. The force is applied through each body's ``velocity_func``, which Chipmunk calls
after it has moved *all* bodies in the step, so the force is evaluated at the new positions
(and the old velocities): symplectic Euler,

    x_{n+1} = x_n + v_n dt,    v_{n+1} = v_n + F(x_{n+1}, v_n) dt / m,

stable for omega dt < 2, with linear momentum and angular momentum about any fixed point
conserved to round-off (both bodies receive equal and opposite forces at the same point in
the same step). Its velocities belong to the middle of the steps (the leapfrog, second
order for forces of the positions): the slip the friction spring integrates is taken at the
middle of the step (:func:`midstep`), the tyre forces at its end (:meth:`_Stepper.ahead`),
the run starts with a half kick, the post-impact velocities are taken back to the
separation instant and the release of a plastic friction force (r = 0) is located inside
its step (:func:`plastic_release`), so that every scene converges at second order
(docs/contact-model.md, "Convergence of pymunk to the reference"). The memory of the
contact law is updated by its implicit step: delta_max = max(delta_max, delta), the
friction spring by :func:`sim.contact_law.tangential_step`.

The contact ends when the normal force has returned to zero on unloading (delta below the
permanent crush); the separation time is interpolated inside the last step. A step too
coarse to resolve the contact (fewer than ``settings.min_steps`` per estimated contact
time), outlines that pass through each other, a contact that never ends, or no contact at
all raise :class:`sim.SimulationError`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np
import pymunk

import pim
from pim.model.numbers import speed_text

from .compliant_setup import (
    CompliantProblem,
    CompliantResult,
    CompliantSettings,
    ContactHistory,
    build_problem,
    kinetic_energy,
    placed_outlines,
    point_contact,
    reversal,
    rotate,
)
from .contact_law import normal_force, permanent_crush, tangential_force, tangential_step
from .contact_tyres import tyre_force
from .failures import SimulationError
from .overlap import outline_overlap, overlap_area
from .result import Trajectory
from .secondary import find_secondary_impact

__all__ = ["simulate_compliant", "step_size", "outline_start"]


def step_size(problem: CompliantProblem) -> float:
    """pymunk's step [s]: ``settings.dt`` or the contact time / ``steps_per_contact``.

    Raises
    ------
    SimulationError
        "tunnelled": fewer than ``settings.min_steps`` steps per estimated contact time.
    """
    s = problem.settings
    dt = s.dt if s.dt is not None else problem.duration_estimate / s.steps_per_contact
    steps = problem.duration_estimate / dt
    if steps < s.min_steps:
        travel = problem.speed_scale * dt
        raise SimulationError(
            "tunnelled",
            f"dt = {dt:.3g} s resolves the {problem.duration_estimate * 1e3:.3g} ms contact in "
            f"{steps:.2g} steps (< min_steps = {s.min_steps}); the vehicles move "
            f"{travel:.3g} m per step: the contact would be crossed or unstable. Reduce dt "
            f"(or leave it None)", 0)
    return dt


def outline_start(problem: CompliantProblem) -> float:
    """When the outlines first touch [s] along the free pre-impact paths (<= 0), or 0.

    The case places the bodies at PIM's impact configuration (t = 0), where illustrative
    outlines often already overlap; the outline contact starts where they first touch,
    found by stepping back along the free paths and bisecting.
    """
    def overlapping(t: float) -> bool:
        state = _free_state(problem.state0, t)
        poly1, poly2 = placed_outlines(problem, state)
        return overlap_area(poly1, _obstacle(problem, poly2)) > 0.0

    if not overlapping(0.0):
        return 0.0
    step = 0.01
    back = step
    while overlapping(-back):
        back += step
        if back > 10.0:
            raise SimulationError("tunnelled", "the outlines overlap along the whole 10 s of "
                                  "pre-impact path: they never approach each other", 0)
    low, high = -back, -back + step       # apart at low, overlapping at high
    for _ in range(60):
        mid = 0.5 * (low + high)
        if overlapping(mid):
            high = mid
        else:
            low = mid
    return low


def _free_state(state0: np.ndarray, t: float) -> np.ndarray:
    s = state0.copy()
    s[0:2] += state0[3:5] * t
    s[2] += state0[5] * t
    s[6:8] += state0[9:11] * t
    s[8] += state0[11] * t
    return s


def _obstacle(problem: CompliantProblem, poly2):
    """Vehicle 2's outline, or a 200 m x 10 m block behind the plane for a bare barrier."""
    if poly2 is not None:
        return poly2
    point = np.asarray(problem.case.impact.point, float).reshape(2)
    gamma = float(problem.case.impact.normal_angle)
    n = np.array([math.cos(gamma), math.sin(gamma)])
    t = np.array([-n[1], n[0]])
    # counter-clockwise: face along t through C, 10 m deep on the -n side
    return np.array([point + 100 * t, point + 100 * t - 10 * n, point - 100 * t - 10 * n,
                     point - 100 * t])


@dataclass(frozen=True)
class ContactMemory:
    """What the contact law remembers from one step to the next (SI).

    Attributes
    ----------
    on : bool
        Contact forces still act (False once separated, and in the free motion after).
    started : bool
        The crush has been positive.
    delta_max, delta, prev_delta : float
        Largest crush so far, this step's and the last step's crush [m].
    z : float
        Elastic tangential displacement of the friction spring [m].
    normal : ndarray (2,) or None
        Outline contact: the normal of the last step with overlap.
    separated : bool
        The normal force returned to zero on unloading in this step.
    slip : float
        Tangential slip of the last step [m/s] (at the middle of the step).
    friction_force : ndarray (2,) or None
        Friction force on vehicle 1 applied in the last step [N].
    """

    on: bool = True
    started: bool = False
    delta_max: float = 0.0
    delta: float = 0.0
    prev_delta: float = 0.0
    z: float = 0.0
    normal: np.ndarray | None = None
    separated: bool = False
    slip: float = 0.0
    friction_force: np.ndarray | None = None


@dataclass(frozen=True)
class ContactGeometry:
    """Where and how the bodies touch at one state.

    Attributes
    ----------
    point : numpy.ndarray
        Contact point, shape (2,) [m] (global frame).
    normal : numpy.ndarray
        Unit contact normal n, shape (2,) [-].
    tangent : numpy.ndarray
        Unit tangent t, shape (2,) [-].
    delta : float
        Crush along the normal [m].
    slip_t : float
        Relative velocity at the point along t [m/s].
    slip_n : float
        Relative velocity at the point along n [m/s].
    overlap : bool
        Whether the outlines overlap (always True for the point contact).
    """

    point: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    delta: float
    slip_t: float
    slip_n: float = 0.0
    overlap: bool = True


@dataclass(frozen=True)
class ContactForce:
    """The contact force of one step.

    Attributes
    ----------
    force : numpy.ndarray
        Total contact force on vehicle 1, shape (2,) [N].
    normal_force : float
        Normal component F_n [N].
    tangential_force : float
        Tangential (friction) component F_t [N].
    sticking : bool
        Whether the friction spring sticks in this step (no sliding).
    """

    force: np.ndarray
    normal_force: float
    tangential_force: float
    sticking: bool


Kinematics = tuple  # (x1, a1, v1, w1, x2, a2, v2, w2): positions, angles, velocities, yaw rates


def read_kinematics(body1, body2) -> Kinematics:
    """Both bodies' position (2,), angle, velocity (2,), yaw rate from pymunk."""
    out = []
    for body in (body1, body2):
        p, v = body.position, body.velocity
        out += [np.array([p.x, p.y]), body.angle, np.array([v.x, v.y]), body.angular_velocity]
    return tuple(out)


def midstep(kin: Kinematics, dt: float) -> Kinematics:
    """``kin`` with the positions and angles moved back half a step of their velocities.

    In the velocity callback pymunk has moved the bodies from t_n to t_{n+1} with the
    velocities it holds, x_{n+1} = x_n + v dt: those velocities are the ones of the middle
    of the step, and this is the state that goes with them (docs/contact-model.md,
    "Integration").
    """
    x1, a1, v1, w1, x2, a2, v2, w2 = kin
    h = 0.5 * dt
    return (x1 - v1 * h, a1 - w1 * h, v1, w1, x2 - v2 * h, a2 - w2 * h, v2, w2)


def contact_geometry(problem: CompliantProblem, memory: ContactMemory, kin: Kinematics,
                     obstacle, when: float, dt: float = 0.0) -> ContactGeometry:
    """The point or outline contact at ``kin`` (docs/contact-model.md).

    The point contact's crush is taken at ``kin`` (the end of the step) and, with ``dt`` >
    0, its tangential slip at :func:`midstep` (the middle of the step, where pymunk's
    velocities belong): the slip the friction spring integrates over the step is then
    second-order accurate, as the crush is (with the slip at the end of the step a sticking
    contact converged to first order only).

    Raises
    ------
    SimulationError
        "tunnelled": the outline normal flipped (the outlines passed through each other).
    """
    if problem.geometry == "point":
        point, n, t, delta, slip_n, slip_t = point_contact(problem, *kin)
        if dt > 0.0:
            slip_t = point_contact(problem, *midstep(kin, dt))[5]
        return ContactGeometry(point, n, t, delta, slip_t, slip_n)
    x1, a1, v1, w1, x2, a2, v2, w2 = kin
    poly1, poly2 = placed_outlines(problem, np.r_[x1, a1, v1, w1, x2, a2, v2, w2])
    ov = outline_overlap(poly1, poly2 if poly2 is not None else obstacle)
    if ov.area <= 0.0:
        n = memory.normal if memory.normal is not None else ov.normal
        return ContactGeometry(np.zeros(2), n, np.array([-n[1], n[0]]), 0.0, 0.0, 0.0, False)
    n = ov.normal
    if memory.normal is not None and n @ memory.normal < 0.0:
        raise SimulationError(
            "tunnelled", f"the contact normal of the outlines flipped at t = {when:.4g} s "
            f"(crush {ov.depth:.3g} m): the outlines passed through each other; reduce dt or "
            f"raise the stiffness", 0)
    c = ov.centroid
    d1, d2 = c - x1, c - x2
    rel = v1 + w1 * np.array([-d1[1], d1[0]]) - v2 - w2 * np.array([-d2[1], d2[0]])
    t = np.array([-n[1], n[0]])
    return ContactGeometry(c, n, t, ov.depth, float(rel @ t), float(rel @ n))


def contact_step(problem: CompliantProblem, memory: ContactMemory, geo: ContactGeometry,
                 dt: float) -> tuple[ContactMemory, ContactForce]:
    """One step of the contact law (:mod:`sim.contact_law`): the new memory and the force.

    Implicit in the memory: delta_max = max(delta_max, delta), the friction spring by
    :func:`sim.contact_law.tangential_step`; separation when the normal force has returned
    to zero on unloading.
    """
    delta = geo.delta
    started = memory.started or delta > 0.0
    delta_max, on, fn = memory.delta_max, memory.on, 0.0
    if started:
        delta_max = max(delta_max, delta)
        fn = float(normal_force(delta, delta_max, problem.eps, problem.preload,
                                problem.stiffness))
        if fn <= 0.0 and delta < delta_max:
            on, fn = False, 0.0
    z, ft, sticking = 0.0, 0.0, False
    if problem.friction > 0.0 and on:
        kt = problem.tangential_stiffness
        limit = problem.friction * fn / kt
        z = float(tangential_step(memory.z, geo.slip_t, dt, limit,
                                  problem.tangential_recovery))
        ft = float(tangential_force(z, kt, problem.friction * fn))
        sticking = abs(z) < limit * (1 - 1e-9)
    new = replace(memory, on=on, started=started, delta_max=delta_max, delta=delta,
                  prev_delta=memory.delta, z=z,
                  normal=geo.normal if geo.overlap else memory.normal, separated=not on,
                  slip=geo.slip_t, friction_force=ft * geo.tangent)
    force = fn * geo.normal + ft * geo.tangent + plastic_release(problem, memory, geo)
    return new, ContactForce(force, fn, ft, sticking)


def plastic_release(problem: CompliantProblem, memory: ContactMemory,
                    geo: ContactGeometry) -> np.ndarray:
    """Correction [N] for a friction force released inside the last kick (r = 0).

    With tangential recovery r = 0 the friction force drops to zero the moment the slip
    turns back against z. The last kick applied the force ``memory.friction_force`` over
    the whole of [t_{n-1/2}, t_{n+1/2}] (the mid-steps where the slips ``memory.slip`` and
    ``geo.slip_t`` belong); the slip, interpolated linearly, turned at t* inside it, so the
    share (t_{n+1/2} - t*) / dt = s_1 / (s_1 - s_0) of that impulse is taken back in this
    step. Without it the jump is located to within a step only and the scene converges at
    first order (docs/contact-model.md, "Convergence of pymunk to the reference").
    """
    s0, s1 = memory.slip, geo.slip_t
    if (problem.tangential_recovery > 0.0 or memory.friction_force is None
            or not (memory.z * s1 < 0.0 and s0 * s1 < 0.0)):
        return np.zeros(2)
    return -memory.friction_force * (s1 / (s1 - s0))


def moments(point, force, x1, x2) -> tuple[float, float]:
    """Moments [N m] of ``force`` on vehicle 1 and of -``force`` on vehicle 2 at ``point``."""
    d1, d2 = point - x1, point - x2
    return (float(d1[0] * force[1] - d1[1] * force[0]),
            float(-(d2[0] * force[1] - d2[1] * force[0])))


def tyre_loads(problem: CompliantProblem, kin: Kinematics):
    """Tyre forces [N], moments [N m] on both vehicles and their power [W] (0 without)."""
    x1, a1, v1, w1, x2, a2, v2, w2 = kin
    zero = np.zeros(2)
    if problem.tyre_friction <= 0.0:
        return zero, 0.0, zero, 0.0, 0.0
    f1, m1 = tyre_force(v1, w1, a1, problem.wheels1, problem.load1, problem.tyre_friction,
                        problem.tyre_mode)
    power = float(f1 @ v1 + m1 * w1)
    f2, m2 = zero, 0.0
    if not problem.fixed2:
        f2, m2 = tyre_force(v2, w2, a2, problem.wheels2, problem.load2,
                            problem.tyre_friction, problem.tyre_mode)
        power += float(f2 @ v2 + m2 * w2)
    return f1, m1, f2, m2, power


@dataclass
class ContactTally:
    """What the result reports, summed over the contact steps (SI).

    Attributes
    ----------
    impulse : numpy.ndarray
        Contact impulse on vehicle 1, sum of F dt, shape (2,) [N s].
    moment_sum : numpy.ndarray
        Sum of |F| dt times the contact point, shape (2,) [N s m] (impulse centroid numerator).
    normal_sum : numpy.ndarray
        Sum of |F| dt times the contact normal, shape (2,) [N s].
    body_point_sum : numpy.ndarray
        As ``moment_sum`` with the point relative to vehicle 1's CG in its body frame [N s m].
    body_normal_sum : numpy.ndarray
        As ``normal_sum`` with the normal in vehicle 2's body frame [N s].
    weight : float
        Sum of |F| dt, the weight of the centroids above [N s].
    peak : float
        Largest contact force magnitude [N].
    tyre_work : float
        Work done by the tyre forces during contact [J].
    stick_time : float
        Time the friction spring stuck [s].
    contact_time : float
        Time in contact [s].
    directions : set
        Signs (+1, -1) of the friction-spring stretch z while the contact slid.
    initial_sign : float or None
        Sign of the tangential slip at first contact (None before contact) [-].
    last_slip : float
        Tangential slip velocity in the last contact step [m/s].
    last_slip_n : float
        Outline contact: normal relative velocity v_rel . n in the last contact step [m/s].
    rows : list or None
        The contact history, one tuple per step (None when not recorded).
    """

    impulse: np.ndarray = field(default_factory=lambda: np.zeros(2))
    moment_sum: np.ndarray = field(default_factory=lambda: np.zeros(2))
    normal_sum: np.ndarray = field(default_factory=lambda: np.zeros(2))
    body_point_sum: np.ndarray = field(default_factory=lambda: np.zeros(2))   # vehicle 1
    body_normal_sum: np.ndarray = field(default_factory=lambda: np.zeros(2))  # vehicle 2
    weight: float = 0.0
    peak: float = 0.0
    tyre_work: float = 0.0
    stick_time: float = 0.0
    contact_time: float = 0.0
    directions: set = field(default_factory=set)   # signs of z while it slid
    initial_sign: float | None = None               # sign of the slip at first contact
    last_slip: float = 0.0                          # slip in the last contact step [m/s]
    last_slip_n: float = 0.0                        # outline: v_rel . n there [m/s]
    rows: list | None = None                        # the contact history

    def add(self, geo: ContactGeometry, cf: ContactForce, z: float, dt: float,
            when: float, mu: float, kin: Kinematics) -> None:
        """Account for one step in contact."""
        size = math.hypot(cf.force[0], cf.force[1])
        self.impulse += cf.force * dt
        self.moment_sum += size * dt * geo.point
        self.normal_sum += size * dt * geo.normal
        self.body_point_sum += size * dt * rotate(geo.point - kin[0], -kin[1])
        self.body_normal_sum += size * dt * rotate(geo.normal, -kin[5])
        self.weight += size * dt
        self.contact_time += dt
        self.stick_time += dt if cf.sticking else 0.0
        self.peak = max(self.peak, size)
        if mu > 0.0 and not cf.sticking and z != 0.0:
            self.directions.add(1 if z > 0 else -1)
        if self.rows is not None:
            self.rows.append((when, geo.delta, cf.force[0], cf.force[1], cf.normal_force,
                              cf.tangential_force, geo.slip_t, cf.sticking, geo.point[0],
                              geo.point[1]))


class _Stepper:
    """Computes the forces once per step and feeds them to pymunk's velocity callbacks.

    An exception raised inside a callback (a KeyboardInterrupt included) cannot cross
    Chipmunk's C frames: cffi would print and ignore it. It is kept in ``error`` and
    :meth:`step` re-raises it after ``space.step`` returns.
    """

    def __init__(self, problem: CompliantProblem, space, body1, body2, dt: float,
                 start: float):
        self.p, self.space, self.b1, self.b2 = problem, space, body1, body2
        self.dt, self.start, self.step_count, self.done_step = dt, start, 0, -1
        self.memory = ContactMemory()
        self.tally = ContactTally(rows=[] if problem.settings.record else None)
        self.loads = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))   # (fx, fy, torque) per body
        self.error: BaseException | None = None
        self.obstacle = (_obstacle(problem, None) if problem.geometry == "outline"
                         and problem.outline2 is None else None)
        body1.velocity_func = self.velocity1
        if body2.body_type == pymunk.Body.DYNAMIC:
            body2.velocity_func = self.velocity2

    def accelerations(self) -> tuple:
        """(a1 (2,), yaw acceleration 1, a2, yaw acceleration 2) of the last kick [SI]."""
        (fx1, fy1, m1), (fx2, fy2, m2) = self.loads
        p = self.p
        if p.fixed2:
            return np.array([fx1, fy1]) / p.mass1, m1 / p.inertia1, np.zeros(2), 0.0
        return (np.array([fx1, fy1]) / p.mass1, m1 / p.inertia1,
                np.array([fx2, fy2]) / p.mass2, m2 / p.inertia2)

    def ahead(self, kin: Kinematics, span: float | None = None) -> Kinematics:
        """``kin`` with the velocities moved on by ``span`` (default dt / 2) of the last
        kick's accelerations: from the middle of the step, where pymunk's velocities
        belong, to its end, where the velocity-dependent tyre force is wanted."""
        x1, a1, v1, w1, x2, a2, v2, w2 = kin
        h = 0.5 * self.dt if span is None else span
        acc1, alpha1, acc2, alpha2 = self.accelerations()
        return (x1, a1, v1 + acc1 * h, w1 + alpha1 * h, x2, a2, v2 + acc2 * h,
                w2 + alpha2 * h)

    def half_kick(self) -> None:
        """Start the leapfrog: the velocities of the first step are those at dt / 2, so the
        forces at t = 0 (the tyres; the contact force is zero there) act for half a step."""
        if self.p.tyre_friction <= 0.0:
            return
        t1, n1, t2, n2, _ = tyre_loads(self.p, read_kinematics(self.b1, self.b2))
        self.loads = ((float(t1[0]), float(t1[1]), float(n1)),
                      (float(t2[0]), float(t2[1]), float(n2)))
        _, _, v1, w1, _, _, v2, w2 = self.ahead(read_kinematics(self.b1, self.b2))
        for body, v, w in ((self.b1, v1, w1), (self.b2, v2, w2)):
            if body.body_type == pymunk.Body.DYNAMIC:
                body.velocity, body.angular_velocity = (float(v[0]), float(v[1])), float(w)

    def step(self) -> None:
        """One pymunk step; re-raises what a callback raised."""
        self.space.step(self.dt)
        self.step_count += 1
        if self.error is not None:
            error, self.error = self.error, None
            raise error

    def velocity1(self, body, gravity, damping, dt):
        self._callback(body, 0, gravity, damping, dt)

    def velocity2(self, body, gravity, damping, dt):
        self._callback(body, 1, gravity, damping, dt)

    def _callback(self, body, index, gravity, damping, dt) -> None:
        try:
            if self.error is not None:
                return
            if self.done_step != self.step_count:
                self.done_step = self.step_count
                self.loads = self._loads(read_kinematics(self.b1, self.b2))
            fx, fy, torque = self.loads[index]
            body.force = (fx, fy)
            body.torque = torque
            pymunk.Body.update_velocity(body, gravity, damping, dt)
        except BaseException as exc:      # noqa: BLE001 -- re-raised after space.step
            self.error = exc

    def _loads(self, kin: Kinematics):
        f1 = f2 = np.zeros(2)
        m1 = m2 = 0.0
        when = self.start + (self.step_count + 1) * self.dt
        mem, tally = self.memory, self.tally
        if mem.on:
            geo = contact_geometry(self.p, mem, kin, self.obstacle, when, self.dt)
            if mem.started or geo.delta > 0.0:
                if tally.initial_sign is None:
                    tally.initial_sign = math.copysign(1.0, geo.slip_t) if geo.slip_t else 0.0
                tally.last_slip = geo.slip_t
            if self.p.geometry == "outline" and geo.overlap:
                tally.last_slip_n = geo.slip_n
            mem, cf = contact_step(self.p, mem, geo, self.dt)
            self.memory = mem
            if mem.on and mem.started:
                tally.add(geo, cf, mem.z, self.dt, when, self.p.friction, kin)
                f1, f2 = cf.force, -cf.force
                m1, m2 = moments(geo.point, cf.force, kin[0], kin[4])
        t1, n1, t2, n2, power = tyre_loads(self.p, self.ahead(kin))
        tally.tyre_work += power * self.dt
        f1, f2, m1, m2 = f1 + t1, f2 + t2, m1 + n1, m2 + n2
        return ((float(f1[0]), float(f1[1]), float(m1)), (float(f2[0]), float(f2[1]),
                                                          float(m2)))


def _row(t: float, b1, b2) -> tuple:
    p1, v1, p2, v2 = b1.position, b1.velocity, b2.position, b2.velocity
    return (t, p1.x, p1.y, b1.angle, p2.x, p2.y, b2.angle, v1.x, v1.y, b1.angular_velocity,
            v2.x, v2.y, b2.angular_velocity)


def _check_approach(problem: CompliantProblem, state: np.ndarray) -> None:
    """The point contact must start with the vehicles approaching at C."""
    *_, slip_n, _ = point_contact(problem, state[0:2], state[2], state[3:5], state[5],
                                  state[6:8], state[8], state[9:11], state[11])
    if not slip_n < 0.0:
        raise SimulationError("no_contact", f"no contact: the vehicles do not approach at "
                              f"C (u_n = {speed_text(slip_n, '.6g')} >= 0)", 0)


def _space(problem: CompliantProblem, state: np.ndarray):
    """A gravity-free pymunk space with both bodies at ``state`` (no shapes)."""
    space = pymunk.Space()
    space.gravity = (0.0, 0.0)
    space.damping = 1.0
    body1 = pymunk.Body(problem.mass1, problem.inertia1)
    body2 = (pymunk.Body(body_type=pymunk.Body.STATIC) if problem.fixed2
             else pymunk.Body(problem.mass2, problem.inertia2))
    for body, k in ((body1, 0), (body2, 6)):
        body.position = (float(state[k]), float(state[k + 1]))
        body.angle = float(state[k + 2])
        if body.body_type == pymunk.Body.DYNAMIC:
            body.velocity = (float(state[k + 3]), float(state[k + 4]))
            body.angular_velocity = float(state[k + 5])
    space.add(body1, body2)
    return space, body1, body2


def _run_contact(stepper: _Stepper, rows: list | None) -> None:
    """Step until the contact separates (or fail: never separated, never touched)."""
    s, dt, start = stepper.p.settings, stepper.dt, stepper.start
    max_steps = int(math.ceil(s.max_contact_time / dt)) + 1
    while True:
        stepper.step()
        if rows is not None:
            rows.append(_row(start + stepper.step_count * dt, stepper.b1, stepper.b2))
        if stepper.memory.separated:
            break
        if stepper.step_count >= max_steps:
            started = stepper.memory.started
            text = (f"the contact still pushed after {s.max_contact_time:g} s "
                    f"(max_contact_time)" if started else
                    f"the outlines never touched within {s.max_contact_time:g} s")
            raise SimulationError("never_separated" if started else "no_contact", text,
                                  stepper.step_count)
    problem, tally, mem = stepper.p, stepper.tally, stepper.memory
    if problem.geometry == "outline" and tally.last_slip_n < -1e-3 * problem.speed_scale:
        raise SimulationError(
            "tunnelled", f"the outlines passed through each other: their overlap ended at "
            f"t = {start + stepper.step_count * dt:.4g} s while they still approached at "
            f"{speed_text(-tally.last_slip_n, '.3g')} (mean crush {mem.delta_max:.3g} m); the "
            f"crush is deeper than the vehicles: raise the stiffness", stepper.step_count)


def _separation_time(stepper: _Stepper, delta_p: float) -> float:
    """The separation instant [s], interpolated between the last two crushes (delta_p)."""
    mem = stepper.memory
    frac = 1.0
    if mem.prev_delta != mem.delta:
        frac = min(max((mem.prev_delta - delta_p) / (mem.prev_delta - mem.delta), 0.0), 1.0)
    return stepper.start + (stepper.step_count - 1 + frac) * stepper.dt


def _post_velocities(stepper: _Stepper, t_end: float) -> tuple:
    """(v1, v2, w1, w2) at the separation instant ``t_end``.

    pymunk's velocities after the last step belong half a step past its end; without tyres
    nothing acts after separation and they are the answer; with tyres they are taken back
    to ``t_end`` along the last kick's (tyre) accelerations.
    """
    now = stepper.start + stepper.step_count * stepper.dt
    kin = read_kinematics(stepper.b1, stepper.b2)
    if stepper.p.tyre_friction > 0.0:
        kin = stepper.ahead(kin, -(0.5 * stepper.dt + now - t_end))
    _, _, v1, w1, _, _, v2, w2 = kin
    return np.array(v1), np.array(v2), float(w1), float(w2)


def _records(problem: CompliantProblem, rows: list, stepper: _Stepper, separation: int):
    """Trajectory, contact history and the secondary impact time from the recorded rows."""
    arr = np.array(rows, float)
    trajectory = Trajectory(
        time=arr[:, 0], position1=arr[:, 1:3], angle1=arr[:, 3], position2=arr[:, 4:6],
        angle2=arr[:, 6], velocity1=arr[:, 7:9], yaw_rate1=arr[:, 9],
        velocity2=arr[:, 10:12], yaw_rate2=arr[:, 12], impact_index=separation,
        outline1=problem.outline1, outline2=problem.outline2, fixed2=problem.fixed2)
    h = np.array(stepper.tally.rows, float).reshape(-1, 10)
    history = ContactHistory(time=h[:, 0], crush=h[:, 1], force=h[:, 2:4],
                             normal_force=h[:, 4], tangential_force=h[:, 5], slip=h[:, 6],
                             sticking=h[:, 7].astype(bool), point=h[:, 8:10])
    found = find_secondary_impact(trajectory, separation)
    return trajectory, history, None if found is None else found.time


def simulate_compliant(case: pim.Case, eps, stiffness, friction=0.0, geometry="point",
                       tyre_friction=0.0, settings: CompliantSettings | None = None
                       ) -> CompliantResult:
    """Simulate the impact with a finite-duration crush contact, stepped by pymunk.

    Takes only physical inputs (never a PIM output). docs/contact-model.md has the
    equations and the sources of the default parameters.

    Parameters
    ----------
    case : pim.Case
        A single case: masses, inertias, pre-impact motion, C and Gamma (the point contact
        starts at C at t = 0 with normal n at Gamma), outlines for ``geometry="outline"``.
    eps : float
        Restitution of the crush hysteresis [-] in [0, 1] (exact for a point mass).
    stiffness : float
        Loading stiffness k [N/m] > 0 (a car: about 7.5e5, :data:`DEFAULT_STIFFNESS`).
    friction : float
        Coulomb coefficient mu_c between the vehicles [-] >= 0.
    geometry : {"point", "outline"}
        Point against the plane, or the outlines crushing into each other.
    tyre_friction : float
        Tyre/ground friction mu_tyre [-] >= 0 acting during the contact (0: none).
    settings : CompliantSettings, optional
        Numerics, and the tangential stiffness and recovery of the friction spring.

    Returns
    -------
    CompliantResult

    Raises
    ------
    ValueError
        Bad input (the field is named).
    SimulationError
        "no_contact", "never_separated", "tunnelled".
    """
    wall = time.perf_counter()
    problem = build_problem(case, eps, stiffness, friction, geometry, tyre_friction, settings)
    s = problem.settings
    dt = step_size(problem)
    start = 0.0 if geometry == "point" else outline_start(problem)
    state = _free_state(problem.state0, start)
    if geometry == "point":
        _check_approach(problem, state)
    space, body1, body2 = _space(problem, state)
    stepper = _Stepper(problem, space, body1, body2, dt, start)
    rows = [_row(start, body1, body2)] if s.record else None
    stepper.half_kick()
    _run_contact(stepper, rows)
    # the contact force was zero in the last step: these are the post-impact velocities
    delta_p = float(permanent_crush(stepper.memory.delta_max, problem.eps, problem.preload,
                                    problem.stiffness))
    t_end = _separation_time(stepper, delta_p)
    post = _post_velocities(stepper, t_end)
    separation_index = len(rows) - 1 if rows is not None else 0
    stepper.memory = replace(stepper.memory, on=False)   # free motion; tyres still act
    for _ in range(int(math.ceil(s.duration / dt)) if s.duration > 0 else 0):
        stepper.step()
        if rows is not None:
            rows.append(_row(start + stepper.step_count * dt, body1, body2))
    records = (None, None, None)
    if rows is not None:
        records = _records(problem, rows, stepper, separation_index)
    return _result(problem, stepper, post, delta_p, t_end, records,
                   time.perf_counter() - wall)


def _result(problem: CompliantProblem, stepper: _Stepper, post: tuple, delta_p: float,
            t_end: float, records: tuple, wall: float) -> CompliantResult:
    """The typed result from the stepper's tally and the post-impact motion ``post``."""
    v1, v2, w1, w2 = post
    tally, mem, start = stepper.tally, stepper.memory, stepper.start
    trajectory, history, secondary = records
    return CompliantResult(
        velocity1=v1, velocity2=v2, yaw_rate1=w1, yaw_rate2=w2,
        contact_duration=t_end - start, contact_start=start, impulse=tally.impulse.copy(),
        impact_point=(tally.moment_sum / tally.weight if tally.weight > 0
                      else np.full(2, np.nan)),
        peak_force=tally.peak, peak_crush=mem.delta_max, permanent_crush=delta_p,
        energy_before=problem.energy_before,
        energy_after=(kinetic_energy(problem.mass1, problem.inertia1, v1, w1)
                      + kinetic_energy(problem.mass2, problem.inertia2, v2, w2)),
        tyre_work=tally.tyre_work,
        stick_fraction=tally.stick_time / max(tally.contact_time, 1e-300),
        slip_reversed=reversal(tally.initial_sign or 0.0, tally.last_slip,
                               problem.speed_scale, tally.directions),
        steps=stepper.step_count, wall_time=wall, integrator="pymunk", eps=problem.eps,
        stiffness=problem.stiffness, friction=problem.friction,
        tyre_friction=problem.tyre_friction, geometry=problem.geometry,
        settings=problem.settings, history=history, trajectory=trajectory,
        secondary_impact=secondary, problems=_problems(problem, mem.delta_max),
        tangential_recovery=problem.tangential_recovery,
        impulse_normal=_unit(tally.normal_sum, tally.weight),
        impact_point_body1=(tally.body_point_sum / tally.weight if tally.weight > 0
                            else np.full(2, np.nan)),
        impulse_normal_body2=_unit(tally.body_normal_sum, tally.weight))


def _unit(total: np.ndarray, weight: float) -> np.ndarray:
    return total / math.hypot(*total) if weight > 0 else np.full(2, np.nan)


def _problems(problem: CompliantProblem, peak_crush: float) -> tuple:
    """Flags of an inadmissible outcome (never hidden)."""
    out = []
    lengths = [v.length for v in (problem.case.vehicle1, problem.case.vehicle2)
               if v.length is not None and not bool(v.fixed)]
    if lengths and peak_crush > 0.5 * min(lengths):
        out.append(f"peak crush {peak_crush:.3g} m exceeds half the shorter vehicle's length "
                   f"({0.5 * min(lengths):.3g} m): the vehicles would pass through each other")
    return tuple(out)
