"""The simulated event (sim.simulate_event): momentum and energy through each impact, a
straight slide checked by hand, no outlines through each other, RICSAC 9 to rest,
refusals."""

import math

import numpy as np
import pytest

import pim
import sim
from pim.model.geometry import outline_penetration
from pim.model.tyres import STANDARD_GRAVITY
from sim.event_check import SIDE_SLAP_OFFSETS, side_slap_case

# the generated side slaps: offsets toward the struck car's front corner, two restitutions,
# sticking and sliding first impacts
SLAPS = [(off, eps, beta) for off in SIDE_SLAP_OFFSETS for eps, beta in ((0.1, 1.0),
                                                                         (0.3, 0.5))]


@pytest.fixture(scope="module")
def slaps():
    return {key: sim.simulate_event(side_slap_case(key[0], eps=key[1], beta=key[2]))
            for key in SLAPS}


@pytest.fixture(scope="module")
def ricsac9():
    return pim.load_case("ricsac9")


def _energy(case, event):
    total = np.zeros(len(event))
    for vehicle, track in zip((case.vehicle1, case.vehicle2), event.tracks, strict=True):
        if vehicle.fixed:
            continue
        total += 0.5 * float(vehicle.mass) * track.speed ** 2
        total += 0.5 * float(vehicle.yaw_inertia) * track.yaw_rate ** 2
    return total


@pytest.mark.parametrize("key", SLAPS)
def test_side_slaps_have_secondary_impacts_that_conserve_momentum(slaps, key):
    case = side_slap_case(key[0], eps=key[1], beta=key[2])
    event = slaps[key]
    assert len(event.impacts) >= 2                       # the slap is found
    m = np.array([float(case.vehicle1.mass), float(case.vehicle2.mass)])
    for imp in event.impacts:
        p = m[:, None] * imp.delta_v                     # each vehicle's momentum change
        scale = float(np.max(np.abs(p))) + 1e-12
        assert np.all(np.abs(p[0] + p[1]) <= 1e-9 * scale)     # momentum conserved
        assert np.allclose(p[0], imp.impulse, rtol=1e-9, atol=1e-9 * scale)
        assert imp.energy_loss >= -1e-6 * _energy(case, event)[0]   # no energy gained


@pytest.mark.parametrize("key", SLAPS)
def test_side_slaps_never_gain_energy_and_never_pass_through(slaps, key):
    case = side_slap_case(key[0], eps=key[1], beta=key[2])
    event = slaps[key]
    energy = _energy(case, event)
    after = event.time >= 0
    assert np.all(np.diff(energy[after]) <= 1e-6 * energy[0])
    # the outlines touch at C without overlap; a step at 1 ms closes at most 14 mm
    depth = outline_penetration(*[(t.position, t.heading, 4.5, 1.8, None)
                                  for t in event.tracks])
    assert np.max(depth[after]) < 0.03
    assert event.stopped == (True, True) and event.phase[-1] == "rest"


def test_straight_slide_into_a_barrier_ends_at_v_squared_over_2_mu_g():
    # head-on into a wall, frictionless central impact: vehicle 1 rebounds straight back at
    # eps v0 and slides on locked wheels to rest (v0 eps)^2 / (2 mu g) behind C's pose
    v0, eps, mu = 15.0, 0.3, 0.7
    car = pim.Vehicle(mass=1500.0, yaw_inertia=2500.0, cg=[-2.25, 0.0], velocity=[v0, 0.0],
                      heading=0.0, length=4.5, width=1.8)
    wall = pim.Vehicle.obstacle(cg=[5.0, 0.0])
    case = pim.Case(car, wall, pim.Impact(point=[0.0, 0.0], normal_angle=math.pi,
                                          restitution=eps, beta=0.0))
    event = sim.simulate_event(case, tyre_friction=mu)
    by_hand = (eps * v0) ** 2 / (2 * mu * STANDARD_GRAVITY)     # 1.4749 m
    rest = event.vehicle1.position[-1]
    # 1 cm: the regularised Coulomb law's creep (about 1 mm), the rest test at 0.05 m/s and
    # the first-order step (v dt / 2 = 2 mm)
    assert rest[0] == pytest.approx(-2.25 - by_hand, abs=0.01)
    assert abs(rest[1]) < 1e-9 and abs(event.vehicle1.heading[-1]) < 1e-9
    assert len(event.impacts) == 1 and event.stopped[0]
    # the approach: v0 held back 1 s
    assert event.time[0] == pytest.approx(-1.0)
    assert event.vehicle1.position[0, 0] == pytest.approx(-2.25 - v0, abs=1e-9)


