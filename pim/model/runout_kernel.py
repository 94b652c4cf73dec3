"""Compiled, parallel fixed-step integration of many run-outs (the Monte Carlo's forward model).

numba compiles the run-out's right-hand side from its one source,
:mod:`pim.model.runout_formula` (the functions Python and numpy evaluate in
:mod:`pim.model.runout`), with the tyre law :func:`pim.model.tyres.wheel_force` (Coulomb) or
:func:`pim.model.tyres.field_wheel_force` with :func:`pim.model.tyres.transferred_load` (the
field tyre) compiled from :mod:`pim.model.tyres` itself (one law, every evaluator, as
:mod:`pim.model.kernel` compiles the PIM formula). Each sample is integrated by the
classical Runge-Kutta method with a fixed step (for the field tyre, shrunk with the speed
near rest, where its lateral slope ``C_y / V_r`` is stiff: ``h <= 2.7 sqrt(S^2 + v_r^2) /
sum_w C_y,w (1/m + r_w^2/I)``, ``S`` the stop measure) until it stops (``|v| + |omega| r_max <
stop_speed``) or ``max_time`` passes, on all cores (``prange`` over samples, each with its
own early stop, so a short run-out does not wait for a long one). Along the way the distance
from each given path point to the CG's polyline is tracked (closest point on each step's
segment, signed: negative to the right of the direction of travel), so a fit to tyre-mark
points needs no stored trajectory.

numba is imported only when this module is (the run-out fits and the reconstruction Monte
Carlo import it); the kernels are cached on disk under a key that covers this file,
pim/model/runout_formula.py and pim/model/tyres.py.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from . import runout_formula, tyres
from .numba_cache import compile_module, stamped_cache
from .numbers import InputError
from .runout import MAX_TIME, RhsData, RunoutVehicle

__all__ = ["integrate_many", "one_signature", "RUNOUT_STEP", "CompiledRhs", "rk4_stages",
           "STABLE_STEP"]

#: Default fixed step [s] (as :func:`pim.model.runout.runout_many`).
RUNOUT_STEP = 0.004

#: The tyre law, compiled from pim/model/tyres.py (the names the formula calls).
_TYRE_LAW = {
    "wheel_force": njit(inline="always", error_model="numpy")(tyres.wheel_force),
    "field_wheel_force": njit(inline="always", error_model="numpy")(tyres.field_wheel_force),
    "transferred_load": njit(inline="always", error_model="numpy")(tyres.transferred_load),
    "brake_ramp": njit(inline="always", error_model="numpy")(tyres.brake_ramp),
}
_derivative = compile_module(runout_formula, _TYRE_LAW).derivative
#: Decorator caching a kernel under a key that covers this file, the formula and the tyres.
_cached = stamped_cache(runout_formula, tyres)


@njit(inline="always", error_model="numpy")
def _segment_distance(ax, ay, bx, by, qx, qy):  # pragma: no cover - compiled
    """Distance from q to the segment a-b, negative when q is to the right of a -> b."""
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0
    if length2 > 0.0:
        t = min(max(((qx - ax) * dx + (qy - ay) * dy) / length2, 0.0), 1.0)
    ex, ey = qx - (ax + t * dx), qy - (ay + t * dy)
    d = np.sqrt(ex * ex + ey * ey)
    return -d if dx * ey - dy * ex < 0.0 else d


@njit(inline="always", error_model="numpy")
def _lateral_stiffness(m, ii, px, py, tyre):  # pragma: no cover - compiled
    """``sum_w C_y,w (1/m + r_w^2/I)`` [N/(m/s) per kg]: the field tyre's lateral adhesion
    slope ``C_y / V_r`` on the body's translation and yaw, times the rolling speed (0 for the
    Coulomb law)."""
    k = 0.0
    if tyre.shape[0] > 0:
        for w in range(4):
            k += tyre[4 + w] * (1.0 / m + (px[w] * px[w] + py[w] * py[w]) / ii)
    return k


@njit(inline="always", error_model="numpy")
def _rk4_stages(t, dt, motion, vehicle, ks):  # pragma: no cover - compiled
    """The four stage derivatives of one classical RK4 step of ``dt`` [s] from ``motion``
    (psi, v_x, v_y, omega) into the rows of ``ks`` (4, 6). One call site of the inlined
    right-hand side in a loop over the stages, not four: numba inlines the formula's body
    (both tyre passes, four wheels each) once, which cuts a clean checkout's compile of the
    kernel by minutes of CPU, with the same arithmetic in the same order (bitwise the
    unrolled k1..k4)."""
    psi, vx, vy, om = motion
    h = 0.5 * dt
    for stage in range(4):
        if stage == 0:
            ts, state = t, (psi, vx, vy, om)
        else:
            a = dt if stage == 3 else h
            ts = t + a
            state = (psi + a * ks[stage - 1, 2], vx + a * ks[stage - 1, 3],
                     vy + a * ks[stage - 1, 4], om + a * ks[stage - 1, 5])
        d = _derivative(ts, state, vehicle)
        for j in range(6):
            ks[stage, j] = d[j]


#: The four stage derivatives of one RK4 step (compiled, inlined where called): the event
#: kernel (:mod:`pim.model.event_kernel`) steps each vehicle with it too.
rk4_stages = _rk4_stages

#: RK4's stability limit on a real eigenvalue is h |lambda| < 2.785; the step near rest keeps
#: h lambda below this (margin for the yaw-sideslip coupling).
STABLE_STEP = 2.7


@_cached
@njit(parallel=True, cache=True, error_model="numpy")
def _integrate(y0, mass, inertia, px, py, load, mu, times, steer_tab, brake_tab, tyre, vr,
               reach, dt, max_time, stop_speed, points, out, stop_time, stopped,
               distance):  # pragma: no cover - compiled
    n = y0.shape[0]
    k = points.shape[1]
    for i in prange(n):
        x, y, psi = y0[i, 0], y0[i, 1], y0[i, 2]
        vx, vy, om = y0[i, 3], y0[i, 4], y0[i, 5]
        for j in range(k):
            qx, qy = points[i, j, 0] - x, points[i, j, 1] - y
            distance[i, j] = np.sqrt(qx * qx + qy * qy)
        speed = np.sqrt(vx * vx + vy * vy) + abs(om) * reach[i]
        done = speed < stop_speed
        vehicle = (mass[i], inertia[i], px[i], py[i], load[i], mu[i], vr, times,
                   steer_tab[i], brake_tab[i], tyre[i])
        stiff = _lateral_stiffness(mass[i], inertia[i], px[i], py[i], tyre[i])
        ks = np.empty((4, 6))
        t = 0.0
        while not done and t < max_time:
            # the field tyre's lateral adhesion is stiff at low rolling speed (slope
            # C_y / V_r): below about 1 m/s the step shrinks with the speed so that RK4
            # stays stable there instead of chattering about rest (Coulomb: always dt)
            dt_i = min(dt, STABLE_STEP * np.sqrt(speed * speed + vr * vr) / stiff) \
                if stiff > 0.0 else dt
            _rk4_stages(t, dt_i, (psi, vx, vy, om), vehicle, ks)
            k1, k2, k3, k4 = ks[0], ks[1], ks[2], ks[3]
            w = dt_i / 6.0
            nx = x + w * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
            ny = y + w * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
            for j in range(k):
                d = _segment_distance(x, y, nx, ny, points[i, j, 0], points[i, j, 1])
                if abs(d) < abs(distance[i, j]):
                    distance[i, j] = d
            x, y = nx, ny
            psi = psi + w * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2])
            vx = vx + w * (k1[3] + 2.0 * k2[3] + 2.0 * k3[3] + k4[3])
            vy = vy + w * (k1[4] + 2.0 * k2[4] + 2.0 * k3[4] + k4[4])
            om = om + w * (k1[5] + 2.0 * k2[5] + 2.0 * k3[5] + k4[5])
            t += dt_i
            speed = np.sqrt(vx * vx + vy * vy) + abs(om) * reach[i]
            done = speed < stop_speed
        out[i, 0], out[i, 1], out[i, 2] = x, y, psi
        out[i, 3], out[i, 4], out[i, 5] = vx, vy, om
        stop_time[i] = min(t, max_time)
        stopped[i] = done


@_cached
@njit(cache=True, error_model="numpy")
def _rhs_one(t, y, vehicle):  # pragma: no cover - compiled
    """The formula's derivative of one vehicle on a state array (6,), returning dy/dt (6,):
    for solve_ivp."""
    d = _derivative(t, (y[2], y[3], y[4], y[5]), vehicle)
    out = np.empty(6)
    for j in range(6):
        out[j] = d[j]
    return out


class CompiledRhs:
    """The run-out's right-hand side of one vehicle, compiled: ``rhs(t, y) -> dy/dt``.

    :func:`pim.model.runout_formula.derivative` compiled (the kernel's own right-hand side:
    either tyre law, driver tables, brake build-up), for an adaptive integrator:
    :func:`pim.model.runout.runout` takes it as ``rhs`` (the single run-out inverse
    :func:`pim.analysis.runout_fit.fit_runout` does). It computes what
    :class:`pim.model.runout.TimedRhs` computes on Python floats from the same source, to
    round-off (tested), at a few microseconds a call instead of 0.1-1 ms.

    Parameters
    ----------
    vehicle : RunoutVehicle
        Scalar fields.
    """

    def __init__(self, vehicle: RunoutVehicle):
        self.vehicle = one_signature(*RhsData.of(vehicle, 1).sample(0))

    def __call__(self, t, y) -> np.ndarray:
        return _rhs_one(float(t), np.asarray(y, dtype=float), self.vehicle)


def one_signature(*args) -> tuple:
    """The kernel's arguments with one numba type each, whatever the caller passed: arrays
    C-contiguous and writable (a copy of a read-only ``np.broadcast_to`` view, which numba
    types apart from a writable array of the same shape), numbers as Python floats and ints.

    numba compiles :func:`_integrate` once per distinct tuple of argument types (about a
    minute each); with this the run-outs of one sample or many, with per-sample or shared
    vehicle data, a driver table or not, the field tyre or Coulomb, all share one compiled
    version. Only the arrays' memory layout changes, never a value.
    """
    return tuple([_contiguous(a) if isinstance(a, np.ndarray)
                  else int(a) if isinstance(a, (int, np.integer)) else float(a) for a in args])


def _contiguous(a: np.ndarray) -> np.ndarray:
    """``a`` C-contiguous and writable: itself when it is (``np.require``'s answer then,
    without its cost), else a copy."""
    flags = a.flags
    return a if flags.c_contiguous and flags.writeable else np.require(a, requirements="CW")


def integrate_many(vehicle: RunoutVehicle, position, heading, velocity, yaw_rate, *,
                   path_points=None, dt: float = RUNOUT_STEP, max_time: float = MAX_TIME,
                   stop_speed=None):
    """Integrate n run-outs to rest at once (compiled, parallel, fixed-step RK4).

    Parameters
    ----------
    vehicle : RunoutVehicle
        Fields scalar or broadcasting over the n samples (``braking``, ``steer`` (n, 4)
        or (4,)).
    position : (n, 2) [m]; heading : (n,) [rad]; velocity : (n, 2) [m/s]; yaw_rate : (n,)
        Post-impact states.
    path_points : array_like (n, k, 2) or (k, 2), optional
        Points [m] whose distance to each CG path is returned.
    dt : float
        [s] fixed step (see :func:`pim.model.runout.runout_many` for its stability limit);
        with the field tyre the step shrinks below it near rest (module notes).
    max_time : float
        [s] a sample still moving after it is flagged (``stopped`` False).
    stop_speed : float, optional
        [m/s]; default ``regularisation / 5``.

    Returns
    -------
    final : ndarray (n, 6)
        Last state ``(x, y, psi, v_x, v_y, omega)``: the rest state where ``stopped``.
    stop_time : ndarray (n,) [s]
    stopped : ndarray (n,) of bool
    distance : ndarray (n, k) [m]
        Distance from each path point to the sample's CG path, negative for a point to the
        right of the direction of travel (the cross-track error, smooth through zero).
    """
    position = np.atleast_2d(np.asarray(position, dtype=float))
    n = position.shape[0]
    y0 = np.empty((n, 6))
    y0[:, :2] = position
    y0[:, 2] = np.broadcast_to(np.asarray(heading, dtype=float), (n,))
    y0[:, 3:5] = np.broadcast_to(np.asarray(velocity, dtype=float), (n, 2))
    y0[:, 5] = np.broadcast_to(np.asarray(yaw_rate, dtype=float), (n,))
    if not np.all(np.isfinite(y0)):
        raise InputError("runout: the post-impact states must be finite")
    data = RhsData.of(vehicle, n)
    if path_points is None:
        points = np.zeros((n, 0, 2))
    else:
        pts = np.asarray(path_points, dtype=float)
        points = np.broadcast_to(pts if pts.ndim == 3 else pts.reshape(-1, 2),
                                 (n, pts.shape[-2] if pts.ndim >= 2 else 0, 2))
    stop_speed = vehicle.regularisation / 5 if stop_speed is None else float(stop_speed)
    out = np.empty((n, 6))
    stop_time = np.empty(n)
    stopped = np.empty(n, dtype=np.bool_)
    distance = np.empty((n, points.shape[1]))
    _integrate(*one_signature(
        y0, data.mass, data.yaw_inertia, data.wheel_x, data.wheel_y, data.load, data.friction,
        data.times, data.steer, data.brake, data.tyre, data.regularisation, data.reach,
        float(dt), float(max_time), stop_speed, points, out, stop_time, stopped, distance))
    return out, stop_time, stopped, distance
