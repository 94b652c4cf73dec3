"""The NHTSA fishhook through the planar run-out (field tyre, driver table) against
PC-Crash's published runs of a 2004 Chevrolet Malibu (tests/fishhook.py, tests/data), and the
same steer table at small amplitude against the linear bicycle model's closed form.

Tolerances (stated before the comparison, from what the planar model leaves out: PC-Crash
rolls the body up to 4.9 deg and shifts load through its suspension with a lag, steers the
wheels with Ackermann, and uses its own tyre curve): first yaw-rate peak 10 % and 0.35 s
(the published 0.1 s samples), countersteer yaw-rate peak 5 % and 0.15 s, first-steer lateral
acceleration 0.05 g, CG path 1.5 m for the first 3 s and 8 m over the whole run (a spinning
car, 95-150 m travelled), final heading 8 deg. What a planar model cannot show at all: the
roll angle, the two-wheel lift the fishhook is designed to find, the vertical loads' dynamics.
"""

import numpy as np
import pytest

from pim.model.driver import DriverInputs
from pim.model.runout import runout
from pim.model.tyres import STANDARD_GRAVITY
from tests.bicycle import matrices, table_response
from tests.fishhook import MALIBU, MPH, compare, load, malibu, simulate


def _check(m):
    (pub, mod), (t_pub, t_mod) = m.first_peak_yaw_rate, m.first_peak_time
    assert mod == pytest.approx(pub, rel=0.10) and t_mod == pytest.approx(t_pub, abs=0.35)
    (pub, mod), (t_pub, t_mod) = m.second_peak_yaw_rate, m.second_peak_time
    assert mod == pytest.approx(pub, rel=0.05) and t_mod == pytest.approx(t_pub, abs=0.15)
    pub, mod = m.first_peak_lateral
    assert mod == pytest.approx(pub, abs=0.05 * STANDARD_GRAVITY)
    assert m.path_error_3s < 1.5 and m.path_error_end < 8.0
    pub, mod = m.final_heading
    assert np.degrees(mod) == pytest.approx(np.degrees(pub), abs=8.0)


@pytest.mark.parametrize("speed", [35, 45])
def test_fishhook_matches_pc_crashs_published_run(speed):
    run = load(speed)
    assert run.speed_mph == speed
    _check(compare(run, simulate(run)))


@pytest.mark.slow
@pytest.mark.parametrize("speed", [35, 40, 45])
def test_fishhook_all_speeds_and_the_initial_slope_mapping(speed):
    # 40 mph with the same tolerances; the initial-slope mapping (a tyre 3 times softer at
    # small slip) still spins the car to the published heading within 8 deg, but reaches
    # only 0.55 g in the first steer (docs/tyres.md, the table)
    run = load(speed)
    _check(compare(run, simulate(run)))
    slope = compare(run, simulate(run, "slope"))
    pub, mod = slope.final_heading
    assert np.degrees(mod) == pytest.approx(np.degrees(pub), abs=8.0)
    assert slope.first_peak_lateral[1] < 0.6 * STANDARD_GRAVITY


def test_fishhook_steer_table_at_small_amplitude_is_the_linear_bicycle_models():
    # the published fishhook steer table scaled to 1/100 (0.1 deg of road-wheel angle): the
    # Malibu's yaw rate follows the closed-form response of the linear bicycle model to the
    # same table (tests/bicycle.py, superposed ramps) through the dwell, the countersteer and
    # the unwinding, within 1 % of its peak
    run = load(35)
    steer = run.steer / 100
    car = malibu(DriverInputs(run.motion.time, steer, np.zeros((steer.size, 4))))
    speed = 35 * MPH
    r = runout(car, [0.0, 0.0], 0.0, [speed, 0.0], 0.0, max_time=8.0, dense_output=True,
               rtol=1e-8, atol=1e-10)
    t = np.linspace(0.0, 8.0, 161)
    omega = r.interpolant(t)[5]
    c = np.asarray(car.tyre.cornering_stiffness)
    a_mat, b_vec = matrices(MALIBU["mass"], MALIBU["yaw_inertia"], MALIBU["cg_to_front_axle"],
                            MALIBU["wheelbase"], c[0] + c[1], c[2] + c[3], speed)
    expected = table_response(a_mat, b_vec, run.motion.time, steer, t)[:, 1]
    peak = np.abs(expected).max()
    assert peak > 0.3 * np.abs(run.motion.yaw_rate).max() / 100       # not a null test
    np.testing.assert_allclose(omega, expected, atol=0.01 * peak)
