"""The ``pim`` console script, interruptible from its first moment.

Importing ``pim`` (numpy, scipy, numba, matplotlib) takes about a second; Ctrl-C or SIGTERM
in that second would print Python's traceback of the import. This module imports nothing
heavy: it handles SIGINT and SIGTERM (exit 130 and 143, one line) before importing
:mod:`pim.cli.main`, whose :func:`~pim.cli.main.main` then handles them for the run, and
ignores them once the run's exit code is known (the interpreter's shutdown, which joins
worker processes, is not interrupted).
"""

import signal
import sys

__all__ = ["run"]


class _Interrupted(BaseException):
    """A signal during the import of pim."""


def _during_import(signum, frame):
    raise _Interrupted(signum)


def _exit(code: int | None = None, signum: int | None = None) -> None:
    """Ignore further signals and exit (with 130/143 and one line when ``signum`` is given)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    if signum is not None:
        terminated = signum == signal.SIGTERM
        print("terminated" if terminated else "aborted", file=sys.stderr)
        code = 143 if terminated else 130
    sys.exit(code)


def run() -> None:
    """Exit with ``pim.cli.main.main()``'s code; 130/143 when interrupted while loading."""
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, _during_import)
    try:
        from pim.cli.main import main

        code = main()           # handles SIGINT/SIGTERM itself while it runs
    except _Interrupted as exc:
        _exit(signum=exc.args[0])
    _exit(code)
