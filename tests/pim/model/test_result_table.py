"""pim/model/result_table.py: the result table of `pim solve`, in SI and US units."""

import pytest

import pim
from pim.model.result_table import format_table, rows_to_json, summarize


def test_rows_convert_with_exact_factors():
    r = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    si = {row.key: row for row in summarize(r, "si")}
    us = {row.key: row for row in summarize(r, "us")}
    # speeds as the field reports them: 1 km/h = 1/3.6 m/s, 1 mph = 0.44704 m/s exactly
    assert si["velocity_x"].unit == "km/h"
    assert si["velocity_x"].vehicle1 == pytest.approx(float(r.velocity1[0]) * 3.6)
    assert us["velocity_x"].vehicle1 == pytest.approx(float(r.velocity1[0]) / 0.44704)
    assert us["speed"].unit == "mph" and us["delta_v"].unit == "mph"
    assert us["speed"].vehicle2 == pytest.approx(float(r.speed2) / 0.44704)
    assert us["impulse_n"].unit == "lbf s" and si["energy_loss"].unit == "kJ"
    assert si["clock"].vehicle1 == 11 and si["clock"].vehicle2 == 2   # README's worked PDOF
    text = format_table(list(si.values()), "title")
    assert text.splitlines()[0] == "title" and "post-impact yaw rate" in text
    assert rows_to_json(list(si.values()))["mu0"]["value"] == pytest.approx(float(r.mu0))


def test_summarize_needs_one_case():
    case = pim.load_case("ricsac9")
    with pytest.raises(ValueError, match="single case"):
        summarize(pim.solve(case, [0.2, 0.3], 1.0))


def test_the_impulse_rows_say_whose_impulse_they_are():
    """Issue 28: a row "impulse on vehicle x" (x is an axis, not a vehicle)."""
    rows = {row.key: row for row in summarize(pim.solve(pim.load_case("ricsac9")), "si")}
    assert rows["impulse_x"].label == "impulse on the vehicle, x"
    assert rows["impulse_y"].label == "impulse on the vehicle, y"
    assert rows["impulse_x"].vehicle2 == -rows["impulse_x"].vehicle1


def test_table_title_names_the_law_and_its_parameters():
    from pim.model.result_table import table_title

    case = pim.load_case("ricsac9")
    brach = pim.solve(case, 0.5, 0.25)
    assert table_title("ricsac9", brach) == "ricsac9: epsilon = 0.5, beta = 0.25"
    assert table_title("x", brach, "brach-capped").endswith(
        "(friction-capped Brach, effective beta)")
    ks = pim.solve(pim.load_case("ricsac9-pccrash"))
    title = table_title("pc", ks, "kudlich-slibar")
    assert title.startswith(f"pc: Kudlich-Slibar law, k = {float(ks.eps):g}, mu_c = ")
    assert f"(equivalent PIM beta = {float(ks.beta):g})" in title
