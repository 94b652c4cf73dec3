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
from dataclasses import replace

import numpy as np
import pymunk

import pim
from pim.model.numbers import InputError, speed_text

from . import compliant_formula as f
from .compliant_batch import simulate_batch
from .compliant_formula import (
    contact_loads,
    half_kick,
    point_geometry,
    post_velocities,
    separation_time,
    total_loads,
    write_outputs,
)
from .compliant_setup import (
    CompliantProblem,
    CompliantResult,
    ESTIMATE_MARGIN,
    CompliantSettings,
    ContactHistory,
    build_problem,
    contact_step_limit,
    endless_contact,
    kinetic_energy,
    parameter_rows,
    physics_refusal,
    point_contact,
    problem_arrays,
    refuse_frozen,
    result_from_row,
)
from .contact_law import check_fraction, check_positive, stiffness_for_duration
from .failures import SimulationError
from .result import Trajectory
from .secondary import find_secondary_impact

__all__ = ["simulate_compliant", "simulate_pymunk", "step_size", "outline_start", "free_steps",
           "outline_geometry", "ENGINES"]

#: The integrators of :func:`simulate_compliant`.
ENGINES = ("numba", "pymunk")


def step_size(problem: CompliantProblem) -> float:
    """pymunk's step [s]: ``settings.dt`` or the contact time / ``steps_per_contact``.

    Raises
    ------
    SimulationError
        "tunnelled": fewer than ``settings.min_steps`` steps per estimated contact time.
    """
    s = problem.settings
    if endless_contact(problem.duration_estimate, s):
        raise SimulationError(
            "never_separated",
            f"stiffness = {problem.stiffness:.3g} N/m gives an estimated contact of "
            f"{problem.duration_estimate:.3g} s (pi (1 + eps) / (2 sqrt(k K_nn))), beyond "
            f"{ESTIMATE_MARGIN:g} x settings.max_contact_time = {s.max_contact_time:g} s: a "
            f"contact without end, "
            f"refused before any step (a car's crush stiffness is about 7.5e5 N/m)", 0)
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


def outline_start(problem: CompliantProblem, par: list | None = None) -> float:
    """When the outlines first touch [s] along the free pre-impact paths (<= 0), or 0
    (:func:`sim.compliant_formula.outline_start`).

    The case places the bodies at PIM's impact configuration (t = 0), where illustrative
    outlines often already overlap; the outline contact starts where they first touch,
    found by stepping back along the free paths and bisecting. ``par``: the scene's
    parameters, when made already.

    Raises
    ------
    SimulationError
        "tunnelled": the outlines overlap along the whole 10 s of pre-impact path.
    """
    if par is None:
        par = parameter_rows(problem_arrays(problem), problem_law(problem, 1.0, 0.0))[0]
    start = f.outline_start(par, problem.state0.tolist(), [0.0] * f.N_WORK)
    if math.isnan(start):
        raise SimulationError("tunnelled", "the outlines overlap along the whole 10 s of "
                              "pre-impact path: they never approach each other", 0)
    return start


def outline_geometry(par: list, mem: list, st: list, trig: tuple, wk: list,
                     when: float) -> tuple:
    """The outline contact at the state ``st``: (px, py, nx, ny, delta, slip_n, slip_t,
    overlap) as :func:`sim.compliant_formula.point_geometry` gives the point contact's
    (:func:`sim.compliant_formula.outline_geometry`).

    Raises
    ------
    SimulationError
        "tunnelled": the normal flipped (the outlines passed through each other).
    """
    *geo, flipped = f.outline_geometry(par, mem, st, trig, wk)
    if flipped:
        raise SimulationError(
            "tunnelled", f"the contact normal of the outlines flipped at t = {when:.4g} s "
            f"(crush {geo[4]:.3g} m): the outlines passed through each other; reduce dt or "
            f"raise the stiffness", 0)
    return tuple(geo)


