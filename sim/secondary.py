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

from pim.io.units import convert, quantity_text
from pim.model.geometry import outline_penetration
from pim.model.numbers import InputError

from .failures import SimulationError
from .kudlich_slibar import engine_friction, simulate_kudlich_slibar
from .overlap import clip_convex, overlap_area, place, polygon_area_centroid
from .run import simulate
from .settings import Settings

__all__ = ["SecondaryImpact", "find_secondary_impact", "DEFAULT_TOLERANCE", "part_of",
           "watch_after_impact", "WATCH_AFTER", "watch_after_check"]

#: Seconds of free motion after the impact that ``pim sim`` watches for a secondary contact
#: (the animation's default span after the impact).
WATCH_AFTER = 2.0

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
    point : ndarray (2,) or None
        Where: the centroid of the overlap then [m], global frame.
    parts : tuple of str
        Which parts meet: vehicle 1's and vehicle 2's (:func:`part_of`), e.g.
        ("front right", "left side").
    """

    time: float
    index: int
    overlap: float
    point: np.ndarray | None = None
    parts: tuple = ()

    def message(self, units: str = "si") -> str:
        """One sentence for reports, animations and the command line: when (t = 0 is the
        impact), where (the centroid of the new overlap, in ``units``) and which parts of
        the vehicles meet."""
        where = ""
        if self.point is not None:
            show = quantity_text(units)
            x, y = (show(float(c), "length") for c in self.point)
            where = f" at (x, y) = ({x}, {y})"
        if self.parts:
            where += f", vehicle 1's {self.parts[0]} against vehicle 2's {self.parts[1]}"
        return (f"secondary impact at t = {self.time:.3f} s after the impact{where}: the "
                f"outlines run into each other again after separation (PIM models one "
                f"impact; the motion after this is not PIM's)")

    def to_json(self, units: str = "si") -> dict:
        """Time [s], place (x, y) in ``units``' length unit, the parts and the message."""
        xy, unit = convert(self.point if self.point is not None else [np.nan, np.nan],
                           "length", units)
        return {"time": self.time, "x": float(xy[0]), "y": float(xy[1]), "length_unit": unit,
                "parts": list(self.parts), "message": self.message(units)}


def part_of(corners: np.ndarray, position, angle: float, point) -> str:
    """The part of a body's outline (body-frame ``corners``, placed at ``position`` and
    ``angle`` [rad]) nearest the world ``point``: "front", "rear", "left side", "right side",
    or a corner ("front left" ...) when the point lies near both of its sides."""
    c, s = np.cos(angle), np.sin(angle)
    d = np.asarray(point, float) - np.asarray(position, float)
    x, y = c * d[0] + s * d[1], -s * d[0] + c * d[1]
    front, rear = corners[:, 0].max(), corners[:, 0].min()
    left, right = corners[:, 1].max(), corners[:, 1].min()
    along = "front" if x - rear > front - x else "rear"
    side = "left" if y - right > left - y else "right"
    gap_x = min(abs(front - x), abs(x - rear)) / max(front - rear, 1e-12)
    gap_y = min(abs(left - y), abs(y - right)) / max(left - right, 1e-12)
    if gap_x < 0.15 and gap_y < 0.15:
        return f"{along} {side}"
    return along if gap_x <= gap_y else f"{side} side"


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
    apart = _apart(trajectory)
    lowest = np.inf
    for i in range(start, len(trajectory.time)):
        if apart[i]:            # a separating axis: no overlap (the clipping is the cost)
            lowest = 0.0
            continue
        poly1 = place(o1, trajectory.position1[i], trajectory.angle1[i])
        poly2 = place(o2, trajectory.position2[i], trajectory.angle2[i])
        area = overlap_area(poly1, poly2)
        lowest = min(lowest, area)
        if area > lowest + threshold:
            point = polygon_area_centroid(clip_convex(poly1, poly2))[1]
            parts = tuple(part_of(o, p[i], a[i], point) for o, p, a in (
                (o1, trajectory.position1, trajectory.angle1),
                (o2, trajectory.position2, trajectory.angle2)))
            return SecondaryImpact(float(trajectory.time[i]), i, area, point, parts)
    return None


def _apart(trajectory) -> np.ndarray:
    """Per recorded state: the two rectangular outlines are apart (their separating-axis
    depth, :func:`pim.model.geometry.outline_penetration`, is <= 0), all states at once."""
    def box(corners, position, angle):
        front, rear = corners[:, 0].max(), corners[:, 0].min()
        return position, angle, front - rear, np.ptp(corners[:, 1]), front

    return outline_penetration(box(trajectory.outline1, trajectory.position1, trajectory.angle1),
                               box(trajectory.outline2, trajectory.position2,
                                   trajectory.angle2)) <= 0


def watch_after_impact(case, eps: float, beta: float, after: float = WATCH_AFTER,
                       dt: float = 1e-3) -> SecondaryImpact | None:
    """Play the rigid scene of ``case`` at (eps, beta) ``after`` seconds past the impact
    (free motion, no tyre friction, as the animation does) and return its secondary impact
    (:func:`find_secondary_impact`), or None (also when a vehicle has no outline).

    Raises :class:`sim.SimulationError` when the run fails.
    """
    settings = Settings(dt=dt, record=True, duration=after + 2 * dt)
    return find_secondary_impact(simulate(case, eps, beta, settings).trajectory)


def watch_after_check(case, check, after: float = WATCH_AFTER,
                      dt: float = 1e-3) -> tuple[SecondaryImpact | None, str]:
    """The secondary contact after the impact that ``check`` cross-checked, under the
    case's law: the rigid scene at the check's (eps, beta) played on
    (:func:`watch_after_impact`), or the Kudlich-Slibar two-phase run at its (k, mu_c)
    recorded ``after`` seconds past the impact.

    Returns
    -------
    (SecondaryImpact or None, str)
        The secondary impact (None: none within ``after`` s), and why it was not watched
        ("" when it was): a run that fails after the impact is said, not raised, since the
        cross-check itself succeeded.
    """
    try:
        if (case.impact.law or "brach") != "kudlich-slibar":
            return watch_after_impact(case, check.eps, check.beta, after, dt), ""
        settings = Settings(dt=dt, record=True, duration=after + 2 * dt)
        run = simulate_kudlich_slibar(case, check.k, engine_friction(check.mu_c), settings)
        return find_secondary_impact(run.trajectory), ""
    except SimulationError as exc:
        return None, (f"a secondary contact after the impact was not checked: the run on "
                      f"after the impact failed ({exc.kind})")
