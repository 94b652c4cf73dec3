"""The finite-duration contact stepped by pymunk: PIM's assumptions relaxed, not emulated.

:func:`simulate_compliant` integrates the two bodies with pymunk (Chipmunk2D) while the
project computes the contact force (:mod:`sim.contact_law`) from the bodies' state in
every step: the bodies carry no collision shapes, so Chipmunk's own rigid contact response
never acts. The force is applied through each body's ``velocity_func``, which Chipmunk calls
after it has moved *all* bodies in the step, so the force is evaluated at the new positions
(and the old velocities): symplectic Euler,

    x_{n+1} = x_n + v_n dt,    v_{n+1} = v_n + F(x_{n+1}, v_n) dt / m,

first order, stable for omega dt < 2, with linear momentum and angular momentum about any
fixed point conserved to round-off (both bodies receive equal and opposite forces at the
same point in the same step). The memory of the contact law is updated by its implicit
step: delta_max = max(delta_max, delta), the friction spring by
:func:`sim.contact_law.tangential_step`.

The contact ends when the normal force has returned to zero on unloading (delta below the
permanent crush); the separation time is interpolated inside the last step. A step too
coarse to resolve the contact (fewer than ``settings.min_steps`` per estimated contact
time), outlines that pass through each other, a contact that never ends, or no contact at
all raise :class:`sim.SimulationError`.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pymunk

import pim

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
)
from .contact_law import normal_force, permanent_crush, tangential_force, tangential_step
from .failures import SimulationError
from .overlap import outline_overlap, overlap_area
from .result import Trajectory
from .secondary import find_secondary_impact
from .tyres import tyre_force

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


class _Stepper:
    """Computes the contact and tyre forces once per step and feeds them to pymunk."""

    def __init__(self, problem: CompliantProblem, body1, body2, dt: float, start: float):
        self.p = problem
        self.b1, self.b2 = body1, body2
        self.dt = dt
        self.step = 0
        self.done_step = -1
        self.force1 = (0.0, 0.0, 0.0)      # fx, fy, torque on body 1
        self.force2 = (0.0, 0.0, 0.0)
        self.delta_max = 0.0
        self.z = 0.0
        self.started = False
        self.separated = False
        self.contact = True                # contact forces still on
        self.delta = 0.0
        self.prev_delta = 0.0
        self.normal = None
        self.impulse = np.zeros(2)
        self.moment_sum = np.zeros(2)
        self.weight = 0.0
        self.peak = 0.0
        self.tyre_work = 0.0
        self.stick_time = 0.0
        self.contact_time = 0.0
        self.directions = set()            # directions (sign of z) in which it slid
        self.initial_sign = None           # sign of the slip at first contact
        self.last_slip = 0.0               # slip in the last contact step [m/s]
        self.rows = [] if problem.settings.record else None
        self.start = start
        self.a, self.b, self.eps = problem.preload, problem.stiffness, problem.eps
        self.mu, self.kt = problem.friction, problem.tangential_stiffness
        self.last_slip_n = 0.0             # outline: v_rel . n at the last contact [m/s]
        self.obstacle = None
        if problem.geometry == "outline" and problem.outline2 is None:
            self.obstacle = _obstacle(problem, None)

    # pymunk callbacks ----------------------------------------------------------------------
    def velocity1(self, body, gravity, damping, dt):
        self._compute()
        body.force = self.force1[0:2]
        body.torque = self.force1[2]
        pymunk.Body.update_velocity(body, gravity, damping, dt)

    def velocity2(self, body, gravity, damping, dt):
        self._compute()
        body.force = self.force2[0:2]
        body.torque = self.force2[2]
        pymunk.Body.update_velocity(body, gravity, damping, dt)

    # the forces ------------------------------------------------------------------------------
    def _state(self, body):
        p, v = body.position, body.velocity
        return np.array([p.x, p.y]), body.angle, np.array([v.x, v.y]), body.angular_velocity

    def _compute(self) -> None:
        if self.done_step == self.step:
            return
        self.done_step = self.step
        p, dt = self.p, self.dt
        x1, a1, v1, w1 = self._state(self.b1)
        x2, a2, v2, w2 = self._state(self.b2)
        f1 = np.zeros(2)
        m1 = m2 = 0.0
        f2 = np.zeros(2)
        if self.contact:
            geo = self._geometry(x1, a1, v1, w1, x2, a2, v2, w2)
            if geo is not None:
                point, n, t, delta, slip_t = geo
                if self.started or delta > 0.0:
                    if self.initial_sign is None:
                        self.initial_sign = math.copysign(1.0, slip_t) if slip_t else 0.0
                    self.last_slip = slip_t
                self.prev_delta, self.delta = self.delta, delta
                if delta > 0.0:
                    self.started = True
                fn = 0.0
                if self.started:
                    self.delta_max = max(self.delta_max, delta)
                    fn = float(normal_force(delta, self.delta_max, self.eps, self.a, self.b))
                    if fn <= 0.0 and delta < self.delta_max:
                        self.separated = True
                        self.contact = False
                        fn = 0.0
                ft = 0.0
                if self.mu > 0.0 and self.contact:
                    limit = self.mu * fn / self.kt
                    self.z = float(tangential_step(self.z, slip_t, dt, limit))
                    ft = float(tangential_force(self.z, self.kt, self.mu * fn))
                    sticking = abs(self.z) < limit * (1 - 1e-9)
                else:
                    self.z = 0.0
                    sticking = False
                force = fn * n + ft * t
                if self.contact and self.started:
                    size = math.hypot(force[0], force[1])
                    self.impulse += force * dt
                    self.moment_sum += size * dt * point
                    self.weight += size * dt
                    self.contact_time += dt
                    if sticking:
                        self.stick_time += dt
                    if size > self.peak:
                        self.peak = size
                    if self.mu > 0.0 and not sticking and self.z != 0.0:
                        self.directions.add(1 if self.z > 0 else -1)
                    f1 = force
                    f2 = -force
                    d1, d2 = point - x1, point - x2
                    m1 = d1[0] * force[1] - d1[1] * force[0]
                    m2 = -(d2[0] * force[1] - d2[1] * force[0])
                    if self.rows is not None:
                        self.rows.append((self.start + (self.step + 1) * dt, delta, force[0],
                                          force[1], fn, ft, slip_t, sticking, point[0],
                                          point[1]))
        if p.tyre_friction > 0.0:
            ft1, mt1 = tyre_force(v1, w1, a1, p.wheels1, p.load1, p.tyre_friction, p.tyre_mode)
            f1 = f1 + ft1
            m1 += mt1
            self.tyre_work += float(ft1 @ v1 + mt1 * w1) * dt
            if not p.fixed2:
                ft2, mt2 = tyre_force(v2, w2, a2, p.wheels2, p.load2, p.tyre_friction,
                                      p.tyre_mode)
                f2 = f2 + ft2
                m2 += mt2
                self.tyre_work += float(ft2 @ v2 + mt2 * w2) * dt
        self.force1 = (float(f1[0]), float(f1[1]), float(m1))
        self.force2 = (float(f2[0]), float(f2[1]), float(m2))

    def _geometry(self, x1, a1, v1, w1, x2, a2, v2, w2):
        p = self.p
        if p.geometry == "point":
            point, n, t, delta, _, slip_t = point_contact(p, x1, a1, v1, w1, x2, a2, v2, w2)
            return point, n, t, delta, slip_t
        state = np.r_[x1, a1, v1, w1, x2, a2, v2, w2]
        poly1, poly2 = placed_outlines(p, state)
        poly2 = poly2 if poly2 is not None else self.obstacle
        ov = outline_overlap(poly1, poly2)
        if ov.area <= 0.0:
            n = self.normal if self.normal is not None else ov.normal
            return np.zeros(2), n, np.array([-n[1], n[0]]), 0.0, 0.0
        n = ov.normal
        if self.normal is not None and n @ self.normal < 0.0:
            raise SimulationError(
                "tunnelled", f"the contact normal of the outlines flipped at t = "
                f"{self.start + (self.step + 1) * self.dt:.4g} s (crush {ov.depth:.3g} m): the "
                f"outlines passed through each other; reduce dt or raise the stiffness",
                self.step)
        self.normal = n
        t = np.array([-n[1], n[0]])
        c = ov.centroid
        d1, d2 = c - x1, c - x2
        rel = v1 + w1 * np.array([-d1[1], d1[0]]) - v2 - w2 * np.array([-d2[1], d2[0]])
        self.last_slip_n = float(rel @ n)
        return c, n, t, ov.depth, float(rel @ t)


def _row(t: float, b1, b2) -> tuple:
    p1, v1, p2, v2 = b1.position, b1.velocity, b2.position, b2.velocity
    return (t, p1.x, p1.y, b1.angle, p2.x, p2.y, b2.angle, v1.x, v1.y, b1.angular_velocity,
            v2.x, v2.y, b2.angular_velocity)


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
        _, _, _, _, slip_n, _ = point_contact(problem, state[0:2], state[2], state[3:5],
                                               state[5], state[6:8], state[8], state[9:11],
                                               state[11])
        if not slip_n < 0.0:
            raise SimulationError("no_contact", f"no contact: the vehicles do not approach at "
                                  f"C (u_n = {slip_n:.6g} m/s >= 0)", 0)

    space = pymunk.Space()
    space.gravity = (0.0, 0.0)
    space.damping = 1.0
    body1 = pymunk.Body(problem.mass1, problem.inertia1)
    if problem.fixed2:
        body2 = pymunk.Body(body_type=pymunk.Body.STATIC)
    else:
        body2 = pymunk.Body(problem.mass2, problem.inertia2)
    for body, k in ((body1, 0), (body2, 6)):
        body.position = (float(state[k]), float(state[k + 1]))
        body.angle = float(state[k + 2])
        if body.body_type == pymunk.Body.DYNAMIC:
            body.velocity = (float(state[k + 3]), float(state[k + 4]))
            body.angular_velocity = float(state[k + 5])
    space.add(body1, body2)
    stepper = _Stepper(problem, body1, body2, dt, start)
    body1.velocity_func = stepper.velocity1
    if body2.body_type == pymunk.Body.DYNAMIC:
        body2.velocity_func = stepper.velocity2

    rows = [_row(start, body1, body2)] if s.record else None
    max_steps = int(math.ceil(s.max_contact_time / dt)) + 1
    step = 0
    while True:
        space.step(dt)
        step += 1
        stepper.step = step
        if rows is not None:
            rows.append(_row(start + step * dt, body1, body2))
        if stepper.separated:
            break
        if step >= max_steps:
            kind = "never_separated" if stepper.started else "no_contact"
            text = (f"the contact still pushed after {s.max_contact_time:g} s "
                    f"(max_contact_time)" if stepper.started else
                    f"the outlines never touched within {s.max_contact_time:g} s")
            raise SimulationError(kind, text, step)
    if geometry == "outline" and stepper.last_slip_n < -1e-3 * problem.speed_scale:
        raise SimulationError(
            "tunnelled", f"the outlines passed through each other: their overlap ended at "
            f"t = {start + step * dt:.4g} s while they still approached at "
            f"{-stepper.last_slip_n:.3g} m/s (mean crush {stepper.delta_max:.3g} m); the crush "
            f"is deeper than the vehicles: raise the stiffness", step)
    # the force was zero in the last step: these are the post-impact velocities. The
    # separation instant is interpolated between the last two positions (delta = delta_p).
    delta_p = float(permanent_crush(stepper.delta_max, problem.eps, problem.preload,
                                    problem.stiffness))
    frac = 1.0
    if stepper.prev_delta != stepper.delta:
        frac = min(max((stepper.prev_delta - delta_p) / (stepper.prev_delta - stepper.delta),
                       0.0), 1.0)
    t_end = start + (step - 1 + frac) * dt
    v1 = np.array(body1.velocity)
    v2 = np.array(body2.velocity)
    w1, w2 = float(body1.angular_velocity), float(body2.angular_velocity)
    energy_after = (kinetic_energy(problem.mass1, problem.inertia1, v1, w1)
                    + kinetic_energy(problem.mass2, problem.inertia2, v2, w2))
    separation_index = len(rows) - 1 if rows is not None else 0

    # free motion after separation (animation, secondary impact); tyres keep acting
    if s.duration > 0:
        stepper.contact = False
        for _ in range(int(math.ceil(s.duration / dt))):
            space.step(dt)
            step += 1
            stepper.step = step
            if rows is not None:
                rows.append(_row(start + step * dt, body1, body2))
    trajectory = history = secondary = None
    if rows is not None:
        arr = np.array(rows, float)
        trajectory = Trajectory(
            time=arr[:, 0], position1=arr[:, 1:3], angle1=arr[:, 3], position2=arr[:, 4:6],
            angle2=arr[:, 6], velocity1=arr[:, 7:9], yaw_rate1=arr[:, 9],
            velocity2=arr[:, 10:12], yaw_rate2=arr[:, 12], impact_index=separation_index,
            outline1=problem.outline1, outline2=problem.outline2, fixed2=problem.fixed2)
        h = np.array(stepper.rows, float).reshape(-1, 10)
        history = ContactHistory(time=h[:, 0], crush=h[:, 1], force=h[:, 2:4],
                                 normal_force=h[:, 4], tangential_force=h[:, 5], slip=h[:, 6],
                                 sticking=h[:, 7].astype(bool), point=h[:, 8:10])
        found = find_secondary_impact(trajectory, separation_index)
        secondary = None if found is None else found.time
    impact_point = (stepper.moment_sum / stepper.weight if stepper.weight > 0
                    else np.full(2, np.nan))
    problems = _problems(problem, stepper.delta_max)
    return CompliantResult(
        velocity1=v1, velocity2=v2, yaw_rate1=w1, yaw_rate2=w2,
        contact_duration=t_end - start, contact_start=start, impulse=stepper.impulse.copy(),
        impact_point=impact_point, peak_force=stepper.peak, peak_crush=stepper.delta_max,
        permanent_crush=delta_p, energy_before=problem.energy_before,
        energy_after=energy_after, tyre_work=stepper.tyre_work,
        stick_fraction=stepper.stick_time / max(stepper.contact_time, 1e-300),
        slip_reversed=reversal(stepper.initial_sign or 0.0, stepper.last_slip,
                               problem.speed_scale, stepper.directions),
        steps=step, wall_time=time.perf_counter() - wall,
        integrator="pymunk", eps=problem.eps, stiffness=problem.stiffness,
        friction=problem.friction, tyre_friction=problem.tyre_friction, geometry=geometry,
        settings=s, history=history, trajectory=trajectory, secondary_impact=secondary,
        problems=problems)


def _problems(problem: CompliantProblem, peak_crush: float) -> tuple:
    """Flags of an inadmissible outcome (never hidden)."""
    out = []
    lengths = [v.length for v in (problem.case.vehicle1, problem.case.vehicle2)
               if v.length is not None and not bool(v.fixed)]
    if lengths and peak_crush > 0.5 * min(lengths):
        out.append(f"peak crush {peak_crush:.3g} m exceeds half the shorter vehicle's length "
                   f"({0.5 * min(lengths):.3g} m): the vehicles would pass through each other")
    return tuple(out)
