"""pim/analysis/reconstruction_mc.py: the Monte Carlo of a reconstruction.

Coverage is checked against the truth the synthetic measurements were generated from: with
measured motion drawn with stated sigmas, the 5-95 % interval must contain the true speed in
about 90 % of independent data sets (binomial bounds over 200 seeds); an ill-conditioned
(near-collinear) scene must give a wide interval, not a false precision."""

from __future__ import annotations

import os
from dataclasses import replace

import numpy as np
import pytest

import pim
from pim.analysis.inverse_pim import inverse_pim
from pim.analysis.reconstruction_mc import reconstruction_samples, residual_standard_error
from tests.pim.analysis.test_inverse_pim import UNKNOWN, synthetic

SIGMA_V, SIGMA_W = 0.3, 0.05          # [m/s], [rad/s] stated measurement error


def noisy(case, rng):
    m = case.measured
    return replace(case, measured=pim.Measured(
        velocity1=m.velocity1 + SIGMA_V * rng.standard_normal(2),
        velocity2=m.velocity2 + SIGMA_V * rng.standard_normal(2),
        yaw_rate1=m.yaw_rate1 + SIGMA_W * rng.standard_normal(),
        yaw_rate2=m.yaw_rate2 + SIGMA_W * rng.standard_normal(),
        velocity1_sigma=(SIGMA_V, SIGMA_V), velocity2_sigma=(SIGMA_V, SIGMA_V),
        yaw_rate1_sigma=SIGMA_W, yaw_rate2_sigma=SIGMA_W))


def test_the_interval_covers_the_truth_at_its_stated_rate():
    """200 independent noisy data sets; P(truth in [p5, p95]) should be 0.9: 200 x 0.9 = 180,
    binomial sd 4.2; accept 165..195 (3.5 sd). Speeds only (eps, beta as given), so the
    problem is nearly linear and the nominal interval calibrated."""
    truth = synthetic()
    truth = replace(truth, impact=replace(truth.impact, restitution=0.28, beta=0.85),
                    uncertainty=None)
    unknown = {k: UNKNOWN[k] for k in ("vehicle1.speed", "vehicle2.speed")}
    rng = np.random.default_rng(2024)
    hits = np.zeros(2, dtype=int)
    for seed in range(200):
        case = noisy(truth, rng)
        f = inverse_pim(case, unknown)
        mc = reconstruction_samples(case, f, unknown, n=400, seed=seed)
        for j, (key, true) in enumerate(zip(("vehicle1.speed", "vehicle2.speed"), (8.3, 10.7),
                                            strict=True)):
            st = mc.stats[key]
            hits[j] += st.p5 <= true <= st.p95
    assert np.all((165 <= hits) & (hits <= 195)), hits


def test_measured_error_drives_the_spread_when_nothing_else_varies():
    case = noisy(synthetic(), np.random.default_rng(0))
    case = replace(case, uncertainty=None)
    f = inverse_pim(case, UNKNOWN)
    mc = reconstruction_samples(case, f, UNKNOWN, n=2000, seed=1)
    assert mc.measured_sigma_source == "stated"
    assert all(name.startswith("measured.") for name in mc.varying)
    top, index = mc.stats["vehicle2.speed"].drivers[0]
    assert top.startswith("measured.") and index > 0.2


def test_near_collinear_approach_gives_a_wide_interval():
    """Vehicle 2 meeting vehicle 1 almost head-on (2 deg off its line): with eps and beta
    unknown too, the speeds are ill-conditioned and the interval must say so, compared with
    the 90-degree scene under the same measurement error."""
    def width(heading2, cg2):
        base = synthetic()
        base = replace(base, vehicle2=replace(base.vehicle2, heading=heading2, cg=cg2),
                       uncertainty=None)
        truth = replace(base, vehicle1=replace(base.vehicle1, velocity=(-8.3, 0.0)),
                        vehicle2=replace(base.vehicle2, velocity=10.7 * np.array(
                            [np.cos(heading2), np.sin(heading2)])))
        r = pim.solve(truth, 0.28, 0.85)
        assert r.approaching
        case = replace(base, measured=pim.Measured(
            velocity1=r.velocity1, velocity2=r.velocity2, yaw_rate1=float(r.yaw_rate1),
            yaw_rate2=float(r.yaw_rate2), velocity1_sigma=(SIGMA_V, SIGMA_V),
            velocity2_sigma=(SIGMA_V, SIGMA_V), yaw_rate1_sigma=SIGMA_W,
            yaw_rate2_sigma=SIGMA_W))
        f = inverse_pim(case, UNKNOWN)
        mc = reconstruction_samples(case, f, UNKNOWN, n=2000, seed=0)
        st = mc.stats["vehicle1.speed"]
        return st.p95 - st.p5

    square = width(np.pi / 2, synthetic().vehicle2.cg)
    head_on = width(np.radians(2.0), (-2.6, -0.3))
    assert head_on > 4 * square


def test_residual_standard_error_is_the_textbook_one():
    case = synthetic()
    m = case.measured
    shifted = replace(case, measured=replace(m, velocity1=m.velocity1 + [0.5, -0.4]))
    f = inverse_pim(shifted, UNKNOWN)
    k, n = len(f.residual_names), len(f.values)
    assert residual_standard_error(f) == pytest.approx(np.sqrt(f.cost / (k - n)))


