"""Tyre/ground forces on a vehicle during the finite-duration contact.

The force law is the project's one tyre model, :mod:`pim.model.tyres` (the run-out model
uses it too); this module only places the wheels from a vehicle's outline and sums the
forces for the contact scenes.

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

from pim.model import tyres
from pim.model.numbers import InputError

__all__ = ["TYRE_MODES", "WHEELBASE_FRACTION", "TRACK_FRACTION", "SLIP_REGULARISATION",
           "wheels_from_outline", "tyre_force"]

TYRE_MODES = ("rolling", "locked")
#: Wheelbase / length and track / width of the four-tyre model [-].
WHEELBASE_FRACTION = 0.6
TRACK_FRACTION = 0.86
#: Slip speed [m/s] below which the tyre force is rounded off (v_r above).
SLIP_REGULARISATION = 0.05


def wheels_from_outline(length, width, radius_of_gyration=None) -> np.ndarray:
    """Body-frame positions (4, 2) [m] of the wheels (front left, front right, rear left,
    rear right; :func:`pim.model.tyres.wheel_positions` with the CG midway between axles).

    Parameters
    ----------
    length, width : float or None
        Outline [m]; None: from ``radius_of_gyration`` (module notes).
    radius_of_gyration : float, optional
        sqrt(I / m) [m], used only without an outline.
    """
    if length is None or width is None:
        if radius_of_gyration is None:
            raise InputError("wheels_from_outline needs length and width or "
                             "radius_of_gyration")
        length = float(radius_of_gyration) / 0.3
        width = 0.4 * length
    wheelbase = WHEELBASE_FRACTION * float(length)
    return tyres.wheel_positions(wheelbase, TRACK_FRACTION * float(width), 0.5 * wheelbase)


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
    wheels : ndarray (4, 2)
        Wheel positions in the body frame [m] (:func:`wheels_from_outline`).
    load : float
        Normal load per tyre [N].
    mu : float
        Tyre/ground friction coefficient [-].
    mode : {"rolling", "locked"}
        Free-rolling (lateral slip only: braking fraction 0) or locked wheels (full slip:
        braking fraction 1) in :func:`pim.model.tyres.tyre_forces`.
    regularisation : float
        v_r [m/s] of the module notes.

    Returns
    -------
    force : ndarray (2,)
        Sum of the tyre forces [N], global frame.
    moment : float
        Their moment about the CG [N m], counter-clockwise positive.
    """
    if mode not in TYRE_MODES:
        raise InputError(f"tyre mode must be one of {TYRE_MODES}, got {mode!r}")
    braking = np.full(4, 1.0 if mode == "locked" else 0.0)
    forces = tyres.tyre_forces(velocity, yaw_rate, angle, wheels, np.full(4, float(load)), mu,
                               braking, regularisation=regularisation)
    force, moment = tyres.net_force_and_moment(forces, wheels, angle)
    return force, float(moment)
