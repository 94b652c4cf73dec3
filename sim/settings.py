"""Numerical settings and physics switches of the pymunk cross-check.

The defaults recreate exactly what PIM assumes (one contact point at C, normal at Gamma,
placed at the impact configuration, no tyre forces) at the cheapest step size and solver
iteration count that still reproduces :func:`pim.solve` to relative 1e-6; the figures
behind that choice are printed by ``benchmarks/bench_sim.py`` and recorded in docs/sim.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from pim.model.numbers import InputError
from pim.model.tyres import STANDARD_GRAVITY

__all__ = ["Settings", "DEFAULT_TYRE_FRICTION", "CONTACTS", "STARTS"]

#: Tyre/ground friction coefficient [-] used when ``tyre_friction=True``.
DEFAULT_TYRE_FRICTION = 0.7

CONTACTS = ("point", "outline")
STARTS = ("exact", "detected")


@dataclass(frozen=True)
class Settings:
    """How :func:`sim.simulate` steps the scene.

    Parameters
    ----------
    dt : float
        Fixed time step [s], in (0, 1]. With ``start="exact"`` the impulse is applied in one
        step at the impact configuration, so dt only sets the resolution of the recorded
        trajectory; with ``start="detected"`` the lever-arm error grows about linearly in dt.
    iterations : int or None
        Solver iterations per step (Chipmunk's sequential-impulse sweeps), in [1, 100000].
        None (default): chosen per scene from the predicted convergence rate of the contact
        (:func:`sim.convergence.auto_iterations`; 20 to 20000 sweeps, ~0.02 us each).
    contact : {"point", "outline"}
        "point": a small circle at C on vehicle 1 against a segment along the tangent
        through C on vehicle 2 -- exactly one contact point with normal n (PIM's
        assumption). "outline": the length x width rectangles collide (a contact patch of
        up to two points where the engine finds them); needs length and width of both
        vehicles (an obstacle without them becomes a straight barrier face through C).
    start : {"exact", "detected"}
        "exact": the bodies start one step before the impact configuration, so that the
        contact is processed with PIM's lever arms (the contact point is pinned to C).
        "detected": the bodies start ``lead_steps`` steps before it, apart, and the engine
        finds the contact itself (a fraction of a step late, with its own contact point).
    tyre_friction : bool or float
        Post-impact tyre/ground friction so that the vehicles come to rest (animations
        only; never during the impact). False: off. True: coefficient 0.7. A number: the
        coefficient [-] (deceleration = coefficient x g), >= 0.
    duration : float
        Extra simulated time after separation [s], >= 0, recorded for animations; 0 stops
        at separation. With tyre friction the run also stops once both vehicles rest.
    record : bool
        Store the state after every step in the trajectory; otherwise only the start, the
        impact and the final state are kept.
    max_contact_time : float
        Longest contact accepted [s], > 0; a contact still pushing after it is reported as
        "never_separated".
    lead_steps : float
        With ``start="detected"``: how many steps [-] before the impact instant the bodies
        start, > 1. A fractional part makes the engine find the contact part-way into a
        step, as it would in practice.
    contact_radius : float
        Radius [m] of the contact circle of the point contact, > 0. The engine misses the
        contact (tunnelling) when the approach speed x dt exceeds about twice this.
    max_contact_points : int or None
        Most contact points allowed in one step; more is reported as "multiple_contacts".
        None: 1 for the point contact, unlimited for the outlines (set 1 there to insist on
        PIM's single point).
    convergence_tolerance : float or None
        Largest residual [-] of the contact law after a contact step, relative to the speed
        scale of the scene (Newton restitution at the contact point; zero tangential
        velocity when sticking, friction opposing the sliding when sliding), checked for a
        point contact; more is reported as "not_converged". None: no check.
    energy_tolerance : float
        Kinetic energy may rise by this fraction [-] of its initial value (solver round-off)
        before the run is reported as "energy_gained"; >= 0.
    gravity : float
        g [m/s^2] for the tyre friction deceleration, > 0.
    """

    dt: float = 1e-3
    iterations: int | None = None
    contact: str = "point"
    start: str = "exact"
    tyre_friction: bool | float = False
    duration: float = 0.0
    record: bool = False
    max_contact_time: float = 0.25
    lead_steps: float = 2.5
    contact_radius: float = 0.05
    max_contact_points: int | None = None
    convergence_tolerance: float | None = 1e-8
    energy_tolerance: float = 1e-6
    gravity: float = STANDARD_GRAVITY

    def __post_init__(self) -> None:
        def number(name, low, high, low_open=False, high_open=False):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise InputError(f"settings.{name} must be a number, got {value!r}")
            value = float(value)
            ok = math.isfinite(value) or (high == math.inf and value == math.inf and not high_open)
            ok = ok and (value > low if low_open else value >= low)
            ok = ok and (value < high if high_open else value <= high)
            if not ok:
                lo = "(" if low_open else "["
                hi = ")" if high_open else "]"
                raise InputError(f"settings.{name} must be in {lo}{low:g}, {high:g}{hi}, "
                                 f"got {value!r}")
            object.__setattr__(self, name, value)

        number("dt", 0.0, 1.0, low_open=True)
        its = self.iterations
        if its is not None:
            if isinstance(its, bool) or not isinstance(its, int | float) or int(its) != its \
                    or not 1 <= int(its) <= 100_000:
                raise InputError(f"settings.iterations must be None (automatic) or an integer "
                                 f"in [1, 100000], got {its!r}")
            object.__setattr__(self, "iterations", int(its))
        if self.contact not in CONTACTS:
            raise InputError(f"settings.contact must be one of {CONTACTS}, got {self.contact!r}")
        if self.start not in STARTS:
            raise InputError(f"settings.start must be one of {STARTS}, got {self.start!r}")
        tyre = self.tyre_friction
        if not isinstance(tyre, bool):
            if not isinstance(tyre, int | float) or not (math.isfinite(tyre) and tyre >= 0):
                raise InputError(f"settings.tyre_friction must be True/False or a coefficient "
                                 f">= 0, got {tyre!r}")
            object.__setattr__(self, "tyre_friction", float(tyre))
        number("duration", 0.0, 1e6)
        if not isinstance(self.record, bool):
            raise InputError(f"settings.record must be True or False, got {self.record!r}")
        number("max_contact_time", 0.0, 1e6, low_open=True)
        number("lead_steps", 1.0, 1e6, low_open=True)
        number("contact_radius", 0.0, 1e3, low_open=True)
        points = self.max_contact_points
        if points is not None:
            if isinstance(points, bool) or int(points) != points or points < 1:
                raise InputError(f"settings.max_contact_points must be None or an integer "
                                 f">= 1, got {points!r}")
            object.__setattr__(self, "max_contact_points", int(points))
        if self.convergence_tolerance is not None:
            number("convergence_tolerance", 0.0, 1.0, low_open=True)
        number("energy_tolerance", 0.0, 1.0)
        number("gravity", 0.0, 1e3, low_open=True)

    @property
    def tyre_coefficient(self) -> float:
        """Tyre/ground friction coefficient [-] in use (0 when off)."""
        if self.tyre_friction is True:
            return DEFAULT_TYRE_FRICTION
        if self.tyre_friction is False:
            return 0.0
        return float(self.tyre_friction)

    @property
    def points_allowed(self) -> int | None:
        """Contact points allowed per step (None: unlimited)."""
        if self.max_contact_points is not None:
            return self.max_contact_points
        return 1 if self.contact == "point" else None

    def as_dict(self) -> dict:
        """The settings as plain values (for JSON)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}
