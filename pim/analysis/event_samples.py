"""The Monte Carlo of a reconstruction through the event: thousands of draws of the rest
evidence (and of the sampled masses, inertias, friction and impact poses) fitted through the
event, each sample at the cost of a few events.

When the nominal reconstruction's post-impact motion was fitted through the event
(:func:`pim.analysis.event_fit.fit_through_event`: the single-impact run-outs re-contact),
every Monte Carlo sample's post-impact motion is fitted through the event too: the six
unknowns x (three against a fixed obstacle) whose event ends at the sample's rest positions
and headings, r(x) = 0 with r the rest states' misfits in the evidence's standard deviations
(:func:`pim.analysis.event_fit.event_residuals`; as many residuals as unknowns).

The full fit (:func:`pim.analysis.event_fit.fit_through_event_many`) spends n + 1 events per
Levenberg-Marquardt iteration on its forward-difference Jacobian. The samples differ from the
nominal problem by about one standard deviation of the evidence, so each sample starts from
the nominal motion with the nominal Jacobian and learns its own from the events it runs,
one event per step (one parallel kernel call for every sample still running):

- ``J0``, by central differences at the nominal motion (:func:`nominal_jacobian`: one call of
  the compiled kernel for 2 n events, once per Monte Carlo), starts every sample's Jacobian;
  at the nominal motion a sample's residuals are the nominal event's against its own draws
  (no event run) unless its inputs are sampled too;
- Broyden's method (:func:`broyden_roots`; C. G. Broyden, "A class of methods for solving
  nonlinear simultaneous equations", Math. Comp. 19, 577-593, 1965: the Gauss-Newton step on
  the current Jacobian, then its rank-one secant update) for up to :data:`BROYDEN_STEPS`
  steps; a sample converges when every residual is within :data:`TOLERANCE` standard
  deviations (its event's rest positions within 0.05 mm of its draws at 5 cm);
- a sample left (its draw has no root nearby: the rest map folds where the impact sequence
  changes, and a draw beyond the fold is fitted in the least-squares sense, as the full fit
  would) goes on the project's least-squares engine
  (:func:`pim.analysis.least_squares_batch.least_squares_batch`, its stopping rules those of
  the full fit) with the Jacobian still updated by the secant of every event it runs, for up
  to :data:`SECANT_STEPS` steps;
- a sample that has not converged then is refitted by the full fit from its best point; one
  that does not converge there either is counted (:attr:`EventSamples.counts`) and left out by
  the caller, never used as if fitted.

scipy's root finders (``broyden1``) solve one system at a time: here thousands of small
independent systems share each kernel call, so the iteration is written once, vectorised.

Samples run in chunks of :data:`CHUNK` (memory bounded whatever the sample count).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..model.case import Case
from ..model.motion import Term
from .event import EventRest, event_rest_many
from .event_fit import (
    SampleInputs,
    event_residuals,
    fit_through_event_many,
    fitted_unknowns,
    rest_residuals,
    sample_residuals,
    unknown_bounds,
)
from .least_squares_batch import least_squares_batch
from .progress import report
from .reconstruction_mc import rest_draws
from .residuals import measured_terms

__all__ = ["EventSamples", "fit_event_samples", "nominal_jacobian", "sampled_inputs",
           "event_sampler", "broyden_roots", "TOLERANCE", "BROYDEN_STEPS", "CHUNK", "DIFFERENCE_STEP",
           "SPEED_BOUND", "YAW_RATE_BOUND"]

#: A sample's fit has converged when every residual is within this many standard deviations
#: of its evidence [-] (the kernel's own round-off in the rest states is about 1e-5).
TOLERANCE = 1e-3
#: Broyden steps before a sample falls back to the full fit.
BROYDEN_STEPS = 5
#: Steps of the least-squares fit on the secant Jacobians for the samples whose draw has no
#: root nearby, before the full fit.
SECANT_STEPS = 80
#: Relative cost decrease of a secant step below which it stops: at a least-squares minimum
#: beyond the fold the cost is flat along the fold and the kernel's round-off blurs it, so
#: a tighter rule (the full fit's 1e-10) buys steps, not speed that matters (the benchmark
#: prints the agreement with the full fit).
SECANT_FTOL = 1e-3
#: Samples fitted together (memory: the kernel's arrays and the full fit's differences; the
#: progress is reported after each chunk, :func:`pim.analysis.progress.report`). The results
#: do not depend on it: each sample's steps are its own.
CHUNK = 1000
#: Central-difference step of the nominal Jacobian [m/s, rad/s].
DIFFERENCE_STEP = 1e-3
#: Shortest step [m/s, rad/s] whose secant updates a Jacobian: the kernel's round-off in the
#: rest states (about 1e-5 standard deviations) would dominate a shorter one's.
SECANT_MIN_STEP = 1e-4
#: The box of the fits (as :func:`pim.analysis.event_fit.fit_through_event`'s defaults):
#: velocity components within +- SPEED_BOUND [m/s], yaw rates within +- YAW_RATE_BOUND
#: [rad/s].
SPEED_BOUND, YAW_RATE_BOUND = 60.0, 15.0


@dataclass(frozen=True)
class EventSamples:
    """Samples' post-impact motions fitted through the event (:func:`fit_event_samples`).

    Attributes
    ----------
    x : ndarray (n, 6)
        Each sample's (v1x, v1y, w1, v2x, v2y, w2) [m/s, rad/s] (the last iterate where not
        converged).
    converged : ndarray of bool (n,)
        The fit converged: by Broyden's steps (every residual within :data:`TOLERANCE`), by
        the least-squares steps on the secant Jacobian, or by the full fit.
    refitted : ndarray of bool (n,)
        The sample fell back to the full fit.
    steps : ndarray of int (n,)
        Broyden steps taken.
    """

    x: np.ndarray
    converged: np.ndarray
    refitted: np.ndarray
    steps: np.ndarray

    @property
    def counts(self) -> dict:
        """``samples``, ``converged``, ``fast`` (converged without finite differences: the
        Broyden and secant steps), ``refitted`` (converged by the full fit) and
        ``unconverged``."""
        n, ok = len(self.converged), int(np.count_nonzero(self.converged))
        refit = int(np.count_nonzero(self.converged & self.refitted))
        return {"samples": n, "converged": ok, "fast": ok - refit, "refitted": refit,
                "unconverged": n - ok}

    @staticmethod
    def joined(parts) -> EventSamples:
        """The samples of ``parts`` (chunks) in order."""
        return EventSamples(*(np.concatenate([getattr(p, f.name) for p in parts])
                              for f in fields(EventSamples)))


def nominal_jacobian(case: Case, x0, *, tyre_friction=None) -> np.ndarray:
    """d r / d x (k, len(free)) of the event residuals at the motion ``x0`` (6,) by central
    differences of :data:`DIFFERENCE_STEP` (all 2 len(free) events in one kernel call)."""
    free = fitted_unknowns(case)
    x0 = np.asarray(x0, float)
    points = np.repeat(x0[None], 2 * free.size, axis=0)
    for j, column in enumerate(free):
        points[2 * j, column] += DIFFERENCE_STEP
        points[2 * j + 1, column] -= DIFFERENCE_STEP
    r = event_residuals(case, points, tyre_friction=tyre_friction)
    return ((r[0::2] - r[1::2]) / (2 * DIFFERENCE_STEP)).T


def fit_event_samples(case: Case, x0, targets, *, jacobian=None,
                      inputs: SampleInputs | None = None, chunk: int = CHUNK,
                      refit: bool = True) -> EventSamples:
    """Post-impact motions whose events end at n draws of the rest evidence (module notes).

    Parameters
    ----------
    case : Case
        With ``[evidence]`` for both vehicles (vehicle 1 against a fixed obstacle).
    x0 : array_like (6,)
        The nominal fit's motion (v1x, v1y, w1, v2x, v2y, w2) [m/s, rad/s].
    targets : (ndarray (n, 2, 2), ndarray (n, 2))
        Each sample's rest positions [m] and headings [rad].
    jacobian : ndarray (k, len(free)), optional
        The starting Jacobian (default :func:`nominal_jacobian` at ``x0``).
    inputs : SampleInputs, optional
        Each sample's masses, inertias, friction and poses (default the case's).
    chunk : int
        Samples fitted together.
    refit : bool
        Refit the samples the fast steps leave unconverged by the full fit (False: they stay
        unconverged).

    Returns
    -------
    EventSamples
    """
    x0 = np.asarray(x0, float)
    jacobian = nominal_jacobian(case, x0) if jacobian is None else np.asarray(jacobian, float)
    nominal = None if inputs is not None else event_rest_many(
        case, np.stack([x0[0:2], x0[3:5]])[None], x0[[2, 5]][None])
    n = len(targets[1])
    parts = []
    for lo in range(0, n, int(chunk)):
        part = slice(lo, min(lo + int(chunk), n))
        parts.append(_fit_chunk(case, x0, (targets[0][part], targets[1][part]), jacobian,
                                None if inputs is None else inputs.take(
                                    np.arange(n)[part]), nominal, refit))
        report(part.stop, n, "samples fitted through the event")
    return EventSamples.joined(parts)


def _fit_chunk(case, x0, targets, jacobian, inputs, nominal, refit) -> EventSamples:
    """:func:`fit_event_samples` of one chunk (``nominal`` the nominal event's EventRest, or
    None when the inputs are sampled)."""
    free = fitted_unknowns(case)
    m = len(targets[1])
    start = np.repeat(x0[None], m, axis=0)
    residuals = sample_residuals(case, start, targets, inputs=inputs)
    r0 = (residuals(start[:, None, free], np.arange(m))[:, 0] if nominal is None
          else rest_residuals(case, _tiled(nominal, m), targets))
    bound = unknown_bounds(free, SPEED_BOUND, YAW_RATE_BOUND)
    xf, rf, jac, converged, steps = broyden_roots(residuals, start[:, free], r0, jacobian,
                                                  bound)
    x = start.copy()
    x[:, free] = xf
    rest = np.flatnonzero(~converged)
    if rest.size:          # no root near: least squares on the secant Jacobians
        fit = least_squares_batch(_secant(residuals, rest, xf[rest], rf[rest], jac[rest]),
                                  xf[rest], -bound, bound, max_iter=SECANT_STEPS,
                                  ftol=SECANT_FTOL, xtol=1e-9, atol=TOLERANCE)
        x[rest[:, None], free] = fit.x
        converged[rest] = fit.converged & np.isfinite(fit.cost)   # stopped at a finite cost
    refitted = ~converged if refit else np.zeros(m, bool)
    bad = np.flatnonzero(refitted)
    if bad.size:
        xb, full = fit_through_event_many(case, x[bad], (targets[0][bad], targets[1][bad]),
                                          speed_bound=SPEED_BOUND, yaw_rate_bound=YAW_RATE_BOUND,
                                          inputs=None if inputs is None else inputs.take(bad),
                                          atol=TOLERANCE)
        x[bad], converged[bad] = xb, full.converged & np.isfinite(full.cost)
    return EventSamples(x, converged, refitted, steps)


def broyden_roots(residuals, x, r, jacobian, bound) -> tuple:
    """Broyden's method for m problems r_i(x_i) = 0 at once (module notes).

    Parameters
    ----------
    residuals : callable
        ``residuals(points (p, 1, n), index (p,)) -> (p, 1, k)`` (k >= n).
    x : ndarray (m, n)
        Starting points; ``r`` (m, k) the residuals there.
    jacobian : ndarray (k, n)
        The starting Jacobian of every problem.
    bound : ndarray (n,)
        Each unknown within +- ``bound``.

    Returns
    -------
    (x (m, n), converged (m,), steps (m,))
        The point with the smallest residual each problem reached, whether every residual
        there is within :data:`TOLERANCE`, and the steps taken.
    """
    x, r = np.array(x, float), np.array(r, float)
    m = len(x)
    jac = np.repeat(np.asarray(jacobian, float)[None], m, axis=0)
    best, r_best, size = x.copy(), r.copy(), _size(r)
    converged = size <= TOLERANCE
    running, steps = ~converged & np.isfinite(size), np.zeros(m, int)
    for _ in range(BROYDEN_STEPS):
        idx = np.flatnonzero(running)
        if not idx.size:
            break
        ja = jac[idx]
        step = -np.einsum("pik,pk->pi", np.linalg.pinv(ja), r[idx])     # least squares
        trial = np.clip(x[idx] + step, -bound, bound)
        rt = residuals(trial[:, None, :], idx)[:, 0]
        steps[idx] += 1
        s, ok = trial - x[idx], np.all(np.isfinite(rt), axis=1)
        ss = np.maximum(np.einsum("pi,pi->p", s, s), 1e-300)
        learn = ok & (ss >= SECANT_MIN_STEP**2)
        jac[idx] += np.where(learn[:, None, None], np.einsum(
            "pk,pi->pki", rt - r[idx] - np.einsum("pki,pi->pk", ja, s), s) / ss[:, None, None], 0)
        x[idx[ok]], r[idx[ok]] = trial[ok], rt[ok]
        better = ok & (_size(rt) < size[idx])
        best[idx[better]], r_best[idx[better]] = trial[better], rt[better]
        size[idx[better]] = _size(rt[better])
        converged[idx] = size[idx] <= TOLERANCE
        running[idx[converged[idx] | ~ok]] = False
    return best, r_best, jac, converged, steps


def _secant(residuals, rows, x, r, jac):
    """The engine's ``fun`` for the problems ``rows`` of ``residuals``: the residuals at the
    points (one event each), and each problem's Jacobian ``jac`` (p, k, n) updated by
    Broyden's rank-one secant update from its previous point to this one; its first call (at
    ``x``, where the residuals are ``r``) runs no event."""
    last_x, last_r, jac = np.array(x), np.array(r), np.array(jac)
    first = [True]

    def fun(points, index):
        if first[0]:
            first[0] = False
            return last_r[index], jac[index]
        rt = residuals(np.asarray(points, float)[:, None, :], rows[index])[:, 0]
        s = points - last_x[index]
        ss = np.einsum("pi,pi->p", s, s)
        ok = np.all(np.isfinite(rt), axis=1) & (ss >= SECANT_MIN_STEP**2)
        i = index[ok]
        jac[i] += np.einsum("pk,pi->pki", rt[ok] - last_r[i] - np.einsum(
            "pki,pi->pk", jac[i], s[ok]), s[ok]) / ss[ok, None, None]
        last_x[i], last_r[i] = points[ok], rt[ok]
        return rt, jac[index]

    return fun


def _size(r: np.ndarray) -> np.ndarray:
    """The largest |residual| of each row (inf where any is not finite)."""
    size = np.max(np.abs(r), axis=-1)
    return np.where(np.isfinite(size), size, np.inf)


def _tiled(rest: EventRest, m: int) -> EventRest:
    """One event's :class:`EventRest` repeated for m samples."""
    return EventRest(**{f.name: np.repeat(getattr(rest, f.name), m, axis=0)
                        for f in fields(EventRest)})


