"""Compiled, parallel fixed-step integration of many run-outs (the Monte Carlo's forward model).

The same equations as :mod:`pim.model.runout` and the same tyre law: numba compiles
:func:`pim.model.tyres.wheel_force` itself (one law, two evaluators, as
:mod:`pim.model.kernel` compiles the PIM formula). Each sample is integrated by the
classical Runge-Kutta method with a fixed step until it stops (``|v| + |omega| r_max <
stop_speed``) or ``max_time`` passes, on all cores (``prange`` over samples, each with its
own early stop, so a short run-out does not wait for a long one). Along the way the distance
from each given path point to the CG's polyline is tracked (closest point on each step's
segment, signed: negative to the right of the direction of travel), so a fit to tyre-mark
points needs no stored trajectory.

numba is imported only when this module is (the reconstruction Monte Carlo imports it); the
kernel is cached on disk under a key that covers this file and pim/model/tyres.py.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from . import tyres
from .numba_cache import stamped_cache
from .numbers import InputError
from .runout import MAX_TIME, RunoutVehicle

__all__ = ["integrate_many", "RUNOUT_STEP"]

#: Default fixed step [s] (as :func:`pim.model.runout.runout_many`).
RUNOUT_STEP = 0.004

_wheel_force = njit(inline="always", error_model="numpy")(tyres.wheel_force)


@njit(inline="always", error_model="numpy")
def _rhs(x, y, psi, vx, vy, om, mass, inertia, px, py, load, mu, braking, cd, sd,
         vr):  # pragma: no cover - compiled
    c, s = np.cos(psi), np.sin(psi)
    fx = 0.0
    fy = 0.0
    mz = 0.0
    for w in range(4):
        cw, sw = c * cd[w] - s * sd[w], s * cd[w] + c * sd[w]    # psi + steer angle
        a, b, m = _wheel_force(c, s, vx, vy, om, px[w], py[w], cw, sw, load[w], mu,
                               braking[w], vr)
        fx += a
        fy += b
        mz += m
    return vx, vy, om, fx / mass, fy / mass, mz / inertia


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


@stamped_cache(tyres)
@njit(parallel=True, cache=True, error_model="numpy")
def _integrate(y0, mass, inertia, px, py, load, mu, braking, cos_steer, sin_steer, vr, reach,
               dt,
               max_steps, stop_speed, points, out, stop_time, stopped,
               distance):  # pragma: no cover - compiled
    n = y0.shape[0]
    k = points.shape[1]
    for i in prange(n):
        x, y, psi = y0[i, 0], y0[i, 1], y0[i, 2]
        vx, vy, om = y0[i, 3], y0[i, 4], y0[i, 5]
        for j in range(k):
            qx, qy = points[i, j, 0] - x, points[i, j, 1] - y
            distance[i, j] = np.sqrt(qx * qx + qy * qy)
        done = np.sqrt(vx * vx + vy * vy) + abs(om) * reach[i] < stop_speed
        steps = 0
        while not done and steps < max_steps:
            m, ii, p1, p2, ld = mass[i], inertia[i], px[i], py[i], load[i]
            f, br, cd, sd = mu[i], braking[i], cos_steer[i], sin_steer[i]
            k1 = _rhs(x, y, psi, vx, vy, om, m, ii, p1, p2, ld, f, br, cd, sd, vr)
            h = 0.5 * dt
            k2 = _rhs(x + h * k1[0], y + h * k1[1], psi + h * k1[2], vx + h * k1[3],
                      vy + h * k1[4], om + h * k1[5], m, ii, p1, p2, ld, f, br, cd, sd, vr)
            k3 = _rhs(x + h * k2[0], y + h * k2[1], psi + h * k2[2], vx + h * k2[3],
                      vy + h * k2[4], om + h * k2[5], m, ii, p1, p2, ld, f, br, cd, sd, vr)
            k4 = _rhs(x + dt * k3[0], y + dt * k3[1], psi + dt * k3[2], vx + dt * k3[3],
                      vy + dt * k3[4], om + dt * k3[5], m, ii, p1, p2, ld, f, br, cd, sd, vr)
            w = dt / 6.0
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
            steps += 1
            done = np.sqrt(vx * vx + vy * vy) + abs(om) * reach[i] < stop_speed
        out[i, 0], out[i, 1], out[i, 2] = x, y, psi
        out[i, 3], out[i, 4], out[i, 5] = vx, vy, om
        stop_time[i] = steps * dt
        stopped[i] = done


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
        [s] fixed step (see :func:`pim.model.runout.runout_many` for its stability limit).
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
    velocity = np.broadcast_to(np.asarray(velocity, dtype=float), (n, 2))
    y0 = np.empty((n, 6))
    y0[:, :2] = position
    y0[:, 2] = np.broadcast_to(np.asarray(heading, dtype=float), (n,))
    y0[:, 3:5] = velocity
    y0[:, 5] = np.broadcast_to(np.asarray(yaw_rate, dtype=float), (n,))
    if not np.all(np.isfinite(y0)):
        raise InputError("runout: the post-impact states must be finite")
    positions = np.broadcast_to(vehicle.positions, (n, 4, 2))
    px = np.ascontiguousarray(positions[..., 0])
    py = np.ascontiguousarray(positions[..., 1])
    load = np.ascontiguousarray(np.broadcast_to(vehicle.loads, (n, 4)))

    def per_sample(value, shape):
        return np.ascontiguousarray(np.broadcast_to(np.asarray(value, dtype=float), shape))

    reach = np.max(np.hypot(px, py), axis=-1)
    steer = per_sample(vehicle.steer, (n, 4))
    if path_points is None:
        points = np.zeros((n, 0, 2))
    else:
        pts = np.asarray(path_points, dtype=float)
        points = per_sample(pts if pts.ndim == 3 else pts.reshape(-1, 2),
                            (n, pts.shape[-2] if pts.ndim >= 2 else 0, 2))
    stop_speed = vehicle.regularisation / 5 if stop_speed is None else float(stop_speed)
    out = np.empty((n, 6))
    stop_time = np.empty(n)
    stopped = np.empty(n, dtype=np.bool_)
    distance = np.empty((n, points.shape[1]))
    _integrate(y0, per_sample(vehicle.mass, (n,)), per_sample(vehicle.yaw_inertia, (n,)), px,
               py, load, per_sample(vehicle.friction, (n,)), per_sample(vehicle.braking, (n, 4)),
               np.cos(steer), np.sin(steer), float(vehicle.regularisation), reach,
               float(dt), int(np.ceil(max_time / dt)), stop_speed, points, out, stop_time,
               stopped, distance)
    return out, stop_time, stopped, distance
