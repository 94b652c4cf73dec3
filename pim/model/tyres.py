"""Tyre forces of a four-wheeled vehicle on a flat road: Coulomb friction against slip.

One force law for the whole project (the post-impact run-out here; tyre forces during the
contact may call the same functions). Everything is vectorised: leading axes broadcast
(samples), the last axis of per-wheel arrays has length 4 in the order
front-left, front-right, rear-left, rear-right (``WHEELS``).

Model (documented in full in :func:`tyre_forces`):

- wheel positions in the body frame (x forward, y left, origin at the CG):
  front axle at ``+a``, rear axle at ``-(L - a)``, left/right at ``+-T/2``
  (``L`` wheelbase, ``T`` track, ``a`` CG to front axle);
- static loads from the moment balance about each axle, split equally left/right:
  ``N_front = m g (L - a) / (2 L)``, ``N_rear = m g a / (2 L)`` (no load transfer);
- each wheel's braking fraction ``f`` in [0, 1]: 0 free-rolling (friction against the
  lateral slip only), 1 locked (full Coulomb against the slip velocity), in between a
  convex combination of the two, so straight braking decelerates at ``f mu g`` and the
  force never exceeds ``mu N``;
- optional fixed steer angle per wheel (counter-clockwise, from the vehicle's heading).

Coulomb's law ``F = -mu N s / |s|`` is discontinuous at zero slip ``s``; it is regularised
as ``F = -mu N s / sqrt(|s|^2 + v_r^2)`` with ``v_r`` = ``regularisation`` [m/s] (default
0.05 m/s). Above a few ``v_r`` this is Coulomb's law; below it the force is viscous, so the
motion decays exponentially with time constant ``v_r / (mu g)`` and an ODE integrator stops
cleanly instead of chattering. The extra sliding distance this causes for a straight slide
from speed ``v0`` is ``(v_r^2 / (2 mu g)) (asinh(v0 / v_r) + ...)``, about 1 mm from 20 m/s
at mu = 0.8 (the exact regularised stopping distance is :func:`regularised_slide_distance`).
"""

from __future__ import annotations

import numpy as np

from .geometry import rotate

__all__ = ["WHEELS", "STANDARD_GRAVITY", "DEFAULT_REGULARISATION", "wheel_positions",
           "static_loads", "tyre_forces", "wheel_force", "net_force_and_moment",
           "regularised_slide_distance"]

WHEELS = ("front_left", "front_right", "rear_left", "rear_right")
STANDARD_GRAVITY = 9.80665  # [m/s^2]
DEFAULT_REGULARISATION = 0.05  # [m/s]


def wheel_positions(wheelbase, track, cg_to_front) -> np.ndarray:
    """Tyre contact points in the body frame (x forward, y left, origin at the CG).

    Parameters
    ----------
    wheelbase : array_like
        Distance front axle - rear axle ``L`` [m].
    track : array_like
        Distance left - right tyre ``T`` [m] (same front and rear).
    cg_to_front : array_like
        Distance from the CG back to the front axle ``a`` [m], 0 <= a <= L.

    Returns
    -------
    ndarray, shape (..., 4, 2)
        [m], wheels in the order of ``WHEELS``.
    """
    length, track, a = np.broadcast_arrays(*(np.asarray(v, dtype=float)
                                            for v in (wheelbase, track, cg_to_front)))
    x = np.stack([a, a, a - length, a - length], axis=-1)
    y = np.stack([track / 2, -track / 2, track / 2, -track / 2], axis=-1)
    return np.stack([x, y], axis=-1)


def static_loads(mass, wheelbase, cg_to_front, gravity=STANDARD_GRAVITY) -> np.ndarray:
    """Static normal loads on the four tyres (moments about each axle, equal left/right).

    ``N_front = m g (L - a) / (2 L)``, ``N_rear = m g a / (2 L)``.

    Parameters
    ----------
    mass : array_like
        [kg].
    wheelbase, cg_to_front : array_like
        ``L`` and ``a`` [m] (see :func:`wheel_positions`).
    gravity : array_like
        [m/s^2].

    Returns
    -------
    ndarray, shape (..., 4)
        [N], summing to ``m g``.
    """
    mass, length, a, g = np.broadcast_arrays(*(np.asarray(v, dtype=float)
                                              for v in (mass, wheelbase, cg_to_front, gravity)))
    front = mass * g * (length - a) / (2 * length)
    rear = mass * g * a / (2 * length)
    return np.stack([front, front, rear, rear], axis=-1)


