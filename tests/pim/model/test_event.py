"""The event's timeline type: shapes checked, resampling, differences, joins, JSON rows.

Expected values are worked by hand from straight-line motion (x = x0 + v t)."""

import numpy as np
import pytest

import pim
from pim.model.event import Event, ImpactRecord, Track, phase_labels
from pim.model.numbers import InputError


def straight(time, x0, v, heading=0.0, yaw=0.0):
    time = np.asarray(time, float)
    pos = np.asarray(x0, float) + time[:, None] * np.asarray(v, float)
    return Track(pos, heading + yaw * time, np.broadcast_to(v, (len(time), 2)).astype(float),
                 np.full(len(time), yaw), outline=np.array([[2, 1], [-2, 1], [-2, -1], [2, -1.]]))


def impact_at(t):
    v = np.zeros((2, 2))
    return ImpactRecord(t, np.zeros(2), 0.0, "brach", {"eps": 0.2, "beta": 1.0},
                        np.zeros(2), v, v + [[1, 0], [0, 1]], np.zeros(2), np.zeros(2), 10.0,
                        np.zeros(2))


def make(time, v1=(10.0, 0.0), v2=(0.0, 5.0)):
    time = np.asarray(time, float)
    return Event(time, straight(time, (0, 0), v1), straight(time, (20, -10), v2),
                 phase_labels(time, [0.0]), impacts=(impact_at(0.0),), source="test")


def test_track_checks_shapes_and_names_the_field():
    with pytest.raises(InputError, match="Track.velocity"):
        Track(np.zeros((3, 2)), np.zeros(3), np.zeros((2, 2)), np.zeros(3))
    with pytest.raises(InputError, match=r"Track.sliding must have shape \(3, 4\)"):
        Track(np.zeros((3, 2)), np.zeros(3), np.zeros((3, 2)), np.zeros(3),
              sliding=np.zeros((3, 2), bool))
    with pytest.raises(InputError, match="Track.position"):
        Track(np.zeros(2), 0.0, np.zeros(2), 0.0)           # one state, not a sample axis
    track = Track([[0.0, 0.0]] * 3, [0.0] * 3, [[1.0, 0.0]] * 3, [0.0] * 3)   # lists
    assert len(track) == 3 and track.sliding is None
    with pytest.raises(InputError, match="Event.time"):
        make([0.0, 1.0, 0.5])
    with pytest.raises(InputError, match="Event.time"):
        make([0.0, np.nan, 0.5, 0.4])


def test_phases_mark_approach_each_impact_and_rest():
    time = np.array([-1.0, -0.5, 0.0, 0.0, 0.5, 1.0, 2.0])
    labels = phase_labels(time, [0.0, 0.5], rest_time=2.0)
    # the impact's before-state (first t = 0) is free motion up to it; the after-state is
    # the impact sample
    assert labels.tolist() == ["approach", "approach", "free", "impact 1", "impact 2",
                               "free", "rest"]


def test_resampling_is_exact_for_straight_motion_and_extrapolates_back():
    ev = make(np.linspace(0, 2, 5))
    times = np.array([-0.5, 0.1, 0.77, 2.0, 3.0])
    at = ev.at(times)
    # x = 10 t before the end; held at the last state (x = 20) afterwards
    np.testing.assert_allclose(at.vehicle1.position[:, 0], [-5.0, 1.0, 7.7, 20.0, 20.0])
    np.testing.assert_allclose(at.vehicle2.position[:, 1], [-12.5, -9.5, -6.15, 0.0, 0.0])
    assert at.phase.tolist() == ["approach", "impact 1", "free", "free", "free"]


def test_velocity_jumps_at_an_impact_instead_of_smearing():
    # before the impact v = 10, after it v = 2: two samples share t = 0
    time = np.array([-1.0, 0.0, 0.0, 1.0])
    vel = np.array([[10.0, 0], [10.0, 0], [2.0, 0], [2.0, 0]])
    pos = np.array([[-10.0, 0], [0.0, 0], [0.0, 0], [2.0, 0]])
    tr = Track(pos, np.zeros(4), vel, np.zeros(4))
    ev = Event(time, tr, tr, phase_labels(time, [0.0]))
    at = ev.at(np.array([-0.5, 0.0, 0.5]))
    np.testing.assert_allclose(at.vehicle1.velocity[:, 0], [10.0, 2.0, 2.0])
    np.testing.assert_allclose(at.vehicle1.position[:, 0], [-5.0, 0.0, 1.0])


def test_difference_of_two_events_is_a_subtraction():
    a = make(np.linspace(0, 2, 21))
    b = make(np.linspace(0, 2, 11), v1=(9.0, 0.0))
    d = a.difference(b)
    # vehicle 1's positions differ by 1 m/s x t; vehicle 2's not at all
    np.testing.assert_allclose(d.position[:, 0], d.time * 1.0, atol=1e-12)
    np.testing.assert_allclose(d.position[:, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(d.speed[:, 0], 1.0)
    np.testing.assert_allclose(d.rest_position, [2.0, 0.0], atol=1e-12)
    assert d.impacts == 0


def test_join_keeps_order_impacts_and_rows():
    first = make(np.linspace(-1, 0, 3))
    second = make(np.linspace(0, 1, 3))
    joined = Event.join([first, second], source="joined", stopped=(True, False))
    assert len(joined) == 6 and len(joined.impacts) == 2 and joined.source == "joined"
    assert joined.approach_duration == pytest.approx(1.0)
    rows = joined.records()
    assert rows[0]["x1"] == pytest.approx(-10.0) and rows[-1]["vy2"] == pytest.approx(5.0)
    summary = joined.to_dict()
    assert summary["rest"][0]["stopped"] is True
    assert summary["impacts"][0]["delta_v_magnitude"] == pytest.approx([1.0, 1.0])


def test_corners_follow_position_and_heading():
    time = np.array([0.0, 1.0])
    tr = straight(time, (0, 0), (0.0, 0.0), heading=np.pi / 2)
    corners = tr.corners()
    # front-left (2, 1) turned by 90 deg is (-1, 2)
    np.testing.assert_allclose(corners[0, 0], [-1.0, 2.0], atol=1e-12)


def test_the_reconstruction_run_outs_become_an_event():
    case = pim.load_case("synthetic-runout")
    post = pim.post_impact_motion(case)
    ev = post.event()
    assert ev.source == "reconstruction" and all(ev.stopped)
    for i, fit in post.runouts.items():
        np.testing.assert_allclose(ev.tracks[i - 1].position[-1], fit.rest_position, atol=1e-9)
        np.testing.assert_allclose(ev.tracks[i - 1].position[0], fit.runout.states[0, :2])
    assert ev.phase[-1] == "rest"
