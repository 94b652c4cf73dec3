"""Independent integration of the point contact with ``scipy.integrate.solve_ivp``.

The reference of the finite-duration scene: the same equations of motion and contact law
(:mod:`sim.contact_law`, the model under test; the point kinematics of
:func:`sim.compliant_setup.point_contact`) integrated by an adaptive high-order method,
explicit ("DOP853", 8th order) or implicit ("Radau", 5th order), with events instead of
fixed steps:

* loading (F_n = F_L(delta), delta_max = delta) until the crush stops growing
  (d delta/dt = -v_rel . n crosses zero downward): delta_max is frozen there; with
  epsilon = 0 this is the separation (no rebound);
* unloading along the straight line to delta_p until delta = delta_p (separation, the end),
  or back to loading if delta climbs to delta_max again;
* the friction spring z is a state variable of the sweeping process of
  :mod:`sim.contact_law` written as modes, so that the right-hand side is smooth inside each
  solve_ivp call: sticking (dz/dt = v_t, F_t = -k_t z) until k_t |z| reaches mu_c F_n,
  sliding (z on the cone, dz/dt = +-dz_max/dt with dz_max/dt = mu_c (dF_n/d delta)
  (d delta/dt) / k_t, F_t = -+mu_c F_n) until the slip stops pushing outward.

Each smooth phase is one ``solve_ivp`` call; ``settings.max_phases`` caps the phases (a
chattering stick/slip switch) and ``settings.max_steps`` the accepted steps over all of them
(a stiff scene), both raising ``SimulationError("not_converged")``.

State: x1, y1, theta1, vx1, vy1, w1, x2, y2, theta2, vx2, vy2, w2, z (a fixed vehicle 2
keeps zero velocity). Nothing is shared with the pymunk stepping of :mod:`sim.compliant`.
"""

from __future__ import annotations

import math
import time

import numpy as np

import pim
from pim.model.numbers import InputError, speed_text

from .compliant_setup import (
    CompliantProblem,
    CompliantResult,
    CompliantSettings,
    ContactHistory,
    build_problem,
    kinetic_energy,
    refuse_frozen,
    point_contact,
    reversal,
)
from .contact_law import normal_force, normal_stiffness, permanent_crush
from .contact_tyres import tyre_force
from .failures import SimulationError
from .result import Trajectory

__all__ = ["reference_compliant"]


def _unpack(y):
    return (y[0:2], y[2], y[3:5], y[5], y[6:8], y[8], y[9:11], y[11])


STICK, UNLOAD = 0, 2        # friction modes besides sliding (+1 / -1, z = +- z_max)


