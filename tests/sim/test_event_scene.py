"""The simulated event's tyres, outlines and secondary-impact law (sim.event_scene)."""

import math
from dataclasses import replace

import numpy as np
import pymunk
import pytest

import pim
from pim.analysis.event import TRACK_PER_WIDTH, WHEELBASE_PER_LENGTH
from pim.model.case import ImpactSpec
from pim.model.event import DEFAULT_TYRE_FRICTION
from pim.model.tyres import STANDARD_GRAVITY
from sim.event_check import side_slap_case
from sim.event_scene import (
    SecondaryLaw,
    event_tyres,
    outline_shapes,
    secondary_law,
    tyre_friction_source,
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


def test_default_tyres_are_the_analytic_events():
    case = side_slap_case(1.6)                    # 4.5 m x 1.8 m, 1400 kg, CG mid-outline
    tyres = event_tyres(case, 1, 0.7)
    rv = tyres.vehicle
    assert float(rv.wheelbase) == pytest.approx(WHEELBASE_PER_LENGTH * 4.5)
    assert float(rv.track) == pytest.approx(TRACK_PER_WIDTH * 1.8)
    assert float(rv.cg_to_front_axle) == pytest.approx(0.5 * WHEELBASE_PER_LENGTH * 4.5)
    assert np.all(np.asarray(rv.braking) == 1.0)            # locked
    assert np.sum(rv.loads) == pytest.approx(1400.0 * STANDARD_GRAVITY)
    assert tyres.reach == pytest.approx(math.hypot(0.3 * 4.5, TRACK_PER_WIDTH * 0.9))
    assert event_tyres(case, 1, 0.0) is None          # no friction: no tyres


def test_secondary_law_follows_the_cases_impacts():
    case = side_slap_case(1.6)
    law, name, note = secondary_law(case, 2)
    assert (law.restitution, law.friction, name, note) == (0.1, 0.5, "brach-capped", "")
    spec = ImpactSpec(law="brach", restitution=0.2, beta=0.5)
    law, name, note = secondary_law(replace(case, impacts=(spec,)), 3)
    assert (law.restitution, law.friction, name) == (0.2, math.inf, "brach")
    assert "beta 0.5" in note                          # pymunk cannot run it: said
    assert secondary_law(case, 2, SecondaryLaw(0.3, 0.2))[0].restitution == 0.3


def test_locked_tyres_brake_a_sliding_car_at_mu_g():
    case = side_slap_case(1.6)
    tyres = event_tyres(case, 2, 0.7)
    body = pymunk.Body(1400.0, 1.0)
    body.velocity = (10.0, 0.0)
    (fx, fy), moment = tyres.force(0.0, body)
    # the regularised Coulomb law at 10 m/s: mu m g / sqrt(1 + (v_r / v)^2)
    assert fx == pytest.approx(-0.7 * 1400.0 * STANDARD_GRAVITY, rel=1e-4)
    assert fy == pytest.approx(0.0, abs=1e-9) and moment == pytest.approx(0.0, abs=1e-6)


def test_outlines_carry_the_secondary_law():
    case = side_slap_case(1.6)
    b1, b2 = pymunk.Body(1.0, 1.0), pymunk.Body(1.0, 1.0)
    s1, s2 = outline_shapes(case, b1, b2, SecondaryLaw(0.25, 0.4))
    assert s1.elasticity * s2.elasticity == 0.25 and s1.friction * s2.friction == 0.4
    assert len(s1.get_vertices()) == 4
