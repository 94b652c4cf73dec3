"""What `pim fit` shows of a fit (comparisons.report.fit): the JSON in the user's units (1 mph
= 0.44704 m/s exactly, NIST SP 811), the coefficients with their ranges, a Kudlich-Slibar
mu_c given as the lower bound it is, the bound the optimum sits on, the residual table."""

import math

import pytest

import pim
from comparisons.report.fit import (
    bound_notes,
    coefficient_lines,
    cost_lines,
    fit_json,
    fit_lines,
    fit_values_json,
    quantity_factor,
    residual_lines,
    shown_value,
)

MPH = 0.44704       # m/s, exact


@pytest.fixture(scope="module")
def brach():
    return pim.fit(pim.load_case("ricsac9"))


@pytest.fixture(scope="module")
def capped():
    """beta held under 0.3, where the optimum sits on the bound."""
    return pim.fit(pim.load_case("ricsac9"), bounds=((0.0, 1.0), (0.0, 0.3)))


@pytest.fixture(scope="module")
def ks():
    return pim.fit(pim.load_case("ricsac9-pccrash"))


def test_factors_and_values_in_the_users_units():
    assert quantity_factor(None, "us") == (1.0, "-")
    factor, unit = quantity_factor("velocity", "us")
    assert unit == "mph" and factor == pytest.approx(1 / MPH)
    assert shown_value(math.pi, "angle", "si") == {"value": pytest.approx(180.0), "unit": "deg"}


def test_json_speaks_mph_and_mph_squared(brach):
    data = fit_json(brach, "us")
    si = brach.to_dict()
    assert data["rms"] == pytest.approx(si["rms"] / MPH) and data["rms_unit"] == "mph"
    assert data["cost"] == pytest.approx(si["cost"] / MPH**2)
    assert data["cost_unit"] == "(mph)^2"
    assert data["residuals"]["velocity1_x"] == pytest.approx(si["residuals"]["velocity1_x"] / MPH)
    assert data["residual_units"]["velocity1_x"] == "mph"
    assert data["minima"][0]["cost"] == pytest.approx(si["minima"][0]["cost"] / MPH**2)
    assert data["eps"] == si["eps"]                 # unit-free: as it is
    assert data["units"]["velocity"] == "mph"
    assert fit_values_json(brach, "us") == {}       # Brach's law, nothing freed


def test_kudlich_slibar_shows_its_values_and_a_lower_bound(ks):
    extra = fit_values_json(ks, "us")
    assert set(extra) == {"values", "value_units", "identifiability"}
    assert extra["value_units"]["impact.k"] == "-"
    lines = coefficient_lines(ks)
    assert lines[0].startswith("  k       = ")
    assert lines[1].startswith("  mu_c    >= ") and "only a lower bound" in lines[1]
    assert "Brach's at eps" in lines[2]
    assert any("identifiability: rank 1 of 1" in line for line in fit_lines("x", ks, "us"))


def test_brach_coefficients_and_the_sum_of_squares(brach):
    lines = coefficient_lines(brach)
    assert lines[0] == f"  epsilon = {brach.eps:.6f}   search range [0, 1]"
    assert "mu0 = " in lines[1]
    (cost,) = cost_lines(brach, "us")
    assert f"{brach.cost / MPH**2:.6g} (mph)^2 (sum of squares)" in cost
    assert f"rms residual = {brach.rms / MPH:.4g} mph" in cost


def test_a_bound_the_optimum_sits_on_is_said_with_its_slope(capped):
    (note,) = bound_notes(capped, "us")
    slope = capped.gradient[1] / MPH**2
    assert note == (f"beta sits on its upper bound 0.3 (d cost / d beta = {slope:.4g} "
                    f"(mph)^2: the error would keep falling beyond it)")
    assert f"  note: {note}" in fit_lines("ricsac9", capped, "us")


def test_residual_table_in_the_users_units(brach):
    header, rule, *rows = residual_lines(brach, "si")
    assert header.split() == ["term", "model", "measured", "residual", "unit"]
    assert set(rule.strip()) == {"-"}
    row = next(r for r in brach.residual_table if r["name"] == "velocity1_x")
    fields = next(line for line in rows if line.split()[0] == "velocity1_x").split()
    assert float(fields[1]) == pytest.approx(row["fitted"] * 3.6, abs=1e-4)
    assert float(fields[2]) == pytest.approx(row["measured"] * 3.6, abs=1e-4)
    assert fields[4] == "km/h"


def test_the_text_opens_with_the_case_and_what_was_fitted(brach):
    lines = fit_lines("ricsac9", brach, "us")
    assert lines[0] == "ricsac9: least-squares fit of the post-impact velocities"
    assert "" in lines


def test_a_residual_that_rounds_to_zero_prints_without_a_sign(brach):
    """A term the fit meets to within the table's 4 decimals printed "-0.0000"."""
    from types import SimpleNamespace

    row = dict(brach.residual_table[0])
    row["fitted"] = row["measured"] - 1e-7
    exact = SimpleNamespace(residual_table=(row,))
    fields = residual_lines(exact, "si")[2].split()
    assert fields[3] == "0.0000"
