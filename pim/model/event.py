"""The event: one typed timeline of both vehicles, from the approach to rest.

Every producer of motion returns an :class:`Event` (the analytic event, the pymunk event,
PIM's single impact with its post-impact free motion or run-out, a reconstruction's fitted
run-outs) and every consumer reads one (the animation, the plan view, tables, JSON, the
cross-check). What differs between producers is how the motion was computed, never what is
returned, so comparing two events is a subtraction (:meth:`Event.difference`); a renderer
never asks where the data came from (python-control's ``TimeResponseData``, poliastro's one
ephemeris type for any propagator).

Layout (SI, global frame, angles counter-clockwise from +x):

- :attr:`Event.time` (N,) [s], increasing; 0 is the first impact (PIM's instant);
- :attr:`Event.vehicle1`, :attr:`Event.vehicle2`: a :class:`Track` each, the CG position
  (N, 2) [m], heading (N,) [rad] (integrated continuously, not wrapped), CG velocity (N, 2)
  [m/s], yaw rate (N,) [rad/s] and, where the producer models tyres, each wheel's sliding
  flag (N, 4) (front-left, front-right, rear-left, rear-right);
- :attr:`Event.phase` (N,): the phase of each sample, one of ``"approach"``, ``"impact k"``
  (the sample just after the k-th impact's impulse, k from 1), ``"free"`` (free motion or
  run-out between and after impacts) and ``"rest"`` (both vehicles at rest);
- :attr:`Event.impacts`: an :class:`ImpactRecord` per impact, in time order: time, C,
  Gamma, law and coefficients, impulse, each vehicle's delta-V and PDOF, energy lost.

A sample's state holds on the interval up to the next sample: positions and headings
interpolate linearly between samples (:meth:`Event.at`); velocities jump at an impact, which
has two samples at the same time (before and after), so interpolation never smears an
impulse over a step.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .geometry import rotate
from .numbers import InputError

__all__ = ["Track", "ImpactRecord", "Event", "EventDifference", "PHASES", "impact_phase",
           "phase_labels", "DEFAULT_TYRE_FRICTION", "DEFAULT_APPROACH", "REST_SPEED"]

#: Tyre-road friction of an event's run-out where the case gives none [-]: a dry asphalt
#: road's sliding friction, the middle of the 0.6-0.8 range of the reconstruction literature
#: (docs/references.md: Fricke, Traffic Accident Reconstruction, 1990).
DEFAULT_TYRE_FRICTION = 0.7
#: How long before the first impact an event starts by default [s].
DEFAULT_APPROACH = 1.0
#: Below this CG speed plus yaw rate x largest tyre arm a vehicle counts as at rest [m/s]
#: (the run-out's stop test, :mod:`pim.model.runout`).
REST_SPEED = 0.05

#: The phases a sample may be in (``"impact k"`` is written with its number).
PHASES = ("approach", "impact", "free", "rest")


def impact_phase(k: int) -> str:
    """The phase label of the sample after the k-th impact (k from 1): ``"impact k"``."""
    return f"impact {int(k)}"


def _shape(value) -> tuple:
    """``value``'s shape (an array's read directly, without numpy's conversion)."""
    return value.shape if isinstance(value, np.ndarray) else np.shape(value)


#: The per-sample fields of a :class:`Track` and their width (None: one number a sample).
_TRACK_SHAPES = (("position", 2), ("heading", None), ("velocity", 2), ("yaw_rate", None),
                 ("sliding", 4))


