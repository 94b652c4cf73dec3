"""pim/analysis/reconstruction_mc.py: the Monte Carlo of a reconstruction.

Coverage is checked against the truth the synthetic measurements were generated from: with
measured motion drawn with stated sigmas, the 5-95 % interval must contain the true speed in
about 90 % of independent data sets (binomial bounds over 200 seeds); an ill-conditioned
(near-collinear) scene must give a wide interval, not a false precision."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import pim
from pim.analysis.inverse_pim import inverse_pim
from pim.analysis.reconstruction_mc import reconstruction_samples, residual_standard_error
from tests.test_inverse_pim import UNKNOWN, synthetic

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


@pytest.mark.slow
def test_evidence_chain_interval_covers_the_truth_over_200_seeds():
    """The whole chain with noise, 200 times: rest positions, headings and the tyre-mark
    points of the synthetic case (generated by the forward models from 21.2 mph each) get
    independent noise with the evidence's stated sigmas; each noisy set is reconstructed
    (run-out inverse -> inverse PIM, nominal and a 200-sample Monte Carlo over the same
    sigmas, everything batched across seeds) and the 5-95 % interval of each speed must
    contain 21.2 mph in about 90 % of the seeds (binomial: 165-195 of 200).

    The nominal run-out fits start from the noise-free solution (the single fit's global
    search is tested elsewhere; a batch of 200 solve_ivp searches would take an hour)."""
    from scipy.special import ndtri

    from pim.analysis.free_fit import residual_terms
    from pim.analysis.free_inputs import case_state
    from pim.analysis.inverse_pim import inverse_pim_many
    from pim.analysis.residuals import measured_terms
    from pim.analysis.runout_fit_batch import fit_runout_many

    case = pim.load_case("synthetic-runout")
    truth = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    known = 31.09 * 0.3048
    seeds, n = 200, 200
    rng = np.random.default_rng(11)
    post = {}          # vehicle -> (velocity (seeds*n, 2), yaw (seeds*n,), nominal (seeds, 3))
    for i in (1, 2):
        v, ev = getattr(case, f"vehicle{i}"), getattr(case.evidence, f"vehicle{i}")
        vehicle = ev.runout_vehicle(float(v.mass), float(v.yaw_inertia))
        vel, w = getattr(truth, f"velocity{i}"), float(getattr(truth, f"yaw_rate{i}"))
        start = (np.hypot(*vel), np.arctan2(vel[1], vel[0]), w)
        sp, sh = ev.position_sigma, ev.heading_sigma
        rest = ev.rest_position + sp * rng.standard_normal((seeds, 2))
        heading = ev.rest_heading + sh * rng.standard_normal(seeds)
        points = ev.path_points[None] + sp * rng.standard_normal((seeds,) + ev.path_points.shape)
        nominal = fit_runout_many(vehicle, np.tile(v.cg, (seeds, 1)), np.full(seeds, float(
            v.heading)), rest, heading, start=start, path_points=points,
            position_sigma=sp, heading_sigma=sh)
        assert nominal.converged.all()
        # Monte Carlo of each seed: the evidence redrawn about the noisy one with its sigmas
        u = rng.random((3, seeds * n)) + 2.0**-54
        rs = np.repeat(rest, n, axis=0) + sp * ndtri(u[:2].T)
        hs = np.repeat(heading, n) + sh * ndtri(u[2])
        ps = np.repeat(points, n, axis=0) + sp * rng.standard_normal((seeds * n,)
                                                                      + ev.path_points.shape)
        starts = tuple(np.repeat(x, n) for x in (nominal.speed, nominal.direction,
                                                   nominal.yaw_rate))
        mc = fit_runout_many(vehicle, np.tile(v.cg, (seeds * n, 1)),
                             np.full(seeds * n, float(v.heading)), rs, hs, start=starts,
                             path_points=ps, position_sigma=sp, heading_sigma=sh)
        post[i] = (nominal, mc)
    # inverse PIM of every nominal and every sample at once
    names = measured_terms(case, True) if case.measured else ("velocity1_x", "velocity1_y",
                                                               "velocity2_x", "velocity2_y",
                                                               "yaw_rate1", "yaw_rate2")
    rows, _, factor = residual_terms(replace(case, measured=pim.Measured(
        velocity1=truth.velocity1, velocity2=truth.velocity2, yaw_rate1=float(truth.yaw_rate1),
        yaw_rate2=float(truth.yaw_rate2))), names)
    keys = ("impact.restitution", "vehicle1.speed", "vehicle2.speed")
    bounds = [case.unknown[k] for k in keys]
    base = case_state(case, 0.5, 1.0)

    def targets(which):
        n1, n2 = post[1][which], post[2][which]
        return np.column_stack([n1.velocity, n2.velocity, n1.yaw_rate, n2.yaw_rate])

    x0 = np.array([0.355, known, known]) * 0.9
    nominal = inverse_pim_many(np.tile(base, (seeds, 1)), keys, bounds, x0, rows,
                               targets(0), factor)
    samples = inverse_pim_many(np.tile(base, (seeds * n, 1)), keys, bounds,
                               np.repeat(nominal.x, n, axis=0), rows, targets(1), factor)
    ok = samples.converged & post[1][1].stopped & post[2][1].stopped
    speeds = np.where(ok[:, None], samples.x, np.nan).reshape(seeds, n, 3)[:, :, 1:]
    p5, p95 = np.nanpercentile(speeds, [5, 95], axis=1)
    hits = np.sum((p5 <= known) & (known <= p95), axis=0)
    print(f"coverage of the 5-95 % interval over {seeds} seeds: vehicle1 {hits[0]}, "
          f"vehicle2 {hits[1]}; median width {np.median(p95 - p5, axis=0) / 0.44704} mph")
    assert np.all((165 <= hits) & (hits <= 195)), hits


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
