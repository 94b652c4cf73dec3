"""The design sheet's graphs: outputs versus epsilon, and the least-squares cost map.

Computation and drawing are separate. :func:`sweep_epsilon` and :func:`cost_map` are pure
functions that return result objects (:class:`EpsilonSweep`, :class:`CostMap`); the
``plot_*`` functions take those objects (and a :class:`pim.FitResult`) and return a
matplotlib ``Figure`` without touching pyplot or any screen; :func:`write_plots` computes,
draws and writes the whole set atomically. matplotlib is imported inside the functions so
that ``import pim`` stays fast.

Figures (file stem: content):

- ``velocity_error``: least-squares cost vs epsilon (lowest over beta, and at fixed betas);
- ``impulse_ratio``: impulse ratio mu and the critical ratio mu0 vs epsilon;
- ``impulse_vehicle2``: magnitude of the impulse on vehicle 2 vs epsilon;
- ``pdof``: principal direction of force of each vehicle vs epsilon;
- ``energy_loss``: kinetic energy lost [%] vs epsilon;
- ``velocities``: post-impact velocity components and yaw rates vs epsilon, measured values
  as horizontal lines;
- ``cost_map``: contours of the cost over (epsilon, beta) with the optimum marked.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.fitting import FitResult
from ..analysis.residuals import has_measured_terms, residuals
from ..io.files import save_figure
from ..io.units import convert
from ..model.case import Case
from ..model.numbers import InputError
from ..model.result import Result
from ..model.solver import defaults, solve

__all__ = ["EpsilonSweep", "CostMap", "sweep_epsilon", "cost_map", "write_plots", "PLOTS",
           "plot_velocity_error", "plot_impulse_ratio", "plot_impulse_vehicle2", "plot_pdof",
           "plot_energy_loss", "plot_velocities", "plot_cost_map", "colour_limits",
           "save_figure"]


# ---------------------------------------------------------------------------------------------
# data (pure)
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class EpsilonSweep:
    """The outputs of a case over a range of epsilon, for a few values of beta.

    Attributes
    ----------
    case : Case
        The case swept.
    eps : ndarray (n,)
        Coefficients of restitution [-].
    beta : ndarray (m,)
        Values of beta, one curve each [-]; the first is the fitted (or chosen) one.
    result : Result
        :func:`pim.solve` over the grid, shape (m, n).
    residual_names : tuple of str
        Fitted terms (empty when nothing is measured).
    cost : ndarray (m, n) or None
        The fit's cost at each point: sum of squares [m^2/s^2], or the chi-square [-] with
        measured standard deviations (None when nothing is measured).
    profile_cost, profile_beta : ndarray (n,) or None
        Lowest cost over beta within the fit's beta bounds at each epsilon, and the beta
        where it occurs.
    """

    case: Case
    eps: np.ndarray
    beta: np.ndarray
    result: Result
    residual_names: tuple[str, ...] = ()
    cost: np.ndarray | None = None
    profile_cost: np.ndarray | None = None
    profile_beta: np.ndarray | None = None


def _default_betas(beta: float) -> np.ndarray:
    out = [float(beta)]
    for b in (1.0, 0.75, 0.5):
        if all(abs(b - x) > 0.02 for x in out):
            out.append(b)
    return np.array(out[:3])


def sweep_epsilon(case: Case, fit_result: FitResult | None = None, *, betas=None,
                  eps=None, n_profile_beta: int = 401) -> EpsilonSweep:
    """Solve ``case`` over a grid of epsilon for a few betas (one vectorised call).

    Parameters
    ----------
    case : Case
        A single case.
    fit_result : FitResult, optional
        Supplies the fitted beta (first curve), the fitted terms and the beta bounds of the
        cost profile. Without it the case's beta (else 1) is used and no cost is computed.
    betas : array_like, optional
        Betas of the curves [-]; default: the fitted beta, then 1, 0.75, 0.5 (distinct).
    eps : array_like, optional
        Epsilon grid [-]; default 201 points over the fit's eps bounds (else [0, 1]).
    n_profile_beta : int
        Points along beta for the lowest-cost profile.
    """
    if fit_result is not None:
        (e_lo, e_hi), (b_lo, b_hi) = fit_result.bounds
        names = fit_result.residual_names
        beta0 = fit_result.beta
    else:
        (e_lo, e_hi), (b_lo, b_hi) = (0.0, 1.0), (0.0, 1.0)
        names = ()
        beta0 = float(defaults(case, 0.0, None)[1])
    eps = np.linspace(e_lo, e_hi, 201) if eps is None else np.asarray(eps, dtype=float)
    betas = _default_betas(beta0) if betas is None else np.atleast_1d(np.asarray(betas, float))
    result = solve(case, eps[None, :], betas[:, None])
    cost = profile_cost = profile_beta = None
    if names:
        cost = np.sum(residuals(result, names, weighted=True) ** 2, axis=-1)
        if "beta" in fit_result.fixed:
            profile_cost, profile_beta = cost[0], np.full(eps.shape, beta0)
        else:
            grid = np.linspace(b_lo, b_hi, n_profile_beta)
            full = np.sum(residuals(solve(case, eps[None, :], grid[:, None]), names) ** 2, -1)
            full = np.where(np.isfinite(full), full, np.inf)
            k = np.argmin(full, axis=0)
            profile_cost = full[k, np.arange(eps.size)]
            profile_beta = grid[k]
    return EpsilonSweep(case=case, eps=eps, beta=betas, result=result, residual_names=names,
                        cost=cost, profile_cost=profile_cost, profile_beta=profile_beta)


@dataclass(frozen=True, eq=False)
class CostMap:
    """The least-squares cost on a fine (epsilon, beta) grid.

    Attributes
    ----------
    eps, beta : ndarray
        Grid axes [-]; beta may extend past the fit's upper bound to show what lies beyond.
    cost : ndarray (n_beta, n_eps)
        The fit's cost: sum of squares [m^2/s^2], or the chi-square [-] when the measured
        values carry standard deviations; NaN where q is singular.
    fit : FitResult
        The fit it belongs to.
    """

    eps: np.ndarray
    beta: np.ndarray
    cost: np.ndarray
    fit: FitResult


def cost_map(fit_result: FitResult, n: int = 161, beta_margin: float = 0.5) -> CostMap:
    """Evaluate the fit's cost on an n x n grid (one vectorised solve).

    Parameters
    ----------
    fit_result : FitResult
        Gives the case, fitted terms and bounds.
    n : int
        Grid points per axis.
    beta_margin : float
        Extend beta past the upper bound by this fraction of the beta range, so the map
        shows where the cost would go without the constraint.
    """
    (e_lo, e_hi), (b_lo, b_hi) = fit_result.bounds
    eps = np.linspace(e_lo, e_hi, n)
    beta = np.linspace(b_lo, b_hi + beta_margin * (b_hi - b_lo), n)
    res = solve(fit_result.case, eps[None, :], beta[:, None])
    cost = np.sum(residuals(res, fit_result.residual_names, weighted=True) ** 2, axis=-1)
    return CostMap(eps=eps, beta=beta, cost=np.where(np.isfinite(cost), cost, np.nan),
                   fit=fit_result)


# ---------------------------------------------------------------------------------------------
# drawing
# ---------------------------------------------------------------------------------------------

def _figure(size=(7.0, 4.6), **subplots):
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(**subplots) if subplots else fig.add_subplot()
    return fig, axes


def _factor(kind: str, units: str):
    value, unit = convert(1.0, kind, units)
    return float(value), unit


def _cost_axis(fit_result: FitResult, units: str) -> tuple[float, str]:
    """Display factor and axis label of the fit's cost: the chi-square [-] (unit-free, the
    same in every unit system) with standard deviations, else the sum of squared errors in
    the user's velocity unit squared."""
    if fit_result.chi_square:
        return 1.0, "chi-square Σ((model − measured)/σ)² [-]"
    f, unit = _factor("velocity", units)
    yaw = " and k·yaw-rate" if fit_result.include_yaw else ""
    return f * f, f"sum of squared velocity{yaw} errors [({unit})²]"


