"""pim/analysis/runout_fit_batch.py: many run-out inverses at once, against the truth the
evidence was generated from (solve_ivp forward runs) and against the single fit
(pim.analysis.runout_fit.fit_runout) on the same noisy evidence."""

import numpy as np
import pytest

from pim.analysis.runout_fit import fit_runout
from pim.analysis.runout_fit_batch import fit_runout_many
from pim.model.runout import RunoutVehicle, runout

# one xdist worker runs every test of the compiled run-out (--dist loadgroup): two workers
# would each compile it at once (about a minute each on a fresh clone)
pytestmark = pytest.mark.xdist_group("runout_kernel")

CAR = RunoutVehicle(mass=1500.0, yaw_inertia=2500.0, wheelbase=2.7, track=1.5,
                    cg_to_front_axle=1.2, friction=0.8, braking=(1.0, 1.0, 0.3, 0.3))
V, OMEGA, PSI = np.array([6.0, 1.5]), 1.2, 0.4


@pytest.fixture(scope="module")
def evidence():
    ref = runout(CAR, [0.0, 0.0], PSI, V, OMEGA, rtol=1e-12, atol=1e-13, dense_output=True)
    point = ref.interpolant(0.3 * ref.stop_time)[:2]
    return ref.rest_position, ref.rest_heading, point


def start():
    return (np.hypot(*V) * 1.1, np.arctan2(V[1], V[0]) + 0.05, OMEGA * 0.9)


def test_noise_free_evidence_gives_back_the_motion(evidence):
    rest, heading, point = evidence
    fit = fit_runout_many(CAR, [[0.0, 0.0]] * 3, [PSI] * 3, [rest] * 3, [heading] * 3,
                          start=start(), path_points=[point])
    assert fit.converged.all() and fit.reachable.all() and fit.stopped.all()
    # fixed 4 ms steps against solve_ivp's 1e-12 evidence: agreement to ~1e-4
    np.testing.assert_allclose(fit.velocity, np.tile(V, (3, 1)), atol=2e-4)
    np.testing.assert_allclose(fit.yaw_rate, OMEGA, atol=2e-4)


def test_agrees_with_the_single_fit_on_noisy_evidence(evidence):
    rest, heading, point = evidence
    rng = np.random.default_rng(4)
    rests = rest + 0.1 * rng.standard_normal((2, 2))
    headings = heading + np.radians(2.0) * rng.standard_normal(2)
    batch = fit_runout_many(CAR, [[0.0, 0.0]] * 2, [PSI] * 2, rests, headings,
                            start=start(), path_points=[point])
    for k in range(2):
        single = fit_runout(CAR, [0.0, 0.0], PSI, rests[k], headings[k], path_points=[point])
        np.testing.assert_allclose(batch.velocity[k], single.velocity, atol=2e-3)
        assert batch.yaw_rate[k] == pytest.approx(single.yaw_rate, abs=2e-3)
        assert batch.cost[k] == pytest.approx(2 * single.cost, rel=0.05, abs=1e-3)


def test_per_sample_inputs_and_an_unreachable_rest_is_flagged(evidence):
    rest, heading, _ = evidence
    far = rest + np.array([80.0, 0.0])
    car = RunoutVehicle(mass=[1500.0, 1400.0], yaw_inertia=[2500.0, 2300.0], wheelbase=2.7,
                        track=1.5, cg_to_front_axle=1.2, friction=[0.8, 0.75],
                        braking=(1.0, 1.0, 0.3, 0.3))
    fit = fit_runout_many(car, [[0.0, 0.0]] * 2, [PSI] * 2, [rest, far], [heading] * 2,
                          start=start(), speed_bounds=(0.0, 10.0))
    assert fit.reachable.tolist() == [True, False]
    assert fit.speed[1] == pytest.approx(10.0)       # pushed against its bound


@pytest.mark.parametrize("field, value", [("rest_position", [[np.nan, 0.0]]),
                                          ("heading_sigma", 0.0)])
def test_bad_evidence_is_named(evidence, field, value):
    rest, heading, _ = evidence
    kwargs = {"rest_position": [rest], "heading_sigma": 0.03, field: value}
    with pytest.raises(ValueError, match=field.split("_")[0]):
        fit_runout_many(CAR, [[0.0, 0.0]], [PSI], kwargs.pop("rest_position"), [heading],
                        start=start(), **kwargs)
