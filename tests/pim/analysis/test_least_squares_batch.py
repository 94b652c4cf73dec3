"""pim/analysis/least_squares_batch.py against closed forms (Rosenbrock's minimum), scipy's
bounded linear least squares (BVLS) and the active-set optimality conditions."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import lsq_linear

from pim.analysis.least_squares_batch import least_squares_batch


def rosenbrock(x, idx):
    r = np.stack([10 * (x[:, 1] - x[:, 0] ** 2), 1 - x[:, 0]], -1)
    jac = np.zeros((len(x), 2, 2))
    jac[:, 0, 0] = -20 * x[:, 0]
    jac[:, 0, 1] = 10.0
    jac[:, 1, 0] = -1.0
    return r, jac


def test_rosenbrock_from_a_thousand_starts_at_once():
    x0 = np.random.default_rng(0).uniform(-2, 2, (1000, 2))
    out = least_squares_batch(rosenbrock, x0, [-3, -3], [3, 3])
    np.testing.assert_allclose(out.x, 1.0, atol=1e-12)     # the minimum is (1, 1)
    assert out.converged.all() and (out.on_bound == 0).all()
    assert out.cost.max() < 1e-24


def test_an_active_bound_is_reported_and_the_constrained_minimum_found():
    # with x1 <= 0.5 the minimum is (0.5, 0.25): on the constraint, r1 = 0 there
    x0 = np.random.default_rng(1).uniform(-2, 0.5, (200, 2))
    out = least_squares_batch(rosenbrock, x0, [-3, -3], [0.5, 3])
    np.testing.assert_allclose(out.x, np.tile([0.5, 0.25], (200, 1)), atol=1e-9)
    assert (out.on_bound[:, 0] == 1).all() and (out.on_bound[:, 1] == 0).all()


def test_bounded_linear_problems_match_bvls():
    rng = np.random.default_rng(2)
    a, b = rng.normal(size=(100, 6, 3)), rng.normal(size=(100, 6))

    def linear(x, idx):
        return np.einsum("pki,pi->pk", a[idx], x) - b[idx], a[idx]

    out = least_squares_batch(linear, np.zeros((100, 3)), -0.2, 0.3)
    for k in range(100):
        ref = lsq_linear(a[k], b[k], bounds=(-0.2, 0.3), method="bvls", tol=1e-15)
        # a problem with nonzero residual resolves x to ~sqrt(machine eps) of the cost
        np.testing.assert_allclose(out.x[k], ref.x, atol=1e-7)
        assert out.cost[k] <= 2 * ref.cost * (1 + 1e-12)


def test_non_finite_residuals_are_refused_steps():
    def guarded(x, idx):
        r, j = rosenbrock(x, idx)
        return np.where(x[:, :1] > 1.5, np.nan, r), j

    out = least_squares_batch(guarded, [[-1.0, 1.0]], [-3, -3], [3, 3])
    np.testing.assert_allclose(out.x[0], [1.0, 1.0], atol=1e-10)


def test_bad_bounds_are_an_error():
    with pytest.raises(ValueError, match="lower < upper"):
        least_squares_batch(rosenbrock, [[0.0, 0.0]], [1, 1], [1, 2])


def _rosenbrock_residuals(x, idx):
    """Residuals alone, at points x (p, q, 2)."""
    return np.stack([10 * (x[..., 1] - x[..., 0] ** 2), 1 - x[..., 0]], -1)


def test_forward_differences_match_the_exact_jacobian_and_reach_the_minimum():
    from pim.analysis.least_squares_batch import with_forward_differences

    fun = with_forward_differences(_rosenbrock_residuals, [-3, -3], [3, 3], step=1e-7)
    x = np.random.default_rng(3).uniform(-2, 2, (50, 2))
    x[0] = (3.0, 3.0)                                   # on the upper bound: backward steps
    r, jac = fun(x, np.arange(50))
    r_exact, jac_exact = rosenbrock(x, None)
    np.testing.assert_allclose(r, r_exact, rtol=1e-12, atol=1e-12)   # x through the box
    np.testing.assert_allclose(jac, jac_exact, rtol=1e-5, atol=1e-4)
    out = least_squares_batch(fun, np.random.default_rng(4).uniform(-2, 2, (100, 2)),
                              [-3, -3], [3, 3], max_iter=500)
    np.testing.assert_allclose(out.x, 1.0, atol=1e-5)


def test_merging_stays_within_a_group():
    """Two problems from several starts each, told apart by ``groups``: the minimum of one is
    never copied into the other, though their starts lie close together."""
    from pim.analysis.least_squares_batch import with_forward_differences

    targets = np.array([0.3, 0.34])                    # group g: r = (x - targets[g])^3

    def residuals(x, idx):
        return (x - targets[groups[idx]][:, None, None]) ** 3

    groups = np.repeat([0, 1], 3)
    starts = np.array([0.3 + 1e-9, 0.9, 0.1, 0.31, 0.9, 0.1])[:, None]
    fun = with_forward_differences(residuals, [0.0], [1.0], step=1e-6)
    out = least_squares_batch(fun, starts, [0.0], [1.0], merge=0.05, groups=groups)
    np.testing.assert_allclose(out.x[:, 0], targets[groups], atol=0.01)
    merged = least_squares_batch(fun, starts, [0.0], [1.0], merge=0.05)
    assert merged.x[3, 0] == out.x[0, 0]        # one group: group 1's start copied group 0
    with pytest.raises(ValueError, match="groups"):
        least_squares_batch(fun, starts, [0.0], [1.0], merge=0.05, groups=[0, 1])
