"""Energies of a PIM result: kinetic energy before and after, the loss and its crush split.

A mixin of :class:`pim.Result`. The loss is -P.(u + U)/2 (the work of the impulse on the
relative motion at C), whose n and t parts are the normal and tangential crush energies
(Brach & Welsh, SAE 2007-01-0737); Brach's closed form T_L is in
:class:`pim.model.sheet_notation.SheetNotation` as a check.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from .evidence_terms import impulse_work
from .geometry import contact_velocity, kinetic_energy

__all__ = ["EnergyOutputs"]


class EnergyOutputs:
    """Kinetic energies and losses, from a result's core fields."""

    @cached_property
    def kinetic_energy_before(self) -> np.ndarray:
        """Total kinetic energy before impact [J]."""
        v1, v2 = self.case.vehicle1, self.case.vehicle2
        return (kinetic_energy(v1.mass, v1.yaw_inertia, v1.velocity, v1.yaw_rate)
                + kinetic_energy(v2.mass, v2.yaw_inertia, v2.velocity, v2.yaw_rate))

    @cached_property
    def kinetic_energy_after(self) -> np.ndarray:
        """Total kinetic energy after impact [J]."""
        v1, v2 = self.case.vehicle1, self.case.vehicle2
        return (kinetic_energy(v1.mass, v1.yaw_inertia, self.velocity1, self.yaw_rate1)
                + kinetic_energy(v2.mass, v2.yaw_inertia, self.velocity2, self.yaw_rate2))

    @cached_property
    def energy_loss(self) -> np.ndarray:
        """Kinetic energy lost in the impact [J] (negative: energy gained).

        Computed from the impulse, -P.(u + U)/2 (the sum of the normal and tangential crush
        energies), not as the difference of the kinetic energies before and after, which
        round-off wipes out at extreme mass ratios (a car against a 1e12 kg body). u and U
        are formed from the pre- and post-impact motion and the arms C - G_i, so only core
        fields are read (no auxiliary pass of the batch kernel).
        """
        v1, v2, point = self.case.vehicle1, self.case.vehicle2, self.case.impact.point
        r1, r2 = point - v1.cg, point - v2.cg
        before = (contact_velocity(v1.velocity, v1.yaw_rate, r1)
                  - contact_velocity(v2.velocity, v2.yaw_rate, r2))
        after = (contact_velocity(self.velocity1, self.yaw_rate1, r1)
                 - contact_velocity(self.velocity2, self.yaw_rate2, r2))
        p = self.impulse
        return impulse_work(p[..., 0], p[..., 1], before[..., 0], before[..., 1],
                            after[..., 0], after[..., 1])

    @cached_property
    def energy_loss_percent(self) -> np.ndarray:
        """Energy lost as a percentage of the kinetic energy before impact [%]."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return 100.0 * self.energy_loss / self.kinetic_energy_before

    @cached_property
    def crush_energy_normal(self) -> np.ndarray:
        """Energy lost in the normal direction, -Pn (u_n + U_n) / 2 [J]."""
        return -0.5 * self.impulse_n * (self.approach_n + self.separation_n)

    @cached_property
    def crush_energy_tangential(self) -> np.ndarray:
        """Energy lost in the tangential direction, -Pt (u_t + U_t) / 2 [J]."""
        return -0.5 * self.impulse_t * (self.approach_t + self.separation_t)

    @cached_property
    def tangential_share(self) -> np.ndarray:
        """Tangential crush energy as a fraction of the total loss [-] (0 where nothing is lost)."""
        total = self.crush_energy_normal + self.crush_energy_tangential
        return np.divide(self.crush_energy_tangential, total,
                         out=np.zeros(np.shape(total)), where=total != 0)
