"""The analytic event: one event's time (compiled), against the pymunk event when the branch
has it (``sim.simulate_event``); and the Monte Carlo of a reconstruction through the event:
N samples' post-impact motions fitted so that their events end at N draws of the rest
evidence (``fit_through_event_many``: the event kernel in parallel, the one least-squares
engine), on the side slap of docs/event.md.

    python benchmarks/bench_event_reconstruction.py [--samples 10000] [--repeat 20]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import pim
from comparisons.docs.event import side_slap_case, with_rest_evidence
from pim.analysis.event_fit import fit_through_event_many


def event_seconds(case: pim.Case, repeat: int, **options) -> float:
    """Median wall time [s] of one analytic event (after a warm-up that compiles)."""
    pim.event(case, **options)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        pim.event(case, **options)
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def pymunk_seconds(case: pim.Case, repeat: int, **options) -> float | None:
    """Median wall time [s] of the pymunk event, or None where ``sim.simulate_event`` is not
    on this branch (the hook for the other side of the ratio)."""
    import sim

    simulate_event = getattr(sim, "simulate_event", None)
    if simulate_event is None:
        return None
    times = []
    for _ in range(max(1, repeat // 4)):
        start = time.perf_counter()
        simulate_event(case, **options)
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def monte_carlo(case: pim.Case, samples: int, rng) -> tuple[float, float, float]:
    """(seconds, share converged, median |error| of the fitted speeds [m/s]) of fitting
    ``samples`` draws of the rest evidence through the event."""
    res = pim.solve(case)
    truth = np.array([*res.velocity1, float(res.yaw_rate1), *res.velocity2,
                      float(res.yaw_rate2)])
    ev = pim.event(case)
    rest = ev.rest_position[None] + 0.05 * rng.standard_normal((samples, 2, 2))
    heading = ev.rest_heading[None] + np.radians(1.0) * rng.standard_normal((samples, 2))
    warm = fit_through_event_many(case, truth[None], (rest[:1], heading[:1]))
    assert warm[0].shape == (1, 6)
    start = time.perf_counter()
    x, fit = fit_through_event_many(case, np.repeat(truth[None], samples, 0), (rest, heading))
    seconds = time.perf_counter() - start
    speeds = np.hypot(x[:, [0, 3]], x[:, [1, 4]])
    error = np.abs(speeds - np.hypot(truth[[0, 3]], truth[[1, 4]]))
    return seconds, float(np.mean(fit.converged)), float(np.median(error))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()
    case = side_slap_case()
    for label, options in (("side slap, tyres 0.7", {}),
                           ("RICSAC 9 free motion 3 s", {"tyre_friction": 0.0})):
        scene = case if not options else pim.load_case("ricsac9")
        ours = event_seconds(scene, args.repeat, **options)
        theirs = pymunk_seconds(scene, args.repeat, **options)
        ratio = "n/a (sim.simulate_event not on this branch)" if theirs is None \
            else f"{theirs / ours:.0f}x (pymunk {theirs * 1e3:.1f} ms)"
        print(f"analytic event, {label}: {ours * 1e3:.2f} ms; pymunk / analytic: {ratio}")
    seconds, converged, error = monte_carlo(with_rest_evidence(case), args.samples,
                                            np.random.default_rng(0))
    print(f"reconstruction through the event, {args.samples} Monte Carlo samples: "
          f"{seconds:.1f} s ({converged:.1%} converged, median speed error "
          f"{error:.3f} m/s), goal < 60 s on 2 cores")


if __name__ == "__main__":
    main()