class _Model:
    """Right-hand side and events of one phase of the contact."""

    def __init__(self, problem: CompliantProblem):
        self.p = problem
        self.loading = True
        self.delta_max = 0.0
        self.delta_p = 0.0
        self.mode = STICK        # friction: STICK, UNLOAD (sticking, |z| shrinking), +-1 sliding
        self.cone = (0.0, 0.0)   # (k_t |z| - mu F_n, mode v_t - dz_max/dt) at the last call

    def contact(self, y):
        return point_contact(self.p, _unpack(y))

    def forces(self, y):
        p = self.p
        point, n, t, delta, slip_n, slip_t = self.contact(y)
        dmax = max(delta, self.delta_max) if self.loading else self.delta_max
        fn = float(normal_force(delta, dmax, p.eps, p.preload, p.stiffness))
        z = y[12]
        dz = 0.0
        ft = 0.0
        if p.friction > 0:
            kt = p.tangential_stiffness
            stiff = float(normal_stiffness(delta, dmax, p.eps, p.preload, p.stiffness))
            rate = p.friction * stiff * (-slip_n) / kt
            if self.mode == STICK:             # sticking, loading: the spring follows the slip
                dz, ft = slip_t, -kt * z
            elif self.mode == UNLOAD:          # sticking, unloading at 1 / r the rate
                dz, ft = slip_t / p.tangential_recovery, -kt * z
            else:                              # sliding on the cone
                dz, ft = self.mode * rate, -self.mode * p.friction * fn
            # z leaves the cone when its own rate inward (v_t, or v_t / r unloading)
            # beats the cone's: with r < 1 a slip turning back releases the spring faster
            out = self.mode * slip_t
            if out < 0 and p.tangential_recovery < 1:
                out = out / max(p.tangential_recovery, 1e-12)
            self.cone = (kt * abs(z) - p.friction * fn, out - rate)
        return point, n * fn + t * ft, dz

    def rhs(self, t, y):
        p = self.p
        x1, a1, v1, w1, x2, a2, v2, w2 = _unpack(y)
        point, force, dz = self.forces(y)
        d1, d2 = point - x1, point - x2
        f1, f2 = force, -force
        m1 = d1[0] * force[1] - d1[1] * force[0]
        m2 = -(d2[0] * force[1] - d2[1] * force[0])
        if p.tyre_friction > 0:
            ft, mt = tyre_force(v1, w1, a1, p.wheels1, p.load1, p.tyre_friction, p.tyre_mode)
            f1, m1 = f1 + ft, m1 + mt
            if not p.fixed2:
                ft, mt = tyre_force(v2, w2, a2, p.wheels2, p.load2, p.tyre_friction,
                                    p.tyre_mode)
                f2, m2 = f2 + ft, m2 + mt
        out = np.zeros(13)
        out[0:2] = v1
        out[2] = w1
        out[3:5] = f1 / p.mass1
        out[5] = m1 / p.inertia1
        if not p.fixed2:
            out[6:8] = v2
            out[8] = w2
            out[9:11] = f2 / p.mass2
            out[11] = m2 / p.inertia2
        out[12] = dz
        return out

    def impulse_rate(self, t, y):
        """d/dt of (impulse x, impulse y, |F|, |F| P_x, |F| P_y) (quadrature states)."""
        point, force, _ = self.forces(y)
        size = math.hypot(force[0], force[1])
        return np.array([force[0], force[1], size, size * point[0], size * point[1]])


def _event(function, direction: int):
    function.terminal = True
    function.direction = direction
    return function


def _phase_events(model: _Model, y, d: float, v: float) -> dict:
    """name -> terminal event of the current phase (crush and friction modes)."""
    problem = model.p
    events = {}
    if model.loading:            # d delta / dt = -v_rel . n crosses zero downward
        events["peak"] = _event(lambda t, y: -model.contact(y)[4], -1)
    else:                        # delta falls to delta_p, or climbs back to delta_max
        events["released"] = _event(lambda t, y: model.contact(y)[3] - model.delta_p, -1)
        events["reloaded"] = _event(      # (a margin of 1e-9 of it: no chattering)
            lambda t, y: model.contact(y)[3] - model.delta_max * (1.0 + 1e-9), 1)
    if problem.friction <= 0:
        return events

    def cone(t, y, i):
        model.forces(y)
        return model.cone[i]

    if model.mode in (STICK, UNLOAD):     # the spring force reaches the Coulomb limit
        events["slips"] = _event(
            lambda t, y: cone(t, y, 0) - 1e-9 * problem.friction * problem.stiffness * d, 1)
    else:                                 # sliding: the slip stops pushing outward
        events["sticks"] = _event(lambda t, y: cone(t, y, 1) + 1e-9 * v, -1)
    if problem.tangential_recovery < 1 and model.mode == STICK:   # the slip turns back
        events["turns"] = _event(lambda t, y: y[12] * model.contact(y)[5], -1)
    if model.mode == UNLOAD:
        sign = 1.0 if y[12] > 0 else -1.0    # z reaches 0, or the slip pushes out again
        events["unloaded"] = _event(lambda t, y: sign * y[12], -1)
        events["reloads"] = _event(lambda t, y: y[12] * model.contact(y)[5], 1)
    return events