def _eps_axis(ax, fit_result: FitResult | None, label=True):
    ax.set_xlabel("coefficient of restitution ε [-]")
    ax.grid(True, alpha=0.3)
    if fit_result is not None and "eps" not in fit_result.fixed:
        ax.axvline(fit_result.eps, color="0.35", lw=1.0, ls=":",
                   label=f"fitted ε = {fit_result.eps:.3f}" if label else None)


def _beta_label(beta: float, fitted: bool) -> str:
    return f"β = {beta:.3g}" + (" (fit)" if fitted else "")


def _curves(ax, sweep: EpsilonSweep, values, fit_result, color="C0", label_prefix=""):
    """Draw one curve per beta: the first bold, the others thin and dashed."""
    styles = ["-", "--", "-.", ":"]
    for k, beta in enumerate(sweep.beta):
        ax.plot(sweep.eps, values[k], color=color, lw=2.2 if k == 0 else 1.0,
                ls=styles[k % len(styles)], alpha=1.0 if k == 0 else 0.8,
                label=label_prefix + _beta_label(beta, k == 0 and fit_result is not None))


def _title(fig, sweep_or_case, text):
    case = sweep_or_case if isinstance(sweep_or_case, Case) else sweep_or_case.case
    fig.suptitle(f"{case.name or 'case'}: {text}", fontsize=12)


