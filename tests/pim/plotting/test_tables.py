"""pim/plotting/tables.py: the result table of `pim solve`, in SI and US units."""

import pytest

import pim
from pim.plotting.tables import format_table, rows_to_json, summarize


def test_rows_convert_with_exact_factors():
    r = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    si = {row.key: row for row in summarize(r, "si")}
    us = {row.key: row for row in summarize(r, "us")}
    assert si["velocity_x"].vehicle1 == pytest.approx(float(r.velocity1[0]))
    assert us["velocity_x"].vehicle1 == pytest.approx(float(r.velocity1[0]) / 0.3048)
    assert us["speed"].unit == "ft/s"      # one speed unit per system
    assert us["speed"].vehicle2 == pytest.approx(float(r.speed2) / 0.3048)
    assert si["clock"].vehicle1 == 11 and si["clock"].vehicle2 == 2   # README's worked PDOF
    text = format_table(list(si.values()), "title")
    assert text.splitlines()[0] == "title" and "post-impact yaw rate" in text
    assert rows_to_json(list(si.values()))["mu0"]["value"] == pytest.approx(float(r.mu0))


def test_summarize_needs_one_case():
    case = pim.load_case("ricsac9")
    with pytest.raises(ValueError, match="single case"):
        summarize(pim.solve(case, [0.2, 0.3], 1.0))
