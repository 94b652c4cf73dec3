"""Brach's (theta, phi, d) description of the impact geometry, as an adapter to the vector form.

Brach's worksheet places each CG relative to the common point C by a distance d and an angle
phi measured from the vehicle's heading angle theta. Reading the RICSAC 9 sheet
(``d_c = d1 sin(theta1 + phi1 - Gamma)`` with ``v_cn1 = v_n1 + d_c w1`` but
``v_cn2 = v_n2 - d_a w2``) gives the convention this module implements:

* vehicle 2: theta2 is its heading; the arm CG2 -> C points at theta2 + phi2;
* vehicle 1: theta1 has the opposite datum (0 deg = "moving to the left", -x), so its heading
  is theta1 + 180 deg, and the arm CG1 -> C points at heading1 + phi1 = theta1 + phi1 + 180 deg.

In both cases phi is the angle of the arm CG -> C measured counter-clockwise from the
vehicle's true heading and d its length. Brach's moment arms d_a ... d_d are the n-t
components of the arms: C - CG1 = -(d_d, d_c), C - CG2 = (d_b, d_a).
"""

from __future__ import annotations

import numpy as np

from ..model.numbers import InputError

__all__ = ["heading_from_theta", "cg_from_brach", "brach_arms", "brach_angles"]


def heading_from_theta(theta, vehicle: int) -> np.ndarray:
    """True heading [rad] from Brach's theta [rad]; vehicle 1's datum is rotated by pi."""
    if vehicle not in (1, 2):
        raise InputError(f"vehicle must be 1 or 2, got {vehicle}")
    theta = np.asarray(theta, dtype=float)
    return theta + np.pi if vehicle == 1 else theta


def cg_from_brach(theta, phi, d, vehicle: int, point=(0.0, 0.0)) -> np.ndarray:
    """CG position [m] from Brach's (theta [rad], phi [rad], d [m]) and C [m].

    Returns ``point - d (cos(h + phi), sin(h + phi))`` with h the true heading.
    """
    d = np.asarray(d, dtype=float)
    if (d < 0).any() or not np.isfinite(d).all():
        raise InputError("d (distance CG to C) must be >= 0 [m]")
    angle = heading_from_theta(theta, vehicle) + np.asarray(phi, dtype=float)
    arm = d[..., None] * np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    return np.asarray(point, dtype=float) - arm


def brach_arms(case) -> dict[str, np.ndarray]:
    """Brach's moment arms d_a, d_b, d_c, d_d [m] of a :class:`pim.Case` (sheet, p. 3)."""
    g = case.impact.normal_angle
    n = np.stack([np.cos(g), np.sin(g)], -1)
    t = np.stack([-np.sin(g), np.cos(g)], -1)
    r1 = case.impact.point - case.vehicle1.cg
    r2 = case.impact.point - case.vehicle2.cg
    return {
        "d_a": (r2 * t).sum(-1), "d_b": (r2 * n).sum(-1),
        "d_c": -(r1 * t).sum(-1), "d_d": -(r1 * n).sum(-1),
    }


def brach_angles(case) -> dict[str, np.ndarray]:
    """Inverse of :func:`cg_from_brach`: theta [rad], phi [rad], d [m] of both vehicles."""
    out = {}
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        arm = case.impact.point - v.cg
        h = np.asarray(v.heading, dtype=float)
        out[f"theta{i}"] = h - np.pi if i == 1 else h
        out[f"phi{i}"] = np.arctan2(arm[..., 1], arm[..., 0]) - h
        out[f"d{i}"] = np.hypot(arm[..., 0], arm[..., 1])
    return out
