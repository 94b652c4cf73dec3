"""Run-out forward model (pim.model.runout) against closed forms, and the batched
fixed-step integrator against the solve_ivp reference."""

import numpy as np
import pytest

from pim.model.runout import RunoutVehicle, runout, runout_many
from pim.model.tyres import STANDARD_GRAVITY, regularised_slide_distance

CAR = RunoutVehicle(mass=1500.0, yaw_inertia=2500.0, wheelbase=2.7, track=1.5,
                    cg_to_front=1.2, friction=0.8)


@pytest.mark.parametrize("v0, psi", [(20.0, 0.3), (8.0, -2.0), (31.0, 1.0)])
def test_locked_straight_slide_distance_is_v2_over_2mug(v0, psi):
    d = np.array([np.cos(psi), np.sin(psi)])
    r = runout(CAR, [1.0, -2.0], psi, v0 * d, 0.0)
    assert r.stopped
    # exact for the regularised law (up to the stop threshold's last few micrometres) ...
    assert r.distance == pytest.approx(regularised_slide_distance(v0, 0.8), abs=2e-4)
    # ... and Coulomb's v^2 / (2 mu g) within the regularisation's millimetres
    assert r.distance == pytest.approx(v0 ** 2 / (2 * 0.8 * STANDARD_GRAVITY), abs=3e-3)
    np.testing.assert_allclose((r.rest_position - [1.0, -2.0]) / r.distance, d, atol=1e-9)
    assert r.rest_heading == pytest.approx(psi, abs=1e-9)
    assert r.stop_time == pytest.approx(v0 / (0.8 * STANDARD_GRAVITY), abs=0.05)


def test_braked_fraction_scales_the_deceleration():
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8, braking=(0.5, 0.5, 0.5, 0.5))
    r = runout(car, [0, 0], 0.0, [15.0, 0.0], 0.0)
    assert r.distance == pytest.approx(15.0 ** 2 / (2 * 0.4 * STANDARD_GRAVITY), abs=5e-3)


def test_spinning_locked_vehicle_rotation_angle():
    """CG at mid-wheelbase, no translation: I domega/dt = -mu m g rho u/sqrt(u^2+vr^2),
    u = rho omega, so rho * (total rotation) is a regularised slide of u0 = rho omega0 with
    mu' = mu m rho^2 / I; Coulomb: angle = omega0^2 I / (2 mu m g rho)."""
    car = RunoutVehicle(1500.0, 2500.0, 2.6, 1.6, 1.3, 0.8)
    rho = np.hypot(1.3, 0.8)
    w0 = 3.0
    r = runout(car, [0, 0], 0.5, [0.0, 0.0], w0)
    assert r.stopped
    np.testing.assert_allclose(r.rest_position, 0.0, atol=1e-9)
    mu_eff = 0.8 * 1500.0 * rho ** 2 / 2500.0
    angle = regularised_slide_distance(rho * w0, mu_eff) / rho
    assert r.rest_heading - 0.5 == pytest.approx(angle, abs=2e-4)
    coulomb = w0 ** 2 * 2500.0 / (2 * 0.8 * 1500.0 * STANDARD_GRAVITY * rho)
    assert r.rest_heading - 0.5 == pytest.approx(coulomb, abs=3e-3)


def test_free_rolling_straight_keeps_its_speed_and_is_flagged():
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8, braking=(0, 0, 0, 0))
    r = runout(car, [0, 0], 0.2, 12.0 * np.array([np.cos(0.2), np.sin(0.2)]), 0.0,
               max_time=5.0)
    assert not r.stopped and r.stop_time == 5.0
    np.testing.assert_allclose(r.states[-1, 3:5], r.states[0, 3:5], atol=1e-9)
    assert r.distance == pytest.approx(60.0, rel=1e-9)
    b = runout_many(car, [[0, 0]], [0.2], [12.0 * np.array([np.cos(0.2), np.sin(0.2)])],
                    [0.0], max_time=2.0)
    assert not b.stopped[0]


def test_free_rolling_skid_loses_lateral_speed_only():
    """Free-rolling, sliding sideways: the lateral slip dies, the rolling speed stays."""
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.35, 0.8, braking=(0, 0, 0, 0))
    r = runout(car, [0, 0], 0.0, [10.0, 3.0], 0.0, max_time=3.0)
    assert r.states[-1, 3] == pytest.approx(10.0, abs=1e-6)
    assert abs(r.states[-1, 4]) < 1e-3


def test_batched_rk4_matches_solve_ivp():
    rng = np.random.default_rng(3)
    n = 12
    speed = rng.uniform(3, 25, n)
    direction = rng.uniform(-np.pi, np.pi, n)
    velocity = speed[:, None] * np.column_stack([np.cos(direction), np.sin(direction)])
    heading = rng.uniform(-np.pi, np.pi, n)
    yaw_rate = rng.uniform(-3, 3, n)
    braking = rng.choice([0.0, 0.3, 1.0], size=(n, 4))
    braking[:, 0] = 1.0  # at least one braked wheel so every sample stops
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, rng.uniform(0.5, 0.9, n),
                        braking=braking)
    batch = runout_many(car, np.zeros((n, 2)), heading, velocity, yaw_rate)
    assert batch.stopped.all()
    for i in range(n):
        one = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, car.friction[i],
                            braking=braking[i])
        ref = runout(one, [0, 0], heading[i], velocity[i], yaw_rate[i])
        np.testing.assert_allclose(batch.rest_position[i], ref.rest_position, atol=2e-3)
        assert batch.rest_heading[i] == pytest.approx(ref.rest_heading, abs=1e-3)


@pytest.mark.parametrize("field, value", [("friction", 0.0), ("friction", -0.2),
                                          ("mass", float("nan")), ("wheelbase", "2.7")])
def test_bad_vehicle_names_the_field(field, value):
    kwargs = dict(mass=1500.0, yaw_inertia=2500.0, wheelbase=2.7, track=1.5,
                  cg_to_front=1.2, friction=0.8)
    kwargs[field] = value
    with pytest.raises(ValueError, match=f"runout.{field}"):
        RunoutVehicle(**kwargs)


def test_nan_state_names_the_field():
    with pytest.raises(ValueError, match="runout.velocity"):
        runout(CAR, [0, 0], 0.0, [np.nan, 1.0], 0.0)
