"""The [evidence] and [unknown] tables (pim.io.evidence_table) and their errors."""

import logging
import math

import numpy as np
import pytest

import pim
from pim.io import evidence_table
from pim.io.evidence_table import parse_evidence, parse_unknown
from pim.model.evidence import VehicleEvidence
from pim.model.runout import RunoutVehicle

GOOD = {"vehicle1": {"rest_position": ["30 ft", "12 ft"], "rest_heading": "95 deg",
                     "wheelbase": "108 in", "track": "58 in", "friction": 0.75,
                     "wheels": ["locked", "locked", "free", 0.3], "steer": "5 deg",
                     "path_points": [["10 ft", "3 ft"]]}}


def test_parses_in_si():
    ev = parse_evidence(GOOD).vehicle1
    np.testing.assert_allclose(ev.rest_position, [30 * 0.3048, 12 * 0.3048], rtol=1e-12)
    assert ev.rest_heading == pytest.approx(math.radians(95))
    assert ev.wheelbase == pytest.approx(108 * 0.0254)
    assert ev.cg_to_front_axle == ev.wheelbase / 2
    assert ev.braking == (1.0, 1.0, 0.0, 0.3)
    assert ev.steer == pytest.approx((math.radians(5), math.radians(5), 0.0, 0.0))
    assert ev.path_points.shape == (1, 2)
    assert parse_evidence(GOOD).vehicle2 is None


@pytest.mark.parametrize("key, value, match", [
    ("friction", 0, "evidence.vehicle1.friction"),
    ("friction", -0.3, "evidence.vehicle1.friction"),
    ("rest_position", ["nan ft", "1 ft"], r"evidence.vehicle1.rest_position\[0\]"),
    ("rest_heading", "nan deg", "evidence.vehicle1.rest_heading"),
    ("wheels", ["locked", "skid", "free", "free"], r"evidence.vehicle1.wheels\[1\]"),
    ("wheels", [1.5, 1, 1, 1], r"evidence.vehicle1.wheels\[0\]"),
    ("track", "3 kg", "evidence.vehicle1.track"),
    ("tyres", 4, "unknown key 'tyres'"),
])
def test_bad_evidence_names_the_field(key, value, match):
    table = {"vehicle1": dict(GOOD["vehicle1"], **{key: value})}
    with pytest.raises(ValueError, match=match):
        parse_evidence(table)


def test_unknown_bounds_in_si():
    u = parse_unknown({"vehicle1": {"speed": {"bounds": ["0 mph", "80 mph"]}},
                       "impact": {"restitution": {"bounds": [0, 1]}}})
    assert u["vehicle1.speed"] == pytest.approx((0.0, 80 * 0.44704))
    assert u["impact.restitution"] == (0.0, 1.0)


@pytest.mark.parametrize("table, match", [
    ({"vehicle1": {"speed": {"bounds": ["-5 mph", "80 mph"]}}}, "unknown.vehicle1.speed"),
    ({"vehicle1": {"speed": {"bounds": ["50 mph", "20 mph"]}}}, "low .* must be <= high"),
    ({"vehicle1": {"colour": {"bounds": [0, 1]}}}, "'vehicle1.colour' cannot be solved"),
    ({"impact": {"beta": {"bounds": [0, 2]}}}, r"unknown.impact.beta.bounds must lie"),
    ({"vehicle2": {"speed": [0, 10]}}, r"must be \{bounds = \[low, high\]\}"),
])
def test_bad_unknown_names_the_key(table, match):
    with pytest.raises(ValueError, match=match):
        parse_unknown(table)


def test_an_empty_vehicle_table_is_refused_by_name():
    """An empty [evidence.vehicle1] was accepted without a word (issue 33 point 11): now an
    error naming the table and what it may hold."""
    with pytest.raises(ValueError, match=r"\[evidence.vehicle1\] is empty: give the "
                                         r"run-out's rest_position"):
        parse_evidence({"vehicle1": {}})


