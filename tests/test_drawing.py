"""pim/plotting/drawing.py: the conventions figure (outlines, nose triangles, C, n, t)."""

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

import pim
from pim.plotting.drawing import draw_case, outline


def test_outline_and_nose_sit_on_the_front_edge():
    case = pim.load_case("ricsac9")
    fig = draw_case(case)
    assert isinstance(fig, Figure)
    v2 = case.vehicle2
    corners = outline(v2)
    heading = np.array([np.cos(float(v2.heading)), np.sin(float(v2.heading))])
    front = np.asarray(v2.cg) + 0.5 * v2.length * heading     # the front edge's midpoint
    np.testing.assert_allclose(corners.mean(axis=0), v2.cg, atol=1e-12)
    tips = [p.get_xy()[1] for p in fig.axes[0].patches
            if isinstance(p, Polygon) and len(p.get_xy()) in (3, 4)]
    assert any(np.allclose(t, front, atol=1e-9) for t in tips)


def test_a_barrier_draws():
    car = pim.Vehicle(1400.0, 2100.0, (-2.2, 0.0), (12.0, 0.0), length=4.4, width=1.8)
    wall = pim.Vehicle.obstacle(cg=(1.0, 0.0))
    fig = draw_case(pim.Case(car, wall, pim.Impact((0.0, 0.0), np.pi)))
    assert fig.axes and fig.axes[0].patches
