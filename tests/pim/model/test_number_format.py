"""The one number format of the reports (pim.model.number_format), issue 28 item 4:
digits matched to the uncertainty, one format for a value and its interval, round-off as 0,
never ``0.0000``.

Expected strings are written by hand from the rule (two significant digits of the
interval's half-width), not taken from the program's output.
"""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from pim.model.number_format import (
    ROUND_OFF,
    format_interval,
    format_number,
    interval_decimals,
    round_off,
)


@pytest.mark.parametrize("x, text", [
    (28.0467, "28.05"), (31485.5, "31490"), (0.0142, "0.0142"), (1.0, "1"), (180.0, "180"),
    (-27.1288, "-27.13"), (6.09e-05, "6.09e-05"), (2.33e-16, "2.33e-16"), (1e7, "1e+07"),
    (-0.0, "0"), (0.0, "0"), (3, "3"), (True, "yes"), (None, ""), (math.nan, ""),
    ("text", "text")])
def test_significant_digits(x, text):
    assert format_number(x) == text


def test_explicit_decimals_keep_their_zeros_and_round_to_tens():
    assert format_number(28.0467, decimals=1) == "28.0"
    assert format_number(1.0, decimals=3) == "1.000"
    assert format_number(31485.5, decimals=-2) == "31500"
    assert format_number(-0.04, decimals=1) == "0"              # no "-0"
    assert format_number(1.2345e-05, decimals=8) == "1.234e-05"  # scientific, same digits


@pytest.mark.parametrize("low, high, decimals", [
    (24.81, 31.27, 1),          # half-width 3.23: 3.2
    (27450.0, 35810.0, -2),     # half-width 4180: 4200
    (-227.3, -168.9, 0),        # half-width 29.2: 29
    (0.0, 1.0, 2),              # half-width 0.5: 0.50
    (5.0, 5.0, None), (math.nan, 1.0, None), (2.0, 1.0, None)])
def test_interval_decimals_show_two_digits_of_the_half_width(low, high, decimals):
    assert interval_decimals(low, high) == decimals


def test_ricsac9_results_in_one_format():
    """Issue 28: `|delta-V| 28.0467 ft/s` beside 24.81 to 31.27, and `31485.5 | 2.745e+04 to
    3.581e+04`: the value and its interval now share one format and the digits the
    interval allows."""
    assert format_interval(28.0467, 24.81, 31.27) == ("28.0", "24.8", "31.3")
    assert format_interval(31485.5, 27450.0, 35810.0) == ("31500", "27400", "35800")
    assert format_interval(3e6, 2.5e6, 3.6e6) == ("3.00e+06", "2.50e+06", "3.60e+06")
    assert format_interval(12.5, math.nan, math.nan) == ("12.5", "", "")


def test_never_a_run_of_zeros():
    """Issue 28: a time printed as `0.0000 ms`."""
    for x in (6.09e-05, 4.9e-05, 1e-9, -3.2e-07):
        text = format_number(x)
        assert float(text) == pytest.approx(x, rel=1e-3) and not text.startswith(("0.0", "-0.0"))


def test_round_off_is_zero_against_the_scale_of_its_quantity():
    """Issue 28: `tangential crush energy 4.96e-16 kJ` beside a loss of tens of kJ."""
    assert round_off(4.96e-16, 92.3) == 0.0
    assert round_off(13.9, 92.3) == 13.9
    assert round_off(-1e-12, 1.0) == 0.0 and round_off(1e-8, 1.0) == 1e-8
    assert round_off(1e-20, 0.0) == 1e-20                          # no scale: kept
    assert math.isnan(round_off(math.nan, 1.0))


@given(st.floats(-1e12, 1e12, allow_nan=False), st.floats(1e-9, 1e9))
def test_the_value_and_its_interval_round_to_within_half_a_unit(value, half):
    low, high = value - half, value + half
    v, lo, hi = format_interval(value, low, high)
    decimals = interval_decimals(low, high)
    if decimals is None:            # the half-width is lost in round-off beside the value
        return
    unit = 10.0 ** -decimals
    tol = 0.5 * unit + 1e-9 * abs(value) + 1e-300
    assert abs(float(v) - value) <= tol
    assert abs(float(lo) - low) <= tol and abs(float(hi) - high) <= tol


@given(st.floats(-1e300, 1e300))
def test_every_finite_float_reads_back(x):
    text = format_number(x)
    assert text == "0" if x == 0 else float(text) == pytest.approx(x, rel=1e-3)
    assert ROUND_OFF < 1e-6


def test_duration_text_picks_seconds_minutes_or_hours():
    from pim.model.number_format import duration_text

    assert duration_text(119) == "119 s"
    assert duration_text(120) == "2 min"
    assert duration_text(7199) == "120 min"
    assert duration_text(7200) == "2.0 h"
