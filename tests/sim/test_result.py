"""What sim.simulate returns (sim.result)."""

import numpy as np

import pim
import sim
from sim.result import SimResult


def test_simulate_returns_a_sim_result_close_to_pim():
    case = pim.load_case("ricsac9")
    r = sim.simulate(case, 0.355, 1.0)
    assert isinstance(r, SimResult)
    assert r.velocity1.shape == (2,) and r.contact_duration > 0
    ref = pim.solve(case, 0.355, 1.0)
    np.testing.assert_allclose(r.velocity1, ref.velocity1, atol=1e-3)