@dataclass(frozen=True, eq=False)
class Track:
    """One vehicle's motion over an event's samples (SI, global frame).

    Attributes
    ----------
    position : ndarray (N, 2)
        CG position [m].
    heading : ndarray (N,)
        Heading of the vehicle's x axis from global +x, counter-clockwise [rad], integrated
        continuously (not wrapped to +-pi).
    velocity : ndarray (N, 2)
        CG velocity [m/s].
    yaw_rate : ndarray (N,)
        Yaw rate, counter-clockwise positive [rad/s].
    sliding : ndarray of bool (N, 4) or None
        Each wheel sliding (tyre marks): front-left, front-right, rear-left, rear-right;
        None where the producer models no tyres.
    outline : ndarray (4, 2) or None
        Corners of the outline in the body frame [m] (x forward from the CG), None without
        dimensions.
    fixed : bool
        A fixed obstacle (never moves).
    wheels : ndarray (4, 2) or None
        The tyres' contact points in the body frame [m] (front-left, front-right, rear-left,
        rear-right, :func:`pim.model.tyres.wheel_positions`), where the tyre marks of
        ``sliding`` are drawn; None where the producer knows no axles.
    """

    position: np.ndarray
    heading: np.ndarray
    velocity: np.ndarray
    yaw_rate: np.ndarray
    sliding: np.ndarray | None = None
    outline: np.ndarray | None = None
    fixed: bool = False
    wheels: np.ndarray | None = None

    def __post_init__(self):
        heading = _shape(self.heading)
        n = heading[0] if heading else None
        for name, width in _TRACK_SHAPES:
            value = getattr(self, name)
            if value is None and name == "sliding":
                continue
            expected, shape = (n,) if width is None else (n, width), _shape(value)
            if n is None or shape != expected:
                raise InputError(f"Track.{name} must have shape {expected} (N samples), got "
                                 f"{shape}")

    def __len__(self) -> int:
        return len(self.heading)

    @property
    def speed(self) -> np.ndarray:
        """CG speed [m/s] (N,)."""
        return np.hypot(self.velocity[:, 0], self.velocity[:, 1])

    def take(self, index) -> Track:
        """The samples ``index`` (a slice, mask or index array)."""
        return replace(self, position=self.position[index], heading=self.heading[index],
                       velocity=self.velocity[index], yaw_rate=self.yaw_rate[index],
                       sliding=None if self.sliding is None else self.sliding[index])

    def corners(self) -> np.ndarray | None:
        """The outline's corners in the global frame [m] (N, 4, 2), or None."""
        return None if self.outline is None else self.placed(self.outline)

    def wheel_points(self) -> np.ndarray | None:
        """The wheels' contact points in the global frame [m] (N, 4, 2), or None without
        :attr:`wheels`."""
        return None if self.wheels is None else self.placed(self.wheels)

    def placed(self, body) -> np.ndarray:
        """Body-frame points ``body`` (K, 2) [m] in the global frame at every sample
        (N, K, 2) [m]."""
        body = np.asarray(body, float)[None]
        return self.position[:, None, :] + rotate(body, self.heading[:, None])

    @classmethod
    def concatenate(cls, tracks) -> Track:
        """Tracks of consecutive pieces of one vehicle's motion joined in order."""
        tracks = list(tracks)
        first = tracks[0]
        slid = [t.sliding for t in tracks]
        sliding = None
        if any(s is not None for s in slid):
            sliding = np.concatenate([np.zeros((len(t), 4), bool) if s is None else s
                                      for t, s in zip(tracks, slid, strict=True)])
        return replace(first, **{name: np.concatenate([getattr(t, name) for t in tracks])
                                 for name in ("position", "heading", "velocity",
                                              "yaw_rate")}, sliding=sliding)


