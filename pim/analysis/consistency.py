"""Momentum consistency of measured pre/post-impact data, checked before any fit.

In a two-vehicle impact with negligible external impulse (tyre forces during the ~0.1 s
contact), the impulses on the two vehicles are equal and opposite:

    m1 dv1 + m2 dv2 = 0                                          (linear momentum)
    I_i dw_i = ((C - G_i) x P_i) . k ,  P_i = m_i dv_i            (angular momentum about G_i)

Measured data that break the first equation cannot be reproduced by *any* PIM coefficients;
fitted coefficients of such a test absorb the measurement error. Three measures per test:

* ``impulse_ratio``: m1 |dv1| / (m2 |dv2|) - 1 from *published delta-V magnitudes* (for RICSAC
  the Brach & Smith 2002 corrected values); 0 when balanced.
* ``linear_imbalance``: |m1 dv1 + m2 dv2| / max(|m1 dv1|, |m2 dv2|) from the measured pre- and
  post-impact velocity *vectors*; 0 when balanced.
* ``arm1``, ``arm2``: the distance of the impulse's line of action from each CG implied by
  the angular balance, I_i |dw_i| / |P_i| [m] (P_i = m_i dv_i); both must be below the
  vehicle's half-diagonal for a common impact point C to exist (the CG-to-C distances are not
  published, so the angular balance can only bound them). Pre-impact yaw rates are taken
  as 0 (staged tests).

A test is flagged when either linear measure exceeds ``tolerance`` (default 15 %) or an
implied arm exceeds ``max_arm`` (default 3 m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.numbers import InputError, unit_text

__all__ = ["MomentumCheck", "CrashTestVehicle", "momentum_check", "check_ricsac",
           "DEFAULT_TOLERANCE", "DEFAULT_MAX_ARM"]

DEFAULT_TOLERANCE = 0.15   # relative imbalance [-]
DEFAULT_MAX_ARM = 3.0      # m: about half the diagonal of a large car


@dataclass(frozen=True)
class CrashTestVehicle:
    """One vehicle's measured data in a crash test, as :func:`momentum_check` reads them
    (SI; what a test does not publish is None).

    Attributes
    ----------
    mass : float
        [kg].
    delta_v : float or None
        Published delta-V magnitude [m/s] (for ``impulse_ratio``).
    velocity_pre, velocity_post : array_like (2,) or None
        Measured velocities before and after the impact [m/s] (for ``linear_imbalance``
        and the arm).
    yaw_inertia : float or None
        [kg m^2].
    yaw_rate_change : float or None
        [rad/s].
    """

    mass: float
    delta_v: float | None = None
    velocity_pre: object = None
    velocity_post: object = None
    yaw_inertia: float | None = None
    yaw_rate_change: float | None = None

    def momentum_change(self) -> np.ndarray | None:
        """m (v_post - v_pre) [kg m/s], or None without both velocities."""
        if self.velocity_pre is None or self.velocity_post is None:
            return None
        return self.mass * (np.asarray(self.velocity_post, float)
                            - np.asarray(self.velocity_pre, float))

    def arm(self, impulse: float) -> float | None:
        """I |dw| / P [m] for an impulse of magnitude ``impulse`` [N s] (None without the
        yaw inertia or the yaw-rate change)."""
        if self.yaw_inertia is None or self.yaw_rate_change is None:
            return None
        return float(self.yaw_inertia * abs(self.yaw_rate_change) / impulse)


@dataclass(frozen=True)
class MomentumCheck:
    """The momentum balance of one test (module notes); ``flagged`` names what failed.

    Attributes
    ----------
    test : str
        Test name for the report.
    impulse_ratio : float or None
        m1 |dv1| / (m2 |dv2|) - 1 from the published delta-V magnitudes [-] (None without
        them).
    linear_imbalance : float or None
        |m1 dv1 + m2 dv2| / max(|m1 dv1|, |m2 dv2|) from the measured velocity vectors [-]
        (None without them).
    arm1, arm2 : float or None
        Distance of the impulse's line of action from each CG implied by the angular
        balance, I_i |dw_i| / P [m] (P the mean of |m1 dv1| and |m2 dv2|; None without the
        velocities, yaw inertia or yaw-rate change).
    tolerance : float
        Largest allowed ``|impulse_ratio|`` and ``linear_imbalance`` [-].
    max_arm : float
        Largest allowed arm [m].
    reasons : list of str
        Why the test is inconsistent, in words (property; empty when it is not).
    flagged : bool
        True when any reason applies (property).
    """

    test: str
    impulse_ratio: float | None
    linear_imbalance: float | None
    arm1: float | None
    arm2: float | None
    tolerance: float
    max_arm: float

    @property
    def reasons(self) -> list[str]:
        """Plain-language reasons why the test is inconsistent (empty when it is not)."""
        out = []
        if self.impulse_ratio is not None and abs(self.impulse_ratio) > self.tolerance:
            out.append(f"m1|dV1|/(m2|dV2|) off by {100 * self.impulse_ratio:+.1f} %")
        if self.linear_imbalance is not None and self.linear_imbalance > self.tolerance:
            out.append(f"linear momentum of measured velocities off by "
                       f"{100 * self.linear_imbalance:.1f} %")
        for i, arm in ((1, self.arm1), (2, self.arm2)):
            if arm is not None and arm > self.max_arm:
                out.append(f"angular balance puts the impulse "
                           f"{unit_text(arm, 'length', '.3g')} from CG{i} "
                           f"(> {unit_text(self.max_arm, 'length', '.3g')})")
        return out

    @property
    def flagged(self) -> bool:
        """True when the measured data break momentum balance beyond the tolerances."""
        return bool(self.reasons)


def momentum_check(test, vehicle1: CrashTestVehicle, vehicle2: CrashTestVehicle, *,
                   tolerance=DEFAULT_TOLERANCE, max_arm=DEFAULT_MAX_ARM) -> MomentumCheck:
    """Momentum balance of one test's measured data.

    Parameters
    ----------
    test : str
        Test name for the report.
    vehicle1, vehicle2 : CrashTestVehicle
        Each vehicle's mass and what the test measured of it.
    tolerance : float
        Largest allowed ``|impulse_ratio|`` and ``linear_imbalance`` [-].
    max_arm : float
        Largest allowed arm [m].
    """
    v1, v2 = vehicle1, vehicle2
    if not (v1.mass > 0 and v2.mass > 0):
        raise InputError(f"{test}: masses must be > 0 [kg]")
    ratio = None
    if v1.delta_v is not None and v2.delta_v is not None and v2.delta_v > 0:
        ratio = v1.mass * v1.delta_v / (v2.mass * v2.delta_v) - 1.0
    imbalance = arm1 = arm2 = None
    p1, p2 = v1.momentum_change(), v2.momentum_change()
    if p1 is not None and p2 is not None:
        scale = max(np.hypot(*p1), np.hypot(*p2))
        if scale > 0:
            imbalance = float(np.hypot(*(p1 + p2)) / scale)
            impulse = 0.5 * (np.hypot(*p1) + np.hypot(*p2))
            arm1, arm2 = v1.arm(impulse), v2.arm(impulse)
    return MomentumCheck(str(test), ratio, imbalance, arm1, arm2, tolerance, max_arm)


def check_ricsac(tests, tolerance=DEFAULT_TOLERANCE, max_arm=DEFAULT_MAX_ARM,
                 analysis="BrachSmith2002") -> list[MomentumCheck]:
    """:func:`momentum_check` of every RICSAC test with data (:func:`pim.io.datasets.load_ricsac`).

    ``analysis`` names the published delta-V magnitudes used for ``impulse_ratio``.
    """
    out = []
    for t in tests:
        dv1, dv2 = t.published_delta_v.get(analysis, (None, None))
        if dv1 is None and not t.has_motion:
            continue
        vehicles = [CrashTestVehicle(
            mass=getattr(t, f"mass{i}"), delta_v=dv, velocity_pre=getattr(t, f"velocity{i}_pre"),
            velocity_post=getattr(t, f"velocity{i}_post"),
            yaw_inertia=getattr(t, f"yaw_inertia{i}"),
            yaw_rate_change=getattr(t, f"yaw_rate{i}_post"))     # staged: no yaw before
            for i, dv in ((1, dv1), (2, dv2))]
        out.append(momentum_check(f"RICSAC {t.number}", *vehicles, tolerance=tolerance,
                                  max_arm=max_arm))
    return out
