"""Planar vector helpers and rigid-body quantities, defined once for the whole project.

Vectors are arrays of shape (..., 2) in the global x-y frame; angles are counter-clockwise
from +x [rad]. Every function broadcasts over leading axes and is pure.
"""

from __future__ import annotations

import numpy as np

__all__ = ["outline_distance", "vehicle_outline", "cross", "dot", "perp", "vec", "rotate", "rotate_by",
           "contact_velocity", "kinetic_energy", "radius_of_gyration", "outline_corners",
           "outline_world", "point_outline_distance", "outline_penetration",
           "heading_velocity_angle"]


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


def vehicle_outline(vehicle) -> np.ndarray | None:
    """A :class:`pim.Vehicle`'s outline corners in its body frame [m] (4, 2)
    (:func:`outline_corners`), or None without length and width."""
    if vehicle.length is None or vehicle.width is None:
        return None
    return outline_corners(float(vehicle.length), float(vehicle.width),
                           None if vehicle.cg_to_front is None else float(vehicle.cg_to_front))


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


def _box(cg, heading, length, width, cg_to_front=None):
    """Centre [m], unit axes (along the heading, to the left) and half-extents [m] of the
    rectangle of :func:`outline_corners` placed at ``cg``, turned to ``heading``."""
    length = np.asarray(length, dtype=float)
    front = length / 2 if cg_to_front is None else np.asarray(cg_to_front, dtype=float)
    along = vec(np.cos(heading), np.sin(heading))
    centre = np.asarray(cg, dtype=float) + (front - length / 2)[..., None] * along
    return centre, along, perp(along), length / 2, np.asarray(width, dtype=float) / 2


def point_outline_distance(point, cg, heading, length, width, cg_to_front=None) -> np.ndarray:
    """Signed distance [m] from ``point`` to a vehicle's rectangular outline: > 0 outside
    (the Euclidean distance to the outline), < 0 inside (minus the depth below its nearest
    side), 0 on it.

    Parameters
    ----------
    point, cg : array_like, shape (..., 2)
        The point and the vehicle's CG [m].
    heading : array_like
        Direction of the vehicle's nose [rad].
    length, width : array_like
        Outline [m], > 0.
    cg_to_front : array_like, optional
        CG to the front of the outline [m] (default ``length / 2``), as in
        :func:`outline_corners`.

    Notes
    -----
    In the box's frame, with q = |p - centre| - half-extents per axis, the distance is
    |max(q, 0)| + min(max(q_x, q_y), 0) (the signed distance of an axis-aligned box).
    """
    centre, along, left, hx, hy = _box(cg, heading, length, width, cg_to_front)
    rel = np.asarray(point, dtype=float) - centre
    qx, qy = np.abs(dot(rel, along)) - hx, np.abs(dot(rel, left)) - hy
    outside = np.hypot(np.maximum(qx, 0.0), np.maximum(qy, 0.0))
    return outside + np.minimum(np.maximum(qx, qy), 0.0)


def outline_penetration(outline1, outline2) -> np.ndarray:
    """Depth [m] by which two placed rectangular outlines overlap: the least overlap of
    their projections over the four axes of the two rectangles (the separating-axis test);
    <= 0 when they are apart (then minus a lower bound of the gap).

    Parameters
    ----------
    outline1, outline2 : tuple
        ``(cg, heading, length, width, cg_to_front)`` of each vehicle [m, rad, m, m, m or
        None], each entry broadcasting over leading axes.

    Notes
    -----
    A rectangle of centre c, unit axes e_x, e_y and half-extents h_x, h_y projects on a unit
    axis u to c.u +- (h_x |e_x.u| + h_y |e_y.u|); two projections overlap by
    r_1 + r_2 - |(c_1 - c_2).u|.
    """
    c1, a1, l1, hx1, hy1 = _box(*outline1)
    c2, a2, l2, hx2, hy2 = _box(*outline2)
    gap = c1 - c2
    depths = []
    for axis in (a1, l1, a2, l2):
        r1 = hx1 * np.abs(dot(a1, axis)) + hy1 * np.abs(dot(l1, axis))
        r2 = hx2 * np.abs(dot(a2, axis)) + hy2 * np.abs(dot(l2, axis))
        depths.append(r1 + r2 - np.abs(dot(gap, axis)))
    return np.minimum.reduce(np.broadcast_arrays(*depths))


def heading_velocity_angle(heading, velocity) -> np.ndarray:
    """Angle [rad] in [0, pi] between a vehicle's heading and its CG velocity; NaN where
    the vehicle does not move. Above pi / 2 the vehicle moves backwards (reversing)."""
    velocity = np.asarray(velocity, dtype=float)
    along = vec(np.cos(heading), np.sin(heading))
    angle = np.abs(np.arctan2(cross(along, velocity), dot(along, velocity)))
    moving = np.hypot(velocity[..., 0], velocity[..., 1]) > 0
    return np.where(moving, angle, np.nan)
