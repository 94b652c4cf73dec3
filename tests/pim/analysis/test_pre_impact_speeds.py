"""Speeds before the impact (pim.analysis.pre_impact_speeds): the case's and the
reconstruction's impact speeds through the marks' closed form and the driver table's root
find, and the Monte Carlo's intervals (the commands:
tests/comparisons/report/test_pre_impact.py)."""

import math
from dataclasses import replace
from importlib import resources
from types import SimpleNamespace

import numpy as np
import pytest

from pim.analysis.pre_impact_speeds import (
    case_pre_impact,
    draw_marks,
    impact_speed_samples,
    reconstruction_pre_impact,
)
from pim.analysis.reconstruction import reconstruct
from pim.io.casefile import load_case
from pim.model.distributions import Distribution, UncertaintyTable
from pim.model.driver import DriverInputs
from pim.model.evidence import Evidence, VehicleEvidence
from pim.model.numbers import InputError
from pim.model.pre_impact import PreImpactMarks, speed_at_mark_start

G = 9.80665
FT = 0.3048
MPH = 0.44704
V_CASE = 31.09 * FT                     # the bundled case's impact speeds [m/s]


def bundled(name: str) -> str:
    return (resources.files("pim.io") / "cases" / f"{name}.toml").read_text()


def by_hand_mph(v_ft_s, length_ft, drag, grade=0.0):
    """sqrt(v^2 + 2 g L (f mu cos + sin)) in US units, g = 32.174 ft/s^2, then mph."""
    theta = math.atan(grade)
    v2 = v_ft_s ** 2 + 2 * 32.174049 * length_ft * (drag * 0.7 * math.cos(theta)
                                                     + math.sin(theta))
    return math.sqrt(v2) * FT / MPH


def test_the_bundled_case_from_its_impact_velocities():
    rows = case_pre_impact(load_case("pre-impact-skids"))
    assert [(r.vehicle, r.source) for r in rows] == [(1, "marks"), (2, "marks")]
    assert rows[0].impact_speed == pytest.approx(V_CASE)
    assert rows[0].start_speed / MPH == pytest.approx(by_hand_mph(31.09, 30, 1.0), rel=1e-6)
    # vehicle 2: front wheels locked, front share (3.0 - 1.4) / 3.0, downhill 2 %
    assert rows[1].start_speed / MPH == pytest.approx(
        by_hand_mph(31.09, 20, 1.6 / 3.0, -0.02), rel=1e-6)
    assert math.isnan(rows[0].p5) and rows[0].name == "vehicle1.speed_at_marks_start"


def vehicle_evidence(**kwargs):
    return VehicleEvidence(rest_position=np.zeros(2), rest_heading=0.0, wheelbase=2.6,
                           track=1.5, cg_to_front_axle=1.2, friction=0.7, **kwargs)


def _fake_reconstruction(v_samples, marks, uncertainty=None, driver=None):
    """A reconstruction of vehicle 1's speed alone: its samples as given."""
    case = load_case("ricsac9")
    ev = vehicle_evidence(pre_impact=marks, driver=driver,
                   where="evidence.vehicle1")
    case = replace(case, evidence=Evidence(vehicle1=ev), uncertainty=uncertainty)
    fitted = replace(case, vehicle1=replace(case.vehicle1, velocity=(-float(np.median(
        v_samples)), 0.0)))
    return SimpleNamespace(case=case, fit=SimpleNamespace(values={"vehicle1.speed": 1.0},
                                                          case=fitted),
                           samples=SimpleNamespace(samples={"vehicle1.speed": v_samples},
                                                   n_used=len(v_samples)))


def test_interval_coverage_with_drawn_friction():
    """Impact speed known exactly, friction uniform on 0.7 +- 0.1: the start speed rises with
    the friction, so its q-quantile is the closed form at the friction's q-quantile
    0.6 + 0.2 q (5 %: 0.61, 95 %: 0.79); 20 000 samples hold them to about 0.2 %."""
    marks = PreImpactMarks(15.0, 0.7, where="evidence.vehicle1.pre_impact")
    table = UncertaintyTable({"evidence.vehicle1.pre_impact.friction":
                              Distribution("plusminus", None, 0.1)})
    rec = _fake_reconstruction(np.full(20_000, 12.0), marks, table)
    (row,) = reconstruction_pre_impact(rec, seed=3)
    assert row.start_speed == pytest.approx(speed_at_mark_start(12.0, 15.0, 0.7))
    for p, mu in ((row.p5, 0.61), (row.p50, 0.70), (row.p95, 0.79)):
        assert p == pytest.approx(speed_at_mark_start(12.0, 15.0, mu), rel=2e-3)
    assert row.varied == ("evidence.vehicle1.pre_impact.friction",) and row.n_used == 20_000
    # the friction alone varies: it drives all of the spread
    assert row.drivers[0][0] == "evidence.vehicle1.pre_impact.friction"
    assert row.drivers[0][1] == pytest.approx(1.0, abs=0.02)


