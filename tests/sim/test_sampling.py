"""Random scenes for the simulator's property tests (sim.sampling)."""

import numpy as np

import pim
from sim.sampling import random_scene, random_scenes


def test_scenes_are_admissible_and_reproducible():
    scenes = random_scenes(30, seed=3)
    again = random_scenes(30, seed=3)
    for (case, eps, beta), (case2, eps2, beta2) in zip(scenes, again, strict=True):
        assert bool(pim.solve(case, eps, beta).admissible)
        assert (eps, beta) == (eps2, beta2)
        np.testing.assert_array_equal(case.vehicle1.velocity, case2.vehicle1.velocity)
        assert 0 <= eps <= 1 and 0 <= beta <= 1


def test_ranges_and_barrier_share():
    rng = np.random.default_rng(0)
    draws = [random_scene(rng, barrier_fraction=0.5) for _ in range(400)]
    barriers = sum(bool(case.vehicle2.fixed) for case, _, _ in draws)
    # binomial(400, 0.5): standard deviation 10, so 4 sigma is +-40
    assert abs(barriers - 200) < 40
    for case, eps, beta in draws:
        assert 0 <= eps <= 1 and 0 <= beta <= 1
        assert 400 <= float(case.vehicle1.mass) <= 4000
        assert np.hypot(*case.vehicle1.velocity) <= 40 * np.sqrt(2) + 1e-9
