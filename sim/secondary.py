"""Plausibility after the impact: do the outlines run into each other again?

PIM models one impact. After separation the vehicles move apart, but with yaw (or a slow
separation) the outlines may close in again: a secondary impact PIM does not model, which a
rigid-body animation would otherwise draw as cars passing through each other.
:func:`find_secondary_impact` watches the overlap area of the two outlines along a recorded
trajectory after separation: the outlines may still overlap at separation (permanent crush,
or the illustrative outlines of a case placed at PIM's impact configuration), so a
secondary impact is reported when the overlap *grows again* after separation, by more than
``tolerance`` (a fraction of the smaller outline's area) above its smallest value since
separation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pim.model.numbers import InputError

from .overlap import overlap_area, place

__all__ = ["SecondaryImpact", "find_secondary_impact", "DEFAULT_TOLERANCE"]

#: Growth of the overlap area, as a fraction of the smaller outline's area, that counts.
DEFAULT_TOLERANCE = 0.005


@dataclass(frozen=True)
class SecondaryImpact:
    """A second contact of the outlines after separation.

    Attributes
    ----------
    time : float
        First recorded time [s] at which the overlap has grown by the tolerance.
    index : int
        Its index in the trajectory.
    overlap : float
        Overlap area then [m^2].
    """

    time: float
    index: int
    overlap: float

    def message(self) -> str:
        """One sentence for reports and animations."""
        return (f"secondary impact at t = {self.time:.3f} s: the outlines run into each other "
                f"again after separation (PIM models one impact; the motion after this is not "
                f"PIM's)")


def find_secondary_impact(trajectory, start_index: int | None = None,
                          tolerance: float = DEFAULT_TOLERANCE) -> SecondaryImpact | None:
    """First secondary impact along ``trajectory`` after ``start_index``, or None.

    Parameters
    ----------
    trajectory : sim.Trajectory
        Recorded motion with both outlines (None is returned without them).
    start_index : int, optional
        Index of the separation state (default: ``trajectory.impact_index``).
    tolerance : float
        Overlap growth that counts, as a fraction [-] of the smaller outline's area, > 0.
    """
    if not tolerance > 0:
        raise InputError(f"tolerance must be > 0, got {tolerance!r}")
    o1, o2 = trajectory.outline1, trajectory.outline2
    if o1 is None or o2 is None:
        return None
    start = trajectory.impact_index if start_index is None else int(start_index)
    areas = [float(np.prod(np.ptp(o, axis=0))) for o in (o1, o2)]
    threshold = tolerance * min(areas)
    lowest = np.inf
    for i in range(start, len(trajectory.time)):
        poly1 = place(o1, trajectory.position1[i], trajectory.angle1[i])
        poly2 = place(o2, trajectory.position2[i], trajectory.angle2[i])
        area = overlap_area(poly1, poly2)
        lowest = min(lowest, area)
        if area > lowest + threshold:
            return SecondaryImpact(float(trajectory.time[i]), i, area)
    return None
