"""Post-impact motion: the shape every producer of it shares, and its typed terms.

Three things in the project hold the motion of two vehicles after an impact: the solver's
:class:`pim.Result`, the measured values :class:`pim.Measured` (the ``[measured]`` table, or
the run-out fits of a reconstruction) and a simulation's result (``sim.SimResult``). Each has
``velocity1``, ``velocity2`` [m/s, (..., 2)] and ``yaw_rate1``, ``yaw_rate2`` [rad/s]:
:class:`PostImpactMotion` names that shape, so a fit, a reconstruction or a comparison takes
any of them.

A fit compares such motions term by term. A :class:`Term` names one scalar of it, e.g.
``Term(1, "vx")`` is vehicle 1's post-impact x velocity, and reads it from any
:class:`PostImpactMotion` (:meth:`Term.of`) and its standard deviation from a
:class:`pim.Measured` (:meth:`Term.sigma_of`). Its :attr:`Term.name` is the string the
outputs use (``"velocity1_x"``, ``"yaw_rate2"``; the rows of
:data:`pim.model.dual.MOTION_OUTPUTS`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Protocol, runtime_checkable

import numpy as np

from .geometry import radius_of_gyration
from .numbers import InputError

__all__ = ["PostImpactMotion", "MotionValues", "Term", "QUANTITIES", "TERMS", "as_terms",
           "velocity_changes", "impact_error"]

#: The scalar quantities of one vehicle's post-impact motion: CG velocity x and y [m/s] and
#: yaw rate [rad/s].
QUANTITIES = ("vx", "vy", "omega")


@runtime_checkable
class PostImpactMotion(Protocol):
    """Velocities and yaw rates of both vehicles after the impact (SI).

    Attributes
    ----------
    velocity1, velocity2 : array_like (..., 2) or None
        Post-impact CG velocities [m/s] (None where not known, e.g. not measured).
    yaw_rate1, yaw_rate2 : array_like or None
        Post-impact yaw rates [rad/s].
    """

    velocity1: object
    velocity2: object
    yaw_rate1: object
    yaw_rate2: object


@dataclass(frozen=True)
class MotionValues:
    """Plain post-impact motion (a :class:`PostImpactMotion`): arrays as given, unchecked
    (NaN allowed, e.g. for failed simulation runs) [m/s, rad/s].

    Attributes
    ----------
    velocity1, velocity2 : array_like
        Post-impact CG velocities of vehicles 1 and 2, shape (..., 2) [m/s].
    yaw_rate1, yaw_rate2 : array_like
        Post-impact yaw rates of vehicles 1 and 2, CCW positive [rad/s].
    """

    velocity1: object
    velocity2: object
    yaw_rate1: object
    yaw_rate2: object


def velocity_changes(case, motion: PostImpactMotion) -> np.ndarray:
    """(dV1x, dV1y, dV2x, dV2y, k1 dW1, k2 dW2) [m/s] of ``motion`` against the single
    ``case``'s pre-impact motion, shape (..., 6); k_i = sqrt(I_i / m_i) the radius of
    gyration, so a yaw-rate change counts as the speed it gives a point at k_i from the CG.
    A fixed obstacle's changes are 0."""
    a, b = case.vehicle1, case.vehicle2
    d1 = np.asarray(motion.velocity1, float) - np.asarray(a.velocity, float).reshape(2)
    d2 = np.asarray(motion.velocity2, float) - np.asarray(b.velocity, float).reshape(2)
    if bool(np.all(b.fixed)):
        d2 = np.zeros_like(d2)
    k1 = float(radius_of_gyration(a.mass, a.yaw_inertia))
    k2 = float(radius_of_gyration(b.mass, b.yaw_inertia))
    e1 = k1 * (np.asarray(motion.yaw_rate1, float) - float(np.asarray(a.yaw_rate).reshape(())))
    e2 = (k2 * (np.asarray(motion.yaw_rate2, float) - float(np.asarray(b.yaw_rate).reshape(())))
          if k2 else np.zeros_like(e1))
    return np.concatenate([d1, d2, np.asarray(e1)[..., None], np.asarray(e2)[..., None]], -1)