def plot_velocity_error(sweep: EpsilonSweep, fit_result: FitResult, units: str = "si"):
    """Least-squares cost vs epsilon: lowest over beta, and at each swept beta."""
    if sweep.cost is None:
        raise InputError("the sweep has no cost: nothing was measured")
    f2, cost_label = _cost_axis(fit_result, units)
    fig, ax = _figure()
    ax.plot(sweep.eps, sweep.profile_cost * f2, color="k", lw=2.4,
            label="lowest over β" if "beta" not in fit_result.fixed else
            _beta_label(fit_result.beta, False) + " (fixed)")
    for k, beta in enumerate(sweep.beta):
        ax.plot(sweep.eps, sweep.cost[k] * f2, lw=1.0, ls=["--", "-.", ":"][k % 3],
                label=_beta_label(beta, k == 0))
    _eps_axis(ax, fit_result, label=False)
    bound = ", ".join(f"{p} on {s} bound" for p, s in fit_result.on_bound.items())
    ax.plot([fit_result.eps], [fit_result.cost * f2], "o", color="C3", ms=8, zorder=5,
            label=f"optimum ε = {fit_result.eps:.3f}, β = {fit_result.beta:.3f}"
                  + (f" ({bound})" if bound else ""))
    ax.set_ylabel(cost_label)
    finite = sweep.profile_cost[np.isfinite(sweep.profile_cost)] * f2
    if finite.size:
        ax.set_ylim(0, 1.15 * max(np.percentile(finite, 98), 3 * fit_result.cost * f2))
    ax.legend(fontsize=8)
    _title(fig, sweep, "least-squares error of the post-impact motion")
    return fig


def plot_impulse_ratio(sweep: EpsilonSweep, fit_result: FitResult | None = None):
    """Impulse ratio mu = beta mu0 and the critical ratio mu0 vs epsilon."""
    fig, ax = _figure()
    _curves(ax, sweep, sweep.result.mu, fit_result, label_prefix="μ, ")
    ax.plot(sweep.eps, sweep.result.mu0[0], color="k", lw=1.6, ls=(0, (4, 3)), zorder=4,
            label="critical μ0 (no sliding at C after impact)")
    _eps_axis(ax, fit_result)
    ax.set_ylabel("impulse ratio μ = Pt / Pn [-]")
    ax.legend(fontsize=8)
    _title(fig, sweep, "impulse ratio")
    return fig


def plot_impulse_vehicle2(sweep: EpsilonSweep, fit_result: FitResult | None = None,
                          units: str = "si"):
    """Magnitude of the impulse on vehicle 2 (= m2 |delta-V2|) vs epsilon."""
    f, unit = _factor("impulse", units)
    p = sweep.result.impulse
    fig, ax = _figure()
    _curves(ax, sweep, np.hypot(p[..., 0], p[..., 1]) * f, fit_result, color="C2")
    _eps_axis(ax, fit_result)
    ax.set_ylabel(f"impulse on vehicle 2, |P| [{unit}]")
    ax.legend(fontsize=8)
    _title(fig, sweep, "impulse on vehicle 2")
    return fig


def plot_pdof(sweep: EpsilonSweep, fit_result: FitResult | None = None):
    """PDOF of vehicles 1 and 2 [deg, clockwise from the heading] vs epsilon."""
    fig, axes = _figure(size=(10.0, 4.4), ncols=2)
    for ax, i, color in zip(axes, (1, 2), ("C0", "C1"), strict=True):
        pdof = np.degrees(np.unwrap(getattr(sweep.result, f"pdof{i}"), axis=-1))
        _curves(ax, sweep, pdof, fit_result, color=color)
        _eps_axis(ax, fit_result)
        ax.set_ylabel(f"PDOF{i} [deg clockwise from heading; 0 = frontal]")
        ax.set_title(f"vehicle {i}")
        ax.legend(fontsize=8)
    _title(fig, sweep, "principal direction of force")
    return fig


