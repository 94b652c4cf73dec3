"""Which (epsilon, beta) a comparison uses: given, fitted to the measured motion, or the
case's own."""

from __future__ import annotations

import pim

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
    has_measured = case.measured is not None and (
        case.measured.velocity1 is not None or case.measured.velocity2 is not None)
    if has_measured and (eps is None or beta is None):
        fit = pim.fit(case, eps=eps, beta=beta)
        eps, beta = fit.eps, fit.beta
    if eps is None:
        eps = case.impact.restitution
        if eps is None:
            raise ValueError("eps is required: the case has no impact.restitution and no "
                             "measurements to fit")
    if beta is None:
        beta = 1.0 if case.impact.beta is None else case.impact.beta
    return float(eps), float(beta), fit
