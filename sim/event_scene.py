"""What the simulated event puts in its pymunk Space besides the rigid scene of the first
impact: each vehicle's tyres (the run-out's one right-hand side) and the outlines that
collide after it, with the secondary-impact law's coefficients.

Tyres (:func:`event_tyres`): the analytic event's vehicles exactly
(:func:`pim.analysis.event.event_vehicle`: the case's evidence where it gives wheelbase,
track, axle position, braking and friction; otherwise wheelbase and track fixed fractions of
the outline, four locked wheels and the tyre friction ``tyre_friction`` if given, else the
evidence's, else :data:`pim.model.event.DEFAULT_TYRE_FRICTION`). The forces are those of
:class:`pim.model.runout.TimedRhs` (:mod:`pim.model.runout_formula`, the tyre law of
:mod:`pim.model.tyres`), applied at the CG with their yaw moment every step, as
:mod:`sim.runout_check` does.

Outlines (:func:`outline_shapes`): each vehicle's length x width rectangle as a pymunk
polygon (a fixed obstacle without dimensions: a straight face through C along the tangent),
elasticity eps_2 on vehicle 1 and 1 on vehicle 2 (Chipmunk multiplies them: Newton's
restitution eps_2 at the contact), friction mu_c and 1 (a Coulomb cap |P_t| <= mu_c P_n):
the friction-capped Brach law ("brach-capped") at beta = 1, which is what Chipmunk's polygon
contact does. Impact k's coefficients are the case's ``[[impacts]]`` entry for it
(:func:`pim.analysis.event.impact_spec`) or the analytic event's defaults
(:data:`pim.model.event_formula.SECONDARY_RESTITUTION`,
:data:`~pim.model.event_formula.SECONDARY_CONTACT_FRICTION`), set on the contact each step
(:func:`secondary_law`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

import pim
from pim.analysis.event import event_vehicle, impact_spec
from pim.model.event import DEFAULT_TYRE_FRICTION
from pim.model.event_formula import SECONDARY_CONTACT_FRICTION, SECONDARY_RESTITUTION
from pim.model.numbers import InputError
from pim.model.runout import RunoutVehicle, TimedRhs

from .contact_law import check_fraction, check_positive
from .scene import outline_corners

__all__ = ["SecondaryLaw", "EventTyres", "event_tyres", "outline_shapes", "secondary_law",
           "OUTLINE1", "OUTLINE2", "tyre_friction_source"]

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
        Coulomb cap mu_c [-] >= 0 on the impulse ratio |P_t| / P_n (inf: no cap, the
        contact sticks: Brach's law at beta = 1).
    """

    restitution: float = SECONDARY_RESTITUTION
    friction: float = SECONDARY_CONTACT_FRICTION

    def __post_init__(self):
        object.__setattr__(self, "restitution",
                           check_fraction(self.restitution, "secondary restitution"))
        if not (isinstance(self.friction, int | float) and self.friction == math.inf):
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
    if vehicle.fixed or friction == 0:
        return None
    ev = getattr(case.evidence, f"vehicle{index}", None) if case.evidence is not None else None
    runout = event_vehicle(vehicle, ev, friction, f"vehicle{index}")
    positions = runout.positions
    return EventTyres(runout, TimedRhs(runout), float(np.max(np.hypot(*positions.T))))


def secondary_law(case: pim.Case, k: int, override: SecondaryLaw | None = None
                  ) -> tuple[SecondaryLaw, str, str]:
    """The law pymunk's contact runs for the event's impact number ``k`` (2, 3, ...), its
    name and a note ("" when pymunk's contact is the law itself).

    ``override`` when given; else the case's ``[[impacts]]`` entry for it
    (:func:`pim.analysis.event.impact_spec`, the analytic event's defaults without one):
    its restitution and its cap (Brach's law: no cap, sticking). A beta below 1 or the
    Kudlich-Slibar law is not pymunk's contact: its restitution and cap are run, and said.
    """
    if override is not None:
        return override, "brach-capped", ""
    spec = impact_spec(case, k)
    eps = SECONDARY_RESTITUTION if spec.restitution is None else float(spec.restitution)
    cap = math.inf if spec.contact_friction is None else float(spec.contact_friction)
    note = ""
    if spec.law == "kudlich-slibar" or (spec.beta is not None and spec.beta < 1):
        note = (f"impact {k}'s law {spec.law} (beta {spec.beta}) is run as pymunk's contact "
                f"at restitution {eps:g} and friction cap {cap:g}")
    return SecondaryLaw(eps, cap), spec.law, note


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
        shape.friction = min(law.friction, 1e9) if first else 1.0
        shapes.append(shape)
    return shapes


def _barrier_face(case: pim.Case, body: pymunk.Body) -> pymunk.Segment:
    """A fixed obstacle without dimensions: a straight face through C along the tangent,
    100 m each way (in the static body's frame)."""
    point = np.asarray(case.impact.point, float).reshape(2)
    t = np.asarray(case.impact.tangent, float).reshape(2)
    local = [body.world_to_local(tuple(map(float, point + k * 100.0 * t))) for k in (-1, 1)]
    return pymunk.Segment(body, local[0], local[1], 0.0)
