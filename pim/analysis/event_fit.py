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

from dataclasses import dataclass, replace

import numpy as np

from ..model.case import Case
from ..model.numbers import InputError
from .event import event_rest_many
from .least_squares_batch import least_squares_batch, with_forward_differences

__all__ = ["EventFit", "SampleInputs", "fit_through_event", "fit_through_event_many",
           "event_residuals", "rest_residuals", "sample_residuals", "fitted_unknowns", "unknown_bounds",
           "START_SCALES", "MAX_ITERATIONS"]

#: The starts of :func:`fit_through_event`: the single-impact fit's speeds scaled by these
#: factors (its directions and yaw rates kept), solved together and merged.
START_SCALES = (1.0, 0.8, 1.25, 0.6, 1.5)
#: Iteration limit of each fit (the event's rest states are piecewise smooth in the motion:
#: a fit that straddles a change of its impact sequence stops there, unconverged).
MAX_ITERATIONS = 40


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


@dataclass(frozen=True)
class SampleInputs:
    """Per-sample inputs of n events (the Monte Carlo's sampled values, SI).

    Attributes
    ----------
    mass, yaw_inertia : ndarray (n, 2)
        Each vehicle's mass [kg] and yaw inertia [kg m^2] (column i: vehicle i + 1).
    friction : ndarray (n, 2)
        Each vehicle's tyre-road friction [-] (its run-out evidence's, sampled).
    poses : ndarray (n, 2, 3)
        Each vehicle's CG (x, y) [m] and heading [rad] at the impact.
    """

    mass: np.ndarray
    yaw_inertia: np.ndarray
    friction: np.ndarray
    poses: np.ndarray

    def take(self, index) -> SampleInputs:
        """The samples ``index`` (an index array)."""
        return SampleInputs(self.mass[index], self.yaw_inertia[index], self.friction[index],
                            self.poses[index])

    def event_options(self, case: Case) -> dict:
        """The ``vehicles`` and ``poses`` of :func:`pim.analysis.event.event_rest_many`: each
        vehicle's run-out evidence at these masses, inertias and friction (None for a fixed
        obstacle)."""
        vehicles = []
        for i in (1, 2):
            ev = getattr(case.evidence, f"vehicle{i}")
            if i == 2 and bool(case.vehicle2.fixed):
                vehicles.append(None)
                continue
            rv = ev.runout_vehicle(self.mass[:, i - 1], self.yaw_inertia[:, i - 1])
            vehicles.append(replace(rv, friction=self.friction[:, i - 1]))
        return {"vehicles": tuple(vehicles), "poses": self.poses}


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


def event_residuals(case: Case, x: np.ndarray, *, tyre_friction=None,
                    targets=None, inputs: SampleInputs | None = None) -> np.ndarray:
    """Residuals (..., 3 per vehicle with evidence) of post-impact motions ``x`` (..., 6):
    (v1x, v1y, w1, v2x, v2y, w2) [m/s, rad/s], the event's rest position and heading minus
    the evidence's, in its standard deviations; NaN where the event did not end at rest.
    ``targets`` (rest positions (..., 2, 2), rest headings (..., 2)), broadcasting against
    ``x``'s leading axes, replace the evidence's measured rest states (the Monte Carlo's
    drawn ones); ``inputs``, one row per motion, replace the case's masses, inertias,
    friction and poses."""
    x = np.asarray(x, float)
    flat = x.reshape(-1, 6)
    velocity = np.stack([flat[:, 0:2], flat[:, 3:5]], axis=1)
    rest = event_rest_many(case, velocity, flat[:, [2, 5]], tyre_friction=tyre_friction,
                           **({} if inputs is None else inputs.event_options(case)))
    return rest_residuals(case, rest, targets, x.shape[:-1])


def rest_residuals(case: Case, rest, targets=None, lead=None) -> np.ndarray:
    """:func:`event_residuals` of events already run: ``rest`` an
    :class:`pim.analysis.event.EventRest` of n events, ``lead`` the leading shape (product n,
    default (n,)) the residuals take and ``targets`` broadcast against."""
    lead = rest.ok.shape if lead is None else tuple(lead)
    cols = []
    for v, position, heading, sp, sh in _targets(case):
        if targets is not None:
            position = np.broadcast_to(targets[0][..., v, :], lead + (2,)).reshape(-1, 2).T
            heading = np.broadcast_to(targets[1][..., v], lead).reshape(-1)
        cols += [(rest.rest_position[:, v, 0] - position[0]) / sp,
                 (rest.rest_position[:, v, 1] - position[1]) / sp,
                 (rest.rest_heading[:, v] - heading) / sh]
    r = np.stack(cols, axis=-1)
    r[~(rest.ok & rest.stopped.all(axis=1))] = np.nan
    return r.reshape(lead + (r.shape[-1],))


def fitted_unknowns(case: Case) -> np.ndarray:
    """The indices of (v1x, v1y, w1, v2x, v2y, w2) fitted (vehicle 1's only against a fixed
    obstacle), after checking the evidence."""
    fixed = bool(case.vehicle2.fixed)
    if len(_targets(case)) < (1 if fixed else 2):
        raise InputError("evidence: a fit through the event needs both vehicles' rest "
                         "positions ([evidence.vehicle1] and [evidence.vehicle2])")
    return np.arange(3) if fixed else np.arange(6)


