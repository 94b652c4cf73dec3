"""Fit of any inputs of a case (beyond epsilon and beta) to measured post-impact motion.

A free parameter is named by its dotted case-file key (:data:`FREE_KEYS`, defined with the
way each moves the case in :mod:`pim.analysis.free_inputs`): every scalar input of
:data:`pim.model.quantities.INPUTS` plus ``vehicle{1,2}.speed``,
``vehicle{1,2}.radius_of_gyration``, Brach's ``vehicle{1,2}.phi`` and ``vehicle{1,2}.d``,
and ``impact.point_along`` (C along the crush edge).

Strategy (as :func:`pim.analysis.fitting.fit`): a coarse global search over the bounded box
(a scrambled Sobol sample, seeded, so runs repeat) evaluated in one vectorised call of the
formula, then a bounded Levenberg-Marquardt refinement of the best few samples, all starts
at once (:func:`pim.analysis.least_squares_batch.least_squares_batch`), with exact
derivatives: dual numbers through the map free keys -> model inputs
(:func:`pim.analysis.free_inputs.free_inputs`) and through the formula
(:func:`pim.model.dual.motion_of_inputs`). At the optimum the Jacobian of the (weighted)
residuals with respect to the free parameters, each scaled by its bound width, gives the
rank from its singular values, the *families* of exact fits from its near-null right
singular vectors (parameters that trade against each other with no change in the fitted
motion), and the parameter correlations from (J^T J)^-1.

Why families appear: the post-impact motion depends only on the impulse vector P and the line
of action through C, three numbers. Free (eps, beta, Gamma), or (eps, beta) with both
coordinates of C, can all move while P stays put, so a whole curve of parameters fits
equally well: the fit reports that, and does not present one member as the answer.

The yaw-rate residuals are weighted by each vehicle's radius of gyration in the case as
given (:mod:`pim.analysis.residuals`), also when k is fitted, so that the weights stay fixed
during the fit.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..model.case import Case
from ..model.dual import MOTION_OUTPUTS
from ..model.evidence_terms import (
    EvidenceTerm,
    ModelQuantities,
    as_residual_terms,
    split_terms,
)
from ..model.motion import Term
from .free_inputs import (
    FREE_KEYS,
    STATE,
    case_state,
    check_free,
    check_free_for_case,
    current_value,
    free_inputs,
    set_inputs,
    state_motion,
)
from .least_squares_batch import least_squares_batch
from .residuals import residual_terms

__all__ = ["FREE_KEYS", "Identifiability", "FreeFit", "set_inputs", "check_free",
           "current_value", "fit_free", "identifiability", "free_residuals",
           "residual_terms", "evidence_values", "deciding_evidence", "evidence_list",
           "candidate_evidence", "terms_jacobian", "variance_shares"]

#: Box-scaled distance within which two starts of the local search count as one minimum.
MERGE = 1e-3
#: Residual that stands for a failed evaluation (singular q, no approach) [weighted units].
PENALTY = 1e6


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
    deciding : tuple of (str, int)
        Evidence not in the fit that would decide its null directions, with how many
        (:func:`deciding_evidence`); empty when identifiable or when no candidate was given.
    """

    names: tuple
    rank: int
    singular_values: np.ndarray
    correlation: np.ndarray
    families: tuple
    under_determined: bool
    n_data: int
    warnings: tuple = ()
    deciding: tuple = ()

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
                "warnings": list(self.warnings),
                "deciding": [{"evidence": e, "decides": k} for e, k in self.deciding]}


#: Relative singular value below which a direction counts as null (a family of fits).
NULL_TOL = 1e-6
#: Weight above which a parameter belongs to a null direction's family.
FAMILY_WEIGHT = 0.05


#: Share of a candidate row's length that must lie in the null space for it to decide.
DECIDE_TOL = 1e-3


def deciding_evidence(null: np.ndarray, candidates: dict) -> list[tuple[str, int]]:
    """Which candidate evidence would decide the null directions ``null`` (k, n), and how
    many of them each decides: the rank that its Jacobian rows (c, n, columns scaled as
    the fit's) add, i.e. the rank of their projection on the null space, each row taken at
    unit length (a row nearly orthogonal to the null space decides nothing)."""
    out = []
    if not len(null):
        return out
    for label, rows in candidates.items():
        rows = np.asarray(rows, dtype=float)
        norm = np.linalg.norm(rows, axis=1, keepdims=True)
        rows = rows[np.isfinite(norm[:, 0]) & (norm[:, 0] > 0)]
        if not len(rows):
            continue
        proj = (rows / np.linalg.norm(rows, axis=1, keepdims=True)) @ null.T
        gain = int(np.count_nonzero(np.linalg.svd(proj, compute_uv=False) > DECIDE_TOL))
        if gain:
            out.append((label, gain))
    return out


