"""The run-out's right-hand side, written once.

Every evaluation of the post-impact run-out's equations of motion runs these functions (as
:mod:`pim.model.formula` is for PIM):

* Python evaluates them on floats for one vehicle (:class:`pim.model.runout.TimedRhs`, the
  reference right-hand side that scipy's ``solve_ivp`` integrates in
  :func:`pim.model.runout.runout`, and the pymunk check :mod:`sim.runout_check`);
* numpy evaluates them on arrays of samples (:func:`pim.model.runout.runout_rhs`, the
  fixed-step :func:`pim.model.runout.runout_many`): every per-sample value carries the
  samples on its last axis;
* numba compiles the very same functions (:mod:`pim.model.runout_kernel`, through
  :func:`pim.model.numba_cache.compile_module`) into the parallel fixed-step integrator of
  the Monte Carlo and the single fit's compiled right-hand side
  (:class:`pim.model.runout_kernel.CompiledRhs`).

Equations (global frame, state ``(x, y, psi, v_x, v_y, omega)``, sources in docs/tyres.md):

``m dv/dt = sum_i F_i``, ``I domega/dt = sum_i (R(psi) p_i) x F_i``, ``dx/dt = v``,
``dpsi/dt = omega``,

with the force ``F_i`` of tyre i from the project's one tyre law (:mod:`pim.model.tyres`):
the Coulomb law :func:`~pim.model.tyres.wheel_force` at the static load, or the field tyre
:func:`~pim.model.tyres.field_wheel_force` at the load that the acceleration transfers
(:func:`~pim.model.tyres.transferred_load`: the acceleration of the forces at the static loads,
then the forces again at the transferred loads, one fixed-point pass of the algebraic loop
load -> force -> acceleration -> load). The wheel's steer angle and braking fraction are read at
time ``t`` from the driver's tables (``numpy.interp``, held beyond them) or are constant, the
braking times the build-up ramp :func:`~pim.model.tyres.brake_ramp` of the field tyre.

The vehicle travels as one tuple, ``vehicle = (mass, yaw_inertia, wheel_x, wheel_y, load,
friction, regularisation, times, steer, brake, tyre)`` (:meth:`pim.model.runout.RhsData.sample`
for one vehicle, :meth:`~pim.model.runout.RhsData.columns` for samples on the last axis):

* ``mass`` [kg], ``yaw_inertia`` [kg m^2], ``friction`` [-], ``regularisation`` [m/s];
* ``wheel_x``, ``wheel_y`` (4,) tyre positions in the body frame [m], ``load`` (4,) static loads
  [N] (front-left, front-right, rear-left, rear-right);
* ``times`` (k,) [s] the driver's table times, or one zero for constant inputs;
* ``steer`` (k, 4) [rad] the steer angles at those times, or, for constant inputs, (2, 4) the
  cosine and sine of the constant angles;
* ``brake`` (k, 4) [-] the braking fractions (k = 1: constant);
* ``tyre`` (15,) the field tyre's data (longitudinal stiffness (4) [N], cornering stiffness
  (4) [N/rad], brake start [s], build-up time [s], rolling resistance [-], CG height [m],
  wheelbase [m], track [m], CG to the front axle [m]), or empty (0,) for the Coulomb law.

The functions hold arithmetic, ``numpy`` functions and conditionals on shapes only, so the
three evaluations compute the same numbers to round-off (tested with hypothesis in
tests/pim/model/test_runout_formula.py).
"""

from __future__ import annotations

import numpy as np

from .tyres import brake_ramp, field_wheel_force, transferred_load, wheel_force

__all__ = ["derivative", "tyre_sum", "wheel_inputs", "wheel_load", "VEHICLE_FIELDS",
           "TYRE_COLUMNS"]

#: The fields of the ``vehicle`` tuple, in order (module notes).
VEHICLE_FIELDS = ("mass", "yaw_inertia", "wheel_x", "wheel_y", "load", "friction",
                  "regularisation", "times", "steer", "brake", "tyre")
#: The columns of the field tyre's data row, in order (module notes).
TYRE_COLUMNS = ("longitudinal_stiffness",) * 4 + ("cornering_stiffness",) * 4 + (
    "brake_start", "buildup_time", "rolling_resistance", "cg_height", "wheelbase", "track",
    "cg_to_front_axle")


