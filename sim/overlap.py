"""Overlap of two vehicle outlines (convex polygons): clipping, area, centroid, and the
contact normal of the outline crush model.

The arithmetic is written once, on floats, in :mod:`sim.compliant_formula` (the pymunk scene
and the compiled integrator run it there); the functions here take and give numpy arrays:

* :func:`clip_convex`: Sutherland-Hodgman clipping of one convex polygon by another;
* :func:`polygon_area_centroid`: shoelace area and centroid;
* :func:`separating_axis`: the edge normal of either outline along which the outlines
  overlap least (the separating-axis test of rigid-body engines), oriented from vehicle 2
  toward vehicle 1, and that overlap [m];
* :func:`outline_overlap`: all of it for two placed rectangles, as the outline contact of
  :mod:`sim.compliant` uses it (docs/contact-model.md);
* :func:`place`: body-frame corners to world corners.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import compliant_formula as formula

__all__ = ["place", "clip_convex", "polygon_area_centroid", "separating_axis", "Overlap",
           "outline_overlap", "overlap_area"]


def place(corners: np.ndarray, position, angle: float) -> np.ndarray:
    """World coordinates (N, 2) [m] of body-frame ``corners`` at ``position``, ``angle``."""
    c, s = np.cos(angle), np.sin(angle)
    x, y = corners[:, 0], corners[:, 1]
    return np.stack([position[0] + c * x - s * y, position[1] + s * x + c * y], axis=-1)


def _work(*polygons) -> tuple[list, list]:
    """A work list holding ``polygons`` ((m, 2) each) and two clipping buffers; the offsets
    of the polygons and of the buffers."""
    wk, offsets = [], []
    for poly in polygons:
        offsets.append(len(wk))
        wk += np.asarray(poly, dtype=float).reshape(-1).tolist()
    room = 2 * sum(len(p) for p in polygons) + 4
    offsets += [len(wk), len(wk) + room]
    return wk + [0.0] * (2 * room), offsets


def _polygon(wk, offset: int, count: int) -> np.ndarray:
    return np.array(wk[offset:offset + 2 * count], dtype=float).reshape(count, 2)


def clip_convex(subject: np.ndarray, clipper: np.ndarray) -> np.ndarray:
    """Intersection (M, 2) of convex polygon ``subject`` with convex ``clipper`` [m]
    (:func:`sim.compliant_formula.clip_polygon`).

    Both counter-clockwise; an empty (0, 2) array when they do not overlap.
    """
    wk, (p1, p2, a, b) = _work(subject, clipper)
    offset, count = formula.clip_polygon(wk, p1, len(subject), p2, len(clipper), a, b)
    return _polygon(wk, offset, count)


def polygon_area_centroid(poly: np.ndarray) -> tuple[float, np.ndarray]:
    """Area [m^2] (>= 0 for counter-clockwise) and centroid (2,) [m] of a polygon
    (:func:`sim.compliant_formula.area_centroid`)."""
    wk, (p, _, _) = _work(poly)
    area, cx, cy = formula.area_centroid(wk, p, len(poly))
    return area, np.array([cx, cy])


def separating_axis(poly1: np.ndarray, poly2: np.ndarray) -> tuple[np.ndarray, float]:
    """Unit normal n (from polygon 2 toward polygon 1) of least overlap, and the overlap [m].

    The candidate axes are the edge normals of both polygons; along each the projections'
    overlap is min(max1 - min2, max2 - min1); the smallest wins. A negative overlap means
    the polygons are apart along that axis (:func:`sim.compliant_formula.separating_axis`).
    """
    wk, (p1, p2, _, _) = _work(poly1, poly2)
    nx, ny, depth = formula.separating_axis(wk, p1, len(poly1), p2, len(poly2))
    return np.array([nx, ny]), depth


@dataclass(frozen=True)
class Overlap:
    """The overlap of two outlines, as the outline contact model reads it.

    Attributes
    ----------
    area : float
        Overlap area [m^2] (0: apart).
    centroid : ndarray (2,)
        Its centroid [m], where the crush force acts.
    normal : ndarray (2,)
        Contact normal (from vehicle 2 toward vehicle 1), the separating axis of least
        overlap.
    width : float
        Extent of the overlap along the tangent (normal turned +90 deg) [m].
    depth : float
        Mean crush depth area / width [m] (the delta of the contact law).
    axis_depth : float
        Overlap of the outlines along the normal [m] (the largest crush anywhere).
    """

    area: float
    centroid: np.ndarray
    normal: np.ndarray
    width: float
    depth: float
    axis_depth: float


def overlap_area(poly1: np.ndarray, poly2: np.ndarray) -> float:
    """Area [m^2] of the overlap of two convex counter-clockwise polygons."""
    return polygon_area_centroid(clip_convex(poly1, poly2))[0]


def outline_overlap(poly1: np.ndarray, poly2: np.ndarray) -> Overlap:
    """:class:`Overlap` of two convex counter-clockwise polygons in world coordinates
    (:func:`sim.compliant_formula.outline_overlap`)."""
    wk, (p1, p2, a, b) = _work(poly1, poly2)
    area, cx, cy, nx, ny, width, depth, axis_depth = formula.outline_overlap(
        wk, p1, len(poly1), p2, len(poly2), a, b)
    return Overlap(area, np.array([cx, cy]), np.array([nx, ny]), width, depth, axis_depth)
