"""The report of `pim reconstruct` (comparisons.report.reconstruct) on RICSAC 9 turned around
(measured post-impact motion -> impact speeds, eps, beta): typed rows (an unknown and a
momentum check are told apart by their type, not by a name prefix), digits from each
unknown's interval, the impact speeds first among the cards, the document's sections."""

import math
import re

import pytest

import pim
from comparisons.report.document import Cards
from pim.model.number_format import format_number
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
    shown = cells["impact speed of vehicle 2"][2]
    assert shown == (f"{speed.value:.{decimals}f}" if decimals > 0 else shown)
    assert cells["momentum check: impact speed of vehicle 1"][3:6] == ["", "", ""]
    assert cells["momentum check: impact speed of vehicle 1"][6].startswith("1 sd = ")
    assert table.column("value")[0] == rows.unknowns[0].value        # CSV: full precision


def test_the_document_leads_with_the_impact_speeds(rec):
    rows = reconstruction_rows(rec, "us")
    doc = reconstruction_document(rec, rows, "us")
    cards = doc.sections[0].blocks[0]
    assert isinstance(cards, Cards)
    # issue 33, point 6: cards titled by what they are, not by their keys ("VEHICLE1.SPEED"
    # in the page's capitals)
    assert [c.label for c in cards.cards] == ["impact speed of vehicle 1",
                                              "impact speed of vehicle 2", "beta = mu / mu0",
                                              "restitution epsilon"]
    assert cards.cards[0].value.endswith(" mph") and cards.cards[0].note.startswith("5-95 %")
    text = render_markdown(doc)
    assert "delta-V, vehicle 1" in text and "Impact law: Brach's PIM" in text
    assert [s.id for s in doc.sections][:2] == ["results", "drivers"]
    assert "nan" not in text.lower()


def test_a_lower_bound_is_said():
    row = UnknownRow("impact.mu_c", "-", 0.31, math.nan, math.nan, math.nan, "", math.nan,
                     lower_bound=True)
    assert row.value_text() == ">= 0.31" and not row.has_spread


def test_spread_text_never_prints_nan(rec):
    from comparisons.report.reconstruct import spread_text

    row = reconstruction_rows(rec, "us").unknowns[0]
    assert spread_text(row, 0) == "(5/50/95 %: not computed, --samples 0)"
    assert spread_text(row, 200) == "[" + ", ".join(format_number(x) for x in (
        row.p5, row.p50, row.p95)) + "]"
    empty = UnknownRow("vehicle1.speed", "mph", 20.0, *[math.nan] * 3, driver="",
                       driver_index=math.nan)
    assert spread_text(empty, 200) == "(5/50/95 %: no usable Monte Carlo sample)"


def test_text_lines_say_the_law_then_the_warnings_then_the_table(rec):
    from comparisons.report.reconstruct import law_line, reconstruction_lines, table_lines

    rows = reconstruction_rows(rec, "us")
    lines = reconstruction_lines(rec, rows, "us", samples=200)
    assert lines[0] == law_line(rec)
    table = table_lines(rows, 200)
    assert len(table) == len(rows.unknowns) + len(rows.momentum)
    assert lines.index(table[0]) > max(i for i, x in enumerate(lines)
                                       if x.startswith("warning: "))
    speed = next(x for x in table if x.startswith("impact speed of vehicle 1 "))
    assert " mph  [" in speed
    assert table[-1].startswith("momentum check: impact speed of vehicle 2")
    assert "(1 sd = " in table[-1]
    assert not any(re.search(r"\b(vehicle\d|impact|measured)\.", x) for x in lines), lines


def test_json_holds_each_unknown_in_the_users_units_and_the_findings_in_place(rec):
    from comparisons.report.reconstruct import reconstruction_json

    rows = reconstruction_rows(rec, "us")
    data = reconstruction_json(rec, rows, "us", samples=200, findings={"admissible": True})
    keys = list(data)
    assert keys.index("momentum_check") < keys.index("admissible") < keys.index("pre_impact")
    speed = data["unknowns"]["vehicle1.speed"]
    assert speed["unit"] == "mph"
    assert speed["value"] == pytest.approx(rec.values["vehicle1.speed"] / 0.44704)
    assert data["law"] == "brach" and data["crush"] == {} and data["tyre_models"] == {}
    assert data["secondary_impact"] is None and data["samples"] == 200


def test_crush_json_in_the_users_units():
    from comparisons.report.reconstruct import crush_json, crush_lines

    crushed = reconstruct(pim.load_case("synthetic-crush"), samples=0)
    data = crush_json(crushed, "si")
    c = crushed.crush[0]
    entry = data[f"vehicle{c.vehicle}"]
    assert entry["energy"]["unit"] == "kJ"
    assert entry["energy"]["value"] == pytest.approx(c.energy / 1000)
    assert entry["ees"] == {"value": pytest.approx(c.ees * 3.6), "unit": "km/h"}
    assert len(crush_lines(crushed, "si")) == len(data)


def test_runout_contact_needs_both_run_outs(rec):
    from comparisons.report.reconstruct import runout_contact

    assert rec.post is None and runout_contact(rec, "us") is None
