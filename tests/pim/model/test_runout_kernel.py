"""pim/model/runout_kernel.py: the compiled batched run-out against closed forms, the numpy
fixed-step integrator (same scheme: agreement to round-off), solve_ivp (the reference), and
the path-point distance against geometry."""

from dataclasses import replace

import numpy as np
import pytest

from pim.model.driver import DriverInputs
from pim.model.runout import RunoutVehicle, TimedRhs, runout, runout_many, runout_rhs
from pim.model.runout_kernel import CompiledRhs, integrate_many
from pim.model.tyres import TyreData, regularised_slide_distance

# one xdist worker runs every test of the compiled run-out (--dist loadgroup): two workers
# would each compile it at once (about a minute each on a fresh clone)
pytestmark = pytest.mark.xdist_group("runout_kernel")

CAR = RunoutVehicle(mass=1500.0, yaw_inertia=2500.0, wheelbase=2.7, track=1.5,
                    cg_to_front_axle=1.2, friction=0.8, braking=(1.0, 1.0, 0.3, 0.3),
                    steer=(0.2, 0.2, 0.0, 0.0))


def test_locked_straight_slide_is_the_closed_form():
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8)
    v0 = np.array([20.0, 8.0, 31.0])
    psi = np.array([0.3, -2.0, 1.0])
    d = np.stack([np.cos(psi), np.sin(psi)], axis=-1)
    final, _, stopped, _ = integrate_many(car, np.zeros((3, 2)), psi, v0[:, None] * d,
                                          np.zeros(3))
    assert stopped.all()
    np.testing.assert_allclose(np.hypot(*final[:, :2].T),
                               regularised_slide_distance(v0, 0.8), atol=5e-4)


def test_same_scheme_as_the_numpy_integrator_and_close_to_solve_ivp():
    rng = np.random.default_rng(5)
    n = 40
    pos = rng.uniform(-3, 3, (n, 2))
    psi = rng.uniform(-np.pi, np.pi, n)
    vel = rng.uniform(-12, 12, (n, 2))
    omega = rng.uniform(-3, 3, n)
    final, stop_time, stopped, _ = integrate_many(CAR, pos, psi, vel, omega)
    batch = runout_many(CAR, pos, psi, vel, omega)
    np.testing.assert_allclose(final[:, :2], batch.rest_position, atol=1e-9)
    np.testing.assert_allclose(final[:, 2], batch.rest_heading, atol=1e-9)
    np.testing.assert_array_equal(stopped, batch.stopped)
    for k in range(5):
        ref = runout(CAR, pos[k], psi[k], vel[k], omega[k], rtol=1e-11, atol=1e-12)
        assert np.hypot(*(final[k, :2] - ref.rest_position)) < 2e-3
        assert abs(final[k, 2] - ref.rest_heading) < 1e-3


def test_path_distance_is_the_distance_to_the_travelled_line():
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8)
    # straight slide along +x from the origin: a point at (5, 0.7) is 0.7 m off the path,
    # one to its right is at -0.4 m (signed cross-track error)
    _, _, _, dist = integrate_many(car, [[0.0, 0.0]], [0.0], [[15.0, 0.0]], [0.0],
                                   path_points=[[5.0, 0.7], [6.0, -0.4]])
    np.testing.assert_allclose(dist[0], [0.7, -0.4], atol=1e-9)   # left +, right -


def test_free_rolling_is_flagged_not_stopped():
    car = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.2, 0.8, braking=(0, 0, 0, 0))
    final, stop_time, stopped, _ = integrate_many(car, [[0.0, 0.0]], [0.0], [[12.0, 0.0]],
                                                  [0.0], max_time=2.0)
    assert not stopped[0] and stop_time[0] == pytest.approx(2.0, abs=0.004)
    assert final[0, 3] == pytest.approx(12.0, abs=1e-9)


def test_non_finite_state_is_an_error():
    with pytest.raises(ValueError, match="finite"):
        integrate_many(CAR, [[0.0, np.nan]], [0.0], [[1.0, 0.0]], [0.0])


def test_field_tyre_and_driver_tables_match_solve_ivp():
    # the compiled brush law with load transfer, build-up and a steer/brake table against
    # the numpy right-hand side integrated by solve_ivp
    driver = DriverInputs([0.0, 0.4, 1.0], [0.0, 0.15, 0.05],
                          [[0, 0, 0, 0], [0.6, 0.6, 0.2, 0.2], [1, 1, 0.3, 0.3]])
    car = replace(CAR, tyre=TyreData(buildup_time=0.2), driver=driver)
    pos = np.array([[0.0, 0.0], [1.0, 2.0], [-1.0, 0.5]])
    psi = np.array([0.3, -1.0, 2.0])
    vel = np.array([[18.0, 4.0], [-6.0, 7.0], [3.0, -9.0]])
    omega = np.array([1.0, -2.0, 0.0])
    final, _, stopped, _ = integrate_many(car, pos, psi, vel, omega)
    assert stopped.all()
    for k in range(3):
        ref = runout(car, pos[k], psi[k], vel[k], omega[k], rtol=1e-10, atol=1e-12)
        assert np.hypot(*(final[k, :2] - ref.rest_position)) < 1e-2
        assert abs(final[k, 2] - ref.rest_heading) < 2e-3


