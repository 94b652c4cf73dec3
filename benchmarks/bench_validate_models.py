"""Figures of ``pim validate-models`` (issues 26 and 34), printed, not asserted.

Run:  python benchmarks/bench_validate_models.py [--skip-command] [--warm-too]

Prints
1. the scene's throughput inside a class fit (the leave-one-out batch of the barrier
   non-sideswipe class, Coulomb scene): scenes per CPU second, against the pymunk scene
   stepping the same scenes one at a time in the same run (the baseline: the machine is
   shared, compare the ratio);
2. what issue 34 added, in CPU seconds against the Coulomb scene's class fit and
   leave-one-out refits of the same class in the same run (the baseline): the scene held to
   the physical ranges (its class fit and refits), the profile over the contact time, the
   mechanisms switched off one at a time (non-sideswipe class);
3. ``pim validate-models`` end to end in a subprocess with an empty numba cache (as from a
   clean checkout: the compiled scene is compiled first): wall time, CPU time and the wall
   time against the goal of 120 s on 2 cores; with ``--warm-too`` the same command again
   with the cache the first run filled (the baseline: what compiling costs).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import sim
from comparisons.studies import contact_time as C
from comparisons.studies import crash_records as R
from comparisons.studies import tuned_scene as T

GOAL = 120.0


class _Count:
    n = 0

    def update(self, k):
        self.n += k


def throughput() -> None:
    radii = R.fitted_radii()
    records = R.crash_classes(radii=radii)[R.NON_SIDESWIPE]
    variant = R.input_variants(records, radii)[0]
    T.run_model(T.SCENE_MODEL, records[0].case, [0.2, 0.5, 0.1, 0.7])    # compiled
    count, cpu = _Count(), time.process_time()
    T.fit_class(T.SCENE_MODEL, records, variant, bar=count)
    cpu = time.process_time() - cpu
    x = T.sobol_starts(T.SCENE_MODEL, 16)
    base = time.process_time()
    for row in x:
        sim.simulate_compliant(records[0].case, row[0], friction=row[1], tyre_friction=row[3],
                               contact_time=row[2], settings=T.scene_settings(),
                               engine="pymunk")
    base = (time.process_time() - base) / len(x)
    rate = count.n / cpu
    print(f"1. class fit + 16 leave-one-out refits, {len(records)} tests: {count.n} scenes "
          f"in {cpu:.1f} s CPU = {rate:,.0f} scenes/s; pymunk {1 / base:,.0f} scenes/s "
          f"({base * 1e3:.1f} ms each): {rate * base:,.0f}x")


def _cpu(work) -> float:
    cpu = time.process_time()
    work()
    return time.process_time() - cpu


def added_pieces() -> None:
    radii = R.fitted_radii()
    records = R.crash_classes(radii=radii)[R.NON_SIDESWIPE]
    variant = R.input_variants(records, radii)[0]
    base = _cpu(lambda: T.fit_class(T.SCENE_MODEL, records, variant))
    phys = _cpu(lambda: T.fit_class(T.SCENE_PHYSICAL_MODEL, records, variant))
    prof = _cpu(lambda: C.profile_contact_time(records, variant))
    mech = _cpu(lambda: C.mechanism_study(records, variant))
    print(f"2. non-sideswipe class, CPU s: the Coulomb scene's class fit + leave-one-out "
          f"{base:.1f} (baseline); the physical scene's {phys:.1f} ({phys / base:.1f}x) per "
          f"input variant; the profile over {len(C.PROFILE_TIMES)} contact times "
          f"{prof:.1f} ({prof / base:.1f}x); the {len(C.MECHANISMS)} mechanisms "
          f"{mech:.1f} ({mech / base:.1f}x)")


def _run(env: dict, out: Path) -> tuple[float, float]:
    """(wall, CPU) seconds of ``pim validate-models`` in a fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.perf_counter()
    subprocess.run([sys.executable, "-m", "pim_cli", "validate-models", "--out", str(out),
                    "--no-progress"], env=env, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - wall
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def command(warm: bool) -> None:
    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=os.pathsep.join(
            [str(root), *filter(None, [os.environ.get("PYTHONPATH")])]))
        load = os.getloadavg()[0]
        wall, cpu = _run(env, Path(out) / "cold")
        print(f"3. pim validate-models, empty numba cache: {wall:.1f} s wall, {cpu:.1f} s CPU "
              f"(load {load:.1f} before, {os.getloadavg()[0]:.1f} after); goal {GOAL:.0f} s "
              f"on 2 cores: {wall / GOAL:.2f} of it by wall time, {cpu / GOAL:.2f} by CPU "
              f"time (the command's CPU time bounds its wall time on 2 idle cores from "
              f"above: the fits run on 2 threads, the compilation on 1)")
        if warm:
            wall_w, cpu_w = _run(env, Path(out) / "warm")
            print(f"   the same again with the cache it filled (the baseline without "
                  f"compilation): {wall_w:.1f} s wall, {cpu_w:.1f} s CPU; compiling cost "
                  f"about {cpu - cpu_w:.1f} s CPU")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-command", action="store_true")
    parser.add_argument("--warm-too", action="store_true",
                        help="run the command again with the cache the first run filled")
    args = parser.parse_args()
    np.seterr(all="ignore")
    throughput()
    added_pieces()
    if not args.skip_command:
        command(args.warm_too)


if __name__ == "__main__":
    main()