def test_too_few_samples_is_an_error():
    case = synthetic()
    f = inverse_pim(case, UNKNOWN)
    with pytest.raises(ValueError, match="samples"):
        reconstruction_samples(case, f, UNKNOWN, n=5)


def noisy_evidence_case(case, rng):
    """``case`` with its evidence redrawn once with the evidence's own stated sigmas."""
    evidence = {}
    for i in (1, 2):
        ev = getattr(case.evidence, f"vehicle{i}")
        sp, sh = ev.position_sigma, ev.heading_sigma
        evidence[f"vehicle{i}"] = replace(
            ev, rest_position=ev.rest_position + sp * rng.standard_normal(2),
            rest_heading=ev.rest_heading + sh * rng.standard_normal(),
            path_points=ev.path_points + sp * rng.standard_normal(ev.path_points.shape))
    return replace(case, evidence=replace(case.evidence, **evidence))


#: Seeds of the coverage test (PIM_COVERAGE_SEEDS): each is one full reconstruct() call.
COVERAGE_SEEDS = int(os.environ.get("PIM_COVERAGE_SEEDS", "40"))


@pytest.mark.slow
def test_evidence_chain_interval_covers_the_truth():
    """The whole chain as users call it, :func:`pim.analysis.reconstruction.reconstruct`
    (run-out inverse -> inverse PIM, nominal fit and a 200-sample Monte Carlo over the
    evidence's sigmas), on COVERAGE_SEEDS noisy copies of the synthetic case's evidence
    (generated by the forward models from 31.09 ft/s = 21.2 mph each, noise with the stated
    sigmas): the 5-95 % interval of each speed must contain the truth in 90 % of the seeds,
    within 4 binomial standard deviations, 4 sqrt(0.09 N)."""
    from pim.analysis.reconstruction import reconstruct

    case = pim.load_case("synthetic-runout")
    known = 31.09 * 0.3048
    rng = np.random.default_rng(11)
    hits = np.zeros(2, int)
    for seed in range(COVERAGE_SEEDS):
        rec = reconstruct(noisy_evidence_case(case, rng), samples=200, seed=seed)
        for j, key in enumerate(("vehicle1.speed", "vehicle2.speed")):
            st = rec.samples.stats[key]
            hits[j] += st.p5 <= known <= st.p95
    n = COVERAGE_SEEDS
    print(f"coverage of the 5-95 % interval over {n} seeds: {hits}")
    assert np.all(np.abs(hits - 0.9 * n) <= 4 * np.sqrt(0.09 * n) + 1), hits


def test_blocks_on_an_executor_pool_into_the_same_distribution():
    """The Monte Carlo spread over an executor (here threads, and a stand-in for a Dask
    client, which hands out its executor by get_executor) gives the same intervals as one
    block, to the sampling error of 4000 samples, and repeats exactly for a given seed."""
    from concurrent.futures import ThreadPoolExecutor

    from pim.analysis.reconstruction import reconstruct

    case = pim.load_case("ricsac9-reconstruct")
    one = reconstruct(case, samples=4000, seed=3)

    class Client:                                  # what pim needs of dask.distributed.Client
        def __init__(self, pool):
            self.pool = pool

        def get_executor(self):
            return self.pool

    with ThreadPoolExecutor(2) as pool:
        spread = reconstruct(case, samples=4000, seed=3, executor=pool, blocks=4)
        again = reconstruct(case, samples=4000, seed=3, executor=Client(pool), blocks=4)
    assert spread.samples.n == 4000
    for key in ("vehicle1.speed", "vehicle2.speed"):
        a, b = one.samples.stats[key], spread.samples.stats[key]
        width = a.p95 - a.p5
        assert abs(a.p50 - b.p50) < 0.05 * width and abs(a.p95 - b.p95) < 0.08 * width
        assert again.samples.stats[key] == b


def test_inadmissible_samples_are_left_out_and_counted():
    """Issue 28: a Monte Carlo says what share of its samples were inadmissible and how they
    were treated. admissible_samples re-solves each sample's state under the law: RICSAC 9
    at beta 0.8 is admissible, at beta 1.2 the slip reverses (pim.solve's own flags)."""
    from pim.analysis.free_inputs import case_state
    from pim.analysis.reconstruction_mc import SampleBlock, admissible_samples, summarise

    case = pim.load_case("ricsac9")
    state = np.stack([case_state(case, 0.355, b) for b in (0.8, 1.2, 0.8)])
    ok, counts = admissible_samples(case, state, "brach")
    assert ok.tolist() == [True, False, True]
    reverses = [(text, bad) for text, bad, _ in counts if "beta > 1" in text]
    assert reverses and reverses[0][1] == 1
    # summarise words it: the share, the treatment, the reasons with their counts
    fit = inverse_pim(synthetic(), UNKNOWN)
    keys = tuple(fit.values)
    x = np.tile([fit.values[k] for k in keys], (10, 1))
    block = SampleBlock(x, np.r_[[True] * 8, [False] * 2], {}, "stated", [],
                        inadmissible={"kinetic energy is gained": 2}, n_inadmissible=2)
    messages = summarise(fit, [block]).messages
    assert ("2 of 10 samples (20 %) are inadmissible impacts, left out of the percentiles and "
            "the drivers: kinetic energy is gained (2)") in messages
    assert not any("fit not converged" in m for m in messages)
