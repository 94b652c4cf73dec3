"""pim/analysis/inverse_pim.py: the pre-impact unknowns from the post-impact motion.

The expected values are the inputs the synthetic measurements were generated with by the
forward model (pim.solve at known speeds, eps, beta): the inverse must give them back, and
the batched solver must agree with the single one."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import pim
from pim.analysis.free_fit import residual_terms
from pim.analysis.free_inputs import case_state
from pim.analysis.inverse_pim import inverse_pim, inverse_pim_many, under_determined
from pim.analysis.residuals import measured_terms

SPEEDS = (8.3, 10.7)        # [m/s] the truth
EPS, BETA = 0.28, 0.85
UNKNOWN = {"vehicle1.speed": (0.0, 35.0), "vehicle2.speed": (0.0, 35.0),
           "impact.restitution": (0.0, 1.0), "impact.beta": (0.0, 1.0)}


def synthetic(speeds=SPEEDS, eps=EPS, beta=BETA):
    base = pim.load_case("ricsac9-reconstruct")
    truth = replace(base, vehicle1=replace(base.vehicle1, velocity=(-speeds[0], 0.0)),
                    vehicle2=replace(base.vehicle2, velocity=(0.0, speeds[1])))
    r = pim.solve(truth, eps, beta)
    measured = pim.Measured(velocity1=r.velocity1, velocity2=r.velocity2,
                            yaw_rate1=float(r.yaw_rate1), yaw_rate2=float(r.yaw_rate2))
    return replace(base, measured=measured)


def test_noise_free_motion_gives_back_the_speeds_eps_and_beta():
    f = inverse_pim(synthetic(), UNKNOWN)
    assert f.values["vehicle1.speed"] == pytest.approx(SPEEDS[0], abs=1e-6)
    assert f.values["vehicle2.speed"] == pytest.approx(SPEEDS[1], abs=1e-6)
    assert f.eps == pytest.approx(EPS, abs=1e-6) and f.beta == pytest.approx(BETA, abs=1e-6)
    assert f.identifiability.identifiable and f.cost < 1e-18


def test_what_the_table_does_not_name_stays_as_given():
    case = synthetic()
    case = replace(case, impact=replace(case.impact, restitution=EPS, beta=BETA))
    f = inverse_pim(case, {k: UNKNOWN[k] for k in ("vehicle1.speed", "vehicle2.speed")})
    assert set(f.values) == {"vehicle1.speed", "vehicle2.speed"}
    assert (f.eps, f.beta) == (EPS, BETA)
    assert f.values["vehicle2.speed"] == pytest.approx(SPEEDS[1], abs=1e-6)


def test_under_determined_names_what_is_missing():
    case = synthetic()
    one = replace(case, measured=pim.Measured(velocity1=case.measured.velocity1,
                                              yaw_rate1=case.measured.yaw_rate1))
    why = under_determined(one, UNKNOWN)
    assert "4 unknowns" in why and "3 measured" in why
    assert "vehicle2's post-impact velocity" in why and "vehicle2's post-impact yaw rate" in why
    with pytest.raises(ValueError, match="under-determined"):
        inverse_pim(one, UNKNOWN)
    assert under_determined(case, UNKNOWN) == ""


@pytest.mark.parametrize("unknown, words", [
    ({"vehicle1.speed": (-1.0, 30.0)}, ">= 0"),
    ({"vehicle1.speed": (0.0, float("nan"))}, "finite"),
    ({}, "nothing to solve"),
    ({"impact.restitution": (0.0, 1.5)}, r"\[0, 1\]"),
])
def test_bad_unknowns_are_named(unknown, words):
    with pytest.raises(ValueError, match=words):
        inverse_pim(synthetic(), unknown)


def test_restitution_must_be_given_or_unknown():
    case = synthetic()
    case = replace(case, impact=replace(case.impact, restitution=None))
    with pytest.raises(ValueError, match="impact.restitution"):
        inverse_pim(case, {"vehicle1.speed": (0.0, 30.0), "vehicle2.speed": (0.0, 30.0)})


def test_batched_solver_agrees_with_the_single_one():
    rng = np.random.default_rng(3)
    cases = [synthetic(speeds=(rng.uniform(5, 15), rng.uniform(5, 15)),
                       eps=rng.uniform(0.1, 0.6), beta=rng.uniform(0.5, 1.0)) for _ in range(8)]
    singles = [inverse_pim(c, UNKNOWN) for c in cases]
    keys = tuple(singles[0].values)
    names = measured_terms(cases[0], True)
    rows, _, factor = residual_terms(cases[0], names)
    targets = np.array([residual_terms(c, names)[1] for c in cases])
    base = np.stack([case_state(c, 0.5, 0.5) for c in cases])
    x0 = np.array([singles[0].values[k] for k in keys])       # one start for all
    out = inverse_pim_many(base, keys, [UNKNOWN[k] for k in keys], x0, rows, targets, factor)
    assert out.converged.all()
    for k, single in enumerate(singles):
        np.testing.assert_allclose(out.x[k], [single.values[key] for key in keys], atol=1e-6)