@dataclass(frozen=True, eq=False)
class ImpactRecord:
    """One impact of an event: where, when, under which law, and what it did (SI).

    Attributes
    ----------
    time : float
        Time of the impact [s] (0 for the first).
    point : ndarray (2,)
        Impact point C [m], global frame.
    normal_angle : float
        Gamma: the angle of the contact plane's normal n from global +x [rad].
    law : str
        Impact law (:data:`pim.LAW_NAMES`).
    coefficients : dict
        The law's coefficients by name (e.g. ``{"eps": 0.3, "beta": 1.0}``) [-].
    impulse : ndarray (2,)
        Impulse on vehicle 1 [N s] (vehicle 2 receives its negative).
    velocity_before, velocity_after : ndarray (2, 2)
        Both vehicles' CG velocities just before and after [m/s] (row i: vehicle i + 1).
    yaw_rate_before, yaw_rate_after : ndarray (2,)
        Both vehicles' yaw rates just before and after [rad/s].
    energy_loss : float
        Kinetic energy lost in the impact [J] (>= 0 for an admissible impact).
    pdof : ndarray (2,)
        Each vehicle's principal direction of force, from its heading, counter-clockwise
        [rad] (NaN for a fixed obstacle).
    source : str
        Who found it: ``"case"`` (the case's first impact), ``"outlines"`` (a contact found
        by the analytic event's outline watch), ``"simulation"`` (the engine's contact).
    """

    time: float
    point: np.ndarray
    normal_angle: float
    law: str
    coefficients: dict
    impulse: np.ndarray
    velocity_before: np.ndarray
    velocity_after: np.ndarray
    yaw_rate_before: np.ndarray
    yaw_rate_after: np.ndarray
    energy_loss: float
    pdof: np.ndarray
    source: str = "case"

    @property
    def delta_v(self) -> np.ndarray:
        """Each vehicle's CG velocity change [m/s] (2, 2) (row i: vehicle i + 1)."""
        return np.asarray(self.velocity_after, float) - np.asarray(self.velocity_before, float)

    @property
    def delta_v_magnitude(self) -> np.ndarray:
        """|delta-V| of each vehicle [m/s] (2,)."""
        d = self.delta_v
        return np.hypot(d[:, 0], d[:, 1])

    def to_dict(self) -> dict:
        """Plain SI values (lists and floats) for JSON."""
        return {"time": float(self.time), "point": [float(v) for v in self.point],
                "normal_angle": float(self.normal_angle), "law": self.law,
                "coefficients": {k: float(v) for k, v in self.coefficients.items()},
                "impulse": [float(v) for v in self.impulse],
                "delta_v": self.delta_v.tolist(),
                "delta_v_magnitude": self.delta_v_magnitude.tolist(),
                "pdof": [float(v) for v in self.pdof],
                "energy_loss": float(self.energy_loss), "source": self.source}


def phase_labels(time, impact_times, rest_time=None) -> np.ndarray:
    """Phases of samples at ``time`` [s] (N,): ``"approach"`` before the first impact,
    ``"impact k"`` at the first sample at or after the k-th impact time, ``"free"`` after
    it and ``"rest"`` from ``rest_time`` on (None: never at rest)."""
    time = np.asarray(time, float)
    out = np.full(time.shape, "free", dtype="<U10")
    if len(impact_times):
        out[time < impact_times[0]] = "approach"
    else:
        out[:] = "approach"
    # the first sample at or after each impact time; two samples may share it (before,
    # after): the later one is after, the last of the samples at that time
    first = np.searchsorted(time, impact_times, side="left").tolist()
    last = np.searchsorted(time, impact_times, side="right").tolist()
    for k, (at, end) in enumerate(zip(first, last), start=1):
        if at < len(time):
            out[end - 1 if end > at else at] = impact_phase(k)
    if rest_time is not None:
        out[time >= rest_time] = "rest"
    return out


@dataclass(frozen=True, eq=False)
class EventDifference:
    """One event minus another at common times (the cross-check).

    Attributes
    ----------
    time : ndarray (M,)
        The times compared [s].
    position : ndarray (M, 2)
        Largest CG distance of the two vehicles [m] at each time.
    heading : ndarray (M, 2)
        Heading difference of each vehicle [rad], ``self - other``.
    speed : ndarray (M, 2)
        Speed difference of each vehicle [m/s], ``self - other``.
    rest_position : ndarray (2,)
        Distance between the rest positions of each vehicle [m].
    rest_heading : ndarray (2,)
        Rest-heading difference of each vehicle [rad].
    impacts : int
        Number of impacts of ``self`` minus that of ``other``.
    """

    time: np.ndarray
    position: np.ndarray
    heading: np.ndarray
    speed: np.ndarray
    rest_position: np.ndarray
    rest_heading: np.ndarray
    impacts: int


