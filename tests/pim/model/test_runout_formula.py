"""pim/model/runout_formula.py: the run-out's right-hand side written once, evaluated three
ways (Python floats: TimedRhs, the solve_ivp reference; numpy arrays: runout_rhs; numba:
CompiledRhs), agreeing to round-off on random run-out states (hypothesis), for both tyre laws,
every wheel state (locked, braked, free-rolling, steered) and driver tables; and against an
independent evaluation of the equations of motion from the tyre law's vectorised form."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pim.model import runout_formula
from pim.model.driver import DriverInputs
from pim.model.runout import RhsData, RunoutVehicle, TimedRhs, runout_rhs
from pim.model.runout_kernel import CompiledRhs
from pim.model.tyres import TyreData, net_force_and_moment, tyre_forces

pytestmark = pytest.mark.xdist_group("runout_kernel")   # one worker compiles the kernel

DRIVER = DriverInputs([0.0, 0.4, 1.0], [0.0, 0.15, -0.05],
                      [[0, 0, 0, 0], [0.6, 0.6, 0.2, 0.2], [1, 1, 0.3, 0.3]])

fraction = st.floats(0.0, 1.0)
vehicles = st.builds(
    lambda m, ratio, length, track, a, mu, braking, steer, tyre, driver, height: RunoutVehicle(
        mass=m, yaw_inertia=ratio * m, wheelbase=length, track=track,
        cg_to_front_axle=a * length, friction=mu, braking=braking,
        steer=(steer, steer, 0.0, 0.0),
        tyre=TyreData(cg_height=height, buildup_time=0.2) if tyre else None,
        driver=DRIVER if driver else None),
    st.floats(800.0, 3000.0), st.floats(0.8, 2.5), st.floats(2.2, 3.4), st.floats(1.3, 1.8),
    st.floats(0.1, 0.9), st.floats(0.2, 1.1),
    st.tuples(fraction, fraction, fraction, fraction) | st.sampled_from(
        [(1.0, 1.0, 1.0, 1.0), (0.0, 0.0, 0.0, 0.0), (1.0, 1.0, 0.0, 0.0)]),
    st.floats(-0.5, 0.5), st.booleans(), st.booleans(), st.floats(0.3, 0.8))
states = st.tuples(st.floats(-50, 50), st.floats(-50, 50), st.floats(-7, 7),
                   st.floats(-30, 30), st.floats(-30, 30), st.floats(-6, 6))
speed_scales = st.sampled_from([1.0, 0.05, 1e-3])   # sliding, rolling near rest, at rest


def scaled(state, scale):
    y = np.array(state, dtype=float)
    y[3:] *= scale
    return y


@settings(max_examples=150, deadline=None)
@given(vehicles, states, speed_scales, st.floats(0.0, 1.5))
def test_compiled_and_numpy_are_the_reference_to_round_off(car, state, scale, t):
    y = scaled(state, scale)
    ref = TimedRhs(car)(t, y)
    assert np.all(np.isfinite(ref))
    bound = 1e-12 * (np.abs(ref) + np.max(np.abs(ref[3:5])) + 1e-300)
    bound[5] += 1e-12 * np.max(np.abs(ref[3:5])) * 3.0     # moment: arms of ~3 m
    assert np.all(np.abs(CompiledRhs(car)(t, y) - ref) <= 64 * bound)
    assert np.all(np.abs(runout_rhs(t, y, car) - ref) <= 64 * bound)


@settings(max_examples=40, deadline=None)
@given(vehicles, st.lists(states, min_size=2, max_size=6), st.floats(0.0, 1.5))
def test_numpy_over_samples_is_each_sample(car, rows, t):
    # per-sample friction and braking: the samples travel on the last axis of every array
    n = len(rows)
    y = np.array(rows)
    friction = np.linspace(0.3, 1.0, n)
    braking = np.linspace(0.0, 1.0, 4 * n).reshape(n, 4)
    many = replace(car, friction=friction, braking=braking)
    batch = runout_rhs(t, y, many)
    for i in range(n):
        one = replace(car, friction=friction[i], braking=braking[i])
        np.testing.assert_allclose(batch[i], TimedRhs(one)(t, y[i]), rtol=1e-13, atol=1e-10)


@settings(max_examples=60, deadline=None)
@given(vehicles.filter(lambda v: not v.timed), states, speed_scales)
def test_coulomb_rhs_is_newton_with_the_vectorised_tyre_law(car, state, scale):
    # independent of the formula's loop: the tyre law's vectorised form (tyre_forces, its
    # wheel headings by cos(psi + delta) rather than by angle addition) and the resultant
    # force and moment, then m dv/dt = F, I domega/dt = M
    y = scaled(state, scale)
    forces = tyre_forces(y[3:5], y[5], y[2], car.positions, car.loads, car.friction,
                         np.asarray(car.braking), np.asarray(car.steer),
                         regularisation=car.regularisation)
    force, moment = net_force_and_moment(forces, car.positions, y[2])
    expected = np.concatenate([y[3:6], force / car.mass, [moment / car.yaw_inertia]])
    np.testing.assert_allclose(TimedRhs(car)(0.0, y), expected, rtol=1e-9,
                               atol=1e-9 * np.max(np.abs(expected)))


def test_field_tyre_loads_follow_the_acceleration():
    # braking hard straight ahead: the front axle gains m a h / L, the forces are those of
    # the transferred loads (one fixed-point pass), not of the static ones
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8, tyre=TyreData(cg_height=0.55))
    data = RhsData.of(car, 1).sample(0)
    y = (0.0, 20.0, 0.0, 0.0)
    static = runout_formula.tyre_sum(0.0, (1.0, 0.0, 20.0, 0.0, 0.0), data, (0.0, 0.0), 1.0)
    d = runout_formula.derivative(0.0, y, data)
    along = static[0] / car.mass
    transferred = runout_formula.tyre_sum(0.0, (1.0, 0.0, 20.0, 0.0, 0.0), data,
                                          (along, 0.0), 1.0)
    assert d[3] == transferred[0] / car.mass
    front = runout_formula.wheel_load(0, car.loads[0], car.mass, data[10], along, 0.0)
    assert front == pytest.approx(car.loads[0] - car.mass * along * 0.55 / (2 * 2.7))
    assert front > car.loads[0]

