"""The process around a run: SIGINT and SIGTERM, and worker pools that end with it.

A run (one ``pim`` command) installs an :class:`Interrupts` handler for its length: SIGINT
raises KeyboardInterrupt and SIGTERM :class:`Terminated` (a KeyboardInterrupt too), so that
every atomic writer and every output folder (:mod:`pim.io.output`) removes its temporary
files on the way out, and the handler remembers which signal arrived. The command line holds
the handler and turns what it remembers into the exit code (130 for SIGINT, 143 for
SIGTERM); an output folder asks :func:`signal_received` before it swaps a run in, so a run
whose interrupt was swallowed on its way (an extension's callback that ignores exceptions)
is never swapped in. The record lives in the handler the run installed, not in this module:
a new run starts with a new handler and nothing to forget.

:func:`held_signals` holds the two signals back for the few steps that must not be cut in
two (swapping a folder in, starting a process: :func:`starting_processes`);
:func:`worker_pool` is a process pool whose workers ignore Ctrl-C (the parent handles it)
and are ended, and waited for, with an error or an interrupt.

Output folders stay in :mod:`pim.io.output` (file-system transactions); this module is the
process's side, which they use. Nothing here imports numpy.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator

__all__ = ["started_pool", "STARTUP_SIGNALS", "Interrupts", "Terminated", "signal_received",
           "held_signals", "ignore_interrupts", "worker_pool", "stop_workers", "end_pool",
           "starting_processes", "INTERRUPT_EXIT_CODES", "in_callback", "CALLBACK_PATHS",
           "CALLBACK_NAMES"]

#: Exit code of a run ended by each signal (128 + its number, as a shell reports it).
INTERRUPT_EXIT_CODES = {signal.SIGINT: 130, signal.SIGTERM: 143}
_HANDLED = (signal.SIGINT, signal.SIGTERM)
#: Signals blocked while a pool's processes start (:func:`starting_processes`): Ctrl-C, which
#: reaches every process of the terminal's group. A SIGTERM to the group ends a starting
#: worker without a word (its default action; a forked one inherits the parent's held
#: handler, which only records it).
STARTUP_SIGNALS = frozenset({signal.SIGINT})


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that every atomic writer removes its temporary file."""


#: Code run from C with its exceptions printed and dropped ("Exception ignored from callback
#: for ffi.gc", "Exception ignored on calling ctypes callback function"): pymunk's collision
#: callbacks and object destructors, llvmlite's object-cache callbacks (numba compiling),
#: at-fork hooks, finalizers. A signal handled there is raised at the first moment outside.
CALLBACK_PATHS = tuple(f"{os.sep}{package}{os.sep}" for package in ("pymunk", "cffi",
                                                                    "llvmlite"))
CALLBACK_NAMES = frozenset({"__del__", "_releaseLock", "_acquireLock",
                            "_after_at_fork_child_reinit_locks", "_after_fork"})


def in_callback(frame) -> bool:
    """Whether ``frame`` (the one a signal handler interrupted) runs inside code whose
    exceptions are dropped (:data:`CALLBACK_PATHS`, :data:`CALLBACK_NAMES`)."""
    while frame is not None:
        code = frame.f_code
        if code.co_name in CALLBACK_NAMES or any(p in code.co_filename
                                                 for p in CALLBACK_PATHS):
            return True
        frame = frame.f_back
    return False


