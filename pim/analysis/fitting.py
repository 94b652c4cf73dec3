"""Least-squares fit of (epsilon, beta), and of any other inputs, to measured post-impact motion.

The cost is the design sheet's sum of squared post-impact velocity errors,

    S(eps, beta) = sum_i (V_i(eps, beta) - V_i,measured)^2            [m^2/s^2],

over the measured components of V1 and V2 (x and y). The yaw rates join as velocities, each
weighted by its vehicle's radius of gyration k_i = sqrt(I_i / m_i): the residual is
k_i (Omega_i - Omega_i,measured) [m/s], the speed that spin gives a point at distance k_i
from the CG; by default a measured yaw rate enters when it has a standard deviation (every
measured quantity with a sigma is fitted), ``include_yaw=True`` fits every measured one and
``include_yaw=False`` none. Only measured quantities enter; a case with nothing measured is
an error. With the ``[measured]`` standard deviations each residual is divided by its sigma:
the cost is then the chi-square [-], and the result carries its degrees of freedom and
p-value (:class:`pim.analysis.residuals.GoodnessOfFit`).

Standard errors and correlations of the fitted parameters come from the Jacobian J of the
residuals at the optimum (:func:`parameter_errors`): with sigmas, C = (J^T W J)^-1, W the
inverse variances, the sigmas taken as stated (not rescaled by chi-square / dof: the
chi-square test says whether they hold); without sigmas, C = s^2 (J^T J)^-1 with the residual
variance s^2 = S / (m - n) of m measured values and n parameters (none when m <= n). A
parameter on a bound keeps its linearised standard error, flagged: its interval is one-sided.

Constraints as in the sheet: eps >= 0 (and <= 1, the solver's range) and beta <= 1, with
beta >= 0 unless the caller widens the bounds. The result records which bound it sits on.

One engine (:func:`pim.analysis.free_fit.fit_free`) for every fit: (eps, beta) is the
two-key case of the free fit. A scrambled Sobol sample of the bounded box is evaluated in one
vectorised call of the formula; the best few samples are refined together by a bounded
Levenberg-Marquardt iteration (:mod:`pim.analysis.least_squares_batch`) on exact derivatives
(dual numbers through the one formula, :mod:`pim.model.dual`), and the lowest minimum wins.
Inside the default box the cost is convex in the impulse and the map (eps, beta) -> impulse
is one-to-one, so there is one basin; a second basin appears when the box contains the
singular beta where A - mu B = 0 (q infinite), which a local search from the sheet's guess
cannot cross.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..model.case import BETA_RANGE_TEXT, Case, checked_case
from ..model.display import convert, display_units
from ..model.evidence_terms import as_residual_terms, split_terms
from ..model.impact_laws import check_contact_friction, law_of
from ..model.law import solve as solve_under_law
from ..model.motion import Term
from ..model.notebook import Notebook, Table, short
from ..model.numbers import InputError, check_counts, check_numbers, checked_count
from ..model.quantities import OUTPUTS
from ..model.result import Result
from ..model.solver import solve
from .free_fit import (
    FREE_KEYS,
    MERGE,
    FreeFit,
    Identifiability,
    check_free,
    fit_free,
    free_residuals,
    identifiability,
    variance_shares,
)
from .free_inputs import MU_C_BOUNDS, case_state, free_kind, free_label, friction_floor
from .residuals import (
    GoodnessOfFit,
    contradiction,
    goodness_of_fit,
    measured_terms,
    measured_value,
    measured_weights,
    model_value,
    residual_terms,
)

__all__ = ["fit", "FitResult", "parameter_errors", "FREE_KEYS", "DEFAULT_BOUNDS",
           "DEFAULT_GRID", "MAX_STARTS", "SAMPLES", "SHORT_NAMES"]

#: Default search box ((eps_min, eps_max), (beta_min, beta_max)) [-], the sheet's constraints.
DEFAULT_BOUNDS = ((0.0, 1.0), (0.0, 1.0))
#: Former grid of the coarse search; kept so that ``grid=`` still validates (see :func:`fit`).
DEFAULT_GRID = (41, 41)
#: Number of coarse-search minima refined by the local search.
MAX_STARTS = 5
#: Default size of the coarse Sobol sample.
SAMPLES = 256
#: The short names of restitution and beta in ``on_bound``, ``fixed`` and messages.
SHORT_NAMES = {"impact.restitution": "eps", "impact.beta": "beta", "impact.k": "k",
               "impact.mu_c": "mu_c"}


@dataclass(frozen=True, eq=False)
class FitResult(Notebook):
    """Outcome of :func:`fit`.

    In a notebook it shows as a table in the case's units (:meth:`display_table`: each fitted
    parameter with its standard error, each measured quantity against the fit);
    :meth:`to_dict` is its JSON summary in SI, ``to_frame()`` the table's numbers (pandas).

    Attributes
    ----------
    case : Case
        The case fitted, with the fitted ``free`` inputs put in (eps and beta are the
        fields below; :attr:`result` solves at them).
    eps, beta : float
        Optimum (or fixed) coefficient of restitution and fraction of mu0 [-].
    cost : float
        Sum of squared residuals at the optimum [m^2/s^2]; with measured standard
        deviations the chi-square sum of (residual / sigma)^2 [-] (see ``weights``).
    residuals : ndarray
        Residuals at the optimum [m/s] (model minus measured; yaw terms times k_i).
    residual_names : tuple of str
        Which measured term each residual is (the names of ``terms``).
    include_yaw : bool
        Whether any measured yaw rate was fitted.
    bounds : ((float, float), (float, float))
        The search box of (eps, beta); of (k, mu_c) under "kudlich-slibar".
    fixed : tuple of str
        Parameters held fixed ("eps" and/or "beta"); they are not fitted.
    on_bound : dict
        Parameter ("eps", "beta" or a ``free`` key) -> "lower" or "upper" for every fitted
        parameter that sits on a bound (empty when the optimum is interior).
    gradient : ndarray (2,)
        d cost / d (eps, beta) at the optimum (0 for a fixed one): nonzero on an active
        bound, where its sign shows the direction in which the cost would keep falling.
    minima : tuple of (eps, beta, cost)
        Every refined local minimum, best first (more than one means several basins);
        (k, mu_c, cost) under "kudlich-slibar".
    nfev : int
        Number of evaluations of the residuals in the local refinement (each over every
        start still running; the coarse sample counts as one).
    values : dict
        Every fitted parameter by its dotted key -> value [SI], on every path:
        ``impact.restitution`` and ``impact.beta`` unless fixed, and the ``free`` keys.
    identifiability : Identifiability
        Rank, singular values, correlations, families of exact fits, under-determination.
    minima_values : tuple
        Every refined local minimum as (values dict of the fitted keys, cost), best first.
    weights : ndarray or None
        Residual weights 1/sigma (``[measured]`` standard deviations), or None (unweighted).
        With weights, ``cost`` is the chi-square sum (w r)^2 [-]; ``residuals`` stay in m/s.
    terms : tuple of Term
        The residual terms, typed.
    goodness : GoodnessOfFit or None
        Chi-square, degrees of freedom and p-value; None without standard deviations.
    law : str
        The impact law fitted under ("brach", "brach-capped" or "kudlich-slibar"). Under
        "kudlich-slibar" ``eps`` is its restitution k and ``beta`` the PIM beta with the
        same answer (docs/impact-laws.md).
    contact_friction : float or None
        mu_c (fitted or fixed) of "kudlich-slibar" and "brach-capped", else None.
    lower_bounds : dict
        Key -> value of the parameters that only have a lower bound (``impact.mu_c`` where
        the contact does not reach it: any mu_c >= the value gives the same answer; the
        value stands in ``values``).
    standard_errors : dict
        Fitted key -> its standard error [SI] (:func:`parameter_errors`: (J^T W J)^-1 with
        the stated sigmas, else s^2 (J^T J)^-1 from the residual scatter); empty when the data
        do not decide the parameters or leave no scatter (as many values as parameters). A
        parameter with only a lower bound (``lower_bounds``) has none.
    correlation : dict
        (key a, key b) -> the correlation of the two fitted parameters [-], from the same
        covariance as ``standard_errors`` (empty where those are).
    error_basis : str
        How the standard errors were found, or why there are none, in words.
    left_out : tuple of str
        Measured quantities not fitted (a yaw rate without a sigma, by default).
    evidence_shares : dict
        Fitted key -> {evidence group: share of its variance [-]}
        (:func:`pim.analysis.free_fit.variance_shares`): which evidence drove it.
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
    minima: tuple = field(repr=False)
    nfev: int = 0
    values: dict = field(default_factory=dict)
    identifiability: Identifiability | None = field(default=None, repr=False)
    minima_values: tuple = field(default=(), repr=False)
    weights: np.ndarray | None = field(default=None, repr=False)
    terms: tuple[Term, ...] = field(default=(), repr=False)
    goodness: GoodnessOfFit | None = field(default=None, repr=False)
    law: str = "brach"
    contact_friction: float | None = None
    lower_bounds: dict = field(default_factory=dict)
    standard_errors: dict = field(default_factory=dict, repr=False)
    evidence_shares: dict = field(default_factory=dict, repr=False)
    error_basis: str = ""
    left_out: tuple = ()
    correlation: dict = field(default_factory=dict, repr=False)

    @property
    def residual_table(self) -> list[dict]:
        """Per measured quantity: name, measured, fitted, error, unit, residual [SI]."""
        rows = []
        for term, r in zip(self.terms, self.residuals, strict=True):
            measured = measured_value(self.case.measured, term)
            fitted = float(model_value(self.result, term))
            rows.append({"name": term.name, "measured": measured, "fitted": fitted,
                         "error": fitted - measured, "unit": term.unit, "residual": float(r),
                         "kind": term.kind if isinstance(term, Term) else term.kind_of_unit})
        return rows

    @property
    def rms(self) -> float:
        """Root-mean-square residual [m/s] of the terms in m/s (velocities, yaw rates times
        k_i, recorded delta-V and speeds; energies left out)."""
        r = np.array([x for t, x in zip(self.terms, self.residuals, strict=True)
                      if t.unit != "J"]) if self.terms else np.asarray(self.residuals)
        return float(np.sqrt(np.mean(np.square(r)))) if r.size else float("nan")

    @property
    def fitted_keys(self) -> tuple[str, ...]:
        """The parameters fitted (dotted keys; fixed eps or beta excluded)."""
        return tuple(self.values)

    @property
    def chi_square(self) -> bool:
        """True when ``cost`` is a chi-square (standard deviations were given)."""
        return self.weights is not None

    @cached_property
    def result(self) -> Result:
        """The solve at the optimum, under the law fitted."""
        if self.law == "brach":
            return solve(self.case, self.eps, self.beta)
        return solve_under_law(self.case, self.eps,
                               None if self.law == "kudlich-slibar" else self.beta,
                               law=self.law, mu_c=self.contact_friction)

    @property
    def contradiction(self) -> str | None:
        """Why the fit's answer is refused when the measured evidence contradicts itself
        beyond :data:`pim.analysis.residuals.P_CONTRADICTED` (the chi-square's p below it;
        :meth:`GoodnessOfFit.refusal`), else None (also without sigmas or degrees of
        freedom)."""
        return contradiction(self.goodness)

    def __repr__(self) -> str:
        speed, unit = convert(self.rms, "velocity", display_units(case=self.case))
        fitted = ", ".join(f"{SHORT_NAMES.get(k, k)}={short(v)}" + (
            f" +- {short(self.standard_errors[k])}" if k in self.standard_errors else "")
            for k, v in self.values.items())
        fit = "chi-square" if self.chi_square else "least squares"
        name = self.case.name or "(unnamed)"
        return (f"FitResult({name!r}, {self.law}: {fitted or 'nothing fitted'}; {fit} over {len(self.residuals)} terms, rms {short(speed, unit)}"
                + (f", p = {short(self.goodness.p_value)}" if self.goodness is not None else "")
                + f"; {len(self.minima)} local minim{'um' if len(self.minima) == 1 else 'a'})")

    def display_table(self, units=None) -> Table:
        """The fit in ``units`` (default the case's): each parameter (fitted, with its
        standard error, or fixed), then each measured quantity, measured against fitted."""
        shown = display_units(units, case=self.case)
        rows = [(f"{name} (fixed)", None, value, None, None, "-") for name, value in
                (("epsilon", self.eps), ("beta", self.beta)) if name[:3] in self.fixed]
        for key, value in self.values.items():
            (v, se), unit = convert([value, self.standard_errors.get(key, np.nan)],
                                    free_kind(key), shown)
            rows.append((free_label(key), None, float(v), None, float(se), unit))
        for row in self.residual_table:
            values, unit = convert([row["measured"], row["fitted"], row["error"]],
                                   row["kind"], shown)
            label = OUTPUTS[row["name"]].label if row["name"] in OUTPUTS else row["name"]
            rows.append((label, *map(float, values), None, unit))
        notes = [f"{shown}; angles in deg, yaw rates in deg/s", f"impact law: {self.law}"]
        if self.goodness is not None:
            notes.append(f"chi-square {short(self.goodness.chi_square)} on "
                         f"{self.goodness.dof} degrees of freedom, p = "
                         f"{short(self.goodness.p_value)}")
        notes += [f"{k} on its {side} bound" for k, side in self.on_bound.items()]
        return Table(f"fit of {self.case.name or 'case'}",
                     ("quantity", "measured", "fitted", "fitted - measured", "standard error",
                      "unit"), tuple(rows), tuple(notes))

    def to_dict(self) -> dict:
        """JSON-ready summary (SI units; :meth:`display_table` and ``to_frame()`` are in the case's
        units)."""
        return {
            "case": self.case.name, "law": self.law, "eps": self.eps, "beta": self.beta,
            "contact_friction": self.contact_friction, "lower_bounds": dict(self.lower_bounds),
            "cost": self.cost,
            "cost_unit": "-" if self.chi_square else "m^2/s^2",
            "cost_kind": "chi-square" if self.chi_square else "sum of squares",
            "rms": self.rms, "rms_unit": "m/s",
            "residuals": dict(zip(self.residual_names, map(float, self.residuals), strict=True)),
            "include_yaw": self.include_yaw,
            "bounds": dict(zip(("k", "mu_c") if self.law == "kudlich-slibar" else
                               ("eps", "beta"), map(list, self.bounds), strict=True)),
            "fixed": list(self.fixed), "on_bound": dict(self.on_bound),
            "gradient": {"eps": float(self.gradient[0]), "beta": float(self.gradient[1])},
            "minima": [{"eps": e, "beta": b, "cost": c} for e, b, c in self.minima],
            "values": dict(self.values),
            "goodness_of_fit": None if self.goodness is None else self.goodness.to_dict(),
            "standard_errors": dict(self.standard_errors),
            "correlation": [{"a": a, "b": b, "r": r} for (a, b), r in self.correlation.items()],
            "error_basis": self.error_basis, "left_out": list(self.left_out),
            "evidence_shares": {k: dict(v) for k, v in self.evidence_shares.items()},
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
    if not (np.isfinite(b_lo) and np.isfinite(b_hi) and 0.0 <= b_lo < b_hi):
        raise InputError(f"bounds on beta must be finite with 0 <= beta_min < beta_max (beta "
                         f"< 0 would drive the sliding at C; beta_max may exceed 1 to "
                         f"explore, and the answer is then flagged), got ({b_lo}, {b_hi})")
    return (e_lo, e_hi), (b_lo, b_hi)


def _check_fixed(eps, beta, free: dict) -> tuple[float | None, float | None]:
    """The fixed eps and beta as floats (None where fitted); a clear error when out of range."""
    if eps is not None and beta is not None and not free:
        raise InputError("eps and beta are both fixed: nothing to fit (fix at most one, or "
                         "free other inputs)")
    if eps is not None:
        eps = float(eps)
        if not 0.0 <= eps <= 1.0:
            raise InputError(f"eps (fixed) must be in [0, 1], got {eps}")
    if beta is not None:
        beta = float(beta)
        if not (np.isfinite(beta) and beta >= 0):
            raise InputError(f"beta (fixed) {BETA_RANGE_TEXT}, got {beta}")
    return eps, beta


def _check_grid(grid) -> None:
    """``grid`` is no longer used (the coarse search is a Sobol sample): validate, warn."""
    try:
        counts = [checked_count(g, "grid", low=3) for g in grid]
    except (InputError, TypeError):
        raise InputError(f"grid must be two integers >= 3 (points per axis: eps, beta), "
                         f"got {grid!r}") from None
    if len(counts) != 2:
        raise InputError(f"grid must be two integers >= 3 (points per axis: eps, beta), "
                         f"got {grid!r}")
    if tuple(counts) == DEFAULT_GRID:
        return
    warnings.warn("pim.fit(grid=...) is ignored: the coarse search is a Sobol sample of "
                  "`samples` points", DeprecationWarning, stacklevel=3)


def _box(bounds, eps, beta, free: dict) -> dict:
    """Every fitted parameter -> (low, high): eps and beta first (unless fixed), then
    ``free``; ``free`` bounds on restitution or beta replace ``bounds``."""
    free = dict(free)
    box = {}
    for key, value, b in (("impact.restitution", eps, bounds[0]),
                          ("impact.beta", beta, bounds[1])):
        given = free.pop(key, b)
        if value is None:
            box[key] = tuple(given)
    return {**box, **free}


def _fit_result(raw: FreeFit, terms, *, left_out, bounds, fixed, eps, beta, weights,
                law: str = "brach", mu_c=None, lower: dict | None = None) -> FitResult:
    """Wrap the engine's outcome into a :class:`FitResult` (one bound detection: ``side``);
    the keywords are what :func:`fit` was asked (``eps``, ``beta``: the fixed values)."""
    values = raw.values
    e_opt = values.get("impact.restitution", values.get("impact.k", eps))
    b_opt = values.get("impact.beta", beta)
    mu_c = values.get("impact.mu_c", mu_c)
    if law == "kudlich-slibar":          # the PIM beta with the same answer
        b_opt = float(solve_under_law(raw.case, e_opt, law=law, mu_c=mu_c).beta)
    grad = dict(zip(raw.keys, raw.gradient, strict=True))
    on_bound = {SHORT_NAMES.get(k, k): ("lower" if s < 0 else "upper")
                for k, s in zip(raw.keys, raw.side, strict=True) if s}

    def pair(x):
        if law == "kudlich-slibar":
            return (float(x.get("impact.k", eps)), float(x.get("impact.mu_c", mu_c)))
        return (float(x.get("impact.restitution", eps)), float(x.get("impact.beta", beta)))

    minima_values = tuple((dict(zip(raw.keys, map(float, x), strict=True)), c)
                          for x, c in raw.minima)
    r = raw.residuals / (1.0 if weights is None else weights)
    sd, corr, basis = parameter_errors(raw, weights is not None, skip=tuple(lower or ()))
    shares = {} if weights is None or not sd or lower else _shares(raw, terms)
    goodness = None if weights is None else goodness_of_fit(
        raw.cost, len(terms), len(raw.keys), raw.residuals, [t.name for t in terms])
    return FitResult(
        case=raw.case, eps=float(e_opt), beta=float(b_opt), cost=raw.cost, residuals=r,
        residual_names=tuple(t.name for t in terms),
        include_yaw=any(isinstance(t, Term) and not t.is_velocity for t in terms),
        bounds=bounds, fixed=fixed, on_bound=on_bound,
        gradient=np.array([grad.get("impact.restitution", 0.0), grad.get("impact.beta", 0.0)]),
        minima=tuple((*pair(v), c) for v, c in minima_values), nfev=raw.nfev + 1,
        values={k: float(v) for k, v in values.items()}, identifiability=raw.identifiability,
        minima_values=minima_values, weights=weights, terms=tuple(terms), goodness=goodness,
        law=law, contact_friction=None if mu_c is None else float(mu_c),
        lower_bounds=dict(lower or {}), standard_errors=sd, evidence_shares=shares,
        error_basis=basis, left_out=left_out, correlation=corr)


def _shares(raw: FreeFit, terms) -> dict:
    """The evidence shares of the fitted keys' variances (:func:`variance_shares`)."""
    _, shares = variance_shares(raw.jacobian, [t.group for t in terms])
    return {k: {g: float(v[j]) for g, v in shares.items()} for j, k in enumerate(raw.keys)}


def parameter_errors(raw: FreeFit, weighted: bool, skip=()) -> tuple[dict, dict, str]:
    """Standard errors [SI] and correlations [-] of the fitted keys (those in ``skip``, which
    only have a lower bound, left out), and the basis they rest on, in words.

    With the ``[measured]`` sigmas (``weighted``: J is the Jacobian of the standardised
    residuals) C = (J^T J)^-1 = (J^T W J)^-1 of the raw residuals, the sigmas as stated;
    without, C = s^2 (J^T J)^-1 with s^2 = S / (m - n), the residual variance of m values
    and n parameters. Empty, with the reason, when J is rank deficient or m <= n unweighted.
    """
    if raw.jacobian is None:
        return {}, {}, "no standard errors: no Jacobian at the optimum"
    keep = [i for i, k in enumerate(raw.keys) if k not in skip]
    keys, jac = [raw.keys[i] for i in keep], raw.jacobian[:, keep]
    m, n = jac.shape
    if n == 0 or m < n or np.linalg.matrix_rank(jac) < n:
        return {}, {}, ("no standard errors: the measured values do not decide every fitted "
                        "parameter (rank-deficient Jacobian; see the identifiability)")
    if not weighted and m == n:
        return {}, {}, (f"no standard errors: {m} measured values for {n} fitted parameters "
                        f"leave no residual scatter to estimate them from; give the "
                        f"[measured] sigmas")
    scale = 1.0 if weighted else raw.cost / (m - n)
    cov = np.linalg.inv(jac.T @ jac)            # the correlations do not depend on the scale
    unit = np.sqrt(np.diag(cov))
    corr = {(a, b): float(cov[i, j] / (unit[i] * unit[j])) for i, a in enumerate(keys)
            for j, b in enumerate(keys) if i < j}
    sd = unit * np.sqrt(scale)
    basis = ("standard errors from (J^T W J)^-1 at the optimum, W = 1/sigma^2 of the stated "
             "sigmas (not rescaled by chi-square/dof)" if weighted else
             f"standard errors from s^2 (J^T J)^-1 at the optimum, s^2 = S/(m - n) = residual "
             f"variance of {m} measured values and {n} parameter{'s' if n > 1 else ''} (no "
             f"sigmas given)")
    return dict(zip(keys, map(float, sd), strict=True)), corr, basis


def _law_box(law: str, box_eb, eps, beta, mu_c, free_box: dict) -> tuple:
    """(eps or k fixed, beta fixed, the box of every fitted key) under ``law``."""
    if law == "kudlich-slibar":
        eps_fixed, box = _ks_box(box_eb, eps, beta, mu_c, free_box)
        return eps_fixed, None, box
    eps_fixed, beta_fixed = _check_fixed(eps, beta, free_box)
    return eps_fixed, beta_fixed, _box(box_eb, eps_fixed, beta_fixed, free_box)


def _fixed_and_searched(law: str, box: dict, box_eb, eps_fixed, beta_fixed, mu_c) -> tuple:
    """The names of the parameters held fixed, and the box of the law's two parameters as
    searched ((k, mu_c) under Kudlich-Slibar)."""
    fixed = tuple(n for n, v in (("k" if law == "kudlich-slibar" else "eps", eps_fixed),
                                 ("beta", beta_fixed),
                                 ("mu_c", None if "impact.mu_c" in box else mu_c))
                  if v is not None)
    if law == "kudlich-slibar":
        box_eb = (tuple(box.get("impact.k", box_eb[0])),
                  tuple(box.get("impact.mu_c", MU_C_BOUNDS)))
    return fixed, box_eb


def _check_approach(case: Case, eps0: float, beta0: float, free_box: dict) -> None:
    """No impact to fit when the vehicles do not approach (and no input is freed)."""
    if not free_box and not np.any(solve(case, eps0, beta0).approaching):
        raise InputError(f"case {case.name or '(unnamed)'}: the vehicles do not approach at C "
                         "(u_n >= 0): there is no impact to fit")


def fit(case: Case, *, include_yaw: bool | None = None, bounds=DEFAULT_BOUNDS, eps=None,
        beta=None,
        grid=DEFAULT_GRID, max_starts: int = MAX_STARTS, free=None,
        samples: int = SAMPLES, seed: int = 0, law: str | None = None,
        mu_c=None) -> FitResult:
    """Least-squares impact-law parameters, and optionally other inputs, that best reproduce
    the measured post-impact motion.

    Parameters
    ----------
    case : Case
        A single (scalar) case with ``case.measured`` set.
    include_yaw : bool, optional
        Which measured yaw rates to fit: default those with a sigma; True all, False none.
    bounds : ((float, float), (float, float))
        Search box ((eps_min, eps_max), (beta_min, beta_max)); default ((0, 1), (0, 1)),
        the sheet's eps >= 0, beta <= 1 with beta >= 0. eps must stay within [0, 1]; beta
        may be widened (values outside [0, 1] are flagged by ``result.problems()``). Under
        "kudlich-slibar" the first pair bounds k.
    eps, beta : float, optional
        Hold that parameter fixed at the given value and fit only the other one (under
        "kudlich-slibar" ``eps`` fixes k; ``beta`` does not apply).
    grid : (int, int)
        No longer used (a DeprecationWarning when not the default).
    max_starts : int
        How many of the best coarse-search points are refined locally.
    free : dict, optional
        Further free parameters: dotted key -> (low, high) bounds [SI]
        (:data:`pim.analysis.free_fit.FREE_KEYS`: the scalar inputs of ``[uncertainty]``,
        e.g. ``impact.normal_angle``, ``impact.point_x``, ``vehicle1.yaw_rate``, plus
        ``vehicle{1,2}.radius_of_gyration`` and ``vehicle{1,2}.speed``;
        ``impact.restitution`` / ``impact.beta`` / ``impact.k`` / ``impact.mu_c`` here
        replace ``bounds``).
    samples, seed : int
        Size and seed of the coarse Sobol sample.
    law : {"brach", "brach-capped", "kudlich-slibar"}, optional
        The impact law to fit under (default the case's ``impact.law``, else "brach").
        "kudlich-slibar" fits (k, mu_c) (mu_c in :data:`MU_C_BOUNDS` unless ``free`` bounds
        it); "brach-capped" fits (eps, beta) under the cap mu_c.
    mu_c : float, optional
        Hold the contact friction fixed (default under "kudlich-slibar": fitted; under
        "brach-capped": the case's cap).

    Returns
    -------
    FitResult
        Where the contact does not reach a fitted mu_c (a sticking Kudlich-Slibar contact,
        an uncapped Brach one), mu_c only has a lower bound: ``values`` holds that bound,
        ``lower_bounds`` names it, and the identifiability says so (module
        :func:`pim.analysis.free_inputs.friction_floor`).

    Raises
    ------
    ValueError
        Nothing measured, a batched case, bad bounds, both parameters fixed, a parameter
        the law does not take, or no approach.
    """
    checked_case(case)
    check_counts(max_starts=max_starts, samples=samples)
    check_numbers(eps=eps, beta=beta)     # mu_c may be inf (always stick): _law_case checks
    if np.size(case.vehicle1.mass) != 1 or np.shape(case.impact.point) != (2,):
        raise InputError("fit needs a single case, not a batch of cases")
    law = law_of(case, law)
    case = _law_case(case, law, mu_c)
    terms = measured_terms(case, include_yaw)
    box_eb = _check_bounds(bounds)
    free_box = check_free(free or {})
    eps_fixed, beta_fixed, box = _law_box(law, box_eb, eps, beta, mu_c, free_box)
    _check_grid(grid)
    eps0 = 0.5 if eps_fixed is None else eps_fixed
    beta0 = 0.5 if beta_fixed is None else beta_fixed
    _check_approach(case, eps0, beta0, free_box)
    weights = measured_weights(case, terms)
    raw = fit_free(case, box, terms, eps0, beta0, samples=samples, max_starts=max_starts,
                   seed=seed)
    raw, lower = _floor(case, raw, terms, case_state(case, eps0, beta0))
    fixed, box_eb = _fixed_and_searched(law, box, box_eb, eps_fixed, beta_fixed, mu_c)
    return _fit_result(raw, terms, left_out=_left_out(case, terms), bounds=box_eb, fixed=fixed,
                       eps=eps_fixed, beta=beta_fixed, weights=weights, law=law,
                       mu_c=case.impact.contact_friction, lower=lower)


def _left_out(case: Case, terms) -> tuple[str, ...]:
    """The measured yaw rates that are not among the fitted ``terms``."""
    m, fitted = case.measured, {t.name for t in terms}
    return tuple(f"yaw_rate{i}" for i in (1, 2) if m is not None
                 and getattr(m, f"yaw_rate{i}") is not None and f"yaw_rate{i}" not in fitted)


def _law_case(case: Case, law: str, mu_c) -> Case:
    """``case`` under ``law`` with contact friction ``mu_c`` (when given): beta dropped
    under "kudlich-slibar", the friction dropped under "brach"."""
    imp = case.impact
    friction = imp.contact_friction if mu_c is None else float(
        check_contact_friction(mu_c, "mu_c (contact friction)"))
    if law == (imp.law or "brach") and friction == imp.contact_friction:
        return case
    changes = {"law": law, "contact_friction": None if law == "brach" else friction}
    if law == "kudlich-slibar":
        changes["beta"] = None
    return replace(case, impact=replace(imp, **changes))


def _ks_box(bounds, eps, beta, mu_c, free: dict) -> tuple:
    """(fixed k or None, box) under "kudlich-slibar": k (``bounds[0]``, or ``free``'s
    ``impact.k`` / ``impact.restitution``) unless fixed, mu_c (:data:`MU_C_BOUNDS`, or
    ``free``'s) unless fixed, then the other ``free`` keys."""
    if beta is not None or "impact.beta" in free:
        raise InputError("beta does not apply to law 'kudlich-slibar' (its parameters are "
                         "restitution k and contact friction mu_c)")
    free = dict(free)
    k_bounds = free.pop("impact.restitution", None) or free.pop("impact.k", bounds[0])
    mu_bounds = free.pop("impact.mu_c", MU_C_BOUNDS)
    if eps is not None:
        eps = float(eps)
        if not 0.0 <= eps <= 1.0:
            raise InputError(f"k (fixed restitution) must be in [0, 1], got {eps}")
    if eps is not None and mu_c is not None and not free:
        raise InputError("k and mu_c are both fixed: nothing to fit (fix at most one, or "
                         "free other inputs)")
    box = {} if eps is not None else {"impact.k": tuple(k_bounds)}
    if mu_c is None:
        box["impact.mu_c"] = tuple(mu_bounds)
    return eps, {**box, **free}


def _floor(case: Case, raw: FreeFit, terms, base) -> tuple[FreeFit, dict]:
    """``raw`` with an unreached contact friction replaced by its lower bound
    (:func:`pim.analysis.free_inputs.friction_floor`) in the optimum and every minimum (the
    minima that then coincide merged), and the identifiability of the other parameters
    with the lower bound stated."""
    if "impact.mu_c" not in raw.keys:
        return raw, {}
    width = raw.box[:, 1] - raw.box[:, 0]
    xs, _ = friction_floor(base, raw.keys, np.array([m for m, _ in raw.minima]))
    minima, kept = [], []
    for xm, (_, cost) in zip(xs, raw.minima, strict=True):
        if all(np.max(np.abs(xm - k) / width) > MERGE for k in kept):
            kept.append(xm)
            minima.append((xm, cost))
    raw = replace(raw, minima=tuple(minima))
    x, floored = friction_floor(base, raw.keys, raw.x[None])
    if not floored[0]:
        return raw, {}
    j = raw.keys.index("impact.mu_c")
    bound = float(x[0, j])
    rows, target, factor = residual_terms(case, terms)
    _, jac = free_residuals(base, raw.keys, x, rows, target, factor,
                            evidence=split_terms(terms)[1])
    keep = [i for i in range(len(raw.keys)) if i != j]
    ident = identifiability(jac[0][:, keep] * width[keep], tuple(raw.keys[i] for i in keep),
                            as_residual_terms(terms))
    said = (f"impact.mu_c only has a lower bound: any mu_c >= {bound:.4g} gives the same "
            f"answer (the contact does not reach its friction: it sticks); {bound:.4g} "
            "stands for it")
    ident = replace(ident, warnings=(said, *ident.warnings))
    side = raw.side.copy()
    side[j] = 0
    fitted = replace(raw.case, impact=replace(raw.case.impact, contact_friction=bound))
    return replace(raw, x=x[0], side=side, identifiability=ident, case=fitted), {
        "impact.mu_c": bound}
