"""Named coefficient priors (pim.io.priors) and the 'prior' distribution kind."""

import numpy as np
import pytest

from pim.io.datasets import load_barrier
from pim.io.priors import PRIORS, prior_distribution, prior_values
from pim.io.uncertainty_table import parse_uncertainty
from pim.model.distributions import Distribution


def test_prior_values_are_the_papers_class_values():
    e = prior_values("iihs-small-overlap-barrier", "impact.restitution")
    assert len(e) == 16 and max(e) == 0.279 and min(e) == 0.0        # CF10005, App. 2
    mu = prior_values("iihs-small-overlap-sideswipe", "impact.beta")
    assert len(mu) == 24 and min(mu) == pytest.approx(0.718)         # CF10028
    assert "CF11006" not in [t.test_id for t in load_barrier() if t.restitution in mu]
    c2c = prior_values("iihs-small-overlap-car-to-car", "impact.restitution")
    assert len(c2c) == 9 and max(c2c) == 0.177


def test_prior_samples_follow_the_empirical_distribution():
    values = prior_values("iihs-small-overlap-sideswipe", "impact.beta")
    dist = prior_distribution("iihs-small-overlap-sideswipe", "impact.beta")
    rng = np.random.default_rng(1)
    x = dist.sample(0.9, rng.random(200_000), "impact.beta")
    assert x.min() >= min(values) and x.max() <= max(values)
    # inverse CDF through the Hazen positions: the sample median is the data's median
    assert np.median(x) == pytest.approx(np.median(values), abs=2e-3)
    assert x.mean() == pytest.approx(np.mean(values), abs=2e-3)
    # common random numbers: the same u gives the same values, monotone in u
    u = np.linspace(0.01, 0.99, 50)
    assert np.all(np.diff(dist.sample(0.9, u, "impact.beta")) >= 0)


def test_prior_in_uncertainty_table():
    table = parse_uncertainty({"impact": {"restitution": {"prior": "iihs-small-overlap-barrier"},
                                          "beta": {"prior": "iihs-small-overlap-car-to-car"}}})
    d = table.inputs["impact.restitution"]
    assert d.kind == "prior" and d.label == "iihs-small-overlap-barrier" and d.varies


@pytest.mark.parametrize("spec, match", [
    ({"impact": {"restitution": {"prior": "nope"}}},
     r"uncertainty.impact.restitution.prior = 'nope' is not a known prior \(known: "
     "iihs-small-overlap-barrier, iihs-small-overlap-sideswipe, iihs-small-overlap-car-to-car"),
    ({"impact": {"beta": {"prior": "iihs-barrier"}}},
     r"uncertainty.impact.beta.prior = 'iihs-barrier' is not a known prior; did you mean "
     "'iihs-small-overlap-barrier'"),
    ({"vehicle1": {"mass": {"prior": "iihs-small-overlap-barrier"}}}, "a prior exists only for"),
    ({"impact": {"beta": {"prior": "iihs-small-overlap-barrier", "mean": 1}}},
     "unknown key|no other"),
    ({"impact": {"beta": {"prior": 3}}}, "must be a prior's name"),
])
def test_bad_prior_rejected(spec, match):
    with pytest.raises(ValueError, match=match):
        parse_uncertainty(spec)


def test_prior_needs_values():
    with pytest.raises(ValueError, match="at least 2"):
        Distribution("prior", values=(0.1,))
    assert set(PRIORS) == {"iihs-small-overlap-barrier", "iihs-small-overlap-sideswipe",
                           "iihs-small-overlap-car-to-car"}
