"""Figures of ``pim validate`` (its report: :mod:`comparisons.report.validate`).

matplotlib is imported inside the functions (``import pim`` stays fast). Values are shown in
the user's unit system.
"""

from __future__ import annotations

import numpy as np

from ..analysis.validation import SPEED_TOLERANCE, YAW_TOLERANCE
from ..io.units import convert

__all__ = ["plot_predicted_vs_measured", "plot_coefficients"]


def _speed(x, units):
    return convert(x, "speed", units)


def _yaw(x, units):
    return convert(x, "angular_velocity", units)


def plot_predicted_vs_measured(series: dict, units: str = "si"):
    """Predicted against measured delta-V magnitude and yaw rate.

    ``series``: label -> list of :class:`pim.analysis.validation.BarrierReproduction` (or
    any rows with ``predicted`` and ``measured`` (dVx, dVy, Omega) [SI]). Returns a Figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4.6))
    axes = fig.subplots(1, 2)
    for (label, rows), marker in zip(series.items(), "os^vD", strict=False):
        if not rows:
            continue
        pred = np.array([r.predicted for r in rows])
        meas = np.array([r.measured for r in rows])
        dv_p, su = _speed(np.hypot(pred[:, 0], pred[:, 1]), units)
        dv_m, _ = _speed(np.hypot(meas[:, 0], meas[:, 1]), units)
        om_p, yu = _yaw(pred[:, 2], units)
        om_m, _ = _yaw(meas[:, 2], units)
        axes[0].plot(dv_m, dv_p, marker, ms=5, mfc="none", label=label)
        axes[1].plot(om_m, om_p, marker, ms=5, mfc="none", label=label)
    for ax, what, unit, tol in ((axes[0], "delta-V", su, _speed(SPEED_TOLERANCE, units)[0]),
                                (axes[1], "yaw rate", yu, _yaw(YAW_TOLERANCE, units)[0])):
        lo, hi = ax.get_xlim()
        lo, hi = min(lo, ax.get_ylim()[0]), max(hi, ax.get_ylim()[1])
        x = np.array([lo, hi])
        ax.plot(x, x, "k-", lw=0.8)
        ax.fill_between(x, x - tol, x + tol, color="0.85", zorder=0,
                        label=f"+-{float(tol):.3g} {unit}")
        ax.set_xlim(lo, hi)
        ax.set_ylim(lo, hi)
        ax.set_xlabel(f"measured {what} [{unit}]")
        ax.set_ylabel(f"PIM {what} [{unit}]")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("IIHS small-overlap barrier tests (Brach et al. 2014): PIM against measured")
    fig.tight_layout()
    return fig


def plot_coefficients(stats):
    """Strip plots of epsilon and beta by crash class (:func:`coefficient_stats` output)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4))
    axes = fig.subplots(1, 2)
    for ax, coefficient in zip(axes, ("epsilon", "beta"), strict=False):
        rows = [s for s in stats if s.coefficient == coefficient]
        for i, s in enumerate(rows):
            jitter = np.linspace(-0.15, 0.15, s.n)
            ax.plot(i + jitter, s.values, "o", ms=4, mfc="none")
            ax.plot([i - 0.25, i + 0.25], [s.median] * 2, "k-", lw=2)
        ax.set_xticks(range(len(rows)), [f"{s.crash_class}\n(n={s.n})" for s in rows], fontsize=8)
        ax.set_ylabel("epsilon [-]" if coefficient == "epsilon" else "beta = mu/mu0 [-]")
        ax.grid(alpha=0.3)
    fig.suptitle("PIM coefficients by crash class (Brach et al. 2014); bar = median")
    fig.tight_layout()
    return fig
