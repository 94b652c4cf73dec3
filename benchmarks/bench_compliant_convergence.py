"""Convergence of the pymunk contact to the solve_ivp reference, per scene (printed).

Run:  python benchmarks/bench_compliant_convergence.py [--steps 800,1600,3200,6400]

For RICSAC 9 (eps 0.355, k = 7.5e5 N/m) and each scene (frictionless; mu_c 0.5, sliding;
mu_c 3 sticking with r = eps^2 and r = 1; r = 0 at mu_c 0.5 and 3;
tyres mu_tyre 0.7) prints the largest error
in the post-impact velocities [m/s] of ``sim.simulate_compliant`` against
``sim.reference_compliant`` (DOP853, rtol 1e-12) at each step count per contact time, and
the order per halving of dt between consecutive counts (docs/contact-model.md,
"Convergence of pymunk to the reference"). About a minute on a shared 2-core machine.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import pim
import sim
from sim import CompliantSettings

SCENES = {
    "frictionless": dict(friction=0.0),
    "mu_c 0.5 (sliding)": dict(friction=0.5),
    "mu_c 3, r = eps^2": dict(friction=3.0),
    "mu_c 3, r = 1": dict(friction=3.0, recovery=1.0),
    "mu_c 0.5, r = 0": dict(friction=0.5, recovery=0.0),
    "mu_c 3, r = 0": dict(friction=3.0, recovery=0.0),
    "tyres 0.7": dict(friction=0.0, tyre_friction=0.7),
}


def errors(case, steps, friction, tyre_friction=0.0, recovery=None):
    """{steps per contact: largest velocity error [m/s]} against the reference."""
    extra = {} if recovery is None else dict(tangential_recovery=recovery)
    kw = dict(friction=friction, tyre_friction=tyre_friction)
    ref = sim.reference_compliant(case, 0.355, sim.DEFAULT_STIFFNESS, **kw,
                                  settings=CompliantSettings(rtol=1e-12, record=False, **extra))
    out = {}
    for n in steps:
        r = sim.simulate_compliant(case, 0.355, sim.DEFAULT_STIFFNESS, **kw,
                                   settings=CompliantSettings(steps_per_contact=n,
                                                              record=False, **extra),
                                   engine="pymunk")
        out[n] = float(np.abs(np.r_[r.velocity1 - ref.velocity1,
                                    r.velocity2 - ref.velocity2]).max())
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", default="800,1600,3200,6400")
    steps = [int(n) for n in parser.parse_args().steps.split(",")]
    case = pim.load_case("ricsac9")
    print("scene".ljust(22) + "".join(f"{n:>12d}" for n in steps) + "   orders")
    for name, scene in SCENES.items():
        err = errors(case, steps, **scene)
        orders = [math.log2(err[a] / err[b]) / math.log2(b / a)
                  for a, b in zip(steps[:-1], steps[1:], strict=True)]
        print(name.ljust(22) + "".join(f"{err[n]:12.2e}" for n in steps) + "   "
              + " ".join(f"{o:5.2f}" for o in orders), flush=True)


if __name__ == "__main__":
    main()
