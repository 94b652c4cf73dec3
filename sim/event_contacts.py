"""The outline contacts of the simulated event: which are processed, and what each impact
did (the collision callbacks of :mod:`sim.event`; the rule is stated there).

:class:`OutlineContacts` is the callbacks' bookkeeping: whether the contact is armed (the
outlines came apart, or their overlap grew by the tolerance since the last impact),
whether it was processed in the current step and its closing speed then (the largest
approach speed of its points before the step), and the sums over the current impact's steps
(impulse, impulse-weighted contact point and normal, the tyres' impulse and angular
impulse, to take out of the contact's delta-V).
"""

from __future__ import annotations

import numpy as np
import pymunk

from .event_scene import OUTLINE1, OUTLINE2
from .overlap import overlap_area, place
from .run import APPROACH_TOLERANCE
from .secondary import DEFAULT_TOLERANCE

__all__ = ["OutlineContacts", "attach_outline_contacts"]


class OutlineContacts:
    """Bookkeeping of the outline contacts (module notes).

    Parameters
    ----------
    bodies : tuple of pymunk.Body
        Vehicle 1's and vehicle 2's bodies.
    outlines : tuple of ndarray (4, 2) or None
        Body-frame corners of each outline (None: a barrier face, never overlapping by area).
    speed_scale : float
        [m/s] for the approach tolerance.
    armed : bool
        Whether the contact counts from the start (the outlines are apart).
    """

    def __init__(self, bodies, outlines, speed_scale: float, armed: bool) -> None:
        self.bodies = bodies
        self.outlines = outlines
        self.tol = APPROACH_TOLERANCE * speed_scale
        areas = [float(np.prod(np.ptp(o, axis=0))) for o in outlines if o is not None]
        self.threshold = DEFAULT_TOLERANCE * min(areas) if areas else 0.0
        self.armed = armed
        self.lowest = np.inf
        self.accepted = False
        self.closing = 0.0
        self.points = 0
        self.clear()

    def clear(self) -> None:
        """Forget the current impact's sums."""
        self.impulse = np.zeros(2)
        self.weight = 0.0
        self.point = np.zeros(2)
        self.normal = np.zeros(2)
        self.steps = 0

    def overlap(self) -> float:
        """Overlap area of the outlines now [m^2] (0 with a barrier face)."""
        if any(o is None for o in self.outlines):
            return 0.0
        polys = [place(o, tuple(b.position), b.angle) for o, b in
                 zip(self.outlines, self.bodies, strict=True)]
        return overlap_area(polys[0], polys[1])

    def relative(self, point_a, point_b):
        """Velocity of vehicle 2's point minus vehicle 1's (Chipmunk's b - a) [m/s]."""
        b1, b2 = self.bodies
        return b2.velocity_at_world_point(point_b) - b1.velocity_at_world_point(point_a)


def _pre_solve(arbiter, space, mon: OutlineContacts) -> None:
    points = arbiter.contact_point_set.points
    if not mon.armed:
        area = mon.overlap()
        mon.lowest = min(mon.lowest, area)
        if area > mon.lowest + mon.threshold:
            mon.armed = True
        else:
            arbiter.process_collision = False
            return
    normal = arbiter.contact_point_set.normal
    closing = max(-mon.relative(p.point_a, p.point_b).dot(normal) for p in points)
    if not closing > mon.tol:
        arbiter.process_collision = False
        return
    arbiter.process_collision = True     # a rejection would otherwise persist to separation
    mon.accepted = True
    mon.closing = max(mon.closing, closing)
    mon.points = max(mon.points, len(points))


def _post_solve(arbiter, space, mon: OutlineContacts) -> None:
    if not mon.accepted:
        return
    j = arbiter.total_impulse                      # on vehicle 1 (shapes[0])
    size = float(np.hypot(j.x, j.y))
    mon.impulse += (j.x, j.y)
    points = arbiter.contact_point_set.points
    centre = np.mean([[(p.point_a.x + p.point_b.x) / 2, (p.point_a.y + p.point_b.y) / 2]
                      for p in points], axis=0)
    normal = arbiter.contact_point_set.normal      # from vehicle 1 to vehicle 2
    mon.point += size * centre
    mon.normal -= size * np.array([normal.x, normal.y])
    mon.weight += size


def _separate(arbiter, space, mon: OutlineContacts) -> None:
    mon.armed = True                               # the outlines came apart


def attach_outline_contacts(space: pymunk.Space, mon: OutlineContacts) -> None:
    """Add the outline contacts' collision callbacks to ``space``."""
    space.on_collision(OUTLINE1, OUTLINE2, pre_solve=_pre_solve, post_solve=_post_solve,
                       separate=_separate, data=mon)