def evidence_list(labels) -> str:
    """"a, b or c", the two vehicles' versions of one piece of evidence said once
    ("a recorded delta-V of either vehicle")."""
    labels = list(dict.fromkeys(labels))
    for one, two, both in (("a recorded delta-V of vehicle1", "a recorded delta-V of vehicle2",
                            "a recorded delta-V of either vehicle"),
                           ("vehicle1's recorded pre-crash speed",
                            "vehicle2's recorded pre-crash speed",
                            "either vehicle's recorded pre-crash speed")):
        if one in labels and two in labels:
            labels[labels.index(one)] = both
            labels.remove(two)
    return labels[0] if len(labels) == 1 else ", ".join(labels[:-1]) + " or " + labels[-1]


def identifiability(jac: np.ndarray, names: tuple, residual_names: tuple,
                    null_tol: float = NULL_TOL, candidates: dict | None = None
                    ) -> Identifiability:
    """Rank, singular values, correlations and families of a scaled Jacobian (m, n).

    ``candidates`` (label -> Jacobian rows (c, n) of evidence not in the fit, columns scaled
    as ``jac``'s) lets the messages name the evidence that would decide an under-determined
    fit or a family (:func:`deciding_evidence`).
    """
    m, n = jac.shape
    s, vt = (np.linalg.svd(jac, full_matrices=True)[1:] if m else
             (np.zeros(0), np.eye(n)))
    s_full = np.zeros(n)
    s_full[:len(s)] = s
    smax = s_full.max() if n else 0.0
    tol = null_tol * max(smax, 1e-300)
    rank = int(np.count_nonzero(s_full > tol))
    families, deciders = [], []
    for k in range(rank, n):
        v = vt[k]
        members = tuple(names[j] for j in np.flatnonzero(np.abs(v) > FAMILY_WEIGHT))
        if members and members not in families:
            families.append(members)
            deciders.append([label for label, _ in deciding_evidence(v[None], candidates or {})])
    if rank == n and n:
        cov = np.linalg.inv(jac.T @ jac)
        d = np.sqrt(np.diag(cov))
        corr = cov / np.outer(d, d)
    else:
        corr = np.full((n, n), np.nan)
    deciding = tuple(deciding_evidence(vt[rank:], candidates or {}))
    warnings = _count_warning(names, residual_names, m, n, deciding)
    warnings += _family_warnings(families, deciders)
    if rank == n and n:
        for a in range(n):
            for b in range(a + 1, n):
                if abs(corr[a, b]) > 0.99:
                    warnings.append(f"{names[a]} and {names[b]} are strongly correlated "
                                    f"(r = {corr[a, b]:+.3f})")
    return Identifiability(names=tuple(names), rank=rank, singular_values=s_full,
                           correlation=corr, families=tuple(families),
                           under_determined=n > m or rank < n, n_data=m,
                           warnings=tuple(warnings), deciding=deciding)


def _count_warning(names, residual_names, m: int, n: int, deciding) -> list[str]:
    """The under-determined message (more parameters than data), naming what would decide."""
    if n <= m:
        return []
    hint = (f"measure {n - m} more (e.g. the other vehicle's velocity or the yaw rates "
            f"with include_yaw) or fix {n - m} parameter(s)")
    if deciding:
        hint = (f"evidence that would decide it: {evidence_list(d for d, _ in deciding)} "
                f"(together at least {n - m} more independent data), or fix {n - m} "
                f"parameter(s)")
    return [f"under-determined: {n} free parameters ({', '.join(names)}) but only {m} "
            f"measured quantities ({', '.join(map(str, residual_names))}); {hint}"]


def _family_warnings(families, deciders) -> list[str]:
    """One message per family of equally good fits, naming the evidence that would decide
    it when there is any."""
    out = []
    for fam, labels in zip(families, deciders, strict=True):
        if len(fam) > 1:
            decide = (f"; {evidence_list(labels)} would decide it, or fix one of them"
                      if labels else "; fix one of them to get a unique answer")
            out.append(f"family of equally good fits: {', '.join(fam)} trade against each "
                       f"other (the data fix only a combination of them){decide}")
        else:
            decide = f"; {evidence_list(labels)} would decide it, or fix it" if labels else \
                "; fix it"
            out.append(f"family of equally good fits: {fam[0]} does not change the fitted "
                       f"motion (the data say nothing about it){decide}")
    return out


