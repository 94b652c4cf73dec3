"""Run-out forward model (pim.model.runout) against closed forms, and the batched
fixed-step integrator against the solve_ivp reference."""

from dataclasses import replace

import numpy as np
import pytest

from pim.model.driver import DriverInputs
from pim.model.runout import RunoutVehicle, runout, runout_many
from pim.model.tyres import (
    STANDARD_GRAVITY,
    TyreData,
    linear_buildup_stopping_distance,
    regularised_slide_distance,
)
from tests.bicycle import (
    matrices,
    ramp_response,
    ramp_response_expm,
    table_response,
    understeer_gradient,
    yaw_rate_gain,
)
from tests.fishhook import published_table

CAR = RunoutVehicle(mass=1500.0, yaw_inertia=2500.0, wheelbase=2.7, track=1.5,
                    cg_to_front_axle=1.2, friction=0.8)


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
                  cg_to_front_axle=1.2, friction=0.8)
    kwargs[field] = value
    with pytest.raises(ValueError, match=f"runout.{field}"):
        RunoutVehicle(**kwargs)


_BAD_VALUES = [0.0, -0.2, float("nan"), float("inf"), "2.7", True, None, 10 ** 400, 3.0]


@pytest.mark.parametrize("field", ["mass", "yaw_inertia", "wheelbase", "track", "friction",
                                   "cg_to_front_axle", "regularisation"])
@pytest.mark.parametrize("value", _BAD_VALUES)
def test_plain_numbers_are_checked_as_arrays_are(field, value):
    """A vehicle of Python numbers (the one-sample fast check) is refused exactly when the
    same values as numpy arrays are, with the same message."""
    def outcome(kwargs):
        try:
            RunoutVehicle(**kwargs)
        except (ValueError, TypeError, OverflowError) as exc:
            return type(exc), str(exc).split(", got")[0]   # (the value's repr differs)
        return None

    kwargs = dict(mass=1500.0, yaw_inertia=2500.0, wheelbase=2.7, track=1.5,
                  cg_to_front_axle=1.2, friction=0.8, regularisation=0.05)
    kwargs[field] = value
    arrays = {k: np.asarray(v) if k != "regularisation" and isinstance(v, float) else v
              for k, v in kwargs.items()}
    assert outcome(kwargs) == outcome(arrays)


@pytest.mark.parametrize("braking, steer", [((1.0, 0.5, 2.0, 1.0), 0.0),
                                            ((1.0, -0.1, 1.0, 1.0), 0.0),
                                            ((1.0, 1.0, 1.0), 0.0),
                                            ((1, 1, 0, 0), (0.1, 0.1, float("nan"), 0.0)),
                                            ((1, 1, 0, 0), (0.1, 0.1)),
                                            ((1, 1, 0, 0), float("inf"))])
def test_bad_wheels_are_refused_as_arrays_are(braking, steer):
    def outcome(b, s):
        try:
            RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8, braking=b, steer=s)
        except ValueError as exc:
            return str(exc).split(", got")[0]      # (the value's repr differs)
        return None

    message = outcome(braking, steer)
    assert message is not None and message == outcome(np.asarray(braking, float),
                                                      np.asarray(steer, float))


@pytest.mark.parametrize("vehicle", [
    RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8),
    RunoutVehicle(1312, 2100.5, 2.61, 1.49, 0.97, 0.7, braking=(1, 1, 0.2, 0.2),
                  steer=(0.21, 0.19, 0.0, 0.0)),
    RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 2.7, 0.9, steer=-0.3,
                  tyre=TyreData(cg_height=0.55, rolling_resistance=0.012)),
    RunoutVehicle(np.float64(1500.0), 2500.0, 2.7, 1.5, 1.2, 0.8)])
def test_one_sample_data_is_the_broadcast_data_bit_for_bit(vehicle):
    """RhsData.one (one sample, no broadcasting) holds RhsData.of(vehicle, 1)'s arrays,
    bitwise: Coulomb and field tyres, braking, steer, Python ints, a numpy scalar."""
    from pim.model.runout import RhsData

    one, of = RhsData.one(vehicle), RhsData.of(vehicle, 1)
    for name in ("mass", "yaw_inertia", "wheel_x", "wheel_y", "load", "friction", "times",
                 "steer", "brake", "tyre"):
        a, b = getattr(one, name), getattr(of, name)
        assert a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes(), name
        assert a.flags.c_contiguous, name
    assert one.regularisation == of.regularisation


def test_nan_state_names_the_field():
    with pytest.raises(ValueError, match="runout.velocity"):
        runout(CAR, [0, 0], 0.0, [np.nan, 1.0], 0.0)


# ---- the field tyre and driver inputs against closed forms ----------------------------------

def _field_car(**tyre):
    settings = {"cg_height": 0.0, "rolling_resistance": 0.0, **tyre}
    return RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8, tyre=TyreData(**settings))