def test_marks_before_the_impact_need_no_run_out():
    """A vehicle may have evidence other than a run-out (issue 19), and marks before the
    impact need none of the run-out's keys (issue 33 point 4): they are kept as the
    vehicle's marks, their per-wheel braking weighed by the given front share (else 0.5)."""
    marks = {"skid_length": "30 ft", "friction": 0.7,
             "braking": ["locked", "locked", "free", "free"]}
    ev = parse_evidence({"vehicle2": {"pre_impact": marks}}, front_shares={2: 0.6})
    assert ev.vehicle2 is None and not ev.has_runout
    assert ev.pre_impact(2).skid_length == pytest.approx(30 * 0.3048)
    assert ev.pre_impact(2).drag == pytest.approx(0.6)
    assert ev.pre_impact(1) is None
    assert parse_evidence({"vehicle2": {"pre_impact": marks}}).pre_impact(2).drag \
        == pytest.approx(0.5)
    with pytest.raises(ValueError, match=r"evidence.vehicle2.pre_impact: missing friction"):
        parse_evidence({"vehicle2": {"pre_impact": {"skid_length": "3 m"}}})


CRUSH = {"side": "front", "width": "1.2 m", "depths": ["0.2 m", "0.3 m"],
         "stiffness_a": "35 kN/m", "stiffness_b": "170 kN/m^2"}


def test_a_vehicle_may_have_only_a_crush_profile():
    ev = parse_evidence({"vehicle1": {"crush": CRUSH}})
    assert ev.vehicle1 is None and ev.crush1.side == "front" and ev.crush_partition == "total"
    assert list(ev.crush) == [1] and not ev.has_runout


def test_crush_partitions_must_agree_and_exist():
    with pytest.raises(ValueError, match="different partitions"):
        parse_evidence({"vehicle1": {"crush": {**CRUSH, "partition": "normal"}},
                        "vehicle2": {"crush": {**CRUSH, "side": "left"}}})
    with pytest.raises(ValueError, match="partition = 'shear' is not known"):
        parse_evidence({"vehicle1": {"crush": {**CRUSH, "partition": "shear"}}})


def test_a_crush_wider_than_the_car_names_the_field():
    with pytest.raises(ValueError, match=r"evidence.vehicle1.crush.width"):
        parse_evidence({"vehicle1": {"crush": {**CRUSH, "width": "3 m"}}},
                       {1: (4.5, 1.8), 2: (4.5, 1.8)})


def test_cg_to_front_axle_is_read():
    table = {"vehicle1": dict(GOOD["vehicle1"], cg_to_front_axle="45 in")}
    ev = parse_evidence(table).vehicle1
    assert ev.cg_to_front_axle == pytest.approx(45 * 0.0254)
    np.testing.assert_allclose(ev.runout_vehicle(1500.0, 2500.0).positions[0],
                               [45 * 0.0254, 58 * 0.0254 / 2])


def test_old_key_is_read_as_the_axle_with_one_message(caplog):
    evidence_table._say_old_axle_key.cache_clear()          # as in a fresh process
    table = {"vehicle1": dict(GOOD["vehicle1"], cg_to_front="45 in"),
             "vehicle2": dict(GOOD["vehicle1"], cg_to_front="40 in")}
    with caplog.at_level(logging.WARNING, logger="pim.io.evidence_table"):
        ev = parse_evidence(table)
        parse_evidence(table)
    assert ev.vehicle1.cg_to_front_axle == pytest.approx(45 * 0.0254)
    assert ev.vehicle2.cg_to_front_axle == pytest.approx(40 * 0.0254)
    assert len(caplog.records) == 1
    assert "cg_to_front_axle" in caplog.text and "deprecated" in caplog.text


def test_old_and_new_key_together_is_an_error():
    table = {"vehicle1": dict(GOOD["vehicle1"], cg_to_front="45 in", cg_to_front_axle="45 in")}
    with pytest.raises(ValueError, match="cg_to_front_axle"):
        parse_evidence(table)


def test_the_two_lengths_are_documented_differently():
    outline = pim.Vehicle.__doc__.split("cg_to_front :")[1].split("\n\n")[0]
    assert "OUTLINE" in outline and "axle" in outline.split("Not")[1]
    for kind in (VehicleEvidence, RunoutVehicle):
        axle = kind.__doc__.split("cg_to_front_axle :")[1]
        assert "front AXLE" in axle.split("\n    friction")[0]
