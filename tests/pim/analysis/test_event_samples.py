"""The Monte Carlo through the event (pim.analysis.event_samples): a reconstruction from rest
positions reached through a side slap, its samples fitted through the event; the fast route
against the full fit; Broyden's method on a system solved by hand; unconverged samples
counted and left out."""

import math

import numpy as np
import pytest

import pim
from comparisons.docs.event import side_slap_case, with_rest_evidence
from pim.analysis.event import event_rest_many
from pim.analysis.event_fit import fit_through_event_many
from pim.analysis.event_samples import (
    TOLERANCE,
    broyden_roots,
    fit_event_samples,
    nominal_jacobian,
    sampled_inputs,
)
from pim.analysis.reconstruction import post_impact_motion, reconstruct
from pim.analysis.inverse_pim import inverse_pim
from pim.analysis.reconstruction_mc import solve_samples, summarise

#: The side slap's impact speeds (comparisons.docs.event.side_slap_case) [m/s].
TRUE_SPEEDS = (50 / 3.6, 10 / 3.6)
UNKNOWN = {"vehicle1.speed": (0.0, 40.0), "vehicle2.speed": (0.0, 40.0)}


@pytest.fixture(scope="module")
def slap():
    """The side slap with rest evidence its own event generated, and its step 1 (the
    single-impact run-outs re-contact: the nominal motion is fitted through the event)."""
    case = with_rest_evidence(side_slap_case())
    post = post_impact_motion(case)
    assert post.event_fit is not None
    fit = post.event_fit
    x0 = np.array([*fit.velocity[0], fit.yaw_rate[0], *fit.velocity[1], fit.yaw_rate[1]])
    return case, post, x0


def test_the_monte_carlo_goes_through_the_event_and_contains_the_true_speeds(slap):
    """Rest positions reached through a side slap (its impact speeds 50 and 10 km/h): every
    Monte Carlo sample is fitted through the event (the counts say so, and the samples'
    post-impact motions scatter about the fit through the event's, not the single-impact
    run-outs'), and each speed's 5-95 % interval holds the true speed."""
    case, post, _ = slap
    rec = reconstruct(case, unknown=UNKNOWN, samples=60, seed=3)
    counts = rec.samples.through_event
    assert counts is not None and counts["samples"] == 60
    assert counts["converged"] + counts["unconverged"] == 60
    assert counts["converged"] >= 50 and rec.samples.n_used <= counts["converged"]
    assert any("Monte Carlo through the event" in m and f"{counts['converged']} of 60" in m
               for m in rec.messages)
    assert rec.to_dict()["monte_carlo"]["through_event"] == counts
    for key, truth in zip(UNKNOWN, TRUE_SPEEDS, strict=True):
        st = rec.samples.stats[key]
        assert st.p5 < truth < st.p95, (key, st.p5 * 3.6, truth * 3.6, st.p95 * 3.6)
        assert st.p95 - st.p5 < 1.5 / 3.6                 # an interval, not the bounds


def test_the_fast_route_equals_the_full_fit(slap):
    """Six draws of the rest evidence within half a standard deviation: the fast route
    (Broyden steps from the nominal fit) and the full fit (Levenberg-Marquardt on forward
    differences) end at the same post-impact motion: speeds within 0.005 km/h."""
    case, post, x0 = slap
    rng = np.random.default_rng(7)
    ev = [case.evidence.vehicle1, case.evidence.vehicle2]
    rest = np.stack([e.rest_position for e in ev])[None] + 0.5 * 0.05 * rng.uniform(
        -1, 1, (6, 2, 2))
    heading = np.array([e.rest_heading for e in ev])[None] + 0.5 * math.radians(1.0) * \
        rng.uniform(-1, 1, (6, 2))
    fast = fit_event_samples(post.case, x0, (rest, heading), refit=False)
    x, full = fit_through_event_many(post.case, np.repeat(x0[None], 6, 0), (rest, heading))
    assert fast.converged.all() and full.converged.all()
    assert not fast.refitted.any()

    def speeds(motion):
        return 3.6 * np.hypot(motion[:, [0, 3]], motion[:, [1, 4]])

    assert np.max(np.abs(speeds(fast.x) - speeds(x))) < 0.005
    assert fast.counts == {"samples": 6, "converged": 6, "fast": 6, "refitted": 0,
                           "unconverged": 0}


