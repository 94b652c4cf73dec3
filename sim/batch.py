"""Run many scenes cheaply: one scene per element of an array-valued :class:`pim.Case`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

import pim

from .errors import SimulationError
from .result import BatchResult
from .run import simulate
from .scene import reject_nan_coefficients
from .settings import Settings

__all__ = ["case_element", "case_count", "simulate_many"]

_SCALARS = ("mass", "yaw_inertia", "yaw_rate", "heading")
_VECTORS = ("cg", "velocity")


def _shape(case: pim.Case) -> tuple:
    shapes = []
    for v in (case.vehicle1, case.vehicle2):
        shapes += [np.shape(getattr(v, f)) for f in _SCALARS]
        shapes += [np.shape(getattr(v, f))[:-1] for f in _VECTORS]
    shapes += [np.shape(case.impact.normal_angle), np.shape(case.impact.point)[:-1]]
    return np.broadcast_shapes(*shapes)


def case_count(case: pim.Case) -> int:
    """Number of scenes an array-valued case holds."""
    return int(np.prod(_shape(case), dtype=int))


def case_element(case: pim.Case, index: int) -> pim.Case:
    """The ``index``-th scene (flat, C order) of an array-valued case, as a scalar Case."""
    shape = _shape(case)
    where = np.unravel_index(index, shape) if shape else ()

    def pick(value, vector):
        full = np.broadcast_to(value, shape + ((2,) if vector else ()))
        return np.array(full[where], dtype=float)

    def vehicle(v):
        kw = {f: pick(getattr(v, f), False) for f in _SCALARS}
        kw.update({f: pick(getattr(v, f), True) for f in _VECTORS})
        return replace(v, **kw)

    impact = replace(case.impact, point=pick(case.impact.point, True),
                     normal_angle=pick(case.impact.normal_angle, False))
    return replace(case, vehicle1=vehicle(case.vehicle1), vehicle2=vehicle(case.vehicle2),
                   impact=impact, measured=None)


def simulate_many(cases: pim.Case | Sequence[pim.Case], eps=None, beta=None,
                  settings: Settings | None = None) -> BatchResult:
    """Simulate many scenes, one pymunk Space each, collecting failures instead of raising.

    Parameters
    ----------
    cases : pim.Case or sequence of pim.Case
        An array-valued case (every element one scene) or a list of single cases.
    eps, beta : array_like, optional
        Restitution and fraction of mu0 [-], broadcast over the scenes; default from each
        case's impact (like :func:`pim.solve`).
    settings : Settings, optional
        Shared settings (``record`` is ignored: no trajectories are kept).

    Returns
    -------
    BatchResult
        Arrays over the scenes; failed scenes hold NaN and their failure kind and message.
        Bad input (ValueError) still raises.
    """
    settings = replace(settings or Settings(), record=False)
    if isinstance(cases, pim.Case):
        count = case_count(cases)
        items = [case_element(cases, i) for i in range(count)]
    else:
        items = list(cases)
        count = len(items)
    reject_nan_coefficients(eps, beta)   # NaN below means "the case's default"
    eps_all = np.broadcast_to(np.asarray(np.nan if eps is None else eps, float), (count,))
    beta_all = np.broadcast_to(np.asarray(np.nan if beta is None else beta, float), (count,))
    v1 = np.full((count, 2), np.nan)
    v2 = np.full((count, 2), np.nan)
    w1 = np.full(count, np.nan)
    w2 = np.full(count, np.nan)
    impulse = np.full((count, 2), np.nan)
    duration = np.full(count, np.nan)
    steps = np.zeros(count, dtype=int)
    wall = np.full(count, np.nan)
    failure = np.full(count, None, dtype=object)
    message = np.full(count, None, dtype=object)
    for i, case in enumerate(items):
        e = None if np.isnan(eps_all[i]) else float(eps_all[i])
        b = None if np.isnan(beta_all[i]) else float(beta_all[i])
        try:
            r = simulate(case, e, b, settings)
        except SimulationError as exc:
            failure[i], message[i], steps[i] = exc.kind, str(exc), exc.step or 0
            continue
        v1[i], v2[i], w1[i], w2[i] = r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2
        impulse[i], duration[i], steps[i], wall[i] = (r.impulse, r.contact_duration, r.steps,
                                                      r.wall_time)
    return BatchResult(velocity1=v1, velocity2=v2, yaw_rate1=w1, yaw_rate2=w2, impulse=impulse,
                       contact_duration=duration, steps=steps, wall_time=wall, failure=failure,
                       message=message, settings=settings)
