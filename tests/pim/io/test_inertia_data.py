"""NHTSA's measured yaw inertias (pim.io.inertia_data): the bundled rows against the summary
their transcriber published, and the yaw dynamic index's estimate against the measured
vehicles it did not see (leave one out)."""

import numpy as np
import pytest
from scipy.stats import binom

from pim.io.inertia_data import (
    dynamic_indices,
    estimate_yaw_inertia,
    estimate_yaw_inertia_from_mass,
    held_out,
    load_inertia_records,
    mass_held_out,
    mass_regressions,
)
from pim.model.inertia import BODIES, dynamic_index, yaw_inertia_estimate
from pim.model.numbers import InputError

CARS, TRUCKS = BODIES["car"], BODIES["suv"] + BODIES["pickup"] + BODIES["van"]


def _indices(codes):
    return np.array([r.dynamic_index for r in load_inertia_records() if r.body in codes])


# K. Tse, "Estimating vehicle inertia and centre-of-gravity height using the NHTSA light
# vehicle inertial parameter database" (kktse.github.io, 2020-10-21), table "Yaw Dynamic
# Index": mean, min, 25/50/75th percentile, max, printed to 3 decimals (tolerance 5e-4),
# and the counts 204 / 73 / 131.
PUBLISHED_INDEX = {
    "all": (None, 204, 1.034, 0.837, 0.962, 1.033, 1.111, 1.242),
    "cars": (CARS, 73, 1.091, 0.914, 1.037, 1.105, 1.148, 1.242),
    "trucks": (TRUCKS, 131, 1.002, 0.837, 0.932, 1.000, 1.055, 1.190),
}


@pytest.mark.parametrize("group", PUBLISHED_INDEX)
def test_rows_reproduce_the_published_dynamic_index_table(group):
    codes, count, mean, low, q25, q50, q75, high = PUBLISHED_INDEX[group]
    d = np.array([r.dynamic_index for r in load_inertia_records()]) if codes is None \
        else _indices(codes)
    assert d.size == count
    assert d.mean() == pytest.approx(mean, abs=5e-4)
    assert np.percentile(d, [0, 25, 50, 75, 100]) == pytest.approx(
        [low, q25, q50, q75, high], abs=5e-4)


# The same post, table of linear fits I_zz = slope m + intercept: (slope, intercept, R^2),
# printed to 3 decimals.
PUBLISHED_FIT = {"all": (None, 2.961, -1596.431, 0.845), "cars": (CARS, 3.176, -1754.164, 0.920),
                 "trucks": (TRUCKS, 3.168, -2021.319, 0.770)}


@pytest.mark.parametrize("group", PUBLISHED_FIT)
def test_rows_reproduce_the_published_yaw_inertia_fits(group):
    codes, slope, intercept, r2 = PUBLISHED_FIT[group]
    rows = [r for r in load_inertia_records() if codes is None or r.body in codes]
    m = np.array([r.mass for r in rows])
    izz = np.array([r.yaw_inertia for r in rows])
    fit = np.polyfit(m, izz, 1)
    residual = izz - np.polyval(fit, m)
    assert fit[0] == pytest.approx(slope, abs=1e-3)
    # the rows carry 0.1 kg and 0.1 kg m^2: the intercept moves by a fraction of 1 kg m^2
    assert fit[1] == pytest.approx(intercept, abs=1.0)
    assert 1 - residual.var() / izz.var() == pytest.approx(r2, abs=5e-4)


@pytest.mark.parametrize("body", BODIES)
def test_estimate_covers_held_out_measured_vehicles(body):
    # Each measured vehicle in turn is left out; the index of the others estimates its yaw
    # inertia from its mass and a b (the database's, I / (m D)); the measured value must
    # fall within 1.96 predictive sd as often as a 95 % interval promises: the count inside
    # may not be significantly low (binomial, one-sided, 1 %), and the standardised errors'
    # sd must be near 1 (neither too wide nor too narrow a scatter).
    inside, n, z_sd = held_out(body)
    assert n == dynamic_indices()[body].count
    assert binom.cdf(inside, n, 0.95) > 0.01, (inside, n)
    assert 0.8 < z_sd < 1.25


# Measured vehicles of the database (Heydinger et al. 1999, as bundled): year, make, model,
# mass [kg], measured yaw inertia [kg m^2].
NAMED = [(1986, "BMW", "325i", 1251.5, 2026.5), (1985, "Ford", "Escort", 1006.6, 1544.7),
         (1986, "Buick", "Electra", 1506.3, 3073.0), (1971, "Volkswagen", "Beetle", 856.5,
                                                       1289.0)]


