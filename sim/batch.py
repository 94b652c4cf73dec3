"""Many scenes: :func:`simulate_many`, the one batch API of :mod:`sim` (serial, a process pool
or a Dask cluster), and the scenes of an array-valued :class:`pim.Case`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

import pim
from pim.model.case import checked_case
from pim.model.numbers import InputError, check_counts, check_type, real_array

from .failures import SimulationError
from .result import BatchResult
from .run import simulate
from .settings import Settings
from .sweep import sweep

__all__ = ["case_element", "case_count", "simulate_many", "simulate_one"]

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


def _coefficient(value, name: str, count: int) -> list:
    """eps or beta for each scene: None (each case's own default) or checked floats."""
    if value is None:
        return [None] * count
    arr = real_array(value, name)
    if np.isnan(arr).any():
        raise InputError(f"{name} is NaN; give a number, or None for each case's own value")
    try:
        arr = np.broadcast_to(arr, (count,))
    except ValueError:
        raise InputError(f"{name} has shape {arr.shape}, but there are {count} scenes") from None
    return [float(x) for x in arr]


def simulate_many(cases: pim.Case | Sequence[pim.Case], eps=None, beta=None, *,
                  settings: Settings | None = None, executor="serial",
                  chunksize: int | None = None, max_workers: int | None = None,
                  progress: bool = False, record: bool = False) -> BatchResult:
    """Simulate many scenes, one pymunk Space each, on an executor; failures are collected.

    The one batch API of :mod:`sim`.

    Parameters
    ----------
    cases : pim.Case or sequence of pim.Case
        An array-valued case (every element one scene) or a list of single cases.
    eps, beta : array_like, optional
        Restitution and fraction of mu0 [-], broadcast over the scenes; None: each case's
        own (like :func:`pim.solve`). NaN is an error, not "use the default".
    settings : Settings, optional
        Shared settings.
    executor : "serial", "process", None, a dask.distributed.Client or an Executor
        Where the scenes run (:func:`sim.sweep.sweep`); default "serial", because one scene
        takes under a millisecond and starting processes costs more below a few thousand.
    chunksize, max_workers, progress
        As :func:`sim.sweep.sweep`.
    record : bool
        Keep each scene's trajectory in ``results`` (more data to send back).

    Returns
    -------
    BatchResult
        Arrays over the scenes (NaN where a scene failed, with its failure kind and
        message), and ``results``: each scene's :class:`sim.SimResult` or
        :class:`sim.SimulationError`. Bad input (ValueError) raises.
    """
    check_counts(chunksize=chunksize, max_workers=max_workers)
    settings = replace(check_type(settings, "settings", Settings, "a sim.Settings",
                                  none=True) or Settings(), record=record)
    if isinstance(cases, pim.Case):
        items = [case_element(cases, i) for i in range(case_count(cases))]
    else:
        items = list(check_type(cases, "cases", Sequence, "a pim.Case or a sequence of them"))
        for i, case in enumerate(items):
            checked_case(case, f"cases[{i}]")
    count = len(items)
    jobs = [(c, e, b, settings) for c, e, b in zip(
        items, _coefficient(eps, "eps", count), _coefficient(beta, "beta", count), strict=True)]
    results = sweep(simulate_one, jobs, executor=executor, chunksize=chunksize,
                    max_workers=max_workers, progress=progress, desc="simulate")
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
    for i, r in enumerate(results):
        if isinstance(r, SimulationError):
            failure[i], message[i], steps[i] = r.kind, str(r), r.step or 0
            continue
        v1[i], v2[i], w1[i], w2[i] = r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2
        impulse[i], duration[i], steps[i], wall[i] = (r.impulse, r.contact_duration, r.steps,
                                                      r.wall_time)
    return BatchResult(velocity1=v1, velocity2=v2, yaw_rate1=w1, yaw_rate2=w2, impulse=impulse,
                       contact_duration=duration, steps=steps, wall_time=wall, failure=failure,
                       message=message, settings=settings, results=tuple(results))


def simulate_one(job: tuple):
    """:func:`sim.simulate` of one ``(case, eps, beta, settings)``; a failure is returned."""
    case, eps, beta, settings = job
    try:
        return simulate(case, eps, beta, settings)
    except SimulationError as exc:
        return exc
