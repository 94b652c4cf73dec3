"""What the simulated event puts in its pymunk Space besides the rigid scene of the first
impact: each vehicle's tyres (the run-out's one right-hand side) and the outlines that
collide after it, with the secondary-impact law's coefficients.

Tyres (:func:`event_tyres`): the case's evidence where it gives wheelbase, track, axle
position, braking and friction (:meth:`pim.model.evidence.VehicleEvidence.runout_vehicle`);
otherwise the four-tyre layout of the contact scenes, wheelbase and track fixed fractions of
the outline (:func:`sim.contact_tyres.wheels_from_outline`: 0.6 L and 0.86 W, the axles
centred on the outline), locked wheels (the run-out's default) and the tyre friction
``tyre_friction`` if given, else the evidence's, else
:data:`pim.model.event.DEFAULT_TYRE_FRICTION`. The forces are those of
:class:`pim.model.runout.TimedRhs` (:mod:`pim.model.runout_formula`, the tyre law of
:mod:`pim.model.tyres`), applied at the CG with their yaw moment every step, as
:mod:`sim.runout_check` does.

Outlines (:func:`outline_shapes`): each vehicle's length x width rectangle as a pymunk
polygon (a fixed obstacle without dimensions: a straight face through C along the tangent),
elasticity eps_2 on vehicle 1 and 1 on vehicle 2 (Chipmunk multiplies them: Newton's
restitution eps_2 at the contact), friction mu_c and 1 (a Coulomb cap |P_t| <= mu_c P_n):
the friction-capped Brach law ("brach-capped") at beta = 1, which is what Chipmunk's polygon
contact does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import pymunk

import pim
from pim.model.event import DEFAULT_TYRE_FRICTION
from pim.model.numbers import InputError
from pim.model.runout import RunoutVehicle, TimedRhs

from .contact_law import check_fraction, check_positive
from .contact_tyres import wheels_from_outline
from .scene import outline_corners

__all__ = ["SecondaryLaw", "EventTyres", "event_tyres", "outline_shapes", "wheel_sliding",
           "SECONDARY_RESTITUTION", "SECONDARY_FRICTION", "OUTLINE1", "OUTLINE2",
           "tyre_friction_source"]

#: Restitution eps_2 [-] of a contact the event finds (nobody measures one): low, as for
#: the side slaps and secondary contacts of the staged tests (RICSAC's 0.1-0.3).
SECONDARY_RESTITUTION = 0.1
#: Coulomb cap mu_c [-] of the friction between the vehicles in a contact the event finds
#: (sheet metal on sheet metal; the assumptions ladder's typical 0.5).
SECONDARY_FRICTION = 0.5
#: Collision types of the outlines (the rigid scene's point contact uses 1 and 2).
OUTLINE1, OUTLINE2 = 3, 4


@dataclass(frozen=True)
class SecondaryLaw:
    """The law of every contact after the first impact: friction-capped Brach at beta = 1.

    Attributes
    ----------
    restitution : float
        Newton's restitution eps_2 [-] in [0, 1].
    friction : float
        Coulomb cap mu_c [-] >= 0 on the impulse ratio |P_t| / P_n.
    """

    restitution: float = SECONDARY_RESTITUTION
    friction: float = SECONDARY_FRICTION

    def __post_init__(self):
        object.__setattr__(self, "restitution",
                           check_fraction(self.restitution, "secondary restitution"))
        object.__setattr__(self, "friction", check_positive(
            self.friction, "secondary contact friction", "-", allow_zero=True))

    @property
    def coefficients(self) -> dict:
        """The law's coefficients by name, as :class:`pim.model.event.ImpactRecord` holds
        them."""
        return {"eps": self.restitution, "beta": 1.0, "mu_c": self.friction}


@dataclass(frozen=True, eq=False)
class EventTyres:
    """One vehicle's tyres in the event.

    Attributes
    ----------
    vehicle : RunoutVehicle
        The run-out's vehicle (wheels, loads, friction, braking, steer).
    rhs : TimedRhs
        Its right-hand side (forces = mass and inertia times its accelerations).
    reach : float
        Largest tyre arm r_max [m] (the rest test |v| + |omega| r_max).
    """

    vehicle: RunoutVehicle
    rhs: TimedRhs
    reach: float

    def force(self, t: float, body: pymunk.Body) -> tuple[tuple, float]:
        """Tyre force [N] (global frame) and yaw moment [N m] on ``body`` at time ``t``."""
        v = body.velocity
        rate = self.rhs(t, (0.0, 0.0, body.angle, v.x, v.y, body.angular_velocity))
        mass, inertia = float(self.vehicle.mass), float(self.vehicle.yaw_inertia)
        return (mass * rate[3], mass * rate[4]), inertia * rate[5]


def tyre_friction_source(case: pim.Case, tyre_friction) -> tuple[float | None, str]:
    """The event's tyre friction [-] and where it comes from, in words: the argument, the
    case's evidence (both vehicles' if equal), or the stated default."""
    if tyre_friction is not None:
        mu = check_positive(tyre_friction, "tyre_friction", "-", allow_zero=True)
        return mu, f"tyre friction {mu:g} (given)"
    ev = case.evidence
    given = [getattr(ev, f"vehicle{i}", None) if ev is not None else None for i in (1, 2)]
    if any(g is not None for g in given):
        return None, "tyre friction from the case's evidence"
    return DEFAULT_TYRE_FRICTION, (f"tyre friction {DEFAULT_TYRE_FRICTION:g} (default: dry "
                                   "asphalt, the case gives none)")


def event_tyres(case: pim.Case, index: int, friction: float | None) -> EventTyres | None:
    """Vehicle ``index``'s (1 or 2) tyres (module notes); None for a fixed obstacle or a
    friction of 0 (no tyre forces). ``friction`` None: the evidence's, else the default."""
    vehicle = getattr(case, f"vehicle{index}")
    if vehicle.fixed:
        return None
    ev = getattr(case.evidence, f"vehicle{index}", None) if case.evidence is not None else None
    mass, inertia = float(vehicle.mass), float(vehicle.yaw_inertia)
    if ev is not None:
        runout = ev.runout_vehicle(mass, inertia)
        if friction is not None:
            if friction == 0:
                return None
            runout = replace(runout, friction=friction)
    else:
        mu = DEFAULT_TYRE_FRICTION if friction is None else friction
        if mu == 0:
            return None
        wheels = wheels_from_outline(vehicle.length, vehicle.width, math.sqrt(inertia / mass),
                                     vehicle.cg_to_front)
        runout = RunoutVehicle(mass, inertia, float(wheels[0, 0] - wheels[2, 0]),
                               float(wheels[0, 1] - wheels[1, 1]), float(wheels[0, 0]), mu)
    positions = runout.positions
    return EventTyres(runout, TimedRhs(runout), float(np.max(np.hypot(*positions.T))))


