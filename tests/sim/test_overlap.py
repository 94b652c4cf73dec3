"""Outline overlap: clipping, area, centroid, separating axis (against closed forms)."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim import overlap as ov

BOX = np.array([[1.0, 0.5], [-1.0, 0.5], [-1.0, -0.5], [1.0, -0.5]])   # 2 m x 1 m, CCW


def test_area_and_centroid_of_a_rectangle():
    area, c = ov.polygon_area_centroid(ov.place(BOX, (3.0, -1.0), 0.7))
    assert area == pytest.approx(2.0, rel=1e-14)
    assert c == pytest.approx([3.0, -1.0], abs=1e-14)


def test_axis_aligned_overlap_is_the_intersection_box():
    a = ov.place(BOX, (0.0, 0.0), 0.0)
    b = ov.place(BOX, (1.5, 0.25), 0.0)          # overlap x in [0.5, 1], y in [-0.25, 0.5]
    o = ov.outline_overlap(a, b)
    assert o.area == pytest.approx(0.5 * 0.75, rel=1e-12)
    assert o.centroid == pytest.approx([0.75, 0.125], abs=1e-12)
    # least overlap along x (0.5 m) rather than y (0.75 m); n points from b toward a
    assert o.normal == pytest.approx([-1.0, 0.0], abs=1e-12)
    assert o.axis_depth == pytest.approx(0.5)
    assert o.width == pytest.approx(0.75) and o.depth == pytest.approx(0.5)


def test_apart_is_empty():
    a = ov.place(BOX, (0.0, 0.0), 0.0)
    b = ov.place(BOX, (2.5, 0.0), 0.3)
    assert ov.overlap_area(a, b) == 0.0
    assert ov.outline_overlap(a, b).area == 0.0


@given(x=st.floats(-2.5, 2.5), y=st.floats(-1.5, 1.5), angle=st.floats(-3.2, 3.2))
def test_overlap_is_symmetric_and_bounded(x, y, angle):
    a = ov.place(BOX, (0.0, 0.0), 0.0)
    b = ov.place(BOX, (x, y), angle)
    ab, ba = ov.overlap_area(a, b), ov.overlap_area(b, a)
    assert ab == pytest.approx(ba, abs=1e-12)
    assert -1e-12 <= ab <= 2.0 + 1e-12
