"""pim/io/brach.py: Brach's (theta, phi, d) adapter, checked by hand on simple geometry."""

import numpy as np
import pytest

import pim
from pim.io.brach import brach_angles, brach_arms, cg_from_brach, heading_from_theta


def test_vehicle1_datum_is_rotated_by_pi():
    assert heading_from_theta(0.0, 1) == pytest.approx(np.pi)
    assert heading_from_theta(0.3, 2) == pytest.approx(0.3)
    with pytest.raises(ValueError, match="vehicle must be 1 or 2"):
        heading_from_theta(0.0, 3)


def test_cg_from_brach_by_hand():
    # vehicle 2 heading +y (theta 90 deg), C 2 m ahead of its CG (phi 0): CG = C - (0, 2)
    np.testing.assert_allclose(cg_from_brach(np.pi / 2, 0.0, 2.0, 2, point=(1.0, 1.0)),
                               [1.0, -1.0], atol=1e-12)
    with pytest.raises(ValueError, match="d"):
        cg_from_brach(0.0, 0.0, -1.0, 2)


def test_angles_and_arms_round_trip_on_ricsac9():
    case = pim.load_case("ricsac9")
    angles = brach_angles(case)
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        cg = cg_from_brach(angles[f"theta{i}"], angles[f"phi{i}"], angles[f"d{i}"], i,
                           case.impact.point)
        np.testing.assert_allclose(cg, v.cg, atol=1e-12)
    arms = brach_arms(case)
    # Gamma = 0: n = +x, so d_b = x of C - CG2 and d_d = -(x of C - CG1)
    assert arms["d_b"] == pytest.approx(case.impact.point[0] - case.vehicle2.cg[0])
    assert arms["d_d"] == pytest.approx(-(case.impact.point[0] - case.vehicle1.cg[0]))
