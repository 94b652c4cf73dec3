"""The analytic event against the simulated one: the difference at each impact and at rest
(the trajectory's part from :meth:`pim.model.event.Event.difference`), and the generated
side-slap scenes both are tested on.

Impacts are paired in time order (impact k of one event with impact k of the other); a
count that differs is reported (``EventCheck.impact_count``, and each impact of the longer
list without a partner in ``EventCheck.unmatched``), the pairs that exist compared: the
time [s], the distance between the two Cs [m], Gamma's difference [rad], each vehicle's
delta-V vector difference [m/s] and PDOF difference [rad] (angles wrapped to (-pi, pi]),
and each vehicle's state at its impact in either event: the CG distance [m], the heading
difference [rad] and the speed differences just before and just after [m/s].
:meth:`EventCheck.to_dict` gives it all in the user's units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import pim
from pim.io.units import convert, display_units
from pim.model.number_format import format_number
from pim.model.event import Event, EventDifference
from pim.model.pdof import wrap_angle

__all__ = ["ImpactDifference", "UnmatchedImpact", "EventCheck", "event_crosscheck",
           "side_slap_case", "SIDE_SLAPS", "AGREEMENT"]

#: The generated suite of side slaps: (offset [m] of C ahead of the struck car's CG,
#: restitution [-], beta [-]) of :func:`side_slap_case`; toward the front corner the struck
#: car's side slaps the bullet car's front twice more, toward the rear once.
SIDE_SLAPS = ((1.6, 0.1, 1.0), (1.6, 0.3, 0.5), (1.9, 0.1, 1.0), (1.9, 0.3, 0.5),
              (-1.6, 0.1, 1.0))
#: How closely the analytic and simulated events of the suite agree: each impact's time [s],
#: the delta-V difference relative to the impact's largest |delta-V| [-], the PDOF [rad], the
#: rest position [m] and heading [rad]. Measured on the suite: at pymunk's default 1 ms step
#: at most 1.1 ms, 1.4 %, 0.3 deg, 1 cm and 0.4 deg; against pymunk converged
#: (dt = 1e-4 s) one late slap differs by 4.9 ms and 3.6 % (the polygon contact's two
#: points against PIM's single point at the penetrating corner move the slap before it by
#: 2 %, and the run-out carries that on).
AGREEMENT = {"time": 0.006, "delta_v": 0.05, "pdof": float(np.radians(3.0)),
             "rest_position": 0.03, "rest_heading": float(np.radians(1.0))}


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
    times : ndarray (2,)
        The impact's time in ``a`` and in ``b`` [s].
    point : float
        Distance between the two impacts' C [m].
    normal_angle : float
        Gamma's difference [rad], wrapped to (-pi, pi].
    position : ndarray (2,)
        Distance between each vehicle's CG at its impact in ``a`` and in ``b`` [m].
    heading : ndarray (2,)
        Heading difference of each vehicle at the impact [rad] (continuous headings, not
        wrapped: a further turn is a difference).
    speed_before, speed_after : ndarray (2,)
        Each vehicle's CG speed difference just before and just after the impact [m/s].
    """

    index: int
    time: float
    delta_v: np.ndarray
    delta_v_scale: float
    pdof: np.ndarray
    times: np.ndarray
    point: float
    normal_angle: float
    position: np.ndarray
    heading: np.ndarray
    speed_before: np.ndarray
    speed_after: np.ndarray

    @property
    def delta_v_relative(self) -> float:
        """Largest delta-V difference over the largest |delta-V| [-]."""
        return float(np.max(self.delta_v) / max(self.delta_v_scale, 1e-12))


