"""The run-out model against pymunk integrating the same tyre forces (sim.runout_check)."""

import numpy as np
import pytest

from pim.model.driver import DriverInputs
from pim.model.runout import RunoutVehicle, runout
from pim.model.tyres import TyreData
from sim.runout_check import pymunk_runout
from tests.bicycle import yaw_rate_gain


@pytest.mark.parametrize("velocity, yaw_rate, braking", [
    ([14.0, 4.0], 1.5, (1, 1, 1, 1)),
    ([9.0, -6.0], -2.5, (1, 1, 0, 0)),
    ([12.0, 2.0], 0.8, (0.3, 0.3, 1.0, 1.0)),
])
def test_pymunk_agrees_with_solve_ivp(velocity, yaw_rate, braking):
    car = RunoutVehicle(1400.0, 2300.0, 2.6, 1.5, 1.1, 0.75, braking=braking,
                        steer=(0.1, 0.1, 0, 0))
    ref = runout(car, [2.0, 1.0], 0.3, velocity, yaw_rate)
    pm = pymunk_runout(car, [2.0, 1.0], 0.3, velocity, yaw_rate, dt=2e-4)
    assert ref.stopped and pm.stopped
    # pymunk is first order: error about |v| dt plus the stop threshold's timing
    np.testing.assert_allclose(pm.rest_position, ref.rest_position, atol=0.02)
    assert pm.rest_heading == pytest.approx(ref.rest_heading, abs=0.01)
    assert pm.stop_time == pytest.approx(ref.stop_time, abs=0.01)


def test_pymunk_runs_the_field_tyre_and_driver_tables_as_solve_ivp():
    # the same brush forces, load transfer and a braking/steer table, integrated by pymunk
    driver = DriverInputs([0.0, 0.3, 1.0], [0.0, 0.1, 0.1],
                          [[0, 0, 0, 0], [1, 1, 0.3, 0.3], [1, 1, 0.3, 0.3]])
    car = RunoutVehicle(1400.0, 2300.0, 2.6, 1.5, 1.1, 0.75, tyre=TyreData(buildup_time=0.1),
                        driver=driver)
    ref = runout(car, [2.0, 1.0], 0.3, [7.0, 3.0], 1.0, rtol=1e-10, atol=1e-12)
    pm = pymunk_runout(car, [2.0, 1.0], 0.3, [7.0, 3.0], 1.0, dt=2e-4)
    assert ref.stopped and pm.stopped
    np.testing.assert_allclose(pm.rest_position, ref.rest_position, atol=0.02)
    assert pm.rest_heading == pytest.approx(ref.rest_heading, abs=0.01)


def test_pymunk_j_turn_settles_to_the_bicycle_models_steady_state():
    # the field tyre's steady cornering integrated by pymunk, not solve_ivp: a J-turn (driver
    # table, ramp to 0.6 deg in 0.3 s) at 20 m/s settles to the bicycle model's yaw rate
    # u delta / (L + K u^2) (tests/bicycle.py) and radius u / r
    c_front, c_rear, delta, speed = 60e3, 90e3, np.radians(0.6), 20.0
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 20.0, braking=(0, 0, 0, 0),
                        tyre=TyreData(cornering_stiffness=(c_front, c_front, c_rear, c_rear),
                                      cg_height=0.55, rolling_resistance=0.0),
                        driver=DriverInputs([0.0, 0.3], [0.0, delta], np.zeros((2, 4))))
    pm = pymunk_runout(car, [0.0, 0.0], 0.0, [speed, 0.0], 0.0, dt=1e-3, max_time=3.0)
    vx, vy, omega = pm.states[-1, 3:]
    expected = yaw_rate_gain(car.mass, car.cg_to_front_axle, car.wheelbase, 2 * c_front,
                             2 * c_rear, speed) * delta
    assert not pm.stopped
    assert omega == pytest.approx(expected, rel=3e-3)
    assert np.hypot(vx, vy) / omega == pytest.approx(speed / expected, rel=3e-3)