def _switch_friction(model: _Model, y, name: str, directions: set) -> None:
    """The friction mode after event ``name`` (module notes; "Tangential recovery" of
    :mod:`sim.contact_law`)."""
    r = model.p.tangential_recovery
    if name == "slips":                          # sticking -> sliding along z
        model.mode = 1 if y[12] > 0 else -1
        directions.add(model.mode)
        return
    if name in ("unloaded", "reloads"):
        model.mode = STICK
        if name == "unloaded":
            y[12] = 0.0
        return
    backward = y[12] * model.contact(y)[5] < 0   # "turns", or "sticks" off the cone
    if name == "sticks" and not (backward and r < 1):
        model.mode = STICK
    elif r == 0.0:                               # plastic: nothing to give back
        model.mode, y[12] = STICK, 0.0
    else:
        model.mode = UNLOAD


def _tolerances(problem: CompliantProblem):
    """Absolute tolerances from the scales of the contact: crush d, speed v, gyration k."""
    v = problem.speed_scale
    d = v / math.sqrt(problem.stiffness * problem.k_nn)
    k1 = math.sqrt(problem.inertia1 / problem.mass1)
    k2 = k1 if problem.fixed2 else math.sqrt(problem.inertia2 / problem.mass2)
    scale = np.array([d, d, d / k1, v, v, v / k1, d, d, d / k2, v, v, v / k2, d])
    return problem.settings.rtol * scale, d, v


def _first_mode(model: _Model, y, directions: set) -> None:
    """At first contact (F_n = 0): slide if the slip outruns the growing Coulomb cone."""
    problem = model.p
    if problem.friction > 0:
        _, _, _, _, slip_n0, slip_t0 = model.contact(y)
        rate0 = problem.friction * problem.stiffness * (-slip_n0) / problem.tangential_stiffness
        if abs(slip_t0) > rate0 or problem.preload > 0:
            model.mode = 1 if slip_t0 > 0 else -1
            directions.add(model.mode)


class _StepCap(Exception):
    """Raised from inside ``solve_ivp`` when a phase used up the steps left."""


def _step_counter(budget: int):
    """A ``solve_ivp`` event that never fires and counts the accepted steps.

    solve_ivp evaluates every event once at the start and once after each accepted step
    (root finding calls only the events that changed sign, which this one never does), so
    the calls after the first are the accepted steps; past ``budget`` it raises
    :class:`_StepCap`.
    """
    calls = [-1]

    def count(t, y):
        calls[0] += 1
        if calls[0] > budget:
            raise _StepCap
        return 1.0

    return count


def _phase(model: _Model, y, t0: float, events: dict, atol, budget: int):
    """solve_ivp over one smooth phase, with the impulse quadratures appended; at most
    ``budget`` accepted steps (:class:`_StepCap` beyond)."""
    from scipy.integrate import solve_ivp

    s = model.p.settings

    def rhs(t, yq):
        return np.r_[model.rhs(t, yq[:13]), model.impulse_rate(t, yq[:13])]

    def wrap(ev):
        return _event(lambda t, yq: ev(t, yq[:13]), ev.direction)

    counter = _step_counter(budget)
    return solve_ivp(rhs, (t0, t0 + s.max_contact_time), np.r_[y, np.zeros(5)],
                     method=s.method, rtol=s.rtol, atol=np.r_[atol, np.full(5, s.rtol * 1e-6)],
                     events=[wrap(e) for e in events.values()] + [counter],
                     dense_output=s.record)


def _capped_phase(model: _Model, y, t0: float, events: dict, atol, steps: int,
                  phases: int):
    """:func:`_phase` within the caps of the settings (``max_phases``, ``max_steps``).

    Raises
    ------
    SimulationError
        "not_converged", naming the cap that was reached and how to raise it.
    """
    s = model.p.settings
    if phases >= s.max_phases:
        raise SimulationError(
            "not_converged", f"the reference switched crush or friction mode {phases} times "
            f"by t = {t0:.6g} s without separating (settings.max_phases = {s.max_phases}): "
            f"a chattering stick/slip switch? Raise CompliantSettings(max_phases=...) if "
            f"the contact really has that many phases", steps)
    try:
        return _phase(model, y, t0, events, atol, s.max_steps - steps)
    except _StepCap:
        raise SimulationError(
            "not_converged", f"solve_ivp ({s.method}, rtol {s.rtol:g}) took more than "
            f"settings.max_steps = {s.max_steps} steps by phase {phases + 1} without "
            f"separating: a stiff scene (try method='Radau') or a tolerance near round-off; "
            f"raise CompliantSettings(max_steps=...) to let it run longer", steps) from None