DRIVER = DriverInputs([0.0, 0.4, 1.0], [0.0, 0.15, 0.05],
                      [[0, 0, 0, 0], [0.6, 0.6, 0.2, 0.2], [1, 1, 0.3, 0.3]])


@pytest.mark.parametrize("car", [CAR, replace(CAR, tyre=TyreData(buildup_time=0.2)),
                                 replace(CAR, driver=DRIVER),
                                 replace(CAR, tyre=TyreData(buildup_time=0.2, cg_height=0.6),
                                         driver=DRIVER)],
                         ids=["coulomb", "brush", "coulomb-driver", "brush-driver"])
def test_compiled_rhs_is_the_numpy_rhs(car):
    # the single fit's compiled right-hand side computes what the numpy ones do (the same
    # tyre functions compiled), at states spanning rolling, sliding and near rest
    rng = np.random.default_rng(2)
    rhs = CompiledRhs(car)
    numpy_rhs = TimedRhs(car)
    for t in (0.0, 0.1, 0.3, 0.7, 2.0):
        for scale in (20.0, 1.0, 0.03):
            y = np.concatenate([rng.uniform(-5, 5, 2), rng.uniform(-4, 4, 1),
                                rng.uniform(-scale, scale, 2), rng.uniform(-scale, scale, 1)])
            ref = numpy_rhs(t, y)
            np.testing.assert_allclose(ref, runout_rhs(t, y, car), rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(rhs(t, y), ref, rtol=1e-11, atol=1e-9)


def test_run_out_on_the_compiled_rhs_is_the_numpy_run_out():
    car = replace(CAR, tyre=TyreData(buildup_time=0.15))
    ref = runout(car, [1.0, 2.0], 0.3, [12.0, 3.0], 1.5)
    fast = runout(car, [1.0, 2.0], 0.3, [12.0, 3.0], 1.5, rhs=CompiledRhs(car))
    np.testing.assert_allclose(fast.rest_position, ref.rest_position, atol=1e-8)
    assert fast.rest_heading == pytest.approx(ref.rest_heading, abs=1e-8)
    assert fast.stop_time == pytest.approx(ref.stop_time, abs=1e-8)


def test_field_tyre_rest_state_is_smooth_in_the_initial_speed():
    # the brush tyre's lateral slope C_y / V_r is stiff near rest: at a fixed 4 ms step RK4
    # chattered about rest and the rest state jumped by ~4e-6 m between neighbouring speeds
    # (noise the Monte Carlo's finite-difference fits then fought for twice the iterations);
    # the step now shrinks with the speed there, and the rest state is smooth
    car = replace(CAR, steer=(0.0, 0.0, 0.0, 0.0), tyre=TyreData(cg_height=0.58))
    k = 21
    ds = np.linspace(-5e-3, 5e-3, k)
    velocity = (7.0 + ds)[:, None] * np.array([0.6, 0.8])
    final, _, stopped, _ = integrate_many(car, np.zeros((k, 2)), np.full(k, 0.4), velocity,
                                          np.full(k, 1.5))
    assert stopped.all()
    for column in (final[:, 0], final[:, 1], final[:, 2]):
        wobble = column - np.polyval(np.polyfit(ds, column, 2), ds)
        assert np.std(wobble) < 1e-6
    ref = runout(car, [0.0, 0.0], 0.4, velocity[k // 2], 1.5, rtol=1e-11, atol=1e-12)
    assert np.hypot(*(final[k // 2, :2] - ref.rest_position)) < 1e-4


def test_every_call_has_the_one_compiled_signature(monkeypatch):
    # numba compiles the kernel once per tuple of argument types (about a minute each):
    # one sample (read-only broadcast views), many, per-sample vehicle data, a driver table,
    # the field tyre and path points must all reach it with the same types
    import numba

    from pim.model import runout_kernel

    seen = set()
    monkeypatch.setattr(runout_kernel, "_integrate",
                        lambda *args: seen.add(tuple(numba.typeof(a) for a in args)))
    driver = DriverInputs([0.0, 0.4, 1.0], [0.0, 0.15, 0.05],
                          [[0, 0, 0, 0], [0.6, 0.6, 0.2, 0.2], [1, 1, 0.3, 0.3]])
    per_sample = replace(CAR, mass=np.array([1500.0, 1400.0, 1300.0]),
                         friction=np.array([0.8, 0.7, 0.75]))
    for car, n, points in [(CAR, 1, None), (CAR, 3, None), (per_sample, 3, [[5.0, 0.7]]),
                           (replace(CAR, tyre=TyreData(), driver=driver), 1, None),
                           (replace(per_sample, tyre=TyreData()), 3, [[1.0, 2.0], [3, 4]])]:
        integrate_many(car, np.zeros((n, 2)), np.zeros(n), np.ones((n, 2)), np.zeros(n),
                       path_points=points, stop_speed=np.float64(0.1))
    assert len(seen) == 1, seen
