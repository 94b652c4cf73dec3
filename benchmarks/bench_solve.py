"""Throughput of pim.solve: compiled fast path vs. the numpy reference vs. the memory-copy bound.

    python benchmarks/bench_solve.py [--n 2000000] [--repeat 7]

Every input varies (masses, inertias, CGs, velocities, yaw rates, C, Gamma, eps, beta). The
fast path is timed as users call it, ``pim.solve(case, eps, beta)`` on a prebuilt Case,
including output allocation and building the Result; the core outputs (post-impact
velocities, yaw rates, impulse, mu0, flags) are computed, the rest on first read. The copy
bound runs a numba kernel with the same parallel loop and thread count that reads every
input and writes every core output with no arithmetic, into freshly allocated buffers as the
solver does. Timings are the best of ``--repeat`` runs, interleaved, because the machine is
shared.
"""

from __future__ import annotations

import argparse
import time

import numba
import numpy as np

import pim
from pim.model import kernel
from pim.model.solver import SINGULAR_TOLERANCE


def random_batch(n: int, seed: int = 0):
    """A Case of n random scenes (every input varying), eps, beta, and the Case build time."""
    rng = np.random.default_rng(seed)

    def vehicle_inputs():
        m = rng.uniform(500, 3000, n)
        return (m, m * rng.uniform(0.8, 2.0, n) ** 2, rng.uniform(-3, 3, (n, 2)),
                rng.uniform(-30, 30, (n, 2)), rng.uniform(-3, 3, n),
                rng.uniform(-np.pi, np.pi, n))

    a, b = vehicle_inputs(), vehicle_inputs()
    point, gamma = rng.uniform(-2, 2, (n, 2)), rng.uniform(-np.pi, np.pi, n)
    t0 = time.perf_counter()
    case = pim.Case(pim.Vehicle(*a), pim.Vehicle(*b), pim.Impact(point, gamma))
    build = time.perf_counter() - t0
    return case, rng.uniform(0, 1, n), rng.uniform(0, 1, n), build


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=2_000_000)
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    n = args.n
    case, eps, beta, build = random_batch(n)
    inputs = kernel.case_inputs(case, eps, beta)
    bytes_in = 19 * 8 * n
    bytes_out = (9 * 8 + 2) * n

    # warm up (compile or load from cache) and page in
    pim.solve(case, eps, beta, backend="numba")
    pim.solve(case, eps, beta, fast_trig=True)
    kernel.stream_copy(inputs)

    fast, fast_trig, copy, numpy_t = [], [], [], []
    for _ in range(args.repeat):
        fast.append(best_of(lambda: pim.solve(case, eps, beta, backend="numba"), 1))
        fast_trig.append(best_of(lambda: pim.solve(case, eps, beta, fast_trig=True), 1))
        copy.append(best_of(lambda: kernel.stream_copy(inputs), 1))
    for _ in range(2):
        numpy_t.append(best_of(lambda: pim.solve(case, eps, beta, backend="numpy"), 1))
    fast, fast_trig, copy, numpy_t = min(fast), min(fast_trig), min(copy), min(numpy_t)
    preallocated = kernel.allocate(n, False)
    args_in = kernel.flatten_inputs(inputs, (n,))
    kern = best_of(lambda: kernel._solve_kernel_libm(*args_in, SINGULAR_TOLERANCE, False,
                                                     *preallocated), args.repeat)
    copy_pre = best_of(lambda: kernel._copy_kernel(*args_in, 0.0, False, *preallocated),
                       args.repeat)
    aux = best_of(lambda: kernel.solve_arrays(inputs, SINGULAR_TOLERANCE, full=True), 3)
    derived = []
    for _ in range(3):
        result = pim.solve(case, eps, beta)
        t0 = time.perf_counter()
        _ = result.energy_loss
        derived.append(time.perf_counter() - t0)
    derived = min(derived)

    def rate(t):
        return f"{n / t / 1e6:7.1f} M cases/s  ({t * 1e3:7.1f} ms)"

    print(f"pim.solve throughput, N = {n:,} cases, every input varying, "
          f"{numba.get_num_threads()} numba threads")
    print(f"  bytes per case: {bytes_in // n} read + {bytes_out // n} written (core outputs)")
    print(f"  fast path  pim.solve(backend='numba')    {rate(fast)}")
    print(f"  fast path, pim.solve(fast_trig=True)     {rate(fast_trig)}")
    print(f"  numpy reference pim.solve(backend='numpy') {rate(numpy_t)}")
    print(f"  memory-copy bound (same bytes, fresh buffers) {rate(copy)}  "
          f"= {(bytes_in + bytes_out) / copy / 1e9:.1f} GB/s")
    print(f"  fraction of the copy bound reached: {copy / fast:.2f} "
          f"(kernel's own sin/cos: {copy / fast_trig:.2f})")
    print(f"  speed-up over numpy: {numpy_t / fast:.1f}x")
    print("  -- breakdown --")
    print(f"  kernel alone, preallocated outputs       {rate(kern)}")
    print(f"  copy bound, preallocated outputs         {rate(copy_pre)}"
          f"  -> fraction {copy_pre / kern:.2f}")
    print(f"  auxiliary fields on first read (2nd pass): {aux * 1e3:.1f} ms")
    print(f"  energy_loss on first read (numpy):         {derived * 1e3:.1f} ms")
    print(f"  building the Case (validation of inputs):  {build * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
