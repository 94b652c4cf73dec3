"""pim/analysis/free_inputs.py: what each free key moves, checked against geometry worked
out by hand (Brach's arm, the contact tangent, v = s u, I = m k^2), and the exact Jacobian of
the map against central differences."""

from __future__ import annotations

import numpy as np
import pytest

import pim
from pim.analysis.free_inputs import (
    FREE_KEYS,
    STATE,
    approach_direction,
    case_state,
    check_free,
    current_value,
    free_inputs,
    set_inputs,
)
from pim.io.brach import cg_from_brach


@pytest.fixture(scope="module")
def ricsac9():
    return pim.load_case("ricsac9")


def test_phi_and_d_move_the_cg_about_c_as_brach_defines_them(ricsac9):
    # vehicle 2: true heading 90 deg; Brach's arm CG -> C points at heading + phi
    c = set_inputs(ricsac9, {"vehicle2.phi": np.radians(-30.0), "vehicle2.d": 2.0})
    h = float(ricsac9.vehicle2.heading)
    point = np.asarray(ricsac9.impact.point)
    want = point - 2.0 * np.array([np.cos(h - np.radians(30.0)), np.sin(h - np.radians(30.0))])
    np.testing.assert_allclose(c.vehicle2.cg, want, atol=1e-12)
    # the same through the Brach adapter (theta2 = heading for vehicle 2)
    np.testing.assert_allclose(c.vehicle2.cg, cg_from_brach(h, np.radians(-30.0), 2.0, 2,
                                                            point), atol=1e-12)
    np.testing.assert_allclose(c.vehicle1.cg, ricsac9.vehicle1.cg)       # untouched
    assert current_value(c, "vehicle2.phi") == pytest.approx(np.radians(-30.0), abs=1e-12)
    assert current_value(c, "vehicle2.d") == pytest.approx(2.0, rel=1e-12)


def test_phi_alone_keeps_the_arm_length(ricsac9):
    d0 = current_value(ricsac9, "vehicle1.d")
    c = set_inputs(ricsac9, {"vehicle1.phi": 0.1})
    assert np.hypot(*(c.impact.point - c.vehicle1.cg)) == pytest.approx(d0, rel=1e-12)


def test_point_along_slides_c_along_the_contact_tangent(ricsac9):
    g = 0.3
    case = set_inputs(ricsac9, {"impact.normal_angle": g})
    moved = set_inputs(case, {"impact.point_along": 0.5})
    np.testing.assert_allclose(moved.impact.point - case.impact.point,
                               0.5 * np.array([-np.sin(g), np.cos(g)]), atol=1e-12)
    np.testing.assert_allclose(moved.vehicle1.cg, case.vehicle1.cg)
    np.testing.assert_allclose(moved.vehicle2.cg, case.vehicle2.cg)
    assert current_value(moved, "impact.point_along") == 0.0


def test_speed_and_radius_of_gyration(ricsac9):
    c = set_inputs(ricsac9, {"vehicle1.speed": 5.0, "vehicle2.radius_of_gyration": 1.5})
    np.testing.assert_allclose(c.vehicle1.velocity, 5.0 * approach_direction(ricsac9.vehicle1))
    assert float(c.vehicle2.yaw_inertia) == pytest.approx(float(ricsac9.vehicle2.mass) * 2.25)
    # a vehicle at rest: the direction is its heading
    still = pim.Vehicle(mass=1000.0, yaw_inertia=1500.0, cg=(0, 0), velocity=(0, 0),
                        heading=np.radians(30.0))
    np.testing.assert_allclose(approach_direction(still),
                               [np.cos(np.radians(30.0)), np.sin(np.radians(30.0))])


def test_the_map_jacobian_is_exact(ricsac9):
    keys = ("impact.point_along", "impact.normal_angle", "vehicle1.phi", "vehicle1.d",
            "vehicle2.speed", "vehicle2.radius_of_gyration", "vehicle2.mass",
            "vehicle1.heading")
    x0 = np.array([0.2, 0.1, 0.3, 2.1, 9.0, 1.4, 2100.0, 3.0])
    _, jac = free_inputs(ricsac9, keys, x0[None], jacobian=True)
    for j in range(len(keys)):
        h = 1e-6 * max(1.0, abs(x0[j]))
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        sp, sm = free_inputs(ricsac9, keys, xp[None])[0], free_inputs(ricsac9, keys, xm[None])[0]
        with np.errstate(invalid="ignore"):       # an unused mu_c column is inf in both
            fd = np.where(sp == sm, 0.0, sp - sm)
        np.testing.assert_allclose(jac[0, :, j], fd[0] / (2 * h), rtol=1e-6, atol=1e-7,
                                   err_msg=keys[j])


def test_state_matches_the_case(ricsac9):
    s = case_state(ricsac9, 0.4, 0.7)
    assert s.shape == (len(STATE),)
    assert s[STATE.index("impact.restitution")] == 0.4
    assert s[STATE.index("vehicle2.heading")] == float(ricsac9.vehicle2.heading)


