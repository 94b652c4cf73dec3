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
