"""Progress inside a long stage: a callback the caller installs for a block of its own.

Some stages run long within one call (the Monte Carlo's fits through the event: about 5 ms
a sample, 10,000 samples). The stage reports what it has done with :func:`report`; whoever
shows progress (the command line's bar) installs a callback for the block with
:func:`reporting`. Without one, :func:`report` does nothing, and the results never depend
on it. A context variable carries the callback, so every function between the two keeps
its signature; a worker process does not inherit it (its blocks are reported by the pool
that collects them).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar

__all__ = ["reporting", "report"]

_CALLBACK: ContextVar[Callable | None] = ContextVar("progress_callback", default=None)


@contextmanager
def reporting(callback: Callable[[int, int, str], None]) -> Iterator[None]:
    """Within the block, :func:`report` calls ``callback(done, total, what)``."""
    token = _CALLBACK.set(callback)
    try:
        yield
    finally:
        _CALLBACK.reset(token)


def report(done: int, total: int, what: str) -> None:
    """Say that ``done`` of ``total`` items (``what``: "samples fitted through the event")
    are done, to the callback of the enclosing :func:`reporting` block, if any."""
    callback = _CALLBACK.get()
    if callback is not None:
        callback(int(done), int(total), what)