class _Stepper:
    """Computes the loads once per step (:mod:`sim.compliant_formula`) and feeds them to
    pymunk's velocity callbacks.

    ``par``, ``mem``, ``tal`` and ``lo`` are the formula's parameters, contact memory, tally
    and last loads, as Python lists. An exception raised inside a callback (a
    KeyboardInterrupt included) cannot cross Chipmunk's C frames: cffi would print and
    ignore it. It is kept in ``error`` and :meth:`step` re-raises it after ``space.step``
    returns.
    """

    def __init__(self, problem: CompliantProblem, space, body1, body2, par: list):
        self.p, self.space, self.b1, self.b2, self.par = problem, space, body1, body2, par
        self.dt, self.start = par[f.P_DT], par[f.P_START]
        self.step_count, self.done_step = 0, -1
        self.mem = [0.0] * f.N_MEM
        self.mem[f.M_ON] = 1.0
        self.tal = [0.0] * f.N_TAL
        self.lo = [0.0] * 6
        self.rows = [] if problem.settings.record else None    # the contact history
        self.error: BaseException | None = None
        self.wk = [0.0] * f.N_WORK          # the outline contact's scratch
        self.trig = f.angles(self.state())  # cos, sin of the headings, turned on each step
        body1.velocity_func = self.velocity1
        if body2.body_type == pymunk.Body.DYNAMIC:
            body2.velocity_func = self.velocity2

    def state(self) -> list:
        """Both bodies' x, y, angle, vx, vy, yaw rate (12 floats, the formula's ``st``)."""
        out = []
        for body in (self.b1, self.b2):
            p, v = body.position, body.velocity
            out += [p.x, p.y, body.angle, v.x, v.y, body.angular_velocity]
        return out

    def set_velocities(self, v: tuple) -> None:
        """Set (vx1, vy1, w1, vx2, vy2, w2) on the moving bodies."""
        for body, k in ((self.b1, 0), (self.b2, 3)):
            if body.body_type == pymunk.Body.DYNAMIC:
                body.velocity, body.angular_velocity = (v[k], v[k + 1]), v[k + 2]

    def half_kick(self) -> None:
        """Start the leapfrog (:func:`sim.compliant_formula.half_kick`)."""
        if self.par[f.P_TYRE] > 0.0:
            self.set_velocities(half_kick(self.par, self.state(), self.lo))

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
                self._loads(self.state())
            body.force = (self.lo[3 * index], self.lo[3 * index + 1])
            body.torque = self.lo[3 * index + 2]
            pymunk.Body.update_velocity(body, gravity, damping, dt)
        except BaseException as exc:      # noqa: BLE001 -- re-raised after space.step
            self.error = exc

    def _loads(self, st: list) -> None:
        """This step's loads into ``lo``: the contact (while on) and the tyres."""
        fx = fy = m1 = m2 = 0.0
        par, mem, dt = self.par, self.mem, self.dt
        trig = self.trig = f.advance_angles(par, self.trig, st, dt)
        if mem[f.M_ON] != 0.0:
            when = self.start + (self.step_count + 1) * dt
            geo = (outline_geometry(par, mem, st, trig, self.wk, when)
                   if self.p.geometry == "outline" else
                   (*point_geometry(par, st, trig, dt), True))
            applied, fx, fy, m1, m2, fn, ft, sticking = contact_loads(par, mem, self.tal, st,
                                                                      trig, dt, *geo)
            if applied and self.rows is not None:
                self.rows.append((when, geo[4], fx, fy, fn, ft, geo[6], sticking, geo[0],
                                  geo[1]))
        total_loads(par, st, trig, self.lo, self.tal, dt, fx, fy, m1, m2)


def _row(t: float, b1, b2) -> tuple:
    p1, v1, p2, v2 = b1.position, b1.velocity, b2.position, b2.velocity
    return (t, p1.x, p1.y, b1.angle, p2.x, p2.y, b2.angle, v1.x, v1.y, b1.angular_velocity,
            v2.x, v2.y, b2.angular_velocity)


