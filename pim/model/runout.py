"""Post-impact run-out: a planar rigid body on four tyres, from the post-impact state to rest.

The only forces are the tyre forces of :mod:`pim.model.tyres` (Coulomb friction against
slip, regularised near zero slip). Equations of motion, global frame, state
``(x, y, psi, v_x, v_y, omega)``:

``m dv/dt = sum_i F_i``, ``I domega/dt = sum_i (R(psi) p_i) x F_i``,
``dx/dt = v``, ``dpsi/dt = omega``.

The right-hand side is written once, in :mod:`pim.model.runout_formula` (the tyre law of
:mod:`pim.model.tyres`, the field tyre's load transfer, the wheels' steer and braking from the
driver's tables, the equations of motion), and evaluated here on Python floats
(:class:`TimedRhs`) and on numpy arrays (:func:`runout_rhs`); numba compiles the same
functions (:mod:`pim.model.runout_kernel`). Integrators:

- :func:`runout`: one vehicle, scipy ``solve_ivp`` with a terminal stop event (the
  reference, adaptive, tolerance given by the caller; on :class:`TimedRhs`, or on the
  compiled :class:`pim.model.runout_kernel.CompiledRhs` when given);
- :func:`runout_many`: many samples at once, a fixed-step classical Runge-Kutta in numpy
  over all samples still moving (Coulomb tyre, constant inputs), checked against
  :func:`runout` in the tests;
- :func:`pim.model.runout_kernel.integrate_many`: the same fixed-step scheme compiled and
  parallel (the Monte Carlo's path), either tyre law.

A vehicle "stops" when ``|v| + |omega| r_max < stop_speed`` (``r_max`` the largest tyre
arm); one that has not stopped after ``max_time`` (60 s by default) is flagged
(``stopped = False``), its last state reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .driver import DriverInputs, wheel_tables
from .event import Track
from .numbers import InputError, real_array
from .runout_formula import derivative
from .tyres import (
    DEFAULT_REGULARISATION,
    STANDARD_GRAVITY,
    TyreData,
    static_loads,
    wheel_positions,
)

__all__ = ["StoppedBeforeImpact", "RunoutVehicle", "Runout", "RunoutBatch", "runout_rhs",
           "runout", "runout_many", "MAX_TIME", "timed_rhs", "TimedRhs", "RhsData",
           "pre_impact_motion"]

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
        object.__setattr__(self, "_plain", _plain_fields(self))    # (read by .plain)
        if not _plain_valid(self):      # arrays, numpy scalars, or a field out of range
            self._check_fields()

    def _check_fields(self):
        """The fields' checks on arrays: an :class:`InputError` naming the first bad one."""
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
    def plain(self) -> bool:
        """True when the fields are Python numbers (one vehicle, no per-sample arrays):
        the one-sample paths (:meth:`RhsData.one`) apply."""
        return self._plain

    @property
    def positions(self) -> np.ndarray:
        """Tyre positions in the body frame [m], shape (..., 4, 2)."""
        return wheel_positions(self.wheelbase, self.track, self.cg_to_front_axle)

    @property
    def loads(self) -> np.ndarray:
        """Static tyre loads [N], shape (..., 4)."""
        return static_loads(self.mass, self.wheelbase, self.cg_to_front_axle, self.gravity)


#: The fields :class:`RunoutVehicle` requires finite and > 0.
_POSITIVE = ("mass", "yaw_inertia", "wheelbase", "track", "friction")
#: Python numbers (``bool`` excluded: :func:`pim.model.numbers.real_array` refuses it).
_PLAIN = (float, int)


def _plain_fields(vehicle: RunoutVehicle) -> bool:
    """:attr:`RunoutVehicle.plain` of ``vehicle`` (worked out once, when it is made)."""
    for name in _PLAIN_FIELDS:
        if type(getattr(vehicle, name)) not in _PLAIN:
            return False
    return _plain_four(vehicle.braking) and (type(vehicle.steer) in _PLAIN
                                             or _plain_four(vehicle.steer))


#: The fields :func:`_plain_fields` requires as Python numbers.
_PLAIN_FIELDS = _POSITIVE + ("cg_to_front_axle",)


def _plain_four(value) -> bool:
    """``value`` is a tuple or list of four Python numbers."""
    if type(value) not in (tuple, list) or len(value) != 4:
        return False
    for v in value:
        if type(v) not in _PLAIN:
            return False
    return True


