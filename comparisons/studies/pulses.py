"""Crash pulses: the contact law's force-time and delta-V-time against NHTSA test 10146.

NHTSA 10146 (2018 Toyota Camry LE, full frontal into a load-cell barrier at 57.09 km/h,
1719 kg; :mod:`sim.crash_data`, the bundled ``sim/data/nhtsa10146_camry_lcb_force_crush.csv``
with its source line) measured the barrier force, the crush and the car's velocity every
2.5 ms. The finite-duration scene of the same test: the car (the test's mass, its CG on the
normal through C, so no rotation) driven at the test's impact speed into a fixed barrier,
the contact law of :mod:`sim.contact_law` with the linear stiffness and the restitution
given as parameters (default: :data:`sim.DEFAULT_STIFFNESS`, which was itself derived from
this test, and the test's rebound over impact speed, so this is a check of the law's *shape*
at parameters from the same test, not an independent prediction), integrated by
:func:`sim.reference_compliant` (``solve_ivp``) with its contact history recorded.

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
from pim.io.units import convert
from sim.crash_data import CrashTest, nhtsa10146

from comparisons.report.number_format import format_number
from comparisons.report.tables import Table

__all__ = ["PulseMetrics", "PulseComparison", "pulse_metrics", "barrier_pulse_case",
           "simulate_pulse", "compare_pulses", "pulse_table", "plot_pulses", "THRESHOLD"]

#: Fraction of the peak force that bounds the contact duration [-].
THRESHOLD = 0.05


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


def _on(t_meas, model: Pulse, values, after: float):
    return np.interp(t_meas, model.time, values, right=after)


def compare_pulses(stiffness: float | None = None, eps: float | None = None,
                   test: CrashTest | None = None) -> PulseComparison:
    """The contact law against a barrier test (default NHTSA 10146), at ``stiffness``
    [N/m] (default :data:`sim.DEFAULT_STIFFNESS`) and ``eps`` (default the test's rebound
    speed over its impact speed)."""
    test = nhtsa10146() if test is None else test
    speed = float(test.velocity[0])
    measured = Pulse(test.time, test.force, test.crush, test.velocity)
    mm = pulse_metrics(test.time, test.force, test.crush, test.velocity)
    k = sim.DEFAULT_STIFFNESS if stiffness is None else float(stiffness)
    e = mm.rebound_speed / speed if eps is None else float(eps)
    model = simulate_pulse(test.mass, speed, k, e)
    f_on = _on(test.time, model, model.force, 0.0)
    v_on = _on(test.time, model, model.velocity, float(model.velocity[-1]))
    return PulseComparison(
        measured, model, mm, pulse_metrics(model.time, model.force, model.crush,
                                           model.velocity), k, e, speed, test.mass,
        float(np.sqrt(np.mean((f_on - test.force) ** 2))),
        float(np.sqrt(np.mean((v_on - test.velocity) ** 2))), test.source)


_ROWS = (("contact duration (force > 5 % of peak)", "duration", 1e3, "ms"),
         ("peak force", "peak_force", 1e-3, "kN"),
         ("time of peak force", "peak_force_time", 1e3, "ms"),
         ("crush at peak force", "crush_at_peak_force", 1.0, "m"),
         ("maximum crush", "max_crush", 1.0, "m"),
         ("time of maximum crush", "max_crush_time", 1e3, "ms"),
         ("rebound speed", "rebound_speed", 1.0, "m/s"),
         ("delta-V", "delta_v", 1.0, "m/s"))


def pulse_table(c: PulseComparison, units: str = "si") -> Table:
    """Measured against modelled metrics, with the error and the relative error."""
    rows = []
    for label, attr, factor, unit in _ROWS:
        a, b = getattr(c.measured_metrics, attr), getattr(c.model_metrics, attr)
        if unit in ("m", "m/s"):
            kind = "length" if unit == "m" else "speed"
            (a, b), unit = convert([a, b], kind, units)
        else:
            a, b = a * factor, b * factor
        rows.append((label, unit, float(a), float(b), float(b - a),
                     100.0 * (b - a) / a if a else math.nan))
    return Table("pulses-nhtsa10146", "NHTSA 10146 against the contact law",
                 ("quantity", "unit", "measured", "contact law", "error", "error [%]"),
                 tuple(rows), {"measured": _three, "contact law": _three, "error": _three,
                               "error [%]": _three})


def _three(x) -> str:
    """Three significant digits in the reports' one number format."""
    return format_number(x, sig=3)


def plot_pulses(c: PulseComparison, units: str = "si"):
    """Force-time, delta-V-time and force-crush, measured against the law (a Figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.5, 4.2), layout="constrained")
    axes = fig.subplots(1, 3)
    su = convert(1.0, "speed", units)[1]
    lu = convert(1.0, "length", units)[1]
    for p, label, style in ((c.measured, "NHTSA 10146 (measured)", dict(color="k", lw=1.4)),
                            (c.model, f"contact law, k = {c.stiffness / 1e3:.0f} kN/m, "
                                      f"eps = {c.eps:.3f}", dict(color="C3", lw=1.6,
                                                                  ls="--"))):
        axes[0].plot(p.time * 1e3, p.force / 1e3, label=label, **style)
        axes[1].plot(p.time * 1e3, convert(c.speed - p.velocity, "speed", units)[0],
                     label=label, **style)
        axes[2].plot(convert(p.crush, "length", units)[0], p.force / 1e3, label=label,
                     **style)
    axes[0].set(xlabel="time [ms]", ylabel="barrier force [kN]",
                title=f"force: RMS difference {c.force_rms / 1e3:.0f} kN")
    axes[1].set(xlabel="time [ms]", ylabel=f"delta-V [{su}]",
                title=f"delta-V: RMS difference "
                      f"{float(convert(c.delta_v_rms, 'speed', units)[0]):.2f} {su}")
    axes[2].set(xlabel=f"crush [{lu}]", ylabel="barrier force [kN]", title="force-crush")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return fig