@dataclass(frozen=True)
class FreeFit:
    """Raw outcome of :func:`fit_free` (wrapped into a :class:`pim.FitResult` by ``fit``).

    Attributes
    ----------
    keys : tuple of str
        The fitted parameters (dotted keys), in the order of ``x``, ``gradient``, ``box``.
    x : ndarray (n,)
        Their values at the optimum [SI].
    box : ndarray (n, 2)
        Their bounds [SI].
    case : Case
        The input case with the fitted inputs put in (eps and beta excepted).
    cost : float
        Sum of squared (weighted) residuals at the optimum.
    residuals : ndarray (k,)
        The weighted residuals at the optimum.
    side : ndarray (n,) of int
        -1 on the lower bound, +1 on the upper bound, 0 inside.
    gradient : ndarray (n,)
        d cost / d x at the optimum.
    minima : tuple of (ndarray (n,), float)
        Distinct local minima (x, cost), best first.
    identifiability : Identifiability
    nfev : int
    converged : bool
    jacobian : ndarray (k, n) or None
        d residuals / d x at the optimum (weighted as ``residuals``).
    """

    keys: tuple
    x: np.ndarray
    box: np.ndarray
    case: Case
    cost: float
    residuals: np.ndarray
    side: np.ndarray
    gradient: np.ndarray
    minima: tuple
    identifiability: Identifiability
    nfev: int
    converged: bool
    jacobian: np.ndarray | None = None

    @property
    def values(self) -> dict:
        """Dotted key -> fitted value [SI]."""
        return dict(zip(self.keys, map(float, self.x), strict=True))


def evidence_values(state, dstate, values, dvalues, evidence) -> tuple:
    """The evidence terms' model values (m, k) and, with ``dstate``, their exact Jacobian
    (m, k, n) by the chain rule: each term (:class:`pim.model.evidence_terms.EvidenceTerm`)
    is evaluated on dual numbers that carry d state / d x and d output / d x."""
    q = ModelQuantities(STATE, state, dstate, MOTION_OUTPUTS, values, dvalues)
    out = [t.value(q) for t in evidence]
    if dstate is None:
        return np.stack(out, axis=-1), None
    return (np.stack([o.value for o in out], axis=-1),
            np.stack([np.broadcast_to(o.grad, dstate.shape[:1] + dstate.shape[2:])
                      for o in out], axis=-2))


def free_residuals(base, keys, x, rows, target, factor, *, jacobian: bool = True,
                   evidence=()):
    """Weighted residuals at the free parameters ``x`` (m, n), and their exact Jacobian.

    Parameters
    ----------
    base : Case or array_like (23,) or (m, 23)
        Everything not freed (:func:`pim.analysis.free_inputs.free_inputs`).
    keys : sequence of str
        Free keys, the columns of ``x``.
    x : array_like (m, n)
        Parameter vectors [SI].
    rows, target, factor : array_like (j,) / (k,) or (m, k) / (k,) or (m, k)
        The residual terms (:func:`pim.analysis.residuals.residual_terms`): rows of the
        motion terms, then targets and factors of every term; target and factor per row or
        shared.
    jacobian : bool
        Also return the Jacobian.
    evidence : sequence of EvidenceTerm
        The evidence terms after the motion rows (k = j + len(evidence)).

    Returns
    -------
    r : ndarray (m, k)
        (output - target) * factor; :data:`PENALTY` where q is singular.
    jac : ndarray (m, k, n) or None
        d r / d x, zero where the penalty stands.
    """
    state, dstate = free_inputs(base, keys, x, jacobian=jacobian)
    values, dvalues = state_motion(state, dstate, jacobian=jacobian)    # under the state's law
    out = values[:, rows]
    dout = None if dvalues is None else dvalues[:, rows, :]
    if len(evidence):
        ev, dev = evidence_values(state, dstate, values, dvalues, evidence)
        out = np.concatenate([out, ev], axis=1)
        dout = None if dev is None else np.concatenate([dout, dev], axis=1)
    with np.errstate(invalid="ignore"):
        r = (out - target) * factor
    bad = ~np.all(np.isfinite(r), axis=1)
    r = np.where(bad[:, None], PENALTY, r)
    if not jacobian:
        return r, None
    jac = dout * np.asarray(factor)[..., None]
    jac = np.where(bad[:, None, None] | ~np.isfinite(jac), 0.0, jac)
    return r, jac