def tyre_forces(velocity, yaw_rate, heading, positions, loads, friction, braking,
                steer=0.0, regularisation=DEFAULT_REGULARISATION) -> np.ndarray:
    """Friction force of each tyre on the road plane, in the global frame.

    For tyre ``i`` at body-frame position ``p_i`` the contact point moves at
    ``s_i = v + omega k x R(psi) p_i`` (the slip velocity: a wheel does not rotate about its
    axle in this model's accounting, free rolling is expressed by dropping the longitudinal
    part). With ``e_t`` the wheel's lateral unit vector (heading ``psi + delta_i`` turned
    +90 deg) and ``g(s) = s / sqrt(|s|^2 + v_r^2)`` (regularised unit vector):

    ``F_i = -mu N_i [ f_i g(s_i) + (1 - f_i) g((s_i . e_t) e_t) ]``

    i.e. locked (f = 1): Coulomb against the full slip velocity; free-rolling (f = 0):
    Coulomb against the lateral slip only; braked 0 < f < 1: the convex combination, so
    ``|F_i| <= mu N_i`` always and straight braking decelerates at ``f mu g``.

    Parameters
    ----------
    velocity : array_like, shape (..., 2)
        CG velocity [m/s], global frame.
    yaw_rate : array_like
        [rad/s].
    heading : array_like
        Vehicle heading ``psi`` [rad] (counter-clockwise from +x).
    positions : array_like, shape (..., 4, 2)
        Tyre positions in the body frame [m] (:func:`wheel_positions`).
    loads : array_like, shape (..., 4)
        Normal loads [N] (:func:`static_loads`).
    friction : array_like
        Tyre-road friction coefficient ``mu`` [-] (> 0).
    braking : array_like, shape (..., 4)
        Braking fraction ``f`` of each wheel in [0, 1]: 0 free-rolling, 1 locked.
    steer : array_like, shape (..., 4) or scalar
        Steer angle ``delta`` of each wheel [rad], counter-clockwise from the heading.
    regularisation : float
        ``v_r`` [m/s], see the module docstring.

    Returns
    -------
    ndarray, shape (..., 4, 2)
        [N], global frame.
    """
    velocity = np.asarray(velocity, dtype=float)
    heading = np.asarray(heading, dtype=float)[..., None]
    positions = np.asarray(positions, dtype=float)
    wheel_heading = heading + np.asarray(steer, dtype=float)
    fx, fy, _ = wheel_force(np.cos(heading), np.sin(heading), velocity[..., None, 0],
                            velocity[..., None, 1], np.asarray(yaw_rate, dtype=float)[..., None],
                            positions[..., 0], positions[..., 1], np.cos(wheel_heading),
                            np.sin(wheel_heading), np.asarray(loads, dtype=float),
                            np.asarray(friction, dtype=float)[..., None],
                            np.asarray(braking, dtype=float), regularisation)
    return np.stack(np.broadcast_arrays(fx, fy), axis=-1)


def wheel_force(c, s, vx, vy, omega, px, py, cw, sw, load, mu, braking, vr):
    """Force of one tyre [N] (global frame) and its yaw moment about the CG [N m].

    The law of :func:`tyre_forces` in plain arithmetic on numbers or broadcasting arrays (so
    numba compiles the same function for the batched run-out, :mod:`pim.model.runout_kernel`).

    Parameters
    ----------
    c, s : cos and sin of the vehicle's heading psi.
    vx, vy : CG velocity [m/s]; omega : yaw rate [rad/s].
    px, py : tyre position in the body frame [m].
    cw, sw : cos and sin of the wheel's heading psi + delta.
    load : normal load N [N]; mu : friction coefficient [-]; braking : f in [0, 1].
    vr : slip regularisation v_r [m/s].

    Returns
    -------
    fx, fy, moment
        ``F = -mu N [f g(s) + (1 - f) g((s . e_t) e_t)]`` with the slip ``s = v + omega k x
        R(psi) p``, ``e_t = (-sin, cos)(psi + delta)`` and ``g(s) = s / sqrt(|s|^2 + v_r^2)``;
        the moment ``(R(psi) p) x F``.
    """
    ax = c * px - s * py                       # arm R(psi) p, global frame
    ay = s * px + c * py
    sx = vx - omega * ay                       # slip velocity of the contact point
    sy = vy + omega * ax
    ex, ey = -sw, cw                           # wheel's lateral unit vector
    lat = sx * ex + sy * ey
    lx, ly = lat * ex, lat * ey
    vr2 = vr * vr
    full = braking / np.sqrt(sx * sx + sy * sy + vr2)
    side = (1.0 - braking) / np.sqrt(lx * lx + ly * ly + vr2)
    scale = -mu * load
    fx = scale * (full * sx + side * lx)
    fy = scale * (full * sy + side * ly)
    return fx, fy, ax * fy - ay * fx


def net_force_and_moment(forces, positions, heading):
    """Resultant force [N] (..., 2) and yaw moment about the CG [N m] (...) of tyre forces.

    Parameters
    ----------
    forces : array_like, shape (..., 4, 2)
        Tyre forces, global frame [N].
    positions : array_like, shape (..., 4, 2)
        Tyre positions in the body frame [m].
    heading : array_like
        [rad].
    """
    forces = np.asarray(forces, dtype=float)
    arms = rotate(positions, np.asarray(heading, dtype=float)[..., None])
    moment = arms[..., 0] * forces[..., 1] - arms[..., 1] * forces[..., 0]
    return forces.sum(axis=-2), moment.sum(axis=-1)


def regularised_slide_distance(speed, friction, gravity=STANDARD_GRAVITY,
                               regularisation=DEFAULT_REGULARISATION) -> np.ndarray:
    """Exact sliding distance [m] of a locked vehicle from ``speed`` [m/s] to rest.

    With deceleration ``mu g v / sqrt(v^2 + v_r^2)``:
    ``s = [v0 sqrt(v0^2 + v_r^2) + v_r^2 asinh(v0 / v_r)] / (2 mu g)``,
    which tends to Coulomb's ``v0^2 / (2 mu g)`` as ``v_r -> 0``.
    """
    v0 = np.asarray(speed, dtype=float)
    vr = regularisation
    return (v0 * np.sqrt(v0 * v0 + vr * vr) + vr * vr * np.arcsinh(v0 / vr)) / (
        2.0 * np.asarray(friction, dtype=float) * gravity)
