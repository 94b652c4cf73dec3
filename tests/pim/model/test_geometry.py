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


# Issue 28: the geometry of the plausibility checks (pim.model.plausibility), against an
# independent construction: the general polygon clipping and separating-axis test of
# sim/overlap.py (Sutherland-Hodgman, written for the crush scene) and brute-force sampling.

sizes = st.floats(0.5, 6.0)
coordinates = st.floats(-8.0, 8.0, allow_nan=False)
angles = st.floats(-7.0, 7.0, allow_nan=False)


@given(coordinates, coordinates, angles, sizes, sizes, st.floats(0.0, 1.0), coordinates,
       coordinates)
def test_point_outline_distance_against_the_polygon(cx, cy, heading, length, width, front,
                                                    px, py):
    """Outside: the distance to the nearest edge of the placed rectangle; inside: minus the
    distance to the nearest edge; the sign says which (point-in-polygon by edge normals)."""
    a = front * length
    corners = g.outline_world(length, width, (cx, cy), heading, a)
    p = np.array([px, py])
    edges = [(corners[k], corners[(k + 1) % 4]) for k in range(4)]

    def to_segment(u, v):
        t = np.clip((p - u) @ (v - u) / ((v - u) @ (v - u)), 0.0, 1.0)
        return np.hypot(*(p - u - t * (v - u)))

    nearest = min(to_segment(u, v) for u, v in edges)
    inside = all(g.cross(v - u, p - u) >= 0 for u, v in edges)       # counter-clockwise
    expected = -nearest if inside else nearest
    got = g.point_outline_distance(p, (cx, cy), heading, length, width, a)
    assert got == pytest.approx(expected, abs=1e-9)


@given(coordinates, coordinates, angles, sizes, sizes, coordinates, coordinates, angles,
       sizes, sizes)
def test_outline_penetration_against_sim_overlap(x1, y1, h1, l1, w1, x2, y2, h2, l2, w2):
    """The rectangles' closed-form separating-axis depth equals sim.overlap's general one,
    is symmetric, and is positive exactly when the clipped overlap has an area."""
    from sim.overlap import overlap_area, separating_axis

    p1 = g.outline_world(l1, w1, (x1, y1), h1)
    p2 = g.outline_world(l2, w2, (x2, y2), h2)
    depth = g.outline_penetration(((x1, y1), h1, l1, w1, None), ((x2, y2), h2, l2, w2, None))
    assert depth == pytest.approx(separating_axis(p1, p2)[1], abs=1e-9)
    assert depth == pytest.approx(g.outline_penetration(((x2, y2), h2, l2, w2, None),
                                                        ((x1, y1), h1, l1, w1, None)), abs=1e-9)
    area = overlap_area(p1, p2)
    if depth > 1e-6:
        assert area > 0
    if depth < -1e-6:
        assert area == 0


def test_geometry_broadcasts_over_a_batch():
    heading = np.linspace(0, 2 * np.pi, 5)
    d = g.point_outline_distance(np.zeros((5, 2)), np.zeros(2), heading, 4.0, 2.0)
    np.testing.assert_allclose(d, -1.0)
    angle = g.heading_velocity_angle(heading, [[0.0, 1.0]] * 5)
    np.testing.assert_allclose(np.degrees(angle), [90, 0, 90, 180, 90], atol=1e-9)
    assert np.isnan(g.heading_velocity_angle(0.0, [0.0, 0.0]))
