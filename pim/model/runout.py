"""Post-impact run-out: a planar rigid body on four tyres, from the post-impact state to rest.

The only forces are the tyre forces of :mod:`pim.model.tyres` (Coulomb friction against
slip, regularised near zero slip). Equations of motion, global frame, state
``(x, y, psi, v_x, v_y, omega)``:

``m dv/dt = sum_i F_i``, ``I domega/dt = sum_i (R(psi) p_i) x F_i``,
``dx/dt = v``, ``dpsi/dt = omega``.

Two integrators of the same right-hand side (:func:`runout_rhs`):

- :func:`runout`: one vehicle, scipy ``solve_ivp`` with a terminal stop event (the
  reference, adaptive, tolerance given by the caller);
- :func:`runout_many`: many samples at once, a fixed-step classical Runge-Kutta in numpy
  over all samples still moving (the Monte Carlo path), checked against :func:`runout` in
  the tests.

A vehicle "stops" when ``|v| + |omega| r_max < stop_speed`` (``r_max`` the largest tyre
arm); one that has not stopped after ``max_time`` (60 s by default) is flagged
(``stopped = False``), its last state reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .driver import DriverInputs, wheel_tables
from .numbers import InputError, real_array
from .tyres import (
    DEFAULT_REGULARISATION,
    STANDARD_GRAVITY,
    TyreData,
    brake_ramp,
    field_wheel_force,
    net_force_and_moment,
    static_loads,
    transferred_load,
    tyre_forces,
    wheel_force,
    wheel_positions,
)

__all__ = ["StoppedBeforeImpact", "RunoutVehicle", "Runout", "RunoutBatch", "runout_rhs",
           "runout", "runout_many", "MAX_TIME", "timed_rhs", "TimedRhs", "pre_impact_motion",
           "FRONT", "LEFT"]

FRONT = np.array([1.0, 1.0, 0.0, 0.0])  # per wheel (FL, FR, RL, RR): front axle
LEFT = np.array([1.0, 0.0, 1.0, 0.0])   # per wheel: left side

MAX_TIME = 60.0  # [s] simulated time after which a vehicle that still moves is flagged


class StoppedBeforeImpact(InputError):
    """:func:`pre_impact_motion`: the vehicle comes to rest before it reaches the impact."""


@dataclass(frozen=True)
class RunoutVehicle:
    """A vehicle as the run-out sees it. Fields may be arrays (one value per sample).

    Attributes
    ----------
    mass : [kg] > 0
    yaw_inertia : [kg m^2] > 0
    wheelbase : [m] > 0
    track : [m] > 0
    cg_to_front_axle : [m], CG forward to the front AXLE, in [0, wheelbase] (not
        :attr:`pim.Vehicle.cg_to_front`, the CG to the front of the outline)
    friction : [-] tyre-road friction coefficient > 0
    braking : [-] four braking fractions in [0, 1] (front-left, front-right, rear-left,
        rear-right): 0 free-rolling, 1 locked
    steer : [rad] four fixed steer angles (counter-clockwise)
    gravity : [m/s^2]
    regularisation : [m/s] slip regularisation (see :mod:`pim.model.tyres`)
    tyre : TyreData or None (None: the Coulomb law (:func:`pim.model.tyres.wheel_force`),
        else the field tyre (:func:`pim.model.tyres.field_wheel_force`, load transfer,
        rolling resistance, brake build-up))
    driver : DriverInputs or None (when given, its tables replace ``braking`` and ``steer``)
    """

    mass: object
    yaw_inertia: object
    wheelbase: object
    track: object
    cg_to_front_axle: object
    friction: object
    braking: object = (1.0, 1.0, 1.0, 1.0)
    steer: object = (0.0, 0.0, 0.0, 0.0)
    gravity: float = STANDARD_GRAVITY
    regularisation: float = DEFAULT_REGULARISATION
    tyre: TyreData | None = None
    driver: DriverInputs | None = None

    @property
    def cg_to_front(self):
        """The old name of :attr:`cg_to_front_axle` [m] (CG to the front AXLE), kept for
        code written before the rename."""
        return self.cg_to_front_axle

    @property
    def tyre_model(self) -> str:
        """``"brush"`` (the field tyre) or ``"coulomb"``."""
        return "coulomb" if self.tyre is None else "brush"

    @property
    def timed(self) -> bool:
        """True when the forces depend on time or on the field tyre (the timed right-hand
        side :func:`timed_rhs`)."""
        return self.tyre is not None or self.driver is not None

    def __post_init__(self):
        for name, unit in (("mass", "kg"), ("yaw_inertia", "kg m^2"), ("wheelbase", "m"),
                           ("track", "m"), ("friction", "-")):
            value = real_array(getattr(self, name), f"runout.{name}", unit)
            if not np.all(np.isfinite(value)) or np.any(value <= 0):
                raise InputError(f"runout.{name} must be finite and > 0 [{unit}], "
                                 f"got {getattr(self, name)!r}")
        a = real_array(self.cg_to_front_axle, "runout.cg_to_front_axle", "m")
        length = real_array(self.wheelbase, "runout.wheelbase", "m")
        if not np.all(np.isfinite(a)) or np.any(a < 0) or np.any(a > length):
            raise InputError(f"runout.cg_to_front_axle must be in [0, wheelbase] [m], "
                             f"got {self.cg_to_front_axle!r}")
        braking = real_array(self.braking, "runout.braking", "-")
        if braking.shape[-1:] != (4,) or not np.all((braking >= 0) & (braking <= 1)):
            raise InputError(f"runout.braking must be four fractions in [0, 1] (front-left, "
                             f"front-right, rear-left, rear-right), got {self.braking!r}")
        steer = real_array(self.steer, "runout.steer", "rad")
        if steer.shape[-1:] not in ((4,), ()) or not np.all(np.isfinite(steer)):
            raise InputError(f"runout.steer must be four finite angles [rad], "
                             f"got {self.steer!r}")
        if not self.regularisation > 0:
            raise InputError(f"runout.regularisation must be > 0 [m/s], "
                             f"got {self.regularisation!r}")

    @property
    def positions(self) -> np.ndarray:
        """Tyre positions in the body frame [m], shape (..., 4, 2)."""
        return wheel_positions(self.wheelbase, self.track, self.cg_to_front_axle)

    @property
    def loads(self) -> np.ndarray:
        """Static tyre loads [N], shape (..., 4)."""
        return static_loads(self.mass, self.wheelbase, self.cg_to_front_axle, self.gravity)


def runout_rhs(state, mass, yaw_inertia, positions, loads, friction, braking, steer,
               regularisation=DEFAULT_REGULARISATION) -> np.ndarray:
    """Time derivative of the run-out state (vectorised over leading axes).

    Parameters
    ----------
    state : array_like, shape (..., 6)
        ``(x [m], y [m], psi [rad], v_x [m/s], v_y [m/s], omega [rad/s])``.
    mass, yaw_inertia : array_like
        [kg], [kg m^2].
    positions, loads, friction, braking, steer, regularisation
        As :func:`pim.model.tyres.tyre_forces`.

    Returns
    -------
    ndarray, shape (..., 6)
    """
    state = np.asarray(state, dtype=float)
    velocity, heading, yaw_rate = state[..., 3:5], state[..., 2], state[..., 5]
    forces = tyre_forces(velocity, yaw_rate, heading, positions, loads, friction, braking,
                         steer, regularisation)
    force, moment = net_force_and_moment(forces, positions, heading)
    return np.concatenate([velocity, yaw_rate[..., None],
                           force / np.asarray(mass, dtype=float)[..., None],
                           (moment / np.asarray(yaw_inertia, dtype=float))[..., None]],
                          axis=-1)


def _inputs_at(t, tables, buildup):
    """Steer [rad] and braking [-] of the four wheels at time ``t`` (braking times the
    build-up ramp)."""
    time, steer, brake, start = tables
    ramp = 1.0 if buildup is None else brake_ramp(t, start, buildup)
    return (np.array([np.interp(t, time, steer[:, w]) for w in range(4)]),
            np.array([np.interp(t, time, brake[:, w]) for w in range(4)]) * ramp)


def timed_rhs(t, state, vehicle: RunoutVehicle, tables=None) -> np.ndarray:
    """Time derivative of one vehicle's run-out state with driver inputs and either tyre law.

    The inputs at ``t`` come from ``tables`` (:func:`pim.model.driver.wheel_tables`, default:
    the vehicle's own). With the field tyre the loads are transferred quasi-statically
    (:func:`pim.model.tyres.transferred_load`) from the acceleration the static loads give,
    and the forces evaluated again at those loads (one fixed-point pass: the algebraic loop
    load -> force -> acceleration -> load closed once). The compiled kernel
    (:mod:`pim.model.runout_kernel`) computes the same.

    Parameters
    ----------
    t : float [s] time since the impact.
    state : array_like (6,) ``(x, y, psi, v_x, v_y, omega)``.
    vehicle : RunoutVehicle with scalar fields.
    tables : tuple, optional
        ``wheel_tables(vehicle.driver, vehicle.braking, vehicle.steer)``, precomputed.
    """
    return TimedRhs(vehicle, tables)(t, state)


class TimedRhs:
    """:func:`timed_rhs` with the vehicle's constant parts computed once (for solve_ivp)."""

    def __init__(self, vehicle: RunoutVehicle, tables=None):
        self.vehicle = vehicle
        self.tables = (wheel_tables(vehicle.driver, vehicle.braking, vehicle.steer)
                       if tables is None else tables)
        self.positions, self.static = vehicle.positions, vehicle.loads
        tyre = vehicle.tyre
        self.buildup = None if tyre is None else tyre.buildup_time
        if tyre is not None:
            self.c_long = tyre.per_wheel("longitudinal_stiffness")
            self.c_lat = tyre.per_wheel("cornering_stiffness")

    def __call__(self, t, state) -> np.ndarray:
        vehicle, tyre = self.vehicle, self.vehicle.tyre
        steer, brake = _inputs_at(t, self.tables, self.buildup)
        _, _, psi, vx, vy, om = np.asarray(state, dtype=float)
        c, s = np.cos(psi), np.sin(psi)
        cw, sw = np.cos(psi + steer), np.sin(psi + steer)
        px, py, static = self.positions[:, 0], self.positions[:, 1], self.static
        mu, vr, mass = vehicle.friction, vehicle.regularisation, vehicle.mass
        if tyre is None:
            fx, fy, mz = wheel_force(c, s, vx, vy, om, px, py, cw, sw, static, mu, brake, vr)
        else:
            loads = static
            for _ in range(2):
                fx, fy, mz = field_wheel_force(c, s, vx, vy, om, px, py, cw, sw, loads, mu,
                                               brake, vr, self.c_long, self.c_lat,
                                               tyre.rolling_resistance)
                ax, ay = fx.sum() / mass, fy.sum() / mass
                loads = transferred_load(static, mass, c * ax + s * ay, -s * ax + c * ay,
                                         tyre.cg_height, vehicle.wheelbase, vehicle.track,
                                         vehicle.cg_to_front_axle, FRONT, LEFT)
        return np.array([vx, vy, om, fx.sum() / mass, fy.sum() / mass,
                         mz.sum() / vehicle.yaw_inertia])


def pre_impact_motion(vehicle: RunoutVehicle, position, heading, velocity, yaw_rate,
                      start_time, *, rtol=1e-8, atol=1e-10):
    """The approach: integrate a vehicle from its state at ``start_time`` < 0 to the impact.

    The driver's tables are read at negative times (a vehicle braking into the impact:
    ``time = ["-1.2 s", "-1 s", "0 s"]``, ``brake`` rising from 0); the result is the state
    at ``t = 0`` as ``(position (2,), heading, velocity (2,), yaw_rate)``, SI, global frame,
    the impact's pre-impact motion. A vehicle that stops before the impact raises.
    """
    from scipy.integrate import solve_ivp

    if not start_time < 0:
        raise InputError(f"pre_impact_motion: start_time must be < 0 [s], got {start_time!r}")
    y0 = _initial_state(position, heading, velocity, yaw_rate)
    sol = solve_ivp(TimedRhs(vehicle), (start_time, 0.0), y0, method="LSODA", rtol=rtol,
                    atol=atol)
    end = sol.y[:, -1]
    if np.hypot(end[3], end[4]) < vehicle.regularisation:
        raise StoppedBeforeImpact("pre_impact_motion: the vehicle stops before the impact")
    return end[:2].copy(), float(end[2]), end[3:5].copy(), float(end[5])


@dataclass(frozen=True)
class Runout:
    """One vehicle's run-out (SI, global frame).

    Attributes
    ----------
    time : ndarray (n,) [s]
    states : ndarray (n, 6) ``(x, y, psi, v_x, v_y, omega)`` along the way
    rest_position : ndarray (2,) [m]
    rest_heading : float [rad]
    stop_time : float [s] (``max_time`` when it did not stop)
    stopped : bool, False when the vehicle still moved after ``max_time``
    interpolant : callable t -> states (6, ...) or None, solve_ivp's dense output (only
        with ``dense_output=True``)
    """

    time: np.ndarray
    states: np.ndarray
    rest_position: np.ndarray
    rest_heading: float
    stop_time: float
    stopped: bool
    interpolant: object = None

    @property
    def distance(self) -> float:
        """Straight-line distance from the start to rest [m]."""
        return float(np.hypot(*(self.rest_position - self.states[0, :2])))


@dataclass(frozen=True)
class RunoutBatch:
    """Run-outs of many samples (SI, global frame); arrays have the samples on axis 0.

    ``trajectory`` (steps, n, 6) is kept only when ``record=True``.

    Attributes
    ----------
    rest_position : ndarray (n, 2)
        CG position at rest (or at ``max_time`` when not stopped) [m].
    rest_heading : ndarray (n,)
        Heading psi at rest, integrated continuously (not wrapped) [rad].
    stop_time : ndarray (n,)
        Time from the impact to rest [s] (``max_time`` when not stopped).
    stopped : ndarray of bool (n,)
        True where the sample came to rest (``|v| + |omega| r_max < stop_speed``) within
        ``max_time``.
    time : ndarray (steps,) or None
        Times of the recorded states [s] (None without ``record``).
    trajectory : ndarray (steps, n, 6) or None
        Every step's state ``(x, y, psi, v_x, v_y, omega)`` [m, m, rad, m/s, m/s, rad/s]
        (None without ``record``).
    """

    rest_position: np.ndarray
    rest_heading: np.ndarray
    stop_time: np.ndarray
    stopped: np.ndarray
    time: np.ndarray | None = None
    trajectory: np.ndarray | None = None


def _initial_state(position, heading, velocity, yaw_rate) -> np.ndarray:
    position = real_array(position, "runout.position", "m")
    velocity = real_array(velocity, "runout.velocity", "m/s")
    heading = real_array(heading, "runout.heading", "rad")
    yaw_rate = real_array(yaw_rate, "runout.yaw_rate", "rad/s")
    for name, value in (("position", position), ("velocity", velocity),
                        ("heading", heading), ("yaw_rate", yaw_rate)):
        if not np.all(np.isfinite(value)):
            raise InputError(f"runout.{name} must be finite, got {value!r}")
    position, velocity = np.broadcast_arrays(position, velocity)
    heading, yaw_rate = np.broadcast_arrays(heading, yaw_rate)
    return np.concatenate([position, heading[..., None], velocity, yaw_rate[..., None]],
                          axis=-1)


def _stop_measure(state, reach) -> np.ndarray:
    """|v| + |omega| r_max: an upper bound of every tyre's slip speed [m/s]."""
    return np.hypot(state[..., 3], state[..., 4]) + np.abs(state[..., 5]) * reach


def runout(vehicle: RunoutVehicle, position, heading, velocity, yaw_rate, *,
           max_time=MAX_TIME, stop_speed=None, rtol=1e-8, atol=1e-10,
           method=None, dense_output=False, rhs=None) -> Runout:
    """Integrate one vehicle from its post-impact state to rest with scipy ``solve_ivp``.

    Parameters
    ----------
    vehicle : RunoutVehicle
        Scalar fields.
    position : array_like (2,) [m]; heading [rad]; velocity (2,) [m/s]; yaw_rate [rad/s]
        Post-impact state of the CG.
    max_time : float
        [s] simulated time after which the vehicle is flagged as not stopped.
    stop_speed : float, optional
        [m/s]; default ``regularisation / 5``.
    rtol, atol, method, dense_output
        Passed to ``scipy.integrate.solve_ivp``; ``method`` defaults to "DOP853" for the
        Coulomb tyre, "LSODA" for the field tyre or driver tables (stiff at low rolling
        speed: the lateral force's slope ``C_y / V_r``).
    rhs : callable, optional
        ``rhs(t, y) -> dy/dt`` of this vehicle to integrate instead of the numpy one
        (:func:`runout_rhs`, :class:`TimedRhs`): the compiled
        :class:`pim.model.runout_kernel.CompiledRhs`, the same equations, for repeated runs
        (the run-out inverse).
    """
    from scipy.integrate import solve_ivp

    y0 = _initial_state(position, heading, velocity, yaw_rate)
    stop_speed = vehicle.regularisation / 5 if stop_speed is None else stop_speed
    positions, loads = vehicle.positions, vehicle.loads
    reach = float(np.max(np.hypot(positions[..., 0], positions[..., 1])))
    args = (vehicle.mass, vehicle.yaw_inertia, positions, loads, vehicle.friction,
            np.asarray(vehicle.braking, dtype=float), np.asarray(vehicle.steer, dtype=float),
            vehicle.regularisation)
    if _stop_measure(y0, reach) < stop_speed:
        return Runout(np.zeros(1), y0[None, :], y0[:2].copy(), float(y0[2]), 0.0, True)

    def event(t, y):
        return _stop_measure(y, reach) - stop_speed

    event.terminal = True
    event.direction = -1
    if vehicle.timed:
        fun = TimedRhs(vehicle) if rhs is None else rhs
        method = method or "LSODA"     # the brush tyre is stiff at low rolling speed
    elif rhs is not None:
        fun = rhs
    else:
        def fun(t, y):
            return runout_rhs(y, *args)
    sol = solve_ivp(fun, (0.0, max_time), y0, method=method or "DOP853",
                    rtol=rtol, atol=atol, events=event, dense_output=dense_output)
    stopped = sol.status == 1
    states = sol.y.T
    return Runout(sol.t, states, states[-1, :2].copy(), float(states[-1, 2]),
                  float(sol.t[-1]), bool(stopped), sol.sol)


def runout_many(vehicle: RunoutVehicle, position, heading, velocity, yaw_rate, *,
                dt=0.004, max_time=MAX_TIME, stop_speed=None, record=False) -> RunoutBatch:
    """Integrate many samples at once: fixed-step RK4 in numpy over the samples still moving.

    Parameters
    ----------
    vehicle : RunoutVehicle
        Fields scalar or arrays broadcasting over the n samples (``braking``/``steer``
        shape (n, 4) or (4,)).
    position : (n, 2) [m]; heading : (n,) [rad]; velocity : (n, 2) [m/s]; yaw_rate : (n,)
        Post-impact states.
    dt : float
        [s] step. The regularised friction makes the motion below ``v_r`` decay at rate
        ``mu g / v_r`` (160 1/s at the defaults); RK4 is stable and accurate for
        ``dt`` well below ``2.8 v_r / (mu g)``.
    record : bool
        Keep every step's state (for plots and animations of a few samples).

    Returns
    -------
    RunoutBatch
    """
    if vehicle.timed:
        raise InputError("runout_many: the field tyre and driver tables run in the compiled "
                         "run-out (pim.model.runout_kernel.integrate_many) or runout()")
    y = np.atleast_2d(_initial_state(position, heading, velocity, yaw_rate)).copy()
    n = y.shape[0]
    stop_speed = vehicle.regularisation / 5 if stop_speed is None else stop_speed
    positions = np.broadcast_to(vehicle.positions, (n, 4, 2))
    loads = np.broadcast_to(vehicle.loads, (n, 4))
    mass = np.broadcast_to(np.asarray(vehicle.mass, dtype=float), (n,))
    inertia = np.broadcast_to(np.asarray(vehicle.yaw_inertia, dtype=float), (n,))
    friction = np.broadcast_to(np.asarray(vehicle.friction, dtype=float), (n,))
    braking = np.broadcast_to(np.asarray(vehicle.braking, dtype=float), (n, 4))
    steer = np.broadcast_to(np.asarray(vehicle.steer, dtype=float), (n, 4))
    reach = np.max(np.hypot(positions[..., 0], positions[..., 1]), axis=-1)
    stop_time = np.full(n, float(max_time))
    stopped = _stop_measure(y, reach) < stop_speed
    stop_time[stopped] = 0.0
    steps = int(np.ceil(max_time / dt))
    frames = [y.copy()] if record else None
    t = 0.0
    for _ in range(steps):
        active = np.flatnonzero(~stopped)
        if active.size == 0:
            break
        args = (mass[active], inertia[active], positions[active], loads[active],
                friction[active], braking[active], steer[active], vehicle.regularisation)
        ya = y[active]
        k1 = runout_rhs(ya, *args)
        k2 = runout_rhs(ya + 0.5 * dt * k1, *args)
        k3 = runout_rhs(ya + 0.5 * dt * k2, *args)
        k4 = runout_rhs(ya + dt * k3, *args)
        ya = ya + (dt / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
        y[active] = ya
        t += dt
        now = _stop_measure(ya, reach[active]) < stop_speed
        stop_time[active[now]] = t
        stopped[active[now]] = True
        if record:
            frames.append(y.copy())
    time = trajectory = None
    if record:
        trajectory = np.stack(frames)
        time = dt * np.arange(trajectory.shape[0])
    return RunoutBatch(y[:, :2].copy(), y[:, 2].copy(), stop_time, stopped, time, trajectory)
