"""pim/analysis/residuals.py: residuals are V - V_measured and k (W - W_measured)."""

from dataclasses import replace

import numpy as np
import pytest

import pim
from pim.analysis.residuals import (
    has_measured_terms,
    measured_terms,
    residuals,
    residuals_and_jacobian,
)


@pytest.fixture()
def ricsac9():
    return pim.load_case("ricsac9")


def test_residuals_by_hand(ricsac9):
    r = pim.solve(ricsac9, 0.3, 0.8)
    m = ricsac9.measured
    names = measured_terms(ricsac9, include_yaw=True)
    got = dict(zip(names, residuals(r, names), strict=True))
    assert got["velocity1_x"] == pytest.approx(r.velocity1[0] - m.velocity1[0])
    assert got["velocity2_y"] == pytest.approx(r.velocity2[1] - m.velocity2[1])
    k1 = np.sqrt(float(ricsac9.vehicle1.yaw_inertia) / float(ricsac9.vehicle1.mass))
    assert got["yaw_rate1"] == pytest.approx(k1 * (float(r.yaw_rate1) - m.yaw_rate1))


def test_jacobian_matches_finite_differences(ricsac9):
    names = measured_terms(ricsac9, include_yaw=True)
    _, jac = residuals_and_jacobian(pim.solve(ricsac9, 0.3, 0.8), names)
    h = 1e-6
    fd_e = (residuals(pim.solve(ricsac9, 0.3 + h, 0.8), names)
            - residuals(pim.solve(ricsac9, 0.3 - h, 0.8), names)) / (2 * h)
    np.testing.assert_allclose(jac[:, 0], fd_e, rtol=1e-6, atol=1e-8)


def test_nothing_measured(ricsac9):
    bare = replace(ricsac9, measured=None)
    assert not has_measured_terms(bare) and has_measured_terms(ricsac9)
    only_yaw = replace(ricsac9, measured=pim.Measured(yaw_rate1=-3.0))
    assert not has_measured_terms(only_yaw) and has_measured_terms(only_yaw, include_yaw=True)
    with pytest.raises(ValueError, match="--include-yaw"):
        measured_terms(only_yaw, include_yaw=False)
