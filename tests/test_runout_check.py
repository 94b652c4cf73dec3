"""The run-out model against pymunk integrating the same tyre forces (sim.runout_check)."""

import numpy as np
import pytest

from pim.model.driver import DriverInputs
from pim.model.runout import RunoutVehicle, runout
from pim.model.tyres import TyreData
from sim.runout_check import pymunk_runout


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
