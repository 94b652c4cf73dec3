"""Overlap of two vehicle outlines (convex polygons) with numpy: clipping, area, centroid,
and the contact normal of the outline crush model.

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

__all__ = ["place", "clip_convex", "polygon_area_centroid", "separating_axis", "Overlap",
           "outline_overlap", "overlap_area"]


def place(corners: np.ndarray, position, angle: float) -> np.ndarray:
    """World coordinates (N, 2) [m] of body-frame ``corners`` at ``position``, ``angle``."""
    c, s = np.cos(angle), np.sin(angle)
    x, y = corners[:, 0], corners[:, 1]
    return np.stack([position[0] + c * x - s * y, position[1] + s * x + c * y], axis=-1)


def clip_convex(subject: np.ndarray, clipper: np.ndarray) -> np.ndarray:
    """Intersection (M, 2) of convex polygon ``subject`` with convex ``clipper`` [m].

    Both counter-clockwise; an empty (0, 2) array when they do not overlap.
    """
    poly = subject
    n = len(clipper)
    for i in range(n):
        if len(poly) == 0:
            break
        a, b = clipper[i], clipper[(i + 1) % n]
        edge = b - a
        # signed distance (times |edge|) to the left of the edge: inside >= 0
        side = edge[0] * (poly[:, 1] - a[1]) - edge[1] * (poly[:, 0] - a[0])
        nxt = np.roll(poly, -1, axis=0)
        side_next = np.roll(side, -1)
        out = []
        for j in range(len(poly)):
            if side[j] >= 0:
                out.append(poly[j])
            if (side[j] >= 0) != (side_next[j] >= 0):
                f = side[j] / (side[j] - side_next[j])
                out.append(poly[j] + f * (nxt[j] - poly[j]))
        poly = np.array(out) if out else np.empty((0, 2))
    return poly


def polygon_area_centroid(poly: np.ndarray) -> tuple[float, np.ndarray]:
    """Area [m^2] (>= 0 for counter-clockwise) and centroid (2,) [m] of a polygon."""
    if len(poly) < 3:
        return 0.0, np.full(2, np.nan)
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * float(cross.sum())
    if area == 0.0:
        return 0.0, poly.mean(axis=0)
    cx = float(((x + xn) * cross).sum()) / (6.0 * area)
    cy = float(((y + yn) * cross).sum()) / (6.0 * area)
    return abs(area), np.array([cx, cy])


def _edge_normals(poly: np.ndarray) -> np.ndarray:
    edges = np.roll(poly, -1, axis=0) - poly
    normals = np.stack([edges[:, 1], -edges[:, 0]], axis=-1)     # outward for CCW
    return normals / np.linalg.norm(normals, axis=-1, keepdims=True)


def separating_axis(poly1: np.ndarray, poly2: np.ndarray) -> tuple[np.ndarray, float]:
    """Unit normal n (from polygon 2 toward polygon 1) of least overlap, and the overlap [m].

    The candidate axes are the edge normals of both polygons; along each the projections'
    overlap is min(max1 - min2, max2 - min1); the smallest wins. A negative overlap means
    the polygons are apart along that axis.
    """
    axes = np.concatenate([_edge_normals(poly1), _edge_normals(poly2)])
    p1 = poly1 @ axes.T                                           # (N1, A)
    p2 = poly2 @ axes.T
    forward = p2.max(axis=0) - p1.min(axis=0)    # overlap if 1 lies on the +axis side of 2
    backward = p1.max(axis=0) - p2.min(axis=0)   # overlap if 1 lies on the -axis side
    depth = np.minimum(forward, backward)
    k = int(np.argmin(depth))
    n = axes[k] if forward[k] <= backward[k] else -axes[k]
    return n, float(depth[k])


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
    """:class:`Overlap` of two convex counter-clockwise polygons in world coordinates."""
    region = clip_convex(poly1, poly2)
    area, centroid = polygon_area_centroid(region)
    normal, axis_depth = separating_axis(poly1, poly2)
    if area <= 0.0:
        return Overlap(0.0, centroid, normal, 0.0, 0.0, axis_depth)
    tangent = np.array([-normal[1], normal[0]])
    along = region @ tangent
    width = float(along.max() - along.min())
    depth = area / width if width > 0 else 0.0
    return Overlap(area, centroid, normal, width, depth, axis_depth)