@pytest.mark.parametrize("year, make, model, mass, measured", NAMED)
def test_named_cars_within_the_estimates_scatter(year, make, model, mass, measured):
    rows = [r for r in load_inertia_records() if r.body in CARS]
    (car,) = [r for r in rows if (r.year, r.make, r.model) == (year, make, model)]
    assert (car.mass, car.yaw_inertia) == pytest.approx((mass, measured))
    index = dynamic_index([r.dynamic_index for r in rows if r is not car], "car", "")
    a = 0.45 * 2.6                                       # a (L - a) = a b of the database
    wheelbase = a + car.axle_product / a
    estimate, sd = yaw_inertia_estimate(car.mass, wheelbase, index, cg_to_front_axle=a)
    assert abs(estimate - measured) < 2 * sd
    assert estimate == pytest.approx(measured, rel=0.15)


def test_classes_and_their_scatter():
    records = load_inertia_records()
    assert (min(r.year for r in records), max(r.year for r in records)) == (1971, 1998)
    indices = dynamic_indices()
    assert set(indices) == set(BODIES)
    assert sum(d.count for d in indices.values()) == 204
    for d in indices.values():     # each class's vehicle-to-vehicle scatter: 6-11 %
        assert 0.06 < d.relative_sd < 0.11


def test_estimate_yaw_inertia_records_its_provenance():
    e = estimate_yaw_inertia(1500.0, 2.7, 1.1, "car", "vehicle2")
    car = dynamic_indices()["car"]
    assert e.name == "vehicle2.yaw_inertia"
    assert e.value == pytest.approx(car.mean * 1500 * 1.1 * 1.6)
    assert e.sd == pytest.approx(car.predictive_sd * 1500 * 1.1 * 1.6)
    assert e.assumptions == () and "Heydinger" in e.source
    # without the axle distance: the class's measured CG position, named with its source
    e = estimate_yaw_inertia(1500.0, 2.7, None, "van", "vehicle1")
    (assumed,) = e.assumptions
    assert "all 52 vehicles" in assumed and "NCAP 2004" in e.source
    with pytest.raises(InputError, match=r"vehicle1\.body must be one of"):
        estimate_yaw_inertia(1500.0, 2.7, None, "truck", "vehicle1")



@pytest.mark.parametrize("group, published", [("car", "cars"), ("truck", "trucks")])
def test_the_mass_only_line_is_the_published_one(group, published):
    """The line the estimate without a wheelbase uses is the one K. Tse (2020) published for
    its group (PUBLISHED_FIT: slope and R^2 to 3 decimals, the intercept to the rows'
    0.1 kg m^2), from the same vehicles."""
    _, slope, intercept, r2 = PUBLISHED_FIT[published]
    line = mass_regressions()[group]
    assert line.slope == pytest.approx(slope, abs=1e-3)
    assert line.intercept == pytest.approx(intercept, abs=1.0)
    assert line.r_squared == pytest.approx(r2, abs=5e-4)
    assert line.count == {"car": 73, "truck": 131}[group]


@pytest.mark.parametrize("group", ["car", "truck"])
def test_the_mass_only_line_covers_held_out_vehicles(group):
    """Each measured vehicle left out in turn, the others' line and relative scatter: the
    measured inertia within 1.96 predictive sd as often as a 95 % interval promises
    (binomial, one-sided, 1 %), the standardised errors' sd near 1."""
    inside, n, z_sd = mass_held_out(group)
    assert n == mass_regressions()[group].count
    assert binom.cdf(inside, n, 0.95) > 0.01, (inside, n)
    assert 0.8 < z_sd < 1.25


def test_the_mass_only_estimate_records_its_provenance():
    e = estimate_yaw_inertia_from_mass(1500.0, "pickup", "vehicle2")
    line = mass_regressions()["truck"]
    assert e.name == "vehicle2.yaw_inertia" and e.inputs == (("mass m", 1500.0, "mass"),)
    assert e.value == pytest.approx(line.slope * 1500 + line.intercept)
    assert e.sd == pytest.approx(float(line.predictive_sd(1500.0)) * e.value)
    assert "131 measured trucks" in e.method and "Tse 2020" in e.source
    assert 0.15 < e.relative_sd < 0.2            # wider than the dynamic index's 7 %
    with pytest.raises(InputError, match=r"vehicle2: no yaw_inertia .* and no wheelbase.* "
                                         r"within the 815-1978 kg of the 73 measured cars"):
        estimate_yaw_inertia_from_mass(2500.0, "car", "vehicle2")
