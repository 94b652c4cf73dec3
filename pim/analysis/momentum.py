"""Linear-momentum check of a reconstruction: the classic two-equation solve for two speeds.

With the pre-impact directions ``u1``, ``u2`` known (unit vectors) and the post-impact
velocities ``V1'``, ``V2'`` measured, conservation of linear momentum over the impact
(no external impulse; PIM's and every impact model's first law) gives two scalar equations
for the two speeds:

``m1 s1 u1 + m2 s2 u2 = m1 V1' + m2 V2'``   i.e.   ``A s = P'`` with ``A = [m1 u1, m2 u2]``.

The solve degrades as ``u1`` and ``u2`` become collinear (``det A = m1 m2 (u1 x u2)``); the
standard deviations propagated from those of ``V1'`` and ``V2'`` through ``A^-1`` say so
(they grow as ``1 / |sin(angle between u1 and u2)|``), rather than a falsely precise number.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.geometry import cross
from ..model.numbers import InputError, speed_text

__all__ = ["MomentumSpeeds", "momentum_speeds", "ILL_CONDITIONED_SINE"]

#: Below this |sin| of the angle between the approach directions the solve is flagged.
ILL_CONDITIONED_SINE = 0.1


@dataclass(frozen=True)
class MomentumSpeeds:
    """Pre-impact speeds from linear momentum (SI).

    Attributes
    ----------
    speed1, speed2 : float [m/s] along ``u1`` and ``u2`` (negative: against it)
    sigma1, sigma2 : float [m/s] standard deviations propagated from the post-impact ones
    sine : float, |sin| of the angle between the approach directions
    ill_conditioned : bool, ``sine < ILL_CONDITIONED_SINE``
    message : str
    """

    speed1: float
    speed2: float
    sigma1: float
    sigma2: float
    sine: float
    ill_conditioned: bool
    message: str


def momentum_speeds(mass1, mass2, direction1, direction2, velocity1_after, velocity2_after,
                    velocity1_sigma=0.0, velocity2_sigma=0.0) -> MomentumSpeeds:
    """Solve ``m1 s1 u1 + m2 s2 u2 = m1 V1' + m2 V2'`` for the speeds ``s1``, ``s2``.

    Parameters
    ----------
    mass1, mass2 : float
        [kg].
    direction1, direction2 : array_like (2,)
        Pre-impact directions of travel (normalised here).
    velocity1_after, velocity2_after : array_like (2,)
        Post-impact CG velocities [m/s].
    velocity1_sigma, velocity2_sigma : float or (2, 2) array
        Standard deviation [m/s] of each component (isotropic) or the covariance [m^2/s^2].

    Returns
    -------
    MomentumSpeeds
    """
    u1 = np.asarray(direction1, dtype=float)
    u2 = np.asarray(direction2, dtype=float)
    for name, u in (("direction1", u1), ("direction2", u2)):
        if not (np.all(np.isfinite(u)) and np.hypot(*u) > 0):
            raise InputError(f"momentum.{name} must be a finite non-zero vector, got {u!r}")
    u1, u2 = u1 / np.hypot(*u1), u2 / np.hypot(*u2)
    m1, m2 = float(mass1), float(mass2)
    a = np.column_stack([m1 * u1, m2 * u2])
    p_after = m1 * np.asarray(velocity1_after, dtype=float) + m2 * np.asarray(
        velocity2_after, dtype=float)
    sine = float(abs(cross(u1, u2)))

    def cov(sigma):
        sigma = np.asarray(sigma, dtype=float)
        return sigma if sigma.shape == (2, 2) else np.eye(2) * float(sigma) ** 2

    cov_p = m1 * m1 * cov(velocity1_sigma) + m2 * m2 * cov(velocity2_sigma)
    if sine < 1e-12:
        return MomentumSpeeds(np.nan, np.nan, np.inf, np.inf, sine, True,
                              "the approach directions are collinear: linear momentum gives "
                              "one equation for two speeds (under-determined)")
    inv = np.linalg.inv(a)
    speeds = inv @ p_after
    cov_s = inv @ cov_p @ inv.T
    ill = sine < ILL_CONDITIONED_SINE
    message = (f"near-collinear approach (|sin| = {sine:.3g}): the momentum speeds are "
               f"ill-conditioned, +-{speed_text(np.sqrt(cov_s[0, 0]), '.3g')} and "
               f"+-{speed_text(np.sqrt(cov_s[1, 1]), '.3g')}" if ill else "")
    return MomentumSpeeds(float(speeds[0]), float(speeds[1]), float(np.sqrt(cov_s[0, 0])),
                          float(np.sqrt(cov_s[1, 1])), sine, ill, message)
