"""Which (epsilon, beta) a comparison uses: given, fitted to the measured motion, or the
case's own."""

from __future__ import annotations

import pim
from pim.analysis.residuals import has_measured_terms
from pim.model.solver import constraints

__all__ = ["coefficients"]


def coefficients(case: pim.Case, eps=None, beta=None):
    """(eps, beta, fit): the given coefficients, the least-squares fit to the case's measured
    motion for those not given (fit is then the :class:`pim.FitResult`, else None), or the
    case's own (beta 1 when the case has none).

    Raises
    ------
    ValueError
        No eps given, none in the case and nothing measured to fit.
    """
    fit = None
    if has_measured_terms(case) and (eps is None or beta is None):
        fit = pim.fit(case, eps=eps, beta=beta)
        eps, beta = fit.eps, fit.beta
    eps, beta = constraints(case, eps, beta)   # the case's own where not given, checked
    return float(eps), float(beta), fit
