"""The plan view of a whole event (issue 32 item 4): outlines at the stated interval with
their times, each impact with its time, lengths in the user's unit."""

import pytest

from comparisons.animation.plan import plan_interval, plan_view
from tests.comparisons.animation.test_render import slide


def test_the_plan_view_draws_every_outline_interval_and_impact(tmp_path):
    ev = slide()
    assert plan_interval(ev) == pytest.approx(0.25)
    fig = plan_view(ev, units="us", measured_rest=((ev.vehicle1.position[-1] + 1, 0.1), None),
                    title="slide")
    ax = fig.axes[0]
    texts = [t.get_text() for t in ax.texts]
    assert "0.5 s" in texts and "2.5 s" in texts and any(t.startswith("impact 1") for t in texts)
    assert "3 s" not in texts                 # at rest from 2.5 s: one outline, not three
    assert texts.count("0 s") == 2            # each vehicle's first outline
    assert "outlines every 0.25 s" in ax.get_title() and ax.get_xlabel() == "x [ft]"