def _integrate(model: _Model, y):
    """Every phase from first contact to separation: (y, t, impulse, steps, pieces,
    stick time, slide directions)."""
    problem, s = model.p, model.p.settings
    atol, d, v = _tolerances(problem)
    t0, steps, stick_time, directions = 0.0, 0, 0.0, set()
    _first_mode(model, y, directions)
    impulse, pieces, phases = np.zeros(5), [], 0
    while True:
        if not model.loading and model.contact(y)[3] <= model.delta_p + 1e-12 * d:
            break                               # released exactly at a mode switch
        events = _phase_events(model, y, d, v)
        sol = _capped_phase(model, y, t0, events, atol, steps, phases)
        phases += 1
        if sol.status < 0:
            raise SimulationError("not_converged", f"solve_ivp ({s.method}) failed: "
                                  f"{sol.message}", steps)
        steps += len(sol.t) - 1
        if s.record:
            pieces.append((sol.t[0], sol.t[-1], sol.sol, model.loading, model.delta_max,
                           model.mode))
        y, impulse = sol.y[:13, -1].copy(), impulse + sol.y[13:, -1]
        if sol.status == 0:
            raise SimulationError("never_separated", f"the contact still pushed after "
                                  f"{s.max_contact_time:g} s (max_contact_time)", steps)
        stick_time += (sol.t[-1] - sol.t[0]) if model.mode in (STICK, UNLOAD) else 0.0
        t0 = sol.t[-1]
        fired = [name for name, e in zip(events, sol.t_events[:-1], strict=True) if len(e)]
        if _after_event(model, y, fired, directions):
            break
    return y, t0, impulse, steps, pieces, stick_time, directions


def _after_event(model: _Model, y, fired: list, directions: set) -> bool:
    """Update the phase after the events ``fired``; True when the contact has ended."""
    problem = model.p
    crush = [name for name in fired if name in ("peak", "released", "reloaded")]
    if not crush:
        _switch_friction(model, y, fired[0], directions)
        return False
    if crush[0] == "peak":                      # reached the peak crush
        model.delta_max = model.contact(y)[3]
        model.delta_p = float(permanent_crush(model.delta_max, problem.eps, problem.preload,
                                              problem.stiffness))
        model.loading = False
        return problem.eps == 0.0               # no rebound: the contact ends at the peak
    if crush[0] == "released":                  # released at delta_p: separated
        return True
    model.loading = True                        # reloaded
    return False


def reference_compliant(case: pim.Case, eps, stiffness, friction=0.0, geometry="point",
                        tyre_friction=0.0, settings: CompliantSettings | None = None
                        ) -> CompliantResult:
    """The point contact integrated by ``solve_ivp`` (``settings.method``, ``settings.rtol``).

    The single-case signature and result of ``sim.simulate_compliant(...,
    engine="pymunk")`` (:class:`sim.CompliantResult`); only ``geometry="point"`` (the outline
    contact has no independent reference). ``history`` holds the dense output
    at 200 instants of the contact with ``settings.record``; ``trajectory`` the states at
    first contact and separation (and dense samples between them with ``record``).

    Raises
    ------
    ValueError
        Bad input, or a geometry other than "point".
    SimulationError
        "no_contact" (no approach at C), "never_separated", "not_converged" (solve_ivp
        failed, or more than ``settings.max_phases`` phases or ``settings.max_steps``
        steps: the message names the cap and how to raise it).
    """
    wall = time.perf_counter()
    if geometry != "point":
        raise InputError(f"reference_compliant integrates the point contact only, "
                         f"got geometry={geometry!r}")
    refuse_frozen(settings, "the solve_ivp reference")
    problem = build_problem(case, eps, stiffness, friction, geometry, tyre_friction, settings)
    model = _Model(problem)
    y = np.r_[problem.state0, 0.0]
    *_, slip_n, slip_t0 = model.contact(y)
    if not slip_n < 0:
        raise SimulationError("no_contact", f"no contact: the vehicles do not approach at C "
                              f"(u_n = {speed_text(slip_n, '.6g')} >= 0)", 0)
    y, t0, impulse, steps, pieces, stick_time, directions = _integrate(model, y)
    return _reference_result(model, y, t0, impulse, steps, pieces, stick_time,
                             slip_reversed=reversal(np.sign(slip_t0), model.contact(y)[5],
                                                    problem.speed_scale, directions),
                             wall=time.perf_counter() - wall)


