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
    TyreData,
    brake_ramp,
    field_wheel_force,
    linear_buildup_stopping_distance,
    net_force_and_moment,
    regularised_slide_distance,
    static_loads,
    transferred_load,
    tyre_forces,
    wheel_force,
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


# ---- the field tyre: combined-slip brush (pim.model.tyres.field_wheel_force) ---------------

def _field(u, w, braking, load=4000.0, mu=0.8, c_long=150e3, c_lat=80e3, rolling=0.0,
           vr=0.05):
    """Force (longitudinal, lateral) of a tyre at the origin heading +x with contact-point
    velocity (u, w) [m/s]."""
    fx, fy, _ = field_wheel_force(1.0, 0.0, u, w, 0.0, 0.0, 0.0, 1.0, 0.0, load, mu, braking,
                                  vr, c_long, c_lat, rolling)
    return np.asarray(fx), np.asarray(fy)


def test_field_tyre_is_linear_at_small_slip():
    # lateral: F_y = -C_y tan(alpha), the small-slip limit of the brush (Pacejka 2012 sec. 3.2)
    u, alpha = 20.0, np.radians(0.002)   # psi = 1e-4: the brush is linear to 1e-4
    _, fy = _field(u, u * np.tan(alpha), 0.0)
    assert fy == pytest.approx(-80e3 * np.tan(alpha), rel=2e-3)
    # longitudinal: f = 0.003 of the grip gives F_x = -C_x sigma_x with the inverted brush
    fx, _ = _field(u, 0.0, 0.003)
    assert fx == pytest.approx(-0.003 * 0.8 * 4000.0, rel=1e-4)


@settings(max_examples=80, deadline=None)
@given(st.floats(0.0, 0.999), st.floats(2.0, 40.0))
def test_straight_braking_force_is_the_demanded_fraction_of_the_grip(f, u):
    # exact but for the slip regularisation (rolling speed sqrt(u^2 + v_r^2)), ~ (v_r / u)^2
    fx, fy = _field(u, 0.0, f)
    assert fx == pytest.approx(-f * 0.8 * 4000.0, rel=1e-3, abs=1e-6)
    assert fy == pytest.approx(0.0, abs=1e-9)


@settings(max_examples=100, deadline=None)
@given(st.floats(-30, 30), st.floats(-30, 30), st.floats(0, 1), st.floats(1e3, 3e5),
       st.floats(1e3, 3e5))
def test_field_tyre_never_exceeds_the_friction_circle(u, w, f, c_long, c_lat):
    fx, fy = _field(u, w, f, c_long=c_long, c_lat=c_lat)
    assert np.hypot(fx, fy) <= 0.8 * 4000.0 * (1 + 1e-12)
    assert fx * u + fy * w <= 1e-9            # dissipative


@settings(max_examples=60, deadline=None)
@given(st.floats(-30, 30), st.floats(-30, 30), st.floats(-3, 3))
def test_locked_wheel_is_the_coulomb_law(u, w, omega):
    # the high-slip limit: a locked wheel slides, F = -mu N V_s / |V_s| (regularised alike)
    args = (np.cos(0.4), np.sin(0.4), u, w, omega, 1.2, 0.75, np.cos(0.5), np.sin(0.5), 4000.0,
            0.8, 1.0, 0.05)
    new = field_wheel_force(*args, 150e3, 80e3, 0.013)
    old = wheel_force(*args)
    np.testing.assert_allclose(new, old, rtol=1e-12, atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 20.0), st.floats(0.2, 30.0).map(lambda x: x * np.sign(x)))
def test_free_rolling_beyond_the_saturation_slip_angle_is_the_coulomb_law(u, w):
    # free rolling at a slip angle with C_y tan(alpha) >= 3 mu N: full sliding sideways
    if 80e3 * w < 3 * 0.8 * 4000.0 * np.hypot(u, 0.05):
        return
    new = field_wheel_force(1.0, 0.0, u, w, 0.0, 0.0, 0.0, 1.0, 0.0, 4000.0, 0.8, 0.0, 0.05,
                            150e3, 80e3, 0.0)
    old = wheel_force(1.0, 0.0, u, w, 0.0, 0.0, 0.0, 1.0, 0.0, 4000.0, 0.8, 0.0, 0.05)
    # equal up to the regularisation, which differs by at most (v_r / w)^2 / 2
    np.testing.assert_allclose(new, old, rtol=(0.05 / w) ** 2 / 2 + 1e-12, atol=1e-9)