class Interrupts:
    """SIGINT and SIGTERM as exceptions for the length of one run, and which of them arrived.

    An instance is the signal handler (callable as one): it records the signal and raises
    KeyboardInterrupt (SIGINT) or :class:`Terminated` (SIGTERM). Install it with
    :meth:`installed`; the caller keeps the instance and asks :meth:`last` afterwards.

    Attributes
    ----------
    received : list of int
        The signals received while installed, in order.
    """

    def __init__(self):
        self.received: list[int] = []

    def __call__(self, signum, frame):
        """Record ``signum`` and raise its exception: here, or, when ``frame`` is inside a
        callback that would drop it (:func:`in_callback`) and let the run go on to its end,
        at the first event of the main thread outside it (a profile hook, removed as it
        raises)."""
        self.received.append(signum)
        error = Terminated if signum == signal.SIGTERM else KeyboardInterrupt
        if not in_callback(frame):
            raise error()

        def outside(event_frame, event, arg):
            if not in_callback(event_frame):
                sys.setprofile(None)
                raise error()
        sys.setprofile(outside)

    def last(self) -> int | None:
        """The last signal received, or None."""
        return self.received[-1] if self.received else None

    @contextlib.contextmanager
    def installed(self) -> Iterator[Interrupts]:
        """Handle SIGINT and SIGTERM by this instance for the block (the previous handlers
        are restored after it); outside the main thread, where handlers cannot be set, the
        block runs with the process's handlers."""
        if threading.current_thread() is not threading.main_thread():
            yield self
            return
        previous = {s: signal.signal(s, self) for s in _HANDLED}
        try:
            yield self
        finally:
            for signum, handler in previous.items():
                signal.signal(signum, handler)


def signal_received() -> int | None:
    """The last SIGINT/SIGTERM the run's :class:`Interrupts` handler (the one installed now)
    received, or None (none received, or no run's handler installed)."""
    handler = signal.getsignal(signal.SIGINT)
    return handler.last() if isinstance(handler, Interrupts) else None


@contextlib.contextmanager
def held_signals() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back for the block (delivered when it ends).

    Used for the few steps that must not be cut in two: swapping a folder in, deleting a
    temporary one. The signals' handlers are replaced by one that only records them (a
    signal mask would not do: the signal may go to any thread of the process); on leaving
    the block the handlers are restored and a recorded signal is raised again. Outside the
    main thread (where handlers cannot be set) a no-op.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []
    previous = {s: signal.signal(s, lambda signum, frame: pending.append(signum))
                for s in _HANDLED}
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        for signum in dict.fromkeys(pending):
            signal.raise_signal(signum)


