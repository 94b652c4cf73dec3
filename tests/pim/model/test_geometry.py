"""pim/model/geometry.py: vector helpers and rigid-body quantities against closed forms."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pim.model import geometry as g

finite = st.floats(-1e3, 1e3, allow_nan=False)


@given(finite, finite, finite, finite, st.floats(-10, 10))
def test_cross_dot_perp_rotate_identities(ax, ay, bx, by, angle):
    a, b = np.array([ax, ay]), np.array([bx, by])
    assert g.cross(a, b) == pytest.approx(np.cross(np.r_[a, 0], np.r_[b, 0])[2], abs=1e-9)
    assert g.dot(a, b) == pytest.approx(a @ b, abs=1e-9)
    assert g.dot(g.perp(a), a) == 0.0 and g.cross(a, g.perp(a)) == pytest.approx(a @ a)
    r = g.rotate(a, angle)
    assert np.hypot(*r) == pytest.approx(np.hypot(*a), rel=1e-12, abs=1e-12)
    assert g.cross(a, r) == pytest.approx((a @ a) * math.sin(angle), abs=1e-7 * (1 + a @ a))


def test_contact_velocity_of_a_spinning_body():
    # w = 2 rad/s about the CG, point 1.5 m ahead on +x: it moves +3 m/s along +y
    np.testing.assert_allclose(g.contact_velocity([1.0, 0.0], 2.0, [1.5, 0.0]), [1.0, 3.0])


def test_kinetic_energy_and_gyration():
    assert g.kinetic_energy(2.0, 3.0, [3.0, 4.0], 2.0) == pytest.approx(0.5 * 2 * 25 + 0.5 * 3 * 4)
    assert g.kinetic_energy(np.inf, np.inf, [0.0, 0.0], 0.0) == 0.0   # a fixed obstacle
    assert g.radius_of_gyration(1500.0, 1500.0 * 1.2 ** 2) == pytest.approx(1.2)
    assert g.radius_of_gyration(np.inf, np.inf) == 0.0


def test_outline_corners_start_front_left_counter_clockwise():
    c = g.outline_corners(4.0, 2.0)
    np.testing.assert_array_equal(c, [[2, 1], [-2, 1], [-2, -1], [2, -1]])
    assert 0.5 * np.sum(c[:, 0] * np.roll(c[:, 1], -1) - np.roll(c[:, 0], -1) * c[:, 1]) == 8.0
    # heading 90 deg: the front-left corner is at (-1, +2) from the CG
    w = g.outline_world(4.0, 2.0, (10.0, 0.0), np.pi / 2)
    np.testing.assert_allclose(w[0], [9.0, 2.0], atol=1e-12)


def test_outline_distance_hits_the_right_edge():
    from pim.model.geometry import outline_distance

    # 4 m x 2 m, CG in the middle: ahead 2 m, sideways 1 m, to the corner sqrt(5)
    np.testing.assert_allclose(outline_distance([0.0, np.pi / 2, np.pi, np.arctan2(1, 2)],
                                                4.0, 2.0),
                               [2.0, 1.0, 2.0, np.sqrt(5.0)], rtol=1e-12)
    # CG 1.5 m behind the front: backwards 2.5 m; 30 deg ahead: front edge 1.5 / cos 30
    np.testing.assert_allclose(outline_distance([np.pi, np.radians(30)], 4.0, 2.0, 1.5),
                               [2.5, 1.5 / np.cos(np.radians(30))], rtol=1e-12)


@given(length=st.floats(0.5, 20), width=st.floats(0.5, 5), share=st.floats(0, 1),
       angle=st.floats(-math.pi, math.pi))
def test_outline_with_cg_to_front_agrees_with_outline_distance(length, width, share, angle):
    """The vehicle table's cg_to_front (issue 22): the outline spans [a - length, a] x
    [-w/2, w/2] with the CG at the origin, the same rectangle outline_distance measures."""
    a = share * length
    c = g.outline_corners(length, width, a)
    assert c[:, 0].max() == pytest.approx(a) and c[:, 0].min() == pytest.approx(a - length)
    assert np.allclose(g.outline_corners(length, width, length / 2),
                       g.outline_corners(length, width))
    r = float(g.outline_distance(angle, length, width, a))
    x, y = r * math.cos(angle), r * math.sin(angle)       # on the rectangle's boundary
    assert a - length - 1e-9 <= x <= a + 1e-9 and abs(y) <= width / 2 + 1e-9
    assert min(abs(x - a), abs(x - (a - length)), abs(abs(y) - width / 2)) < 1e-9 * length
