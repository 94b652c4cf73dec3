"""The outcome of :func:`pim.solve`: post-impact motion and everything derived from it."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .case import Case
from .geometry import contact_velocity, dot, kinetic_energy
from .pdof import clock_position, pdof

__all__ = ["Result"]


@dataclass(frozen=True, eq=False)
class Result:
    """The outcome of :func:`solve`: post-impact motion and everything derived from it.

    Every array broadcasts over the inputs (vectors carry a trailing axis of 2). The core
    fields are computed by :func:`solve`; the properties below them are computed on first
    access and cached. Units: m/s, rad/s, N s, J, rad.

    Attributes
    ----------
    velocity1, velocity2 : ndarray (..., 2)
        Post-impact CG velocities [m/s].
    yaw_rate1, yaw_rate2 : ndarray
        Post-impact yaw rates [rad/s].
    impulse : ndarray (..., 2)
        Impulse P on vehicle 1 [N s] (vehicle 2 receives -P).
    impulse_n, impulse_t : ndarray
        Its components Pn, Pt along n and t [N s].
    critical_impulse_n, critical_impulse_t : ndarray
        The impulse at mu = mu0 (beta = 1) [N s].
    approaching : ndarray of bool
        u_n < 0 beyond round-off (by more than APPROACH_TOLERANCE of |u_n| + |u_t|): the
        vehicles approach at C. Where False no impulse is applied.
    q_singular : ndarray of bool
        A - mu B = 0: the impulse is unbounded; outputs there are NaN.
    """

    case: Case
    eps: np.ndarray
    beta: np.ndarray
    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: np.ndarray
    yaw_rate2: np.ndarray
    impulse: np.ndarray
    impulse_n: np.ndarray
    impulse_t: np.ndarray
    critical_impulse_n: np.ndarray
    critical_impulse_t: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    arm1: np.ndarray
    arm2: np.ndarray
    approach_velocity: np.ndarray
    approach_n: np.ndarray
    approach_t: np.ndarray
    k_nn: np.ndarray
    k_nt: np.ndarray
    k_tt: np.ndarray
    approaching: np.ndarray
    q_singular: np.ndarray

    # ---- impulse ratio -------------------------------------------------------------------
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

    # ---- motion --------------------------------------------------------------------------
    @cached_property
    def delta_v1(self) -> np.ndarray:
        """Change of vehicle 1's CG velocity [m/s], shape (..., 2)."""
        return self.velocity1 - self.case.vehicle1.velocity

    @cached_property
    def delta_v2(self) -> np.ndarray:
        """Change of vehicle 2's CG velocity [m/s], shape (..., 2)."""
        return self.velocity2 - self.case.vehicle2.velocity

    @cached_property
    def delta_v1_magnitude(self) -> np.ndarray:
        """|delta-V| of vehicle 1 [m/s]."""
        return np.hypot(self.delta_v1[..., 0], self.delta_v1[..., 1])

    @cached_property
    def delta_v2_magnitude(self) -> np.ndarray:
        """|delta-V| of vehicle 2 [m/s]."""
        return np.hypot(self.delta_v2[..., 0], self.delta_v2[..., 1])

    @cached_property
    def speed1(self) -> np.ndarray:
        """Post-impact speed of vehicle 1 [m/s]."""
        return np.hypot(self.velocity1[..., 0], self.velocity1[..., 1])

    @cached_property
    def speed2(self) -> np.ndarray:
        """Post-impact speed of vehicle 2 [m/s]."""
        return np.hypot(self.velocity2[..., 0], self.velocity2[..., 1])

    @cached_property
    def separation_velocity(self) -> np.ndarray:
        """Relative velocity of C after impact, U = U_1 - U_2 [m/s], shape (..., 2)."""
        return (contact_velocity(self.velocity1, self.yaw_rate1, self.arm1)
                - contact_velocity(self.velocity2, self.yaw_rate2, self.arm2))

    @cached_property
    def separation_n(self) -> np.ndarray:
        """U_n, normal relative velocity at C after impact [m/s]."""
        return dot(self.separation_velocity, self.normal)

    @cached_property
    def separation_t(self) -> np.ndarray:
        """U_t, tangential relative velocity at C after impact [m/s]."""
        return dot(self.separation_velocity, self.tangent)

    @cached_property
    def restitution_check(self) -> np.ndarray:
        """-U_n / u_n [-]: equals eps by construction (the sheet's consistency check)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return -self.separation_n / self.approach_n

    # ---- energy --------------------------------------------------------------------------
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
        are formed from the pre- and post-impact motion and the arms C - G_i (no K needed).
        """
        v1, v2, point = self.case.vehicle1, self.case.vehicle2, self.case.impact.point
        r1, r2 = point - v1.cg, point - v2.cg
        before = (contact_velocity(v1.velocity, v1.yaw_rate, r1)
                  - contact_velocity(v2.velocity, v2.yaw_rate, r2))
        after = (contact_velocity(self.velocity1, self.yaw_rate1, r1)
                 - contact_velocity(self.velocity2, self.yaw_rate2, r2))
        return -0.5 * dot(self.impulse, before + after)

    @cached_property
    def energy_loss_percent(self) -> np.ndarray:
        """Energy lost as a percentage of the kinetic energy before impact [%]."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return 100.0 * self.energy_loss / self.kinetic_energy_before

    @cached_property
    def total_loss_brach(self) -> np.ndarray:
        """Brach's closed-form total impact loss T_L [J], equal to :attr:`energy_loss`.

        T_L = (1/2) m_c q v_rn^2 (1 + eps) [2 + 2 mu r - (1 + eps) q (A - 2 mu B + mu^2 (1 + C))]
        (the sheet's T_L with the m_c d_e^2, d_f^2 sum expanded), written with
        v_rn^2 r = u_n u_t so that it stays finite as u_n -> 0.
        """
        mu, q = self.mu, self.q
        u_n, u_t = self.approach_n, self.approach_t
        e1 = 1.0 + self.eps
        bracket = (2.0 * u_n * u_n + 2.0 * mu * u_n * u_t
                   - e1 * q * u_n * u_n * (self.A - 2.0 * mu * self.B + mu * mu * (1.0 + self.C)))
        loss = 0.5 * self.reduced_mass * q * e1 * bracket
        return np.where(self.approaching, loss, 0.0)

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

    # ---- direction of force ------------------------------------------------------------------
    @cached_property
    def impulse_angle(self) -> np.ndarray:
        """Direction of the impulse on vehicle 1 from +x [rad]."""
        return np.arctan2(self.impulse[..., 1], self.impulse[..., 0])

    @cached_property
    def pdof1(self) -> np.ndarray:
        """PDOF of vehicle 1 [rad], clockwise from its heading; 0 = frontal (see pdof)."""
        return pdof(self.impulse, self.case.vehicle1.heading)

    @cached_property
    def pdof2(self) -> np.ndarray:
        """PDOF of vehicle 2 [rad], clockwise from its heading; 0 = frontal."""
        return pdof(-self.impulse, self.case.vehicle2.heading)

    @cached_property
    def clock1(self) -> np.ndarray:
        """PDOF of vehicle 1 as a clock position, 12 = frontal, 3 = right side."""
        return clock_position(self.pdof1)

    @cached_property
    def clock2(self) -> np.ndarray:
        """PDOF of vehicle 2 as a clock position, 12 = frontal, 3 = right side."""
        return clock_position(self.pdof2)

    # ---- admissibility -------------------------------------------------------------------
    @cached_property
    def normal_impulse_positive(self) -> np.ndarray:
        """Pn > 0: the contact pushes (a negative Pn would pull the vehicles together)."""
        return self.impulse_n > 0

    @cached_property
    def energy_not_gained(self) -> np.ndarray:
        """Kinetic energy does not rise (loss >= 0 within round-off)."""
        tol = 1e-9 * self.kinetic_energy_before
        return self.energy_loss >= -tol

    @cached_property
    def within_critical(self) -> np.ndarray:
        """|mu| <= |mu0| (0 <= beta <= 1): no reversal of tangential sliding at C."""
        return (self.beta >= 0) & (self.beta <= 1)

    @cached_property
    def friction_opposes_sliding(self) -> np.ndarray:
        """Pt U_t <= 0: the tangential impulse does not point along the slip left at C.

        With beta < 1 and strong n-t coupling, PIM's mu = beta mu0 can push along the
        post-impact sliding, which Coulomb friction cannot (and a simulator will not) do.
        """
        scale = np.abs(self.impulse_t) * (np.abs(self.approach_n) + np.abs(self.approach_t))
        return self.impulse_t * self.separation_t <= 1e-9 * scale

    @cached_property
    def admissible(self) -> np.ndarray:
        """All flags hold: approach, Pn > 0, no energy gain, |mu| <= |mu0|, friction opposing
        the remaining slip, finite q."""
        return (self.approaching & self.normal_impulse_positive & self.energy_not_gained
                & self.within_critical & self.friction_opposes_sliding & ~self.q_singular)

    def problems(self) -> list[str]:
        """Plain-language reasons why any element is inadmissible (empty when all are fine)."""
        checks = [
            (self.approaching, "the vehicles do not approach at C (u_n >= 0): no impact"),
            (~self.q_singular, "q is singular (A - mu B = 0): the impulse is unbounded"),
            (self.normal_impulse_positive | ~self.approaching,
             "the normal impulse is not positive (the contact would pull)"),
            (self.energy_not_gained, "kinetic energy is gained"),
            (self.friction_opposes_sliding | ~self.approaching,
             "the tangential impulse points along the remaining slip at C (not Coulomb friction)"),
            # Sliding reverses only where beta > 1 and there is sliding to reverse (Pt0 != 0);
            # beta < 0 makes the tangential impulse drive the sliding instead.
            (np.broadcast_to((self.beta <= 1) | (self.critical_impulse_t == 0),
                             np.shape(self.impulse_n)),
             "|mu| > |mu0| (beta > 1): tangential sliding at C reverses"),
            (np.broadcast_to((self.beta >= 0) | (self.critical_impulse_t == 0),
                             np.shape(self.impulse_n)),
             "beta < 0: the tangential impulse drives the sliding at C instead of opposing it"),
        ]
        out = []
        for ok, text in checks:
            ok = np.asarray(ok)
            bad = int(np.size(ok) - np.count_nonzero(ok))
            if bad:
                out.append(text if ok.size == 1 else f"{text} ({bad} of {ok.size} cases)")
        return out