def plot_energy_loss(sweep: EpsilonSweep, fit_result: FitResult | None = None):
    """Kinetic energy lost in the impact [% of the energy before] vs epsilon."""
    fig, ax = _figure()
    _curves(ax, sweep, sweep.result.energy_loss_percent, fit_result, color="C4")
    _eps_axis(ax, fit_result)
    ax.set_ylabel("kinetic energy lost [% of initial]")
    ax.legend(fontsize=8)
    _title(fig, sweep, "kinetic energy loss")
    return fig


def plot_velocities(sweep: EpsilonSweep, fit_result: FitResult | None = None,
                    units: str = "si"):
    """Post-impact Vx, Vy and yaw rate of both vehicles vs epsilon, with measured values.

    Three rows (velocity x, velocity y, yaw rate) of two panels (vehicle 1, vehicle 2), 9.6
    inches wide: shown at page width (about 1150 px at 120 dpi), its text keeps the size it
    was drawn at.
    """
    fv, uv = _factor("velocity", units)
    fw, uw = _factor("angular_velocity", units)
    fig, axes = _figure(size=(9.6, 8.8), nrows=3, ncols=2, sharex=True)
    m = sweep.case.measured
    r = sweep.result
    for col, i in enumerate((1, 2)):
        vel = getattr(r, f"velocity{i}")
        meas_v = None if m is None else getattr(m, f"velocity{i}")
        meas_w = None if m is None else getattr(m, f"yaw_rate{i}")
        panels = [(vel[..., 0] * fv, f"V{i}x [{uv}]", None if meas_v is None else meas_v[0] * fv),
                  (vel[..., 1] * fv, f"V{i}y [{uv}]", None if meas_v is None else meas_v[1] * fv),
                  (getattr(r, f"yaw_rate{i}") * fw, f"Ω{i} [{uw}]",
                   None if meas_w is None else meas_w * fw)]
        for row, (values, label, measured) in enumerate(panels):
            ax = axes[row, col]
            _curves(ax, sweep, values, fit_result, color=f"C{col}")
            if measured is not None:
                ax.axhline(measured, color="C3", lw=1.6, ls="--", label="measured")
            _eps_axis(ax, fit_result)
            if row < 2:
                ax.set_xlabel("")
            ax.set_ylabel(label)
            ax.set_title(f"vehicle {i}: " + ["velocity x", "velocity y", "yaw rate"][row],
                         fontsize=10)
    axes[0, 0].legend(fontsize=8)
    _title(fig, sweep, "post-impact motion (model curves, measured lines)")
    return fig


def colour_limits(cost, span: float = 1e6, top: float = 99.0) -> tuple[float, float]:
    """Limits of a logarithmic colour scale for a cost map, lower strictly below upper.

    The upper limit is the ``top`` percentile of the positive finite values, so that a few
    huge values near a singular q (the cost reaches 1e15 where A - mu B vanishes) do not
    wash out the map; the lower limit is their smallest value, but at most ``span`` below
    the upper one (a log scale over more decades shows nothing). With no positive finite
    value (a cost of zero everywhere) the scale is [1, 10].

    Parameters
    ----------
    cost : array_like
        The cost at each grid point [any unit]; NaN where q is singular.
    span : float
        Largest ratio of upper to lower limit [-].
    top : float
        Percentile of the values at the upper limit [%].

    Returns
    -------
    (float, float)
        Lower and upper limit, 0 < lower < upper.
    """
    cost = np.asarray(cost, dtype=float)
    finite = cost[np.isfinite(cost) & (cost > 0)]
    if not finite.size:
        return 1.0, 10.0
    hi = float(np.percentile(finite, top))
    lo = max(float(finite.min()), hi / span)
    return lo, max(hi, 1.01 * lo)


