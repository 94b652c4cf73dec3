"""NHTSA test 10146: the bundled data reproduce the figures its source line and the issue
quote (impulse, crush, stiffness, restitution, duration)."""

from dataclasses import replace

import numpy as np
import pytest

import pim
import sim
from pim.analysis.validation import barrier_case
from pim.io.datasets import load_barrier
from pim.model.numbers import InputError
from sim.crash_data import contact_parameters, contact_type, default_stiffness, nhtsa10146


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


def barrier_pulse_case(mass, speed):
    """A car head-on into a barrier, C on its centreline (the pulse scene's layout)."""
    car = pim.Vehicle(mass=mass, yaw_inertia=mass * 1.2**2, cg=(2.0, 0.0),
                      velocity=(-speed, 0.0), heading=np.pi)
    return pim.Case(car, pim.Vehicle.obstacle(cg=(-1.0, 0.0)),
                    pim.Impact(point=(0.0, 0.0), normal_angle=0.0))


def test_the_stiffness_default_is_sourced_for_a_full_width_frontal_barrier():
    test = nhtsa10146()
    case = barrier_pulse_case(test.mass, float(test.velocity[0]))
    assert contact_type(case) == "full-width frontal barrier"
    d = default_stiffness(contact_type(case))
    assert d.stiffness == sim.DEFAULT_STIFFNESS and d.test == test.name
    # the source's figure is what contact_parameters gives from the bundled record
    assert f"{contact_parameters(test).stiffness / 1e3:.0f} kN/m" in d.source


@pytest.mark.parametrize("test_index", [0, 20])
def test_the_stiffness_default_is_refused_for_a_small_overlap_contact(test_index):
    # Brach et al.'s IIHS small-overlap barrier tests (25 % overlap, Gamma 70-80 deg off
    # the heading) engage part of the front: the full-width frontal default does not apply
    test = load_barrier()[test_index]
    case = barrier_case(test, 1.2)
    kind = contact_type(case)
    assert kind in ("oblique barrier", "offset frontal barrier")
    with pytest.raises(InputError, match=f"no measured default for the contact type '{kind}'"):
        default_stiffness(kind)


def test_a_head_on_but_offset_barrier_contact_and_two_vehicles_are_refused():
    offset = barrier_pulse_case(1500.0, 15.0)
    offset = replace(offset, vehicle1=replace(offset.vehicle1, width=1.8),
                     impact=replace(offset.impact, point=(0.0, 0.6)))       # 33 % off centre
    assert contact_type(offset) == "offset frontal barrier"
    assert contact_type(pim.load_case("ricsac9")) == "vehicle-to-vehicle"
    with pytest.raises(InputError, match="crush in series"):
        default_stiffness("vehicle-to-vehicle")
    with pytest.raises(InputError, match="contact type must be one of"):
        default_stiffness("small overlap")
