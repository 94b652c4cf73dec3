"""Reconstruction through the event: post-impact motion fitted to rest positions reached after
further impacts.

The single-impact run-out inverse (:func:`pim.analysis.runout_fit.fit_runout`) carries each
vehicle from its separation state to rest on its own: where that motion runs the two outlines
into each other again, the rest positions it fits were reached through a sequence of impacts
that it ignores, and the speeds it returns are those of vehicles that passed through each
other. :func:`fit_through_event` fits both vehicles' post-impact velocities and yaw rates
(six unknowns; three with a fixed obstacle) so that the EVENT's rest states
(:func:`pim.analysis.event.event_rest_many`: the run-outs with the outline watch and every
further impact) match the measured ones, residuals in standard deviations as the run-out
inverse's. The fit runs on the project's one least-squares engine
(:func:`pim.analysis.least_squares_batch.least_squares_batch`), its Jacobian by forward
differences computed in one call of the compiled, parallel event kernel; several starts
(the single-impact fit and the stated perturbations of it) are solved together and merged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.case import Case
from ..model.numbers import InputError
from .event import event_rest_many
from .least_squares_batch import least_squares_batch, with_forward_differences

__all__ = ["EventFit", "fit_through_event", "event_residuals", "START_SCALES"]

#: The starts of :func:`fit_through_event`: the single-impact fit's speeds scaled by these
#: factors (its directions and yaw rates kept), solved together and merged.
START_SCALES = (1.0, 0.8, 1.25, 0.6, 1.5)


@dataclass(frozen=True)
class EventFit:
    """Post-impact motion fitted through the event (SI).

    Attributes
    ----------
    velocity : ndarray (2, 2)
        Each vehicle's post-impact CG velocity [m/s] (row i: vehicle i + 1).
    yaw_rate : ndarray (2,)
        Their yaw rates [rad/s].
    cost : float
        Sum of squared residuals (in standard deviations) at the fit.
    impacts : int
        Further impacts of the fitted event.
    first_time : float
        Time of the first further impact [s] (NaN without).
    converged : bool
    starts_agreeing : int
        How many of the starts ended at the best fit (within 1e-6 of its cost + 1e-9).
    starts : int
        How many starts were solved.
    """

    velocity: np.ndarray
    yaw_rate: np.ndarray
    cost: float
    impacts: int
    first_time: float
    converged: bool
    starts_agreeing: int
    starts: int


def _targets(case: Case) -> list:
    """(vehicle index, rest position, rest heading, position sigma, heading sigma) of each
    vehicle with evidence."""
    ev = case.evidence
    out = []
    for i in (1, 2):
        e = None if ev is None else getattr(ev, f"vehicle{i}")
        if e is not None:
            out.append((i - 1, np.asarray(e.rest_position, float), float(e.rest_heading),
                        float(e.position_sigma), float(e.heading_sigma)))
    return out


def event_residuals(case: Case, x: np.ndarray, *, tyre_friction=None) -> np.ndarray:
    """Residuals (..., 3 per vehicle with evidence) of post-impact motions ``x`` (..., 6):
    (v1x, v1y, w1, v2x, v2y, w2) [m/s, rad/s], the event's rest position and heading minus
    the evidence's, in its standard deviations; NaN where the event did not end at rest."""
    x = np.asarray(x, float)
    flat = x.reshape(-1, 6)
    velocity = np.stack([flat[:, 0:2], flat[:, 3:5]], axis=1)
    rest = event_rest_many(case, velocity, flat[:, [2, 5]], tyre_friction=tyre_friction)
    cols = []
    for v, position, heading, sp, sh in _targets(case):
        cols += [(rest.rest_position[:, v, 0] - position[0]) / sp,
                 (rest.rest_position[:, v, 1] - position[1]) / sp,
                 (rest.rest_heading[:, v] - heading) / sh]
    r = np.stack(cols, axis=-1)
    r[~(rest.ok & rest.stopped.all(axis=1))] = np.nan
    return r.reshape(x.shape[:-1] + (r.shape[-1],))


def fit_through_event(case: Case, velocity, yaw_rate, *, speed_bound: float = 60.0,
                      yaw_rate_bound: float = 15.0, tyre_friction=None) -> EventFit:
    """Both vehicles' post-impact motion whose event ends at the measured rest states.

    Parameters
    ----------
    case : Case
        Its impact configuration and outlines, and ``[evidence]`` for both vehicles (or for
        vehicle 1 against a fixed obstacle): rest positions, headings, sigmas, tyres.
    velocity : array_like (2, 2)
        The starting post-impact velocities [m/s] (the single-impact run-out fits).
    yaw_rate : array_like (2,)
        Their yaw rates [rad/s].
    speed_bound, yaw_rate_bound : float
        Each velocity component within +- ``speed_bound`` [m/s], each yaw rate within
        +- ``yaw_rate_bound`` [rad/s].
    tyre_friction : float, optional
        As :func:`pim.event` (default the evidence's).

    Returns
    -------
    EventFit
    """
    fixed = bool(case.vehicle2.fixed)
    targets = _targets(case)
    if len(targets) < (1 if fixed else 2):
        raise InputError("evidence: a fit through the event needs both vehicles' rest "
                         "positions ([evidence.vehicle1] and [evidence.vehicle2])")
    x0 = np.concatenate([np.asarray(velocity, float)[0], [float(yaw_rate[0])],
                         np.asarray(velocity, float)[1], [float(yaw_rate[1])]])
    bound = np.array([speed_bound, speed_bound, yaw_rate_bound] * 2)
    free = np.arange(3) if fixed else np.arange(6)
    lower, upper = -bound[free], bound[free]

    def residuals(points, index):
        full = np.broadcast_to(x0, points.shape[:-1] + (6,)).copy()
        full[..., free] = points
        return event_residuals(case, full, tyre_friction=tyre_friction)

    starts = np.array([_scaled(x0, s) for s in START_SCALES])[:, free]
    fit = least_squares_batch(with_forward_differences(residuals, lower, upper, step=1e-4),
                              np.clip(starts, lower, upper), lower, upper, max_iter=60,
                              merge=1e-6)
    best = int(np.argmin(fit.cost))
    x = x0.copy()
    x[free] = fit.x[best]
    rest = event_rest_many(case, np.stack([x[0:2], x[3:5]])[None], x[[2, 5]][None],
                           tyre_friction=tyre_friction)
    agree = int(np.sum(fit.cost <= fit.cost[best] * (1 + 1e-6) + 1e-9))
    return EventFit(np.stack([x[0:2], x[3:5]]), x[[2, 5]], float(fit.cost[best]),
                    int(rest.impacts[0]), float(rest.first_time[0]),
                    bool(fit.converged[best]), agree, len(starts))


def _scaled(x0: np.ndarray, scale: float) -> np.ndarray:
    """``x0`` with both velocities scaled by ``scale`` (yaw rates kept)."""
    x = x0.copy()
    x[[0, 1, 3, 4]] *= scale
    return x
