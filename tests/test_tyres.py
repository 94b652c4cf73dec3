"""Tyre force law (pim.model.tyres): statics, Coulomb bounds, the free-rolling and locked
limits, and the regularised stopping distance against its integral."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from pim.model.geometry import perp, rotate
from pim.model.tyres import (
    STANDARD_GRAVITY,
    net_force_and_moment,
    regularised_slide_distance,
    static_loads,
    tyre_forces,
    wheel_positions,
)


def test_static_loads_balance_weight_and_pitch_moment():
    positions = wheel_positions(2.7, 1.5, 1.1)
    loads = static_loads(1500.0, 2.7, 1.1)
    assert loads.sum() == pytest.approx(1500.0 * STANDARD_GRAVITY, rel=1e-14)
    # no pitch moment about the CG: sum N_i x_i = 0
    assert (loads * positions[:, 0]).sum() == pytest.approx(0.0, abs=1e-9)
    assert positions[0].tolist() == [1.1, 0.75] and positions[3].tolist() == [1.1 - 2.7, -0.75]


@settings(max_examples=60, deadline=None)
@given(vx=st.floats(-30, 30), vy=st.floats(-30, 30), w=st.floats(-5, 5),
       psi=st.floats(-4, 4), f=st.floats(0, 1), steer=st.floats(-0.6, 0.6))
def test_force_never_exceeds_mu_n_and_opposes_slip(vx, vy, w, psi, f, steer):
    positions = wheel_positions(2.7, 1.5, 1.2)
    loads = static_loads(1500.0, 2.7, 1.2)
    forces = tyre_forces([vx, vy], w, psi, positions, loads, 0.7, [f] * 4,
                         [steer, steer, 0, 0])
    assert np.all(np.hypot(forces[:, 0], forces[:, 1]) <= 0.7 * loads * (1 + 1e-12))
    # dissipative: the power of each tyre force on its contact point's velocity is <= 0
    slip = np.array([vx, vy]) + w * perp(rotate(positions, psi))
    assert np.all((forces * slip).sum(axis=-1) <= 1e-9)


def test_locked_is_coulomb_and_free_rolling_is_lateral_only():
    positions = wheel_positions(2.7, 1.5, 1.35)
    loads = static_loads(1000.0, 2.7, 1.35)
    psi = 0.4
    v = 15.0 * np.array([np.cos(psi + 0.3), np.sin(psi + 0.3)])  # slip angle 0.3 rad
    locked = tyre_forces(v, 0.0, psi, positions, loads, 0.8, [1] * 4, regularisation=1e-9)
    np.testing.assert_allclose(locked, -0.8 * loads[:, None] * v / 15.0, rtol=1e-9)
    free = tyre_forces(v, 0.0, psi, positions, loads, 0.8, [0] * 4, regularisation=1e-9)
    heading = np.array([np.cos(psi), np.sin(psi)])
    np.testing.assert_allclose(free @ heading, 0.0, atol=1e-9)        # no longitudinal force
    np.testing.assert_allclose(np.hypot(*free.T), 0.8 * loads, rtol=1e-9)  # full lateral
    # straight, free rolling: no force at all
    straight = tyre_forces(15 * heading, 0.0, psi, positions, loads, 0.8, [0] * 4)
    np.testing.assert_allclose(straight, 0.0, atol=1e-9)
    # braked at fraction f, straight: f mu N against the motion
    braked = tyre_forces(15 * heading, 0.0, psi, positions, loads, 0.8, [0.25] * 4,
                         regularisation=1e-9)
    np.testing.assert_allclose(braked, -0.25 * 0.8 * loads[:, None] * heading, rtol=1e-9)


def test_pure_spin_moment_about_symmetric_cg():
    positions = wheel_positions(2.6, 1.6, 1.3)
    loads = static_loads(1200.0, 2.6, 1.3)
    forces = tyre_forces([0, 0], 2.0, 0.7, positions, loads, 0.9, [1] * 4,
                         regularisation=1e-9)
    force, moment = net_force_and_moment(forces, positions, 0.7)
    rho = np.hypot(1.3, 0.8)
    np.testing.assert_allclose(force, 0.0, atol=1e-8)
    assert moment == pytest.approx(-0.9 * 1200 * STANDARD_GRAVITY * rho, rel=1e-9)


@pytest.mark.parametrize("v0", [0.01, 0.3, 5.0, 25.0])
def test_regularised_slide_distance_is_the_integral(v0):
    mu, vr = 0.7, 0.05
    # s = int v dv / a(v), a(v) = mu g v / sqrt(v^2 + vr^2)
    expected, _ = quad(lambda v: np.sqrt(v * v + vr * vr) / (mu * STANDARD_GRAVITY), 0, v0)
    assert regularised_slide_distance(v0, mu, regularisation=vr) == pytest.approx(
        expected, rel=1e-10)
    assert regularised_slide_distance(v0, mu, regularisation=1e-9) == pytest.approx(
        v0 * v0 / (2 * mu * STANDARD_GRAVITY), rel=1e-9)