def test_brush_curve_is_pacejkas_isotropic_brush():
    # C_x = C_y: F = mu N (3 psi - 3 psi^2 + psi^3) against the slip, psi = C sigma / (3 mu N)
    # (Pacejka 2012, sec. 3.2.2); free rolling so sigma = tan(alpha) = w / u
    u = 10.0
    for alpha in np.radians([1.0, 3.0, 6.0]):
        psi = 80e3 * np.tan(alpha) / (3 * 0.8 * 4000.0)
        _, fy = _field(u, u * np.tan(alpha), 0.0, c_long=80e3, vr=1e-9)
        expected = 0.8 * 4000.0 * (3 * psi - 3 * psi**2 + psi**3) if psi < 1 else 3200.0
        assert -fy == pytest.approx(expected, rel=1e-9)


def test_rolling_resistance_of_a_free_rolling_wheel():
    fx, fy = _field(15.0, 0.0, 0.0, rolling=0.013)
    assert fx == pytest.approx(-0.013 * 4000.0, rel=1e-5) and fy == 0


@settings(max_examples=60, deadline=None)
@given(st.floats(-8, 8), st.floats(-8, 8))
def test_load_transfer_keeps_weight_and_balances_the_inertial_moments(a_long, a_lat):
    mass, length, track, a, h = 1500.0, 2.7, 1.5, 1.2, 0.55
    static = static_loads(mass, length, a)
    front, left = np.array([1.0, 1, 0, 0]), np.array([1.0, 0, 1, 0])
    loads = transferred_load(static, mass, a_long, a_lat, h, length, track, a, front, left)
    if np.any(loads == 0):                       # a wheel lifted off: no balance expected
        return
    pos = wheel_positions(length, track, a)
    assert loads.sum() == pytest.approx(mass * STANDARD_GRAVITY, rel=1e-12)
    # pitch: sum N x = -m a_x h (braking loads the front); roll: sum N y = -m a_y h
    assert (loads * pos[:, 0]).sum() == pytest.approx(-mass * a_long * h, abs=1e-6)
    assert (loads * pos[:, 1]).sum() == pytest.approx(-mass * a_lat * h, abs=1e-6)


def test_brake_ramp_and_the_build_up_stopping_distance():
    assert brake_ramp(np.array([-1.0, 0.0, 0.1, 0.2, 1.0]), 0.0, 0.2).tolist() == pytest.approx(
        [0, 0, 0.5, 1, 1])
    assert brake_ramp(0.0, 0.0, 0.0) == 1.0
    # closed form against the integral of v(t) (independent: quadrature of the speed)
    v0, a, tb = 20.0, 7.0, 0.4

    def speed(t):
        return v0 - a * t * t / (2 * tb) if t < tb else v0 - a * tb / 2 - a * (t - tb)
    stop = tb + (v0 - a * tb / 2) / a
    distance, _ = quad(speed, 0, stop, points=[tb])
    assert linear_buildup_stopping_distance(v0, a, tb) == pytest.approx(distance, rel=1e-10)
    with pytest.raises(ValueError, match="build-up"):
        linear_buildup_stopping_distance(1.0, 7.0, 1.0)


def test_tyre_data_checks_its_fields():
    assert TyreData().per_wheel("cornering_stiffness").shape == (4,)
    with pytest.raises(ValueError, match="tyres.cornering_stiffness"):
        TyreData(cornering_stiffness=-1.0)
    with pytest.raises(ValueError, match="tyres.cg_height"):
        TyreData(cg_height=float("nan"))


@given(st.floats(-30, 30), st.floats(-30, 30), st.floats(-3, 3), st.floats(-4, 4),
       st.sampled_from([0.0, 1.0]))
@settings(max_examples=200, deadline=None)
def test_a_rolling_or_locked_number_skips_only_zero_terms(vx, vy, w, psi, f):
    # braking 0.0 or 1.0 as a number skips the term it weights by 0: the same bits (signed
    # zeros included) as the general path an array of the same braking takes
    c, s = np.cos(psi), np.sin(psi)
    number = wheel_force(c, s, vx, vy, w, 1.4, -0.8, c, s, 4000.0, 0.8, f, 0.05)
    array = wheel_force(c, s, vx, vy, w, 1.4, -0.8, c, s, 4000.0, 0.8, np.array(f), 0.05)
    assert [float(v).hex() for v in number] == [float(v).hex() for v in array]
