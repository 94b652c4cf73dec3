"""Inverse PIM: the pre-impact unknowns (speeds, velocities, yaw rates, eps, beta ...) from
the measured post-impact motion.

The unknowns are the ``[unknown]`` table's dotted keys (:data:`pim.analysis.free_inputs.FREE_KEYS`,
e.g. ``vehicle1.speed`` along the case's direction of travel); the data are the measured
post-impact velocities and yaw rates with their standard deviations as weights (the
``[measured]`` sigmas). :func:`inverse_pim` is :func:`pim.analysis.fitting.fit` with
``free=`` the unknowns: a vectorised Sobol search, then a batched Levenberg-Marquardt on
exact derivatives, with the rank, families and bounds it reports. Restitution and beta not
named in the table stay as the case gives them (beta 1 when it gives none).

Before any number is given, :func:`under_determined` compares the unknowns with the data:
more unknowns than measured quantities is said plainly, naming what is missing (which
vehicle's post-impact motion); a rank-deficient fit (a family of exact solutions) likewise.

:func:`inverse_pim_many` solves many such problems at once (one per Monte Carlo sample),
each with its own inputs and measured motion, starting from the nominal solution.
"""

from __future__ import annotations

import numpy as np

from ..model.case import Case, Measured
from ..model.numbers import InputError, speed_text
from ..model.solver import defaults
from .fitting import FitResult, fit
from .free_fit import (
    candidate_evidence,
    evidence_list,
    free_residuals,
    identifiability,
    terms_jacobian,
)
from .free_inputs import check_free
from .least_squares_batch import BatchFit, least_squares_batch
from .residuals import measured_terms

__all__ = ["inverse_pim", "inverse_pim_many", "under_determined", "fixed_coefficients",
           "check_evidence"]


def fixed_coefficients(case: Case, unknown: dict) -> tuple:
    """(eps, beta) held fixed: None where the table names it as unknown, else the case's
    (beta defaults to 1). Under "kudlich-slibar": (k, mu_c), k named ``impact.k`` or
    ``impact.restitution``."""
    ks = case.impact.law == "kudlich-slibar"
    named = "impact.restitution" in unknown or (ks and "impact.k" in unknown)
    eps = None if named else case.impact.restitution
    if not named and eps is None:
        raise InputError("impact.restitution: not given in [impact] and not named in "
                         "[unknown]; give it or solve for it")
    if ks:
        mu_c = None if "impact.mu_c" in unknown else case.impact.contact_friction
        if mu_c is None and "impact.mu_c" not in unknown:
            raise InputError("impact.contact_friction: not given in [impact] and not named "
                             "in [unknown] (impact.mu_c); give it or solve for it")
        return eps, mu_c
    beta = None if "impact.beta" in unknown else defaults(case, 0.0, None)[1]
    return eps, beta


def check_evidence(case: Case, unknown: dict) -> None:
    """InputError naming the field when the recorded evidence cannot agree with the
    unknowns' bounds: a recorded delta-V of a vehicle larger than every speed bound of the
    ``[unknown]`` table (no impact within the bounds changes a speed by more than the
    closing speed, itself within them)."""
    bounds = [hi for key, (_, hi) in unknown.items() if key.endswith(".speed")]
    m = case.measured
    if not bounds or m is None:
        return
    for i in (1, 2):
        dv = getattr(m, f"delta_v{i}")
        if dv is not None and float(np.hypot(*dv)) > max(bounds):
            raise InputError(f"measured.vehicle{i}.delta_v: |delta-V| = "
                             f"{speed_text(np.hypot(*dv))} is larger than every speed "
                             f"bound of [unknown] (at most {speed_text(max(bounds))}); check "
                             f"its unit and the bounds")


def under_determined(case: Case, unknown: dict, include_yaw: bool = True) -> str:
    """Why the unknowns cannot be decided by the measured data, or "" when they may be.

    Counts the unknowns (with restitution and beta when named) against the measured
    quantities, names the vehicles whose post-impact motion is missing and the evidence that
    would decide the unknowns: each candidate's Jacobian rows, at the middle of the
    unknowns' bounds, tested against the null directions of the data's Jacobian
    (:func:`pim.analysis.free_fit.deciding_evidence`).
    """
    names = measured_terms(case, include_yaw)
    n_unknown, n_data = len(unknown), len(names)
    if n_unknown <= n_data:
        return ""
    m = case.measured if case.measured is not None else Measured()
    deciding = _deciding(case, unknown, names)
    # a vehicle's missing motion is named when its rest position would help (or when the
    # candidates could not be evaluated)
    helps = [i for i in (1, 2) if not deciding
             or f"vehicle{i}'s rest position (its post-impact motion)" in deciding]
    missing = [f"vehicle{i}'s post-impact {what}" for i in helps for what, value in (
        ("velocity", getattr(m, f"velocity{i}")),
        ("yaw rate", getattr(m, f"yaw_rate{i}") if include_yaw else 0.0)) if value is None
        and not np.any(getattr(case, f"vehicle{i}").fixed)]
    hint = (f"; missing: {', '.join(missing)} (evidence of that vehicle's rest position "
            "gives it)" if missing else "" if deciding else
            "; fix some of them (e.g. beta = 1) instead")
    if deciding:
        hint += f"; evidence that would decide it: {evidence_list(deciding)}"
    return (f"under-determined: {n_unknown} unknowns ({', '.join(unknown)}) but only "
            f"{n_data} measured quantities ({', '.join(t.name for t in names)}){hint}")


