"""comparisons.regression.sections: what each section records, its tolerances, what a case
does not support, and the Monte Carlo's standard errors."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pim
from comparisons.regression.sections import (
    CLOSED_FORM_REL,
    DEFAULT_SETTINGS,
    SIM_REL,
    run_section,
    standard_error,
)


def test_solve_records_every_output_in_si_with_round_off_tolerance(ricsac9):
    rows = {r.name: r for r in run_section("solve", ricsac9, DEFAULT_SETTINGS)}
    r = rows["solve.yaw_rate1"]
    # the design sheet prints -199.702 deg/s (ricsac9.md, relative 2e-3)
    assert math.degrees(r.value) == pytest.approx(-199.702, rel=2e-3)
    assert r.unit == "rad/s" and r.relative == CLOSED_FORM_REL
    # absolute floor: 1e-12 of the largest yaw rate (a well-conditioned case: the scene
    # moved by round-off changes it by less than 1e-11)
    assert CLOSED_FORM_REL * abs(r.value) <= r.absolute < 1e-11 * abs(r.value)
    assert rows["solve.energy_loss"].unit == "J"
    assert rows["solve.kinetic_energy_before"].value == pytest.approx(1.074e5 * 1.3558179,
                                                                      rel=2e-3)


def test_an_ill_conditioned_output_gets_the_tolerance_its_conditioning_needs():
    # hard-near-singular-q: A - mu B ~ 2e-6, q ~ 5e5: a relative perturbation d of the inputs
    # moves q by about q d / 2e-6, far beyond 1e-12 of q; the impulse stays well conditioned
    # (Pn = m_c (1 + eps) v_rn q stays finite, the case file's comment)
    rows = {r.name: r for r in run_section("solve", pim.load_case("hard-near-singular-q"),
                                           DEFAULT_SETTINGS)}
    q = rows["solve.q"]
    assert q.value > 1e5 and 1e-11 * q.value < q.absolute < 1e-6 * q.value
    pn = rows["solve.impulse_n"]
    assert pn.absolute < 1e-10 * pn.value


def test_crosscheck_tolerance_is_the_rigid_scenes_stated_accuracy(ricsac9):
    rows = {r.name: r for r in run_section("crosscheck", ricsac9, DEFAULT_SETTINGS)}
    assert rows["crosscheck.error"].value < 1e-12 and rows["crosscheck.error"].absolute == SIM_REL
    assert rows["crosscheck.speed1"].relative == SIM_REL


@pytest.mark.parametrize("case, section, why", [
    ("hard-pole", "fit", "no \\[measured\\]"),
    ("hard-pole", "uncertainty", "no \\[uncertainty\\]"),
    ("ricsac9", "reconstruct", "no \\[unknown\\]"),
    ("ricsac9-reconstruct", "solve", "restitution"),
    ("ricsac9-reconstruct", "fit", "do not approach"),
])
def test_what_a_case_does_not_support_is_skipped_with_the_reason(case, section, why):
    with pytest.raises(LookupError, match=why):
        run_section(section, pim.load_case(case), DEFAULT_SETTINGS)


def test_unknown_section_is_a_value_error(ricsac9):
    with pytest.raises(ValueError, match="allowed: solve"):
        run_section("solver", ricsac9, DEFAULT_SETTINGS)


def test_monte_carlo_statistics_are_exact_on_same_versions_with_a_stated_spread(ricsac9):
    rows = run_section("uncertainty", ricsac9, {**DEFAULT_SETTINGS, "uncertainty_samples": 500})
    p50 = next(r for r in rows if r.name == "uncertainty.speed1.p50")
    assert p50.exact_same_versions and p50.absolute > 0 and "standard errors" in p50.basis


def test_standard_errors_of_a_normal_sample_match_the_textbook():
    # independent: for N(0, 1), SE(mean) = 1/sqrt(n), SE(median) = sqrt(pi/2)/sqrt(n),
    # SE(p5) = sqrt(p(1-p)/n) / phi(1.645) = 2.11/sqrt(n), SE(sd) = 1/sqrt(2(n-1))
    n = 200_000
    x = np.random.default_rng(1).standard_normal(n)
    assert standard_error(x, "mean") == pytest.approx(1 / math.sqrt(n), rel=0.01)
    assert standard_error(x, "p50") == pytest.approx(math.sqrt(math.pi / 2 / n), rel=0.1)
    phi = math.exp(-1.6449 ** 2 / 2) / math.sqrt(2 * math.pi)
    assert standard_error(x, "p5") == pytest.approx(math.sqrt(0.05 * 0.95 / n) / phi, rel=0.1)
    assert standard_error(x, "sd") == pytest.approx(1 / math.sqrt(2 * (n - 1)), rel=0.01)
    assert math.isnan(standard_error([1.0], "mean"))


@settings(max_examples=30, deadline=None)
@given(st.floats(0.1, 100), st.floats(-1e3, 1e3))
def test_standard_error_scales_with_the_sample_and_ignores_a_shift(scale, shift):
    x = np.random.default_rng(0).standard_normal(400)
    for stat in ("p5", "p50", "p95", "mean", "sd"):
        assert standard_error(scale * x + shift, stat) == pytest.approx(
            scale * standard_error(x, stat), rel=1e-6, abs=1e-9)
