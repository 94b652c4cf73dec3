"""Crash pulses against NHTSA 10146 (comparisons.studies.pulses)."""

import math

import numpy as np
import pytest

import sim
from comparisons.studies import pulses as P
from sim.crash_data import default_stiffness, nhtsa10146


@pytest.fixture(scope="module")
def comparison():
    return P.compare_pulses()


def test_measured_metrics_match_the_csv_header(comparison):
    """The data file's first line: max dynamic crush 0.745 m, t(v = 0) = 73.9 ms, rebound
    2.6 m/s, force above 5 % of its peak from 6 to 100 ms (1 ms data; the file's samples are
    2.5 ms apart), impulse 32.4 kN s against m dV = 31.8 kN s."""
    m = comparison.measured_metrics
    assert m.max_crush == pytest.approx(0.745, abs=0.003)
    assert m.max_crush_time == pytest.approx(0.0739, abs=0.0026)
    assert m.rebound_speed == pytest.approx(2.6, abs=0.15)
    assert m.duration == pytest.approx(0.094, abs=0.006)
    t = nhtsa10146()
    impulse = np.sum(0.5 * (t.force[1:] + t.force[:-1]) * np.diff(t.time))
    assert impulse == pytest.approx(32.4e3, rel=0.02)
    assert t.mass * m.delta_v == pytest.approx(31.8e3, rel=0.015)     # the header's m dV


def test_the_law_matches_the_linear_spring_in_closed_form(comparison):
    """A mass m at v0 on a spring k: peak crush v0 sqrt(m/k) at pi/2 sqrt(m/k), peak force
    v0 sqrt(k m); rebound eps v0 (the bilinear law's definition)."""
    k, m, v0, eps = comparison.stiffness, comparison.mass, comparison.speed, comparison.eps
    law = comparison.model_metrics
    assert law.max_crush == pytest.approx(v0 * math.sqrt(m / k), rel=1e-4)
    assert law.peak_force == pytest.approx(v0 * math.sqrt(k * m), rel=1e-4)
    assert law.max_crush_time == pytest.approx(0.5 * math.pi * math.sqrt(m / k), rel=0.01)
    assert law.rebound_speed == pytest.approx(eps * v0, rel=1e-3)
    assert k == sim.DEFAULT_STIFFNESS == default_stiffness("full-width frontal barrier").stiffness


def test_what_is_fitted_to_the_same_test_and_what_is_predicted(comparison):
    # k (the full-width frontal default) and eps both come from NHTSA 10146 itself: the
    # maximum crush, its time, the rebound and the delta-V agree by construction
    assert comparison.stiffness_fitted and comparison.eps_fitted
    assert "NHTSA test 10146" in comparison.stiffness_source
    role = P.roles(comparison)
    assert {a for a, r in role.items() if r.startswith("fitted")} == set(
        P.FROM_STIFFNESS + P.FROM_RESTITUTION)
    assert {a for a, r in role.items() if r == "predicted"} == set(P.PREDICTED)
    law, test = comparison.model_metrics, comparison.measured_metrics
    assert law.rebound_speed == pytest.approx(test.rebound_speed, rel=1e-3)   # by construction
    assert abs(law.peak_force / test.peak_force - 1) > 0.1                    # a prediction


def test_given_parameters_are_not_fitted():
    c = P.compare_pulses(stiffness=6e5, eps=0.2)
    assert not c.stiffness_fitted and not c.eps_fitted and c.stiffness_source == "given"
    assert set(P.roles(c).values()) == {"predicted"}


def test_pulse_metrics_of_a_half_sine():
    t = np.linspace(0.0, 0.1, 1001)
    f = 1e5 * np.sin(np.pi * t / 0.1)
    m = P.pulse_metrics(t, f, 0.5 * np.sin(np.pi * t / 0.1), np.linspace(10.0, -1.0, t.size))
    assert m.peak_force_time == pytest.approx(0.05)
    assert m.duration == pytest.approx(0.1 - 2 * 0.1 * math.asin(0.05) / math.pi, abs=1e-4)
    assert m.rebound_speed == pytest.approx(1.0)
    assert m.delta_v == pytest.approx(11.0)