def _deciding(case: Case, unknown: dict, names) -> list[str]:
    """Labels of the candidate evidence that would decide some of the unknowns' null
    directions at the middle of their bounds (:func:`pim.analysis.free_fit.deciding_evidence`)."""
    keys = tuple(unknown)
    lo, hi = (np.array([unknown[k][j] for k in keys], dtype=float) for j in (0, 1))
    x, width = (lo + hi) / 2, hi - lo
    eps = 0.5 if case.impact.restitution is None else case.impact.restitution
    beta = 1.0 if case.impact.beta is None else case.impact.beta
    groups = {"data": names, **candidate_evidence(case, names)}
    jac = {k: v * width for k, v in terms_jacobian(case, keys, x, eps, beta, groups).items()}
    data = jac.pop("data")
    ident = identifiability(np.where(np.isfinite(data), data, 0.0), keys, names,
                            candidates=jac)
    return [label for label, _ in ident.deciding]


def inverse_pim(case: Case, unknown: dict | None = None, *, include_yaw: bool = True,
                samples: int = 256, seed: int = 0) -> FitResult:
    """The unknowns that best reproduce the measured post-impact motion.

    Parameters
    ----------
    case : Case
        Single case with ``measured`` (sigmas weight the residuals when given).
    unknown : dict, optional
        Dotted key -> (low, high) [SI]; default ``case.unknown`` (the ``[unknown]`` table).
    include_yaw : bool
        Fit the measured yaw rates too (default).
    samples, seed : int
        Coarse search size and seed (:func:`pim.analysis.fitting.fit`).

    Returns
    -------
    FitResult
        ``values`` holds every unknown by its key [SI]; ``identifiability`` says whether the
        data decide them.

    Raises
    ------
    ValueError
        No unknowns, bad bounds, nothing measured, or more unknowns than measured quantities
        (the message names what is missing).
    """
    unknown = check_free(case.unknown if unknown is None else unknown)
    if not unknown:
        raise InputError("unknown: nothing to solve for (the case has no [unknown] table)")
    check_evidence(case, unknown)
    why = under_determined(case, unknown, include_yaw)
    if why:
        raise InputError(why)
    eps, second = fixed_coefficients(case, unknown)
    if case.impact.law == "kudlich-slibar":
        return fit(case, include_yaw=include_yaw, eps=eps, mu_c=second, free=unknown,
                   samples=samples, seed=seed)
    return fit(case, include_yaw=include_yaw, eps=eps, beta=second, free=unknown,
               samples=samples, seed=seed)


def inverse_pim_many(base, keys, bounds, x0, rows, target, factor, evidence=()) -> BatchFit:
    """Many inverse problems at once: sample p has state ``base[p]`` (the model's inputs,
    :func:`pim.analysis.free_inputs.case_state`) and measured ``target[p]``.

    Parameters
    ----------
    base : ndarray (m, 23)
        Everything not solved for, per sample.
    keys : sequence of str
        The unknowns (restitution and beta first when they are unknown).
    bounds : sequence of (low, high)
        Per key [SI].
    x0 : array_like (n,) or (m, n)
        Starting point(s): the nominal solution.
    rows, target, factor :
        Residual terms (:func:`pim.analysis.free_fit.residual_terms`); target and factor
        (m, k) or (k,).
    evidence : sequence of EvidenceTerm
        The evidence terms after the motion rows (:func:`pim.analysis.free_fit.free_residuals`).

    Returns
    -------
    BatchFit
    """
    base = np.asarray(base, dtype=float)
    m = base.shape[0]
    k = len(rows) + len(evidence)
    target = np.broadcast_to(np.asarray(target, dtype=float), (m, k))
    factor = np.broadcast_to(np.asarray(factor, dtype=float), (m, k))
    lo = np.array([b[0] for b in bounds], dtype=float)
    hi = np.array([b[1] for b in bounds], dtype=float)
    x0 = np.broadcast_to(np.asarray(x0, dtype=float), (m, len(keys)))

    def fun(x, idx):
        return free_residuals(base[idx], keys, x, rows, target[idx], factor[idx],
                              evidence=[t.take(idx) for t in evidence])

    return least_squares_batch(fun, x0, lo, hi, max_iter=100)