def _check_approach(problem: CompliantProblem, state: np.ndarray) -> None:
    """The point contact must start with the vehicles approaching at C."""
    *_, slip_n, _ = point_contact(problem, (state[0:2], state[2], state[3:5], state[5],
                                            state[6:8], state[8], state[9:11], state[11]))
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
    max_steps = int(stepper.par[f.P_MAX_STEPS])
    while True:
        stepper.step()
        if rows is not None:
            rows.append(_row(start + stepper.step_count * dt, stepper.b1, stepper.b2))
        if stepper.mem[f.M_SEPARATED] != 0.0:
            break
        if stepper.step_count >= max_steps:
            started = stepper.mem[f.M_STARTED] != 0.0
            limits = (f"max_contact_time = {s.max_contact_time:g} s, max_fixed_steps = "
                      f"{s.max_fixed_steps} steps of {dt:.3g} s")
            text = (f"the contact still pushed after {stepper.step_count * dt:.4g} s "
                    f"({limits})" if started else
                    f"the outlines never touched within {stepper.step_count * dt:.4g} s "
                    f"({limits})")
            raise SimulationError("never_separated" if started else "no_contact", text,
                                  stepper.step_count)
    problem, tal, mem = stepper.p, stepper.tal, stepper.mem
    last_slip_n = tal[f.T_LAST_SLIP_N]
    if problem.geometry == "outline" and last_slip_n < -1e-3 * problem.speed_scale:
        raise SimulationError(
            "tunnelled", f"the outlines passed through each other: their overlap ended at "
            f"t = {start + stepper.step_count * dt:.4g} s while they still approached at "
            f"{speed_text(-last_slip_n, '.3g')} (mean crush {mem[f.M_DMAX]:.3g} m); the crush "
            f"is deeper than the vehicles: raise the stiffness", stepper.step_count)


def _records(problem: CompliantProblem, rows: list, stepper: _Stepper, separation: int):
    """Trajectory, contact history and the secondary impact time from the recorded rows."""
    arr = np.array(rows, float)
    trajectory = Trajectory(
        time=arr[:, 0], position1=arr[:, 1:3], angle1=arr[:, 3], position2=arr[:, 4:6],
        angle2=arr[:, 6], velocity1=arr[:, 7:9], yaw_rate1=arr[:, 9],
        velocity2=arr[:, 10:12], yaw_rate2=arr[:, 12], impact_index=separation,
        outline1=problem.outline1, outline2=problem.outline2, fixed2=problem.fixed2)
    h = np.array(stepper.rows, float).reshape(-1, 10)
    history = ContactHistory(time=h[:, 0], crush=h[:, 1], force=h[:, 2:4],
                             normal_force=h[:, 4], tangential_force=h[:, 5], slip=h[:, 6],
                             sticking=h[:, 7].astype(bool), point=h[:, 8:10])
    found = find_secondary_impact(trajectory, separation)
    return trajectory, history, None if found is None else found.time


def free_steps(settings: CompliantSettings, dt: float) -> int:
    """Steps of the free motion after separation (``settings.duration`` / dt), bounded up
    front.

    Raises
    ------
    ValueError
        More than ``settings.max_fixed_steps`` steps (names ``settings.duration``).
    """
    if settings.duration <= 0:
        return 0
    steps = math.ceil(settings.duration / dt)
    if steps > settings.max_fixed_steps:
        raise InputError(
            f"settings.duration = {settings.duration:g} s of free motion needs {steps:.3g} steps "
            f"of dt = {dt:.3g} s (the contact's step), more than settings.max_fixed_steps = "
            f"{settings.max_fixed_steps}: shorten settings.duration (at most "
            f"{settings.max_fixed_steps * dt:.3g} s here), soften the contact or raise "
            f"settings.max_fixed_steps")
    return steps


def problem_law(problem: CompliantProblem, dt: float, start: float) -> dict:
    """The contact law's inputs of :func:`sim.compliant_setup.parameter_rows` for ``problem``
    stepped at ``dt`` from ``start``."""
    return dict(eps=problem.eps, preload=problem.preload, stiffness=problem.stiffness,
                friction=problem.friction, tangential_stiffness=problem.tangential_stiffness,
                tangential_recovery=problem.tangential_recovery,
                tyre_friction=problem.tyre_friction,
                braking=1.0 if problem.tyre_mode == "locked" else 0.0, dt=dt, start=start,
                max_steps=contact_step_limit(problem.settings, dt),
                outline=1.0 if problem.geometry == "outline" else 0.0, frozen=0.0)


