"""pim/model/motion.py: typed post-impact terms read from any post-impact motion."""

from __future__ import annotations

import numpy as np
import pytest

import pim
from pim.model.motion import TERMS, PostImpactMotion, Term, as_terms


def test_term_names_and_values():
    result = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    assert Term(1, "vx").name == "velocity1_x" and Term(2, "omega").name == "yaw_rate2"
    assert float(Term(2, "vy").of(result)) == float(result.velocity2[1])
    assert float(Term(1, "omega").of(result)) == float(result.yaw_rate1)
    assert as_terms(["velocity2_y", Term(1, "omega")]) == (Term(2, "vy"), Term(1, "omega"))
    assert [t.name for t in TERMS] == ["velocity1_x", "velocity1_y", "yaw_rate1",
                                       "velocity2_x", "velocity2_y", "yaw_rate2"]


def test_sigma_and_absent_values():
    m = pim.Measured(velocity1=[1.0, 2.0], velocity1_sigma=[0.1, 0.2])
    assert Term(1, "vy").sigma_of(m) == 0.2 and Term(1, "omega").sigma_of(m) is None
    assert np.isnan(Term(2, "vx").of(m))


def test_every_producer_is_a_post_impact_motion():
    case = pim.load_case("ricsac9")
    assert isinstance(case.measured, PostImpactMotion)
    assert isinstance(pim.solve(case, 0.3, 1.0), PostImpactMotion)


@pytest.mark.parametrize("args", [(3, "vx"), (1, "speed")])
def test_bad_terms(args):
    with pytest.raises(ValueError, match="Term"):
        Term(*args)
    with pytest.raises(ValueError, match="unknown post-impact term"):
        as_terms(["velocity3_x"])


def test_impact_error_is_the_largest_change_error_over_the_largest_change():
    """The one error measure (moved from sim.error_measure, which now calls it): written
    out here from the result's fields."""
    from pim.model.motion import MotionValues, impact_error

    case = pim.load_case("ricsac9")
    r = pim.solve(case, 0.355, 1.0)
    k1 = np.sqrt(float(case.vehicle1.yaw_inertia) / float(case.vehicle1.mass))
    k2 = np.sqrt(float(case.vehicle2.yaw_inertia) / float(case.vehicle2.mass))
    changes = np.abs(np.concatenate([
        r.velocity1 - case.vehicle1.velocity, r.velocity2 - case.vehicle2.velocity,
        [k1 * (float(r.yaw_rate1) - float(case.vehicle1.yaw_rate)),
         k2 * (float(r.yaw_rate2) - float(case.vehicle2.yaw_rate))]]))
    v1 = np.array([r.velocity1 + [0.1, 0.0], r.velocity1, [np.nan, 0.0]])
    w2 = np.array([float(r.yaw_rate2), float(r.yaw_rate2) + 0.2, 0.0])
    got = impact_error(case, r, MotionValues(v1, np.broadcast_to(r.velocity2, (3, 2)),
                                             np.full(3, float(r.yaw_rate1)), w2))
    np.testing.assert_allclose(got[:2], [0.1 / changes.max(), k2 * 0.2 / changes.max()],
                               rtol=1e-12)
    assert np.isnan(got[2])
    assert impact_error(case, r, r) == 0.0


def test_sim_error_measure_calls_the_one_formula():
    from pim.model.motion import MotionValues, impact_error
    from sim.error_measure import impact_error as sim_error

    case = pim.load_case("ricsac9")
    r = pim.solve(case, 0.355, 1.0)
    v1 = np.asarray(r.velocity1) + [0.3, -0.2]
    assert sim_error(case, r, v1, r.velocity2, r.yaw_rate1, r.yaw_rate2) == impact_error(
        case, r, MotionValues(v1, r.velocity2, r.yaw_rate1, r.yaw_rate2))