def wheel_sliding(tyres: EventTyres | None, heading, velocity, yaw_rate):
    """Each wheel sliding (tyre marks) at N states (N, 4), or None without tyres.

    A wheel slides where its slip speed (:func:`pim.model.tyres.wheel_force`'s slip: the
    whole ground velocity for its braking share, the lateral component for the rolling
    share) exceeds the law's regularisation speed v_r.
    """
    if tyres is None:
        return None
    rv = tyres.vehicle
    heading, yaw_rate = np.asarray(heading, float), np.asarray(yaw_rate, float)
    velocity = np.asarray(velocity, float)
    c, s = np.cos(heading)[:, None], np.sin(heading)[:, None]
    p = rv.positions
    ax, ay = c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]
    sx = velocity[:, :1] - yaw_rate[:, None] * ay
    sy = velocity[:, 1:] + yaw_rate[:, None] * ax
    wheel = heading[:, None] + np.asarray(rv.steer, float)
    lateral = np.abs(-np.sin(wheel) * sx + np.cos(wheel) * sy)
    braking = np.asarray(rv.braking, float)
    vr = rv.regularisation
    return ((braking > 0) & (np.hypot(sx, sy) > vr)) | ((braking < 1) & (lateral > vr))


def outline_shapes(case: pim.Case, body1: pymunk.Body, body2: pymunk.Body,
                   law: SecondaryLaw) -> list:
    """The colliding outlines of both vehicles (module notes), with their collision types
    :data:`OUTLINE1`, :data:`OUTLINE2`, elasticity and friction."""
    shapes = []
    for vehicle, body, kind in ((case.vehicle1, body1, OUTLINE1),
                                (case.vehicle2, body2, OUTLINE2)):
        corners = outline_corners(vehicle)
        if corners is not None:
            shape = pymunk.Poly(body, [tuple(map(float, c)) for c in corners])
        elif vehicle.fixed:
            shape = _barrier_face(case, body)
        else:
            raise InputError(f"the event needs {('vehicle1', 'vehicle2')[kind - OUTLINE1]}"
                             ".length and .width: its outline is what collides after the "
                             "first impact")
        first = kind == OUTLINE1
        shape.collision_type = kind
        shape.elasticity = law.restitution if first else 1.0
        shape.friction = law.friction if first else 1.0
        shapes.append(shape)
    return shapes


def _barrier_face(case: pim.Case, body: pymunk.Body) -> pymunk.Segment:
    """A fixed obstacle without dimensions: a straight face through C along the tangent,
    100 m each way (in the static body's frame)."""
    point = np.asarray(case.impact.point, float).reshape(2)
    t = np.asarray(case.impact.tangent, float).reshape(2)
    local = [body.world_to_local(tuple(map(float, point + k * 100.0 * t))) for k in (-1, 1)]
    return pymunk.Segment(body, local[0], local[1], 0.0)
