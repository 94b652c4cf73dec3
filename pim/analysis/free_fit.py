"""Fit of any inputs of a case (beyond epsilon and beta) to measured post-impact motion.

A free parameter is named by its dotted case-file key (:data:`FREE_KEYS`): every scalar input
of :data:`pim.model.quantities.INPUTS` (``impact.normal_angle``, ``impact.point_x``,
``vehicle1.yaw_rate`` ...) plus ``vehicle{1,2}.radius_of_gyration`` [m] (the yaw inertia
becomes m k^2) and ``vehicle{1,2}.speed`` [m/s] (the pre-impact speed along the direction of
the case's velocity, or of the heading where the velocity is zero).

Strategy (as :func:`pim.analysis.fitting.fit`): a coarse global search over the bounded box
(a scrambled Sobol sample, seeded, so runs repeat), then bounded local refinement
(``scipy.optimize.least_squares``, trust-region reflective) from the best few samples, with
central finite-difference derivatives. At the optimum the Jacobian of the (weighted)
residuals with respect to the free parameters, each scaled by its bound width, is taken by
central differences; its singular values give the rank, its near-null right singular
vectors the *families* of exact fits (parameters that trade against each other with no change
in the fitted motion), and (J^T J)^-1 the parameter correlations.

Why families appear: the post-impact motion depends only on the impulse vector P and the line
of action through C, three numbers. Free (eps, beta, Gamma), or (eps, beta) with both
coordinates of C, can all move while P stays put, so a whole curve of parameters fits
equally well: the fit reports that, and does not present one member as the answer.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..model.case import Case
from ..model.quantities import INPUTS, field_of
from ..model.solver import solve
from .residuals import measured_weights, residuals

__all__ = ["FREE_KEYS", "Identifiability", "set_inputs", "check_free", "fit_free",
           "identifiability"]

#: Keys accepted in ``free`` beyond :data:`INPUTS`, with their meaning.
EXTRA_KEYS = {
    **{f"vehicle{i}.radius_of_gyration": "radius of gyration k [m]; yaw inertia = m k^2"
       for i in (1, 2)},
    **{f"vehicle{i}.speed": "pre-impact speed [m/s] along the case's velocity direction"
       for i in (1, 2)},
}
#: Every key :func:`fit_free` accepts.
FREE_KEYS = tuple(INPUTS) + tuple(EXTRA_KEYS)

#: Physical lower limits of bounds [SI] (strictly above for mass, inertia, k).
_POSITIVE = ("mass", "yaw_inertia", "radius_of_gyration")


def check_free(free: dict) -> dict:
    """Validate ``free``: known keys, finite bounds with low < high, physical ranges."""
    out = {}
    for key, b in (free or {}).items():
        if key not in FREE_KEYS:
            raise ValueError(f"free parameter {key!r} is unknown (allowed: "
                             f"{', '.join(FREE_KEYS)})")
        try:
            lo, hi = (float(x) for x in b)
        except (TypeError, ValueError):
            raise ValueError(f"free parameter {key}: bounds must be (low, high) numbers in "
                             f"SI, got {b!r}") from None
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise ValueError(f"free parameter {key}: bounds must be finite with low < high, "
                             f"got ({lo}, {hi})")
        attr = key.split(".", 1)[1]
        if attr in _POSITIVE and lo <= 0:
            raise ValueError(f"free parameter {key}: bounds must be > 0, got ({lo}, {hi})")
        if key == "impact.restitution" and not (0.0 <= lo and hi <= 1.0):
            raise ValueError(f"free parameter {key}: bounds must lie in [0, 1], got ({lo}, {hi})")
        if attr == "speed" and lo < 0:
            raise ValueError(f"free parameter {key}: bounds must be >= 0 [m/s], got ({lo}, {hi})")
        out[key] = (lo, hi)
    return out


def _direction(vehicle) -> np.ndarray:
    v = np.asarray(vehicle.velocity, dtype=float)
    s = float(np.hypot(*v))
    if s > 0:
        return v / s
    h = float(np.asarray(vehicle.heading))
    return np.array([np.cos(h), np.sin(h)])


def _set_field(changes: dict, base, key: str, value: float) -> None:
    """Record in ``changes`` the field of ``base`` (a Vehicle or the Impact) that input
    ``key`` names, set to ``value``; for the x or y part of a vector field, the vector as
    changed so far with that component replaced."""
    name, axis = field_of(key)
    attr = name.split(".", 1)[1]
    if axis is None:
        changes[attr] = value
    else:
        vec = np.array(changes.get(attr, getattr(base, attr)), dtype=float)
        vec[axis] = value
        changes[attr] = vec


def set_inputs(case: Case, values: dict) -> Case:
    """``case`` with the inputs named by dotted keys set to ``values`` [SI] (scalars).

    ``impact.restitution`` and ``impact.beta`` are stored on the impact; the others replace the
    vehicle or impact fields they name.
    """
    vehicles = {1: case.vehicle1, 2: case.vehicle2}
    vchanges: dict[int, dict] = {1: {}, 2: {}}
    ichanges: dict = {}
    for key, value in values.items():
        value = float(value)
        group, attr = key.split(".", 1)
        base, ch = ((vehicles[int(group[-1])], vchanges[int(group[-1])])
                    if group.startswith("vehicle") else (case.impact, ichanges))
        if attr == "radius_of_gyration":
            ch["yaw_inertia"] = float(base.mass) * value ** 2
        elif attr == "speed":
            ch["velocity"] = value * _direction(base)
        else:
            _set_field(ch, base, key, value)
    for i in (1, 2):
        ch = vchanges[i]
        if ch:
            vehicles[i] = replace(vehicles[i], **ch)
    impact = replace(case.impact, **ichanges) if ichanges else case.impact
    return replace(case, vehicle1=vehicles[1], vehicle2=vehicles[2], impact=impact)


def current_value(case: Case, key: str) -> float:
    """The value [SI] of a free key in ``case``."""
    group, attr = key.split(".", 1)
    if group.startswith("vehicle"):
        v = case.vehicle1 if group.endswith("1") else case.vehicle2
        if attr == "radius_of_gyration":
            return float(np.sqrt(float(v.yaw_inertia) / float(v.mass)))
        if attr == "speed":
            return float(np.hypot(*np.asarray(v.velocity, dtype=float)))
    name, axis = field_of(key)
    grp, attr = name.split(".", 1)
    obj = case.impact if grp == "impact" else (case.vehicle1 if grp.endswith("1")
                                               else case.vehicle2)
    value = getattr(obj, attr)
    if value is None:
        return float("nan")
    return float(np.asarray(value, dtype=float).reshape(-1)[0 if axis is None else axis])


@dataclass(frozen=True)
class Identifiability:
    """What the data can decide about the free parameters, at the optimum.

    Attributes
    ----------
    names : tuple of str
        The fitted parameters (dotted keys), in the order of the columns below.
    rank : int
        Numerical rank of the weighted-residual Jacobian (columns scaled by bound width).
    singular_values : ndarray
        Its singular values, largest first [residual units per bound width].
    correlation : ndarray (n, n)
        Parameter correlation matrix from (J^T J)^-1 (NaN where J is rank deficient).
    families : tuple of tuple of str
        Groups of parameters that trade against each other along a near-null direction of J:
        every member of the family fits (nearly) as well.
    under_determined : bool
        More free parameters than independent data, or a rank-deficient Jacobian.
    n_data : int
        Number of residual terms (measured quantities).
    warnings : tuple of str
        Plain-language statements of the above.
    """

    names: tuple
    rank: int
    singular_values: np.ndarray
    correlation: np.ndarray
    families: tuple
    under_determined: bool
    n_data: int
    warnings: tuple = ()

    @property
    def identifiable(self) -> bool:
        """True when the Jacobian has full column rank."""
        return not self.under_determined and not self.families

    def to_dict(self) -> dict:
        return {"names": list(self.names), "rank": self.rank,
                "singular_values": [float(s) for s in self.singular_values],
                "correlation": np.where(np.isfinite(self.correlation), self.correlation,
                                        None).tolist(),
                "families": [list(f) for f in self.families],
                "under_determined": self.under_determined, "n_data": self.n_data,
                "warnings": list(self.warnings)}


#: Relative singular value below which a direction counts as null (a family of fits).
NULL_TOL = 1e-6
#: Weight above which a parameter belongs to a null direction's family.
FAMILY_WEIGHT = 0.05


def identifiability(jac: np.ndarray, names: tuple, residual_names: tuple,
                    null_tol: float = NULL_TOL) -> Identifiability:
    """Rank, singular values, correlations and families of a scaled Jacobian (m, n)."""
    m, n = jac.shape
    s, vt = (np.linalg.svd(jac, full_matrices=True)[1:] if m else
             (np.zeros(0), np.eye(n)))
    s_full = np.zeros(n)
    s_full[:len(s)] = s
    smax = s_full.max() if n else 0.0
    tol = null_tol * max(smax, 1e-300)
    rank = int(np.count_nonzero(s_full > tol))
    families = []
    for k in range(rank, n):
        v = vt[k]
        members = tuple(names[j] for j in np.flatnonzero(np.abs(v) > FAMILY_WEIGHT))
        if members and members not in families:
            families.append(members)
    if rank == n and n:
        cov = np.linalg.inv(jac.T @ jac)
        d = np.sqrt(np.diag(cov))
        corr = cov / np.outer(d, d)
    else:
        corr = np.full((n, n), np.nan)
    warnings = []
    under = n > m or rank < n
    if n > m:
        warnings.append(f"under-determined: {n} free parameters ({', '.join(names)}) but only "
                        f"{m} measured quantities ({', '.join(residual_names)}); measure "
                        f"{n - m} more (e.g. the other vehicle's velocity or the yaw rates "
                        f"with include_yaw) or fix {n - m} parameter(s)")
    for fam in families:
        warnings.append(f"family of equally good fits: {', '.join(fam)} trade against each "
                        f"other (the data fix only a combination of them); fix one of them "
                        f"to get a unique answer")
    if rank == n and n:
        for a in range(n):
            for b in range(a + 1, n):
                if abs(corr[a, b]) > 0.99:
                    warnings.append(f"{names[a]} and {names[b]} are strongly correlated "
                                    f"(r = {corr[a, b]:+.3f})")
    return Identifiability(names=tuple(names), rank=rank, singular_values=s_full,
                           correlation=corr, families=tuple(families), under_determined=under,
                           n_data=m, warnings=tuple(warnings))


@dataclass(frozen=True)
class FreeFit:
    """Raw outcome of :func:`fit_free` (wrapped into a :class:`pim.FitResult` by ``fit``)."""

    values: dict
    case: Case
    eps: float
    beta: float
    cost: float
    residuals: np.ndarray
    on_bound: dict
    gradient: np.ndarray
    minima: tuple
    identifiability: Identifiability
    nfev: int
    extra: dict = field(default_factory=dict)


def fit_free(case: Case, free: dict, names: tuple, eps, beta,
             eps_bounds, beta_bounds, samples: int = 256, max_starts: int = 5,
             seed: int = 0) -> FreeFit:
    """Bounded least squares over eps, beta (unless fixed) and the ``free`` keys.

    Parameters
    ----------
    case : Case
        Scalar case with ``measured`` set.
    free : dict
        Validated dotted key -> (low, high) [SI] (see :func:`check_free`).
    names : tuple of str
        Residual terms (:func:`pim.analysis.residuals.measured_terms`).
    eps, beta : float or None
        Fixed values, or None to fit within ``eps_bounds`` / ``beta_bounds``.
    samples : int
        Size of the coarse Sobol sample (rounded up to a power of two).
    max_starts : int
        Number of best samples refined locally.
    seed : int
        Seed of the scrambled Sobol sample.
    """
    from scipy.optimize import least_squares
    from scipy.stats import qmc

    keys, box = [], []
    if eps is None:
        keys.append("impact.restitution")
        box.append(tuple(free.pop("impact.restitution", eps_bounds)))
    else:
        free.pop("impact.restitution", None)
    if beta is None:
        keys.append("impact.beta")
        box.append(tuple(free.pop("impact.beta", beta_bounds)))
    else:
        free.pop("impact.beta", None)
    for k, b in free.items():
        keys.append(k)
        box.append(b)
    lo = np.array([b[0] for b in box])
    hi = np.array([b[1] for b in box])
    width = hi - lo
    n = len(keys)
    nfev = 0

    def model_case(x):
        vals = dict(zip(keys, map(float, x), strict=True))
        e = vals.pop("impact.restitution", eps)
        b = vals.pop("impact.beta", beta)
        return set_inputs(case, vals) if vals else case, e, b

    def resid(x):
        nonlocal nfev
        nfev += 1
        try:
            c, e, b = model_case(x)
            w = measured_weights(c, names)
            r = residuals(solve(c, e, b), names) * (1.0 if w is None else w)
        except (ValueError, ZeroDivisionError, FloatingPointError):
            return np.full(len(names), 1e6)
        r = np.asarray(r, dtype=float)
        return np.where(np.isfinite(r), r, 1e6)

    # ---- coarse global search ----------------------------------------------------------
    m_exp = int(np.ceil(np.log2(max(int(samples), 8))))
    u = qmc.Sobol(d=n, scramble=True, seed=seed).random_base2(m_exp)
    xs = lo + u * width
    costs = np.array([float(np.sum(resid(x) ** 2)) for x in xs])
    order = np.argsort(costs, kind="stable")
    starts = [xs[i] for i in order[:max(1, int(max_starts))]]

    # ---- local refinement ---------------------------------------------------------------
    minima = []
    for x0 in starts:
        out = least_squares(resid, x0, bounds=(lo, hi), x_scale=width, method="trf",
                            jac="3-point", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=400)
        x = np.clip(out.x, lo, hi)
        c = float(np.sum(resid(x) ** 2))
        if all(np.max(np.abs(x - y) / width) > 1e-4 for y, _ in minima):
            minima.append((x, c))
    minima.sort(key=lambda t: t[1])
    x_opt, c_opt = minima[0]
    r = resid(x_opt)

    # ---- Jacobian at the optimum (central differences, scaled by bound width) -----------
    h = 1e-6 * width
    cols = []
    for j in range(n):
        xp, xm = x_opt.copy(), x_opt.copy()
        xp[j] = min(x_opt[j] + h[j], hi[j])
        xm[j] = max(x_opt[j] - h[j], lo[j])
        cols.append((resid(xp) - resid(xm)) / ((xp[j] - xm[j]) / width[j]))
    jac = np.array(cols).T.reshape(len(names), n)
    ident = identifiability(jac, tuple(keys), names)
    gradient = 2.0 * (r @ jac) / width

    on_bound = {}
    for k, v, a, b in zip(keys, x_opt, lo, hi, strict=True):
        tol = 1e-9 * (b - a)
        if v <= a + tol:
            on_bound[k] = "lower"
        elif v >= b - tol:
            on_bound[k] = "upper"
    fitted, e_opt, b_opt = model_case(x_opt)
    values = dict(zip(keys, map(float, x_opt), strict=True))
    minima_out = tuple((dict(zip(keys, map(float, x), strict=True)), float(c))
                       for x, c in minima)
    return FreeFit(values=values, case=fitted, eps=float(e_opt), beta=float(b_opt),
                   cost=float(r @ r), residuals=r, on_bound=on_bound, gradient=gradient,
                   minima=minima_out, identifiability=ident, nfev=nfev)
