"""pim/model/pdof.py: principal direction of force and clock position (SAE J224)."""

import numpy as np
import pytest

from pim.model.pdof import clock_position, pdof, wrap_angle


def test_pdof_of_impulses_from_known_directions():
    heading = np.pi / 2                         # nose toward +y
    # a frontal hit pushes the car backward (-y): it comes from straight ahead -> 0
    assert pdof(np.array([0.0, -100.0]), heading) == pytest.approx(0.0)
    # pushed toward -x, i.e. coming from +x = the car's right side -> +90 deg
    assert pdof(np.array([-100.0, 0.0]), heading) == pytest.approx(np.pi / 2)
    assert pdof(np.array([100.0, 0.0]), heading) == pytest.approx(-np.pi / 2)   # left side
    assert abs(pdof(np.array([0.0, 100.0]), heading)) == pytest.approx(np.pi)   # from behind
    assert np.isnan(pdof(np.array([0.0, 0.0]), heading))                        # no impulse


def test_clock_positions_and_wrapping():
    deg = np.radians([0, 29, 31, 90, -90, 180, -165])
    np.testing.assert_array_equal(clock_position(deg), [12, 1, 1, 3, 9, 6, 6])
    assert clock_position(np.nan) == 0
    np.testing.assert_allclose(wrap_angle(np.array([3 * np.pi, -3 * np.pi + 0.1])),
                               [np.pi, -np.pi + 0.1])
