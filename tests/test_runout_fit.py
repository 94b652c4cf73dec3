"""Run-out inverse (pim.analysis.runout_fit): recovery of a known post-impact motion from
rest states the forward model generated, the unreachable and non-stopping flags, errors."""

import numpy as np
import pytest

from pim.analysis.runout_fit import fit_runout
from pim.model.runout import RunoutVehicle, runout

CAR = RunoutVehicle(1400.0, 2300.0, 2.6, 1.5, 1.1, 0.75)


def test_recovers_a_known_motion_with_a_path_point():
    v, w = np.array([9.0, 4.0]), 1.2
    truth = runout(CAR, [1.0, 2.0], 0.4, v, w, rtol=1e-12, atol=1e-13)
    mid = truth.states[len(truth.states) // 3, :2]
    fit = fit_runout(CAR, [1.0, 2.0], 0.4, truth.rest_position, truth.rest_heading,
                     path_points=[mid])
    assert fit.reachable and fit.stopped and fit.message == ""
    np.testing.assert_allclose(fit.velocity, v, atol=1e-6)
    assert fit.yaw_rate == pytest.approx(w, abs=1e-6)


@pytest.mark.slow
def test_rest_state_alone_has_several_rotations_and_says_so():
    """Three data (x, y, heading mod 2 pi), three unknowns: whole extra turns fit as well."""
    truth = runout(CAR, [1.0, 2.0], 0.4, [9.0, 4.0], 1.2, rtol=1e-12, atol=1e-13)
    fit = fit_runout(CAR, [1.0, 2.0], 0.4, truth.rest_position, truth.rest_heading)
    assert fit.reachable
    assert len(fit.minima) >= 2 and "equally well" in fit.message
    assert fit.yaw_rate == pytest.approx(1.2, abs=1e-6)  # the least rotation is reported


def test_unreachable_rest_is_said_with_the_closest_reachable_one():
    fit = fit_runout(CAR, [0.0, 0.0], 0.0, [80.0, 0.0], 0.0, speed_bounds=(0.0, 10.0),
                     max_evaluations=6, rtol=1e-7, atol=1e-9)
    assert not fit.reachable
    assert "not reached" in fit.message and "closest reachable rest" in fit.message
    assert "speed" in fit.on_bound and fit.speed == pytest.approx(10.0)
    # the closest reachable rest reported is where the fitted motion really stops, short
    # of the evidence (spinning carries a car further than a straight slide's v^2/(2 mu g))
    check = runout(CAR, [0.0, 0.0], 0.0, fit.velocity, fit.yaw_rate)
    np.testing.assert_allclose(fit.rest_position, check.rest_position, atol=1e-6)
    assert 100 / (2 * 0.75 * 9.80665) < fit.rest_position[0] < 40.0


def test_motion_that_does_not_stop_is_flagged():
    free = RunoutVehicle(1400.0, 2300.0, 2.6, 1.5, 1.1, 0.75, braking=(0, 0, 0, 0))
    fit = fit_runout(free, [0.0, 0.0], 0.0, [30.0, 0.0], 0.0, speed_bounds=(2.0, 5.0),
                     max_time=4.0, max_evaluations=2, rtol=1e-7, atol=1e-9)
    assert not fit.stopped and "has not stopped after 4 s" in fit.message


@pytest.mark.parametrize("kwargs, field", [
    (dict(rest_position=[np.nan, 1.0]), "evidence.rest_position"),
    (dict(rest_heading=np.inf), "evidence.rest_heading"),
    (dict(speed_bounds=(-5.0, 10.0)), "unknown.speed bounds"),
    (dict(position_sigma=0.0), "evidence.position_sigma"),
])
def test_bad_evidence_names_the_field(kwargs, field):
    args = dict(rest_position=[5.0, 1.0], rest_heading=0.2)
    args.update(kwargs)
    rest_position, rest_heading = args.pop("rest_position"), args.pop("rest_heading")
    with pytest.raises(ValueError, match=field):
        fit_runout(CAR, [0.0, 0.0], 0.0, rest_position, rest_heading, **args)


def test_path_distance_is_to_the_continuous_path_not_its_chords():
    """A curved run-out (solve_ivp's steps are long, their chords cut inside the curve by
    millimetres): the distance must be the brute-force one on the dense output."""
    from pim.analysis.runout_fit import path_distance
    from pim.model.runout import RunoutVehicle, runout

    car = RunoutVehicle(mass=1500.0, yaw_inertia=2500.0, wheelbase=2.7, track=1.5,
                        cg_to_front=1.2, friction=0.8, braking=(1.0, 1.0, 0.3, 0.3))
    run = runout(car, [0, 0], 0.4, [6.17, 1.53], 1.2, rtol=1e-9, atol=1e-11,
                 dense_output=True)
    points = np.array([[1.63987893, 0.49641693], [2.5, 1.3]])
    t = np.linspace(0.0, run.time[-1], 200_001)
    path = run.interpolant(t)[:2].T
    brute = [np.min(np.hypot(*(path - p).T)) for p in points]
    np.testing.assert_allclose(path_distance(points, run), brute, atol=2e-6)
    np.testing.assert_allclose(np.abs(path_distance(points, run, signed=True)), brute,
                               atol=2e-6)
