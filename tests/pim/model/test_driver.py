"""Driver inputs over time (pim.model.driver): table checks, per-wheel tables, the build-up
start, and a vehicle braking into the impact against the closed form."""

import numpy as np
import pytest

from pim.model.driver import DriverInputs, wheel_tables
from pim.model.runout import RunoutVehicle, pre_impact_motion
from pim.model.tyres import STANDARD_GRAVITY, TyreData


def test_tables_are_checked_naming_the_field():
    with pytest.raises(ValueError, match="driver.time"):
        DriverInputs([0.0, 0.0], [0.0, 0.0], np.zeros((2, 4)))
    with pytest.raises(ValueError, match="driver.steer"):
        DriverInputs([0.0, 1.0], [0.0], np.zeros((2, 4)))
    with pytest.raises(ValueError, match="driver.brake"):
        DriverInputs([0.0, 1.0], [0.0, 0.0], [[0, 0, 0, 0], [0, 0, 0, 1.5]])


def test_wheel_tables_steer_the_front_wheels_and_find_the_brake_start():
    d = DriverInputs([-1.0, 0.0, 0.5], [0.0, 0.1, 0.2], [[0] * 4, [0] * 4, [1, 1, 0.5, 0.5]])
    time, steer, brake, start = wheel_tables(d, None, None)
    assert steer[:, 0].tolist() == steer[:, 1].tolist() == [0.0, 0.1, 0.2]
    assert not steer[:, 2:].any() and brake.shape == (3, 4)
    assert start == 0.0                        # braking rises from zero after t = 0
    assert DriverInputs([0.0], [0.0], [[1, 1, 1, 1]]).brake_start == -np.inf
    time, steer, brake, start = wheel_tables(None, (1, 1, 0, 0), (0.1, 0.1, 0, 0))
    assert time.tolist() == [0.0] and brake.tolist() == [[1, 1, 0, 0]] and start == 0.0


def test_braking_into_the_impact_is_the_closed_form():
    # brake table rising linearly from 0 at -1.5 s to locked at -1.2 s, held to the impact:
    # v(0) = v0 - a (0.3 / 2 + 1.2); x(0) = v0 0.5 + (v0 0.3 - a 0.3^2 / 6) + v1 1.2
    # - a 1.2^2 / 2 with v1 = v0 - a 0.15, a = mu g (straight, equal fractions: sum f mu N)
    driver = DriverInputs([-2.0, -1.5, -1.2, 0.0], [0.0] * 4,
                          [[0] * 4, [0] * 4, [1] * 4, [1] * 4])
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8, driver=driver,
                        tyre=TyreData(rolling_resistance=0.0))
    v0, a = 25.0, 0.8 * STANDARD_GRAVITY
    position, heading, velocity, yaw_rate = pre_impact_motion(car, [0.0, 0.0], 0.0,
                                                              [v0, 0.0], 0.0, -2.0)
    v1 = v0 - a * 0.15
    assert velocity[0] == pytest.approx(v0 - a * 1.35, rel=2e-4)
    assert position[0] == pytest.approx(v0 * 0.5 + v0 * 0.3 - a * 0.09 / 6 + v1 * 1.2
                                        - a * 1.44 / 2, rel=2e-4)
    assert heading == 0.0 and yaw_rate == 0.0 and velocity[1] == 0.0
    with pytest.raises(ValueError, match="start_time"):
        pre_impact_motion(car, [0.0, 0.0], 0.0, [v0, 0.0], 0.0, 1.0)
