"""pim/io/process.py: SIGINT and SIGTERM as exceptions for a run, remembered by the run's own
handler (no module state), held back for the steps that must not be cut in two; worker pools
that end with their parent (issue 22)."""

import multiprocessing
import multiprocessing.context
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

from pim.io.process import (
    INTERRUPT_EXIT_CODES,
    Interrupts,
    Terminated,
    held_signals,
    in_callback,
    signal_received,
)


@pytest.mark.parametrize("signum, kind", [(signal.SIGINT, KeyboardInterrupt),
                                          (signal.SIGTERM, Terminated)])
def test_a_signal_is_raised_and_remembered_by_the_runs_handler(signum, kind):
    interrupts = Interrupts()
    with interrupts.installed():
        with pytest.raises(kind):
            os.kill(os.getpid(), signum)
        assert signal_received() == signum          # what an output folder asks
    assert interrupts.last() == signum and interrupts.received == [signum]
    assert INTERRUPT_EXIT_CODES[signum] == 128 + signum


def test_the_previous_handlers_come_back_and_a_new_run_starts_with_nothing():
    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    first = Interrupts()
    with first.installed(), pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before
    assert signal_received() is None                # no run's handler installed
    second = Interrupts()
    with second.installed():
        assert signal_received() is None            # nothing to forget: a new record
    assert first.last() == signal.SIGINT and second.last() is None


def test_a_swallowed_interrupt_is_still_remembered():
    interrupts = Interrupts()
    with interrupts.installed():
        try:
            os.kill(os.getpid(), signal.SIGTERM)
        except KeyboardInterrupt:
            pass                                     # e.g. an extension's callback
        assert signal_received() == signal.SIGTERM


def test_outside_the_main_thread_the_block_runs_with_the_process_handlers():
    import threading

    seen = []

    def run():
        with Interrupts().installed():
            seen.append(signal.getsignal(signal.SIGINT))

    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    assert seen == [signal.getsignal(signal.SIGINT)]


def test_held_signals_delivers_the_interrupt_after_the_block():
    done = []
    with pytest.raises(KeyboardInterrupt):
        with held_signals():
            # to this thread: a signal sent to the process may be taken by another thread,
            # whose handler can run after the block (the restored handler then takes it)
            signal.pthread_kill(threading.get_ident(), signal.SIGINT)
            done.append(1)             # still runs: the signal waits
    assert done == [1]


def test_a_signal_inside_a_callback_is_raised_at_the_first_moment_outside_it():
    """pymunk's callbacks and destructors print and drop an exception raised inside them
    (the run would go on to its end): the handler raises it once the callback returned."""
    interrupts = Interrupts()
    seen = []

    class Finalised:
        def __del__(self):                  # a callback by its name (CALLBACK_NAMES)
            assert in_callback(sys._getframe())
            interrupts(signal.SIGTERM, sys._getframe())     # not raised in here
            seen.append("callback ran to its end")

    with pytest.raises(Terminated):
        Finalised()                         # no name keeps it: __del__ runs at once
        seen.append("the caller went on")   # pragma: no cover - raised before this
    assert seen == ["callback ran to its end"] and interrupts.last() == signal.SIGTERM
    assert sys.getprofile() is None         # the hook removed as it raised
    assert not in_callback(sys._getframe())


@pytest.mark.parametrize("package", ["pymunk", "cffi", "llvmlite"])
def test_code_called_back_from_c_is_known_by_its_package(package):
    """A SIGTERM while numba compiled printed "Exception ignored on calling ctypes callback
    function: ExecutionEngine._raw_object_cache_notify" and the Terminated traceback (the
    fault harness's compare at "writing", 2 runs in 50): llvmlite's callbacks drop it."""
    where = os.path.join(os.sep, "site-packages", package, "binding", "engine.py")
    namespace = {"sys": sys}
    exec(compile("def notify():\n    return sys._getframe()\n", where, "exec"), namespace)
    assert in_callback(namespace["notify"]())


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_pool_workers_print_nothing_and_end_with_the_parent(tmp_path, signum):
    """Issue 22: a Ctrl-C to the process group printed each worker's KeyboardInterrupt
    traceback; a parent's SIGTERM handler inherited by forked workers did the same."""
    script = tmp_path / "run.py"
    script.write_text(textwrap.dedent("""
        import signal, sys, time
        from pim.io.process import worker_pool

        def task():
            time.sleep(30)

        def on_term(signum, frame):
            raise KeyboardInterrupt

        if __name__ == "__main__":
            signal.signal(signal.SIGTERM, on_term)      # as the pim command line does
            try:
                with worker_pool(2) as pool:
                    futures = [pool.submit(task) for _ in range(2)]
                    print("started", flush=True)
                    futures[0].result()
            except KeyboardInterrupt:
                sys.exit(130)
    """))
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    assert proc.stdout.readline().strip() == "started"
    time.sleep(0.5)                                  # the workers are in their task
    start = time.time()
    os.killpg(proc.pid, signum)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and err == "", err
    assert time.time() - start < 10                  # ended, not waited for (30 s)


