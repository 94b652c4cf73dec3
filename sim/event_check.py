"""The analytic event against the simulated one: the difference at each impact and at rest
(the trajectory's part from :meth:`pim.model.event.Event.difference`), and the generated
side-slap scenes both are tested on.

Impacts are paired in time order (impact k of one event with impact k of the other); a
count that differs is reported (``EventCheck.impact_count``), the pairs that exist compared:
the time [s], each vehicle's delta-V vector difference [m/s] and PDOF difference [rad]
(wrapped to (-pi, pi]).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import pim
from pim.model.event import Event, EventDifference
from pim.model.pdof import wrap_angle

__all__ = ["ImpactDifference", "EventCheck", "event_crosscheck", "side_slap_case",
           "SIDE_SLAP_OFFSETS"]

#: Impact points along the struck car's side of the generated suite [m from its CG]: near
#: the front corner (the bullet car's front swings into the struck car's front again).
SIDE_SLAP_OFFSETS = (1.2, 1.6)


@dataclass(frozen=True)
class ImpactDifference:
    """Impact k of one event against impact k of another (``a - b``).

    Attributes
    ----------
    index : int
        k, from 1.
    time : float
        Time difference [s].
    delta_v : ndarray (2,)
        Magnitude of each vehicle's delta-V vector difference [m/s].
    delta_v_scale : float
        Largest |delta-V| of either vehicle in either impact [m/s] (for relative errors).
    pdof : ndarray (2,)
        PDOF difference of each vehicle [rad] (NaN for a fixed obstacle).
    """

    index: int
    time: float
    delta_v: np.ndarray
    delta_v_scale: float
    pdof: np.ndarray

    @property
    def delta_v_relative(self) -> float:
        """Largest delta-V difference over the largest |delta-V| [-]."""
        return float(np.max(self.delta_v) / max(self.delta_v_scale, 1e-12))


@dataclass(frozen=True, eq=False)
class EventCheck:
    """The cross-check of two events (``a`` against ``b``).

    Attributes
    ----------
    impacts : tuple of ImpactDifference
        The paired impacts.
    impact_count : tuple of int
        Number of impacts of ``a`` and of ``b``.
    trajectory : EventDifference
        :meth:`pim.model.event.Event.difference` at ``a``'s times within both.
    rest_speed : ndarray (2,)
        Difference of each vehicle's final speed [m/s].
    sources : tuple of str
        The events' sources.
    """

    impacts: tuple
    impact_count: tuple
    trajectory: EventDifference
    rest_speed: np.ndarray
    sources: tuple

    @property
    def same_impacts(self) -> bool:
        """Both events had the same number of impacts."""
        return self.impact_count[0] == self.impact_count[1]

    @property
    def rest_position(self) -> np.ndarray:
        """Distance between the rest positions of each vehicle [m] (2,)."""
        return self.trajectory.rest_position

    @property
    def rest_heading(self) -> np.ndarray:
        """Rest-heading difference of each vehicle [rad] (2,)."""
        return self.trajectory.rest_heading

    def to_dict(self) -> dict:
        """Plain SI values for JSON."""
        return {"sources": list(self.sources), "impact_count": list(self.impact_count),
                "impacts": [{"index": d.index, "time": d.time, "delta_v": d.delta_v.tolist(),
                             "delta_v_relative": d.delta_v_relative,
                             "pdof": d.pdof.tolist()} for d in self.impacts],
                "rest_position": self.rest_position.tolist(),
                "rest_heading": self.rest_heading.tolist(),
                "rest_speed": self.rest_speed.tolist(),
                "largest_position": float(np.max(self.trajectory.position, initial=0.0))}


def _impact_difference(k: int, a, b) -> ImpactDifference:
    d = a.delta_v - b.delta_v
    scale = float(max(np.max(a.delta_v_magnitude), np.max(b.delta_v_magnitude)))
    return ImpactDifference(index=k, time=float(a.time - b.time),
                            delta_v=np.hypot(d[:, 0], d[:, 1]), delta_v_scale=scale,
                            pdof=wrap_angle(np.asarray(a.pdof, float)
                                            - np.asarray(b.pdof, float)))


def event_crosscheck(a: Event, b: Event) -> EventCheck:
    """``a`` against ``b`` (e.g. the analytic event against the simulated one): each
    impact's time, delta-V and PDOF, the trajectory and the rest (module notes)."""
    pairs = tuple(_impact_difference(k, x, y)
                  for k, (x, y) in enumerate(zip(a.impacts, b.impacts), start=1))
    speeds = [np.array([t.speed[-1] for t in e.tracks]) for e in (a, b)]
    return EventCheck(impacts=pairs, impact_count=(len(a.impacts), len(b.impacts)),
                      trajectory=a.difference(b), rest_speed=speeds[0] - speeds[1],
                      sources=(a.source, b.source))


def side_slap_case(offset: float, *, speed1: float = 50 / 3.6, speed2: float = 10 / 3.6,
                   eps: float = 0.1, beta: float = 1.0) -> pim.Case:
    """A T-bone that slaps again: a 4.5 m x 1.8 m, 1400 kg car (vehicle 1, heading +y at
    ``speed1`` [m/s]) strikes the right side of the same car (vehicle 2, heading +x at
    ``speed2`` [m/s]) ``offset`` [m] ahead of its CG, the outlines touching at C (the
    middle of the bullet car's front; no overlap), normal -y; restitution ``eps`` and
    ``beta`` [-]. With the offset toward a corner, the struck car yaws and its side runs
    into the bullet car's front again (the issue's T-bone near a corner)."""
    length, width, mass = 4.5, 1.8, 1400.0
    inertia = mass * (0.3 * length) ** 2
    struck = pim.Vehicle(mass=mass, yaw_inertia=inertia, cg=[0.0, 0.0],
                         velocity=[speed2, 0.0], heading=0.0, length=length, width=width)
    bullet = pim.Vehicle(mass=mass, yaw_inertia=inertia, cg=[offset, -(width + length) / 2],
                         velocity=[0.0, speed1], heading=np.pi / 2, length=length, width=width)
    impact = pim.Impact(point=[offset, -width / 2], normal_angle=-np.pi / 2, restitution=eps,
                        beta=beta)
    return pim.Case(bullet, struck, impact, name=f"side-slap {offset:g} m")
