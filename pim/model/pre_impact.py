"""Pre-impact motion: from the speed at the impact back to the speed before it.

Two kinds of evidence turn a vehicle's impact speed into its speed earlier on:

- **Tyre marks before the impact** (skid or yaw marks of length ``L`` ending at the impact):
  a vehicle sliding with the drag fraction ``f`` (the share of its weight on braked wheels
  times their braking fraction) on a road of friction ``mu`` and grade ``G`` (rise over run,
  + uphill in the direction of travel, ``theta = atan(G)``) decelerates at the constant

  ``a = g (f mu cos(theta) + sin(theta))``                                        (1)

  (the force balance along the incline: friction ``f mu m g cos(theta)`` and the weight's
  component ``m g sin(theta)``, both against the motion uphill), so by ``v^2 = v0^2 - 2 a L``
  the speed at the start of the marks is

  ``v_start = sqrt(v_impact^2 + 2 g L (f mu cos(theta) + sin(theta)))``            (2)

  Source: the "combined speed" equation of skid-mark analysis, ``S = sqrt(S_1^2 + S_2^2)``
  with ``S_1^2 = 30 d (f +- G)`` [mph, ft] (Fricke, L. B., *Traffic Accident Reconstruction*,
  Northwestern University Traffic Institute, 1990, speed from skidmarks; Brach, R. M. &
  Brach, R. M., *Vehicle Accident Analysis and Reconstruction Methods*, 2nd ed., SAE 2011,
  straight-line motion at constant deceleration). The textbooks' ``f +- G`` is the
  small-angle form of ``f cos(theta) + sin(theta)``; (1) is exact for a rigid vehicle on a
  plane incline. A yawing (side-slipping) car slides on all four tyres: ``braking = 1``
  whatever its brakes did. The per-wheel drag fraction (:func:`drag_fraction`) weighs each
  wheel's braking fraction with its static load, as the Coulomb run-out tyre does
  (straight braking at ``f mu g``, :mod:`pim.model.tyres`); the textbooks' "braking
  efficiency" is the same number.
- **Driver inputs over time** (a ``[driver.vehicleN]`` table starting at a negative time
  ``t0``): :func:`driver_start_speed` finds the speed at ``t0`` from which the vehicle,
  driven by the table on either run-out tyre (:func:`pim.model.runout.pre_impact_motion`),
  arrives at the impact with the given speed (a one-dimensional root find).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .numbers import InputError, real_array, speed_text
from .runout import RunoutVehicle, StoppedBeforeImpact, pre_impact_motion
from .tyres import STANDARD_GRAVITY

__all__ = ["PreImpactMarks", "drag_fraction", "mark_deceleration", "speed_at_mark_start",
           "driver_speed_at_impact", "driver_start_speed", "MAX_GRADE"]

#: Largest |grade| [-] accepted (100 %, a 45 degree slope): beyond it no road is driven.
MAX_GRADE = 1.0


def drag_fraction(braking, front_share=0.5) -> np.ndarray:
    """The drag fraction ``f`` [-] of four wheels' braking fractions (load-weighted mean).

    ``f = s (b_FL + b_FR) / 2 + (1 - s) (b_RL + b_RR) / 2`` with ``s`` the front axle's static
    share of the weight, ``(L - a) / L`` (:func:`pim.model.tyres.static_loads`).

    Parameters
    ----------
    braking : array_like (..., 4) [-], or a scalar for all four wheels, each in [0, 1].
    front_share : array_like [-] in [0, 1].
    """
    b = np.asarray(braking, dtype=float)
    if b.ndim == 0 or b.shape[-1] != 4:
        return np.asarray(b, dtype=float)
    s = np.asarray(front_share, dtype=float)
    return s * (b[..., 0] + b[..., 1]) / 2 + (1 - s) * (b[..., 2] + b[..., 3]) / 2


def mark_deceleration(friction, braking=1.0, grade=0.0, gravity=STANDARD_GRAVITY):
    """Deceleration [m/s^2] of a vehicle sliding along its marks, eq. (1) of the module notes.

    ``a = g (f mu cos(theta) + sin(theta))``, ``theta = atan(grade)``.

    Parameters
    ----------
    friction : array_like, mu [-] > 0.
    braking : array_like, the drag fraction f [-] in [0, 1] (:func:`drag_fraction`).
    grade : array_like, G [-] (rise over run, + uphill in the direction of travel).
    gravity : float [m/s^2].
    """
    theta = np.arctan(np.asarray(grade, dtype=float))
    return gravity * (np.asarray(braking, dtype=float) * np.asarray(friction, dtype=float)
                      * np.cos(theta) + np.sin(theta))


def _check(value, name, unit, ok, allowed, where):
    arr = real_array(value, f"{where}.{name}", unit)
    if not np.all(np.isfinite(arr) & ok(arr)):
        bad = arr[~(np.isfinite(arr) & ok(arr))].ravel()[0]
        raise InputError(f"{where}.{name} must be {allowed} [{unit}], got {bad:g}")
    return arr


def speed_at_mark_start(impact_speed, length, friction, braking=1.0, grade=0.0,
                        gravity=STANDARD_GRAVITY, where="pre_impact"):
    """Speed [m/s] at the start of marks of length ``length`` ending at the impact, eq. (2).

    ``v_start = sqrt(v_impact^2 + 2 g L (f mu cos(theta) + sin(theta)))``, ``theta =
    atan(grade)`` (Fricke 1990; Brach & Brach 2011; module notes). Vectorised: the arguments
    broadcast (one value per Monte Carlo sample, or one for all).

    Parameters
    ----------
    impact_speed : array_like, v_impact [m/s] >= 0.
    length : array_like, L [m] >= 0, the marks' length up to the impact.
    friction : array_like, mu [-] > 0.
    braking : array_like, drag fraction f [-] in [0, 1] (:func:`drag_fraction`).
    grade : array_like, G [-] in [-1, 1] (+ uphill in the direction of travel).
    gravity : float [m/s^2].
    where : str, the case-file table named in error messages.

    Returns
    -------
    ndarray [m/s], the broadcast shape of the arguments.

    Raises
    ------
    InputError
        A value outside its range, or a grade down which the sliding car speeds up
        (``f mu cos(theta) + sin(theta) < 0``: friction cannot hold it, no such marks).
    """
    v = _check(impact_speed, "impact_speed", "m/s", lambda x: x >= 0, ">= 0", where)
    length = _check(length, "skid_length", "m", lambda x: x >= 0, ">= 0", where)
    mu = _check(friction, "friction", "-", lambda x: x > 0, "> 0", where)
    f = _check(braking, "braking", "-", lambda x: (x >= 0) & (x <= 1), "in [0, 1]", where)
    grade = _check(grade, "grade", "-", lambda x: np.abs(x) <= MAX_GRADE,
                   f"in [-{MAX_GRADE:g}, {MAX_GRADE:g}] (rise over run)", where)
    a = mark_deceleration(mu, f, grade, gravity)
    if np.any(a < 0):
        k = np.unravel_index(np.argmin(a), a.shape)
        g_k, f_k, mu_k = (np.broadcast_to(x, a.shape)[k] for x in (grade, f, mu))
        raise InputError(f"{where}.grade {100 * g_k:g} % is steeper downhill than the "
                         f"friction holds (braking {f_k:g} x friction {mu_k:g} = "
                         f"{f_k * mu_k:g} < {-g_k:g}, the downhill grade): the sliding car "
                         f"would speed up along the marks")
    return np.hypot(v, np.sqrt(2.0 * a * length))      # no under- or overflow of v^2


@dataclass(frozen=True)
class PreImpactMarks:
    """Tyre marks before the impact (``[evidence.vehicleN.pre_impact]``), SI.

    Attributes
    ----------
    skid_length : float [m] >= 0, the marks' length up to the impact
    friction : float [-] > 0, tyre-road friction along the marks
    braking : tuple of four braking fractions in [0, 1] (FL, FR, RL, RR; 1 locked)
    grade : float [-] rise over run in [-1, 1], + uphill in the direction of travel
    length_sigma : float [m] >= 0, standard deviation of the measured length (information
        for the report; the Monte Carlo varies ``skid_length`` from ``[uncertainty]``)
    front_share : float [-] in [0, 1], the front axle's static share of the weight
    where : str, the case-file table named in error messages
    """

    skid_length: float
    friction: float
    braking: tuple = (1.0, 1.0, 1.0, 1.0)
    grade: float = 0.0
    length_sigma: float = 0.0
    front_share: float = 0.5
    where: str = "pre_impact"

    def __post_init__(self):
        w = self.where
        if len(self.braking) != 4 or not all(0 <= b <= 1 for b in self.braking):
            raise InputError(f"{w}.braking must be one fraction in [0, 1] or four (FL, FR, "
                             f"RL, RR), got {self.braking!r}")
        _check(self.length_sigma, "length_sigma", "m", lambda x: x >= 0, ">= 0", w)
        _check(self.front_share, "front_share", "-", lambda x: (x >= 0) & (x <= 1),
               "in [0, 1]", w)
        self.start_speed(0.0)           # every other check of eq. (2)

    @property
    def drag(self) -> float:
        """The drag fraction f [-] of the four wheels (:func:`drag_fraction`)."""
        return float(drag_fraction(self.braking, self.front_share))

    def start_speed(self, impact_speed, *, length=None, friction=None) -> np.ndarray:
        """Speed [m/s] at the start of the marks for ``impact_speed`` [m/s] (arrays
        broadcast: per Monte Carlo sample the impact speed, and optionally the drawn
        ``length`` [m] and ``friction`` [-] instead of the marks' own)."""
        return speed_at_mark_start(impact_speed,
                                   self.skid_length if length is None else length,
                                   self.friction if friction is None else friction,
                                   self.drag, self.grade, where=self.where)


def driver_speed_at_impact(vehicle: RunoutVehicle, start_speed: float, start_time: float,
                           *, rtol=1e-8, atol=1e-10) -> float:
    """Speed [m/s] at the impact (``t = 0``) of a vehicle that drives straight ahead at
    ``start_speed`` [m/s] at ``start_time`` [s] < 0 (no side slip, no yaw rate) and then
    follows its driver table (:func:`pim.model.runout.pre_impact_motion`); 0 when it stops
    before the impact."""
    try:
        _, _, velocity, _ = pre_impact_motion(vehicle, (0.0, 0.0), 0.0, (start_speed, 0.0),
                                              0.0, start_time, rtol=rtol, atol=atol)
    except StoppedBeforeImpact:
        return 0.0
    return float(np.hypot(*velocity))


def driver_start_speed(vehicle: RunoutVehicle, impact_speed: float, start_time=None, *,
                       where="driver", rtol=1e-8, xtol=1e-7) -> float:
    """Speed [m/s] at ``start_time`` from which the driver's inputs bring the vehicle to the
    impact at ``impact_speed`` [m/s].

    The vehicle starts straight ahead (velocity along its heading, no yaw rate) at the
    table's first time ``t0 < 0`` (or ``start_time``) and is integrated to the impact with
    its tyre law (Coulomb, or the field tyre of ``[tyres.vehicleN]``) by
    :func:`pim.model.runout.pre_impact_motion`; the speed at ``t0`` is the root of
    ``v_impact(v0) - impact_speed`` (Brent's method, ``scipy.optimize.brentq``) on
    ``[impact_speed, impact_speed + (mu + c_rr) g |t0| + 1 m/s]``: the model has no
    propulsion, so the vehicle never arrives faster than it started, and the tyres
    decelerate it by at most ``(mu + c_rr) g``.

    A start speed too low for the table's braking stops the vehicle before the impact
    (its impact speed counts as 0 in the root find), so the answer is always a start speed
    from which the vehicle reaches the impact still moving.

    Parameters
    ----------
    vehicle : RunoutVehicle with scalar fields and its ``driver`` table (or constant braking).
    impact_speed : float [m/s] > the tyre law's regularisation speed.
    start_time : float [s] < 0, default the driver table's first time.
    where : str, the case-file table named in error messages.

    Raises
    ------
    InputError
        No negative start time, an impact speed at which the vehicle is (nearly) at rest
        (no start speed reaches it), or no start speed in the bracket reaching it.
    """
    from scipy.optimize import brentq  # scipy on use: `import pim` stays light

    if start_time is None:
        if vehicle.driver is None:
            raise InputError(f"{where}: no driver table and no start time")
        start_time = float(vehicle.driver.time[0])
    if not start_time < 0:
        raise InputError(f"{where}.time: the first time must be < 0 s (before the impact) "
                         f"for pre-impact motion, got {start_time:g} s")
    v_imp = float(impact_speed)
    if not (np.isfinite(v_imp) and v_imp > vehicle.regularisation):
        raise InputError(f"{where}: the impact speed {speed_text(v_imp, 'g')} is (nearly) "
                         f"zero: the vehicle is at rest at the impact, no start speed ends "
                         f"there (pre-impact motion needs > "
                         f"{speed_text(vehicle.regularisation, 'g')})")

    def gap(v0):
        return driver_speed_at_impact(vehicle, v0, start_time, rtol=rtol) - v_imp

    low_gap = gap(v_imp)
    if low_gap >= -xtol:          # no deceleration at all (no braking, no rolling resistance)
        return v_imp
    rolling = 0.0 if vehicle.tyre is None else float(vehicle.tyre.rolling_resistance)
    mu = float(np.max(vehicle.friction))
    high = v_imp + (mu + rolling) * vehicle.gravity * abs(start_time) + 1.0
    if gap(high) < 0:
        raise InputError(f"{where}: no start speed up to {speed_text(high)} at t = "
                         f"{start_time:g} s brings the vehicle to the impact at "
                         f"{speed_text(v_imp)}")
    return float(brentq(gap, v_imp, high, xtol=xtol, rtol=4 * np.finfo(float).eps))