def _worker_signals():
    import signal

    return (signal.getsignal(signal.SIGINT) == signal.SIG_IGN,
            signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, []))


def test_a_started_pool_ignores_ctrl_c_in_its_workers_and_restores_the_parents_mask():
    """Workers start with Ctrl-C blocked (a Ctrl-C while a new interpreter imports its site
    module printed "Fatal Python error: init_import_site"), then ignore it and unblock it;
    the parent's mask is as it was."""
    import multiprocessing
    import signal

    from pim.io.process import started_pool

    before = signal.pthread_sigmask(signal.SIG_BLOCK, [])
    pool = started_pool(1, multiprocessing.get_context("forkserver"), int)
    try:
        ignored, blocked = pool.submit(_worker_signals).result()
    finally:
        pool.shutdown()
    assert ignored and not blocked
    assert signal.pthread_sigmask(signal.SIG_BLOCK, []) == before


class _SignallingProcess(multiprocessing.context.ForkServerProcess):
    """A forkserver process whose start is followed by ``signum`` to the parent while the
    new worker still reads its start-up data (as a Ctrl-C taken by one of numpy's threads is
    handled at the main thread's next step, mask or not)."""

    signum = None

    def start(self):
        super().start()
        os.kill(os.getpid(), self.signum)


class _SignalledContext:
    """The forkserver context, starting :class:`_SignallingProcess` processes."""

    def __init__(self, signum):
        self.context, self.signum = multiprocessing.get_context("forkserver"), signum

    def __getattr__(self, name):
        return getattr(self.context, name)

    def Process(self, *args, **kwargs):  # noqa: N802 - multiprocessing's name
        process = _SignallingProcess(*args, **kwargs)
        process.signum = self.signum
        return process


def test_an_interrupt_while_a_worker_starts_ends_the_pool_before_it_goes_on():
    """The interrupt waits until the worker runs, and the pool is ended (its workers gone)
    before it goes on: an interrupt at the worker's start lost the pool, whose worker was
    left reading its start-up data as the parent removed the semaphores."""
    from pim.io.process import started_pool

    before = set(multiprocessing.active_children())
    with Interrupts().installed() as interrupts, pytest.raises(Terminated):
        started_pool(1, _SignalledContext(signal.SIGTERM), int)
    assert interrupts.received == [signal.SIGTERM]
    assert set(multiprocessing.active_children()) <= before        # none left running


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_an_interrupted_pool_start_prints_nothing(tmp_path, signum):
    """As the pim command line leaves (os._exit after the interrupt): a worker still reading
    its start-up data when multiprocessing's resource tracker removed the lost pool's
    semaphores printed a FileNotFoundError traceback."""
    script = tmp_path / "run.py"
    script.write_text(textwrap.dedent(f"""
        import gc, os, signal, sys
        sys.path.insert(0, {os.path.dirname(__file__)!r})
        from test_process import _SignalledContext
        from pim.io.process import Interrupts, started_pool

        if __name__ == "__main__":
            with Interrupts().installed():
                try:
                    started_pool(1, _SignalledContext({int(signum)}), int)
                except KeyboardInterrupt:
                    gc.collect()
                    os._exit(3)
            os._exit(0)
    """))
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=30)
    assert proc.returncode == 3 and proc.stderr == "", proc.stderr



def test_ending_a_pool_after_its_caller_cancelled_tasks_prints_nothing(monkeypatch):
    """On an interrupt a caller cancels its pending tasks (Executor.map's iterator as the
    exception leaves its loop, sim.sweep) before the pool is ended; the pool's manager
    thread, seeing the killed workers, then set an exception on the cancelled futures and
    died with InvalidStateError (Python 3.11: "Exception in thread ..." on stderr). end_pool
    lets the manager drop them first: it ends cleanly, the running task failed, the
    cancelled ones cancelled, the workers gone."""
    import threading
    import time
    from concurrent.futures.process import BrokenProcessPool

    from pim.io.process import end_pool, worker_pool

    died = []
    monkeypatch.setattr(threading, "excepthook", lambda args: died.append(args.exc_type))
    with worker_pool(1) as pool:
        running = pool.submit(time.sleep, 30)
        pending = [pool.submit(time.sleep, 30) for _ in range(3)]
        while not running.running():
            time.sleep(0.01)
        cancelled = [f for f in pending if f.cancel()]     # not the one already queued
        assert cancelled
        workers = list(pool._processes.values())
        manager = pool._executor_manager_thread
        start = time.monotonic()
        end_pool(pool)
        assert not manager.is_alive() and time.monotonic() - start < 5
        for future in [running, *pending]:
            assert future.cancelled() == (future in cancelled)
            if future not in cancelled:
                assert isinstance(future.exception(timeout=1), BrokenProcessPool)
        assert not any(w.is_alive() for w in workers)
    assert died == []
