"""Figures of the finite-duration contact (issue 10), printed, not asserted.

Run:  python benchmarks/bench_compliant.py [--skip-assumptions]

Prints
1. RICSAC 9 at 100 ms contact (frictionless point contact): PIM's error (beta = 0, the same
   eps) in each vehicle's |delta-V| and yaw rate, with and without tyre forces
   (mu_tyre 0.7, free-rolling), the effective (epsilon, beta) of pim.fit, and the same for
   the hard cases;
2. wall time per impact reaching 1e-3 and 1e-6 relative error for pymunk (over dt) and
   solve_ivp (DOP853, Radau over rtol), against a DOP853 reference at rtol 1e-13, with
   pim.solve's time in the same run as the baseline (the machine is shared: compare
   ratios);
3. `pim assumptions ricsac9` end to end (goal: under 60 s on 2 cores);
4. the stiff limit: error against PIM (beta = 0) over contact time 40 ... 2.5 ms and the
   fitted order (``--figure PATH`` also writes the log-log plot, docs/stiff-limit-ricsac9.png).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from dataclasses import replace

from pim.files import save_figure

import pim
import sim
from comparisons.studies.assumption_legacy import outcome_errors
from comparisons.studies.speed_error_compliant import Grid, compliant_sweep
from comparisons.studies.stiff_limit import plot_stiff_limit, stiff_limit
from sim.compliant_setup import build_problem
from sim.contact_law import stiffness_for_duration


def at_100ms(name: str, eps: float, tyre: float) -> str:
    case = pim.load_case(name)
    k_nn = build_problem(case, eps, sim.DEFAULT_STIFFNESS).k_nn
    k = float(stiffness_for_duration(0.1, k_nn, eps))
    try:
        r = sim.simulate_compliant(case, eps, k, tyre_friction=tyre,
                                   settings=sim.CompliantSettings(record=False), engine="pymunk")
    except sim.SimulationError as exc:
        return f"{name:22s} tyre {tyre:3.1f}: failed ({exc.kind})"
    result = pim.solve(case, eps, 0.0)
    errors, yaw_deg = outcome_errors(case, result, r.velocity1, r.velocity2, r.yaw_rate1,
                                     r.yaw_rate2)
    fixed2 = bool(case.vehicle2.fixed)
    measured = pim.Measured(r.velocity1, None if fixed2 else r.velocity2, r.yaw_rate1,
                            None if fixed2 else r.yaw_rate2)
    fitted = pim.fit(replace(case, measured=measured), include_yaw=True)
    return (f"{name:22s} tyre {tyre:3.1f}: contact {1e3 * r.contact_duration:6.1f} ms  "
            f"err|dV1| {100 * errors['delta_v1']:6.2f} %  err|dV2| "
            f"{100 * errors['delta_v2']:6.2f} %  err yaw1 {yaw_deg[0]:6.2f} deg/s  err yaw2 "
            f"{yaw_deg[1]:6.2f} deg/s  eps_eff {fitted.eps:.3f} beta_eff {fitted.beta:.3f}"
            + (f"  [{'; '.join(r.problems)}]" if r.problems else ""))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--skip-assumptions", action="store_true")
    parser.add_argument("--figure", default=None, help="write the stiff-limit plot here")
    args = parser.parse_args()

    limit = stiff_limit(pim.load_case("ricsac9"), 0.355)
    print("4. stiff limit (frictionless, RICSAC 9): contact [ms] -> error against PIM beta 0")
    for t, e in zip(limit.contact, limit.errors, strict=True):
        print(f"   {1e3 * t:7.2f} ms  {e:.3e}")
    print(f"   fitted order {limit.order:.3f} (expected 1)\n")
    if args.figure:
        save_figure(plot_stiff_limit(limit), args.figure)

    print("1. PIM (beta = 0, same eps) against the frictionless point contact at 100 ms")
    ricsac_eps = pim.fit(pim.load_case("ricsac9")).eps
    for tyre in (0.0, 0.7):
        print("  ", at_100ms("ricsac9", ricsac_eps, tyre))
    for name in ("hard-grazing", "hard-eps0", "hard-barrier", "hard-c-near-cg",
                 "hard-high-speed", "hard-spinning"):
        eps = pim.load_case(name).impact.restitution or 0.0
        for tyre in (0.0, 0.7):
            print("  ", at_100ms(name, eps, tyre))

    print("\n2. wall time per impact for a given error (RICSAC 9, k = 7.5e5 N/m)")
    case = pim.load_case("ricsac9")
    start = time.perf_counter()
    for _ in range(200):
        pim.solve(case, 0.355, 1.0)
    pim_time = (time.perf_counter() - start) / 200
    print(f"   baseline pim.solve: {pim_time * 1e3:.3f} ms per call")
    study = compliant_sweep(case, 0.355, grid=Grid(repeats=3), progress=False)
    for scene in ("frictionless", "friction 0.5"):
        for integrator in ("pymunk", "DOP853", "Radau"):
            for target in (1e-3, 1e-6):
                p = study.fastest(scene, integrator, target)
                text = ("not reached" if p is None else
                        f"{p.wall_time * 1e3:8.2f} ms ({p.wall_time / pim_time:7.0f} x "
                        f"pim.solve) at {p.label}, error {p.error:.1e}")
                print(f"   {scene:13s} {integrator:7s} {target:5.0e}: {text}")

    if not args.skip_assumptions:
        print("\n3. pim assumptions ricsac9 end to end")
        with tempfile.TemporaryDirectory() as tmp:
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", "from pim_cli import run; run()",
                            "assumptions", "ricsac9", "--out", tmp, "--no-progress"],
                           check=True, capture_output=True)
            print(f"   {time.perf_counter() - start:.1f} s (goal < 60 s)")


if __name__ == "__main__":
    main()