def _plain_valid(vehicle: RunoutVehicle) -> bool:
    """True when every checked field of ``vehicle`` is a Python number (a tuple of four
    for braking and steer) within its range: the checks of
    :meth:`RunoutVehicle._check_fields` on numbers, without numpy's small-array cost. False
    leaves the decision (and the error) to those checks."""
    if not vehicle.plain:
        return False
    steer = vehicle.steer
    try:
        v = [float(getattr(vehicle, name)) for name in _POSITIVE]
        a = float(vehicle.cg_to_front_axle)
        for x in v:
            if not (math.isfinite(x) and x > 0):
                return False
        if not (math.isfinite(a) and 0 <= a <= v[2]):
            return False
        for b in vehicle.braking:
            if not 0 <= float(b) <= 1:
                return False
        for x in (steer,) if type(steer) in _PLAIN else steer:
            if not math.isfinite(float(x)):
                return False
        return vehicle.regularisation > 0
    except OverflowError:           # an int beyond float's range
        return False


@dataclass(frozen=True)
class RhsData:
    """A vehicle's data as the run-out's right-hand side reads them, samples on axis 0.

    Built by :meth:`of` from a :class:`RunoutVehicle` (its fields broadcast over n samples);
    :meth:`sample` gives one sample's ``vehicle`` tuple of :mod:`pim.model.runout_formula`
    (Python, numba), :meth:`columns` all samples' with the samples on the last axis (numpy).

    Attributes
    ----------
    mass : ndarray (n,) [kg]
    yaw_inertia : ndarray (n,) [kg m^2]
    wheel_x, wheel_y : ndarray (n, 4) [m] tyre positions in the body frame
    load : ndarray (n, 4) [N] static tyre loads
    friction : ndarray (n,) [-]
    regularisation : float [m/s]
    times : ndarray (k,) [s] the driver's table times, or ``[0]`` for constant inputs
    steer : ndarray (n, k, 4) [rad] steer angles at ``times``, or (n, 2, 4) the cosine and
        sine of constant angles
    brake : ndarray (n, k, 4) [-] braking fractions at ``times``
    tyre : ndarray (n, 15), the field tyre's data row
        (:data:`pim.model.runout_formula.TYRE_COLUMNS`), or (n, 0) for the Coulomb law
    """

    mass: np.ndarray
    yaw_inertia: np.ndarray
    wheel_x: np.ndarray
    wheel_y: np.ndarray
    load: np.ndarray
    friction: np.ndarray
    regularisation: float
    times: np.ndarray
    steer: np.ndarray
    brake: np.ndarray
    tyre: np.ndarray

    @classmethod
    def of(cls, vehicle: RunoutVehicle, n: int) -> RhsData:
        """The data of ``vehicle`` for n samples (C-contiguous arrays)."""
        def per_sample(value, shape):
            return np.ascontiguousarray(np.broadcast_to(np.asarray(value, dtype=float),
                                                        shape))

        positions = np.broadcast_to(vehicle.positions, (n, 4, 2))
        times, steer, brake = _input_tables(vehicle, n)
        return cls(mass=per_sample(vehicle.mass, (n,)),
                   yaw_inertia=per_sample(vehicle.yaw_inertia, (n,)),
                   wheel_x=per_sample(positions[..., 0], (n, 4)),
                   wheel_y=per_sample(positions[..., 1], (n, 4)),
                   load=per_sample(vehicle.loads, (n, 4)),
                   friction=per_sample(vehicle.friction, (n,)),
                   regularisation=float(vehicle.regularisation), times=times, steer=steer,
                   brake=brake, tyre=_tyre_rows(vehicle, n))

    @classmethod
    def one(cls, vehicle: RunoutVehicle, positions=None) -> RhsData:
        """:meth:`of` for one sample (n = 1), the same arrays, without its broadcasting
        (a single event's scene): for a vehicle with :attr:`RunoutVehicle.plain` fields
        and no driver, else :meth:`of`. ``positions``: ``vehicle.positions`` when the
        caller has them."""
        if vehicle.driver is not None or not vehicle.plain:
            return cls.of(vehicle, 1)
        pos = vehicle.positions if positions is None else positions
        steer, turn = np.empty(4), np.empty((1, 2, 4))
        steer[:] = vehicle.steer
        np.cos(steer, out=turn[0, 0])
        np.sin(steer, out=turn[0, 1])
        wheels = np.ascontiguousarray(pos.T)[:, None]          # (2, 1, 4): x, y
        return cls(mass=np.array([float(vehicle.mass)]),
                   yaw_inertia=np.array([float(vehicle.yaw_inertia)]),
                   wheel_x=wheels[0], wheel_y=wheels[1],
                   load=vehicle.loads[None], friction=np.array([float(vehicle.friction)]),
                   regularisation=float(vehicle.regularisation), times=np.zeros(1),
                   steer=turn, brake=np.array([[vehicle.braking]], dtype=float),
                   tyre=_tyre_rows(vehicle, 1))

    @property
    def reach(self) -> np.ndarray:
        """The largest tyre arm of each sample [m] (n,)."""
        return np.hypot(self.wheel_x, self.wheel_y).max(axis=-1)

    def take(self, index) -> RhsData:
        """The samples ``index`` (an index array)."""
        return replace(self, **{name: getattr(self, name)[index] for name in (
            "mass", "yaw_inertia", "wheel_x", "wheel_y", "load", "friction", "steer",
            "brake", "tyre")})

    def sample(self, i: int) -> tuple:
        """Sample i's ``vehicle`` tuple (:mod:`pim.model.runout_formula`): numbers and small
        arrays."""
        return (float(self.mass[i]), float(self.yaw_inertia[i]), self.wheel_x[i],
                self.wheel_y[i], self.load[i], float(self.friction[i]), self.regularisation,
                self.times, self.steer[i], self.brake[i], self.tyre[i])

    def columns(self) -> tuple:
        """All samples' ``vehicle`` tuple with the samples on the last axis (numpy's
        evaluation of :mod:`pim.model.runout_formula`); a driver's tables, shared by all
        samples, stay (k, 4)."""
        def last(a):
            return np.moveaxis(a, 0, -1)

        shared = self.times.shape[0] > 1
        return (self.mass, self.yaw_inertia, last(self.wheel_x), last(self.wheel_y),
                last(self.load), self.friction, self.regularisation, self.times,
                self.steer[0] if shared else last(self.steer),
                self.brake[0] if shared else last(self.brake), last(self.tyre))


