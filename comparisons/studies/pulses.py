"""Crash pulses: the contact law's force-time and delta-V-time against NHTSA test 10146.

NHTSA 10146 (2018 Toyota Camry LE, full frontal into a load-cell barrier at 57.09 km/h,
1719 kg; :mod:`sim.crash_data`, the bundled ``sim/data/nhtsa10146_camry_lcb_force_crush.csv``
with its source line) measured the barrier force, the crush and the car's velocity every
2.5 ms. The finite-duration scene of the same test: the car (the test's mass, its CG on the
normal through C, so no rotation) driven at the test's impact speed into a fixed barrier,
the contact law of :mod:`sim.contact_law` with the linear stiffness and the restitution
given as parameters, integrated by :func:`sim.reference_compliant` (``solve_ivp``) with its
contact history recorded. The defaults come from the same test: the stiffness is the
default of the scene's contact type (:func:`sim.crash_data.default_stiffness`, fitted to
this test's loading force-crush), the restitution the test's rebound over impact speed.

What is fitted and what is predicted (:func:`roles`): with a stiffness fitted to this test,
the maximum crush and its time follow from it (a linear spring: v0 sqrt(m/k) at
(pi/2) sqrt(m/k)); with the test's restitution, the rebound and the delta-V follow from
it. Those agree by construction and check nothing; the other figures (peak force, its time,
the crush at the peak, the contact duration) are the law's predictions.

:func:`pulse_metrics` reduces a history to the numbers compared: contact duration (force
above 5 % of its peak, first to last), peak force and its time, crush at the peak force,
maximum crush and its time, rebound speed (delta-V beyond the impact speed) and delta-V.
:func:`compare_pulses` states each model value beside the measured one with its error, and
the root-mean-square difference of the force-time and delta-V-time curves (the model
interpolated at the measured instants; zero force after separation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_trapezoid

import pim
import sim
from sim.crash_data import CrashTest, contact_type, default_stiffness, nhtsa10146

__all__ = ["PulseMetrics", "PulseComparison", "pulse_metrics", "barrier_pulse_case",
           "simulate_pulse", "compare_pulses", "roles", "THRESHOLD", "FROM_STIFFNESS",
           "FROM_RESTITUTION", "PREDICTED"]

#: Fraction of the peak force that bounds the contact duration [-].
THRESHOLD = 0.05
#: Metrics (attributes of :class:`PulseMetrics`) that follow from a stiffness fitted to the
#: test, from a restitution fitted to it, and those the law predicts.
FROM_STIFFNESS = ("max_crush", "max_crush_time")
FROM_RESTITUTION = ("rebound_speed", "delta_v")
PREDICTED = ("duration", "peak_force", "peak_force_time", "crush_at_peak_force")


@dataclass(frozen=True)
class PulseMetrics:
    """Numbers of one crash pulse [SI].

    Attributes
    ----------
    duration : float
        Contact duration, while the force exceeds :data:`THRESHOLD` of its peak [s].
    peak_force : float
        Largest barrier force [N].
    peak_force_time : float
        Time of the peak force [s].
    crush_at_peak_force : float
        Crush at the peak force [m].
    max_crush : float
        Largest crush [m].
    max_crush_time : float
        Time of the largest crush [s].
    rebound_speed : float
        Speed away from the barrier at the end [m/s] (0 if still moving towards it).
    delta_v : float
        Velocity change over the pulse [m/s].
    """

    duration: float
    peak_force: float
    peak_force_time: float
    crush_at_peak_force: float
    max_crush: float
    max_crush_time: float
    rebound_speed: float
    delta_v: float


def pulse_metrics(time, force, crush, velocity) -> PulseMetrics:
    """:class:`PulseMetrics` of a barrier pulse (module notes).

    Parameters
    ----------
    time, force, crush, velocity : array_like
        Samples [s], [N] (barrier force, >= 0 pushing the car back), [m], [m/s] (the car's
        velocity along its travel, positive towards the barrier).
    """
    t, f, x, v = (np.asarray(a, float) for a in (time, force, crush, velocity))
    above = np.flatnonzero(f > THRESHOLD * f.max())
    i, j = int(np.argmax(f)), int(np.argmax(x))
    return PulseMetrics(duration=float(t[above[-1]] - t[above[0]]), peak_force=float(f[i]),
                        peak_force_time=float(t[i]), crush_at_peak_force=float(x[i]),
                        max_crush=float(x[j]), max_crush_time=float(t[j]),
                        rebound_speed=float(max(-v[-1], 0.0)), delta_v=float(v[0] - v[-1]))


def barrier_pulse_case(mass: float, speed: float) -> pim.Case:
    """A car of ``mass`` [kg] at ``speed`` [m/s] head-on into a fixed barrier [SI]: moving
    along -x, CG 2 m behind C on the normal (no rotation), yaw inertia m (1.2 m)^2."""
    car = pim.Vehicle(mass=mass, yaw_inertia=mass * 1.2**2, cg=(2.0, 0.0),
                      velocity=(-speed, 0.0), heading=math.pi)
    return pim.Case(car, pim.Vehicle.obstacle(cg=(-1.0, 0.0)),
                    pim.Impact(point=(0.0, 0.0), normal_angle=0.0), name="nhtsa10146-scene")


@dataclass(frozen=True, eq=False)
class Pulse:
    """A pulse's samples [SI].

    Attributes
    ----------
    time : numpy.ndarray
        Sample times from first contact [s].
    force : numpy.ndarray
        Barrier force, >= 0 pushing the car back [N].
    crush : numpy.ndarray
        Crush [m].
    velocity : numpy.ndarray
        The car's velocity towards the barrier [m/s].
    """

    time: np.ndarray
    force: np.ndarray
    crush: np.ndarray
    velocity: np.ndarray


def simulate_pulse(mass: float, speed: float, stiffness: float, eps: float,
                   rtol: float = 1e-9) -> Pulse:
    """The contact law's pulse of a car into a barrier (module notes); the velocity is
    ``speed`` minus the integral of the force over the mass (trapezoids)."""
    r = sim.reference_compliant(barrier_pulse_case(mass, speed), eps, stiffness,
                                settings=sim.CompliantSettings(rtol=rtol, record=True))
    h = r.history
    force = np.abs(h.normal_force)
    v = speed - cumulative_trapezoid(force, h.time, initial=0.0) / mass
    return Pulse(h.time - h.time[0], force, h.crush, v)


@dataclass(frozen=True, eq=False)
class PulseComparison:
    """Measured and modelled pulses, their metrics and the curves' RMS differences.

    Attributes
    ----------
    measured, model : Pulse
        The test's pulse and the contact law's.
    measured_metrics, model_metrics : PulseMetrics
        Their numbers.
    stiffness : float
        Contact stiffness k of the model [N/m].
    eps : float
        Restitution of the model [-].
    speed : float
        Impact speed [m/s].
    mass : float
        The car's mass [kg].
    force_rms : float
        RMS difference of the force curves on the measured times [N].
    delta_v_rms : float
        RMS difference of the velocity curves on the measured times [m/s].
    source : str
        Where the test's data come from.
    stiffness_source : str
        Where ``stiffness`` comes from ("given", or the contact type's default and its
        source).
    stiffness_fitted : bool
        ``stiffness`` was fitted to this test (its contact type's default, measured on it).
    eps_fitted : bool
        ``eps`` is this test's rebound over its impact speed.
    """

    measured: Pulse
    model: Pulse
    measured_metrics: PulseMetrics
    model_metrics: PulseMetrics
    stiffness: float
    eps: float
    speed: float
    mass: float
    force_rms: float      # [N]
    delta_v_rms: float    # [m/s]
    source: str
    stiffness_source: str = "given"
    stiffness_fitted: bool = False
    eps_fitted: bool = False


def _on(t_meas, model: Pulse, values, after: float):
    return np.interp(t_meas, model.time, values, right=after)


def _stiffness(stiffness, test: CrashTest, case: pim.Case) -> tuple:
    """(k [N/m], where it comes from, fitted to ``test``)."""
    if stiffness is not None:
        return float(stiffness), "given", False
    d = default_stiffness(contact_type(case))
    return d.stiffness, f"the default of a {d.contact} contact: {d.source}", d.test == test.name


def compare_pulses(stiffness: float | None = None, eps: float | None = None,
                   test: CrashTest | None = None) -> PulseComparison:
    """The contact law against a barrier test (default NHTSA 10146), at ``stiffness``
    [N/m] (default: the default of the test's contact type,
    :func:`sim.crash_data.default_stiffness`) and ``eps`` (default the test's rebound speed
    over its impact speed)."""
    test = nhtsa10146() if test is None else test
    speed = float(test.velocity[0])
    measured = Pulse(test.time, test.force, test.crush, test.velocity)
    mm = pulse_metrics(test.time, test.force, test.crush, test.velocity)
    k, k_source, k_fitted = _stiffness(stiffness, test, barrier_pulse_case(test.mass, speed))
    e = mm.rebound_speed / speed if eps is None else float(eps)
    model = simulate_pulse(test.mass, speed, k, e)
    f_on = _on(test.time, model, model.force, 0.0)
    v_on = _on(test.time, model, model.velocity, float(model.velocity[-1]))
    return PulseComparison(
        measured=measured, model=model, measured_metrics=mm,
        model_metrics=pulse_metrics(model.time, model.force, model.crush, model.velocity),
        stiffness=k, eps=e, speed=speed, mass=test.mass,
        force_rms=float(np.sqrt(np.mean((f_on - test.force) ** 2))),
        delta_v_rms=float(np.sqrt(np.mean((v_on - test.velocity) ** 2))), source=test.source,
        stiffness_source=k_source, stiffness_fitted=k_fitted, eps_fitted=eps is None)


def roles(c: PulseComparison) -> dict:
    """Metric (attribute of :class:`PulseMetrics`) -> "fitted: WHY" when it agrees by
    construction (module notes), else "predicted"."""
    out = dict.fromkeys(PREDICTED + FROM_STIFFNESS + FROM_RESTITUTION, "predicted")
    if c.stiffness_fitted:
        out.update(dict.fromkeys(FROM_STIFFNESS, "fitted: k from this test's loading"))
    if c.eps_fitted:
        out.update(dict.fromkeys(FROM_RESTITUTION, "fitted: eps from this test's rebound"))
    return out
