"""Where PIM's kinematic restitution gains energy, what does the compliant contact do?

Newton's kinematic restitution with sticking friction can *raise* the kinetic energy when
the normal and tangential directions are strongly coupled (eps^2 > det K / (K_nn K_tt), see
tests/pim/test_hard_cases.py): about 6 % of random scenes that otherwise look admissible
(approach, Pn > 0, |mu| <= |mu0|). :func:`energy_gain_study` draws such scenes
(:func:`sim.sampling.random_scene`), keeps those where PIM gains energy, and runs the
finite-duration contact (:func:`sim.simulate_compliant`, point contact, the same eps,
friction :data:`FRICTION` so that it can stick, default stiffness) on each: the compliant
model is passive, so it loses energy where PIM gains it. The table gives, per scene, PIM's
energy change, the simulation's, its stick fraction and slip reversal, and the effective
(epsilon, beta) PIM would need to reproduce the simulated motion (:func:`pim.fit`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

import pim
import sim
from comparisons.report.tables import Table
from pim.model.numbers import InputError
from sim.sampling import random_scene

__all__ = ["energy_gain_study", "FRICTION"]

#: Friction between the vehicles in the compliant runs [-] (high: the contact can stick).
FRICTION = 1.0


def energy_gain_study(count: int = 10, seed: int = 0, max_draws: int = 20000) -> Table:
    """``count`` random PIM-energy-gaining scenes and what the compliant model does there.

    Returns a :class:`comparisons.report.tables.Table` (energy changes as fractions of the initial
    kinetic energy; positive = gained). The first column counts how many approaching,
    otherwise admissible scenes were drawn per energy-gaining one.
    """
    if count < 1:
        raise InputError(f"count must be >= 1, got {count}")
    rng = np.random.default_rng(seed)
    rows = []
    looked = gaining = 0
    for _ in range(max_draws):
        if len(rows) >= count:
            break
        case, eps, _ = random_scene(rng, barrier_fraction=0.0)
        result = pim.solve(case, eps, 1.0)
        plausible = bool(result.approaching & result.normal_impulse_positive
                         & result.friction_opposes_sliding & ~result.q_singular)
        if not plausible:
            continue
        looked += 1
        if bool(result.energy_not_gained):
            continue
        gaining += 1
        e0 = float(result.kinetic_energy_before)
        try:
            r = sim.simulate_compliant(case, eps, sim.DEFAULT_STIFFNESS, friction=FRICTION,
                                       settings=sim.CompliantSettings(record=False),
                                       engine="pymunk")
        except sim.SimulationError as exc:
            rows.append((len(rows) + 1, eps, -float(result.energy_loss) / e0, math.nan,
                         math.nan, False, math.nan, math.nan, exc.kind))
            continue
        measured = pim.Measured(r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2)
        fitted = pim.fit(replace(case, measured=measured), include_yaw=True)
        rows.append((len(rows) + 1, eps, -float(result.energy_loss) / e0,
                     -r.energy_loss / r.energy_before, r.stick_fraction, r.slip_reversed,
                     fitted.eps, fitted.beta, ""))
    share = gaining / looked if looked else math.nan
    columns = ("scene", "eps [-]", "PIM energy change [-]", "compliant energy change [-]",
               "stick fraction [-]", "slip reversed", "eps_eff [-]", "beta_eff [-]",
               "failure")
    return Table("energy_gain", f"Scenes where PIM (beta = 1) gains energy ({gaining} of "
                 f"{looked} plausible random scenes, {100 * share:.1f} %) and the compliant "
                 f"contact there", columns, tuple(rows))
