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


def hand_event(source, impacts, v1=(10.0, 0.0), shift=0.0):
    """Two vehicles in straight motion from t = -1 s to 2 s (vehicle 1 from (shift, 0) at
    ``v1``, vehicle 2 parked at (20, -10) heading 0.1 rad) with the given impact records."""
    from pim.model.event import Event, Track, phase_labels

    t = np.linspace(-1.0, 2.0, 31)
    n = len(t)
    one = Track(np.column_stack([shift + v1[0] * t, v1[1] * t]), np.full(n, 0.2),
                np.tile(v1, (n, 1)).astype(float), np.zeros(n))
    two = Track(np.tile([20.0, -10.0], (n, 1)), np.full(n, 0.1), np.zeros((n, 2)),
                np.zeros(n))
    return Event(t, one, two, phase_labels(t, [i.time for i in impacts]),
                 impacts=tuple(impacts), source=source)


def hand_record(time, point, gamma, before, after, pdof):
    from pim.model.event import ImpactRecord

    return ImpactRecord(time, np.asarray(point, float), gamma, "brach",
                        {"eps": 0.2, "beta": 1.0}, np.zeros(2), np.asarray(before, float),
                        np.asarray(after, float), np.zeros(2), np.zeros(2), 1.0,
                        np.asarray(pdof, float))


def test_each_impact_is_compared_in_time_order_by_hand():
    # worked by hand: impact 2 of a at 0.5 s, of b at 0.45 s; Cs 3-4-5 apart; Gamma 170 deg
    # against -170 deg (20 deg apart across the wrap); vehicle 1 at 10 m/s in a, 8 m/s in b
    # before; after 6 (a) and 3 (b): delta-V vectors (-4, 0) and (-5, 0), 1 m/s apart
    first = hand_record(0.0, (0, 0), 0.0, [[10, 0], [0, 0]], [[6, 0], [1, 0]], [np.pi, 0.0])
    a2 = hand_record(0.5, (1.0, 1.0), np.radians(170), [[10, 0], [0, 0]], [[6, 0], [3, 4]],
                 [np.pi, 0.3])
    b2 = hand_record(0.45, (4.0, 5.0), np.radians(-170), [[8, 0], [0, 0]], [[3, 0], [3, 4]],
                 [np.pi - 0.1, 0.3])
    b3 = hand_record(0.9, (2.0, 2.0), 0.0, [[3, 0], [3, 4]], [[2, 0], [3, 4]], [np.pi, 0.0])
    a = hand_event("analytic", (first, a2))
    b = hand_event("simulated", (first, b2, b3), v1=(8.0, 0.0), shift=0.5)
    check = event_crosscheck(a, b)
    assert check.impact_count == (2, 3) and not check.same_impacts
    d = check.impacts[1]
    assert d.index == 2 and d.time == pytest.approx(0.05)
    np.testing.assert_allclose(d.times, [0.5, 0.45])
    assert d.point == pytest.approx(5.0)
    assert np.degrees(d.normal_angle) == pytest.approx(-20.0)      # wrapped, not 340
    np.testing.assert_allclose(d.delta_v, [1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(d.pdof, [0.1, 0.0], atol=1e-12)
    np.testing.assert_allclose(d.speed_before, [2.0, 0.0])
    np.testing.assert_allclose(d.speed_after, [3.0, 0.0])
    # vehicle 1's CG at its impact: x = 10 x 0.5 = 5 m in a, 0.5 + 8 x 0.45 = 4.1 m in b
    np.testing.assert_allclose(d.position, [0.9, 0.0], atol=1e-12)
    np.testing.assert_allclose(d.heading, [0.0, 0.0])
    assert [(u.event, u.index, u.time) for u in check.unmatched] == [("simulated", 3, 0.9)]
    text = check.count_text()
    assert "2 in the analytic event, 3 in the simulated event" in text
    assert "impact 3 of the simulated event (t = 0.9 s) has no partner" in text


def test_the_per_impact_json_speaks_the_users_units():
    first = hand_record(0.0, (0, 0), 0.0, [[10, 0], [0, 0]], [[6, 0], [1, 0]], [np.pi, np.nan])
    moved = hand_record(0.0, (0.3048, 0), 0.0, [[10, 0], [0, 0]], [[5, 0], [1, 0]],
                    [np.pi, np.nan])
    check = event_crosscheck(hand_event("analytic", (first,)),
                             hand_event("simulated", (moved,), shift=0.3048))
    us, si = check.to_dict("us"), check.to_dict("si")
    assert (us["units"]["length"], us["units"]["speed"]) == ("ft", "mph")
    imp = us["impacts"][0]
    assert imp["C"] == pytest.approx(1.0) and si["impacts"][0]["C"] == pytest.approx(0.3048)
    assert imp["position"][0] == pytest.approx(1.0)                      # 1 ft apart
    assert imp["delta_v"][0] == pytest.approx(1.0 / 0.44704)             # 1 m/s in mph
    assert si["impacts"][0]["delta_v"][0] == pytest.approx(3.6)          # in km/h
    assert imp["pdof"][1] is None                                        # a NaN PDOF
    assert us["unmatched"] == [] and us["same_impacts"]
    assert us["largest_speed"][0] == pytest.approx(0.0)