def sampled_inputs(case: Case, values: dict, n: int) -> SampleInputs | None:
    """The event's per-sample inputs from the Monte Carlo's sampled ``values`` (dotted names
    -> scalars or arrays (n,) [SI]: ``vehicleN.mass``, ``yaw_inertia``, ``cg_x``, ``cg_y``,
    ``heading``, ``evidence.vehicleN.friction``; a missing name keeps the case's value);
    None when none of them varies (every sample's event is the case's)."""
    def value(name, default):
        return values.get(name, default)

    names, columns = [], {}
    for i in (1, 2):
        v, ev = getattr(case, f"vehicle{i}"), getattr(case.evidence, f"vehicle{i}")
        p = f"vehicle{i}."
        for key, default in (("mass", v.mass), ("yaw_inertia", v.yaw_inertia),
                             ("cg_x", np.asarray(v.cg, float)[0]),
                             ("cg_y", np.asarray(v.cg, float)[1]), ("heading", v.heading)):
            names.append(p + key)
            columns[p + key] = value(p + key, default)
        key = f"evidence.vehicle{i}.friction"
        names.append(key)
        columns[key] = value(key, np.nan if ev is None else ev.friction)
    if not any(np.ndim(c) for c in columns.values()):
        return None

    def each(name):
        return np.broadcast_to(np.asarray(columns[name], float), (n,))

    def pair(key):
        return np.stack([each(f"vehicle{i}.{key}") for i in (1, 2)], axis=-1)

    poses = np.stack([np.stack([each(f"vehicle{i}.{k}") for k in ("cg_x", "cg_y", "heading")],
                               axis=-1) for i in (1, 2)], axis=1)
    friction = np.stack([each(f"evidence.vehicle{i}.friction") for i in (1, 2)], axis=-1)
    return SampleInputs(pair("mass"), pair("yaw_inertia"), friction, poses)


