"""Test configuration: hypothesis runs derandomized on CI and without its example database
(a local database replays examples an earlier run found, which a clean CI clone never sees),
so a red CI is reproducible;
no test leaves the process's Ctrl-C and SIGTERM handling changed (:func:`signals_left_as_found`);
no test writes into the checkout (:func:`checkout_stays_clean`, every run);
fixtures shared by several test files (a file may define its own of the same name)."""

import os
import signal
from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import settings

import pim
from tests.checkout import gained, listing

ROOT = Path(__file__).resolve().parents[1]

# A shell without job control starts a background job (`pytest &`, `nohup pytest &`, a CI
# script's) with Ctrl-C ignored, and Python keeps it ignored, in the xdist workers and every
# child too: the tests that interrupt a run or a child would see the interrupt lost. Run as
# from a terminal.
if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


@pytest.fixture(scope="session", autouse=True)
def checkout_stays_clean():
    """Fail the run when the checkout gains a file or folder while it runs (a test wrote
    outside its temporary folder: ``out/`` from a command run without ``--out`` among
    them); each xdist worker checks from its first test to its last."""
    before = listing(ROOT)
    yield
    new = gained(before, listing(ROOT))
    if new:
        pytest.fail(f"the test run wrote into the checkout {ROOT}: {', '.join(new[:10])}"
                    f"{' ...' if len(new) > 10 else ''} (write into tmp_path, or give "
                    f"the command --out)", pytrace=False)


def _signal_state() -> tuple:
    """The main thread's SIGINT and SIGTERM handlers and which of the two it blocks."""
    handled = (signal.SIGINT, signal.SIGTERM)
    blocked = signal.pthread_sigmask(signal.SIG_BLOCK, [])
    return (tuple(signal.getsignal(s) for s in handled),
            tuple(s in blocked for s in handled))


#: The signal state the worker's first test started with, and the last test that ended with it.
_SESSION_SIGNALS = {"start": None, "last": "(none yet)"}


@pytest.fixture(autouse=True)
def signals_left_as_found(request):
    """Fail a test that leaves Ctrl-C or SIGTERM ignored, replaced or blocked in the test
    process (and put them back): every later test of its xdist worker, and every process it
    starts, would inherit that (a SIGINT sent to a child was lost and the child waited out
    its sleep), so the failure would show far from its cause. A test that starts with
    another state than the run's (changed outside any test: a module's fixture, an import)
    fails too, naming the last test that ended with the run's state."""
    before = _signal_state()
    _SESSION_SIGNALS["start"] = _SESSION_SIGNALS["start"] or before
    if before != _SESSION_SIGNALS["start"]:
        pytest.fail(f"the process's signal handling changed outside a test, after "
                    f"{_SESSION_SIGNALS['last']}: {_SESSION_SIGNALS['start']} -> {before}",
                    pytrace=False)
    yield
    after = _signal_state()
    if after == before:
        _SESSION_SIGNALS["last"] = request.node.nodeid
    else:
        for signum, handler in zip((signal.SIGINT, signal.SIGTERM), before[0]):
            signal.signal(signum, handler)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, [s for s, b in zip(
            (signal.SIGINT, signal.SIGTERM), before[1]) if not b])
        pytest.fail(f"the test changed the process's signal handling: {before} -> {after}",
                    pytrace=False)


@pytest.fixture(scope="session")
def ricsac9():
    """RICSAC collision 9 as bundled (Brach Fig. 7.14)."""
    return pim.load_case("ricsac9")


@pytest.fixture(scope="session")
def spinning(ricsac9):
    """RICSAC 9 rotated and moved, with pre-impact yaw rates on both vehicles."""
    case = ricsac9.transformed(rotation=-1.1, translation=(5.0, 1.0))
    return replace(case, vehicle1=replace(case.vehicle1, yaw_rate=0.6),
                   vehicle2=replace(case.vehicle2, yaw_rate=-0.3))
