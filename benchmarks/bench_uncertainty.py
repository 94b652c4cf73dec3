"""Monte Carlo end to end: pim.uncertainty on RICSAC 9 with 8 uncertain inputs.

    python benchmarks/bench_uncertainty.py [--samples 1000000] [--repeat 3]
    python benchmarks/bench_uncertainty.py --memory 1e5 1e6 1e7

``--memory`` runs ``pim uncertainty ricsac9 --samples N`` in a fresh process per N and
prints its peak resident memory (``resource.getrusage(RUSAGE_CHILDREN).ru_maxrss``) against
N, with :func:`pim.analysis.montecarlo.memory_estimate` beside it.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time

import pim
from pim.analysis.montecarlo import memory_estimate
from pim.io.uncertainty_table import parse_uncertainty

TABLE = {
    "vehicle1": {"mass": {"normal": "50 kg"}, "velocity_x": {"normal": "1.5 ft/s"}},
    "vehicle2": {"mass": {"normal": "80 kg"}, "velocity_y": {"normal": "1.5 ft/s"}},
    "impact": {"normal_angle": {"plusminus": "5 deg"},
               "point_x": {"uniform": ["-0.1 m", "0.1 m"]},
               "restitution": {"uniform": [0.2, 0.5]}, "beta": {"uniform": [0.8, 1.0]}},
}


def peak_memory(samples: int) -> tuple[float, float]:
    """(peak resident memory [bytes], wall time [s]) of ``pim uncertainty`` in a child."""
    t0 = time.perf_counter()
    code = ("import sys; from pim_cli.main import main; "
            f"sys.exit(main(['uncertainty', 'ricsac9', '--samples', '{samples}', '--json']))")
    subprocess.run([sys.executable, "-c", code], check=True, stdout=subprocess.DEVNULL)
    # each child is waited for before the next starts, so the maximum is this child's once
    # it exceeds its predecessors' (the list is in increasing order)
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024.0, \
        time.perf_counter() - t0


def memory(counts) -> None:
    print(f"{'samples':>12}  {'peak RSS':>10}  {'estimate':>10}  {'time':>8}")
    for n in sorted(int(float(c)) for c in counts):
        peak, seconds = peak_memory(n)
        print(f"{n:>12,}  {peak / 2**20:>7.0f} MiB  {memory_estimate(n) / 2**20:>6.0f} MiB  "
              f"{seconds:>6.1f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--memory", nargs="+", metavar="N",
                        help="print the peak memory of pim uncertainty for each N")
    args = parser.parse_args()
    if args.memory:
        memory(args.memory)
        return
    case = pim.load_case("ricsac9")
    dists = parse_uncertainty(TABLE)
    pim.uncertainty(case, n=1000, distributions=dists)  # warm up (kernel load, scipy import)
    times = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        result = pim.uncertainty(case, n=args.samples, distributions=dists)
        times.append(time.perf_counter() - t0)
    s = result.stats["delta_v1_magnitude"]
    print(f"Monte Carlo, {args.samples:,} samples, {len(result.varying)} uncertain inputs: "
          f"best {min(times):.2f} s end to end ({args.samples / min(times) / 1e6:.2f} M/s)")
    top, share = result.sensitivity["delta_v1_magnitude"][0]
    print(f"  delta-V1 5/50/95 %: {s.p5:.3f} / {s.p50:.3f} / {s.p95:.3f} m/s, top input "
          f"{top} ({share:.2f})")


if __name__ == "__main__":
    main()
