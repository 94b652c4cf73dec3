"""Linear-momentum speeds (pim.analysis.momentum): exact for any momentum-conserving impact
(PIM conserves momentum), flagged and wide when the approach directions are near-collinear."""

import numpy as np
import pytest

import pim
from pim.analysis.momentum import momentum_speeds


def test_recovers_the_speeds_pim_was_given():
    case = pim.load_case("ricsac9")
    result = pim.solve(case, eps=0.355, beta=1.0)
    v1, v2 = case.vehicle1.velocity, case.vehicle2.velocity
    m = momentum_speeds(case.vehicle1.mass, case.vehicle2.mass, v1, v2, result.velocity1,
                        result.velocity2)
    assert m.speed1 == pytest.approx(np.hypot(*v1), rel=1e-10)
    assert m.speed2 == pytest.approx(np.hypot(*v2), rel=1e-10)
    assert not m.ill_conditioned and m.sine == pytest.approx(1.0)


def test_near_collinear_is_wide_and_flagged():
    right = momentum_speeds(1500, 1200, [1, 0], [0, 1], [5, 3], [4, 6],
                            velocity1_sigma=0.3, velocity2_sigma=0.3)
    near = momentum_speeds(1500, 1200, [1, 0], [np.cos(0.05), np.sin(0.05)], [5, 3], [4, 6],
                           velocity1_sigma=0.3, velocity2_sigma=0.3)
    assert near.ill_conditioned and "ill-conditioned" in near.message
    assert near.sigma1 > 10 * right.sigma1
    collinear = momentum_speeds(1500, 1200, [1, 0], [-2, 0], [5, 0], [4, 0])
    assert collinear.ill_conditioned and "under-determined" in collinear.message
    assert np.isnan(collinear.speed1)


def test_sigma_is_the_linear_propagation():
    # u1 = x, u2 = y: s1 = (m1 V1x + m2 V2x) / m1 -> sigma1 = sqrt(s^2 + (m2/m1)^2 s^2)
    m = momentum_speeds(1000, 2000, [1, 0], [0, 1], [1, 1], [1, 1], 0.5, 0.5)
    assert m.sigma1 == pytest.approx(0.5 * np.sqrt(1 + 4), rel=1e-12)
    assert m.sigma2 == pytest.approx(0.5 * np.sqrt(0.25 + 1), rel=1e-12)


def test_bad_direction_names_the_field():
    with pytest.raises(ValueError, match="momentum.direction2"):
        momentum_speeds(1000, 1000, [1, 0], [np.nan, 0], [1, 0], [0, 1])