def fit_through_event_many(case: Case, start, targets, *, speed_bound: float = 60.0,
                           yaw_rate_bound: float = 15.0, tyre_friction=None, groups=None,
                           inputs: SampleInputs | None = None, atol: float | None = None):
    """:func:`fit_through_event` for m problems at once (the Monte Carlo's samples).

    Parameters
    ----------
    case : Case
        As :func:`fit_through_event`.
    start : array_like (m, 6)
        Starting motions (v1x, v1y, w1, v2x, v2y, w2) [m/s, rad/s].
    targets : (ndarray (m, 2, 2), ndarray (m, 2))
        Each problem's rest positions [m] and headings [rad] (per vehicle).
    groups : array_like (m,), optional
        Problems that are one problem from several starts (merged within a group).
    inputs : SampleInputs, optional
        Each problem's masses, inertias, friction and poses (default the case's).
    atol : float, optional
        Also stop a problem when every residual is within ``atol`` standard deviations
        (:func:`pim.analysis.least_squares_batch.least_squares_batch`).

    Returns
    -------
    (x (m, 6), BatchFit)
        The fitted motions and the engine's answer (cost, convergence per problem).
    """
    free = fitted_unknowns(case)
    start = np.atleast_2d(np.asarray(start, float))
    bound = unknown_bounds(free, speed_bound, yaw_rate_bound)
    residuals = sample_residuals(case, start, targets, tyre_friction=tyre_friction,
                                 inputs=inputs)
    fit = least_squares_batch(with_forward_differences(residuals, -bound, bound, step=1e-4),
                              np.clip(start[:, free], -bound, bound), -bound, bound,
                              max_iter=MAX_ITERATIONS, ftol=1e-10, xtol=1e-9,
                              merge=None if groups is None else 1e-6, groups=groups,
                              atol=atol)
    x = start.copy()
    x[:, free] = fit.x
    return x, fit


def unknown_bounds(free: np.ndarray, speed_bound: float, yaw_rate_bound: float) -> np.ndarray:
    """The bound [m/s or rad/s] of each fitted unknown ``free`` (indices into (v1x, v1y, w1,
    v2x, v2y, w2)): each velocity component within +- ``speed_bound``, each yaw rate within
    +- ``yaw_rate_bound``."""
    return np.array([speed_bound, speed_bound, yaw_rate_bound] * 2, float)[free]


def sample_residuals(case: Case, start, targets, *, tyre_friction=None,
                     inputs: SampleInputs | None = None):
    """``residuals(points (p, q, len(free)), index (p,)) -> (p, q, k)``: the event residuals
    (:func:`event_residuals`) of problem ``index``'s fitted unknowns ``points``
    (:func:`fitted_unknowns`; the others from its ``start`` row (m, 6)) against its rest
    ``targets`` (rest positions (m, 2, 2) [m], headings (m, 2) [rad]), with its ``inputs``
    row; the residual function of :func:`with_forward_differences`."""
    free = fitted_unknowns(case)
    start = np.atleast_2d(np.asarray(start, float))
    rest_position, rest_heading = (np.asarray(t, float) for t in targets)

    def residuals(points, index):
        q = points.shape[1]
        full = np.repeat(start[index][:, None, :], q, axis=1)
        full[..., free] = points
        return event_residuals(case, full, tyre_friction=tyre_friction,
                               targets=(rest_position[index][:, None],
                                        rest_heading[index][:, None]),
                               inputs=None if inputs is None
                               else inputs.take(np.repeat(index, q)))

    return residuals


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
    targets = _targets(case)
    velocity = np.asarray(velocity, float)
    x0 = np.array([*velocity[0], float(yaw_rate[0]), *velocity[1], float(yaw_rate[1])])
    rest = np.zeros((len(START_SCALES), 2, 2))
    heading = np.zeros((len(START_SCALES), 2))
    for v, position, angle, _, _ in targets:
        rest[:, v], heading[:, v] = position, angle
    x, fit = fit_through_event_many(
        case, np.array([_scaled(x0, s) for s in START_SCALES]), (rest, heading),
        speed_bound=speed_bound, yaw_rate_bound=yaw_rate_bound, tyre_friction=tyre_friction,
        groups=np.zeros(len(START_SCALES), int))
    best = int(np.argmin(fit.cost))
    end = event_rest_many(case, np.stack([x[best, 0:2], x[best, 3:5]])[None],
                          x[best, [2, 5]][None], tyre_friction=tyre_friction)
    agree = int(np.sum(fit.cost <= fit.cost[best] * (1 + 1e-6) + 1e-9))
    return EventFit(np.stack([x[best, 0:2], x[best, 3:5]]), x[best, [2, 5]],
                    float(fit.cost[best]), int(end.impacts[0]), float(end.first_time[0]),
                    bool(fit.converged[best]), agree, len(START_SCALES))


def _scaled(x0: np.ndarray, scale: float) -> np.ndarray:
    """``x0`` with both velocities scaled by ``scale`` (yaw rates kept)."""
    x = x0.copy()
    x[[0, 1, 3, 4]] *= scale
    return x
