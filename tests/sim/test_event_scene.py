"""The simulated event's tyres, outlines and secondary-impact law (sim.event_scene)."""

import math

import numpy as np
import pymunk
import pytest

import pim
from pim.model.event import DEFAULT_TYRE_FRICTION
from pim.model.tyres import STANDARD_GRAVITY
from sim.event_check import side_slap_case
from sim.event_scene import (
    SecondaryLaw,
    event_tyres,
    outline_shapes,
    tyre_friction_source,
    wheel_sliding,
)


def test_secondary_law_checks_its_coefficients():
    assert SecondaryLaw(0.2, 0.4).coefficients == {"eps": 0.2, "beta": 1.0, "mu_c": 0.4}
    with pytest.raises(pim.InputError, match="secondary restitution"):
        SecondaryLaw(restitution=1.5)
    with pytest.raises(pim.InputError, match="secondary contact friction"):
        SecondaryLaw(friction=-0.1)


def test_tyre_friction_comes_from_the_argument_then_the_default():
    case = side_slap_case(1.6)
    assert tyre_friction_source(case, 0.4)[0] == 0.4
    mu, words = tyre_friction_source(case, None)
    assert mu == DEFAULT_TYRE_FRICTION and "default" in words
    with pytest.raises(pim.InputError, match="tyre_friction"):
        tyre_friction_source(case, -1.0)


def test_default_tyres_sit_on_the_outline_and_carry_the_weight():
    case = side_slap_case(1.6)                    # 4.5 m x 1.8 m, 1400 kg, CG mid-outline
    tyres = event_tyres(case, 1, 0.7)
    rv = tyres.vehicle
    assert float(rv.wheelbase) == pytest.approx(0.6 * 4.5)
    assert float(rv.track) == pytest.approx(0.86 * 1.8)
    assert float(rv.cg_to_front_axle) == pytest.approx(0.3 * 4.5)
    assert np.sum(rv.loads) == pytest.approx(1400.0 * STANDARD_GRAVITY)
    assert tyres.reach == pytest.approx(math.hypot(1.35, 0.774))
    assert event_tyres(case, 1, 0.0) is None          # no friction: no tyres


def test_locked_tyres_brake_a_sliding_car_at_mu_g():
    case = side_slap_case(1.6)
    tyres = event_tyres(case, 2, 0.7)
    body = pymunk.Body(1400.0, 1.0)
    body.velocity = (10.0, 0.0)
    (fx, fy), moment = tyres.force(0.0, body)
    # the regularised Coulomb law at 10 m/s: mu m g / sqrt(1 + (v_r / v)^2)
    assert fx == pytest.approx(-0.7 * 1400.0 * STANDARD_GRAVITY, rel=1e-4)
    assert fy == pytest.approx(0.0, abs=1e-9) and moment == pytest.approx(0.0, abs=1e-6)


def test_wheels_slide_when_their_slip_exceeds_the_regularisation():
    tyres = event_tyres(side_slap_case(1.6), 1, 0.7)          # locked wheels
    heading = np.zeros(3)
    velocity = np.array([[10.0, 0.0], [0.0, 0.0], [0.01, 0.0]])
    flags = wheel_sliding(tyres, heading, velocity, np.zeros(3))
    assert flags[0].all() and not flags[1].any() and not flags[2].any()
    # yaw alone: every wheel of a spinning car slips
    assert wheel_sliding(tyres, [0.0], [[0.0, 0.0]], [2.0]).all()
    assert wheel_sliding(None, heading, velocity, np.zeros(3)) is None


def test_outlines_carry_the_secondary_law():
    case = side_slap_case(1.6)
    b1, b2 = pymunk.Body(1.0, 1.0), pymunk.Body(1.0, 1.0)
    s1, s2 = outline_shapes(case, b1, b2, SecondaryLaw(0.25, 0.4))
    assert s1.elasticity * s2.elasticity == 0.25 and s1.friction * s2.friction == 0.4
    assert len(s1.get_vertices()) == 4