def wheel_inputs(t, w, c, s, times, steer, brake, ramp):
    """Wheel ``w``'s heading and braking at time ``t`` [s].

    Parameters
    ----------
    t : float [s]; w : int, the wheel (0 front-left, 1 front-right, 2 rear-left, 3 rear-right)
    c, s : cos psi and sin psi of the vehicle's heading
    times, steer, brake : the input tables of the vehicle tuple (module notes)
    ramp : [-] the brake build-up's fraction at ``t`` (1 for the Coulomb law)

    Returns
    -------
    cw, sw, braking
        cos and sin of the wheel's heading ``psi + delta`` (by the angle-addition formulas),
        and its braking fraction [-] times ``ramp``.
    """
    if times.shape[0] == 1:            # constant inputs: the steer's cos and sin given
        cd, sd, braking = steer[0, w], steer[1, w], brake[0, w]
    else:
        angle = np.interp(t, times, steer[:, w])
        cd, sd, braking = np.cos(angle), np.sin(angle), np.interp(t, times, brake[:, w])
    return c * cd - s * sd, s * cd + c * sd, braking * ramp


def wheel_load(w, static, mass, tyre, along, across):
    """Normal load of wheel ``w`` [N] of static load ``static`` [N] and a vehicle of ``mass``
    [kg] under the CG acceleration ``along`` (forward) and ``across`` (to the left) [m/s^2],
    body frame, with the field tyre's data row ``tyre`` (module notes):
    :func:`pim.model.tyres.transferred_load` (the static load exactly at zero
    acceleration)."""
    return transferred_load(static, mass, along, across, tyre[11], tyre[12], tyre[13],
                            tyre[14], 1.0 - w // 2, 1.0 - w % 2)


def tyre_sum(t, kinematics, vehicle, acceleration, ramp):
    """Resultant tyre force [N] (global frame) and yaw moment about the CG [N m].

    Parameters
    ----------
    t : float [s]
    kinematics : (cos psi, sin psi, v_x [m/s], v_y [m/s], omega [rad/s])
    vehicle : the vehicle tuple (module notes)
    acceleration : (along, across) [m/s^2] the body-frame CG acceleration that sets the field
        tyre's loads (:func:`wheel_load`), or None for the static loads (the first pass, which
        then skips the load transfer's arithmetic: the same numbers, as ``wheel_load`` gives
        the static load exactly at zero acceleration)
    ramp : [-] the brake build-up's fraction at ``t``

    Returns
    -------
    fx, fy, moment
        ``sum_i F_i`` and ``sum_i (R(psi) p_i) x F_i`` of the four tyres.
    """
    c, s, vx, vy, omega = kinematics
    mass, _, wheel_x, wheel_y, load, mu, vr, times, steer, brake, tyre = vehicle
    fx = fy = moment = 0.0
    for w in range(4):
        cw, sw, braking = wheel_inputs(t, w, c, s, times, steer, brake, ramp)
        if tyre.shape[0] == 0:         # Coulomb, at the static load
            a, b, m = wheel_force(c, s, vx, vy, omega, wheel_x[w], wheel_y[w], cw, sw,
                                  load[w], mu, braking, vr)
        else:                          # the field tyre, at the transferred load
            ld = load[w] if acceleration is None else wheel_load(w, load[w], mass, tyre,
                                                                 acceleration[0],
                                                                 acceleration[1])
            a, b, m = field_wheel_force(c, s, vx, vy, omega, wheel_x[w], wheel_y[w], cw, sw,
                                        ld, mu, braking, vr, tyre[w], tyre[4 + w], tyre[10])
        fx = fx + a
        fy = fy + b
        moment = moment + m
    return fx, fy, moment


def derivative(t, motion, vehicle):
    """Time derivative of the run-out state (module notes for the equations).

    Parameters
    ----------
    t : float [s] time since the impact.
    motion : (psi [rad], v_x [m/s], v_y [m/s], omega [rad/s]) the heading and the velocities
        (the position does not enter the forces).
    vehicle : the vehicle tuple (module notes).

    Returns
    -------
    dx, dy, dpsi, dv_x, dv_y, domega
        [m/s, m/s, rad/s, m/s^2, m/s^2, rad/s^2].
    """
    psi, vx, vy, omega = motion
    mass, inertia, tyre = vehicle[0], vehicle[1], vehicle[10]
    c, s = np.cos(psi), np.sin(psi)
    kinematics = (c, s, vx, vy, omega)
    brush = tyre.shape[0] > 0
    ramp = brake_ramp(t, tyre[8], tyre[9]) if brush else 1.0
    fx, fy, moment = tyre_sum(t, kinematics, vehicle, None, ramp)
    if brush:                          # the loads that this acceleration transfers
        along, across = (c * fx + s * fy) / mass, (-s * fx + c * fy) / mass
        fx, fy, moment = tyre_sum(t, kinematics, vehicle, (along, across), ramp)
    return vx, vy, omega, fx / mass, fy / mass, moment / inertia