@dataclass(frozen=True, eq=False)
class Event:
    """Both vehicles from the approach to rest, with every impact (SI, global frame).

    Attributes
    ----------
    time : ndarray (N,)
        Sample times [s], non-decreasing (an impact's before and after states share a
        time); 0 is the first impact.
    vehicle1, vehicle2 : Track
        Each vehicle's motion at the sample times.
    phase : ndarray of str (N,)
        ``"approach"``, ``"impact k"``, ``"free"`` or ``"rest"`` (:func:`phase_labels`).
    impacts : tuple of ImpactRecord
        Every impact, in time order.
    source : str
        What produced it (``"analytic"``, ``"simulated"``, ``"pim"`` ...), for labels.
    stopped : tuple of bool
        Whether each vehicle came to rest within the event (False: still moving at its
        end, e.g. free motion without tyres).
    notes : tuple of str
        Plain-language remarks of the producer (a time limit reached, a contact left
        unsolved ...).
    """

    time: np.ndarray
    vehicle1: Track
    vehicle2: Track
    phase: np.ndarray
    impacts: tuple = ()
    source: str = ""
    stopped: tuple = (False, False)
    notes: tuple = field(default_factory=tuple)

    def __post_init__(self):
        time = np.asarray(self.time, float)
        if time.ndim != 1 or len(time) < 1 or (time[1:] < time[:-1]).any():
            raise InputError("Event.time must be a non-empty, non-decreasing 1-D array [s]")
        for name in ("vehicle1", "vehicle2"):
            if len(getattr(self, name)) != len(time):
                raise InputError(f"Event.{name} has {len(getattr(self, name))} samples, "
                                 f"time has {len(time)}")
        if np.shape(self.phase) != time.shape:
            raise InputError(f"Event.phase must have shape {time.shape}")

    def __len__(self) -> int:
        return len(self.time)

    def __repr__(self) -> str:
        return (f"Event({self.source or 'event'}: {len(self.impacts)} impact(s), "
                f"{self.time[0]:.3g} to {self.time[-1]:.3g} s, {len(self)} samples)")

    @property
    def tracks(self) -> tuple[Track, Track]:
        """``(vehicle1, vehicle2)``."""
        return self.vehicle1, self.vehicle2

    @property
    def approach_duration(self) -> float:
        """Time from the start of the event to the first impact [s] (0 without impacts
        before the first sample)."""
        return float(max(-self.time[0], 0.0))

    @property
    def end_time(self) -> float:
        """Time of the last sample [s]."""
        return float(self.time[-1])

    @property
    def rest_position(self) -> np.ndarray:
        """Each vehicle's CG at the end of the event [m] (2, 2) (row i: vehicle i + 1)."""
        return np.stack([self.vehicle1.position[-1], self.vehicle2.position[-1]])

    @property
    def rest_heading(self) -> np.ndarray:
        """Each vehicle's heading at the end of the event [rad] (2,)."""
        return np.array([self.vehicle1.heading[-1], self.vehicle2.heading[-1]])

    def at(self, times) -> Event:
        """The event resampled at ``times`` [s] (M,), e.g. an animation's frame times.

        Positions, headings and sliding flags interpolate linearly (flags: the earlier
        sample's); velocities and yaw rates take the state in force (the sample at or just
        after the time, so the post-impact state from the impact's time on). Times before
        the first sample hold the first state moved back along its velocity and yaw rate
        (free motion); times after the last hold the last state.
        """
        times = np.asarray(times, float)
        src = self.time
        after = np.clip(np.searchsorted(src, times, side="right"), 1, len(src)) - 1
        tracks = [self._track_at(tr, times, after) for tr in self.tracks]
        rest = self.phase == "rest"
        rest_time = float(src[rest][0]) if rest.any() else None
        phase = phase_labels(times, [i.time for i in self.impacts], rest_time)
        return replace(self, time=times, vehicle1=tracks[0], vehicle2=tracks[1], phase=phase)

    def _track_at(self, track: Track, times: np.ndarray, after: np.ndarray) -> Track:
        """One track at ``times`` (see :meth:`at`)."""
        src = self.time
        # interpolate within the segment each time falls into; the last of equal times wins
        pos = np.stack([np.interp(times, src, track.position[:, i]) for i in range(2)], -1)
        head = np.interp(times, src, track.heading)
        state = np.clip(np.searchsorted(src, times, side="left"), 0, len(src) - 1)
        same = (state + 1 < len(src)) & (src[np.minimum(state + 1, len(src) - 1)] == times)
        state = np.where(same, state + 1, state)
        vel, yaw = track.velocity[state], track.yaw_rate[state]
        early = times < src[0]
        if early.any():
            dt = times[early] - src[0]
            pos[early] = track.position[0] + dt[:, None] * track.velocity[0]
            head[early] = track.heading[0] + dt * track.yaw_rate[0]
        sliding = None if track.sliding is None else track.sliding[after]
        return replace(track, position=pos, heading=head, velocity=vel, yaw_rate=yaw,
                       sliding=sliding)

    def difference(self, other: Event, times=None) -> EventDifference:
        """``self - other`` at ``times`` (default: ``self``'s distinct times within both)."""
        if times is None:
            lo, hi = max(self.time[0], other.time[0]), min(self.time[-1], other.time[-1])
            times = np.unique(self.time[(self.time >= lo) & (self.time <= hi)])
        a, b = self.at(times), other.at(times)
        dist = np.stack([np.hypot(*(ta.position - tb.position).T)
                         for ta, tb in zip(a.tracks, b.tracks, strict=True)], -1)
        head = np.stack([ta.heading - tb.heading
                         for ta, tb in zip(a.tracks, b.tracks, strict=True)], -1)
        speed = np.stack([ta.speed - tb.speed for ta, tb in zip(a.tracks, b.tracks,
                                                                  strict=True)], -1)
        return EventDifference(
            time=np.asarray(times, float), position=dist, heading=head, speed=speed,
            rest_position=np.hypot(*(self.rest_position - other.rest_position).T),
            rest_heading=self.rest_heading - other.rest_heading,
            impacts=len(self.impacts) - len(other.impacts))

    def records(self) -> list[dict]:
        """One row per sample (SI), for ``timeline.csv`` and tables: time, phase, and each
        vehicle's x, y, heading, vx, vy, yaw rate."""
        rows = []
        for k in range(len(self)):
            row = {"time": float(self.time[k]), "phase": str(self.phase[k])}
            for i, tr in enumerate(self.tracks, start=1):
                row.update({f"x{i}": float(tr.position[k, 0]),
                            f"y{i}": float(tr.position[k, 1]),
                            f"heading{i}": float(tr.heading[k]),
                            f"vx{i}": float(tr.velocity[k, 0]),
                            f"vy{i}": float(tr.velocity[k, 1]),
                            f"yaw_rate{i}": float(tr.yaw_rate[k])})
            rows.append(row)
        return rows

    def to_dict(self) -> dict:
        """The event's summary (SI) for JSON: impacts, rest, approach duration."""
        return {"source": self.source,
                "approach_duration": self.approach_duration,
                "end_time": self.end_time,
                "impacts": [i.to_dict() for i in self.impacts],
                "rest": [{"position": self.rest_position[i].tolist(),
                          "heading": float(self.rest_heading[i]),
                          "stopped": bool(self.stopped[i])} for i in range(2)],
                "notes": list(self.notes)}

    @classmethod
    def join(cls, pieces, **fields) -> Event:
        """Consecutive events (approach, impact, run-out ...) joined into one; the pieces'
        impacts kept in order. ``fields`` override the result's (``source``, ``stopped``,
        ``notes``, ``phase``)."""
        pieces = list(pieces)
        time = np.concatenate([p.time for p in pieces])
        tracks = [Track.concatenate([getattr(p, n) for p in pieces])
                  for n in ("vehicle1", "vehicle2")]
        phase = np.concatenate([p.phase for p in pieces])
        impacts = tuple(i for p in pieces for i in p.impacts)
        base = dict(time=time, vehicle1=tracks[0], vehicle2=tracks[1], phase=phase,
                    impacts=impacts, source=pieces[-1].source, stopped=pieces[-1].stopped,
                    notes=tuple(n for p in pieces for n in p.notes))
        base.update(fields)
        return cls(**base)
