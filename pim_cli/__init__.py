"""The ``pim`` console script, interruptible from its first moment.

Importing ``pim`` (numpy, scipy, numba, matplotlib) takes about a second; Ctrl-C or SIGTERM
in that second would print Python's traceback of the import. This module imports nothing
heavy: it handles SIGINT and SIGTERM (exit 130 and 143, one line) before importing
:mod:`pim_cli.main`, whose :func:`~pim_cli.main.main` then handles them for the run. Once
the run's exit code is known a signal no longer interrupts (the interpreter's shutdown,
which joins worker processes, runs to its end) but still decides the exit code: 130/143
and one line, after the shutdown (an interrupt at any moment is never an exit 0). A signal
while loading ends the process at once (nothing has been written yet).
"""

import atexit
import os
import signal
import sys

__all__ = ["run"]

def _during_import(signum, frame):
    """Nothing is written yet: leave at once (an exception raised inside an extension
    module's import may be swallowed or turned into an ImportError)."""
    terminated = signum == signal.SIGTERM
    os.write(2, b"terminated\n" if terminated else b"aborted\n")
    os._exit(143 if terminated else 130)


def _leave(late: list) -> None:
    """The last exit handler (registered first): a signal received during the shutdown
    (``late``: the signals received after the run's exit code was known) makes the exit code
    130/143, with its one line."""
    if late:
        terminated = signal.SIGTERM in late
        sys.stdout.flush()
        sys.stderr.flush()
        os.write(2, b"terminated\n" if terminated else b"aborted\n")
        os._exit(143 if terminated else 130)


def run() -> None:
    """Exit with ``pim_cli.main.main()``'s code; 130/143 when interrupted, at any moment."""
    late: list[int] = []        # signals received after the run's exit code was known
    atexit.register(_leave, late)   # first registered, so it runs after every other one
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, _during_import)
    # An interrupted run leaves by os._exit: multiprocessing's resource tracker (a process of
    # its own, started with these -W options) must not then warn of a worker pool's
    # semaphore below the one line "aborted"/"terminated".
    sys.warnoptions.append("ignore:resource_tracker:UserWarning")
    from pim_cli.main import main

    code = main()           # handles SIGINT/SIGTERM itself while it runs
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda received, frame: late.append(received))
    if code in (130, 143):
        # Interrupted (its files already removed). A KeyboardInterrupt that went through
        # an extension's PyRun_* call (a lazy import) leaves the interpreter's flag that
        # makes it end by SIGINT (-2) after any normal exit; leave with os._exit instead,
        # once the dropped worker pools' semaphores are freed (gc runs their finalizers,
        # else multiprocessing's resource tracker warns of leaked semaphores).
        import gc

        gc.collect()
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)
