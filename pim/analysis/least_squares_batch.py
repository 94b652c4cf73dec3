"""Bounded nonlinear least squares for many independent problems at once.

``least_squares_batch`` minimises ``sum_i r_i(x)^2`` for each of m problems of the same size
(n parameters in a box, k residuals) with a Levenberg-Marquardt iteration vectorised over the
problems: one call of the residual function evaluates every problem still running, and the
m small n x n systems are solved together by ``numpy.linalg.solve``. It is what a Monte
Carlo of a fit needs (one fit per sample, thousands of samples) and what a multi-start fit
needs (every start refined at once), where a Python loop of ``scipy.optimize.least_squares``
calls would spend its time in call overhead.

Method (Moré, "The Levenberg-Marquardt algorithm: implementation and theory", Lecture Notes
in Mathematics 630, 1978, with Marquardt's diagonal scaling):

- work in box-scaled variables u = (x - lower) / (upper - lower) in [0, 1];
- step: (J^T J + lambda diag(J^T J)) du = -J^T r over the *free* variables; a variable on a
  bound whose gradient pushes it outward is held (the projected-gradient active set), the
  trial point is clipped into the box;
- accept the step when the cost falls (then lambda /= 3), else lambda *= 4 and retry;
- stop a problem when the relative cost decrease of an accepted step is below ``ftol``, its
  step below ``xtol`` (in scaled variables), its projected gradient below ``gtol``, every
  residual (at the start or after an accepted step) within ``atol`` (a root-finding use: square systems whose
  solution has r = 0, e.g. with a frozen Jacobian, where the cost's round-off floor would
  otherwise cost further steps to find), a refused
  step was promised a decrease below 1e-14 of the cost by the linear model (round-off), or
  lambda has grown past 1e12 (no descent left at round-off).

Rank-deficient problems (families of exact fits) are handled by the damping: the iteration
converges to one member of the family, and the caller reports the family.

Where no derivative is available (a simulation's outputs), :func:`with_forward_differences`
turns a residual function into the ``fun`` this engine takes: one call evaluates every
point and its n forward neighbours in box-scaled variables, so a batched simulator runs the
whole Jacobian of every problem in one batch.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.numbers import InputError

__all__ = ["BatchFit", "least_squares_batch", "with_forward_differences"]


@dataclass(frozen=True)
class BatchFit:
    """Outcome of :func:`least_squares_batch`, one row per problem.

    Attributes
    ----------
    x : ndarray (m, n)
        The minimisers, inside the box.
    cost : ndarray (m,)
        Sum of squared residuals at ``x``.
    residuals : ndarray (m, k)
    jacobian : ndarray (m, k, n)
        d r / d x at ``x`` (unscaled).
    on_bound : ndarray (m, n) of int8
        -1 on the lower bound, +1 on the upper bound, 0 inside.
    converged : ndarray (m,) of bool
        False where ``max_iter`` ran out first.
    iterations : ndarray (m,) of int
    nfev : int
        Number of calls of the residual function (each over the problems still running).
    """

    x: np.ndarray
    cost: np.ndarray
    residuals: np.ndarray
    jacobian: np.ndarray
    on_bound: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    nfev: int


def least_squares_batch(fun, x0, lower, upper, *, max_iter: int = 200, ftol: float = 0.0,
                        xtol: float = 1e-13, gtol: float = 1e-14,
                        lam0: float = 1e-3, merge: float | None = None, groups=None,
                        atol: float | None = None) -> BatchFit:
    """Minimise ``sum r(x)^2`` for m problems at once, each x in the box [lower, upper].

    Parameters
    ----------
    fun : callable
        ``fun(x, index) -> (r, J)``: residuals (p, k) and Jacobian (p, k, n) at the points
        ``x`` (p, n) of the problems ``index`` (p,) (integer indices into the m problems).
        Non-finite residuals count as an infinite cost (the step is refused).
    x0 : array_like (m, n)
        Starting points (clipped into the box).
    lower, upper : array_like (n,) or (m, n)
        Finite bounds with lower < upper.
    max_iter : int
        Iteration limit per problem (accepted and refused steps both count).
    ftol, xtol, gtol, atol : float
        Stopping tolerances (module notes): ``xtol``, ``gtol`` box-scaled, ``atol`` optional.
    lam0 : float
        Initial damping.
    merge : float, optional
        For multi-start use (the m problems are one problem from m starts): a running start
        that comes within ``merge`` (box-scaled, max norm) of a converged one with no lower
        cost is stopped as a duplicate of it (``x`` and ``cost`` become the converged one's).
    groups : array_like (m,) of int, optional
        With ``merge``, for several problems each from several starts (the folds of a
        leave-one-out): the problem of each row; a start merges only within its group.

    Returns
    -------
    BatchFit
    """
    x0 = np.atleast_2d(np.asarray(x0, dtype=float))
    m, n = x0.shape
    lo, width = _box(lower, upper, (m, n))
    u = np.clip((x0 - lo) / width, 0.0, 1.0)
    r, j = fun(lo + u * width, np.arange(m))
    nfev, r = 1, np.array(r, dtype=float)
    j = np.array(j, dtype=float) * width[:, None, :]      # d r / d u
    cost = _cost(r)
    lam, group = np.full(m, float(lam0)), _groups(groups, m)
    converged = _within(r, atol)
    running, iterations = ~converged, np.zeros(m, dtype=int)
    for _ in range(int(max_iter)):
        idx = np.flatnonzero(running)
        if idx.size == 0:
            break
        iterations[idx] += 1
        ua = u[idx]
        gfree, jf, step = _step(ua, r[idx], j[idx], lam[idx])
        small_grad = np.max(np.abs(gfree), axis=1) <= gtol * np.maximum(cost[idx], 1e-300) ** 0.5
        trial = np.clip(ua + step, 0.0, 1.0)
        rt, jt = fun(lo[idx] + trial * width[idx], idx)
        nfev, rt = nfev + 1, np.asarray(rt, dtype=float)
        ct = _cost(rt)
        better = ct < cost[idx]
        acc = idx[better]
        moved = np.max(np.abs(trial - ua), axis=1)
        drop = np.subtract(cost[idx], ct, where=better, out=np.zeros_like(ct))  # inf - inf
        u[acc] = trial[better]
        r[acc] = rt[better]
        j[acc] = np.asarray(jt, dtype=float)[better] * width[acc][:, None, :]
        cost[acc] = ct[better]
        lam[acc] = np.maximum(lam[acc] / 3.0, 1e-12)
        lam[idx[~better]] *= 4.0
        flat = _flat(jf, gfree, step, cost[idx])
        done = (small_grad
                | (better & ((drop <= ftol * ct) | (moved <= xtol) | _within(rt, atol)))
                | (~better & ((moved <= xtol) | flat))
                | (lam[idx] > 1e12))
        converged[idx[done]] = True
        running[idx[done]] = False
        if merge is not None and converged.any() and running.any():
            _merge_duplicates(u, r, j, cost, (running, converged, group), merge)
    x = lo + u * width
    on_bound = np.where(u <= 0.0, -1, np.where(u >= 1.0, 1, 0)).astype(np.int8)
    return BatchFit(x=x, cost=cost, residuals=r, jacobian=j / width[:, None, :],
                    on_bound=on_bound, converged=converged, iterations=iterations, nfev=nfev)


def _groups(groups, m: int) -> np.ndarray:
    """The group of each of the m problems (one group when ``groups`` is None)."""
    group = np.zeros(m, dtype=int) if groups is None else np.asarray(groups, dtype=int)
    if group.shape != (m,):
        raise InputError(f"groups must hold one integer per problem ({m}), got shape "
                         f"{group.shape}")
    return group


def _box(lower, upper, shape) -> tuple[np.ndarray, np.ndarray]:
    """Lower bounds and widths (m, n); a clear error unless finite with lower < upper."""
    lo = np.broadcast_to(np.asarray(lower, dtype=float), shape)
    hi = np.broadcast_to(np.asarray(upper, dtype=float), shape)
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo < hi)):
        raise InputError("bounds must be finite with lower < upper")
    return lo, hi - lo


def _flat(jf, gfree, step, cost) -> np.ndarray:
    """Whether the decrease of sum r^2 that the linear model promised for the step is below
    round-off (1e-14 of the cost)."""
    jstep = np.einsum("pki,pi->pk", jf, step)
    promised = -2.0 * np.einsum("pi,pi->p", gfree, step) - np.sum(jstep**2, axis=1)
    return promised <= 1e-14 * np.maximum(cost, 1e-300)


def _step(ua: np.ndarray, ra: np.ndarray, ja: np.ndarray, lam: np.ndarray) -> tuple:
    """One damped Gauss-Newton step per problem in box-scaled variables (module notes).

    Returns the projected gradient J^T r (zero on the held variables), the Jacobian with the
    held columns zeroed, and the step (p, n); a variable on a bound whose gradient pushes it
    outward is held (the projected-gradient active set)."""
    g = np.einsum("pki,pk->pi", ja, ra)
    held = ((ua <= 0.0) & (g > 0.0)) | ((ua >= 1.0) & (g < 0.0))
    gfree = np.where(held, 0.0, g)
    jf = np.where(held[:, None, :], 0.0, ja)
    a = np.einsum("pki,pkj->pij", jf, jf)
    diag = np.einsum("pii->pi", a)
    diag = np.maximum(diag, 1e-12 * np.maximum(diag.max(axis=1, keepdims=True), 1e-300))
    eye = np.eye(ua.shape[1])
    lhs = a + (lam[:, None] * diag)[:, :, None] * eye
    lhs = np.where(held[:, :, None] | held[:, None, :], 0.0, lhs) + held[:, :, None] * eye
    with np.errstate(all="ignore"):
        step = -np.linalg.solve(lhs, gfree[..., None])[..., 0]
    return gfree, jf, np.where(np.isfinite(step), step, 0.0)


def _merge_duplicates(u, r, j, cost, state, merge: float) -> None:
    """Stop (in place) each running start within ``merge`` (box-scaled, max norm) of a
    converged one of its own group with no lower cost: it becomes a copy of that one.
    ``state``: the (running, converged, group) arrays."""
    running, converged, group = state
    live, fixed = np.flatnonzero(running), np.flatnonzero(converged)
    dist = np.max(np.abs(u[live][:, None, :] - u[fixed][None, :, :]), axis=-1)
    dist = np.where(group[live][:, None] == group[fixed][None, :], dist, np.inf)
    near = np.argmin(dist, axis=1)
    dup = (dist[np.arange(live.size), near] <= merge) & (
        cost[live] >= cost[fixed[near]] * (1.0 - 1e-9))
    for p_, q_ in zip(live[dup], fixed[near[dup]], strict=True):
        u[p_], r[p_], j[p_], cost[p_] = u[q_], r[q_], j[q_], cost[q_]
    converged[live[dup]] = True
    running[live[dup]] = False


def _within(r: np.ndarray, atol: float | None) -> np.ndarray:
    """Whether every residual of each row is within ``atol`` (all False without one)."""
    if atol is None:
        return np.zeros(r.shape[0], dtype=bool)
    return np.all(np.abs(r) <= atol, axis=-1)


def _cost(r: np.ndarray) -> np.ndarray:
    c = np.sum(r * r, axis=-1)
    return np.where(np.isfinite(c), c, np.inf)


def with_forward_differences(residuals, lower, upper, step=1e-3):
    """The ``fun`` of :func:`least_squares_batch` from residuals alone, by forward differences.

    Parameters
    ----------
    residuals : callable
        ``residuals(x, index) -> r``: residuals (p, q, k) at the points ``x`` (p, q, n), q
        points of each problem ``index`` (p,) (its base point and its n neighbours).
    lower, upper : array_like (n,) or (m, n)
        The box (finite, lower < upper), shared or one per problem (as
        :func:`least_squares_batch` takes it).
    step : float or array_like (n,)
        Step in box-scaled variables u = (x - lower) / (upper - lower), one for all unknowns
        or one each; backward where the forward step would leave the box.

    Returns
    -------
    callable
        ``fun(x, index) -> (r, J)`` with r (p, k) at ``x`` (p, n) and J (p, k, n), the
        difference quotients, from one call of ``residuals`` on (p, n + 1) points.
    """
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    n = lower.shape[-1] if lower.ndim else 1
    lo, width = _box(lower, upper, np.broadcast_shapes(lower.shape, upper.shape, (n,)))
    step = np.broadcast_to(np.asarray(step, dtype=float), (n,))
    eye = np.eye(n)

    def fun(x, index):
        rows = (lo, width) if lo.ndim == 1 else (lo[index], width[index])
        u = (np.asarray(x, dtype=float) - rows[0]) / rows[1]
        h = np.where(u + step <= 1.0, step, -step)                   # (p, n)
        points = np.repeat(u[:, None, :], n + 1, axis=1)
        points[:, 1:, :] += h[:, None, :] * eye
        r = np.asarray(residuals(rows[0][..., None, :] + points * rows[1][..., None, :],
                                 index), dtype=float)
        jac = (r[:, 1:, :] - r[:, :1, :]) / (h * rows[1])[:, :, None]  # (p, n, k)
        return r[:, 0, :], np.swapaxes(jac, 1, 2)

    return fun
