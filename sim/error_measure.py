"""How far a simulation is from the analytic answer: per quantity, and as one number.

The project's one comparison error measure: ``pim sim``, ``pim compare``, ``pim speed-error``
and ``pim hard-cases`` all report :func:`impact_error` and say what it is
(:data:`ERROR_DEFINITION`).

Per quantity (:func:`compare_results`): absolute error |sim - PIM| and relative error
|sim - PIM| / |PIM| (undefined, NaN, where the analytic value is zero to round-off, e.g.
the velocity of a fixed barrier or the tangential impulse of a frictionless impact).

One number per impact (:func:`impact_error`): the largest error in the *changes* the impact
makes, relative to the largest such change,

    e = max(|dV1_sim - dV1|, |dV2_sim - dV2|, k1 |dW1_sim - dW1|, k2 |dW2_sim - dW2|)
        / max(|dV1|, |dV2|, k1 |dW1|, k2 |dW2|)                                   [-]

where |.| of a velocity change is its largest component, |x| or |y| (the maximum norm),
with k_i = sqrt(I_i / m_i) the radius of gyration (a yaw rate error times k_i is the speed
error it gives a point at k_i from the CG). Measuring against the change rather than the
speed keeps a grazing impact (tiny impulse, large speeds) honest: there a 1e-6 error in
the impulse is a 1e-6 error, not 1e-10 of the speed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import pim
from pim.io.units import convert
from pim.model import motion

__all__ = ["QuantityError", "compare_results", "impact_error", "analytic_residual",
           "ERROR_DEFINITION", "QUANTITIES", "KIND_OF_UNIT", "TABLE_HEADER"]

#: One line saying what :func:`impact_error` measures, printed next to it by every command.
ERROR_DEFINITION = ("largest error in the velocity changes, yaw rates times the radius of "
                    "gyration, relative to the largest change")


def _f(x) -> float:
    return float(np.asarray(x, dtype=float).reshape(()))


@dataclass(frozen=True)
class QuantityError:
    """One post-impact quantity, analytic against simulated.

    Attributes
    ----------
    key, label, unit : str
        Machine name, description, SI unit.
    analytic, simulated : float
        PIM's value and the simulator's.
    absolute : float
        |simulated - analytic| [unit].
    relative : float
        absolute / |analytic| [-]; NaN where the analytic value is zero to round-off.
    """

    key: str
    label: str
    unit: str
    analytic: float
    simulated: float
    absolute: float
    relative: float

    def to_json(self, units: str = "si") -> dict:
        """The row for ``--json``, its values in the ``units`` system with their unit."""
        (a, b, e), unit = convert(np.array([self.analytic, self.simulated, self.absolute]),
                                  KIND_OF_UNIT[self.unit], units)
        return {"key": self.key, "label": self.label, "unit": unit, "analytic": float(a),
                "simulated": float(b), "abs_error": float(e), "rel_error": self.relative}

    def line(self, units: str = "si") -> str:
        """The row of a plain-text comparison table (:data:`TABLE_HEADER`'s columns)."""
        d = self.to_json(units)
        rel = "-" if self.relative != self.relative else f"{self.relative:.3g}"
        return (f"{self.label:<26}{d['unit']:<7}{d['analytic']:>15.8g}{d['simulated']:>15.8g}"
                f"{d['abs_error']:>12.3g}{rel:>12}")


#: Header of the plain-text comparison tables (:meth:`QuantityError.line`).
TABLE_HEADER = (f"{'quantity':<26}{'unit':<7}{'analytic':>15}{'simulated':>15}"
                f"{'abs error':>12}{'rel error':>12}")


def _sim_quantities(case: pim.Case, result: pim.Result, s) -> dict:
    n = np.asarray(result.normal, float).reshape(2)
    t = np.asarray(result.tangent, float).reshape(2)
    v1 = np.asarray(case.vehicle1.velocity, float).reshape(2)
    v2 = np.asarray(case.vehicle2.velocity, float).reshape(2)
    dv1, dv2 = s.velocity1 - v1, s.velocity2 - v2
    p = np.asarray(s.impulse, float)
    return {
        "velocity1_x": s.velocity1[0], "velocity1_y": s.velocity1[1],
        "velocity2_x": s.velocity2[0], "velocity2_y": s.velocity2[1],
        "speed1": np.hypot(*s.velocity1), "speed2": np.hypot(*s.velocity2),
        "yaw_rate1": s.yaw_rate1, "yaw_rate2": s.yaw_rate2,
        "delta_v1": np.hypot(*dv1), "delta_v2": np.hypot(*dv2),
        "impulse_x": p[0], "impulse_y": p[1], "impulse_n": p @ n, "impulse_t": p @ t,
        "energy_loss": s.energy_before - s.energy_after,
    }


def _pim_quantities(result: pim.Result) -> dict:
    v1 = np.asarray(result.velocity1, float).reshape(2)
    v2 = np.asarray(result.velocity2, float).reshape(2)
    p = np.asarray(result.impulse, float).reshape(2)
    return {
        "velocity1_x": v1[0], "velocity1_y": v1[1], "velocity2_x": v2[0], "velocity2_y": v2[1],
        "speed1": _f(result.speed1), "speed2": _f(result.speed2),
        "yaw_rate1": _f(result.yaw_rate1), "yaw_rate2": _f(result.yaw_rate2),
        "delta_v1": _f(result.delta_v1_magnitude), "delta_v2": _f(result.delta_v2_magnitude),
        "impulse_x": p[0], "impulse_y": p[1], "impulse_n": _f(result.impulse_n),
        "impulse_t": _f(result.impulse_t), "energy_loss": _f(result.energy_loss),
    }


#: Unit kind (pim.io.units) of each SI unit in :data:`QUANTITIES`, for display.
KIND_OF_UNIT = {"m/s": "velocity", "rad/s": "angular_velocity", "N s": "impulse",
                "J": "energy"}

#: (key, label, SI unit) of every compared post-impact quantity, in table order.
QUANTITIES = (
    ("velocity1_x", "vehicle 1 velocity x", "m/s"),
    ("velocity1_y", "vehicle 1 velocity y", "m/s"),
    ("velocity2_x", "vehicle 2 velocity x", "m/s"),
    ("velocity2_y", "vehicle 2 velocity y", "m/s"),
    ("speed1", "vehicle 1 speed", "m/s"),
    ("speed2", "vehicle 2 speed", "m/s"),
    ("yaw_rate1", "vehicle 1 yaw rate", "rad/s"),
    ("yaw_rate2", "vehicle 2 yaw rate", "rad/s"),
    ("delta_v1", "vehicle 1 |delta-V|", "m/s"),
    ("delta_v2", "vehicle 2 |delta-V|", "m/s"),
    ("impulse_x", "impulse on vehicle 1, x", "N s"),
    ("impulse_y", "impulse on vehicle 1, y", "N s"),
    ("impulse_n", "normal impulse Pn", "N s"),
    ("impulse_t", "tangential impulse Pt", "N s"),
    ("energy_loss", "kinetic energy lost", "J"),
)


def compare_results(case: pim.Case, result: pim.Result, simulated) -> list[QuantityError]:
    """Every post-impact quantity of :data:`QUANTITIES`, analytic against simulated.

    Parameters
    ----------
    case : pim.Case
        The single case both were computed for.
    result : pim.Result
        ``pim.solve(case, eps, beta)``.
    simulated : sim.SimResult
        ``sim.simulate(case, eps, beta, ...)``.

    Returns
    -------
    list of QuantityError
    """
    a, s = _pim_quantities(result), _sim_quantities(case, result, simulated)
    scales = {"m/s": max(abs(a[k]) for k in ("velocity1_x", "velocity1_y", "velocity2_x",
                                                "velocity2_y", "speed1", "speed2")),
              "rad/s": max(abs(a["yaw_rate1"]), abs(a["yaw_rate2"])),
              "N s": max(abs(a["impulse_x"]), abs(a["impulse_y"])),
              "J": abs(_f(result.kinetic_energy_before))}
    out = []
    for key, label, unit in QUANTITIES:
        x, y = float(a[key]), float(s[key])
        err = abs(y - x)
        tiny = abs(x) <= 1e-12 * max(scales[unit], 1e-300)
        out.append(QuantityError(key, label, unit, x, y, err, float("nan") if tiny
                                 else err / abs(x)))
    return out


def impact_error(case: pim.Case, result: pim.Result, velocity1, velocity2, yaw_rate1,
                 yaw_rate2) -> np.ndarray:
    """Largest error in the impact's velocity changes, relative to the largest change [-].

    Parameters
    ----------
    case : pim.Case
        The single case.
    result : pim.Result
        The analytic answer ``pim.solve(case, eps, beta)``.
    velocity1, velocity2 : array_like, shape (..., 2)
        Simulated post-impact CG velocities [m/s] (NaN for failed runs).
    yaw_rate1, yaw_rate2 : array_like
        Simulated post-impact yaw rates [rad/s].

    Returns
    -------
    ndarray
        e (module docstring) per run; NaN where the run failed.
    """
    return motion.impact_error(case, result, motion.MotionValues(velocity1, velocity2,
                                                                 yaw_rate1, yaw_rate2))


def analytic_residual(case: pim.Case, result: pim.Result) -> float:
    """How well PIM's answer meets its own equations, on the scale of :func:`impact_error`.

    The largest of: Newton's restitution at C, |U_n + eps u_n|; the impulse ratio,
    |Pt - mu Pn| times K_tt (as a velocity); and linear momentum, |m1 dV1 + m2 dV2| / m_c
    (for two moving bodies) -- divided by the largest velocity change. The floating-point
    error of the closed form, plotted next to the simulator's errors.
    """
    eps = _f(result.eps)
    un, sn = _f(result.approach_n), _f(result.separation_n)
    res = [abs(sn + eps * un)]
    pn, pt, mu = _f(result.impulse_n), _f(result.impulse_t), _f(result.mu)
    res.append(abs(pt - mu * pn) * abs(_f(result.k_tt)))
    a, b = case.vehicle1, case.vehicle2
    if not bool(b.fixed):
        m1, m2 = _f(a.mass), _f(b.mass)
        d1 = np.asarray(result.velocity1, float).reshape(2) - np.asarray(a.velocity).reshape(2)
        d2 = np.asarray(result.velocity2, float).reshape(2) - np.asarray(b.velocity).reshape(2)
        res.append(float(np.hypot(*(m1 * d1 + m2 * d2))) * (1 / m1 + 1 / m2))
    return max(res) / max(float(np.abs(motion.velocity_changes(case, result)).max()), 1e-300)