def _reference_result(model: _Model, y, t0, impulse, steps, pieces, stick_time, *,
                      slip_reversed, wall) -> CompliantResult:
    problem, s = model.p, model.p.settings
    v1, w1 = y[3:5].copy(), float(y[5])
    v2, w2 = y[9:11].copy(), float(y[11])
    history = _history(model, pieces) if s.record else None
    states = [np.r_[0.0, problem.state0]]
    if s.record:
        for a, b, dense, *_ in pieces:
            states += [np.r_[t, dense(t)[:12]] for t in np.linspace(a, b, 20)[1:]]
    else:
        states.append(np.r_[t0, y[:12]])
    arr = np.array(states)
    trajectory = Trajectory(
        time=arr[:, 0], position1=arr[:, 1:3], angle1=arr[:, 3], position2=arr[:, 7:9],
        angle2=arr[:, 9], velocity1=arr[:, 4:6], yaw_rate1=arr[:, 6], velocity2=arr[:, 10:12],
        yaw_rate2=arr[:, 12], impact_index=len(arr) - 1, outline1=problem.outline1,
        outline2=problem.outline2, fixed2=problem.fixed2)
    return CompliantResult(
        velocity1=v1, velocity2=v2, yaw_rate1=w1, yaw_rate2=w2, contact_duration=t0,
        contact_start=0.0, impulse=impulse[0:2],
        impact_point=impulse[3:5] / impulse[2] if impulse[2] > 0 else np.full(2, np.nan),
        peak_force=float(np.max(np.hypot(*history.force.T))) if history is not None
        else math.nan, peak_crush=model.delta_max, permanent_crush=model.delta_p,
        energy_before=problem.energy_before,
        energy_after=(kinetic_energy(problem.mass1, problem.inertia1, v1, w1)
                      + kinetic_energy(problem.mass2, problem.inertia2, v2, w2)),
        tyre_work=math.nan, stick_fraction=stick_time / t0 if problem.friction > 0 else 0.0,
        slip_reversed=bool(slip_reversed), steps=steps, wall_time=wall, integrator=s.method,
        eps=problem.eps, stiffness=problem.stiffness, friction=problem.friction,
        tyre_friction=problem.tyre_friction, geometry=problem.geometry, settings=s,
        history=history, trajectory=trajectory,
        tangential_recovery=problem.tangential_recovery)


def _history(model: _Model, pieces):
    rows = []
    total = sum(b - a for a, b, *_ in pieces)
    for a, b, dense, loading, dmax, mode in pieces:
        count = max(2, int(round(200 * (b - a) / max(total, 1e-300))))
        model.loading, model.delta_max, model.mode = loading, dmax, mode
        for t in np.linspace(a, b, count):
            y = dense(t)[:13]
            point, n, tt, delta, slip_n, slip_t = model.contact(y)
            _, force, _ = model.forces(y)
            fn, ft = float(force @ n), float(force @ tt)
            rows.append((t, delta, force[0], force[1], fn, ft, slip_t,
                         mode in (STICK, UNLOAD),
                         point[0], point[1]))
    h = np.array(rows, float)
    return ContactHistory(time=h[:, 0], crush=h[:, 1], force=h[:, 2:4], normal_force=h[:, 4],
                          tangential_force=h[:, 5], slip=h[:, 6],
                          sticking=h[:, 7].astype(bool), point=h[:, 8:10])