def candidate_evidence(case: Case, present) -> dict[str, tuple]:
    """Evidence not (wholly) in the fit that an engineer could gather, by label: each
    vehicle's post-impact motion (what its rest position gives), a recorded delta-V and
    pre-crash speed of each vehicle, the energy loss; a fixed obstacle's left out."""
    present = set(as_residual_terms(present))
    groups: dict[str, tuple] = {}
    for i in (1, 2):
        if bool(np.any(getattr(case, f"vehicle{i}").fixed)):
            continue
        groups[f"vehicle{i}'s rest position (its post-impact motion)"] = (
            Term(i, "vx"), Term(i, "vy"), Term(i, "omega"))
        groups[f"a recorded delta-V of vehicle{i}"] = (EvidenceTerm("delta_v", i, 0),
                                                       EvidenceTerm("delta_v", i, 1))
        groups[f"vehicle{i}'s recorded pre-crash speed"] = (EvidenceTerm("pre_crash_speed", i),)
    groups["an energy loss (crush)"] = (EvidenceTerm("energy_loss"),)
    return {label: terms for label, terms in groups.items() if not set(terms) <= present}


def terms_jacobian(case: Case, keys, x, eps, beta, groups: dict,
                   contact_friction=None) -> dict:
    """label -> d value / d x (c, n) of each group's terms at the single parameter vector
    ``x`` [SI] (unweighted; :func:`free_residuals` with zero targets), under the case's
    impact law (``contact_friction``: its mu_c, default the case's)."""
    base = case_state(case, eps, beta, contact_friction=contact_friction)
    out = {}
    for label, terms in groups.items():
        motion, evidence = split_terms(terms)
        rows = np.array([MOTION_OUTPUTS.index(t.name) for t in motion], dtype=int)
        k = len(motion) + len(evidence)
        _, jac = free_residuals(base, keys, np.asarray(x, dtype=float)[None], rows,
                                np.zeros(k), np.ones(k), evidence=evidence)
        out[label] = jac[0]
    return out


def variance_shares(jac: np.ndarray, groups) -> tuple[np.ndarray, dict]:
    """Standard errors of the parameters and the share of each one's variance that each
    group of residuals contributes.

    With the weighted (standardised) Jacobian J (k, n) at the optimum, the parameters'
    covariance is C = (J^T J)^-1 and the estimate's change with the data is C J^T, so
    C = sum_g C J_g^T J_g C over the groups g of rows: the diagonal of each term, divided by
    diag(C), is group g's share of the variance (shares sum to 1 per parameter).

    Parameters
    ----------
    jac : ndarray (k, n)
        Weighted Jacobian [1 / SI unit of each parameter].
    groups : sequence of str (k,)
        The group of each row.

    Returns
    -------
    sd : ndarray (n,)
        sqrt(diag C) [SI]; NaN when J is rank deficient.
    shares : dict
        group -> ndarray (n,) of shares [-] (empty when rank deficient).
    """
    jac = np.asarray(jac, dtype=float)
    n = jac.shape[1]
    if jac.shape[0] < n or np.linalg.matrix_rank(jac) < n:
        return np.full(n, np.nan), {}
    cov = np.linalg.inv(jac.T @ jac)
    var = np.diag(cov)
    shares = {}
    for g in dict.fromkeys(groups):
        rows = jac[[j for j, h in enumerate(groups) if h == g]]
        a = cov @ rows.T
        shares[g] = np.sum(a * a, axis=1) / var
    return np.sqrt(var), shares


def _starts(u: np.ndarray, costs: np.ndarray, max_starts: int) -> list[int]:
    """The best samples of the coarse search, at most one per box-scaled cell of 1/8."""
    starts: list[int] = []
    for i in np.argsort(costs, kind="stable"):
        if len(starts) >= max(1, int(max_starts)):
            break
        if all(np.max(np.abs(u[i] - u[j])) > 0.125 for j in starts):
            starts.append(int(i))
    return starts


#: Costs this close to the best [-] (weighted, dimensionless) are ties of round-off: an exact
#: fit (cost 0 to 1e-30) with several minima picks by start order, not by the last bit
#: (which differs between processors).
TIE_COST = 1e-16


