"""The outline contacts of the simulated event (sim.event_contacts): the overlap the rule
reads, and an armed contact processed while its points approach."""

import numpy as np
import pymunk
import pytest

from sim.event_contacts import OutlineContacts, attach_outline_contacts
from sim.event_scene import OUTLINE1, OUTLINE2, SecondaryLaw

BOX = np.array([[1.0, 0.5], [-1.0, 0.5], [-1.0, -0.5], [1.0, -0.5]])   # 2 m x 1 m


def _space(x2: float, v1: float):
    space = pymunk.Space()
    bodies = (pymunk.Body(1000.0, 1000.0), pymunk.Body(1000.0, 1000.0))
    bodies[0].velocity = (v1, 0.0)
    bodies[1].position = (x2, 0.0)
    space.add(*bodies)
    for body, kind in zip(bodies, (OUTLINE1, OUTLINE2), strict=True):
        shape = pymunk.Poly(body, [tuple(c) for c in BOX])
        shape.collision_type = kind
        shape.elasticity, shape.friction = 1.0, 0.0
        space.add(shape)
    space.collision_slop = 1e6
    space.iterations = 30               # the event's count: two points converge
    return space, bodies


def test_overlap_depth_and_area():
    space, bodies = _space(1.5, 0.0)                       # 0.5 m x 1 m overlap
    mon = OutlineContacts(bodies, (BOX, BOX), 10.0, 0.01, SecondaryLaw())
    assert mon.overlap() == pytest.approx(0.5) and mon.depth() == pytest.approx(0.5)
    barrier = OutlineContacts(bodies, (BOX, None), 10.0, 0.01, SecondaryLaw())
    assert barrier.overlap() == 0.0 and barrier.armed     # a barrier face: always armed


def test_an_armed_closing_contact_is_an_impulse_under_its_law():
    space, bodies = _space(2.001, 5.0)                     # 1 mm apart, closing at 5 m/s
    mon = OutlineContacts(bodies, (BOX, BOX), 5.0, 0.01, SecondaryLaw(1.0, 0.0))
    mon.armed = True
    attach_outline_contacts(space, mon)
    space.step(1e-3)
    assert mon.accepted and mon.closing == pytest.approx(5.0)
    # restitution 1, equal masses: the velocities swap; the impulse on vehicle 1 is -m v
    assert mon.impulse == pytest.approx([-5000.0, 0.0], rel=1e-6)
    normal = mon.normal / np.hypot(*mon.normal)
    assert normal == pytest.approx([-1.0, 0.0])            # from vehicle 2 toward vehicle 1
    assert bodies[1].velocity.x == pytest.approx(5.0, rel=1e-6)


def test_a_disarmed_contact_is_ignored_until_the_depth_grows():
    space, bodies = _space(1.5, 1.0)                       # deep overlap (a crush)
    mon = OutlineContacts(bodies, (BOX, BOX), 1.0, 0.01, SecondaryLaw())
    mon.disarm()
    attach_outline_contacts(space, mon)
    for _ in range(9):                                     # 9 mm deeper: not yet
        space.step(1e-3)
    assert not mon.armed and bodies[0].velocity.x == 1.0
    for _ in range(3):                                     # past 1 cm: armed, processed
        space.step(1e-3)
    assert mon.armed and mon.accepted and bodies[0].velocity.x < 1.0