def _tyre_rows(vehicle: RunoutVehicle, n: int) -> np.ndarray:
    """Per-sample field-tyre data (n, 15) (:data:`pim.model.runout_formula.TYRE_COLUMNS`), or
    (n, 0) for the Coulomb law."""
    tyre = vehicle.tyre
    if tyre is None:
        return np.zeros((n, 0))
    brake_start = 0.0 if vehicle.driver is None else vehicle.driver.brake_start
    rows = np.empty((n, 15))
    rows[:, 0:4] = tyre.per_wheel("longitudinal_stiffness")
    rows[:, 4:8] = tyre.per_wheel("cornering_stiffness")
    for col, value in enumerate((brake_start, tyre.buildup_time, tyre.rolling_resistance,
                                 tyre.cg_height, vehicle.wheelbase, vehicle.track,
                                 vehicle.cg_to_front_axle), start=8):
        rows[:, col] = np.broadcast_to(np.asarray(value, dtype=float), (n,))
    return rows


def _input_tables(vehicle: RunoutVehicle, n: int) -> tuple:
    """``(time (k,), steer (n, k, 4), brake (n, k, 4))``: the driver's tables, or the
    per-sample constant ``braking`` and ``steer`` as one-row tables (then ``steer`` is
    (n, 2, 4): the cos and sin of the constant angles)."""
    if vehicle.driver is not None:
        time, steer, brake, _ = wheel_tables(vehicle.driver, None, None)
        return (np.ascontiguousarray(time, dtype=float),
                np.ascontiguousarray(np.broadcast_to(steer, (n,) + steer.shape)),
                np.ascontiguousarray(np.broadcast_to(brake, (n,) + brake.shape)))
    steer = np.broadcast_to(np.asarray(vehicle.steer, dtype=float), (n, 4))
    brake = np.broadcast_to(np.asarray(vehicle.braking, dtype=float), (n, 4))
    return (np.zeros(1), np.ascontiguousarray(np.stack([np.cos(steer), np.sin(steer)], axis=1)),
            np.ascontiguousarray(brake[:, None, :]))


def runout_rhs(t, state, vehicle: RunoutVehicle) -> np.ndarray:
    """Time derivative of run-out states (numpy, vectorised over leading axes).

    :func:`pim.model.runout_formula.derivative` evaluated on arrays: the same equations that
    :class:`TimedRhs` evaluates on floats and the compiled kernel compiles.

    Parameters
    ----------
    t : float
        [s] time since the impact (reads driver tables and the brake build-up).
    state : array_like, shape (..., 6)
        ``(x [m], y [m], psi [rad], v_x [m/s], v_y [m/s], omega [rad/s])``.
    vehicle : RunoutVehicle
        Fields scalar or broadcasting over the states' leading axes (``braking``, ``steer``
        (..., 4)).

    Returns
    -------
    ndarray, shape (..., 6)
    """
    state = np.asarray(state, dtype=float)
    lead = state.shape[:-1]
    flat = state.reshape(-1, 6)
    data = RhsData.of(_flat_vehicle(vehicle, lead), flat.shape[0])
    rate = derivative(t, (flat[:, 2], flat[:, 3], flat[:, 4], flat[:, 5]), data.columns())
    return np.stack(np.broadcast_arrays(*rate), axis=-1).reshape(lead + (6,))