def simulate_pymunk(problem: CompliantProblem) -> CompliantResult:
    """Step ``problem`` with pymunk: the contact, then ``settings.duration`` of free motion
    (the engine behind ``simulate_compliant(..., engine="pymunk")``)."""
    wall = time.perf_counter()
    s = problem.settings
    dt = step_size(problem)
    free = free_steps(s, dt)
    par = parameter_rows(problem_arrays(problem), problem_law(problem, dt, 0.0))[0].tolist()
    if problem.geometry == "outline":
        par[f.P_START] = outline_start(problem, par)
    start = par[f.P_START]
    state = [0.0] * 12
    f.free_state(problem.state0.tolist(), start, state)
    state = np.array(state)
    if problem.geometry == "point":
        _check_approach(problem, state)
    space, body1, body2 = _space(problem, state)
    stepper = _Stepper(problem, space, body1, body2, par)
    rows = [_row(start, body1, body2)] if s.record else None
    stepper.half_kick()
    _run_contact(stepper, rows)
    # the contact force was zero in the last step: these are the post-impact velocities
    mem, steps = stepper.mem, stepper.step_count
    delta_p = f.permanent_crush(mem[f.M_DMAX], problem.eps, problem.preload, problem.stiffness)
    t_end = separation_time(mem, start, steps, dt, delta_p)
    post = post_velocities(par, stepper.state(), stepper.lo, start + steps * dt, t_end)
    out = np.zeros(f.N_OUT)
    write_outputs(par, mem, stepper.tal, out, steps, t_end, post)
    _check_physics(problem, out)
    separation_index = len(rows) - 1 if rows is not None else 0
    mem[f.M_ON] = 0.0                     # free motion; tyres still act
    for _ in range(free):
        stepper.step()
        if rows is not None:
            rows.append(_row(start + stepper.step_count * dt, body1, body2))
    out[f.O_STEPS] = stepper.step_count
    records = (None, None, None)
    if rows is not None:
        records = _records(problem, rows, stepper, separation_index)
    return result_from_row(out, problem, records, time.perf_counter() - wall)


def _check_physics(problem: CompliantProblem, out) -> None:
    """SimulationError when the stepped contact gained energy or outlasted
    ``settings.max_contact_time`` (:func:`sim.compliant_setup.physics_refusal`)."""
    after = (kinetic_energy(problem.mass1, problem.inertia1, out[f.O_V1:f.O_V1 + 2],
                            out[f.O_W1])
             + kinetic_energy(problem.mass2, problem.inertia2, out[f.O_V2:f.O_V2 + 2],
                              out[f.O_W2]))
    with np.errstate(invalid="ignore", over="ignore"):
        refused = physics_refusal(problem.energy_before, float(after), float(out[f.O_DURATION]),
                                  problem.settings)
    if refused is not None:
        raise SimulationError(refused[0], refused[1], int(out[f.O_STEPS]))


