"""The analytic event: one event's time (compiled), against the pymunk event when the branch
has it (``sim.simulate_event``); and a reconstruction through the event with its Monte Carlo
(``pim.analysis.reconstruction.reconstruct``: each sample's post-impact motion fitted so that
its event ends at its draw of the rest evidence, ``pim.analysis.event_samples``) on the side
slap of docs/event.md: its time against the goal (10,000 samples in under a minute on 2
cores) and against the old per-sample full fit (``fit_through_event_many`` from the nominal
motion) measured on a subset of draws in the same run, and the two routes' agreement there.

    python benchmarks/bench_event_reconstruction.py [--samples 10000] [--subset 200] [--repeat 20]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import pim
from comparisons.docs.event import side_slap_case, with_rest_evidence
from pim.analysis.event_fit import fit_through_event_many
from pim.analysis.event_samples import fit_event_samples
from pim.analysis.reconstruction import post_impact_motion, reconstruct
from pim.analysis.reconstruction_mc import rest_draws


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


#: The reconstruction's unknowns (the side slap's impact speeds) [m/s].
UNKNOWN = {"vehicle1.speed": (0.0, 40.0), "vehicle2.speed": (0.0, 40.0)}


def reconstruction_seconds(case: pim.Case, samples: int) -> tuple:
    """(total seconds, Monte Carlo seconds, Reconstruction) of ``pim reconstruct``'s chain
    with ``samples`` Monte Carlo samples (the Monte Carlo timed from its stage's start)."""
    marks = {}
    start = time.perf_counter()
    rec = reconstruct(case, unknown=UNKNOWN, samples=samples,
                      progress=lambda stage: marks.setdefault(stage, time.perf_counter()))
    end = time.perf_counter()
    return end - start, end - marks["Monte Carlo"], rec


def draws(case: pim.Case, n: int, rng) -> tuple:
    """n draws of both vehicles' rest evidence (rest positions (n, 2, 2), headings (n, 2))."""
    rest, heading = np.zeros((n, 2, 2)), np.zeros((n, 2))
    for i in (1, 2):
        rest[:, i - 1], heading[:, i - 1], _ = rest_draws(
            getattr(case.evidence, f"vehicle{i}"), i, rng, n)
    return rest, heading


def speeds_kmh(x: np.ndarray) -> np.ndarray:
    """Both vehicles' post-impact speeds [km/h] of motions x (n, 6)."""
    return 3.6 * np.hypot(x[:, [0, 3]], x[:, [1, 4]])


def against_full_fit(case: pim.Case, subset: int, rng) -> dict:
    """The Monte Carlo's fits through the event (:func:`fit_event_samples`) against the old
    per-sample full fit (:func:`fit_through_event_many` from the nominal motion) on the
    same ``subset`` draws: seconds of each, convergence, the speeds' differences."""
    post = post_impact_motion(case)
    fit = post.event_fit
    x0 = np.array([*fit.velocity[0], fit.yaw_rate[0], *fit.velocity[1], fit.yaw_rate[1]])
    targets = draws(post.case, subset, rng)
    start = time.perf_counter()
    fast = fit_event_samples(post.case, x0, targets)
    fast_seconds = time.perf_counter() - start
    start = time.perf_counter()
    x, full = fit_through_event_many(post.case, np.repeat(x0[None], subset, 0), targets)
    full_seconds = time.perf_counter() - start
    both = fast.converged & full.converged
    diff = np.max(np.abs(speeds_kmh(fast.x) - speeds_kmh(x)), axis=1)[both]
    return {"fast": fast_seconds, "full": full_seconds, "fast_ok": fast.converged.mean(),
            "full_ok": full.converged.mean(), "both": int(both.sum()), "diff": diff,
            "p_fast": np.percentile(speeds_kmh(fast.x)[fast.converged], (5, 50, 95), axis=0),
            "p_full": np.percentile(speeds_kmh(x)[full.converged], (5, 50, 95), axis=0)}


def report_monte_carlo(samples: int, subset: int) -> None:
    """Print the Monte Carlo through the event's time against the goal and against the old
    per-sample full fit measured in this run, and their agreement."""
    case = with_rest_evidence(side_slap_case())
    total, mc, rec = reconstruction_seconds(case, samples)
    c = rec.samples.through_event
    print(f"reconstruction through the event, {samples} Monte Carlo samples: {total:.1f} s "
          f"(Monte Carlo {mc:.1f} s); goal < 60 s on 2 cores: "
          f"{'met' if total < 60 else 'NOT met'}; {c['converged']} of {c['samples']} fits "
          f"converged ({c['fast']} by secant steps, {c['refitted']} by the full fit), "
          f"{c['unconverged']} left out; {rec.samples.n_used} samples used")
    cmp = against_full_fit(case, subset, np.random.default_rng(1))
    old = cmp["full"] / subset * samples
    print(f"old per-sample full fit, measured on {subset} draws in this run: "
          f"{cmp['full'] / subset * 1e3:.0f} ms per sample ({cmp['full_ok']:.1%} converged), "
          f"i.e. {old:.0f} s for {samples}: the Monte Carlo above is {old / mc:.1f}x faster; "
          f"on the same {subset} draws the new route takes "
          f"{cmp['fast'] / subset * 1e3:.1f} ms per sample ({cmp['fast_ok']:.1%} converged), "
          f"{cmp['full'] / cmp['fast']:.1f}x faster (load average {os.getloadavg()[0]:.1f} on "
          f"{os.cpu_count()} cores at the end: absolute times scale with it, the ratios less)")
    d = cmp["diff"]
    print(f"agreement on those draws ({cmp['both']} converged in both): post-impact speeds "
          f"differ by at most {d.max():.3f} km/h (median {np.median(d):.5f}, 95th percentile "
          f"{np.percentile(d, 95):.3f}; {np.mean(d <= 0.01):.1%} within 0.01 km/h: the rest "
          f"draw's other root or least-squares minimum); 5/50/95 % of vehicle 1's, 2's speed "
          f"[km/h]: new " + ", ".join(f"{a:.2f}/{b:.2f}" for a, b in cmp["p_fast"])
          + "; full fit " + ", ".join(f"{a:.2f}/{b:.2f}" for a, b in cmp["p_full"]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--subset", type=int, default=200,
                        help="draws fitted by both the new route and the old full fit")
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
    report_monte_carlo(args.samples, args.subset)


if __name__ == "__main__":
    main()
