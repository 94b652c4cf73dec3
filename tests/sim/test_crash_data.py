"""NHTSA test 10146: the bundled data reproduce the figures its source line and the issue
quote (impulse, crush, stiffness, restitution, duration)."""

import numpy as np
import pytest

from sim.crash_data import contact_parameters, nhtsa10146


def test_source_line_and_units():
    test = nhtsa10146()
    assert "10146" in test.source and "Camry" in test.source
    assert test.time[0] == 0.0 and test.time[-1] == pytest.approx(0.1)
    assert test.velocity[0] == pytest.approx(57.09 / 3.6, abs=0.02)     # 57.09 km/h


def test_impulse_matches_momentum_change():
    # source line: int F dt = 32.4 kN s against m dV = 31.8 kN s
    test = nhtsa10146()
    impulse = np.trapezoid(test.force, test.time)
    assert impulse == pytest.approx(32.4e3, rel=0.03)
    assert test.mass * (test.velocity[0] - test.velocity[-1]) == pytest.approx(31.8e3, rel=0.01)


def test_contact_parameters_match_the_quoted_values():
    p = contact_parameters(nhtsa10146())
    assert 7.4e5 <= p.stiffness <= 7.8e5            # issue: 750-780 kN/m
    assert p.peak_crush == pytest.approx(0.745, abs=0.002)
    assert p.peak_force == pytest.approx(731e3, rel=0.03)   # 731 kN at 1 ms; 719 kN at 2.5 ms
    assert p.restitution == pytest.approx(0.165, abs=0.012)
    assert p.contact_start == pytest.approx(0.006, abs=0.002)
    assert p.contact_end == pytest.approx(0.100, abs=0.003)