def event_sampler(case: Case, post, include_yaw: bool = True):
    """The Monte Carlo's post-impact motion per sample through the event (the
    ``post_impact`` of :func:`pim.analysis.reconstruction_mc.solve_samples`).

    Returns ``sampler(values, uniforms, rng, n) -> (targets (n, k), ok (n,), uniforms,
    counts)``: each vehicle's rest position and heading drawn as
    :func:`pim.analysis.reconstruction_mc.rest_draws` draws them, the sampled masses,
    inertias, friction and poses (:func:`sampled_inputs`), every sample's post-impact
    motion fitted through the event (:func:`fit_event_samples`, from ``post.event_fit``'s
    motion, its Jacobian computed on first use); ``ok`` the converged samples, ``counts``
    :attr:`EventSamples.counts`. ``post`` is the reconstruction's
    :class:`pim.analysis.reconstruction.PostImpact` (``event_fit`` set).
    """
    solved = post.case
    terms = measured_terms(solved, include_yaw)
    fit = post.event_fit
    x0 = np.array([*fit.velocity[0], fit.yaw_rate[0], *fit.velocity[1], fit.yaw_rate[1]])
    cache = {}

    def sampler(values, uniforms, rng, n):
        rest, heading, extra = np.zeros((n, 2, 2)), np.zeros((n, 2)), {}
        for i in post.runouts:
            rest[:, i - 1], heading[:, i - 1], u = rest_draws(
                getattr(case.evidence, f"vehicle{i}"), i, rng, n)
            extra.update(u)
        if "jacobian" not in cache:
            cache["jacobian"] = nominal_jacobian(solved, x0)
        out = fit_event_samples(solved, x0, (rest, heading), jacobian=cache["jacobian"],
                                inputs=sampled_inputs(solved, values, n))
        targets = np.empty((n, len(terms)))
        for j, term in enumerate(terms):
            if isinstance(term, Term):
                column = 3 * (term.vehicle - 1) + (2 if term.axis is None else term.axis)
                targets[:, j] = out.x[:, column]
        return targets, out.converged, extra, out.counts

    return sampler
