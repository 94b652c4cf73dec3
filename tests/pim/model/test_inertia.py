"""The yaw-inertia estimate from mass and wheelbase (pim.model.inertia): its equation, its
bounds on the CG position, its scatter and its refusals."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pim.model.inertia import (
    AxleFraction,
    DynamicIndex,
    InputEstimate,
    axle_fraction,
    dynamic_index,
    mass_regression,
    yaw_inertia_estimate,
    yaw_inertia_from_mass,
)
from pim.model.numbers import InputError

CAR = DynamicIndex("car", 1.1, 0.08, 50, "test data")


def test_estimate_is_the_index_times_m_a_b():
    # I = D m a (L - a): 1.1 x 1500 kg x 1.2 m x 1.5 m; sd = D's predictive sd x m a b
    inertia, sd = yaw_inertia_estimate(1500.0, 2.7, CAR, cg_to_front_axle=1.2)
    assert inertia == pytest.approx(1.1 * 1500 * 1.2 * 1.5, rel=1e-12)
    assert sd == pytest.approx(0.08 * math.sqrt(1 + 1 / 50) * 1500 * 1.2 * 1.5, rel=1e-12)


def test_default_axle_is_half_the_wheelbase():
    inertia, _ = yaw_inertia_estimate(1500.0, 2.7, CAR)
    assert inertia == pytest.approx(1.1 * 1500 * 2.7**2 / 4, rel=1e-12)


@given(st.floats(0.05, 0.95))
def test_half_the_wheelbase_gives_the_largest_estimate(fraction):
    # a b = f (1 - f) L^2 is largest at f = 1/2: the default is an upper estimate, by
    # 4 f (1 - f) (4 % at f = 0.4 or 0.6, the figure the module's notes state)
    top, _ = yaw_inertia_estimate(1200.0, 2.5, CAR)
    inertia, _ = yaw_inertia_estimate(1200.0, 2.5, CAR, cg_to_front_axle=fraction * 2.5)
    assert inertia <= top * (1 + 1e-12)
    assert inertia / top == pytest.approx(4 * fraction * (1 - fraction), rel=1e-9)


def test_estimate_broadcasts():
    masses = np.array([1000.0, 1500.0, 2000.0])
    inertia, sd = yaw_inertia_estimate(masses, np.array([[2.5], [3.0]]), CAR)
    assert inertia.shape == sd.shape == (2, 3)
    assert inertia[1, 2] == pytest.approx(1.1 * 2000 * 9 / 4)
    assert np.allclose(sd / inertia, CAR.relative_sd)


@pytest.mark.parametrize("kwargs, field", [
    ({"mass": 0.0}, "mass"), ({"mass": -5.0}, "mass"), ({"wheelbase": 0.0}, "wheelbase"),
    ({"wheelbase": float("nan")}, "wheelbase"), ({"cg_to_front_axle": 2.7}, "cg_to_front_axle"),
    ({"cg_to_front_axle": 0.0}, "cg_to_front_axle"), ({"mass": "1500"}, "mass")])
def test_bad_inputs_are_refused_naming_the_field(kwargs, field):
    args = {"mass": 1500.0, "wheelbase": 2.7, "cg_to_front_axle": None, **kwargs}
    with pytest.raises(InputError, match=field):
        yaw_inertia_estimate(args["mass"], args["wheelbase"], CAR, args["cg_to_front_axle"])


def test_dynamic_index_from_values():
    d = dynamic_index([1.0, 1.2, 1.1, 0.9], "car", "src")
    assert d.mean == pytest.approx(1.05) and d.count == 4
    assert d.sd == pytest.approx(np.std([1.0, 1.2, 1.1, 0.9], ddof=1))
    assert d.predictive_sd == pytest.approx(d.sd * math.sqrt(1.25))
    assert d.relative_sd == pytest.approx(d.predictive_sd / 1.05)
    with pytest.raises(InputError, match="at least 2"):
        dynamic_index([1.0], "car", "src")
    with pytest.raises(InputError, match="mean > 0"):
        DynamicIndex("car", -1.0, 0.1, 5, "src")


def test_input_estimate_tags_itself():
    e = InputEstimate("vehicle1.yaw_inertia", 2000.0, 140.0, "D m a b", "Heydinger et al. 1999")
    assert e.relative_sd == pytest.approx(0.07)
    assert e.short == "estimated, ±7.0 % (1 sd), Heydinger et al. 1999"


# The CG's axle position f = a / L when the case gives none (AxleFraction).
FRACTION = AxleFraction("car", 0.4, 0.025, 21, "test")


@settings(max_examples=200, deadline=None)
@given(mass=st.floats(100, 50_000), wheelbase=st.floats(1.0, 8.0),
       mean=st.floats(0.2, 0.8), sd=st.floats(0.0, 0.1))
def test_estimated_axle_position_lies_between_the_axles_and_below_the_half(
        mass, wheelbase, mean, sd):
    f = AxleFraction("car", mean, sd, 10, "test")
    g, g_sd = f.axle_product()
    assert 0 < mean * wheelbase < wheelbase                  # the CG between the axles
    inertia, spread = yaw_inertia_estimate(mass, wheelbase, CAR, fraction=f)
    half, half_sd = yaw_inertia_estimate(mass, wheelbase, CAR)
    assert inertia <= half * (1 + 1e-12)                     # f (1 - f) <= 1/4
    if g > 0:
        assert inertia > 0 and spread >= half_sd * g / 0.25 * (1 - 1e-12)


def test_axle_fraction_product_moments_against_sampling():
    # E[f (1 - f)] = mu (1 - mu) - s^2 exactly; its sd |1 - 2 mu| s to first order
    rng = np.random.default_rng(3)
    f = rng.normal(FRACTION.mean, FRACTION.predictive_sd, 400_000)
    g, g_sd = FRACTION.axle_product()
    assert (f * (1 - f)).mean() == pytest.approx(g, abs=3e-5)
    assert (f * (1 - f)).std() == pytest.approx(g_sd, rel=0.02)


def test_estimate_with_fraction_is_the_product_of_independent_scatters():
    inertia, sd = yaw_inertia_estimate(1500.0, 2.7, CAR, fraction=FRACTION)
    rng = np.random.default_rng(4)
    d = rng.normal(CAR.mean, CAR.predictive_sd, 400_000)
    f = rng.normal(FRACTION.mean, FRACTION.predictive_sd, 400_000)
    drawn = d * 1500 * 2.7**2 * f * (1 - f)
    assert drawn.mean() == pytest.approx(inertia, rel=1e-3)
    assert drawn.std() == pytest.approx(sd, rel=0.02)
    # a given axle position ignores the fraction (bitwise as without it)
    assert yaw_inertia_estimate(1500.0, 2.7, CAR, 1.1, fraction=FRACTION) == \
        yaw_inertia_estimate(1500.0, 2.7, CAR, 1.1)


def test_axle_fraction_refuses_impossible_positions():
    with pytest.raises(InputError, match="in \\(0, 1\\)"):
        AxleFraction("car", 1.2, 0.02, 10, "x")
    with pytest.raises(InputError, match="at least 2 finite"):
        axle_fraction([0.4], "car", "x")
    assert axle_fraction([0.38, 0.42], "car", "x").mean == pytest.approx(0.4)


def test_mass_regression_is_the_least_squares_line_with_its_relative_scatter():
    """On points a known line times (1 + e): slope and intercept of the line through them
    (independently: the normal equations by hand), R^2, and the relative scatter
    sqrt(sum(e_rel^2) / (n - 2)); the predictive sd grows away from the mean mass."""
    m = np.array([1000.0, 1200.0, 1400.0, 1600.0, 1800.0])
    izz = (3.0 * m - 1500.0) * np.array([1.05, 0.95, 1.0, 1.04, 0.96])
    line = mass_regression(m, izz, "car", "test data")
    n, sx, sy = m.size, m.sum(), izz.sum()
    slope = (n * (m * izz).sum() - sx * sy) / (n * (m * m).sum() - sx * sx)
    assert line.slope == pytest.approx(slope, rel=1e-12)
    assert line.intercept == pytest.approx((sy - slope * sx) / n, rel=1e-9)
    fit = line.slope * m + line.intercept
    assert line.r_squared == pytest.approx(1 - ((izz - fit) ** 2).sum()
                                           / ((izz - izz.mean()) ** 2).sum())
    assert line.relative_sd == pytest.approx(np.sqrt((((izz - fit) / fit) ** 2).sum() / 3))
    assert line.mass_range == (1000.0, 1800.0) and line.count == 5
    centre, edge = line.predictive_sd([1400.0, 1800.0])
    assert centre == pytest.approx(line.relative_sd * math.sqrt(1 + 1 / 5))
    assert edge > centre
    inertia, sd = yaw_inertia_from_mass([1400.0, 1800.0], line)
    assert inertia == pytest.approx(line.slope * np.array([1400, 1800]) + line.intercept)
    assert sd == pytest.approx(line.predictive_sd([1400.0, 1800.0]) * inertia)


def test_the_mass_only_line_refuses_masses_outside_its_vehicles():
    line = mass_regression([1000.0, 1500.0, 2000.0], [1500.0, 3000.0, 4400.0], "car", "t")
    for bad in (999.0, 2000.5, float("nan")):
        with pytest.raises(InputError, match=r"within the 1000-2000 kg of the 3 measured cars"):
            yaw_inertia_from_mass([1500.0, bad], line)
    with pytest.raises(InputError, match="at least 3"):
        mass_regression([1000.0, 1000.0, 1000.0], [1.0, 2.0, 3.0], "car", "t")