def test_rear_end_slide_distances_checked_by_hand():
    # collinear rear-end: 1-D momentum and Newton's restitution give each car's speed,
    # then each slides v^2 / (2 mu g) on locked wheels
    m1, m2, u1, u2, eps, mu = 1200.0, 1600.0, 20.0, 5.0, 0.2, 0.7
    car1 = pim.Vehicle(mass=m1, yaw_inertia=2000.0, cg=[-2.25, 0.0], velocity=[u1, 0.0],
                       heading=0.0, length=4.5, width=1.8)
    car2 = pim.Vehicle(mass=m2, yaw_inertia=2800.0, cg=[2.25, 0.0], velocity=[u2, 0.0],
                       heading=0.0, length=4.5, width=1.8)
    case = pim.Case(car1, car2, pim.Impact(point=[0.0, 0.0], normal_angle=math.pi,
                                           restitution=eps, beta=0.0))
    event = sim.simulate_event(case, tyre_friction=mu)
    v1 = (m1 * u1 + m2 * u2 - m2 * eps * (u1 - u2)) / (m1 + m2)
    v2 = (m1 * u1 + m2 * u2 + m1 * eps * (u1 - u2)) / (m1 + m2)
    for x0, v, track in ((-2.25, v1, event.vehicle1), (2.25, v2, event.vehicle2)):
        assert track.position[-1, 0] == pytest.approx(
            x0 + v * v / (2 * mu * STANDARD_GRAVITY), abs=0.02)
    assert len(event.impacts) == 1


def test_ricsac9_event_with_tyres_reaches_rest(ricsac9):
    event = sim.simulate_event(ricsac9)
    assert event.source == "simulated" and event.stopped == (True, True)
    phases = list(dict.fromkeys(event.phase))
    assert phases[0] == "approach" and phases[-1] == "rest" and "impact 1" in phases
    first = event.impacts[0]
    # the first impact is the rigid scene's, i.e. PIM's answer at the case's eps and beta
    pim_result = pim.solve(ricsac9)
    assert np.allclose(first.velocity_after[0], np.asarray(pim_result.velocity1).ravel(),
                       atol=1e-6)
    assert first.time == 0 and first.source == "case"
    assert 0.5 < event.end_time < 5.0
    assert np.all(np.isfinite(event.rest_position))
    # wheels slide right after the impact, none in the approach or at rest
    s = event.vehicle1.sliding
    assert not s[event.time < 0].any() and s[event.phase == "impact 1"].any()
    assert not s[-1].any()
    assert "0.7" in " ".join(event.notes)                # the default friction, stated


def test_ricsac9_free_motion_has_its_secondary_contact(ricsac9):
    # without tyres the rigid replay's outlines run into each other again near 0.44 s
    # (sim.find_secondary_impact: when the overlap has grown by its tolerance); the event
    # resolves that contact from its first touch
    event = sim.simulate_event(ricsac9, tyre_friction=0.0, max_time=1.0)
    assert len(event.impacts) == 2
    second = event.impacts[1]
    assert 0.40 < second.time < 0.45 and second.source == "simulation"
    assert second.law == "brach-capped" and second.coefficients["mu_c"] == 0.5
    assert event.stopped == (False, False) and "time limit" in event.notes[-1]


def test_a_contact_that_never_ends_is_refused():
    case = side_slap_case(1.6)
    with pytest.raises(sim.SimulationError) as err:
        sim.simulate_event(case, settings=sim.Settings(max_contact_time=1e-4))
    assert err.value.kind == "never_separated"


def test_an_event_that_gains_energy_is_refused(monkeypatch):
    # tyres that push instead of braking: kinetic energy rises in the run-out
    from sim.event_scene import EventTyres

    real = EventTyres.force

    def pushing(self, t, body):
        (fx, fy), moment = real(self, t, body)
        return (-fx, -fy), -moment

    monkeypatch.setattr(EventTyres, "force", pushing)
    with pytest.raises(sim.SimulationError) as err:
        sim.simulate_event(side_slap_case(1.6), max_time=0.2)
    assert err.value.kind == "energy_gained"


@pytest.mark.parametrize("kwargs, field", [
    ({"tyre_friction": -0.1}, "tyre_friction"), ({"approach": -1.0}, "approach"),
    ({"settings": 0.001}, "settings"), ({"max_time": 0.0}, "max_time")])
def test_bad_options_name_the_field(kwargs, field):
    with pytest.raises((pim.InputError, TypeError)) as err:
        sim.simulate_event(side_slap_case(1.6), **kwargs)
    assert field in str(err.value)


def test_outlines_are_required():
    case = side_slap_case(1.6)
    bare = pim.Vehicle(mass=1400.0, yaw_inertia=2000.0, cg=[1.6, -3.15],
                       velocity=[0.0, 13.9], heading=math.pi / 2)
    with pytest.raises(pim.InputError, match="length and width"):
        sim.simulate_event(pim.Case(bare, case.vehicle2, case.impact))