def _distinct(x: np.ndarray, cost: np.ndarray, width: np.ndarray) -> list[int]:
    """Indices of the distinct minima (box-scaled distance > :data:`MERGE`), best first;
    costs within :data:`TIE_COST` of the best keep their start order."""
    kept: list[int] = []
    tied = np.where(cost <= np.min(cost) + TIE_COST, -np.inf, cost)
    for k in np.lexsort((np.arange(len(cost)), tied)):
        if all(np.max(np.abs(x[k] - x[j]) / width) > MERGE for j in kept):
            kept.append(int(k))
    return kept


@lru_cache(maxsize=64)
def sobol_sample(d: int, samples: int, seed: int) -> np.ndarray:
    """Scrambled Sobol points in the unit cube (2^m >= ``samples`` of them, at least 8),
    seeded so that fits repeat; cached (read-only), as building the generator costs more
    than the fit's coarse evaluation."""
    from scipy.stats import qmc

    m_exp = int(np.ceil(np.log2(max(int(samples), 8))))
    u = qmc.Sobol(d=d, scramble=True, seed=seed).random_base2(m_exp)
    u.flags.writeable = False
    return u


def fit_free(case: Case, box: dict, terms, eps: float = 0.5, beta: float = 0.5, *,
             samples: int = 256, max_starts: int = 5, seed: int = 0,
             mu_c: float | None = None) -> FreeFit:
    """Bounded least squares of the residual ``terms`` over the parameters of ``box``.

    Parameters
    ----------
    case : Case
        Scalar case with ``measured`` set.
    box : dict
        Dotted key -> (low, high) [SI] of every fitted parameter, ``impact.restitution`` and
        ``impact.beta`` included when they are fitted (validated: :func:`check_free`).
    terms : sequence of Term or str
        Residual terms (:func:`pim.analysis.residuals.measured_terms`).
    eps, beta : float
        Restitution and beta where they are not in ``box`` (held fixed).
    samples : int
        Size of the coarse Sobol sample (rounded up to a power of two).
    max_starts : int
        Number of best samples refined locally (distinct ones only).
    seed : int
        Seed of the scrambled Sobol sample.
    mu_c : float, optional
        Contact friction where ``impact.mu_c`` is not in ``box`` (default the case's). The
        impact law is the case's (``impact.law``).
    """
    keys = tuple(box)
    check_free_for_case(case, keys)
    lo, hi = (np.array([box[k][j] for k in keys], dtype=float) for j in (0, 1))
    width = hi - lo
    base = case_state(case, eps, beta, contact_friction=mu_c)
    rows, target, factor = residual_terms(case, terms)
    evidence = split_terms(terms)[1]

    def resid(x, jacobian=True):
        return free_residuals(base, keys, x, rows, target, factor, jacobian=jacobian,
                              evidence=evidence)

    # coarse global search: one vectorised evaluation of the Sobol sample
    u = sobol_sample(len(keys), samples, seed)
    xs = lo + u * width
    r0, _ = resid(xs, jacobian=False)
    starts = _starts(u, np.sum(r0 * r0, axis=1), max_starts)
    # local refinement of every start at once, exact derivatives
    out = least_squares_batch(lambda x, idx: resid(x), xs[starts], lo, hi, merge=MERGE)
    order = _distinct(out.x, out.cost, width)
    best = order[0]
    r, jac = out.residuals[best], out.jacobian[best]
    values = dict(zip(keys, map(float, out.x[best]), strict=True))
    fitted = set_inputs(case, {k: v for k, v in values.items()
                               if k not in ("impact.restitution", "impact.beta", "impact.k")})
    ident = identifiability(jac * width, keys, as_residual_terms(terms))
    if not ident.identifiable:      # name the evidence that would decide it
        candidates = terms_jacobian(case, keys, out.x[best], eps, beta,
                                    candidate_evidence(case, terms), contact_friction=mu_c)
        ident = identifiability(jac * width, keys, as_residual_terms(terms),
                                candidates={k: v * width for k, v in candidates.items()})
    return FreeFit(keys=keys, x=out.x[best], box=np.stack([lo, hi], axis=1), case=fitted,
                   cost=float(r @ r), residuals=r, side=out.on_bound[best].astype(int),
                   gradient=2.0 * (r @ jac),
                   minima=tuple((out.x[k], float(out.cost[k])) for k in order),
                   identifiability=ident, jacobian=jac,
                   nfev=int(out.nfev), converged=bool(out.converged.all()))
