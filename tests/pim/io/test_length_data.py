"""Lock's 1993 cars (pim/io/data/lock1993_cars93_dimensions.csv) and the line of the
wheelbase on the overall length (issue 33 point 4: a yaw inertia from the mass and the
length). The bundled rows are checked against the summary R prints for the published data
set (``summary(MASS::Cars93)``, ``table(Cars93$Type)``), the line against an independent
fit (scipy.stats.linregress on the raw CSV), and the estimate's mean and sd against a Monte
Carlo of its three independent factors."""

import csv
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from pim.io.axle_data import axle_fractions
from pim.io.inertia_data import dynamic_indices
from pim.io.length_data import (
    held_out,
    load_dimension_records,
    slope_p_value,
    usable_lines,
    wheelbase_lines,
)
from pim.model.inertia import wheelbase_line, yaw_inertia_from_length
from pim.model.numbers import InputError

DATA = Path(__file__).resolve().parents[3] / "pim" / "io" / "data" / \
    "lock1993_cars93_dimensions.csv"
INCH = 0.0254


def _raw() -> list[dict]:
    lines = [line for line in DATA.read_text().splitlines() if not line.startswith("#")]
    return list(csv.DictReader(lines))


@pytest.mark.parametrize("column, summary", [
    # R: summary(MASS::Cars93[c("Length", "Wheelbase", "Weight")]):
    # Min., 1st Qu., Median, Mean, 3rd Qu., Max.
    ("length_in", (141.0, 174.0, 183.0, 183.2, 192.0, 219.0)),
    ("wheelbase_in", (90.0, 98.0, 103.0, 103.9, 110.0, 119.0)),
    ("weight_lb", (1695.0, 2620.0, 3040.0, 3073.0, 3525.0, 4105.0)),
])
def test_the_bundled_rows_give_the_published_summary(column, summary):
    x = np.array([float(r[column]) for r in _raw()])
    assert x.size == 93
    got = (x.min(), np.percentile(x, 25), np.median(x), x.mean(), np.percentile(x, 75),
           x.max())
    assert got == pytest.approx(summary, rel=5e-4)       # R prints 4 significant digits


def test_the_types_are_the_published_counts_and_become_body_classes():
    types = [r["type"] for r in _raw()]
    assert {t: types.count(t) for t in set(types)} == {
        "Compact": 16, "Large": 11, "Midsize": 22, "Small": 21, "Sporty": 14, "Van": 9}
    records = load_dimension_records()
    assert [r.body for r in records].count("car") == 84
    assert records[0].length == pytest.approx(177 * INCH)      # the Acura Integra
    assert all(0 < r.wheelbase < r.length for r in records)


@pytest.mark.parametrize("body, types", [("car", ("Small", "Compact", "Midsize", "Large",
                                                   "Sporty")), ("van", ("Van",))])
def test_the_line_is_an_independent_least_squares_fit(body, types):
    rows = [r for r in _raw() if r["type"] in types]
    x = np.array([float(r["length_in"]) for r in rows]) * INCH
    y = np.array([float(r["wheelbase_in"]) for r in rows]) * INCH
    fit = stats.linregress(x, y)
    line = wheelbase_lines()[body]
    assert (line.slope, line.intercept, line.r_squared) == pytest.approx(
        (fit.slope, fit.intercept, fit.rvalue ** 2), rel=1e-9)
    assert line.sd == pytest.approx(fit.stderr * np.sqrt(((x - x.mean()) ** 2).sum()),
                                    rel=1e-9)
    assert slope_p_value(line) == pytest.approx(fit.pvalue, rel=1e-6)


def test_only_the_cars_line_is_used_and_it_holds_out():
    """The cars' slope is significant (p ~ 1e-32), the 9 vans' is not (p ~ 0.2): the vans,
    SUVs and pickups take the line on mass."""
    assert list(usable_lines()) == ["car"]
    inside, n, z_sd = held_out("car")
    assert n == 84 and inside / n > 0.9 and 0.85 < z_sd < 1.2


def test_the_estimate_is_the_mean_and_sd_of_its_independent_factors():
    """A Monte Carlo of D, f and L drawn independently (normal, with the predictive sds the
    estimate states) gives the estimate's mean to 0.3 % and its sd to 3 %; f (1 - f)'s sd is
    first order, the rest exact."""
    line = usable_lines()["car"]
    index, fraction = dynamic_indices()["car"], axle_fractions()["car"]
    mass, length = 1500.0, 4.6
    inertia, sd = yaw_inertia_from_length(mass, length, line, index, fraction)
    rng = np.random.default_rng(4)
    n = 400_000
    d = rng.normal(index.mean, index.predictive_sd, n)
    f = rng.normal(fraction.mean, fraction.predictive_sd, n)
    w = rng.normal(float(line.wheelbase(length)), float(line.predictive_sd(length)), n)
    draws = d * mass * w * w * f * (1 - f)
    assert float(inertia) == pytest.approx(draws.mean(), rel=3e-3)
    assert float(sd) == pytest.approx(draws.std(), rel=3e-2)


@settings(max_examples=40, deadline=None)
@given(mass=st.floats(600.0, 3000.0), length=st.floats(3.6, 5.5), k=st.floats(1.01, 1.5))
def test_the_estimate_grows_with_length_and_is_proportional_to_mass(mass, length, k):
    line = usable_lines()["car"]
    index, fraction = dynamic_indices()["car"], axle_fractions()["car"]
    base, sd = yaw_inertia_from_length(mass, length, line, index, fraction)
    longer, _ = yaw_inertia_from_length(mass, min(length * k, 5.56), line, index, fraction)
    heavier, heavier_sd = yaw_inertia_from_length(mass * k, length, line, index, fraction)
    assert longer >= base
    assert (heavier, heavier_sd) == pytest.approx((k * base, k * sd), rel=1e-12)
    assert 0.05 < sd / base < 0.15


def test_bad_lengths_and_lines_are_refused():
    line = usable_lines()["car"]
    index, fraction = dynamic_indices()["car"], axle_fractions()["car"]
    for bad in (3.0, 7.0, float("nan")):
        with pytest.raises(InputError, match=r"length must lie within the 3\.58-5\.56 m"):
            yaw_inertia_from_length(1500.0, bad, line, index, fraction)
    with pytest.raises(InputError, match="mass must be finite and > 0"):
        yaw_inertia_from_length(0.0, 4.6, line, index, fraction)
    with pytest.raises(InputError, match="at least 3 finite"):
        wheelbase_line([4.0, 4.0, 4.0], [2.5, 2.6, 2.7], "car", "x")