def simulate_compliant(case: pim.Case, eps, stiffness=None, friction=0.0, geometry="point",
                       tyre_friction=0.0, settings: CompliantSettings | None = None, *,
                       engine: str = "numba", tyre_mode=None, preload=None,
                       tangential_recovery=None, contact_time=None):
    """Simulate impacts with a finite-duration crush contact (docs/contact-model.md).

    Takes only physical inputs (never a PIM output). Both engines step the same functions
    (:mod:`sim.compliant_formula`) the same way and agree to round-off: "numba" (default)
    runs a batch of scenes on the compiled integrator and returns arrays; "pymunk" steps one
    scene in pymunk (the cross-check), with its history and trajectory.

    Parameters
    ----------
    case : pim.Case
        Masses, inertias, pre-impact motion, C and Gamma (the point contact starts at C at
        t = 0 with normal n at Gamma), outlines for ``geometry="outline"``. Any field may
        be an array on the "numba" engine (a batch; "pymunk" takes a single case).
    eps : array_like
        Restitution of the crush hysteresis [-] in [0, 1] (exact for a point mass).
    stiffness : array_like, optional
        Loading stiffness k [N/m] > 0 (a car: about 7.5e5, :data:`DEFAULT_STIFFNESS`); or
        None with ``contact_time``.
    friction : array_like
        Coulomb coefficient mu_c between the vehicles [-] >= 0.
    geometry : {"point", "outline"}
        Point against the plane, or the outlines crushing into each other ("pymunk" only).
    tyre_friction : array_like
        Tyre/ground friction mu_tyre [-] >= 0 acting during the contact (0: none).
    settings : CompliantSettings, optional
        Numerics and the defaults of the contact inputs below. ``duration`` and ``record``
        (trajectory, history, secondary impact) act on the "pymunk" engine only.
    engine : {"numba", "pymunk"}
        The integrator (:data:`ENGINES`).
    tyre_mode : str or array_like of str, optional
        "rolling" or "locked" wheels per scene; None: ``settings.tyre_mode``.
    preload : array_like, optional
        Force at zero crush a [N] >= 0 of the loading curve; None: ``settings.preload``.
    tangential_recovery : array_like, optional
        Tangential recovery r [-] in [0, 1] of the friction spring; None:
        ``settings.tangential_recovery`` (itself None: eps^2).
    contact_time : array_like, optional
        Instead of ``stiffness``: the frictionless contact time T [s] > 0 the stiffness is
        chosen for, k = (pi (1 + eps) / (2 T))^2 / K_nn
        (:func:`sim.contact_law.stiffness_for_duration`), per scene.

    Returns
    -------
    CompliantBatch or CompliantResult
        "numba": :class:`sim.CompliantBatch`, arrays at the broadcast shape of every input
        (post-impact velocities, yaw rates, contact time, crushes, energies, impulse...),
        with a status code per scene instead of an exception (``status``, ``ok``,
        ``failures()``; ``result(i)`` gives one scene as a CompliantResult).
        "pymunk": :class:`sim.CompliantResult` of the single case.

    Raises
    ------
    ValueError
        Bad input (the field is named), a run longer than ``settings.max_fixed_steps``.
    SimulationError
        "pymunk" only: "no_contact", "never_separated", "tunnelled".
    """
    if engine == "numba":
        return simulate_batch(case, eps, stiffness, friction, geometry, tyre_friction,
                              settings, tyre_mode=tyre_mode, preload=preload,
                              tangential_recovery=tangential_recovery,
                              contact_time=contact_time)
    if engine != "pymunk":
        raise InputError(f"engine must be one of {ENGINES}, got {engine!r}")
    extra = dict(tyre_mode=tyre_mode, preload=preload, tangential_recovery=tangential_recovery)
    return simulate_pymunk(_one_problem(case, eps, stiffness, friction, geometry,
                                        tyre_friction, settings, extra=extra,
                                        contact_time=contact_time))


def _one_problem(case, eps, stiffness, friction, geometry, tyre_friction, settings, *, extra,
                 contact_time) -> CompliantProblem:
    """The single scene of ``engine="pymunk"``: the settings with the given contact inputs
    (``extra``), the stiffness from ``contact_time`` when that is given."""
    settings = settings or CompliantSettings()
    refuse_frozen(settings, "the pymunk engine")
    overrides = {k: v for k, v in extra.items() if v is not None}
    if overrides:
        settings = replace(settings, **overrides)
    if (stiffness is None) == (contact_time is None):
        raise InputError("give either stiffness [N/m] or contact_time [s] (not both, not "
                         "neither)")
    if contact_time is not None:
        k_nn = build_problem(case, eps, 1.0, friction, geometry, tyre_friction, settings).k_nn
        time_ = check_positive(contact_time, "contact_time", "s")
        stiffness = float(stiffness_for_duration(time_, k_nn, check_fraction(eps, "eps")))
    return build_problem(case, eps, stiffness, friction, geometry, tyre_friction, settings)
