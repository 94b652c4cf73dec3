"""The plan view of a whole event (issue 32 item 4): outlines at the stated interval with
their times, each impact with its time, lengths in the user's unit."""

import pytest

from comparisons.animation.plan import plan_interval, plan_view
from pim.model.number_format import format_number
from tests.comparisons.animation.test_render import slide


def test_the_plan_view_draws_every_outline_interval_and_impact(tmp_path):
    ev = slide()
    assert plan_interval(ev) == pytest.approx(0.25)
    fig = plan_view(ev, units="us", measured_rest=((ev.vehicle1.position[-1] + 1, 0.1), None),
                    title="slide")
    ax = fig.axes[0]
    texts = [t.get_text() for t in ax.texts]
    # the 0.5 s outline's time stands under the impact's label, which states it
    assert "0.2 s" in texts and "2.5 s" in texts and "impact 1, 0.5 s" in texts
    assert "3 s" not in texts                 # at rest from 2.5 s: one outline, not three
    assert texts.count("0 s") == 2            # each vehicle's first outline
    assert "outlines every 0.25 s" in ax.get_title() and ax.get_xlabel() == "x [ft]"


def test_no_two_labels_overlap_near_the_impacts():
    """A side slap's three impacts within half a second (sim.event_check.side_slap_case):
    the time labels crowd there; on the drawn figure no two label boxes overlap (measured
    on the renderer as `pim draw`'s test does: the text's box, not an annotation's leader
    line), every impact keeps its label, the rest time is shown."""
    from matplotlib.text import Text

    import pim
    from sim.event_check import side_slap_case

    event = pim.event(side_slap_case(1.6))
    fig = plan_view(event, title="side slap")
    renderer = fig.canvas.get_renderer()
    boxes = [(t.get_text(), Text.get_window_extent(t, renderer)) for t in fig.axes[0].texts
             if t.get_text()]
    for i, (text, box) in enumerate(boxes):
        for other, obox in boxes[i + 1:]:
            assert not box.overlaps(obox), (text, other)
    texts = [text for text, _ in boxes]
    assert sum(t.startswith("impact ") for t in texts) == len(event.impacts) >= 2
    end = f"{format_number(float(event.time[-1]), sig=3)} s"
    assert end in texts and len(texts) >= len(event.impacts) + 6
