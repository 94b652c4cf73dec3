"""Planar vector helpers and rigid-body quantities, defined once for the whole project.

Vectors are arrays of shape (..., 2) in the global x-y frame; angles are counter-clockwise
from +x [rad]. Every function broadcasts over leading axes and is pure.
"""

from __future__ import annotations

import numpy as np

__all__ = ["outline_distance", "cross", "dot", "perp", "vec", "rotate", "rotate_by", "contact_velocity",
           "kinetic_energy", "radius_of_gyration", "outline_corners", "outline_world"]


def cross(a, b) -> np.ndarray:
    """z-component of a x b [product of the units] for vectors of shape (..., 2)."""
    a, b = np.asarray(a), np.asarray(b)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def dot(a, b) -> np.ndarray:
    """a . b [product of the units] for vectors of shape (..., 2)."""
    a, b = np.asarray(a), np.asarray(b)
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def perp(a) -> np.ndarray:
    """k x a: the vector rotated +90 deg, shape (..., 2)."""
    a = np.asarray(a)
    return np.stack([-a[..., 1], a[..., 0]], axis=-1)


def vec(x, y) -> np.ndarray:
    """Stack broadcast x and y components into vectors of shape (..., 2)."""
    x, y = np.broadcast_arrays(x, y)
    return np.stack([x, y], axis=-1)


def rotate(v, angle) -> np.ndarray:
    """The vectors ``v`` (..., 2) turned counter-clockwise by ``angle`` [rad]."""
    return rotate_by(v, np.cos(angle), np.sin(angle))


def rotate_by(v, cos, sin) -> np.ndarray:
    """The vectors ``v`` (..., 2) turned counter-clockwise by the angle whose cosine and sine
    are ``cos`` and ``sin`` [-]: (c x - s y, s x + c y)."""
    v = np.asarray(v, dtype=float)
    return np.stack([cos * v[..., 0] - sin * v[..., 1], sin * v[..., 0] + cos * v[..., 1]],
                    axis=-1)


def contact_velocity(velocity, yaw_rate, arm) -> np.ndarray:
    """Velocity of the material point at ``cg + arm`` of a rigid body in planar motion.

    Parameters
    ----------
    velocity : array_like, shape (..., 2)
        CG velocity [m/s].
    yaw_rate : array_like
        Yaw rate [rad/s].
    arm : array_like, shape (..., 2)
        Vector from the CG to the point [m].

    Returns
    -------
    ndarray, shape (..., 2)
        v + w k x r [m/s] (Brach & Brach 2011, eq. 6.45 in vector form).
    """
    arm = np.asarray(arm, dtype=float)
    return np.asarray(velocity) + np.asarray(yaw_rate)[..., None] * perp(arm)


def kinetic_energy(mass, inertia, velocity, yaw_rate) -> np.ndarray:
    """Kinetic energy m |v|^2 / 2 + I w^2 / 2 [J] of a planar rigid body.

    Parameters
    ----------
    mass : array_like
        Mass [kg]; ``inf`` marks a fixed obstacle, whose energy is 0 (at rest).
    inertia : array_like
        Yaw inertia [kg m^2].
    velocity : array_like, shape (..., 2)
        CG velocity [m/s].
    yaw_rate : array_like
        Yaw rate [rad/s].
    """
    mass = np.asarray(mass, dtype=float)
    with np.errstate(invalid="ignore"):
        energy = (0.5 * mass * dot(velocity, velocity)
                  + 0.5 * np.asarray(inertia) * np.asarray(yaw_rate) ** 2)
    return np.where(np.isinf(mass), 0.0, energy)


def radius_of_gyration(mass, inertia) -> np.ndarray:
    """k = sqrt(I / m) [m]; 0 for a fixed obstacle (infinite mass)."""
    mass = np.asarray(mass, dtype=float)
    with np.errstate(invalid="ignore"):
        k = np.sqrt(np.asarray(inertia, dtype=float) / mass)
    return np.where(np.isinf(mass), 0.0, k)


def outline_corners(length, width, cg_to_front=None) -> np.ndarray:
    """Corners of a length x width rectangle around the CG, in the body frame [m].

    Counter-clockwise from the front left corner: (a, w/2), (a - l, w/2), (a - l, -w/2),
    (a, -w/2), with the body's x axis along its heading and ``a = cg_to_front`` [m] the
    distance from the CG forward to the front (default ``l/2``: centred on the CG).
    Shape (4, 2).
    """
    hw = float(width) / 2.0
    front = float(length) / 2.0 if cg_to_front is None else float(cg_to_front)
    rear = front - float(length)
    return np.array([[front, hw], [rear, hw], [rear, -hw], [front, -hw]])


def outline_world(length, width, cg, heading, cg_to_front=None) -> np.ndarray:
    """Corners [m] of the rectangle of :func:`outline_corners` placed at ``cg``, turned to
    ``heading`` [rad], in the global frame. Shape (4, 2)."""
    return (rotate(outline_corners(length, width, cg_to_front), heading)
            + np.asarray(cg, dtype=float))


def outline_distance(angle, length, width, cg_to_front=None) -> np.ndarray:
    """Distance [m] from the CG to the vehicle's rectangular outline along a direction.

    The outline in the body frame (x forward, y left, CG at the origin) spans
    ``-(length - a) <= x <= a`` and ``|y| <= width / 2`` (``a = cg_to_front``, default
    ``length / 2``); the ray from the CG at ``angle`` [rad] (counter-clockwise from the
    heading, Brach's phi) leaves it at ``min(a / cos, (length - a) / -cos, (width/2) / |sin|)``
    over the positive terms.
    """
    angle = np.asarray(angle, dtype=float)
    length = np.asarray(length, dtype=float)
    width = np.asarray(width, dtype=float)
    a = length / 2 if cg_to_front is None else np.asarray(cg_to_front, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    with np.errstate(divide="ignore", over="ignore"):
        tx = np.where(c > 0, a / c, np.where(c < 0, (a - length) / c, np.inf))
        ty = np.where(s != 0, (width / 2) / np.abs(s), np.inf)
    return np.minimum(tx, ty)
