"""Tyre/ground forces on a vehicle during the finite-duration contact (pure, vectorised).

Four tyres per vehicle, each at its static load N = m g / 4 (the CG midway between the
axles and the wheels), at body-frame positions (+-wheelbase/2, +-track/2). Each tyre
pushes with Coulomb friction mu_tyre N against its slip velocity:

* free-rolling ("rolling"): only the lateral component of the wheel's ground velocity
  slips (the tyre rolls along its heading), F = -mu N v_y e_y / sqrt(v_y^2 + v_r^2);
* locked ("locked"): the whole ground velocity slips, F = -mu N v / sqrt(|v|^2 + v_r^2);

v_r (:data:`SLIP_REGULARISATION`) rounds Coulomb's sign function off near zero slip so that
the force is a continuous function of the state (a sticking tyre is not modelled: during
an impact every tyre slides). Wheelbase and track are fixed fractions of the outline
(:data:`WHEELBASE_FRACTION`, :data:`TRACK_FRACTION`: 2.7 m and 1.55 m for a 4.5 m x 1.8 m
car); without an outline the length is taken as k / 0.3 and the width as 0.4 times it
(k: radius of gyration; k is about 0.3 L for cars).
"""

from __future__ import annotations

import numpy as np

__all__ = ["TYRE_MODES", "WHEELBASE_FRACTION", "TRACK_FRACTION", "SLIP_REGULARISATION",
           "wheel_positions", "tyre_force"]

TYRE_MODES = ("rolling", "locked")
#: Wheelbase / length and track / width of the four-tyre model [-].
WHEELBASE_FRACTION = 0.6
TRACK_FRACTION = 0.86
#: Slip speed [m/s] below which the tyre force is rounded off (v_r above).
SLIP_REGULARISATION = 0.05


def wheel_positions(length, width, radius_of_gyration=None) -> np.ndarray:
    """Body-frame positions (4, 2) [m] of the wheels: front left, front right, rear ...

    Parameters
    ----------
    length, width : float or None
        Outline [m]; None: from ``radius_of_gyration`` (module notes).
    radius_of_gyration : float, optional
        sqrt(I / m) [m], used only without an outline.
    """
    if length is None or width is None:
        if radius_of_gyration is None:
            raise ValueError("wheel_positions needs length and width or radius_of_gyration")
        length = float(radius_of_gyration) / 0.3
        width = 0.4 * length
    a = 0.5 * WHEELBASE_FRACTION * float(length)
    b = 0.5 * TRACK_FRACTION * float(width)
    return np.array([[a, b], [a, -b], [-a, b], [-a, -b]])


def tyre_force(velocity, yaw_rate, angle, wheels, load, mu, mode="rolling",
               regularisation=SLIP_REGULARISATION):
    """Resultant tyre force [N] and its moment about the CG [N m] on one vehicle.

    Parameters
    ----------
    velocity : array_like (2,)
        CG velocity [m/s], global frame.
    yaw_rate : float
        Yaw rate [rad/s].
    angle : float
        Heading [rad] from +x.
    wheels : ndarray (W, 2)
        Wheel positions in the body frame [m] (:func:`wheel_positions`).
    load : float
        Normal load per tyre [N].
    mu : float
        Tyre/ground friction coefficient [-].
    mode : {"rolling", "locked"}
        Free-rolling (lateral slip only) or locked wheels (full slip).
    regularisation : float
        v_r [m/s] of the module notes.

    Returns
    -------
    force : ndarray (2,)
        Sum of the tyre forces [N], global frame.
    moment : float
        Their moment about the CG [N m], counter-clockwise positive.
    """
    c, s = np.cos(angle), np.sin(angle)
    arms = np.stack([c * wheels[:, 0] - s * wheels[:, 1], s * wheels[:, 0] + c * wheels[:, 1]],
                    axis=-1)                                   # (W, 2) world-frame arms
    v = np.asarray(velocity, float) + yaw_rate * np.stack([-arms[:, 1], arms[:, 0]], axis=-1)
    if mode == "rolling":
        lateral = np.array([-s, c])
        slip = (v @ lateral)[:, None] * lateral[None, :]
    elif mode == "locked":
        slip = v
    else:
        raise ValueError(f"tyre mode must be one of {TYRE_MODES}, got {mode!r}")
    size = np.sqrt(np.sum(slip * slip, axis=-1) + regularisation * regularisation)
    forces = -mu * load * slip / size[:, None]
    moment = float(np.sum(arms[:, 0] * forces[:, 1] - arms[:, 1] * forces[:, 0]))
    return forces.sum(axis=0), moment
