"""Least-squares fit of (epsilon, beta) to measured post-impact motion (the sheet's optimum).

The cost is the design sheet's sum of squared post-impact velocity errors,

    S(eps, beta) = sum_i (V_i(eps, beta) - V_i,measured)^2            [m^2/s^2],

over the measured components of V1 and V2 (x and y). With ``include_yaw`` the yaw rates
join as velocities, each weighted by its vehicle's radius of gyration k_i = sqrt(I_i / m_i):
the residual is k_i (Omega_i - Omega_i,measured) [m/s], the speed that spin gives a point at
distance k_i from the CG. Only measured quantities enter; a case with nothing measured is an
error.

Constraints as in the sheet: eps >= 0 (and <= 1, the solver's range) and beta <= 1, with
beta >= 0 unless the caller widens the bounds. The result records which bound it sits on.

Global search: the model is closed-form and vectorised, so the bounded box is first
evaluated on a dense grid in one solver call (41 x 41 by default); the best few local
minima of the grid are then refined by a bounded quasi-Newton method (L-BFGS-B) using the
closed-form gradient 2 J^T r (J from :func:`pim.analysis.derivatives.motion_derivatives`), and the
lowest refined minimum wins. Inside the default box the cost is convex in the impulse and
the map (eps, beta) -> impulse is one-to-one, so there is one basin; a second basin appears
when the box contains the singular beta where A - mu B = 0 (q infinite), which a local
search from the sheet's guess cannot cross.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..model.case import Case
from ..model.numbers import InputError, check_counts, check_numbers
from ..model.result import Result
from ..model.solver import solve
from .free_fit import FREE_KEYS, Identifiability, check_free, fit_free
from .residuals import measured_terms, measured_weights, residuals, residuals_and_jacobian

__all__ = ["fit", "FitResult", "FREE_KEYS", "Landscape", "DEFAULT_BOUNDS", "DEFAULT_GRID",
           "MAX_STARTS"]

#: Default search box ((eps_min, eps_max), (beta_min, beta_max)) [-], the sheet's constraints.
DEFAULT_BOUNDS = ((0.0, 1.0), (0.0, 1.0))
#: Default grid of the coarse search (points along eps, points along beta).
DEFAULT_GRID = (41, 41)
#: Number of grid minima refined by the local search.
MAX_STARTS = 5


@dataclass(frozen=True, eq=False)
class Landscape:
    """The cost evaluated on the search grid.

    Attributes
    ----------
    eps : ndarray (n_eps,)
        Grid of epsilon [-] (one value when epsilon is held fixed).
    beta : ndarray (n_beta,)
        Grid of beta [-] (one value when beta is held fixed).
    cost : ndarray (n_eps, n_beta)
        Sum of squared residuals [m^2/s^2]; inf where q is singular.
    """

    eps: np.ndarray
    beta: np.ndarray
    cost: np.ndarray

    def profile(self) -> np.ndarray:
        """Lowest cost over beta at each grid epsilon [m^2/s^2], shape (n_eps,)."""
        return self.cost.min(axis=1)


@dataclass(frozen=True, eq=False)
class FitResult:
    """Outcome of :func:`fit`.

    Attributes
    ----------
    case : Case
        The fitted case.
    eps, beta : float
        Optimum coefficient of restitution and fraction of mu0 [-].
    cost : float
        Sum of squared residuals at the optimum [m^2/s^2]; with measured standard
        deviations the chi-square sum of (residual / sigma)^2 [-] (see ``weights``).
    residuals : ndarray
        Residuals at the optimum [m/s] (model minus measured; yaw terms times k_i).
    residual_names : tuple of str
        Which measured term each residual is.
    include_yaw : bool
        Whether the yaw rates were fitted.
    bounds : ((float, float), (float, float))
        The search box ((eps_min, eps_max), (beta_min, beta_max)).
    fixed : tuple of str
        Parameters held fixed ("eps" and/or "beta"); they are not fitted.
    on_bound : dict
        Parameter -> "lower" or "upper" for every fitted parameter that sits on a bound
        (empty when the optimum is interior).
    gradient : ndarray (2,)
        d cost / d (eps, beta) at the optimum [m^2/s^2]: nonzero on an active bound, where
        its sign shows the direction in which the cost would keep falling.
    landscape : Landscape
        The coarse grid the global search evaluated.
    minima : tuple of (eps, beta, cost)
        Every refined local minimum, best first (more than one means several basins).
    nfev : int
        Number of solver calls of the local refinement (the grid counts as one).
    """

    case: Case
    eps: float
    beta: float
    cost: float
    residuals: np.ndarray
    residual_names: tuple[str, ...]
    include_yaw: bool
    bounds: tuple
    fixed: tuple[str, ...]
    on_bound: dict
    gradient: np.ndarray
    landscape: Landscape = field(repr=False)
    minima: tuple = field(repr=False)
    nfev: int = 0
    #: Every fitted parameter by its dotted key -> value [SI] ("impact.restitution",
    #: "impact.beta" when fitted, and the ``free`` keys).
    values: dict = field(default_factory=dict)
    #: Rank, singular values, correlations, families of exact fits, under-determination
    #: (None for a plain (eps, beta) fit without ``free``).
    identifiability: Identifiability | None = field(default=None, repr=False)
    #: Free-parameter minima: (values dict, cost), best first.
    minima_values: tuple = field(default=(), repr=False)
    #: Residual weights 1/sigma (``[measured]`` standard deviations), or None (unweighted).
    #: With weights, ``cost`` is the chi-square sum (w r)^2 [-]; ``residuals`` stay in m/s.
    weights: np.ndarray | None = field(default=None, repr=False)

    @property
    def fitted_case(self) -> Case:
        """The case with the fitted values put in (eps and beta on its impact)."""
        return replace(self.case, impact=replace(self.case.impact, restitution=self.eps,
                                                 beta=self.beta))

    @property
    def residual_table(self) -> list[dict]:
        """Per measured quantity: name, measured, fitted, residual [SI]."""
        res, m = self.result, self.case.measured
        rows = []
        for name, r in zip(self.residual_names, self.residuals, strict=True):
            if name.startswith("velocity"):
                i, axis = int(name[8]), "xy".index(name[-1])
                measured = float(getattr(m, f"velocity{i}")[axis])
                fitted = float(np.asarray(getattr(res, f"velocity{i}")).reshape(-1)[axis])
                unit = "m/s"
            else:
                i = int(name[-1])
                measured = float(getattr(m, f"yaw_rate{i}"))
                fitted = float(np.asarray(getattr(res, f"yaw_rate{i}")).reshape(()))
                unit = "rad/s"
            rows.append({"name": name, "measured": measured, "fitted": fitted,
                         "error": fitted - measured, "unit": unit, "residual": float(r)})
        return rows

    @property
    def rms(self) -> float:
        """Root-mean-square residual [m/s]."""
        return float(np.sqrt(np.mean(np.square(self.residuals))))

    @cached_property
    def result(self) -> Result:
        """The solve at the optimum."""
        return solve(self.case, self.eps, self.beta)

    def to_dict(self) -> dict:
        """JSON-ready summary (SI units)."""
        return {
            "case": self.case.name, "eps": self.eps, "beta": self.beta, "cost": self.cost,
            "cost_unit": "m^2/s^2", "rms": self.rms, "rms_unit": "m/s",
            "residuals": dict(zip(self.residual_names, map(float, self.residuals), strict=True)),
            "include_yaw": self.include_yaw, "bounds": {"eps": list(self.bounds[0]),
                                                        "beta": list(self.bounds[1])},
            "fixed": list(self.fixed), "on_bound": dict(self.on_bound),
            "gradient": {"eps": float(self.gradient[0]), "beta": float(self.gradient[1])},
            "minima": [{"eps": e, "beta": b, "cost": c} for e, b, c in self.minima],
            "admissible": bool(self.result.admissible), "problems": self.result.problems(),
        }


def _check_bounds(bounds) -> tuple:
    try:
        (e_lo, e_hi), (b_lo, b_hi) = bounds
        e_lo, e_hi, b_lo, b_hi = map(float, (e_lo, e_hi, b_lo, b_hi))
    except (TypeError, ValueError):
        raise InputError("bounds must be ((eps_min, eps_max), (beta_min, beta_max))") from None
    if not (0.0 <= e_lo < e_hi <= 1.0):
        raise InputError(f"bounds on eps must satisfy 0 <= eps_min < eps_max <= 1, "
                         f"got ({e_lo}, {e_hi})")
    if not (np.isfinite(b_lo) and np.isfinite(b_hi) and b_lo < b_hi):
        raise InputError(f"bounds on beta must be finite with beta_min < beta_max, "
                         f"got ({b_lo}, {b_hi})")
    return (e_lo, e_hi), (b_lo, b_hi)


def _grid_minima(cost: np.ndarray) -> list[tuple[int, int]]:
    """Indices of grid points not higher than any of their 8 neighbours, best first."""
    padded = np.pad(cost, 1, constant_values=np.inf)
    n, m = cost.shape
    is_min = np.isfinite(cost)
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            if di or dj:
                is_min &= cost <= padded[1 + di:1 + di + n, 1 + dj:1 + dj + m]
    idx = np.argwhere(is_min)
    order = np.argsort(cost[is_min], kind="stable")
    chosen: list[tuple[int, int]] = []
    for i, j in idx[order]:
        # plateaus: keep one point per cluster of adjacent minima
        if all(abs(i - a) > 1 or abs(j - b) > 1 for a, b in chosen):
            chosen.append((int(i), int(j)))
    return chosen


def fit(case: Case, *, include_yaw: bool = False, bounds=DEFAULT_BOUNDS, eps=None, beta=None,
        grid=DEFAULT_GRID, max_starts: int = MAX_STARTS, free=None,
        samples: int = 256, seed: int = 0) -> FitResult:
    """Least-squares (epsilon, beta) that best reproduce the measured post-impact motion.

    Parameters
    ----------
    case : Case
        A single (scalar) case with ``case.measured`` set.
    include_yaw : bool
        Also fit the measured yaw rates, weighted by the radius of gyration k_i [m].
    bounds : ((float, float), (float, float))
        Search box ((eps_min, eps_max), (beta_min, beta_max)); default ((0, 1), (0, 1)),
        the sheet's eps >= 0, beta <= 1 with beta >= 0. eps must stay within [0, 1]; beta
        may be widened (values outside [0, 1] are flagged by ``result.problems()``).
    eps, beta : float, optional
        Hold that parameter fixed at the given value and fit only the other one.
    grid : (int, int)
        Points of the coarse search along eps and beta.
    max_starts : int
        How many of the best grid minima are refined locally.
    free : dict, optional
        Further free parameters: dotted key -> (low, high) bounds [SI]
        (:data:`pim.analysis.free_fit.FREE_KEYS`: the scalar inputs of ``[uncertainty]``,
        e.g. ``impact.normal_angle``, ``impact.point_x``, ``vehicle1.yaw_rate``, plus
        ``vehicle{1,2}.radius_of_gyration`` and ``vehicle{1,2}.speed``;
        ``impact.restitution`` / ``impact.beta`` here replace ``bounds``). The coarse search
        is then a Sobol sample of ``samples`` points (``seed``), refined by bounded least
        squares; ``identifiability`` reports rank, correlations and families of exact fits.
    samples, seed : int
        Size and seed of the coarse Sobol sample (``free`` only).

    Returns
    -------
    FitResult

    Raises
    ------
    ValueError
        Nothing measured, a batched case, bad bounds, both parameters fixed, or no approach.
    """
    check_counts(max_starts=max_starts, samples=samples)
    check_numbers(eps=eps, beta=beta)
    if np.size(case.vehicle1.mass) != 1 or np.shape(case.impact.point) != (2,):
        raise InputError("fit needs a single case, not a batch of cases")
    names = measured_terms(case, include_yaw)
    (e_lo, e_hi), (b_lo, b_hi) = _check_bounds(bounds)
    if eps is not None and beta is not None and not free:
        raise InputError("eps and beta are both fixed: nothing to fit (fix at most one, or "
                         "free other inputs)")
    fixed = tuple(n for n, v in (("eps", eps), ("beta", beta)) if v is not None)
    if eps is not None:
        eps = float(eps)
        if not 0.0 <= eps <= 1.0:
            raise InputError(f"eps (fixed) must be in [0, 1], got {eps}")
    if beta is not None:
        beta = float(beta)
        if not np.isfinite(beta):
            raise InputError(f"beta (fixed) must be a finite number, got {beta}")
    if free:
        return _fit_free(case, names, check_free(free), include_yaw, eps, beta, fixed,
                         ((e_lo, e_hi), (b_lo, b_hi)), samples, max_starts, seed)
    n_eps, n_beta = (int(g) for g in grid)
    if n_eps < 3 or n_beta < 3:
        raise InputError(f"grid must have at least 3 points per axis, got {grid}")

    # ---- coarse global search: one vectorised solve over the grid -----------------------
    eps_grid = np.array([eps]) if eps is not None else np.linspace(e_lo, e_hi, n_eps)
    beta_grid = np.array([beta]) if beta is not None else np.linspace(b_lo, b_hi, n_beta)
    grid_result = solve(case, eps_grid[:, None], beta_grid[None, :])
    if not np.any(grid_result.approaching):
        raise InputError(f"case {case.name or '(unnamed)'}: the vehicles do not approach at C "
                         "(u_n >= 0): there is no impact to fit")
    weights = measured_weights(case, names)
    wv = 1.0 if weights is None else weights
    cost = np.sum((residuals(grid_result, names) * wv) ** 2, axis=-1)
    cost = np.where(np.isfinite(cost), cost, np.inf)
    landscape = Landscape(eps=eps_grid, beta=beta_grid, cost=cost)
    starts = _grid_minima(cost)[:max(1, int(max_starts))]
    if not starts:
        raise InputError("the cost is not finite anywhere in the search box")

    # ---- local refinement of the best grid minima ----------------------------------------
    from scipy.optimize import minimize

    free = [n not in fixed for n in ("eps", "beta")]
    full_bounds = ((e_lo, e_hi), (b_lo, b_hi))
    box = [b for b, f in zip(full_bounds, free, strict=True) if f]
    nfev = 0

    def full(x):
        theta = [eps, beta]
        k = 0
        for i, f in enumerate(free):
            if f:
                theta[i] = x[k]
                k += 1
        return theta

    def cost_and_grad(x):
        nonlocal nfev
        nfev += 1
        e, b = full(x)
        res = solve(case, e, b)
        r, j = residuals_and_jacobian(res, names)
        if weights is not None:
            r, j = r * weights, j * weights[:, None]
        c = float(r @ r)
        if not np.isfinite(c):
            return 1e300, np.zeros(len(x))
        g = 2.0 * (r @ j)
        return c, g[free]

    minima = []
    for i, j in starts:
        x0 = [v for v, f in zip((eps_grid[i], beta_grid[j]), free, strict=True) if f]
        out = minimize(cost_and_grad, x0, jac=True, method="L-BFGS-B", bounds=box,
                       options={"ftol": 1e-15, "gtol": 1e-11, "maxiter": 200})
        e, b = full(np.clip(out.x, [lo for lo, _ in box], [hi for _, hi in box]))
        if all(abs(e - a) + abs(b - c) > 1e-6 for a, c, _ in minima):
            minima.append((float(e), float(b), float(out.fun)))
    minima.sort(key=lambda m: m[2])
    e_opt, b_opt, _ = minima[0]

    best = solve(case, e_opt, b_opt)
    r, j = residuals_and_jacobian(best, names)
    rw, jw = (r, j) if weights is None else (r * weights, j * weights[:, None])
    gradient = 2.0 * (rw @ jw)
    on_bound = {}
    for name, value, (lo, hi), f in zip(("eps", "beta"), (e_opt, b_opt), full_bounds, free,
                                        strict=True):
        tol = 1e-9 * (hi - lo)
        if f and value <= lo + tol:
            on_bound[name] = "lower"
        elif f and value >= hi - tol:
            on_bound[name] = "upper"
    return FitResult(case=case, eps=e_opt, beta=b_opt, cost=float(rw @ rw), residuals=r,
                     residual_names=names, include_yaw=bool(include_yaw), bounds=full_bounds,
                     fixed=fixed, on_bound=on_bound, gradient=gradient, landscape=landscape,
                     minima=tuple(minima), nfev=nfev, weights=weights)


def _fit_free(case, names, free, include_yaw, eps, beta, fixed, bounds, samples, max_starts,
              seed) -> FitResult:
    free = dict(free)
    box = list(bounds)
    if "impact.restitution" in free:
        box[0] = free["impact.restitution"]
    if "impact.beta" in free:
        box[1] = free["impact.beta"]
    out = fit_free(case, free, names, eps, beta, bounds[0], bounds[1],
                   samples=samples, max_starts=max_starts, seed=seed)
    base = out.case
    fitted = solve(base, out.eps, out.beta)
    r = residuals(fitted, names)
    w = measured_weights(base, names)
    minima = tuple((v.get("impact.restitution", out.eps), v.get("impact.beta", out.beta), c)
                   for v, c in out.minima)
    landscape = Landscape(eps=np.array([out.eps]), beta=np.array([out.beta]),
                          cost=np.array([[out.cost]]))
    rw = r if w is None else r * w
    return FitResult(case=base, eps=out.eps, beta=out.beta, cost=float(rw @ rw), residuals=r,
                     residual_names=names, include_yaw=bool(include_yaw), bounds=tuple(box),
                     fixed=fixed, on_bound=out.on_bound, gradient=out.gradient,
                     landscape=landscape, minima=minima, nfev=out.nfev, values=out.values,
                     identifiability=out.identifiability, minima_values=out.minima,
                     weights=w)