def impact_error(case, reference: PostImpactMotion, other: PostImpactMotion) -> np.ndarray:
    """The project's one error measure: the largest error in the impact's velocity changes,
    relative to the largest change [-],

        e = max(|dV1' - dV1|, |dV2' - dV2|, k1 |dW1' - dW1|, k2 |dW2' - dW2|)
            / max(|dV1|, |dV2|, k1 |dW1|, k2 |dW2|)

    (component-wise maxima, :func:`velocity_changes`; ``reference`` a single motion, e.g.
    the analytic :class:`pim.Result`, ``other`` any batch shape, e.g. simulations).
    Measured against the change rather than the speed, a grazing impact (tiny impulse, large
    speeds) stays honest: a 1e-6 error in its impulse is a 1e-6 error, not 1e-10 of the
    speed. NaN where ``other`` is NaN."""
    ref = velocity_changes(case, MotionValues(
        np.asarray(reference.velocity1, float).reshape(2),
        np.asarray(reference.velocity2, float).reshape(2),
        float(np.asarray(reference.yaw_rate1).reshape(())),
        float(np.asarray(reference.yaw_rate2).reshape(()))))
    scale = max(float(np.abs(ref).max()), 1e-300)
    return np.max(np.abs(velocity_changes(case, other) - ref), axis=-1) / scale


@dataclass(frozen=True, order=True)
class Term:
    """One scalar of the post-impact motion: a residual term of a fit.

    Attributes
    ----------
    vehicle : int
        1 or 2.
    quantity : {"vx", "vy", "omega"}
        CG velocity x or y [m/s], or yaw rate [rad/s].
    """

    vehicle: int
    quantity: Literal["vx", "vy", "omega"]

    def __post_init__(self) -> None:
        if self.vehicle not in (1, 2):
            raise InputError(f"Term.vehicle must be 1 or 2, got {self.vehicle!r}")
        if self.quantity not in QUANTITIES:
            raise InputError(f"Term.quantity must be one of {', '.join(QUANTITIES)}, "
                             f"got {self.quantity!r}")

    @property
    def is_velocity(self) -> bool:
        """True for a velocity component, False for a yaw rate."""
        return self.quantity != "omega"

    @property
    def axis(self) -> int | None:
        """0 for x, 1 for y, None for the yaw rate."""
        return {"vx": 0, "vy": 1}.get(self.quantity)

    @property
    def field(self) -> str:
        """The attribute of a :class:`PostImpactMotion` that holds it."""
        return f"{'velocity' if self.is_velocity else 'yaw_rate'}{self.vehicle}"

    @property
    def name(self) -> str:
        """Output name, e.g. ``velocity1_x`` or ``yaw_rate2``."""
        return self.field + {"vx": "_x", "vy": "_y", "omega": ""}[self.quantity]

    @property
    def group(self) -> str:
        """The piece of evidence it belongs to: the vehicle's post-impact motion."""
        return f"vehicle{self.vehicle} post-impact motion"

    @property
    def unit(self) -> str:
        """SI unit of the quantity."""
        return "m/s" if self.is_velocity else "rad/s"

    @property
    def kind(self) -> str:
        """Unit kind (:mod:`pim.io.units`) of the quantity."""
        return "velocity" if self.is_velocity else "angular_velocity"

    def of(self, motion: PostImpactMotion) -> np.ndarray:
        """The term's value in ``motion`` [m/s or rad/s], any batch shape (NaN if absent)."""
        value = getattr(motion, self.field)
        if value is None:
            return np.asarray(np.nan)
        value = np.asarray(value, dtype=float)
        return value[..., self.axis] if self.is_velocity else value

    def sigma_of(self, measured) -> float | None:
        """Standard deviation of the term in a :class:`pim.Measured` [SI], or None."""
        sigma = getattr(measured, self.field + "_sigma", None)
        if sigma is None:
            return None
        sigma = np.asarray(sigma, dtype=float)
        return float(sigma[self.axis] if self.is_velocity else sigma.reshape(()))

    def __str__(self) -> str:
        return self.name


#: Every term, in output order (vehicle 1 then 2; x, y, yaw rate).
TERMS = tuple(Term(i, q) for i in (1, 2) for q in QUANTITIES)
_BY_NAME = {t.name: t for t in TERMS}


def as_terms(terms) -> tuple[Term, ...]:
    """Terms from :class:`Term` objects or their names (``"velocity1_x"``, ``"yaw_rate2"``)."""
    out = []
    for t in terms:
        if isinstance(t, Term):
            out.append(t)
        elif t in _BY_NAME:
            out.append(_BY_NAME[t])
        else:
            raise InputError(f"unknown post-impact term {t!r} (allowed: "
                             f"{', '.join(_BY_NAME)})")
    return tuple(out)
