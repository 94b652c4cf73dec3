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

from dataclasses import dataclass

import numpy as np

from .geometry import rotate
from .numbers import InputError

__all__ = ["WHEELS", "STANDARD_GRAVITY", "DEFAULT_REGULARISATION", "wheel_positions",
           "static_loads", "tyre_forces", "wheel_force", "net_force_and_moment",
           "regularised_slide_distance", "SEDAN_TYRE", "TyreData", "TYRE_MODELS",
           "field_wheel_force", "transferred_load", "brake_ramp",
           "linear_buildup_stopping_distance"]

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
        Distance from the CG forward to the front AXLE ``a`` [m], 0 <= a <= L (a case
        file's ``[evidence.vehicleN] cg_to_front_axle``; not the outline's ``cg_to_front``).

    Returns
    -------
    ndarray, shape (..., 4, 2)
        [m], wheels in the order of ``WHEELS``.
    """
    plain, (length, track, a) = _operands(wheelbase, track, cg_to_front)
    x = [a, a, a - length, a - length]
    y = [track / 2, -track / 2, track / 2, -track / 2]
    return np.array(list(zip(x, y))) if plain else np.stack(
        [np.stack(x, axis=-1), np.stack(y, axis=-1)], axis=-1)


def _operands(*values) -> tuple:
    """``(plain, operands)``: Python floats when every value is a Python number (one
    vehicle: its formula on floats, the same IEEE arithmetic as numpy's, without numpy's
    small-array cost), else the values as float arrays broadcast together."""
    for v in values:
        if type(v) not in (float, int):
            break
    else:
        return True, tuple([float(v) for v in values])
    return False, tuple(np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in values)))


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
    plain, (mass, length, a, g) = _operands(mass, wheelbase, cg_to_front, gravity)
    front = mass * g * (length - a) / (2 * length)
    rear = mass * g * a / (2 * length)
    return np.array([front, front, rear, rear]) if plain else np.stack(
        [front, front, rear, rear], axis=-1)


def tyre_forces(velocity, yaw_rate, heading, positions, loads, friction, braking,
                steer=0.0, *, regularisation=DEFAULT_REGULARISATION) -> np.ndarray:
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
    # a number f of 0 (free-rolling) or 1 (locked) skips the square root and division of the
    # term it weights by 0 (the same +0.0 they would give: compiled, half the cost per wheel)
    if isinstance(braking, float) and braking == 0.0:
        full = 0.0
    else:
        full = braking / np.sqrt(sx * sx + sy * sy + vr2)
    if isinstance(braking, float) and braking == 1.0:
        side = 0.0
    else:
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


# --------------------------------------------------------------------------------------------
# The field tyre: combined-slip brush model with load transfer, rolling resistance, build-up
# --------------------------------------------------------------------------------------------

#: Defaults for a mid-size sedan (sources in docs/tyres.md): cornering stiffness per tyre
#: [N/rad] (Rajamani 2012, Vehicle Dynamics and Control, 2nd ed., sec. 2.3 example:
#: C_alpha = 80 000 N/rad per tyre), longitudinal stiffness per tyre [N per unit slip]
#: (Pacejka 2012, Tire and Vehicle Dynamics, 3rd ed., sec. 1.2/3.2: C_Fkappa ~ 1.5-2 C_Falpha
#: for passenger-car tyres), CG height [m] (Heydinger et al. 1999, SAE 1999-01-1336, NHTSA
#: measured sedans 0.52-0.58 m), rolling resistance [-] (Gillespie 1992, Fundamentals of
#: Vehicle Dynamics, sec. 4: 0.010-0.015 on hard roads), brake build-up time [s] (0: the
#: wheels' state at separation holds at once; a driver's build-up is about 0.15-0.2 s,
#: Burg & Moser, Handbuch Verkehrsunfallrekonstruktion, 2017).
SEDAN_TYRE = {"cornering_stiffness": 80_000.0, "longitudinal_stiffness": 150_000.0,
              "cg_height": 0.55, "rolling_resistance": 0.013, "buildup_time": 0.0}

TYRE_MODELS = ("coulomb", "brush")


@dataclass(frozen=True)
class TyreData:
    """Per-vehicle data of the field tyre (:func:`field_wheel_force`), SI; defaults
    :data:`SEDAN_TYRE` (a mid-size sedan).

    Attributes
    ----------
    cornering_stiffness : [N/rad] per tyre, one value or four (FL, FR, RL, RR), > 0
    longitudinal_stiffness : [N per unit slip] per tyre, one value or four, > 0
    cg_height : [m] CG height above the road, >= 0 (load transfer)
    rolling_resistance : [-] rolling-resistance coefficient, >= 0
    buildup_time : [s] brake build-up time, >= 0
    """

    cornering_stiffness: object = SEDAN_TYRE["cornering_stiffness"]
    longitudinal_stiffness: object = SEDAN_TYRE["longitudinal_stiffness"]
    cg_height: float = SEDAN_TYRE["cg_height"]
    rolling_resistance: float = SEDAN_TYRE["rolling_resistance"]
    buildup_time: float = SEDAN_TYRE["buildup_time"]

    def __post_init__(self):
        for name, unit, positive in (("cornering_stiffness", "N/rad", True),
                                     ("longitudinal_stiffness", "N", True),
                                     ("cg_height", "m", False),
                                     ("rolling_resistance", "-", False),
                                     ("buildup_time", "s", False)):
            value = np.asarray(getattr(self, name), dtype=float)
            bad = value <= 0 if positive else value < 0
            if value.shape not in ((), (4,)) or not np.all(np.isfinite(value)) or np.any(bad):
                raise InputError(f"tyres.{name} must be one finite value or four, "
                                 f"{'> 0' if positive else '>= 0'} [{unit}], "
                                 f"got {getattr(self, name)!r}")

    def per_wheel(self, name) -> np.ndarray:
        """A stiffness as four values [N/rad or N] (FL, FR, RL, RR)."""
        return np.broadcast_to(np.asarray(getattr(self, name), dtype=float), (4,)).copy()


def field_wheel_force(c, s, vx, vy, omega, px, py, cw, sw, load, mu, braking, vr, c_long,
                      c_lat, rolling):
    """Force of one tyre [N] (global frame) and its yaw moment [N m]: combined-slip brush.

    Plain arithmetic on numbers or broadcasting arrays (numba compiles this same function in
    :mod:`pim.model.runout_kernel`). Source: the brush model of Pacejka (2012), *Tire and
    Vehicle Dynamics*, 3rd ed., sec. 3.2 (parabolic pressure, combined slip, eqs. 3.50-3.62):
    with the theoretical slip ``sigma = V_s / V_r`` (sliding velocity over rolling speed) and
    ``psi = |(C_x sigma_x, C_y sigma_y)| / (3 mu N)``, the force magnitude is

    ``F = mu N (3 psi - 3 psi^2 + psi^3)`` for ``psi < 1``, ``F = mu N`` beyond,

    the sum of the adhesion part ``F_a = 3 mu N psi (1 - psi)^2`` (along the stiffness-
    weighted slip ``(C_x sigma_x, C_y sigma_y)``, the bristles' deflection) and the sliding
    part ``F_s = mu N psi^2 (3 - 2 psi)`` (against the sliding velocity, Coulomb's law; with
    ``C_x = C_y`` both directions coincide and this is Pacejka's isotropic brush). Small slip:
    ``F_x = -C_x kappa``, ``F_y = -C_y tan(alpha)`` (linear); full sliding (``psi >= 1``):
    ``F = -mu N V_s / |V_s|``, the Coulomb law of :func:`wheel_force`, regularised the same way
    (``V_s / sqrt(|V_s|^2 + v_r^2)`` on a locked wheel; on a rolling wheel the
    regularisation fades as ``v_r^3 / (v_r^2 + V_r^2)`` so that the small sliding
    velocity of a slip-controlled wheel keeps its direction).

    Wheel rotation (quasi-static, no spin state): a braking fraction ``f < 1`` holds the
    longitudinal slip at the value whose pure-braking force is ``f mu N``
    (``C_x sigma_x / (3 mu N) = 1 - (1 - f)^(1/3)``, the brush curve inverted: an ideal
    slip-controlled brake, so straight braking decelerates at ``f mu g``); ``f = 1`` is a
    locked wheel (``V_r = 0``, full sliding). Rolling resistance ``-c_rr N sign(u)`` along
    the wheel acts on the unlocked wheels.

    Parameters
    ----------
    c, s, vx, vy, omega, px, py, cw, sw, load, mu, braking, vr
        As :func:`wheel_force` (``load`` >= 0 [N], the transferred load).
    c_long : longitudinal stiffness C_x [N per unit slip]; c_lat : cornering stiffness C_y
        [N/rad]; rolling : rolling-resistance coefficient c_rr [-].

    Returns
    -------
    fx, fy, moment
    """
    ax = c * px - s * py                       # arm R(psi) p, global frame
    ay = s * px + c * py
    gx = vx - omega * ay                       # velocity of the contact point
    gy = vy + omega * ax
    u = gx * cw + gy * sw                      # along the wheel
    w = -gx * sw + gy * cw                     # across the wheel
    grip = mu * load
    locked = np.floor(braking)                 # 1 for f = 1, else 0
    sigma_x = (1.0 - (1.0 - braking) ** (1.0 / 3.0)) * 3.0 * grip / c_long
    v_roll = (1.0 - locked) * np.sqrt(u * u + vr * vr) / (1.0 + sigma_x)
    slide_x = locked * u + (1.0 - locked) * u * sigma_x / (1.0 + sigma_x)
    kx, ky = c_long * slide_x, c_lat * w       # stiffness-weighted slip (times V_r)
    weighted = np.sqrt(kx * kx + ky * ky)
    # the floor only keeps 0 / 0 away: a locked wheel (v_roll = 0) slides at any slip
    # (psi = 1); a floor near the slips themselves (1e-12 did) made a locked wheel creeping
    # at 1e-18 m/s stick with hundreds of newtons
    psi = weighted / np.maximum(np.maximum(weighted, 3.0 * grip * v_roll), 1e-300)
    adhesion = 3.0 * grip * psi * (1.0 - psi) ** 2 / np.maximum(weighted, 1e-300)
    vr2 = vr * vr                              # Coulomb's regularisation, faded out with
    fade = vr2 / (vr2 + v_roll * v_roll)       # the rolling speed
    sliding = grip * psi * psi * (3.0 - 2.0 * psi) / np.sqrt(
        slide_x * slide_x + w * w + vr2 * fade * fade)
    roll = (1.0 - locked) * rolling * load * u / np.sqrt(u * u + vr * vr)
    f_long = -(adhesion * kx + sliding * slide_x + roll)
    f_lat = -(adhesion * ky + sliding * w)
    fx = f_long * cw - f_lat * sw
    fy = f_long * sw + f_lat * cw
    return fx, fy, ax * fy - ay * fx


def transferred_load(static, mass, a_long, a_lat, cg_height, wheelbase, track, cg_to_front,
                     front, left):
    """Normal load of one tyre [N] with quasi-static load transfer (plain arithmetic).

    Longitudinal: the front axle gains ``-m a_x h / L`` (half per wheel); lateral: the outer
    wheels gain ``m a_y h / T`` in all, shared by the axles as the static load is (front
    ``(L - a) / L``, rear ``a / L``; equal roll stiffness distribution). Rigid body, no
    suspension dynamics (Gillespie 1992, sec. 2 and 6; Milliken & Milliken 1995, ch. 18).
    A wheel whose load would fall below zero has lifted off (load 0).

    Parameters
    ----------
    static : static load of the tyre [N] (:func:`static_loads`).
    mass : [kg]; a_long, a_lat : CG acceleration along the body's x (forward) and y (left)
        [m/s^2]; cg_height : h [m]; wheelbase, track, cg_to_front : L, T, a [m].
    front : 1 for a front tyre, 0 for a rear one; left : 1 for a left tyre, 0 for a right one.
    """
    axle_sign = 2.0 * front - 1.0              # +1 front, -1 rear
    side_sign = 2.0 * left - 1.0               # +1 left, -1 right
    share = front * (wheelbase - cg_to_front) / wheelbase + (1.0 - front) * (
        cg_to_front / wheelbase)
    delta = -axle_sign * mass * a_long * cg_height / (2.0 * wheelbase) - side_sign * (
        mass * a_lat * cg_height * share / track)
    return np.maximum(static + delta, 0.0)


def brake_ramp(time, start, buildup):
    """Fraction of the demanded braking reached at ``time`` [s]: a linear build-up.

    ``0`` before ``start``, ``(t - start) / t_b`` during the build-up time ``t_b``, ``1``
    after it (``t_b = 0``: at once). Plain arithmetic (compiled by numba as well).
    """
    return np.minimum(np.maximum((time - start - buildup) / np.maximum(buildup, 1e-12) + 1.0,
                                 0.0), 1.0)


def linear_buildup_stopping_distance(speed, deceleration, buildup):
    """Stopping distance [m] with a deceleration rising linearly to ``a`` over ``t_b``.

    Derivation: ``a(t) = a t / t_b`` for ``t < t_b``; over the build-up the speed falls by
    ``a t_b / 2`` and the vehicle covers ``v0 t_b - a t_b^2 / 6``; from ``v1 = v0 - a t_b / 2``
    it then needs ``v1^2 / (2 a)``. In all

    ``s = v0^2 / (2 a) + v0 t_b / 2 - a t_b^2 / 24``   (valid for ``v0 >= a t_b / 2``).

    Parameters
    ----------
    speed : v0 [m/s]; deceleration : a [m/s^2] > 0; buildup : t_b [s] >= 0.
    """
    v0, a, tb = (np.asarray(x, dtype=float) for x in (speed, deceleration, buildup))
    if np.any(v0 < a * tb / 2):
        raise InputError("linear_buildup_stopping_distance: the vehicle stops during the "
                         "build-up (speed < deceleration * buildup / 2)")
    return v0 * v0 / (2 * a) + v0 * tb / 2 - a * tb * tb / 24
