"""Which (eps, beta) a comparison uses (comparisons.studies.coefficients)."""

import pytest

import pim
from comparisons.studies.coefficients import coefficients


def test_given_coefficients_are_used_as_given():
    case = pim.load_case("ricsac9")
    assert coefficients(case, 0.3, 0.9) == (0.3, 0.9, None)


def test_measured_motion_is_fitted_for_what_is_not_given():
    case = pim.load_case("ricsac9")
    eps, beta, fit = coefficients(case)
    assert isinstance(fit, pim.FitResult)
    assert (eps, beta) == (fit.eps, fit.beta)
    eps, beta, fit = coefficients(case, beta=1.0)
    assert beta == 1.0 and fit is not None and eps == pytest.approx(fit.eps)


def test_bad_given_eps_is_a_value_error():
    with pytest.raises(ValueError, match="eps"):
        coefficients(pim.load_case("ricsac9"), 1.5, 1.0)
