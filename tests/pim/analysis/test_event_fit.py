"""The fit through the event (pim.analysis.event_fit): rest evidence the event generated at
known post-impact motion is fitted back, many problems at once; what it refuses."""

import math
from dataclasses import replace

import numpy as np
import pytest

import pim
from comparisons.docs.event import side_slap_case, with_rest_evidence
from pim.analysis.event_fit import event_residuals, fit_through_event_many


def test_the_known_motion_has_zero_residuals_and_a_shifted_rest_does_not():
    case = with_rest_evidence(side_slap_case())
    res = pim.solve(case)
    truth = np.array([*res.velocity1, float(res.yaw_rate1), *res.velocity2,
                      float(res.yaw_rate2)])
    assert event_residuals(case, truth) == pytest.approx(np.zeros(6), abs=1e-6)
    moved = truth.copy()
    moved[1] += 0.2                       # 0.2 m/s more along +y for vehicle 1
    assert np.max(np.abs(event_residuals(case, moved))) > 1.0


def test_many_problems_fit_their_own_rest_draws():
    """Two draws of the rest evidence, each fitted from the true motion: each fit ends at
    its own draw (cost ~ 0), and the two motions differ."""
    case = with_rest_evidence(side_slap_case())
    res = pim.solve(case)
    truth = np.array([*res.velocity1, float(res.yaw_rate1), *res.velocity2,
                      float(res.yaw_rate2)])
    ev = pim.event(case)
    shift = np.array([[[0.03, -0.02], [0.0, 0.04]], [[-0.04, 0.0], [0.02, -0.03]]])
    rest = ev.rest_position[None] + shift
    heading = ev.rest_heading[None] + math.radians(0.5) * np.array([[1, -1], [-1, 1]])
    x, fit = fit_through_event_many(case, np.repeat(truth[None], 2, 0), (rest, heading))
    assert fit.cost == pytest.approx([0.0, 0.0], abs=1e-4)
    assert np.max(np.abs(x[0] - x[1])) > 1e-3


def test_one_vehicle_of_evidence_is_refused():
    case = with_rest_evidence(side_slap_case())
    one = replace(case, evidence=replace(case.evidence, vehicle2=None))
    with pytest.raises(pim.InputError, match="both vehicles' rest"):
        fit_through_event_many(one, np.zeros((1, 6)), (np.zeros((1, 2, 2)), np.zeros((1, 2))))
