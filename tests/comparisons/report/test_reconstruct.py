"""The report of `pim reconstruct` (comparisons.report.reconstruct) on RICSAC 9 turned around
(measured post-impact motion -> impact speeds, eps, beta): typed rows (an unknown and a
momentum check are told apart by their type, not by a name prefix), digits from each
unknown's interval, the impact speeds first among the cards, the document's sections."""

import math

import pytest

import pim
from comparisons.report.document import Cards
from comparisons.report.reconstruct import (
    MomentumRow,
    UnknownRow,
    reconstruction_document,
    reconstruction_rows,
    reconstruction_table,
)
from comparisons.report.render import render_markdown
from pim.analysis.reconstruction import reconstruct


@pytest.fixture(scope="module")
def rec():
    return reconstruct(pim.load_case("ricsac9-reconstruct"), samples=200, seed=0)


def test_rows_are_typed_and_in_the_users_units(rec):
    rows = reconstruction_rows(rec, "us")
    assert all(isinstance(r, UnknownRow) for r in rows.unknowns)
    assert all(isinstance(m, MomentumRow) for m in rows.momentum)
    speed = next(r for r in rows.unknowns if r.name == "vehicle1.speed")
    assert speed.unit == "mph" and speed.has_spread and speed.p5 < speed.value < speed.p95
    assert speed.value == pytest.approx(rec.values["vehicle1.speed"] / 0.44704)
    assert [m.name for m in rows.momentum] == ["vehicle1.speed", "vehicle2.speed"]
    assert rows.momentum[0].unit == "mph" and rows.momentum[0].sd > 0


def test_the_table_shows_the_digits_the_interval_allows(rec):
    rows = reconstruction_rows(rec, "us")
    table = reconstruction_table(rows)
    cells = {r[0]: r for r in table.cells()}
    speed = next(r for r in rows.unknowns if r.name == "vehicle2.speed")
    decimals = speed.decimals
    assert decimals is not None
    shown = cells["vehicle2.speed"][2]
    assert shown == (f"{speed.value:.{decimals}f}" if decimals > 0 else shown)
    assert cells["momentum check: vehicle1.speed"][3:6] == ["", "", ""]
    assert cells["momentum check: vehicle1.speed"][6].startswith("1 sd = ")
    assert table.column("value")[0] == rows.unknowns[0].value        # CSV: full precision


def test_the_document_leads_with_the_impact_speeds(rec):
    rows = reconstruction_rows(rec, "us")
    doc = reconstruction_document(rec, rows, "us")
    cards = doc.sections[0].blocks[0]
    assert isinstance(cards, Cards)
    assert [c.label for c in cards.cards][:2] == ["vehicle1.speed", "vehicle2.speed"]
    assert cards.cards[0].value.endswith(" mph") and cards.cards[0].note.startswith("5-95 %")
    text = render_markdown(doc)
    assert "delta-V, vehicle 1" in text and "Impact law: Brach's PIM" in text
    assert [s.id for s in doc.sections][:2] == ["results", "drivers"]
    assert "nan" not in text.lower()


def test_a_lower_bound_is_said():
    row = UnknownRow("impact.mu_c", "-", 0.31, math.nan, math.nan, math.nan, "", math.nan,
                     lower_bound=True)
    assert row.value_text() == ">= 0.31" and not row.has_spread