def test_an_unreachable_draw_is_counted_unconverged(slap):
    """A draw whose residuals are not finite (no event can end there) is refitted, fails
    again, and is counted as unconverged; the others converge."""
    case, post, x0 = slap
    ev = [case.evidence.vehicle1, case.evidence.vehicle2]
    rest = np.repeat(np.stack([e.rest_position for e in ev])[None], 3, 0)
    rest[1, 0, 0] = np.nan
    heading = np.repeat(np.array([e.rest_heading for e in ev])[None], 3, 0)
    out = fit_event_samples(post.case, x0, (rest, heading))
    assert out.converged.tolist() == [True, False, True]
    assert out.refitted.tolist() == [False, True, False]
    assert out.counts["unconverged"] == 1 and out.counts["converged"] == 2


def test_unconverged_samples_are_left_out_and_said(slap):
    """The reconstruction's Monte Carlo uses none of the samples whose fit through the event
    did not converge, counts them and says so."""
    _, post, _ = slap
    fit = inverse_pim(post.case, UNKNOWN)
    left = np.arange(20) % 4 == 0

    def sampler(values, uniforms, rng, n):
        motion = post.case.measured
        row = [*motion.velocity1, motion.yaw_rate1, *motion.velocity2, motion.yaw_rate2]
        targets = np.repeat(np.array(row, float)[None], n, 0) + 1e-3 * rng.standard_normal(
            (n, 6))
        counts = {"samples": n, "converged": int(n - left.sum()), "fast": int(n - left.sum()),
                  "refitted": 0, "unconverged": int(left.sum())}
        return targets, ~left, {"evidence.vehicle1.rest_heading": rng.random(n)}, counts

    block = solve_samples(post.case, fit, UNKNOWN, 20, np.random.default_rng(0),
                          post_impact=sampler)
    assert not block.ok[left].any() and block.ok[~left].any()
    mc = summarise(fit, [block, block])
    assert mc.through_event["unconverged"] == 10 and mc.through_event["samples"] == 40
    assert mc.n_used <= 30
    assert any("10 did not and are left out of the percentiles" in m for m in mc.messages)


def test_broyden_solves_many_systems_at_once():
    """r_i(x) = A x + 0.2 x^3 - b_i (3 unknowns, a cubic term the starting Jacobian A does not
    know): Broyden's steps reach every root within the tolerance; a system without a root
    (x^2 + 1 = 0) is not converged."""
    a = np.array([[3.0, 1.0, 0.0], [0.5, 2.0, 0.3], [0.0, -0.4, 1.5]])
    b = np.random.default_rng(0).uniform(-1, 1, (50, 3))

    def residuals(points, index):
        x = points[:, 0, :]
        return (x @ a.T + 0.2 * x**3 - b[index])[:, None, :]

    x0 = np.zeros((50, 3))
    x, r, _, converged, steps = broyden_roots(residuals, x0, -b, a, np.full(3, 10.0))
    assert converged.all() and np.max(np.abs(residuals(x[:, None], np.arange(50)))) <= TOLERANCE
    assert steps.max() <= 10

    def no_root(points, index):
        return points**2 + 1.0

    _, _, _, converged, _ = broyden_roots(no_root, np.ones((1, 1)), np.array([[2.0]]),
                                          np.array([[2.0]]), np.array([10.0]))
    assert not converged.any()


def test_sampled_inputs_move_the_event(slap):
    """The per-sample vehicles and poses at the case's values give the case's rest states;
    a heavier vehicle 2 moves them. Without any sampled value there are no inputs."""
    case, post, x0 = slap
    solved = post.case
    assert sampled_inputs(solved, {"vehicle1.mass": 1500.0}, 2) is None
    inputs = sampled_inputs(solved, {"vehicle2.mass": np.array([1400.0, 1700.0])}, 2)
    velocity = np.repeat(np.stack([x0[0:2], x0[3:5]])[None], 2, 0)
    yaw = np.repeat(x0[[2, 5]][None], 2, 0)
    nominal = event_rest_many(solved, velocity[:1], yaw[:1])
    sampled = event_rest_many(solved, velocity, yaw, **inputs.event_options(solved))
    assert sampled.rest_position[0] == pytest.approx(nominal.rest_position[0], abs=1e-9)
    assert np.max(np.abs(sampled.rest_position[1] - nominal.rest_position[0])) > 0.05


def test_the_nominal_jacobian_is_the_local_slope(slap):
    """Central differences at the nominal motion predict a small step's change of the
    residuals to first order."""
    _, post, x0 = slap
    jac = nominal_jacobian(post.case, x0)
    from pim.analysis.event_fit import event_residuals

    step = 0.002 * np.array([1.0, -1.0, 0.2, 1.0, 1.0, -0.2])
    change = event_residuals(post.case, x0 + step) - event_residuals(post.case, x0)
    assert change == pytest.approx(jac @ step, abs=0.1 * np.max(np.abs(change)))
