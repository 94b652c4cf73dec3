"""Progress inside a long stage (pim.analysis.progress): the callback of the enclosing block
hears each report; the Monte Carlo's fits through the event report after each chunk, and
their results do not depend on the chunk (the reports' granularity)."""

import math

import numpy as np

from comparisons.docs.event import side_slap_case, with_rest_evidence
from pim.analysis.event_samples import fit_event_samples
from pim.analysis.progress import report, reporting
from pim.analysis.reconstruction import post_impact_motion


def test_reports_reach_the_enclosing_blocks_callback_only():
    heard, inner = [], []
    report(1, 2, "nobody listens")                       # no block: nothing, no error
    with reporting(lambda *a: heard.append(a)):
        report(1, 3, "x")
        with reporting(lambda *a: inner.append(a)):
            report(2, 3, "y")
        report(np.int64(3), 3.0, "z")
    report(4, 4, "after")
    assert heard == [(1, 3, "x"), (3, 3, "z")] and inner == [(2, 3, "y")]
    assert all(type(d) is int and type(t) is int for d, t, _ in heard)


def test_the_fits_through_the_event_report_each_chunk_and_do_not_depend_on_it():
    """13 draws of the side slap's rest evidence in chunks of 5: reports at 5, 10 and 13 of
    13; the motions equal those of one chunk, bit for bit (each sample's steps are its own:
    the chunk only sets how often progress is said)."""
    case = with_rest_evidence(side_slap_case())
    post = post_impact_motion(case)
    fit = post.event_fit
    x0 = np.array([*fit.velocity[0], fit.yaw_rate[0], *fit.velocity[1], fit.yaw_rate[1]])
    rng = np.random.default_rng(11)
    ev = [case.evidence.vehicle1, case.evidence.vehicle2]
    rest = np.stack([e.rest_position for e in ev])[None] + 0.05 * rng.normal(size=(13, 2, 2))
    heading = np.array([e.rest_heading for e in ev])[None] + math.radians(1.0) * rng.normal(
        size=(13, 2))
    heard = []
    with reporting(lambda *a: heard.append(a)):
        chunked = fit_event_samples(post.case, x0, (rest, heading), chunk=5)
    assert heard == [(k, 13, "samples fitted through the event") for k in (5, 10, 13)]
    whole = fit_event_samples(post.case, x0, (rest, heading), chunk=13)
    assert np.array_equal(chunked.x, whole.x)
    assert np.array_equal(chunked.converged, whole.converged)
    assert chunked.counts == whole.counts and chunked.counts["converged"] >= 11