def plot_cost_map(cmap: CostMap, units: str = "si"):
    """Filled contours of the cost over (epsilon, beta), optimum and bounds marked."""
    from matplotlib.colors import LogNorm
    from matplotlib.ticker import FormatStrFormatter, LogLocator

    fit_result = cmap.fit
    f2, cost_label = _cost_axis(fit_result, units)
    cost = cmap.cost * f2
    fig, ax = _figure(size=(7.5, 5.6))
    lo, hi = colour_limits(cost)
    levels = np.geomspace(lo, hi, 25)
    shown = np.clip(np.where(np.isfinite(cost), cost, hi), lo, hi)
    filled = ax.contourf(cmap.eps, cmap.beta, shown, levels=levels, norm=LogNorm(lo, hi),
                         cmap="viridis_r")
    filled.set_rasterized(True)  # keeps the SVG small and quick to write
    ax.contour(cmap.eps, cmap.beta, shown, levels=levels[::3], colors="w", linewidths=0.5,
               alpha=0.6)
    bar = fig.colorbar(filled, ax=ax)
    bar.ax.yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 3.0, 5.0, 7.0)))
    bar.ax.yaxis.set_major_formatter(FormatStrFormatter("%.3g"))
    bar.ax.yaxis.set_minor_formatter(FormatStrFormatter(""))
    bar.set_label(cost_label)
    (e_lo, e_hi), (b_lo, b_hi) = fit_result.bounds
    if cmap.beta[-1] > b_hi:
        ax.axhspan(b_hi, cmap.beta[-1], color="w", alpha=0.35, lw=0)
        ax.axhline(b_hi, color="k", lw=1.4, ls="--")
        ax.text(e_lo + 0.02 * (e_hi - e_lo), b_hi + 0.02 * (cmap.beta[-1] - b_lo),
                f"β > {b_hi:g}: outside the fit bounds (|μ| > |μ0| if β > 1)", fontsize=8)
        outside = np.where(cmap.beta[:, None] > b_hi, cmap.cost, np.nan)
        if np.isfinite(outside).any() and np.nanmin(outside) < fit_result.cost:
            i, j = np.unravel_index(np.nanargmin(outside), outside.shape)
            if 0 < i < cmap.beta.size - 1 and 0 < j < cmap.eps.size - 1:
                ax.plot(cmap.eps[j], cmap.beta[i], "P", color="w", mec="k", ms=10,
                        label=f"unconstrained minimum (ε ≈ {cmap.eps[j]:.2f}, "
                              f"β ≈ {cmap.beta[i]:.2f}), excluded")
    for e, b, _ in fit_result.minima[1:]:
        ax.plot(e, b, "x", color="w", ms=8, mew=2)
    ax.plot(fit_result.eps, fit_result.beta, "*", color="C3", ms=16, mec="k",
            label=f"optimum ε = {fit_result.eps:.3f}, β = {fit_result.beta:.3f}")
    ax.set_xlabel("coefficient of restitution ε [-]")
    ax.set_ylabel("β = μ / μ0 [-]")
    ax.legend(loc="lower right", fontsize=8)
    _title(fig, fit_result.case, "least-squares cost over (ε, β)")
    return fig


# ---------------------------------------------------------------------------------------------
# files
# ---------------------------------------------------------------------------------------------

#: File stems of the plot set, in report order.
PLOTS = ("velocity_error", "velocities", "cost_map", "impulse_ratio", "impulse_vehicle2",
         "pdof", "energy_loss")


def write_plots(case: Case, fit_result: FitResult | None, out_dir, formats=("png", "svg"),
                units: str = "si") -> list[Path]:
    """Compute and write the design sheet's set of plots.

    Parameters
    ----------
    case : Case
        A single case.
    fit_result : FitResult or None
        Its fit (:func:`pim.fit`). With None (nothing measured) the fit-related plots
        (``velocity_error``, ``cost_map``) are skipped and the curves use the case's beta.
    out_dir : path
        Directory to write to (created if missing).
    formats : sequence of str
        File formats, e.g. ("png", "svg").
    units : {"si", "us"} or pim.io.units.DisplayUnits
        Display units of the axes.

    Returns
    -------
    list of Path
        The files written, in the order of :data:`PLOTS` then ``formats``.
    """
    formats = tuple(formats)
    for fmt in formats:
        if fmt not in ("png", "svg", "pdf"):
            raise InputError(f"formats must be among png, svg, pdf; got {fmt!r}")
    if fit_result is None and has_measured_terms(case):
        raise InputError("the case has measured values: pass its fit (pim.fit(case))")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    sweep = sweep_epsilon(case, fit_result)
    makers = {
        "velocity_error": lambda: plot_velocity_error(sweep, fit_result, units),
        "velocities": lambda: plot_velocities(sweep, fit_result, units),
        "cost_map": lambda: plot_cost_map(cost_map(fit_result), units),
        "impulse_ratio": lambda: plot_impulse_ratio(sweep, fit_result),
        "impulse_vehicle2": lambda: plot_impulse_vehicle2(sweep, fit_result, units),
        "pdof": lambda: plot_pdof(sweep, fit_result),
        "energy_loss": lambda: plot_energy_loss(sweep, fit_result),
    }
    written = []
    for stem in PLOTS:
        if fit_result is None and stem in ("velocity_error", "cost_map"):
            continue
        fig = makers[stem]()
        for fmt in formats:
            written.append(save_figure(fig, out / f"{stem}.{fmt}"))
    return written
