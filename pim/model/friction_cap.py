"""Friction-capped Brach ("brach-capped"): PIM's impulse ratio limited by a friction limit.

PIM's tangential constraint is mu = beta mu0 (Brach & Brach 2011, sec. 6.3), which for a
grazing impact can ask for |mu| well above what sheet metal sliding on sheet metal can
transmit. This law caps the ratio of tangential to normal impulse at a friction coefficient:

    mu = sign(mu0) min(beta |mu0|, limit),

which is PIM's own constraint with the effective fraction beta_eff = min(beta, limit / |mu0|)
(beta >= 0), so the capped answer is :func:`pim.solve` at beta_eff: one formula, solved twice
(once for mu0, once with the capped beta).

It is a variant of Brach's law, not the law of PC-Crash, Virtual CRASH or pycrash's ``cof``:
there (Kudlich-Slibar, :mod:`pim.model.impact_laws`) the cap applies to the compression
impulse, mu0 is taken at eps = 0, and the restitution impulse k times the compression one
leaves a sticking contact with slip -k u_t; here mu0 is taken at the final eps and a sticking
contact ends with no slip. The two agree only at k = 0 or where the contact slides at the cap
with the same ratio.
"""

from __future__ import annotations

import numpy as np

from .case import Case
from .dual import Dual, where
from .numbers import InputError, real_array
from .result import Result
from .solver import constraints, solve

__all__ = ["capped_beta", "solve_capped"]


def capped_beta(mu0, beta, limit):
    """Effective fraction of mu0 under a friction cap: min(beta, limit / |mu0|) [-].

    Parameters
    ----------
    mu0 : array_like or Dual
        Critical impulse ratio [-] (Brach eq. 6.60).
    beta : array_like or Dual
        Requested fraction of mu0 [-], >= 0.
    limit : array_like or Dual
        Friction limit [-], >= 0: the largest |Pt / Pn| the contact can transmit.

    Returns
    -------
    ndarray or Dual
        beta_eff, such that beta_eff mu0 = sign(mu0) min(beta |mu0|, limit); equal to beta
        where mu0 = 0. On dual numbers (:mod:`pim.model.dual`) the derivative is that of
        the side taken: beta's where beta |mu0| <= limit (the cap is not reached, ties
        included), limit / |mu0|'s beyond (the cap is a kink).
    """
    if not any(isinstance(v, Dual) for v in (mu0, beta, limit)):
        mu0, beta, limit = np.broadcast_arrays(np.asarray(mu0, float), np.asarray(beta, float),
                                               np.asarray(limit, float))
    size = abs(mu0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return where(beta * size <= limit, beta, limit / size)


def solve_capped(case: Case, eps=None, beta=None, limit=np.inf) -> Result:
    """:func:`pim.solve` with the impulse ratio capped at a friction limit.

    Parameters
    ----------
    case : Case
        The impact.
    eps, beta : array_like, optional
        As for :func:`pim.solve` (beta must be >= 0 here).
    limit : array_like
        Friction limit [-], >= 0 (inf: no cap, the plain PIM answer).

    Returns
    -------
    Result
        The post-impact state at mu = sign(mu0) min(beta |mu0|, limit); ``result.beta`` is
        the effective beta.
    """
    limit = real_array(limit, "friction limit")
    if np.isnan(limit).any() or (limit < 0).any():
        raise InputError("friction limit must be >= 0 (inf for no cap)")
    eps, beta = constraints(case, eps, beta)
    if (beta < 0).any():
        raise InputError("beta must be >= 0 with a friction limit (the cap bounds |mu|)")
    critical = solve(case, eps, 1.0)
    return solve(case, eps, capped_beta(critical.mu0, beta, limit))
