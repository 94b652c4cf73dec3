"""pim/model/dual.py: exact derivatives through the one formula, against two independent
references: the hand-derived closed form of tests/closed_form.py (for eps and beta) and
central finite differences of pim.solve (for Gamma, C and the pre-impact motion)."""

from dataclasses import replace

import numpy as np
from hypothesis import given, settings

import pim
from pim.model.dual import MOTION_INPUTS, MOTION_OUTPUTS, Dual, motion_jacobian
from tests.closed_form import motion_derivatives
from tests.scenes import random_cases, scenes


def test_dual_arithmetic_matches_calculus():
    x = Dual(np.array([2.0, -3.0]), np.array([[1.0, 0.0], [1.0, 0.0]]))
    y = 3.0 * x * x - 1.0 / x + abs(x) - (x - 4.0) / 2.0
    d = 6.0 * x.value + 1.0 / x.value ** 2 + np.sign(x.value) - 0.5
    np.testing.assert_allclose(y.grad[:, 0], d, rtol=1e-15)
    assert (x < 0.0).tolist() == [False, True]


@settings(max_examples=300, deadline=None)
@given(scenes())
def test_dual_equals_hand_derived_eps_beta_derivatives(case):
    """The closed-form derivatives w.r.t. (eps, beta) equal automatic differentiation."""
    result = pim.solve(case, 0.4, 0.7)
    values, jac = motion_jacobian(case, 0.4, 0.7)
    d_eps, d_beta = motion_derivatives(result)
    out = {name: k for k, name in enumerate(MOTION_OUTPUTS)}
    for col, md in ((0, d_eps), (1, d_beta)):
        got = np.array([jac[out["velocity1_x"], col], jac[out["velocity1_y"], col],
                        jac[out["velocity2_x"], col], jac[out["velocity2_y"], col],
                        jac[out["yaw_rate1"], col], jac[out["yaw_rate2"], col]])
        want = np.array([*md.velocity1, *md.velocity2, md.yaw_rate1, md.yaw_rate2], float)
        scale = np.max(np.abs(want)) + 1e-300
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(values[out["velocity1_x"]], result.velocity1[0], rtol=1e-14,
                               atol=1e-12)


def _moved(case, key, h):
    group, name = key.split(".")
    if group == "impact":
        if name == "normal_angle":
            return replace(case, impact=replace(case.impact,
                                                normal_angle=case.impact.normal_angle + h))
        point = case.impact.point + (np.array([h, 0.0]) if name == "point_x" else [0.0, h])
        return replace(case, impact=replace(case.impact, point=point))
    vehicle = getattr(case, group)
    if name in ("yaw_rate", "mass", "yaw_inertia"):
        vehicle = replace(vehicle, **{name: getattr(vehicle, name) + h})
    else:
        field, axis = name.rsplit("_", 1)
        step = np.array([h, 0.0]) if axis == "x" else np.array([0.0, h])
        vehicle = replace(vehicle, **{field: getattr(vehicle, field) + step})
    return replace(case, **{group: vehicle})


def test_dual_matches_finite_differences_for_every_other_input():
    case = random_cases(200, seed=21)
    eps, beta = 0.35, 0.8
    _, jac = motion_jacobian(case, eps, beta)
    base = pim.solve(case, eps, beta)
    # away from the kink u_n = 0 and from singular q, where finite differences lose digits
    ok = base.approaching & (np.abs(base.approach_n) > 0.5) & (np.abs(base.q) < 5)
    assert ok.sum() > 50
    for col, key in enumerate(MOTION_INPUTS[2:], start=2):
        h = 1e-6 * (1e3 if key.endswith(("mass", "yaw_inertia")) else 1.0)
        plus, minus = pim.solve(_moved(case, key, h), eps, beta), \
            pim.solve(_moved(case, key, -h), eps, beta)
        fd = (plus.velocity1 - minus.velocity1) / (2 * h)
        got = jac[:, 4:6, col]
        np.testing.assert_allclose(got[ok], fd[ok], rtol=1e-5, atol=1e-6, err_msg=key)


def test_tangent_carries_the_chain_rule():
    """motion_of_inputs(x, tangent=T) gives d output / d p = J T, n columns wide."""
    from pim.model.dual import MOTION_INPUTS, motion_inputs, motion_of_inputs

    case = pim.load_case("ricsac9")
    x = motion_inputs(case, 0.3, 0.8)[None]
    rng = np.random.default_rng(1)
    t = rng.normal(size=(1, len(MOTION_INPUTS), 3))
    values, jac = motion_of_inputs(x)
    v2, j2 = motion_of_inputs(x, tangent=t)
    np.testing.assert_array_equal(values, v2)
    np.testing.assert_allclose(j2, jac @ t, rtol=1e-12, atol=1e-12)


def test_where_selects_value_and_gradient_of_the_side_taken():
    from pim.model.dual import value_of, where

    a = Dual(np.array([1.0, 2.0]), np.array([[1.0, 0.0], [0.0, 1.0]]))
    out = where(np.array([True, False]), a, 5.0)
    np.testing.assert_array_equal(out.value, [1.0, 5.0])
    np.testing.assert_array_equal(out.grad, [[1.0, 0.0], [0.0, 0.0]])
    np.testing.assert_array_equal(where([False, True], 0.0, np.array([3.0, 4.0])), [3.0, 0.0])
    np.testing.assert_array_equal(value_of(out), out.value)
    assert value_of(2.0) == 2.0
