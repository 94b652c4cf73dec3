"""The stiff limit: the finite-duration contact converges to PIM as the contact shortens.

Frictionless point contact (:func:`sim.reference_compliant`, solve_ivp) at contact times T
from 40 ms down to 2.5 ms (k from :func:`sim.contact_law.stiffness_for_duration`) against
PIM with beta = 0 and the same epsilon: the error (:func:`sim.error_measure.impact_error`)
falls in proportion to T, because the bodies move and turn by O(T) during the contact. The
fitted order is the slope of log(error) against log(T) (expected 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import pim
import sim
from sim.compliant_setup import build_problem
from sim.contact_law import stiffness_for_duration
from sim.error_measure import impact_error

__all__ = ["StiffLimit", "stiff_limit", "plot_stiff_limit", "DURATIONS"]

DURATIONS = (0.04, 0.02, 0.01, 0.005, 0.0025)


@dataclass(frozen=True, eq=False)
class StiffLimit:
    """Errors against PIM (beta = 0) over contact durations, and the fitted order.

    Attributes
    ----------
    case_name : str
        The case's name.
    eps : float
        Restitution [-].
    durations : ndarray (n,)
        Requested contact times [s].
    contact : ndarray (n,)
        Simulated contact times [s].
    errors : ndarray (n,)
        :func:`sim.error_measure.impact_error` of each simulation against PIM [-].
    order : float
        Slope of log(error) against log(simulated contact time) [-] (property).
    """

    case_name: str
    eps: float
    durations: np.ndarray     # requested contact times [s]
    contact: np.ndarray       # simulated contact times [s]
    errors: np.ndarray        # impact_error against PIM [-]

    @property
    def order(self) -> float:
        """Slope of log(error) against log(simulated contact time)."""
        return float(np.polyfit(np.log(self.contact), np.log(self.errors), 1)[0])


def stiff_limit(case: pim.Case, eps: float, durations=DURATIONS, rtol: float = 1e-11
                ) -> StiffLimit:
    """Run the frictionless point contact over ``durations`` [s] (module notes)."""

    result = pim.solve(case, eps, 0.0)
    k_nn = build_problem(case, eps, sim.DEFAULT_STIFFNESS).k_nn
    contact, errors = [], []
    for duration in durations:
        k = float(stiffness_for_duration(duration, k_nn, eps))
        r = sim.reference_compliant(case, eps, k,
                                    settings=sim.CompliantSettings(rtol=rtol, record=False))
        contact.append(r.contact_duration)
        errors.append(float(impact_error(case, result, r.velocity1, r.velocity2, r.yaw_rate1,
                                         r.yaw_rate2)))
    return StiffLimit(case.name, float(eps), np.asarray(durations, float), np.array(contact),
                      np.array(errors))


def plot_stiff_limit(limit: StiffLimit):
    """Log-log error against contact time with the fitted slope (a Figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.6, 4.2), layout="constrained")
    ax = fig.subplots()
    ax.loglog(1e3 * limit.contact, limit.errors, "o-", label="finite-duration contact")
    fit = np.polyfit(np.log(limit.contact), np.log(limit.errors), 1)
    t = np.geomspace(limit.contact.min(), limit.contact.max(), 20)
    ax.loglog(1e3 * t, np.exp(np.polyval(fit, np.log(t))), "--", color="0.4",
              label=f"fitted slope {fit[0]:.3f} (expected 1)")
    ax.set_xlabel("contact time [ms]")
    ax.set_ylabel("error against PIM, beta = 0 [-]")
    ax.set_title(f"{limit.case_name}: frictionless, k -> infinity (eps = {limit.eps:.3g})",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return fig
