"""The compare report on a case whose yaw inertia pim estimated (issue 28, point 5): the
inputs table tags it, its full note follows, and the intervals' note says its scatter is
drawn."""

from pathlib import Path

import pytest

import pim
from comparisons.report.compare import inputs_table
from comparisons.report.data import monte_carlo_note

CASE = Path(__file__).resolve().parents[2] / "data" / "no-yaw-inertia.toml"


def test_inputs_table_tags_the_estimate():
    case = pim.load_case(CASE)
    rows = {(r[0], r[1]): r[2] for r in inputs_table(case, "si").rows}
    tag = ("yaw inertia (estimated, ±7.4 % (1 sd), NHTSA's measured vehicles, "
           "Heydinger et al. 1999; NHTSA's NCAP 2004 measurements)")
    assert rows[("vehicle 1", tag)] == pytest.approx(case.estimates[0].value)
    assert ("vehicle 2", "yaw inertia") in rows                  # given: no tag


def test_monte_carlo_note_names_the_estimates_scatter():
    case = pim.load_case(CASE)
    note = monte_carlo_note(case)
    assert "`vehicle1.yaw_inertia`" in note and "±7.4 %" in note
    assert "[uncertainty]` table" not in note          # the file has none: only the estimate
    given = pim.load_case("ricsac9")                   # a table, no estimate
    assert "the case's `[uncertainty]` table" in monte_carlo_note(given)
    assert "estimated" not in monte_carlo_note(given)
