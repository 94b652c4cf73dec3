"""pim/model/distributions.py: sampling by inverse CDF, truncated to admissible ranges."""

import numpy as np
import pytest
from scipy.special import ndtr

from pim.model.distributions import Distribution


def test_restitution_normal_is_truncated_to_unit_interval():
    dist = Distribution("normal", 0.9, 0.3)
    u = (np.arange(100_000) + 0.5) / 100_000
    x = dist.sample(0.5, u, "impact.restitution")
    assert x.min() >= 0 and x.max() <= 1
    # truncated normal CDF at 0.8: (Phi((0.8-0.9)/0.3) - Phi(-3)) / (Phi(1/3) - Phi(-3))
    expected = (ndtr(-1 / 3) - ndtr(-3)) / (ndtr(1 / 3) - ndtr(-3))
    assert np.mean(x <= 0.8) == pytest.approx(expected, abs=1e-4)


@pytest.mark.parametrize("dist, nominal, mean, sd", [
    (Distribution("normal", None, 2.0), 10.0, 10.0, 2.0),
    (Distribution("uniform", 1.0, 3.0), 0.0, 2.0, 2.0 / np.sqrt(12)),
    (Distribution("plusminus", None, 1.5), 5.0, 5.0, 3.0 / np.sqrt(12)),
])
def test_moments_of_each_kind(dist, nominal, mean, sd):
    u = (np.arange(200_000) + 0.5) / 200_000
    x = dist.sample(nominal, u, "vehicle1.velocity_x")
    assert x.mean() == pytest.approx(mean, abs=1e-3 * max(sd, 1))
    assert x.std() == pytest.approx(sd, rel=1e-3)
    assert dist.sd(nominal) == pytest.approx(x.std(), rel=1e-3)     # issue 33: the sd it states


def test_sd_of_a_fixed_value_and_of_a_prior():
    assert Distribution("fixed", 3.0).sd(3.0) == 0.0
    prior = Distribution("prior", values=(0.1, 0.2, 0.4), label="p")
    assert prior.sd(0.2) == pytest.approx(np.std([0.1, 0.2, 0.4], ddof=1), rel=1e-15)