def test_without_drawn_marks_the_percentiles_are_those_of_the_impact_speed_carried_over():
    marks = PreImpactMarks(15.0, 0.7)
    v = np.random.default_rng(1).normal(12.0, 1.0, 5000)
    (row,) = reconstruction_pre_impact(_fake_reconstruction(v, marks))
    for p, q in zip((row.p5, row.p50, row.p95), np.percentile(v, [5, 50, 95]), strict=True):
        assert p == pytest.approx(speed_at_mark_start(q, 15.0, 0.7), rel=1e-3)
    assert row.p5 < row.start_speed < row.p95
    (driver,) = row.drivers                    # nothing drawn for the marks: all the impact's
    assert driver[0] == "vehicle1.speed (impact)" and driver[1] == pytest.approx(1, abs=0.02)


def test_drivers_split_the_spread_between_impact_speed_and_friction():
    marks = PreImpactMarks(15.0, 0.7, where="evidence.vehicle1.pre_impact")
    table = UncertaintyTable({"evidence.vehicle1.pre_impact.friction":
                              Distribution("plusminus", None, 0.1)})
    v = np.random.default_rng(4).normal(12.0, 1.0, 20_000)
    (row,) = reconstruction_pre_impact(_fake_reconstruction(v, marks, table), seed=1)
    drivers = dict(row.drivers)
    # additive to first order: the two first-order indices nearly exhaust the variance
    assert drivers["vehicle1.speed (impact)"] > 0.4 and drivers[
        "evidence.vehicle1.pre_impact.friction"] > 0.1
    assert sum(drivers.values()) == pytest.approx(1.0, abs=0.03)


def test_driver_table_percentiles_through_the_root_find():
    driver = DriverInputs([-1.0, 0.0], [0.0, 0.0], [[1.0] * 4] * 2)
    v = np.random.default_rng(2).normal(12.0, 1.0, 2000)
    (row,) = reconstruction_pre_impact(_fake_reconstruction(v, None, driver=driver))
    assert row.source == "driver" and row.start_time == -1.0
    assert row.name == "vehicle1.speed_at_driver_start"
    for p, q in zip((row.p5, row.p50, row.p95), np.percentile(v, [5, 50, 95]), strict=True):
        assert p == pytest.approx(q + 0.7 * G, rel=1e-4)


def test_uncertainty_of_marks_a_vehicle_does_not_have_is_an_error():
    table = UncertaintyTable({"evidence.vehicle2.pre_impact.friction":
                              Distribution("plusminus", None, 0.1)})
    rec = _fake_reconstruction(np.full(50, 12.0), PreImpactMarks(15.0, 0.7), table)
    with pytest.raises(InputError, match=r"evidence\.vehicle2\.pre_impact\.friction: the case "
                                         r"has no \[evidence\.vehicle2\.pre_impact\]"):
        reconstruction_pre_impact(rec)


def test_drawn_length_is_truncated_at_zero_and_friction_checked():
    marks = PreImpactMarks(0.5, 0.7)
    table = UncertaintyTable({"evidence.vehicle1.pre_impact.skid_length":
                              Distribution("normal", None, 1.0)})
    length, friction, uniforms = draw_marks(marks, table, 1, 2000, np.random.default_rng(0))
    assert length.min() >= 0 and np.all(friction == 0.7) and list(uniforms) == [
        "evidence.vehicle1.pre_impact.skid_length"]
    table = UncertaintyTable({"evidence.vehicle1.pre_impact.friction":
                              Distribution("plusminus", None, 0.8)})
    with pytest.raises(InputError, match=r"pre_impact\.friction: value -0\.1 outside"):
        draw_marks(marks, table, 1, 10, np.random.default_rng(0))


def test_impact_speeds_of_a_real_reconstruction():
    """RICSAC 9 turned around (fast: measured motion): each sample's unknowns give its
    impact speeds; their percentiles are the reconstruction's own."""
    rec = reconstruct(load_case("ricsac9-reconstruct"), samples=300, seed=0)
    speeds = impact_speed_samples(rec)
    for i in (1, 2):
        st = rec.samples.stats[f"vehicle{i}.speed"]
        assert np.percentile(speeds[i], 5) == pytest.approx(st.p5, rel=1e-12)
        assert np.percentile(speeds[i], 95) == pytest.approx(st.p95, rel=1e-12)
