"""The cross-check of two events (sim.event_check) and the generated side slaps."""

import numpy as np
import pytest

import pim
import sim
from pim.model.geometry import outline_penetration
from sim.event_check import AGREEMENT, SIDE_SLAPS, event_crosscheck, side_slap_case


@pytest.fixture(scope="module")
def events():
    case = side_slap_case(1.6)
    return (sim.simulate_event(case), sim.simulate_event(case, tyre_friction=0.5),
            sim.simulate_event(case, settings=sim.Settings(dt=5e-4)))


def test_an_event_against_itself_differs_by_nothing(events):
    check = event_crosscheck(events[0], events[0])
    assert check.same_impacts and check.impact_count[0] >= 2
    assert all(d.time == 0 and np.all(d.delta_v == 0) for d in check.impacts)
    assert np.all(check.rest_position == 0) and np.all(check.trajectory.position == 0)
    assert check.to_dict()["largest_position"] == 0


def test_the_json_speaks_the_users_units(events):
    check = event_crosscheck(events[0], events[1])
    si, us = check.to_dict("si"), check.to_dict("us")
    assert si["units"]["speed"] == "km/h" and us["units"]["length"] == "ft"
    assert us["rest_position"][0] == pytest.approx(si["rest_position"][0] / 0.3048)
    assert si["rest_speed"][0] == pytest.approx(3.6 * float(check.rest_speed[0]))
    assert si["rest_heading"][0] == pytest.approx(np.degrees(check.rest_heading[0]))


def test_less_tyre_friction_moves_the_rest_positions(events):
    check = event_crosscheck(events[0], events[1])
    assert np.all(check.rest_position > 0.1)
    assert check.impacts[0].delta_v_relative < 1e-9        # the first impact is the same


def test_a_finer_step_moves_little(events):
    check = event_crosscheck(events[0], events[2])
    assert check.same_impacts
    assert np.max(check.rest_position) < 0.1
    assert max(d.delta_v_relative for d in check.impacts) < 0.1


def test_side_slap_outlines_touch_at_c():
    case = side_slap_case(1.2)
    boxes = [(v.cg, v.heading, 4.5, 1.8, None) for v in (case.vehicle1, case.vehicle2)]
    assert float(outline_penetration(*boxes)) == pytest.approx(0.0, abs=1e-12)
    assert case.impact.point == pytest.approx([1.2, -0.9])


@pytest.mark.parametrize("slap", SIDE_SLAPS)
def test_analytic_and_simulated_side_slaps_agree(slap):
    # the generated suite: both events find the same impacts, at the same times,
    # with the same delta-V and PDOF, and rest at the same place (tolerances: AGREEMENT)
    case = side_slap_case(slap[0], eps=slap[1], beta=slap[2])
    check = event_crosscheck(pim.event(case), sim.simulate_event(case))
    assert check.same_impacts and check.impact_count[0] >= 2
    for d in check.impacts:
        assert abs(d.time) <= AGREEMENT["time"]
        assert d.delta_v_relative <= AGREEMENT["delta_v"]
        assert np.all(np.abs(d.pdof) <= AGREEMENT["pdof"])
    assert np.all(check.rest_position <= AGREEMENT["rest_position"])
    assert np.all(np.abs(check.rest_heading) <= AGREEMENT["rest_heading"])


def test_ricsac9_secondary_contact_in_free_motion_agrees():
    case = pim.load_case("ricsac9")
    check = event_crosscheck(pim.event(case, tyre_friction=0.0),
                             sim.simulate_event(case, tyre_friction=0.0))
    assert check.impact_count == (2, 2)
    assert abs(check.impacts[1].time) <= AGREEMENT["time"]
    assert check.impacts[1].delta_v_relative <= AGREEMENT["delta_v"]
