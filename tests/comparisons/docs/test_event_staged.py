"""The staged-test block of docs/event.md (comparisons.docs.event_staged): the page holds
what the code gives, the case is built from the published data as stated, and the analytic
and pymunk events of RICSAC 10 agree on its further impact and its rest."""

import math
from pathlib import Path

import numpy as np
import pytest

import pim
from comparisons.docs import event_staged as D
from pim.io.datasets import load_ricsac
from pim.io.staged_rest import staged_rest
from pim.model.event_formula import CONTACT_TOLERANCE
from pim.model.geometry import outline_penetration

DOCS = Path(__file__).resolve().parents[3] / "docs"


def test_the_committed_page_holds_the_block_the_code_gives():
    assert D.block() in (DOCS / "event.md").read_text(encoding="utf-8")


def test_the_case_is_ricsac10_at_ricsac9s_distances():
    """Test 10's masses and speeds; each CG at RICSAC 9's distance from C, along test 10's
    phi (the Honda's on its axis: phi1 = 0); the coefficients fitted within [0, 1]."""
    case, r9 = D.ricsac10_case(), pim.load_case("ricsac9")
    test = {t.number: t for t in load_ricsac()}[10]
    assert case.vehicle1.mass == test.mass1 and case.vehicle2.mass == test.mass2
    assert math.hypot(*case.vehicle1.cg) == pytest.approx(4.8 * 0.3048, rel=1e-6)
    assert math.hypot(*case.vehicle2.cg) == pytest.approx(math.hypot(*r9.vehicle2.cg))
    assert case.vehicle1.cg[1] == pytest.approx(0.0, abs=1e-12)
    assert 0 < case.impact.restitution < 1 and 0 <= case.impact.beta <= 1


def test_implied_drag_by_hand():
    """v^2 / (2 g range): the Honda's measured 8.73 m/s over its published 13.2 m."""
    honda = np.hypot(-1.55, 8.59) ** 2 / (2 * 9.80665 * math.hypot(5, 43) * 0.3048)
    assert D.implied_drag(staged_rest(10))[0] == pytest.approx(honda, rel=1e-9)
    assert honda == pytest.approx(0.294, abs=1e-3)


def test_analytic_and_pymunk_events_agree_on_the_side_slap_and_rest():
    """Each friction's two runs: the same impacts, the further one within 5 ms (the pymunk
    step and the event's contact bisection), ranges within 0.5 ft and turns within 5 deg
    (the step's drift over a run-out of seconds); the further impact at the implied drag
    and without tyres, none at the default 0.7."""
    rows = D.staged_table().rows
    runs = [r for r in rows if r[0] != "published"]
    for a, s in zip(runs[::2], runs[1::2], strict=True):
        assert (a[1], s[1]) == ("pim.event", "sim.simulate_event") and a[2] == s[2]
        if a[2] > 1:
            assert abs(a[3].value - s[3].value) <= 5e-3
        assert all(abs(a[k].value - s[k].value) <= 0.5 for k in (4, 5))
        assert all(abs(a[k].value - s[k].value) <= 5 for k in (6, 7))
    assert [r[2] for r in runs[::2]] == [2, 1, 2]


def test_variations_span_the_fits_error_and_ricsac9s_point_uncertainty():
    """Three restitutions (the fit's, one standard error either side, within [0, 1]) by nine
    C positions (0 or +-0.5 ft, ricsac9.toml's impact.point half-range, in x and y)."""
    fit = D.ricsac10_fit()
    runs = D.variations()
    assert len(runs) == 27
    eps = sorted({e for e, _ in runs})
    se = fit.standard_errors["impact.restitution"]
    assert eps == pytest.approx([fit.eps - se, fit.eps, min(fit.eps + se, 1.0)])
    shifts = {s for _, s in runs}
    assert max(abs(x) for x, _ in shifts) == pytest.approx(0.5 * 0.3048)
    assert len(shifts) == 9


def test_sensitivity_rows_count_nine_positions_each():
    table = D.sensitivity_table()
    assert [r[1].endswith("of 9") for r in table.rows] == [True] * 3
    hits = [int(r[1].split()[0]) for r in table.rows]
    assert hits[1] >= 1  # the fitted case at the nominal C: the main table's side slap


def test_measured_start_recontacts_when_the_crush_overlap_deepens_by_1_cm():
    """RICSAC 9 from its published measured post-impact motion (the sheet's table) at PIM's
    configuration: in free motion (straight lines, constant yaw rates: exact by hand) the
    outlines' separating-axis depth (pim.model.geometry, numpy) grows from the crush overlap;
    the compiled event's first further impact is where it has grown by the contact tolerance
    (1 cm), within 0.2 ms (the hand scan's 10 us grid and the kernel's bisection)."""
    case = pim.load_case("ricsac9")
    m = case.measured
    t = np.arange(0.0, 0.05, 1e-5)
    outlines = []
    for v, velocity, w in ((case.vehicle1, m.velocity1, m.yaw_rate1),
                           (case.vehicle2, m.velocity2, m.yaw_rate2)):
        outlines.append((np.asarray(v.cg) + t[:, None] * velocity, v.heading + w * t, v.length,
                         v.width, None))
    depth = outline_penetration(*outlines)
    growth = depth - np.minimum.accumulate(depth)
    by_hand = t[np.argmax(growth >= CONTACT_TOLERANCE)]
    count, first = D.measured_start()
    assert count >= 1 and growth.max() >= CONTACT_TOLERANCE
    assert first == pytest.approx(by_hand, abs=2e-4)
    assert first < 0.02


def test_the_side_slap_is_the_spinning_hondas_side_against_the_torinos_rear_corner():
    """What docs/event.md says of it: the Honda has turned (clockwise) by more than 45 deg,
    its side meets a rear corner of the Torino."""
    (part1, part2), (turn1, _) = D.side_slap_parts()
    assert part1.endswith("side") and part2.startswith("rear ")
    assert turn1 < -math.radians(45)
