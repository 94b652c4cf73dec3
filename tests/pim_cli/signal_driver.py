"""``python signal_driver.py PHASE ARGS...``: ``pim ARGS`` with one phase made slow, writing
"MARK" on stderr as it starts: the moment tests/pim_cli/test_signals.py sends its signal.

Phases: ``callback`` (pymunk's collision callback), ``destructor`` (pymunk's ffi.gc
destructor of a body), ``shutdown`` (the interpreter's shutdown after the run, where worker
processes are joined), ``frame:K`` (drawing frame K of an animation), ``simulation:K`` (the
K-th simulation of a sweep).
"""

import os
import sys
import time

PAUSE = 3.0     # [s] how long the phase lasts: the signal arrives within it


def mark() -> None:
    os.write(2, b"MARK\n")


def once(function):
    """``function``, slowed down (with the mark) on its first call only."""
    def slowed(*args, **kwargs):
        if not slowed.done:
            slowed.done = True
            mark()
            time.sleep(PAUSE)
        return function(*args, **kwargs)
    slowed.done = False
    return slowed


def callback() -> None:
    import sim.run

    sim.run._post_solve = once(sim.run._post_solve)


def destructor() -> None:
    import gc
    import importlib

    import pymunk.body

    crosscheck = importlib.import_module("sim.crosscheck")   # sim.crosscheck: the function
    real = pymunk.body.lib

    class Lib:
        cpBodyFree = staticmethod(once(real.cpBodyFree))

        def __getattr__(self, name):
            return getattr(real, name)
    pymunk.body.lib = Lib()
    simulate = crosscheck.simulate

    def simulate_and_collect(*args, **kwargs):
        out = simulate(*args, **kwargs)
        gc.collect()        # the scene's bodies freed now, as a longer run's collector does
        return out
    crosscheck.simulate = simulate_and_collect


def shutdown() -> None:
    import atexit

    import pim_cli.main

    real = pim_cli.main.main

    def run(argv=None):
        code = real(argv)
        atexit.register(lambda: (mark(), time.sleep(PAUSE)))
        return code
    pim_cli.main.main = run


def nth(k: int, function):
    """``function``, with the mark and the pause before its ``k``-th call (from 1)."""
    def slowed(*args, **kwargs):
        slowed.calls += 1
        if slowed.calls == k:
            mark()
            time.sleep(PAUSE)
        return function(*args, **kwargs)
    slowed.calls = 0
    return slowed


def frame(k: str) -> None:
    from comparisons.animation.render import Renderer

    Renderer.frame = nth(int(k) + 1, Renderer.frame)


def simulation(k: str) -> None:
    import sim
    import sim.run

    sim.simulate = sim.run.simulate = nth(int(k), sim.run.simulate)


if __name__ == "__main__":
    phase, _, arg = sys.argv[1].partition(":")
    globals()[phase](*([arg] if arg else []))
    sys.argv = ["pim"] + sys.argv[2:]
    from pim_cli import run

    run()
