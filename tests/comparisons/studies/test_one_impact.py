"""The ladder's "one impact" rung (comparisons.studies.one_impact): the whole event against
PIM's single impact, in the ladder's physical units."""

import math

import numpy as np
import pytest

import pim
from comparisons.studies.one_impact import one_impact_rung


def test_ricsac9_without_tyres_has_a_second_impact_that_moves_the_rest():
    rung = one_impact_rung(pim.load_case("ricsac9"), tyre_friction=0.0)
    assert rung.impacts == 2 and not rung.holds
    assert rung.further_time == pytest.approx(0.42, abs=0.03)
    # free motion for 3 s: the second impact turns both paths by metres
    assert (rung.rest_position > 1.0).all()
    assert (rung.post_delta_v > 0.5).all() and np.isfinite(rung.post_yaw_rate).all()


def test_a_case_with_one_impact_holds_with_zeros():
    rung = one_impact_rung(pim.load_case("ricsac9"))          # default tyres: no re-contact
    assert rung.holds and math.isnan(rung.further_time)
    assert rung.rest_position == pytest.approx([0.0, 0.0], abs=1e-9)
    assert rung.post_delta_v == pytest.approx([0.0, 0.0])


def test_an_event_refused_leaves_the_rung_not_assessed_and_the_ladder_running():
    """The sideswipe of tests/data/sideswipe-ladder.toml stays in contact (more than 12
    further impacts): pim.event refuses it, and the ladder that called the rung crashed."""
    from pathlib import Path

    case = pim.load_case(Path(__file__).resolve().parents[2] / "data" / "sideswipe-ladder.toml")
    rung = one_impact_rung(case)
    assert "impacts after the first" in rung.refused and not rung.holds
    assert np.isnan(rung.rest_position).all()
