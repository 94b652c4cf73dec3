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

__all__ = ["PostImpactMotion", "Term", "QUANTITIES", "TERMS", "as_terms"]

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
            raise ValueError(f"Term.vehicle must be 1 or 2, got {self.vehicle!r}")
        if self.quantity not in QUANTITIES:
            raise ValueError(f"Term.quantity must be one of {', '.join(QUANTITIES)}, "
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
            raise ValueError(f"unknown post-impact term {t!r} (allowed: "
                             f"{', '.join(_BY_NAME)})")
    return tuple(out)
