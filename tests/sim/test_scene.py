"""The pymunk scene of a case (sim.scene)."""

import numpy as np
import pytest

import pim
from sim.scene import footprint_lever, outline_corners, resolve_coefficients


def test_outline_and_footprint_lever():
    v = pim.load_case("ricsac9").vehicle1
    corners = outline_corners(v)
    assert corners.shape == (4, 2)
    np.testing.assert_allclose(np.ptp(corners, axis=0), [float(v.length), float(v.width)])
    # mean distance of a uniform L x W rectangle from its centre, by dense midpoint sampling
    n = 400
    x = (np.arange(n) + 0.5) / n - 0.5
    grid = np.hypot(*np.meshgrid(x * float(v.length), x * float(v.width)))
    assert footprint_lever(v) == pytest.approx(grid.mean(), rel=1e-3)


def test_coefficients_outside_coulomb_are_rejected():
    case = pim.load_case("ricsac9")
    assert resolve_coefficients(case, 0.3, 0.5) == (0.3, 0.5)
    with pytest.raises(ValueError, match="beta"):
        resolve_coefficients(case, 0.3, 1.5)
