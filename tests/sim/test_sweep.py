"""sim.sweep: ordered results on serial, process and Dask executors, equal to the serial run."""

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import pim
from sim import simulate_many
from sim.sweep import sweep


def scenes(n):
    case = pim.load_case("ricsac9")
    return [case.transformed(rotation=r, translation=(r, -r)) for r in np.linspace(0, 2, n)]


def test_sweep_keeps_input_order_on_every_local_executor():
    items = list(range(200))
    expected = [math.sqrt(i) for i in items]
    assert sweep(math.sqrt, items, executor="serial", progress=False) == expected
    assert sweep(math.sqrt, items, chunksize=7, max_workers=2, progress=False) == expected
    with ThreadPoolExecutor(3) as pool:
        assert sweep(math.sqrt, items, executor=pool, chunksize=5, progress=False) == expected
    assert sweep(math.sqrt, [], progress=False) == []
    with pytest.raises(ValueError, match="executor"):
        sweep(math.sqrt, items, executor="gpu")
    with pytest.raises(ValueError, match="math domain"):
        sweep(math.sqrt, [1, -1], max_workers=2, progress=False)


def _same(a, b):
    for x, y in zip(a, b, strict=True):
        assert type(x) is type(y)
        np.testing.assert_array_equal(x.velocity1, y.velocity1)
        np.testing.assert_array_equal(x.yaw_rate2, y.yaw_rate2)
        np.testing.assert_array_equal(x.impulse, y.impulse)


def test_simulation_sweep_process_pool_equals_serial():
    cases = scenes(24)
    serial = simulate_many(cases, eps=0.355, beta=1.0, executor="serial").results
    pool = simulate_many(cases, eps=0.355, beta=1.0, executor="process", max_workers=2,
                         chunksize=5).results
    _same(serial, pool)
    # the simulation reproduces PIM (independent check that the sweep ran real scenes)
    ref = pim.solve(cases[3], 0.355, 1.0)
    np.testing.assert_allclose(serial[3].velocity1, ref.velocity1, atol=0.05)


def test_simulation_sweep_on_a_local_dask_cluster_equals_serial():
    distributed = pytest.importorskip("dask.distributed")
    cases = scenes(16)
    serial = simulate_many(cases, eps=0.3, beta=0.8, executor="serial").results
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = simulate_many(cases, eps=0.3, beta=0.8, executor=client).results
    _same(serial, remote)


@pytest.mark.parametrize("bad", [{"eps": np.array([0.3, np.nan])}, {"beta": [0.5, float("nan")]},
                                 {"eps": "0.3"}, {"eps": [0.3, 0.3, 0.3]}])
def test_simulate_many_rejects_nan_strings_and_wrong_shapes(bad):
    """NaN is not "the case's default" (None is): issue 12, defect 9."""
    with pytest.raises(ValueError, match="eps|beta"):
        simulate_many(scenes(2), **bad)


def test_ctrl_c_in_a_default_process_sweep_ends_it_without_worker_tracebacks(tmp_path):
    """executor=None made a plain ProcessPoolExecutor: a Ctrl-C reached every worker, each
    printed its own KeyboardInterrupt traceback, and the pool waited for their tasks. The
    sweep's pool is now :func:`pim.io.process.worker_pool`'s: workers ignore Ctrl-C and are
    ended at once; one traceback (the parent's) remains."""
    import os
    import signal
    import subprocess
    import sys
    import textwrap
    import time

    script = tmp_path / "run.py"
    ready = tmp_path / "ready"
    script.write_text(textwrap.dedent(f"""
        import pathlib, signal, time
        from sim.sweep import sweep

        def slow(i):
            pathlib.Path({str(ready)!r}).touch()
            time.sleep(20)
            return i

        if __name__ == "__main__":
            signal.signal(signal.SIGINT, signal.default_int_handler)
            sweep(slow, list(range(4)), max_workers=2, progress=False)
    """))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.Popen([sys.executable, str(script)], stderr=subprocess.PIPE, text=True,
                            env=env, start_new_session=True)
    deadline = time.time() + 60
    while not ready.exists() and time.time() < deadline:
        time.sleep(0.05)
    time.sleep(0.3)
    start = time.time()
    os.killpg(proc.pid, signal.SIGINT)           # as a terminal's Ctrl-C: the whole group
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0 and time.time() - start < 10, err      # not 20 s of tasks
    assert err.count("Traceback") == 1 and "KeyboardInterrupt" in err, err