def _flat_vehicle(vehicle: RunoutVehicle, lead: tuple) -> RunoutVehicle:
    """``vehicle`` with its per-sample fields broadcast to ``lead`` and flattened."""
    n = int(np.prod(lead))

    def flat(value, tail=()):
        return np.broadcast_to(np.asarray(value, dtype=float), lead + tail).reshape(
            (n,) + tail)

    return replace(vehicle, **{name: flat(getattr(vehicle, name)) for name in (
        "mass", "yaw_inertia", "wheelbase", "track", "cg_to_front_axle", "friction")},
        braking=flat(vehicle.braking, (4,)), steer=flat(vehicle.steer, (4,)))


def timed_rhs(t, state, vehicle: RunoutVehicle) -> np.ndarray:
    """Time derivative of one vehicle's run-out state (either tyre law, driver inputs).

    :class:`TimedRhs` for one call (see there).

    Parameters
    ----------
    t : float [s] time since the impact.
    state : array_like (6,) ``(x, y, psi, v_x, v_y, omega)``.
    vehicle : RunoutVehicle with scalar fields.
    """
    return TimedRhs(vehicle)(t, state)


class TimedRhs:
    """One vehicle's run-out right-hand side on Python floats: ``rhs(t, y) -> dy/dt``.

    :func:`pim.model.runout_formula.derivative` on the vehicle's data (computed once): the
    reference that scipy's ``solve_ivp`` integrates in :func:`runout`, for either tyre law,
    with or without driver tables. The compiled kernel
    (:class:`pim.model.runout_kernel.CompiledRhs`) compiles the same function.

    Parameters
    ----------
    vehicle : RunoutVehicle
        Scalar fields.
    """

    def __init__(self, vehicle: RunoutVehicle):
        self.vehicle = vehicle
        self.data = RhsData.of(vehicle, 1).sample(0)

    def __call__(self, t, state) -> np.ndarray:
        _, _, psi, vx, vy, omega = (float(v) for v in state)
        return np.array(derivative(float(t), (psi, vx, vy, omega), self.data), dtype=float)


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

    def track(self, times, outline=None) -> Track:
        """The run-out as an event's :class:`pim.model.event.Track` at ``times`` [s] after
        the impact: states interpolated linearly, the rest state held after its end."""
        t = np.minimum(np.asarray(times, float), self.time[-1])
        states = np.stack([np.interp(t, self.time, self.states[:, k]) for k in range(6)], -1)
        return Track(states[:, :2], states[:, 2], states[:, 3:5], states[:, 5],
                     outline=outline)


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
        ``rhs(t, y) -> dy/dt`` of this vehicle to integrate instead of the reference one
        (:class:`TimedRhs`, Python floats): the compiled
        :class:`pim.model.runout_kernel.CompiledRhs`, the same equations, for repeated runs
        (the run-out inverse).
    """
    from scipy.integrate import solve_ivp

    y0 = _initial_state(position, heading, velocity, yaw_rate)
    stop_speed = vehicle.regularisation / 5 if stop_speed is None else stop_speed
    positions = vehicle.positions
    reach = float(np.max(np.hypot(positions[..., 0], positions[..., 1])))
    if _stop_measure(y0, reach) < stop_speed:
        return Runout(np.zeros(1), y0[None, :], y0[:2].copy(), float(y0[2]), 0.0, True)

    def event(t, y):
        return _stop_measure(y, reach) - stop_speed

    event.terminal = True
    event.direction = -1
    fun = TimedRhs(vehicle) if rhs is None else rhs
    if vehicle.timed:
        method = method or "LSODA"     # the brush tyre is stiff at low rolling speed
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
    data = RhsData.of(vehicle, n)
    reach = data.reach
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
        ya = _rk4_step(t, y[active], data.take(active).columns(), dt)
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


def _rk4_step(t, y, vehicle, dt) -> np.ndarray:
    """One classical Runge-Kutta step of the states ``y`` (n, 6) (numpy, samples on the last
    axis of ``vehicle``, :meth:`RhsData.columns`)."""
    def rate(time, state):
        d = derivative(time, (state[:, 2], state[:, 3], state[:, 4], state[:, 5]), vehicle)
        return np.stack(np.broadcast_arrays(*d), axis=-1)

    k1 = rate(t, y)
    k2 = rate(t + 0.5 * dt, y + 0.5 * dt * k1)
    k3 = rate(t + 0.5 * dt, y + 0.5 * dt * k2)
    k4 = rate(t + dt, y + dt * k3)
    return y + (dt / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