@dataclass(frozen=True)
class UnmatchedImpact:
    """An impact of one event beyond the other event's count (no partner to compare).

    Attributes
    ----------
    event : str
        The source of the event that has it (e.g. ``"simulated"``).
    index : int
        Its number k in that event, from 1.
    time : float
        Its time [s].
    """

    event: str
    index: int
    time: float


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
    unmatched : tuple of UnmatchedImpact
        The impacts of the event with more of them that have no partner (empty when both
        have as many).
    """

    impacts: tuple
    impact_count: tuple
    trajectory: EventDifference
    rest_speed: np.ndarray
    sources: tuple
    unmatched: tuple = ()

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

    def count_text(self) -> str:
        """The impact counts in words, naming the impacts without a partner."""
        (a, b), (na, nb) = self.sources, self.impact_count
        text = f"impacts found: {na} in the {a} event, {nb} in the {b} event"
        if self.same_impacts:
            return text + ", paired in time order"
        extra = ", ".join(f"impact {u.index} of the {u.event} event (t = "
                          f"{format_number(u.time, sig=3)} s)" for u in self.unmatched)
        return f"{text}: the counts differ; {extra} has no partner and is not compared"

    def to_dict(self, units="si") -> dict:
        """The differences for JSON in the display ``units`` (a system "si"/"us" or a
        :class:`pim.io.units.DisplayUnits`: speeds in its speed unit, lengths in its length
        unit, angles in degrees; times in s; relative delta-V unit-free), the units named
        under ``"units"``; ``a - b`` throughout."""
        shown = display_units(units) if isinstance(units, str) else units

        def conv(value, kind):
            return _plain(convert(np.asarray(value, float), kind, shown)[0])

        return {"units": shown.to_json(), "sources": list(self.sources),
                "impact_count": list(self.impact_count), "same_impacts": self.same_impacts,
                "counts": self.count_text(),
                "impacts": [_impact_dict(d, conv) for d in self.impacts],
                "unmatched": [{"event": u.event, "index": u.index, "time": u.time}
                              for u in self.unmatched],
                "rest_position": conv(self.rest_position, "length"),
                "rest_heading": conv(self.rest_heading, "angle"),
                "rest_speed": conv(self.rest_speed, "velocity"),
                "largest_position": conv(np.max(self.trajectory.position, initial=0.0),
                                         "length"),
                "largest_speed": conv(np.max(np.abs(self.trajectory.speed), axis=0,
                                             initial=0.0), "velocity")}


def _plain(values):
    """Floats (or lists of them) for JSON, NaN as None (a fixed obstacle's PDOF)."""
    values = np.asarray(values, float)
    if values.ndim == 0:
        return None if np.isnan(values) else float(values)
    return [_plain(v) for v in values]


def _impact_dict(d: ImpactDifference, conv) -> dict:
    """One pair of impacts for :meth:`EventCheck.to_dict` (``conv(value, kind)`` converts
    into the display units)."""
    return {"index": d.index, "times": [float(t) for t in d.times], "time": d.time,
            "C": conv(d.point, "length"), "Gamma": conv(d.normal_angle, "angle"),
            "delta_v": conv(d.delta_v, "velocity"), "delta_v_relative": d.delta_v_relative,
            "pdof": conv(d.pdof, "angle"), "position": conv(d.position, "length"),
            "heading": conv(d.heading, "angle"),
            "speed_before": conv(d.speed_before, "velocity"),
            "speed_after": conv(d.speed_after, "velocity")}


def _speeds(velocity) -> np.ndarray:
    v = np.asarray(velocity, float)
    return np.hypot(v[:, 0], v[:, 1])


def _impact_difference(k: int, pair: tuple, events: tuple) -> ImpactDifference:
    """Impact ``k`` of both events (``pair``: their records) compared; the states at the
    impacts read from ``events``."""
    a, b = pair
    d = a.delta_v - b.delta_v
    scale = float(max(np.max(a.delta_v_magnitude), np.max(b.delta_v_magnitude)))
    at = [e.at([i.time]) for e, i in zip(events, pair, strict=True)]
    position = np.array([np.hypot(*(ta.position[0] - tb.position[0]))
                         for ta, tb in zip(at[0].tracks, at[1].tracks, strict=True)])
    heading = np.array([ta.heading[0] - tb.heading[0]
                        for ta, tb in zip(at[0].tracks, at[1].tracks, strict=True)])
    return ImpactDifference(
        index=k, time=float(a.time - b.time), delta_v=np.hypot(d[:, 0], d[:, 1]),
        delta_v_scale=scale,
        pdof=wrap_angle(np.asarray(a.pdof, float) - np.asarray(b.pdof, float)),
        times=np.array([a.time, b.time], float),
        point=float(np.hypot(*(np.asarray(a.point, float) - np.asarray(b.point, float)))),
        normal_angle=float(wrap_angle(float(a.normal_angle) - float(b.normal_angle))),
        position=position, heading=heading,
        speed_before=_speeds(a.velocity_before) - _speeds(b.velocity_before),
        speed_after=_speeds(a.velocity_after) - _speeds(b.velocity_after))


def event_crosscheck(a: Event, b: Event) -> EventCheck:
    """``a`` against ``b`` (e.g. the analytic event against the simulated one): each
    impact's time, C, Gamma, delta-V, PDOF and the vehicles' states at it, the impacts
    without a partner, the trajectory and the rest (module notes)."""
    pairs = tuple(_impact_difference(k, pair, (a, b))
                  for k, pair in enumerate(zip(a.impacts, b.impacts, strict=False), start=1))
    n = len(pairs)
    unmatched = tuple(UnmatchedImpact(e.source, k, float(i.time)) for e in (a, b)
                      for k, i in enumerate(e.impacts[n:], start=n + 1))
    speeds = [np.array([t.speed[-1] for t in e.tracks]) for e in (a, b)]
    return EventCheck(impacts=pairs, impact_count=(len(a.impacts), len(b.impacts)),
                      trajectory=a.difference(b), rest_speed=speeds[0] - speeds[1],
                      sources=(a.source, b.source), unmatched=unmatched)


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