def test_locked_spinning_slide_with_the_field_tyre_is_the_coulomb_run_out():
    # locked wheels slide: the brush law is Coulomb's there, so the whole run-out is the same
    coulomb = runout(CAR, [1.0, -2.0], 0.4, [14.0, 5.0], 2.5)
    field = runout(_field_car(), [1.0, -2.0], 0.4, [14.0, 5.0], 2.5)
    assert CAR.tyre_model == "coulomb" and _field_car().tyre_model == "brush"
    np.testing.assert_allclose(field.rest_position, coulomb.rest_position, atol=1e-6)
    assert field.rest_heading == pytest.approx(coulomb.rest_heading, abs=1e-7)


@pytest.mark.parametrize("fraction, buildup, height", [(1.0, 0.3, 0.55), (0.5, 0.2, 0.55),
                                                       (0.7, 0.0, 0.0)])
def test_straight_braking_distance_with_a_linear_build_up(fraction, buildup, height):
    # closed form s = v0^2 / (2a) + v0 t_b / 2 - a t_b^2 / 24 (derived in
    # pim.model.tyres.linear_buildup_stopping_distance, checked there by quadrature); the
    # load transfer moves load to the front but keeps sum(f mu N) = f mu m g
    car = replace(_field_car(buildup_time=buildup, cg_height=height),
                  braking=(fraction,) * 4)
    v0 = 20.0
    r = runout(car, [0.0, 0.0], 0.0, [v0, 0.0], 0.0)
    expected = linear_buildup_stopping_distance(v0, fraction * 0.8 * STANDARD_GRAVITY, buildup)
    assert r.stopped and r.distance == pytest.approx(expected, rel=5e-4)


@pytest.mark.parametrize("speed", [10.0, 25.0])
def test_j_turn_settles_to_the_bicycle_models_steady_state_cornering(speed):
    # a J-turn (steer ramp 0 -> delta over 0.5 s, driver table) at small lateral
    # acceleration: the yaw rate settles to r = v delta / (L + K v^2) and the radius to
    # R = (L + K v^2) / delta; mu is large so the brush stays at its linear slope
    c_front, c_rear = 60e3, 90e3
    delta = 0.01
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 20.0,
                        tyre=TyreData(cornering_stiffness=(c_front, c_front, c_rear, c_rear),
                                      cg_height=0.55, rolling_resistance=0.0),
                        driver=DriverInputs([0.0, 0.5], [0.0, delta], np.zeros((2, 4))))
    r = runout(car, [0.0, 0.0], 0.0, [speed, 0.0], 0.0, max_time=4.0)
    vx, vy, omega = r.states[-1, 3:]
    v = np.hypot(vx, vy)
    k = understeer_gradient(car.mass, car.cg_to_front_axle, car.wheelbase, 2 * c_front, 2 * c_rear)
    assert k > 0                                          # understeer
    assert omega == pytest.approx(v * delta / (car.wheelbase + k * v * v), rel=3e-3)
    assert v / omega == pytest.approx((car.wheelbase + k * v * v) / delta, rel=3e-3)


def test_bicycle_oracles_eigenvector_form_is_the_matrix_exponential():
    a_mat, b_vec = matrices(1500.0, 2500.0, 1.2, 2.7, 110e3, 150e3, 20.0)
    t = np.linspace(-0.5, 3.0, 36)
    np.testing.assert_allclose(ramp_response(a_mat, b_vec, t),
                               ramp_response_expm(a_mat, b_vec, t), atol=1e-12)


@pytest.mark.parametrize("speed, ramp", [(20.0, 0.05), (30.0, 0.2)])
def test_step_steer_transient_is_the_linear_bicycle_models(speed, ramp):
    # ISO 7401-style step steer (a fast ramp to 0.3 deg of road-wheel angle) at small lateral
    # acceleration: the yaw rate and lateral velocity follow the closed-form response of the
    # linear bicycle model (tests/bicycle.py, matrix exponentials, no integrator) over the
    # whole transient, overshoot and settling included; the four-wheel brush model with load
    # transfer differs from it only at second order in the slip (track, tan, cos delta)
    c_front, c_rear, delta = 55e3, 75e3, np.radians(0.3)
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 20.0,
                        tyre=TyreData(cornering_stiffness=(c_front, c_front, c_rear, c_rear),
                                      cg_height=0.55, rolling_resistance=0.0),
                        driver=DriverInputs([0.0, ramp], [0.0, delta], np.zeros((2, 4))))
    r = runout(car, [0.0, 0.0], 0.0, [speed, 0.0], 0.0, max_time=2.5, dense_output=True,
               rtol=1e-10, atol=1e-12)
    t = np.linspace(0.0, 2.5, 126)
    x, y, psi, vx, vy, omega = r.interpolant(t)
    lateral = -np.sin(psi) * vx + np.cos(psi) * vy                  # body frame
    a_mat, b_vec = matrices(car.mass, car.yaw_inertia, car.cg_to_front_axle, car.wheelbase,
                            2 * c_front, 2 * c_rear, speed)
    expected = table_response(a_mat, b_vec, [0.0, ramp], [0.0, delta], t)
    steady = yaw_rate_gain(car.mass, car.cg_to_front_axle, car.wheelbase, 2 * c_front,
                           2 * c_rear, speed) * delta
    assert expected[-1, 1] == pytest.approx(steady, rel=1e-3)       # settled by 2.5 s
    np.testing.assert_allclose(omega, expected[:, 1], atol=5e-3 * steady)
    np.testing.assert_allclose(lateral, expected[:, 0], atol=5e-3 * np.abs(expected[:, 0]).max())
    # the response time (to 90 % of the steady yaw rate) to one output step (0.02 s)
    t90 = t[np.argmax(expected[:, 1] >= 0.9 * steady)]
    assert t[np.argmax(omega >= 0.9 * steady)] == pytest.approx(t90, abs=0.021)