@pytest.mark.parametrize("free, words", [
    ({"vehicle1.wheelbase": (1, 2)}, "unknown"),
    ({"vehicle1.d": (0.0, 2.0)}, "> 0"),
    ({"vehicle1.speed": (-1.0, 2.0)}, ">= 0"),
    ({"impact.point_along": (1.0, 1.0)}, "low < high"),
    ({"vehicle1.speed": (0, 20), "vehicle1.velocity_x": (-5, 5)}, "same field"),
    ({"vehicle2.phi": (0, 1), "vehicle2.cg_y": (-1, 1)}, "same field"),
    ({"vehicle1.phi": ("a", 1)}, "numbers"),
])
def test_bad_free_parameters_are_named(free, words):
    with pytest.raises(ValueError, match=words):
        check_free(free)


def test_every_extra_key_is_a_free_key():
    for key in ("impact.point_along", "vehicle1.phi", "vehicle2.d", "vehicle1.speed"):
        assert key in FREE_KEYS


# ---- the law keys: impact.k, impact.mu_c, the law in the state -------------------------------
@pytest.fixture(scope="module")
def pccrash():
    return pim.load_case("ricsac9-pccrash")


def test_law_keys_set_the_restitution_and_friction_columns(pccrash):
    from pim.analysis.free_inputs import fields_set_by, state_law

    state, jac = free_inputs(pccrash, ("impact.k", "impact.mu_c"), [[0.25, 0.3]],
                             jacobian=True)
    assert state[0, STATE.index("impact.restitution")] == 0.25
    assert state[0, STATE.index("impact.contact_friction")] == 0.3
    assert jac[0, STATE.index("impact.restitution"), 0] == 1.0
    assert jac[0, STATE.index("impact.contact_friction"), 1] == 1.0
    assert state_law(state) == "kudlich-slibar"
    assert fields_set_by("impact.k") == ("impact.restitution",)
    assert fields_set_by("impact.mu_c") == ("impact.contact_friction",)
    assert {"impact.k", "impact.mu_c"} <= set(FREE_KEYS)
    moved = set_inputs(pccrash, {"impact.k": 0.25, "impact.mu_c": 0.3})
    assert (moved.impact.restitution, moved.impact.contact_friction) == (0.25, 0.3)
    assert (current_value(moved, "impact.k"), current_value(moved, "impact.mu_c")) == (0.25,
                                                                                       0.3)


def test_a_case_without_contact_friction_has_none_in_its_state(ricsac9):
    s = case_state(ricsac9)
    assert np.isinf(s[STATE.index("impact.contact_friction")])
    assert s[STATE.index("impact.law")] == 0.0          # Brach's


@pytest.mark.parametrize("free, words", [
    ({"impact.k": (0.0, 1.5)}, "must lie in [0, 1]"),
    ({"impact.mu_c": (-0.1, 1.0)}, "must be >= 0"),
    ({"impact.k": (0, 1), "impact.restitution": (0, 1)}, "set the same field"),
])
def test_law_key_bounds_are_checked(free, words):
    with pytest.raises(ValueError, match=words.replace("[", r"\[").replace("]", r"\]")):
        check_free(free)


def test_law_keys_need_their_law(ricsac9, pccrash):
    from pim.analysis.free_inputs import check_free_for_case

    with pytest.raises(ValueError, match="impact.k does not apply to impact law 'brach'"):
        check_free_for_case(ricsac9, ("impact.k",))
    with pytest.raises(ValueError, match="impact.beta does not apply to impact law "
                                         "'kudlich-slibar'"):
        check_free_for_case(pccrash, ("impact.beta",))
    check_free_for_case(pccrash, ("impact.k", "impact.mu_c", "vehicle1.speed"))
    check_free_for_case(ricsac9, ("impact.mu_c",), law="brach-capped")


def test_friction_floor_replaces_an_unreached_mu_c_by_the_sticking_ratio(pccrash):
    from pim.analysis.free_inputs import friction_floor

    needed = float(pim.solve(pccrash, 0.0, 1.0, law="brach").mu0)   # Brach's mu0 at eps = 0
    x, floored = friction_floor(case_state(pccrash), ("impact.k", "impact.mu_c"),
                                [[0.3, 0.4], [0.3, 1.7], [0.3, needed]])
    np.testing.assert_array_equal(floored, [False, True, True])
    np.testing.assert_allclose(x[:, 1], [0.4, needed, needed], rtol=1e-12)
    same, none = friction_floor(case_state(pccrash), ("impact.k",), [[0.3]])
    assert same[0, 0] == 0.3 and not none.any()


def test_free_kind_names_each_free_keys_unit_kind():
    from pim.analysis.free_inputs import FREE_KEYS, free_kind

    assert free_kind("impact.normal_angle") == "angle"
    assert free_kind("vehicle1.speed") == "velocity"            # beyond the model's inputs
    assert free_kind("vehicle2.radius_of_gyration") == "length"
    assert free_kind("impact.mu_c") == "dimensionless"
    assert {free_kind(k) for k in FREE_KEYS} <= {
        "angle", "velocity", "length", "dimensionless", "angular_velocity", "mass",
        "inertia"}
    with pytest.raises(KeyError):
        free_kind("vehicle3.mass")