def ignore_interrupts() -> None:
    """Initializer of worker processes: ignore Ctrl-C (the parent handles it and ends them)
    and let SIGTERM end the worker silently.

    A Ctrl-C reaches every process of the terminal's process group; a worker that raised
    KeyboardInterrupt would print its own traceback. A forked worker inherits the parent's
    SIGTERM handler (which raises an exception, printed from inside a simulation's
    callback); the default action ends it without a word.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    # a worker starts with Ctrl-C blocked as the parent started the pool
    # (:func:`started_pool`): now that it is ignored, unblock it
    signal.pthread_sigmask(signal.SIG_UNBLOCK, STARTUP_SIGNALS)


def stop_workers(pool) -> None:
    """End the worker processes of ``pool`` (a ProcessPoolExecutor) at once and wait for
    them to be gone.

    ``ProcessPoolExecutor.shutdown`` waits for running tasks; after an interrupt they must
    not run on (nor write into a folder that is being removed). SIGKILL ends a worker at any
    stage, one still starting too (its Ctrl-C and SIGTERM may be blocked or held then,
    :func:`starting_processes`); the join makes sure none is left reading its start-up data
    when the pool's semaphores are removed (it would print a FileNotFoundError traceback).
    """
    _kill(list((getattr(pool, "_processes", None) or {}).values()))


def _kill(processes: list) -> None:
    for process in processes:
        process.kill()
    for process in processes:
        process.join()


#: Longest wait [s] for a pool's manager thread to drop its cancelled tasks, and to end.
MANAGER_WAIT = 10.0


def end_pool(pool) -> None:
    """End ``pool`` after an error or an interrupt: its pending tasks cancelled, its workers
    ended at once (as :func:`stop_workers`), its threads joined.

    The pool is shut down (tasks cancelled) first and its manager thread let drop every
    cancelled task before the workers are killed: seeing them killed, the manager sets an
    exception on each pending task, and on Python 3.11 a task its caller had cancelled
    (``Executor.map``'s iterator and :func:`sim.sweep.sweep` cancel theirs on an interrupt)
    made it die with "Exception in thread ... InvalidStateError" beside the interrupt."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    deadline = time.monotonic() + MANAGER_WAIT
    while (getattr(pool, "_cancel_pending_futures", False) and manager is not None
           and manager.is_alive() and time.monotonic() < deadline):
        time.sleep(0.001)                  # the manager clears the flag once it dropped them
    _kill(processes)
    if manager is not None:
        manager.join(MANAGER_WAIT)


@contextlib.contextmanager
def starting_processes() -> Iterator[None]:
    """Start processes in the block: Ctrl-C blocked (:data:`STARTUP_SIGNALS`) and SIGINT and
    SIGTERM held back (:func:`held_signals`; raised when the block ends).

    A process started here inherits the blocked mask, so a Ctrl-C to the terminal's process
    group while a new interpreter imports its site module (before any handler exists) waits
    instead of killing it with "Fatal Python error"; the worker unblocks it once it ignores
    it (:func:`ignore_interrupts`). Holding the handlers too keeps an interrupt from cutting
    a start in two: the mask is the main thread's alone, and a signal taken by another
    thread (numpy's BLAS threads) still runs the handler in the main thread at its next
    step, which could leave a process started but unknown to its pool (or the pool unknown
    to its caller) -- never stopped, still reading its start-up data when the interrupted
    parent removes the pool's semaphores, printing a FileNotFoundError traceback.
    """
    with held_signals():
        old = signal.pthread_sigmask(signal.SIG_BLOCK, STARTUP_SIGNALS)
        try:
            yield
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _pool_class():
    """ProcessPoolExecutor whose ``submit`` (which starts a new worker when none is idle,
    on forkserver and spawn) runs under :func:`starting_processes`; built when a pool is
    (importing concurrent.futures.process costs every command a few milliseconds)."""
    from concurrent.futures import ProcessPoolExecutor

    class StartingPool(ProcessPoolExecutor):
        """A ProcessPoolExecutor that starts its workers whole (:func:`starting_processes`)."""

        def submit(self, fn, /, *args, **kwargs):
            with starting_processes():
                return super().submit(fn, *args, **kwargs)

    return StartingPool


def started_pool(max_workers: int | None, mp_context, first, *args):
    """A ProcessPoolExecutor whose workers ignore Ctrl-C and run, with ``first(*args)``
    submitted.

    The pool is built and its processes (a resource tracker, a forkserver, the workers) and
    threads started under :func:`starting_processes`, and so is every worker it starts
    later (on forkserver and spawn, a task submitted while no worker is idle starts one).
    A signal received meanwhile is raised once the first worker runs; the pool is then
    ended (:func:`end_pool`) before the interrupt goes on, so that no worker outlives it.
    """
    if mp_context is not None and mp_context.get_start_method() != "fork":
        # multiprocessing starts its resource tracker with SIGINT and SIGTERM blocked and
        # then UNBLOCKS them (resource_tracker.ensure_running): start it before the mask
        from multiprocessing import resource_tracker

        resource_tracker.ensure_running()
    pool = None
    try:
        with starting_processes():
            pool = _pool_class()(max_workers, mp_context=mp_context,
                                 initializer=ignore_interrupts)
            # wait until a worker runs (it has read its start-up data)
            pool.submit(os.getpid).result()
        pool.submit(first, *args)
    except BaseException:
        if pool is not None:
            end_pool(pool)
        raise
    return pool


@contextlib.contextmanager
def worker_pool(max_workers: int | None = None, mp_context=None):
    """A ProcessPoolExecutor whose workers ignore Ctrl-C and end with an error or interrupt.

    On leaving the block normally the pool shuts down as usual; on an exception (Ctrl-C,
    SIGTERM, an error) its workers are ended first and pending tasks are cancelled.
    """
    pool = started_pool(max_workers, mp_context, os.getpid)
    try:
        yield pool
    except BaseException:
        end_pool(pool)
        raise
    pool.shutdown(wait=True, cancel_futures=True)
