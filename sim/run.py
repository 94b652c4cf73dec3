"""Step a scene through the impact and report what the engine did.

When is the impact over?
------------------------
PIM's impact is instantaneous. The engine processes a contact in a step only while some
contact point still *approaches* (relative normal velocity below ``-1e-9`` x the speed scale
of the scene); the pre-solve callback rejects a contact whose points all separate or slide
tangentially. This is what makes the emulation clean:

* with the default exact placement the whole impulse is applied in the one step in which the
  contact is found, at the impact configuration, with Chipmunk's Newton restitution and
  Coulomb friction solved by its iterations; afterwards U_n = -epsilon u_n >= 0, so the next
  step rejects the contact and the impact has ended (contact duration = one step);
* epsilon = 0 needs no special case: the contact then neither approaches nor separates
  (U_n = 0 to round-off) and is rejected, instead of lingering with zero separation speed
  and having Chipmunk re-apply ("warm start") the stored impulse in later steps;
* a contact that has not converged (too few iterations, or the engine's own late contact
  with ``start="detected"`` / outlines) keeps being processed while it approaches.

So the impact ends at the first step, after the contact began, in which no contact was
processed; velocities are unchanged in that step (no other forces act). The run fails
(:class:`sim.SimulationError`) when no contact is ever processed, when a contact still
pushes after ``settings.max_contact_time``, when a step has more contact points than the
scene allows, or when kinetic energy rises.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import pymunk

import pim
from pim.model.case import checked_case
from pim.model.geometry import kinetic_energy
from pim.model.numbers import check_type, speed_text

from .failures import SimulationError
from .result import SimResult, Trajectory
from .scene import TYPE1, TYPE2, Scene, build_scene, resolve_coefficients
from .settings import Settings

__all__ = ["simulate", "run_scene", "run_impact", "ImpactSteps", "continue_after_impact", "trajectory_of", "body_state",
           "APPROACH_TOLERANCE"]

#: A contact point approaches when its relative normal velocity is below -this x speed scale.
APPROACH_TOLERANCE = 1e-9


class _Monitor:
    """Per-step bookkeeping filled by the collision callbacks."""

    __slots__ = ("accepted", "points", "max_points", "impulse", "tol", "pin", "normal",
                 "allowed", "body1", "body2", "before", "residual", "eps", "friction",
                 "check", "done")

    def __init__(self, scene: Scene, settings: Settings) -> None:
        self.accepted = False
        self.points = 0
        self.max_points = 0
        self.impulse = [0.0, 0.0]
        self.tol = APPROACH_TOLERANCE * scene.speed_scale
        self.pin = settings.contact == "point" and settings.start == "exact"
        # engine normal runs from vehicle 1's shape to vehicle 2's: -n
        self.normal = pymunk.Vec2d(-float(scene.normal[0]), -float(scene.normal[1]))
        self.allowed = settings.points_allowed
        self.body1, self.body2 = scene.body1, scene.body2
        self.before = None       # (point_a, point_b, vrn, vrt) of a single-point contact
        self.residual = 0.0      # worst contact-law residual [m/s] over the contact steps
        self.eps, self.friction = scene.eps, scene.friction
        self.check = settings.convergence_tolerance is not None
        self.done = False        # exact placement: the one impulse has been applied


def _relative(mon: _Monitor, point_a, point_b):
    """Velocity of vehicle 2's point minus vehicle 1's (Chipmunk's b - a) [m/s]."""
    return mon.body2.velocity_at_world_point(point_b) - mon.body1.velocity_at_world_point(point_a)


def _pre_solve(arbiter, space, mon: _Monitor) -> None:
    point_set = arbiter.contact_point_set
    points = point_set.points
    count = len(points)
    mon.points += count
    if mon.done:                  # PIM's impact is one impulse: later touches are ignored
        arbiter.process_collision = False
        return
    normal = point_set.normal
    approaching = False
    for p in points:
        if _relative(mon, p.point_a, p.point_b).dot(normal) < -mon.tol:
            approaching = True
            break
    if not approaching:
        arbiter.process_collision = False
        return
    if mon.pin and count == 1:
        c = points[0].point_b
        normal = mon.normal
        arbiter.contact_point_set = pymunk.ContactPointSet(
            normal, (pymunk.ContactPoint(c, c, 0.0),))
        points = arbiter.contact_point_set.points
    if count == 1:
        p = points[0]
        rel = _relative(mon, p.point_a, p.point_b)
        mon.before = (p.point_a, p.point_b, normal, rel.dot(normal),
                      rel.dot(normal.perpendicular()))
    else:
        mon.before = None
    mon.accepted = True


def _post_solve(arbiter, space, mon: _Monitor) -> None:
    j = arbiter.total_impulse          # on the body of shapes[0] = vehicle 1
    mon.impulse[0] += j.x
    mon.impulse[1] += j.y
    if mon.check and mon.before is not None:
        point_a, point_b, normal, vrn0, vrt0 = mon.before
        tangent = normal.perpendicular()
        jn, jt = -j.dot(normal), -j.dot(tangent)     # Chipmunk's accumulated jnAcc, jtAcc
        rel = _relative(mon, point_a, point_b)
        vrn, vrt = rel.dot(normal), rel.dot(tangent)
        residual = abs(vrn + mon.eps * vrn0) if jn > 0 else max(0.0, -vrn - mon.eps * vrn0)
        if abs(jt) < mon.friction * jn * (1.0 - 1e-9):
            residual = max(residual, abs(vrt))        # sticking: no tangential velocity
        elif jt * vrt > 0:
            residual = max(residual, abs(vrt))        # sliding must oppose the friction
        mon.residual = max(mon.residual, residual)


def _state(t: float, b1: pymunk.Body, b2: pymunk.Body) -> tuple:
    p1, v1, p2, v2 = b1.position, b1.velocity, b2.position, b2.velocity
    return (t, p1.x, p1.y, b1.angle, p2.x, p2.y, b2.angle, v1.x, v1.y, b1.angular_velocity,
            v2.x, v2.y, b2.angular_velocity)


def _kinetic(body: pymunk.Body) -> float:
    """Kinetic energy [J] of a pymunk body (0 for a static or kinematic one)."""
    if body.body_type != pymunk.Body.DYNAMIC:
        return 0.0
    return float(kinetic_energy(body.mass, body.moment, tuple(body.velocity),
                                body.angular_velocity))


def _tyre_step(body: pymunk.Body, decel: float, yaw_decel: float, dt: float) -> bool:
    """Slow a body by tyre/ground friction for one step; True if it is at rest."""
    if body.body_type != pymunk.Body.DYNAMIC:
        return True
    v = body.velocity
    speed = v.length
    body.velocity = v * max(0.0, 1.0 - decel * dt / speed) if speed > 0 else v
    w = body.angular_velocity
    if w != 0.0:
        body.angular_velocity = w * max(0.0, 1.0 - yaw_decel * dt / abs(w))
    return body.velocity.length == 0.0 and body.angular_velocity == 0.0


def run_scene(scene: Scene, settings: Settings) -> dict:
    """Step a built scene until the impact has ended (plus ``settings.duration``).

    Returns a dict of the SimResult fields except ``wall_time``, ``settings`` and the
    coefficients. Raises :class:`sim.SimulationError` on a failed run.
    """
    b1, b2 = scene.body1, scene.body2
    dt = settings.dt
    states = [_state(scene.start_time, b1, b2)]
    impact = run_impact(scene, settings, states)
    step = continue_after_impact(scene, settings, impact.steps, states)
    trajectory = trajectory_of(scene, states, impact.index)
    return dict(iterations=scene.iterations, contraction_rate=scene.contraction_rate,
        velocity1=impact.velocity1, velocity2=impact.velocity2, yaw_rate1=impact.yaw_rate1,
        yaw_rate2=impact.yaw_rate2, impulse=impact.impulse,
        contact_duration=impact.contact_steps * dt, contact_steps=impact.contact_steps,
        contact_points=impact.contact_points, steps=step, energy_before=scene.energy_before,
        energy_after=impact.energy_after, trajectory=trajectory,
        final_velocity1=np.array(b1.velocity), final_velocity2=np.array(b2.velocity),
        final_yaw_rate1=float(b1.angular_velocity), final_yaw_rate2=float(b2.angular_velocity))


@dataclass(frozen=True)
class ImpactSteps:
    """What :func:`run_impact` did: the engine's impact of a rigid scene.

    Attributes
    ----------
    steps : int
        Steps taken from the scene's start until the contact ended [-].
    contact_steps : int
        Steps in which the contact was processed [-].
    index : int
        Index in the recorded states of the first state after the contact was processed.
    impulse : ndarray (2,)
        Impulse the engine applied to vehicle 1 [N s].
    contact_points : int
        Most contact points in one step [-].
    velocity1, velocity2 : ndarray (2,)
        CG velocities at separation [m/s].
    yaw_rate1, yaw_rate2 : float
        Yaw rates at separation [rad/s].
    energy_after : float
        Kinetic energy at separation [J].
    """

    steps: int
    contact_steps: int
    index: int
    impulse: np.ndarray
    contact_points: int
    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: float
    yaw_rate2: float
    energy_after: float


def run_impact(scene: Scene, settings: Settings, states: list) -> ImpactSteps:
    """Step a built rigid scene from its start until its one impact has ended, under the
    scene's contact law (module notes), appending the recorded states to ``states``.

    The collision handler of the scene's contact shapes is added here. Raises
    :class:`sim.SimulationError` when no contact is processed, when it never separates,
    when a step has more contact points than allowed, or when the impact gains energy.
    """
    b1, b2 = scene.body1, scene.body2
    mon = _Monitor(scene, settings)
    scene.space.on_collision(TYPE1, TYPE2, pre_solve=_pre_solve, post_solve=_post_solve,
                             data=mon)
    step, contact_steps, impact_index = _step_impact(scene, settings, mon, states)
    _check_impulse(mon, contact_steps, step)
    velocity1, velocity2 = np.array(b1.velocity), np.array(b2.velocity)
    yaw_rate1, yaw_rate2 = float(b1.angular_velocity), float(b2.angular_velocity)
    energy_after = _kinetic(b1) + _kinetic(b2)
    _check_energy(scene, settings, energy_after,
                  np.r_[velocity1, velocity2, yaw_rate1, yaw_rate2], step)
    return ImpactSteps(step, contact_steps, impact_index, np.array(mon.impulse),
                       mon.max_points, velocity1, velocity2, yaw_rate1, yaw_rate2,
                       energy_after)


def _step_impact(scene: Scene, settings: Settings, mon: _Monitor, states: list) -> tuple:
    """Step from the start until the contact has ended (run_scene), appending the recorded
    states to ``states``; return (steps, contact steps, index of the first contact state)."""
    space, b1, b2 = scene.space, scene.body1, scene.body2
    dt = settings.dt
    if settings.contact == "point":
        search_end = (0.0 if settings.start == "exact" else dt) + 0.5 * dt
    else:
        search_end = settings.max_contact_time
    record = settings.record
    step = 0
    contact_steps = 0
    impact_index = None
    while True:
        mon.accepted = False
        mon.points = 0
        space.step(dt)
        step += 1
        now = scene.start_time + step * dt
        if mon.points > mon.max_points:
            mon.max_points = mon.points
        if mon.accepted:
            if mon.allowed is not None and mon.points > mon.allowed:
                raise SimulationError(
                    "multiple_contacts",
                    f"{mon.points} contact points in step {step} (t = {now:.6g} s) where the "
                    f"scene allows {mon.allowed}: the contact is a patch, not PIM's single "
                    f"point", step)
            contact_steps += 1
            if mon.check and mon.residual > settings.convergence_tolerance * scene.speed_scale:
                raise SimulationError("not_converged", _not_converged_message(scene, mon), step)
            if mon.pin:
                mon.done = True
            if impact_index is None:
                states.append(_state(now, b1, b2))
                impact_index = len(states) - 1
            elif record:
                states.append(_state(now, b1, b2))
            if contact_steps * dt > settings.max_contact_time + 0.5 * dt:
                raise SimulationError(
                    "never_separated",
                    f"the contact still pushed after {contact_steps} steps "
                    f"({contact_steps * dt:.6g} s > max_contact_time = "
                    f"{settings.max_contact_time:g} s)", step)
            if not mon.pin:
                continue
            break                      # exact placement: the one impulse is the impact
        if record:
            states.append(_state(now, b1, b2))
        if impact_index is not None:
            break                      # contact began earlier and is over: separated
        if now > search_end:
            raise SimulationError("no_contact", _no_contact_message(scene, settings, now), step)
    return step, contact_steps, impact_index


def _check_impulse(mon: _Monitor, contact_steps: int, step: int) -> None:
    """A touch that applied no impulse is no impact (run_scene)."""
    if not np.any(np.asarray(mon.impulse, dtype=float) != 0):
        raise SimulationError(
            "no_contact", f"the shapes touched for {contact_steps} step(s) but no impulse was "
            f"applied (a grazing touch, not an impact)", step)


def _check_energy(scene: Scene, settings: Settings, energy_after: float, motion, step: int
                  ) -> None:
    """The impact may not gain kinetic energy nor leave a non-finite ``motion`` (run_scene)."""
    finite = np.isfinite(motion).all()
    limit = scene.energy_before * (1.0 + settings.energy_tolerance) + 1e-12
    if not finite or energy_after > limit:
        gain = energy_after - scene.energy_before
        raise SimulationError(
            "energy_gained",
            f"kinetic energy rose from {scene.energy_before:.9g} J to {energy_after:.9g} J "
            f"(+{gain:.3g} J, {100 * gain / max(scene.energy_before, 1e-300):.3g} %) in the "
            f"impact" if finite else "the engine returned a non-finite state", step)


def _run_after(scene: Scene, settings: Settings, states: list, step: int) -> int:
    """Free motion after separation (run_scene): the point contact removed, tyre friction,
    for ``settings.duration``; append the recorded states; return the step count."""
    space, b1, b2 = scene.space, scene.body1, scene.body2
    dt = settings.dt
    record = settings.record
    if settings.contact == "point":
        space.remove(*scene.contact_shapes)
    coefficient = settings.tyre_coefficient
    decel = coefficient * settings.gravity
    yaw1 = yaw2 = 0.0
    if coefficient > 0:
        if b1.body_type == pymunk.Body.DYNAMIC:
            yaw1 = decel * scene.lever1 / (b1.moment / b1.mass)
        if b2.body_type == pymunk.Body.DYNAMIC:
            yaw2 = decel * scene.lever2 / (b2.moment / b2.mass)
    extra = int(np.ceil(settings.duration / dt - 1e-9))
    for _ in range(extra):
        space.step(dt)
        step += 1
        rest = False
        if coefficient > 0:
            rest = _tyre_step(b1, decel, yaw1, dt) & _tyre_step(b2, decel, yaw2, dt)
        if record:
            states.append(_state(scene.start_time + step * dt, b1, b2))
        if rest:
            break
    return step


def body_state(t: float, scene: Scene) -> tuple:
    """One row of a recorded trajectory: time and both bodies' poses and velocities."""
    return _state(t, scene.body1, scene.body2)


def continue_after_impact(scene: Scene, settings: Settings, step: int, states: list) -> int:
    """Free motion after separation for ``settings.duration`` (point contact removed, tyre
    friction if set), appending to ``states`` when recording; the last state is always
    appended. Returns the step count reached."""
    if settings.duration > 0:
        step = _run_after(scene, settings, states, step)
    t = scene.start_time + step * settings.dt
    if states[-1][0] != t:
        states.append(_state(t, scene.body1, scene.body2))
    return step


def trajectory_of(scene: Scene, states: list, impact_index: int) -> Trajectory:
    """The :class:`Trajectory` of recorded rows (:func:`body_state`): time, then each body's
    pose and velocity."""
    arr = np.array(states, dtype=float)
    return Trajectory(
        time=arr[:, 0], position1=arr[:, 1:3], angle1=arr[:, 3], position2=arr[:, 4:6],
        angle2=arr[:, 6], velocity1=arr[:, 7:9], yaw_rate1=arr[:, 9], velocity2=arr[:, 10:12],
        yaw_rate2=arr[:, 12], impact_index=int(impact_index), outline1=scene.outline1,
        outline2=scene.outline2, fixed2=scene.fixed2)


def _not_converged_message(scene: Scene, mon: _Monitor) -> str:
    text = (f"the contact solver did not converge: contact-law residual "
            f"{mon.residual / scene.speed_scale:.3g} (relative) after {scene.iterations} "
            f"iterations; predicted error factor per sweep rho = {scene.contraction_rate:.4g}")
    if scene.beta < 1.0 and scene.contraction_rate >= 1.0:
        text += (f" >= 1: with sliding friction u = |mu| = {scene.friction:.4g}, "
                 "|u K_nt| >= K_nn, so "
                 "Chipmunk's sequential impulses diverge; PIM's sliding impulse cannot be "
                 "reproduced by this engine at any iteration count")
    else:
        text += "; raise the solver iterations per step (settings.iterations)"
    return text


def _no_contact_message(scene: Scene, settings: Settings, now: float) -> str:
    if not scene.approach_n < 0:
        return (f"no contact: the vehicles do not approach at C (u_n = "
                f"{speed_text(scene.approach_n, '.6g')} >= 0), so there is no impact to "
                f"simulate")
    travel = abs(scene.approach_n) * settings.dt
    # A step that covers the whole diameter can carry the circle from just outside to just
    # outside the other side: equality tunnels too.
    if settings.contact == "point" and travel >= 2 * settings.contact_radius:
        return (f"no contact found by t = {now:.6g} s: the contact circle tunnelled through "
                f"(approach speed x dt = {travel:.3g} m >= its diameter "
                f"{2 * settings.contact_radius:.3g} m); reduce dt or raise contact_radius")
    return f"no contact found by t = {now:.6g} s (the shapes never touched while approaching)"


def simulate(case: pim.Case, eps=None, beta=None, settings: Settings | None = None,
             analytic: pim.Result | None = None) -> SimResult:
    """Simulate one PIM case with pymunk and return the engine's post-impact state.

    Parameters
    ----------
    case : pim.Case
        A single case (scalar fields).
    eps : float, optional
        Coefficient of restitution [-] in [0, 1]; default ``case.impact.restitution``.
    beta : float, optional
        Fraction of the critical impulse ratio [-] in [0, 1]; default ``case.impact.beta``,
        else 1.
    settings : Settings, optional
        Step size, iterations and physics switches; default ``Settings()``.
    analytic : pim.Result, optional
        ``pim.solve(case, eps, 1.0)`` if already at hand (supplies mu0 for the friction).

    Returns
    -------
    SimResult
        Velocities and yaw rates at separation, the impulse the engine applied, contact
        duration, steps, wall time (building and stepping the Space, not the analytic
        reference), energies and the trajectory.

    Raises
    ------
    ValueError
        Bad input (eps or beta outside [0, 1], an array case, missing outlines).
    SimulationError
        The run failed: no contact, never separated, multiple contacts, energy gained.
    """
    checked_case(case)
    settings = check_type(settings, "settings", Settings, "a sim.Settings (e.g. "
                          "sim.Settings(dt=1e-4))", none=True) or Settings()
    eps, beta = resolve_coefficients(case, eps, beta)
    if analytic is None:
        analytic = pim.solve(case, eps, 1.0, law="brach")
    start = time.perf_counter()
    scene = build_scene(case, eps, beta, settings, analytic=analytic)
    fields = run_scene(scene, settings)
    wall = time.perf_counter() - start
    return SimResult(**fields, wall_time=wall, eps=eps, beta=beta, friction=scene.friction,
                     settings=settings)
