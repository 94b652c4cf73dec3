"""Brach's design-sheet notation of a PIM result: mu0, mu, A, B, C, q, r and T_L.

A mixin of :class:`pim.Result`: every property reads the core fields (critical impulse,
approach velocity, K) and is computed on first access. Equation numbers are those of
Brach & Brach (2011), ch. 6.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

__all__ = ["SheetNotation"]


class SheetNotation:
    """Brach's coefficients and closed forms, from a result's core fields."""

    @cached_property
    def mu0(self) -> np.ndarray:
        """Critical impulse ratio mu0 = Pt0 / Pn0 [-] (eq. 6.60): no sliding at C after impact."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.critical_impulse_t / self.critical_impulse_n

    @cached_property
    def mu(self) -> np.ndarray:
        """Impulse ratio mu = beta mu0 = Pt / Pn [-]."""
        return self.beta * self.mu0

    # ---- Brach's coefficients ------------------------------------------------------------
    @cached_property
    def reduced_mass(self) -> np.ndarray:
        """m_c = m1 m2 / (m1 + m2) [kg]; m1 for a fixed vehicle 2."""
        return 1.0 / (self.case.vehicle1.inverse_mass + self.case.vehicle2.inverse_mass)

    @cached_property
    def A(self) -> np.ndarray:  # noqa: N802 - Brach's symbol
        """Brach's A = 1 + m_c d_c^2/(m1 k1^2) + m_c d_a^2/(m2 k2^2) [-] (eq. 6.46)."""
        return self.reduced_mass * self.k_nn

    @cached_property
    def B(self) -> np.ndarray:  # noqa: N802
        """Brach's B = m_c d_c d_d/(m1 k1^2) + m_c d_a d_b/(m2 k2^2) [-] (eq. 6.46)."""
        return -self.reduced_mass * self.k_nt

    @cached_property
    def C(self) -> np.ndarray:  # noqa: N802
        """Brach's C = m_c d_d^2/(m1 k1^2) + m_c d_b^2/(m2 k2^2) [-] (eq. 6.46; no leading 1)."""
        return self.reduced_mass * self.k_tt - 1.0

    @cached_property
    def q(self) -> np.ndarray:
        """Brach's q = 1 / (A - mu B) [-] (eq. 6.55)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return 1.0 / (self.A - self.mu * self.B)

    @cached_property
    def r(self) -> np.ndarray:
        """Brach's r = u_t / u_n [-], tangential over normal approach velocity at C (eq. 6.60)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.approach_t / self.approach_n

    @cached_property
    def total_loss_brach(self) -> np.ndarray:
        """Brach's closed-form total impact loss T_L [J], equal to :attr:`energy_loss`.

        T_L = (1/2) m_c q v_rn^2 (1 + eps) [2 + 2 mu r - (1 + eps) q (A - 2 mu B + mu^2 (1 + C))]
        (the sheet's T_L with the m_c d_e^2, d_f^2 sum expanded), written with
        v_rn^2 r = u_n u_t so that it stays finite as u_n -> 0, and with q taken into the
        bracket as q and q mu,

        T_L = (1/2) m_c (1 + eps) [2 q u_n^2 + 2 (q mu) u_n u_t
              - (1 + eps) u_n^2 (q^2 A - 2 q (q mu) B + (q mu)^2 (1 + C))],

        so that it stays finite for any finite beta (q mu -> -1/B as mu grows, where mu^2
        alone overflows beyond mu ~ 1e154).
        """
        q = self.q
        with np.errstate(over="ignore", invalid="ignore"):    # a singular q: NaN, flagged
            qmu = q * self.mu
            u_n, u_t = self.approach_n, self.approach_t
            e1 = 1.0 + self.eps
            bracket = (2.0 * q * u_n * u_n + 2.0 * qmu * u_n * u_t
                       - e1 * u_n * u_n * (q * q * self.A - 2.0 * q * qmu * self.B
                                           + qmu * qmu * (1.0 + self.C)))
            loss = 0.5 * self.reduced_mass * e1 * bracket
        return np.where(self.approaching, loss, 0.0)
