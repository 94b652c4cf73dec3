"""Pre-impact motion (pim.model.pre_impact): tyre marks before the impact in closed form, and
the driver-table path (a root find on pim.model.runout.pre_impact_motion) against the closed
forms of constant deceleration and of a brake build-up integrated by hand."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pim.model.driver import DriverInputs
from pim.model.numbers import InputError
from pim.model.pre_impact import (
    PreImpactMarks,
    drag_fraction,
    driver_speed_at_impact,
    driver_start_speed,
    mark_deceleration,
    speed_at_mark_start,
)
from pim.model.runout import RunoutVehicle
from pim.model.tyres import TyreData

G = 9.80665
MPH = 0.44704
FT = 0.3048


def test_locked_skid_on_level_ground_is_the_energy_balance():
    # v_start^2 - v_imp^2 = 2 mu g L: the friction work mu m g L is the kinetic energy lost
    v = speed_at_mark_start(12.0, 20.0, 0.7)
    assert v ** 2 - 12.0 ** 2 == pytest.approx(2 * 0.7 * G * 20.0, rel=1e-14)


def test_skid_to_stop_matches_the_textbook_mph_formula():
    """Fricke (1990), speed from skidmarks: S = sqrt(30 d f) [mph, ft] for a skid to a stop
    (the 30 rounds 2 g / (1.4667 ft/s per mph)^2 = 29.92: tolerance 0.3 %); the combined
    speed equation S = sqrt(S_imp^2 + 30 d f) the same."""
    for d_ft, f, s_imp in ((100.0, 0.7, 0.0), (42.0, 0.75, 25.0), (8.0, 0.4, 40.0)):
        textbook = math.sqrt(s_imp ** 2 + 30 * d_ft * f)
        v = speed_at_mark_start(s_imp * MPH, d_ft * FT, f) / MPH
        assert v == pytest.approx(textbook, rel=3e-3)


def test_grade_is_the_force_balance_along_the_incline():
    # braking 0: no friction work, only the climb: v_start^2 = v^2 + 2 g (L sin theta)
    theta = math.radians(10.0)
    v = speed_at_mark_start(10.0, 30.0, 0.7, braking=0.0, grade=math.tan(theta))
    assert v ** 2 == pytest.approx(100.0 + 2 * G * 30.0 * math.sin(theta), rel=1e-13)
    # locked on a 30 degree slope: friction mu N = mu m g cos(30) plus the weight's m g sin(30)
    a = mark_deceleration(0.8, 1.0, math.tan(math.radians(30.0)))
    assert a == pytest.approx(G * (0.8 * math.sqrt(3) / 2 + 0.5), rel=1e-14)


def test_small_grade_is_the_textbooks_f_plus_minus_g():
    # S = sqrt(30 d (f +- G)): the small-angle form, within O(G^2) of the exact one
    for grade in (0.02, -0.02, 0.05):
        exact = speed_at_mark_start(0.0, 30.0, 0.7, grade=grade)
        textbook = math.sqrt(2 * G * 30.0 * (0.7 + grade))
        assert exact == pytest.approx(textbook, rel=grade ** 2)
    assert speed_at_mark_start(10.0, 30.0, 0.7, grade=0.05) > speed_at_mark_start(
        10.0, 30.0, 0.7) > speed_at_mark_start(10.0, 30.0, 0.7, grade=-0.05)


def test_braking_fraction_and_per_wheel_drag():
    v = speed_at_mark_start(5.0, 25.0, 0.8, braking=0.3)
    assert v ** 2 - 25.0 == pytest.approx(2 * 0.3 * 0.8 * G * 25.0, rel=1e-14)
    # front wheels locked, rear rolling: the front axle's share of the weight brakes
    assert drag_fraction((1, 1, 0, 0), front_share=0.6) == pytest.approx(0.6)
    assert drag_fraction((0, 0, 1, 1), front_share=0.6) == pytest.approx(0.4)
    assert drag_fraction((1, 0, 1, 0), front_share=0.6) == pytest.approx(0.5)
    marks = PreImpactMarks(20.0, 0.7, braking=(1.0, 1.0, 0.0, 0.0), front_share=0.6)
    assert marks.drag == pytest.approx(0.6)
    assert marks.start_speed(10.0) == pytest.approx(speed_at_mark_start(10.0, 20.0, 0.7, 0.6))


def test_vectorised_over_samples():
    v = np.array([8.0, 10.0, 12.0])
    mu = np.array([0.6, 0.7, 0.8])
    out = PreImpactMarks(20.0, 0.7).start_speed(v, friction=mu, length=np.array([19., 20, 21]))
    assert out.shape == (3,)
    for k in range(3):
        assert out[k] == pytest.approx(speed_at_mark_start(v[k], 19.0 + k, mu[k]))


@given(st.floats(0, 60), st.floats(0, 200), st.floats(0.05, 1.5), st.floats(0, 1))
def test_start_speed_never_below_impact_speed_on_level_ground(v, length, mu, braking):
    assert speed_at_mark_start(v, length, mu, braking) >= v


@given(st.floats(0, 60), st.floats(0, 100), st.floats(0, 100), st.floats(0.05, 1.5))
def test_longer_marks_mean_a_higher_start_speed(v, a, b, mu):
    short, long = sorted((a, b))
    assert speed_at_mark_start(v, long, mu) >= speed_at_mark_start(v, short, mu)


@pytest.mark.parametrize("kwargs, words", [
    ({"length": -1.0}, "pre_impact.skid_length must be >= 0"),
    ({"friction": 0.0}, "pre_impact.friction must be > 0"),
    ({"friction": -0.3}, "pre_impact.friction must be > 0"),
    ({"braking": 1.2}, "pre_impact.braking must be in [0, 1]"),
    ({"braking": -0.1}, "pre_impact.braking must be in [0, 1]"),
    ({"grade": 1.5}, "pre_impact.grade must be in [-1, 1]"),
    ({"grade": -0.3, "friction": 0.2}, "steeper downhill than the friction holds"),
    ({"impact_speed": -1.0}, "pre_impact.impact_speed must be >= 0"),
    ({"length": float("nan")}, "pre_impact.skid_length"),
    ({"friction": "0.7"}, "pre_impact.friction must be a number"),
])
def test_every_bad_input_names_its_field(kwargs, words):
    args = {"impact_speed": 10.0, "length": 20.0, "friction": 0.7, **kwargs}
    with pytest.raises(InputError, match=None) as exc:
        speed_at_mark_start(**args)
    assert words in str(exc.value)


def test_marks_check_their_fields_where_they_were_written():
    where = "evidence.vehicle2.pre_impact"
    with pytest.raises(InputError, match=r"evidence\.vehicle2\.pre_impact\.braking must be one"):
        PreImpactMarks(20.0, 0.7, braking=(1.0, 1.0), where=where)
    with pytest.raises(InputError, match=r"evidence\.vehicle2\.pre_impact\.length_sigma"):
        PreImpactMarks(20.0, 0.7, length_sigma=-1.0, where=where)
    with pytest.raises(InputError, match=r"evidence\.vehicle2\.pre_impact\.grade .*speed up"):
        PreImpactMarks(20.0, 0.3, grade=-0.5, where=where)
    with pytest.raises(InputError, match=r"evidence\.vehicle2\.pre_impact\.friction"):
        PreImpactMarks(20.0, 0.0, where=where)


# --- the driver-table path ------------------------------------------------------------------

def _car(driver, friction=0.7, tyre=None):
    return RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, friction, driver=driver, tyre=tyre)


def test_locked_from_the_first_time_is_constant_deceleration():
    # Coulomb tyre, all wheels locked from t0 = -1.5 s: v0 = v_imp + mu g |t0|
    car = _car(DriverInputs([-1.5, 0.0], [0.0, 0.0], [[1.0] * 4] * 2))
    v0 = driver_start_speed(car, 12.0)
    assert v0 == pytest.approx(12.0 + 0.7 * G * 1.5, rel=2e-5)   # regularisation: ~1e-5
    # the same as the marks' closed form over the distance slid
    distance = (v0 ** 2 - 12.0 ** 2) / (2 * 0.7 * G)
    assert speed_at_mark_start(12.0, distance, 0.7) == pytest.approx(v0, rel=1e-12)


def test_a_braking_ramp_in_the_table_integrated_by_hand():
    # brake fraction rising linearly 0 -> 1 over T = 0.4 s from t0 = -2 s, then held:
    # the deceleration mu g b(t) loses mu g (T / 2 + (|t0| - T)) of speed (Coulomb tyre)
    car = _car(DriverInputs([-2.0, -1.6, 0.0], [0.0] * 3, [[0.0] * 4, [1.0] * 4, [1.0] * 4]))
    v0 = driver_start_speed(car, 10.0)
    assert v0 == pytest.approx(10.0 + 0.7 * G * (0.2 + 1.6), rel=2e-5)


def test_field_tyre_brake_build_up_integrated_by_hand():
    """Field tyre, braking demanded from t0 = -2 s (a step in the table) with a build-up of
    t_b = 0.25 s and rolling resistance c: during the build-up the slip-controlled brake
    gives r(t) mu N (r rising linearly 0 -> 1) and the rolling wheels c N; then the wheels
    lock (mu N). Speed lost: g (mu (t_b / 2 + |t0| - t_b) + c t_b)."""
    tb, c, t0 = 0.25, 0.013, -2.0
    table = DriverInputs([t0, t0 + 1e-9, 0.0], [0.0] * 3, [[0.0] * 4, [1.0] * 4, [1.0] * 4])
    car = _car(table, tyre=TyreData(buildup_time=tb, rolling_resistance=c))
    v0 = driver_start_speed(car, 12.0)
    expected = 12.0 + G * (0.7 * (tb / 2 + abs(t0) - tb) + c * tb)
    assert v0 == pytest.approx(expected, rel=1e-4)


def test_a_start_speed_too_low_stops_the_car_and_counts_as_zero():
    car = _car(DriverInputs([-1.5, 0.0], [0.0, 0.0], [[1.0] * 4] * 2))
    assert driver_speed_at_impact(car, 5.0, -1.5) == 0.0          # stops after 0.73 s
    assert driver_speed_at_impact(car, 15.0, -1.5) == pytest.approx(15 - 0.7 * G * 1.5,
                                                                   rel=1e-4)


def test_no_braking_keeps_the_speed():
    car = _car(DriverInputs([-1.0, 0.0], [0.0, 0.0], [[0.0] * 4] * 2))
    assert driver_start_speed(car, 9.0) == 9.0


def test_driver_path_errors_name_the_table():
    car = _car(DriverInputs([-1.5, 0.0], [0.0, 0.0], [[1.0] * 4] * 2))
    with pytest.raises(InputError, match=r"driver\.vehicle1: the impact speed 0 m/s .* at rest"):
        driver_start_speed(car, 0.0, where="driver.vehicle1")
    with pytest.raises(InputError, match=r"driver\.vehicle1\.time: the first time must be < 0"):
        driver_start_speed(_car(DriverInputs([0.0, 1.0], [0.0, 0.0], [[1.0] * 4] * 2)), 10.0,
                           where="driver.vehicle1")
    with pytest.raises(InputError, match="no driver table"):
        driver_start_speed(_car(None), 10.0)
