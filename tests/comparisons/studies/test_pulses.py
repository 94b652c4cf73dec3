"""Crash pulses against NHTSA 10146 (comparisons.studies.pulses)."""

import math

import numpy as np
import pytest

import sim
from comparisons.studies import pulses as P
from sim.crash_data import nhtsa10146


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
    assert k == sim.DEFAULT_STIFFNESS


def test_errors_are_stated_against_the_csv_numbers(comparison):
    table = P.pulse_table(comparison)
    rows = {r[0]: r for r in table.rows}
    peak = rows["peak force"]
    assert peak[2] == pytest.approx(719.0, abs=1.0)          # kN, the file's largest sample
    assert peak[4] == pytest.approx(peak[3] - peak[2])
    crush = rows["maximum crush"]
    assert abs(crush[5]) < 5.0                                # % : the law gets the crush
    assert rows["peak force"][5] < -10.0                      # and misses the force spikes
    assert comparison.delta_v_rms < 1.0
    us = P.pulse_table(comparison, "us")
    assert {r[0]: r for r in us.rows}["maximum crush"][1] == "ft"


def test_pulse_metrics_of_a_half_sine():
    t = np.linspace(0.0, 0.1, 1001)
    f = 1e5 * np.sin(np.pi * t / 0.1)
    m = P.pulse_metrics(t, f, 0.5 * np.sin(np.pi * t / 0.1), np.linspace(10.0, -1.0, t.size))
    assert m.peak_force_time == pytest.approx(0.05)
    assert m.duration == pytest.approx(0.1 - 2 * 0.1 * math.asin(0.05) / math.pi, abs=1e-4)
    assert m.rebound_speed == pytest.approx(1.0)
    assert m.delta_v == pytest.approx(11.0)
