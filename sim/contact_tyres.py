"""Tyre/ground forces on a vehicle during the finite-duration contact.

The force law is the project's one tyre model, :mod:`pim.model.tyres` (the run-out model
uses it too); this module only places the wheels from a vehicle's outline and sums the
forces for the contact scenes.

Four tyres per vehicle at body-frame positions (a, +-track/2) and (a - wheelbase, +-track/2),
the axles centred on the OUTLINE (a = cg_to_front - length/2 + wheelbase/2, with the case's
``cg_to_front``, the CG to the bumper; a = wheelbase/2 for an outline centred on the CG),
each at its static load (:func:`pim.model.tyres.static_loads`: m g / 4 when the CG is
midway between the axles). Each tyre
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

import math

import numpy as np

from pim.model import tyres
from pim.model.numbers import InputError

from .compliant_formula import vehicle_tyre_force

__all__ = ["TYRE_MODES", "WHEELBASE_FRACTION", "TRACK_FRACTION", "SLIP_REGULARISATION",
           "wheels_from_outline", "wheel_loads", "tyre_force"]

TYRE_MODES = ("rolling", "locked")
#: Wheelbase / length and track / width of the four-tyre model [-].
WHEELBASE_FRACTION = 0.6
TRACK_FRACTION = 0.86
#: Slip speed [m/s] below which the tyre force is rounded off (v_r above).
SLIP_REGULARISATION = 0.05


def wheels_from_outline(length, width, radius_of_gyration=None,
                        cg_to_front=None) -> np.ndarray:
    """Body-frame positions (..., 4, 2) [m] of the wheels (front left, front right, rear left,
    rear right; :func:`pim.model.tyres.wheel_positions`), the axles centred on the outline.

    Parameters
    ----------
    length, width : float or None
        Outline [m]; None: from ``radius_of_gyration`` (module notes).
    radius_of_gyration : array_like, optional
        sqrt(I / m) [m], used only without an outline (an array gives wheels per sample).
    cg_to_front : float, optional
        CG to the front of the OUTLINE [m] (:attr:`pim.Vehicle.cg_to_front`, the bumper;
        default length / 2); the CG to the front axle is then
        ``a = cg_to_front - length / 2 + wheelbase / 2``, which must lie in [0, wheelbase].
    """
    if length is None or width is None:
        if radius_of_gyration is None:
            raise InputError("wheels_from_outline needs length and width or "
                             "radius_of_gyration")
        length = np.asarray(radius_of_gyration, dtype=float) / 0.3
        width = 0.4 * length
    length = np.asarray(length, dtype=float)
    wheelbase = WHEELBASE_FRACTION * length
    front = 0.5 * length if cg_to_front is None else np.asarray(cg_to_front, dtype=float)
    axle = front - 0.5 * length + 0.5 * wheelbase
    if not np.all((axle >= 0) & (axle <= wheelbase)):
        bad = np.argmax(~((axle >= 0) & (axle <= wheelbase)))
        front, axle, wheelbase = (np.broadcast_to(v, np.shape(axle)).flat[bad]
                                  for v in (front, axle, wheelbase))
        raise InputError(f"cg_to_front = {front:g} m puts the CG outside the axles of the "
                         f"four-tyre model (wheelbase {WHEELBASE_FRACTION:g} x length, centred "
                         f"on the outline): it must lie in [{front - axle:g}, "
                         f"{front - axle + wheelbase:g}] m")
    return tyres.wheel_positions(wheelbase, TRACK_FRACTION * np.asarray(width, dtype=float),
                                 axle)


def wheel_loads(mass, wheels, gravity=tyres.STANDARD_GRAVITY) -> np.ndarray:
    """Static loads (..., 4) [N] of the wheels at ``wheels`` (..., 4, 2)
    (:func:`wheels_from_outline`): :func:`pim.model.tyres.static_loads` with their wheelbase
    and CG-to-front-axle distance.
    """
    wheels = np.asarray(wheels, dtype=float)
    return tyres.static_loads(mass, wheels[..., 0, 0] - wheels[..., 2, 0], wheels[..., 0, 0],
                              gravity)


def tyre_force(velocity, yaw_rate, angle, wheels, load, mu, mode="rolling",
               regularisation=SLIP_REGULARISATION):
    """Resultant tyre force [N] and its moment about the CG [N m] on one vehicle
    (:func:`sim.compliant_formula.vehicle_tyre_force`, the sum the scenes step with).

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
    load : float or array_like (4,)
        Normal load per tyre [N] (:func:`wheel_loads`).
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
    loads = np.broadcast_to(np.asarray(load, dtype=float), (4,))
    velocity = np.asarray(velocity, dtype=float).reshape(2)
    angle = float(angle)
    data = np.asarray(wheels, dtype=float).reshape(8).tolist() + loads.tolist()
    fx, fy, moment = vehicle_tyre_force(
        data, 0, 8, float(velocity[0]), float(velocity[1]), float(yaw_rate), math.cos(angle),
        math.sin(angle), float(mu), 1.0 if mode == "locked" else 0.0, float(regularisation))
    return np.array([fx, fy], dtype=float), float(moment)
