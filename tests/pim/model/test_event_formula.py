"""The event's contact geometry and secondary impact (pim.model.event_formula): configurations
checked by hand, and the further impact under each law against pim.solve (the library's
laws)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import pim
from pim.model import event_formula as ef
from pim.model.geometry import outline_penetration


REST = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def _box(x, y, psi, length=4.0, width=2.0, front=None):
    return ef.box(x, y, psi, length / 2 if front is None else front, length, width)


def test_corner_into_edge_by_hand():
    # box 2 (4 x 2) at the origin, axis-aligned; box 1 turned 45 deg with its lowest corner
    # 5 cm below box 2's top edge (y = 1): C is that corner, Gamma the edge's normal +y
    psi = math.radians(45.0)
    low = 2.0 * math.sin(psi) + 1.0 * math.cos(psi)     # its lowest corner below the centre
    b1 = _box(0.3, 1.0 + low - 0.05, psi)
    b2 = _box(0.0, 0.0, 0.0)
    depth, cx, cy, nx, ny, _ = ef.contact_geometry(b1, b2, REST, REST)
    assert depth == pytest.approx(0.05, abs=1e-12)
    assert (nx, ny) == pytest.approx((0.0, 1.0), abs=1e-12)
    # the lowest corner, centre + R(psi) (-2, -1), by hand
    corner_x = 0.3 - 2.0 * math.cos(psi) + 1.0 * math.sin(psi)
    assert (cx, cy) == pytest.approx((corner_x, 0.95), abs=1e-12)


def test_parallel_sides_give_the_middle_of_the_shared_stretch():
    # a side slap: box 1 beside box 2, shifted 1 m along x, sides overlapping by 2 cm
    b1 = _box(1.0, 1.98, 0.0)
    b2 = _box(0.0, 0.0, 0.0)
    depth, cx, cy, nx, ny, _ = ef.contact_geometry(b1, b2, REST, REST)
    assert depth == pytest.approx(0.02)
    assert (nx, ny) == pytest.approx((0.0, 1.0))
    # shared stretch x in [-1, 2] (box 1 spans [-1, 3], box 2 [-2, 2]): middle 0.5
    assert cx == pytest.approx(0.5)
    assert cy == pytest.approx(0.99)


def test_normal_points_from_vehicle2_to_vehicle1():
    b1 = _box(-3.98, 0.0, 0.0)       # vehicle 1 behind (to -x of) vehicle 2
    b2 = _box(0.0, 0.0, 0.0)
    _, _, _, nx, ny, _ = ef.contact_geometry(b1, b2, REST, REST)
    assert (nx, ny) == pytest.approx((-1.0, 0.0))


@settings(max_examples=200, deadline=None)
@given(st.floats(-6, 6), st.floats(-6, 6), st.floats(-3.2, 3.2), st.floats(-3.2, 3.2),
       st.floats(0.3, 4.5))
def test_depth_is_the_separating_axis_depth(x, y, a1, a2, front):
    b1 = ef.box(x, y, a1, front, 4.5, 1.8)
    b2 = ef.box(0.0, 0.0, a2, 2.0, 4.0, 1.7)
    depth = ef.contact_geometry(b1, b2, REST, REST)[0]
    expected = outline_penetration(((x, y), a1, 4.5, 1.8, front), ((0.0, 0.0), a2, 4.0, 1.7, 2.0))
    assert depth == pytest.approx(float(expected), abs=1e-9)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.05, 2.0),
       st.floats(-math.pi, math.pi), st.floats(-20, 20), st.floats(-20, 20),
       st.floats(-2, 2))
def test_capped_impact_is_pim_solve_capped(eps, beta, cap, gamma, vx, vy, w):
    assume(abs(vx) + abs(vy) > 0.1)      # (pim.solve_capped has no mu0 with no motion)
    s1 = (0.0, 0.0, 0.3, vx, vy, w)
    s2 = (3.0, 1.0, -0.2, 0.0, 0.0, 0.0)
    c = (1.4, 0.7)
    n = (math.cos(gamma), math.sin(gamma))
    out = ef.capped_impact(c[0], c[1], n[0], n[1], s1, s2, (1 / 1500, 1 / 2500, 1 / 1200,
                                                            1 / 2000),
                           (eps, beta, cap), (1e-12, 1e-12))
    case = pim.Case(pim.Vehicle(1500.0, 2500.0, (0.0, 0.0), (vx, vy), w, 0.3),
                    pim.Vehicle(1200.0, 2000.0, (3.0, 1.0), (0.0, 0.0), 0.0, -0.2),
                    pim.Impact(c, gamma))
    ref = pim.solve_capped(case, eps, beta, cap)
    if float(ref.energy_loss) < 0:       # Kane and Levinson's paradox: solved frictionless
        ref = pim.solve_capped(case, eps, 0.0, cap)
    if not bool(ref.approaching):
        assert out[0] == 0.0 and out[1] == 0.0
        return
    scale = 1 + float(np.hypot(*ref.impulse))
    assert out[:2] == pytest.approx(tuple(ref.impulse), abs=1e-9 * scale)
    assert out[2:4] == pytest.approx(tuple(ref.velocity1), abs=1e-9 * (1 + abs(vx) + abs(vy)))
    assert out[5:7] == pytest.approx(tuple(ref.velocity2), abs=1e-9 * (1 + abs(vx) + abs(vy)))
    assert out[4] == pytest.approx(float(ref.yaw_rate1), abs=1e-9 * (1 + abs(w)))


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 3.0), st.floats(-math.pi, math.pi),
       st.floats(-20, 20), st.floats(-20, 20), st.floats(-2, 2), st.floats(-1.5, 1.5))
def test_kudlich_slibar_impact_is_pim_solve(k, mu_c, gamma, vx, vy, w, cy):
    """The kernel's Kudlich-Slibar impact (PIM at eps = k with the compression impulse's
    ratio) against pim.solve's law (the compression impulse's own vector formula,
    pim.model.impact_laws.solve_kudlich_slibar): the same impulse and motion."""
    s1 = (0.0, 0.0, 0.3, vx, vy, w)
    s2 = (3.0, 1.0, -0.2, 0.5, -0.3, 0.1)
    c = (1.4, cy)
    n = (math.cos(gamma), math.sin(gamma))
    inverse = (1 / 1500, 1 / 2500, 1 / 1200, 1 / 2000)
    out = ef.further_impact(c[0], c[1], n[0], n[1], s1, s2, inverse,
                            (k, 0.7, mu_c, ef.KUDLICH_SLIBAR), (1e-12, 1e-12))
    case = pim.Case(pim.Vehicle(1500.0, 2500.0, (0.0, 0.0), (vx, vy), w, 0.3),
                    pim.Vehicle(1200.0, 2000.0, (3.0, 1.0), (0.5, -0.3), 0.1, -0.2),
                    pim.Impact(c, gamma))
    ref = pim.solve(case, law="kudlich-slibar", k=k, mu_c=mu_c)
    assume(not bool(ref.q_singular))
    if not bool(ref.approaching):
        assert out[0] == 0.0 and out[1] == 0.0
        return
    scale = 1 + float(np.hypot(*ref.impulse))
    speed = 1 + abs(vx) + abs(vy)
    assert out[:2] == pytest.approx(tuple(ref.impulse), abs=1e-9 * scale)
    assert out[2:4] == pytest.approx(tuple(ref.velocity1), abs=1e-9 * speed)
    assert out[5:7] == pytest.approx(tuple(ref.velocity2), abs=1e-9 * speed)
    assert (out[4], out[7]) == pytest.approx((float(ref.yaw_rate1), float(ref.yaw_rate2)),
                                             abs=1e-9 * (1 + abs(w)))


def test_further_impact_dispatches_on_the_law():
    """Law codes 0 and 1 are the capped Brach impact (an infinite cap: Brach's own),
    code 2 Kudlich-Slibar's: at a sliding contact they differ."""
    s1, s2 = (0.0, 0.0, 0.0, 0.0, -5.0, 0.0), (0.0, -3.0, 0.0, 3.0, 0.0, 0.0)
    args = (0.5, -1.0, 0.0, 1.0, s1, s2, (1 / 1500, 1 / 2500, 1 / 1500, 1 / 2500))
    brach = ef.further_impact(*args, (0.2, 1.0, np.inf, 0.0), (1e-12, 1e-12))
    capped = ef.further_impact(*args, (0.2, 1.0, 0.1, 1.0), (1e-12, 1e-12))
    ks = ef.further_impact(*args, (0.2, 1.0, 0.1, ef.KUDLICH_SLIBAR), (1e-12, 1e-12))
    assert brach == ef.capped_impact(*args, (0.2, 1.0, np.inf), (1e-12, 1e-12))
    assert capped == ef.capped_impact(*args, (0.2, 1.0, 0.1), (1e-12, 1e-12))
    assert abs(ks[0] / ks[1]) == pytest.approx(0.1) and ks[8] == pytest.approx(-0.1)
    assert ks[:8] != capped[:8]


def test_closing_speed_sign():
    s1 = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0)
    s2 = (5.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    # n from 2 toward 1 is -x; vehicle 1 moves toward 2 (+x): u.n = -1 (closing)
    assert ef.closing_speed(2.5, 0.0, -1.0, 0.0, s1, s2) == pytest.approx(-1.0)


def test_bound_radius_holds_the_far_corner():
    assert float(ef.bound_radius(1.0, 4.0, 2.0)) == pytest.approx(math.hypot(3.0, 1.0))


def test_only_closing_corners_make_c():
    """Two corners inside, vehicle 1's rear-right (-1, 0.98) and vehicle 2's front-left
    (2, 1); vehicle 1 turns clockwise about its CG (1, 1.98), so the relative velocity
    along n = +y is u_y = -(x - 1): the first parts (+2 m/s), the second closes (-1 m/s).
    C is the closing one (an earlier overlap that parts makes no contact)."""
    b1 = _box(1.0, 1.98, 0.0)
    b2 = _box(0.0, 0.0, 0.0)
    s1 = (1.0, 1.98, 0.0, 0.0, 0.0, -1.0)
    depth, cx, cy, nx, ny, closing = ef.contact_geometry(b1, b2, s1, REST)
    assert closing == 1
    assert (cx, cy) == pytest.approx((2.0, 1.0))
    assert ef.contact_geometry(b1, b2, REST, REST)[1:3] == pytest.approx((0.5, 0.99))
