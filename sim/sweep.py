"""Sweeps of simulations on a ``concurrent.futures`` executor: local processes or a Dask cluster.

A pymunk simulation steps one scene at a time and cannot be vectorised, so many scenes are
spread over processes. :func:`sweep` maps a picklable top-level function over items in chunks
on any executor and returns the results in input order, with a tqdm progress bar:

- ``executor=None`` or ``"process"``: a local ``ProcessPoolExecutor`` (created and shut down
  here, :func:`pim.io.process.worker_pool`: its workers ignore Ctrl-C and are ended at once
  on an interrupt or error), one worker per core by default;
- ``"serial"``: in this process, no executor (for debugging and as the reference);
- a ``dask.distributed.Client``: its ``get_executor()``, i.e. the cluster's workers (the same
  API and the same results; dask is never imported here);
- any other ``concurrent.futures.Executor``: used as given and left running.

:func:`sim.simulate_many` applies :func:`sim.simulate` to many scenes this way; a scene whose
simulation fails (:class:`sim.SimulationError`) gives its error in place of a result instead
of stopping the sweep.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable
from concurrent.futures import Executor, as_completed

from pim.io.process import worker_pool
from pim.model.numbers import InputError, check_counts

__all__ = ["sweep"]


def _run_chunk(func: Callable, chunk: list) -> list:
    return [func(item) for item in chunk]


def _chunks(items: list, size: int) -> list[tuple[int, list]]:
    return [(start, items[start:start + size]) for start in range(0, len(items), size)]


def _workers(executor) -> int:
    for attr in ("_max_workers",):
        n = getattr(executor, attr, None)
        if isinstance(n, int) and n > 0:
            return n
    return os.cpu_count() or 1


def sweep(func: Callable, items: Iterable, executor=None, chunksize: int | None = None,
          max_workers: int | None = None, progress: bool = True,
          desc: str = "sweep") -> list:
    """``[func(item) for item in items]`` on an executor, in input order.

    Parameters
    ----------
    func : callable
        A picklable (module-level) function of one item.
    items : iterable
        The items; each must pickle.
    executor : None, "process", "serial", dask.distributed.Client or Executor
        Where to run (module notes). Default: a local process pool.
    chunksize : int, optional
        Items per task; default about four tasks per worker (fewer round trips, still
        balanced).
    max_workers : int, optional
        Size of the local process pool (default: the number of cores).
    progress : bool
        Show a tqdm progress bar (on stderr).
    desc : str
        Label of the progress bar.

    Returns
    -------
    list
        ``func(item)`` for every item, in the order of ``items``. The first exception raised
        by ``func`` propagates (pending chunks are cancelled).
    """
    check_counts(chunksize=chunksize, max_workers=max_workers)
    from tqdm.auto import tqdm

    items = list(items)
    n = len(items)
    bar = tqdm(total=n, desc=desc, disable=not progress, unit="scene", leave=False)
    try:
        if isinstance(executor, str) and executor == "serial":
            out = []
            for item in items:
                out.append(func(item))
                bar.update(1)
            return out
        if executor is None or (isinstance(executor, str) and executor == "process"):
            workers = max_workers or os.cpu_count() or 1
            with worker_pool(workers) as pool:      # Ctrl-C ends its workers at once
                return _map(pool, func, items, chunksize, workers, bar, cancel=False)
        if isinstance(executor, str):
            raise InputError(f"executor must be None, 'process', 'serial', a dask Client or a "
                             f"concurrent.futures.Executor, got {executor!r}")
        if hasattr(executor, "get_executor") and not isinstance(executor, Executor):
            workers = max(1, sum(getattr(executor, "nthreads", lambda: {})().values()))
            return _map(executor.get_executor(), func, items, chunksize, workers, bar)
        if isinstance(executor, Executor):
            return _map(executor, func, items, chunksize, _workers(executor), bar)
        raise InputError(f"executor must be None, 'process', 'serial', a dask Client or a "
                         f"concurrent.futures.Executor, got {type(executor).__name__}")
    finally:
        bar.close()


def _map(executor, func, items, chunksize, workers, bar, cancel: bool = True) -> list:
    """``func`` over ``items`` in chunks on ``executor``, in input order. On an error or
    interrupt the pending chunks are cancelled (``cancel``); a pool this module ends itself
    (:func:`pim.io.process.worker_pool`) cancels them as it ends."""
    n = len(items)
    if n == 0:
        return []
    size = chunksize or max(1, math.ceil(n / (4 * workers)))
    results: list = [None] * n
    futures = {executor.submit(_run_chunk, func, chunk): (start, len(chunk))
               for start, chunk in _chunks(items, size)}
    try:
        for future in as_completed(futures):
            start, length = futures[future]
            results[start:start + length] = future.result()
            bar.update(length)
    except BaseException:
        for future in futures if cancel else ():
            future.cancel()
        raise
    return results