def test_locked_spin_on_the_field_tyre_turns_through_the_closed_form_angle():
    # a pure spin (CG at mid-wheelbase, no translation) on the field tyre with its default
    # load transfer and rolling resistance: locked wheels slide (Coulomb), the CG does not
    # accelerate (no transfer), a locked wheel has no rolling resistance; so the spin stops
    # after Coulomb's angle omega0^2 I / (2 mu m g rho), rho the wheels' arm
    car = RunoutVehicle(1500.0, 2500.0, 2.6, 1.6, 1.3, 0.8, tyre=TyreData())
    rho, w0 = np.hypot(1.3, 0.8), 3.0
    r = runout(car, [0, 0], 0.5, [0.0, 0.0], w0)
    assert r.stopped
    np.testing.assert_allclose(r.rest_position, 0.0, atol=1e-9)
    coulomb = w0 ** 2 * 2500.0 / (2 * 0.8 * 1500.0 * STANDARD_GRAVITY * rho)
    assert r.rest_heading - 0.5 == pytest.approx(coulomb, abs=3e-3)


def _constant_steer_gradient(car, delta, speeds=(10.0, 15.0, 20.0, 25.0, 30.0)):
    """ISO 4138 constant-steer-angle method: settle at each speed with the front wheels
    held at ``delta``; the understeer gradient is the slope of ``delta - L / R`` against
    ``a_y`` [rad s^2/m] (Gillespie eq. 6-15), ``R = v / r``. Returns (gradient, max a_y)."""
    lateral, excess = [], []
    for speed in speeds:
        vx, vy, omega = runout(replace(car, steer=(delta, delta, 0.0, 0.0)), [0, 0], 0.0,
                               [speed, 0.0], 0.0, max_time=6.0).states[-1, 3:]
        v = np.hypot(vx, vy)
        lateral.append(v * omega)
        excess.append(delta - car.wheelbase * omega / v)
    return np.polyfit(lateral, excess, 1)[0], max(lateral)


def test_steady_state_circular_driving_gives_a_measured_cars_understeer_gradient():
    # a 2007 Acura TSX (tests/data, measured on the road: D_f = 6.7, D_r = 3.1, K = 3.6
    # deg/g): the axle cornering stiffnesses are the measured compliances (C = axle weight /
    # D), split over two tyres; friction 0.9 (dry road), CG height 0.55 m and track 1.52 m
    # assumed. In the linear range (0.1 deg held, a_y < 0.02 g) the four-wheel brush model
    # with load transfer gives the car's K to the published digit; at 0.5 deg (a_y up to
    # 0.09 g) the brush's saturation already raises it (progressive understeer, about 5 %)
    tsx = {k: float(v[0]) for k, v in published_table(
        "acura-tsx-2007-cornering-compliance.csv").items()}
    a, b, m = tsx["cg_to_front_m"], tsx["cg_to_rear_m"], tsx["mass_kg"]
    length, per_g = a + b, np.radians(1.0) / STANDARD_GRAVITY        # deg/g -> rad s^2/m
    c_front = m * b / length / (tsx["front_compliance_deg_per_g"] * per_g) / 2
    c_rear = m * a / length / (tsx["rear_compliance_deg_per_g"] * per_g) / 2
    car = RunoutVehicle(m, tsx["yaw_inertia_kgm2"], length, 1.52, a, 0.9,
                        braking=(0, 0, 0, 0),
                        tyre=TyreData(cornering_stiffness=(c_front, c_front, c_rear, c_rear),
                                      cg_height=0.55, rolling_resistance=0.0))
    linear, top = _constant_steer_gradient(car, np.radians(0.1))
    assert top < 0.02 * STANDARD_GRAVITY
    assert linear / per_g == pytest.approx(tsx["understeer_gradient_deg_per_g"], abs=0.1)
    higher, top = _constant_steer_gradient(car, np.radians(0.5))
    assert 0.08 * STANDARD_GRAVITY < top < 0.1 * STANDARD_GRAVITY
    assert 1.02 * linear < higher < 1.08 * linear
