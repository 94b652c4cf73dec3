"""`pim draw` and the conventions figure (issue 12, item 4 and defect 6): no label under an
arrow or another label; a barrier without outline data is drawn as its contact plane."""

import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

import pim
from pim.io.casefile import list_cases
from pim.plotting.drawing import draw_case, outline
from pim_cli.main import main

CASES = [name for name, _ in list_cases()]


def label_boxes(fig):
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    return [(t.get_text(), t.get_window_extent(renderer)) for t in ax.texts if t.get_text()]


def arrow_segments(fig):
    """Start and end [px] of every arrow (annotations without text carry the arrows)."""
    ax = fig.axes[0]
    out = []
    for t in ax.texts:
        if not t.get_text() and t.arrow_patch is not None:
            out.append((ax.transData.transform(t.xyann), ax.transData.transform(t.xy)))
    return out


@pytest.mark.parametrize("name", CASES)
def test_no_label_covers_another_label_or_an_arrow(name):
    case = pim.load_case(name)
    result = pim.solve(case) if case.impact.restitution is not None else None
    fig = draw_case(case, result, units=case.units)
    boxes = label_boxes(fig)
    for i, (text, box) in enumerate(boxes):
        for other, obox in boxes[i + 1:]:
            assert not box.overlaps(obox), (text, other)
        for a, b in arrow_segments(fig):
            inside = [box.x0 + 1 < x < box.x1 - 1 and box.y0 + 1 < y < box.y1 - 1
                      for x, y in (a + f * (b - a) for f in np.linspace(0, 1, 40))]
            assert not any(inside), (text, "arrow")
    assert fig.pim_labels.overlaps(fig) == []


def test_us_case_is_drawn_in_feet(tmp_path):
    fig = draw_case(pim.load_case("ricsac9"), units="us")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "x [ft]"
    assert any("mph" in t.get_text() for t in ax.texts)          # speeds as the field says


def test_barrier_without_outline_draws_the_contact_plane(tmp_path):
    case = pim.load_case("hard-barrier")
    bare = pim.Case(case.vehicle1, pim.Vehicle.obstacle(), case.impact, name="bare")
    fig = draw_case(bare, pim.solve(bare, 0.1, 1.0))
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert any("contact plane" in t for t in texts)
    assert not any("CG2" in t for t in texts)
    assert main(["draw", "hard-barrier", "--out", str(tmp_path / "b.png")]) == 0


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
