"""Poses of the two vehicles at the animation's frame times: simulated and analytic (ghost).

Time 0 is PIM's impact instant (the case's configuration). Before it both vehicles move
freely with the case's velocities and yaw rates (no forces act; the simulation itself starts
one step before impact, so these frames are the same rigid motion for both). After it:

* simulated: the recorded pymunk trajectory (:class:`sim.Trajectory`), linearly interpolated
  between steps (exact for free motion, whose position is linear in time);
* analytic (ghost): free rigid motion from the impact configuration with PIM's post-impact
  velocities and yaw rates. With tyre friction the ghost decelerates like the simulator's
  model: speed falls by mu_t g per second along a fixed direction, the yaw rate by
  mu_t g d / k^2 (d the mean distance of a uniformly loaded footprint from the CG, k the
  radius of gyration), each stopping at zero.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import pim
from pim.analysis.event import impact_record
from pim.model.case import ImpactSpec
from pim.model.event import REST_SPEED, Event, ImpactRecord, Track, phase_labels
from pim.model.geometry import vehicle_outline
from pim.model.tyres import STANDARD_GRAVITY
from sim.scene import footprint_lever

__all__ = ["free_motion", "analytic_motion", "simulated_motion", "motion_event",
           "case_impact", "rest_time"]


def _vec(x) -> np.ndarray:
    return np.asarray(x, float).reshape(2)


def _decelerated(v0: np.ndarray, w0: float, t: np.ndarray, decel: float, yaw_decel: float):
    """Displacement, heading change, velocity after time t >= 0 under constant deceleration."""
    speed = float(np.hypot(*v0))
    if decel > 0 and speed > 0:
        stop = speed / decel
        tc = np.minimum(t, stop)
        dist = speed * tc - 0.5 * decel * tc * tc
        direction = v0 / speed
        disp = dist[:, None] * direction
        vel = np.maximum(speed - decel * t, 0.0)[:, None] * direction
    else:
        disp = t[:, None] * v0
        vel = np.broadcast_to(v0, (len(t), 2)).copy()
    if yaw_decel > 0 and w0 != 0:
        stop = abs(w0) / yaw_decel
        tc = np.minimum(t, stop)
        turn = np.sign(w0) * (abs(w0) * tc - 0.5 * yaw_decel * tc * tc)
    else:
        turn = w0 * t
    return disp, turn, vel


def free_motion(vehicle: pim.Vehicle, velocity, yaw_rate, time, tyre: float = 0.0,
                gravity: float = STANDARD_GRAVITY):
    """Pose of one vehicle moving from its case CG/heading at ``velocity`` and ``yaw_rate``.

    Negative times rewind (always free motion); positive times go forward, decelerated by
    tyre friction coefficient ``tyre`` [-] when > 0. Returns (position, angle, velocity).
    """
    time = np.asarray(time, float)
    cg, heading = _vec(vehicle.cg), float(vehicle.heading)
    v0, w0 = _vec(velocity), float(yaw_rate)
    if bool(vehicle.fixed):
        return (np.broadcast_to(cg, (len(time), 2)).copy(), np.full(len(time), heading),
                np.zeros((len(time), 2)))
    decel = tyre * gravity
    yaw_decel = 0.0
    if decel > 0:
        k2 = float(vehicle.yaw_inertia / vehicle.mass)
        yaw_decel = decel * footprint_lever(vehicle) / k2
    after = time > 0
    disp, turn, vel = _decelerated(v0, w0, np.where(after, time, 0.0), decel, yaw_decel)
    before = ~after
    disp[before] = time[before, None] * v0
    turn = np.where(before, w0 * time, turn)
    vel[before] = v0
    return cg + disp, heading + turn, vel


def motion_event(case: pim.Case, time, poses, source: str, *, tyre: float = 0.0,
                 impact: ImpactRecord | None = None) -> Event:
    """An :class:`pim.model.event.Event` of ``poses`` ((position, heading, velocity,
    yaw_rate) per vehicle) at ``time``, with the case's single impact at t = 0 (``impact``
    its record, if given) and the rest phase from :func:`rest_time` on. With tyre friction
    (``tyre`` > 0) every wheel slides after the impact while the vehicle moves (the sliding
    footprint of the simulator's tyre model and of the ghost's deceleration)."""
    time = np.asarray(time, float)
    tracks = []
    for (p, a, v, w), veh in zip(poses, (case.vehicle1, case.vehicle2), strict=True):
        track = Track(p, a, v, w, outline=vehicle_outline(veh), fixed=bool(veh.fixed))
        if tyre > 0:
            track = replace(track, sliding=np.repeat(((time > 0) & _moving(track))[:, None],
                                                     4, 1))
        tracks.append(track)
    rest = rest_time(time, tracks)
    return Event(time, tracks[0], tracks[1], phase_labels(time, [0.0], rest),
                 impacts=() if impact is None else (impact,), source=source,
                 stopped=(rest is not None,) * 2)


def _moving(track: Track) -> np.ndarray:
    """CG speed plus yaw rate times the outline's farthest corner from the CG at or above
    :data:`pim.model.event.REST_SPEED` (the run-out's stop test) at each sample."""
    reach = 2.5 if track.outline is None else float(np.hypot(*track.outline.T).max())
    return track.speed + np.abs(track.yaw_rate) * reach >= REST_SPEED


def rest_time(time, tracks) -> float | None:
    """The first time after the impact from which every track is at rest (None: never)."""
    time = np.asarray(time, float)
    moving = (time <= 0) | np.any([_moving(t) for t in tracks], axis=0)
    last = np.flatnonzero(moving)
    first = last[-1] + 1 if len(last) else 0
    return float(time[first]) if first < len(time) else None


def case_impact(case: pim.Case, result: pim.Result, impulse=None,
                source: str = "case") -> ImpactRecord:
    """The case's single impact at t = 0 as an :class:`pim.model.event.ImpactRecord`, from
    PIM's answer ``result`` (:func:`pim.analysis.event.impact_record`; ``impulse`` [N s] on
    vehicle 1: another producer's, e.g. the simulator's, for its event)."""
    record = impact_record(case, result, 0.0, ImpactSpec(law="brach"), source)
    if impulse is None:
        return record
    return replace(record, impulse=np.asarray(impulse, float).reshape(2))


def analytic_motion(case: pim.Case, result: pim.Result, time, tyre: float = 0.0,
                    gravity: float = STANDARD_GRAVITY) -> Event:
    """The ghost: pre-impact motion of the case, then PIM's post-impact motion (with its
    impact's record)."""
    time = np.asarray(time, float)
    out = []
    for vehicle, after, w_after in ((case.vehicle1, result.velocity1, result.yaw_rate1),
                                    (case.vehicle2, result.velocity2, result.yaw_rate2)):
        pre_p, pre_a, pre_v = free_motion(vehicle, vehicle.velocity, vehicle.yaw_rate, time)
        post_p, post_a, post_v = free_motion(vehicle, after, float(np.asarray(w_after)),
                                             time, tyre, gravity)
        b = time < 0
        w = np.where(b, float(np.asarray(vehicle.yaw_rate)), _yaw_rate(post_a, time, w_after))
        out.append((np.where(b[:, None], pre_p, post_p), np.where(b, pre_a, post_a),
                    np.where(b[:, None], pre_v, post_v), w))
    return motion_event(case, time, out, "pim", tyre=tyre, impact=case_impact(case, result))


def _yaw_rate(heading: np.ndarray, time: np.ndarray, w_after) -> np.ndarray:
    """Yaw rates along a decelerated heading: its slope (the post-impact value at t = 0)."""
    w = np.full(time.shape, float(np.asarray(w_after)))
    if len(time) > 1:
        slope = np.gradient(heading, time)
        w[1:] = slope[1:]
    return w


def simulated_motion(case: pim.Case, trajectory, time, *, tyre: float = 0.0,
                     impact: ImpactRecord | None = None) -> Event:
    """The simulated vehicles: the case's pre-impact motion, then the recorded trajectory
    (``tyre`` [-]: its tyre friction after the impact; ``impact``: the impact's record).

    Frames after the end of the recording hold its last state (vehicles at rest with tyre
    friction).
    """
    time = np.asarray(time, float)
    tr = trajectory
    t0 = float(tr.time[0])
    out = []
    for vehicle, pos, ang, vel, yaw in (
            (case.vehicle1, tr.position1, tr.angle1, tr.velocity1, tr.yaw_rate1),
            (case.vehicle2, tr.position2, tr.angle2, tr.velocity2, tr.yaw_rate2)):
        pre_p, pre_a, pre_v = free_motion(vehicle, vehicle.velocity, vehicle.yaw_rate, time)
        p = np.stack([np.interp(time, tr.time, pos[:, i]) for i in range(2)], -1)
        a = np.interp(time, tr.time, ang)
        # velocities are piecewise constant over a step: take the state at the step's end
        idx = np.clip(np.searchsorted(tr.time, time, side="left"), 0, len(tr.time) - 1)
        v, w = vel[idx], np.asarray(yaw, float)[idx]
        early = time < t0
        p[early], a[early], v[early] = pre_p[early], pre_a[early], pre_v[early]
        w[early] = float(np.asarray(vehicle.yaw_rate))
        out.append((p, a, v, w))
    return motion_event(case, time, out, "simulated", tyre=tyre, impact=impact)
