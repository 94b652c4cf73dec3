"""pim/model/numbers.py: numbers are numbers; strings, booleans and complex values are not."""

import numpy as np
import pytest

from pim.model.numbers import InputError, checked_count, checked_number, real_array


@pytest.mark.parametrize("value", [1, 2.5, [1, 2], np.arange(3), np.float32(1.5)])
def test_real_numbers_pass_as_float_arrays(value):
    assert real_array(value, "x").dtype == float


@pytest.mark.parametrize("value", ["1000", b"1", True, np.bool_(False), None, 1j,
                                   [1, "a"], np.array([1 + 0j]), [[1, 2], [3]]])
def test_everything_else_names_the_field(value):
    with pytest.raises(ValueError, match="vehicle1.mass"):
        real_array(value, "vehicle1.mass", "kg")


# --- Issue 22: one validator for the API's numeric arguments ----------------------------



@pytest.mark.parametrize("value", ["0.3", None, True, float("nan"), float("inf"), -1.0, 1j])
def test_checked_number_refuses_and_names_the_argument(value):
    with pytest.raises(InputError, match="approach_tol"):
        checked_number(value, "approach_tol", low=0.0)


def test_checked_number_accepts_numbers_in_range():
    assert checked_number(0, "x", low=0.0) == 0.0
    assert checked_number(np.float32(0.5), "x", low=0.0, high=1.0) == 0.5
    with pytest.raises(InputError, match=r"x .*\(0, 1\]"):
        checked_number(0.0, "x", low=0.0, high=1.0, low_open=True)


@pytest.mark.parametrize("value", ["100", 10.5, True, None, float("nan"), 0, -1])
def test_checked_count_refuses(value):
    with pytest.raises(InputError, match="samples"):
        checked_count(value, "samples")


def test_checked_count_accepts_integers_and_integral_floats():
    assert checked_count(np.int64(5), "n") == 5
    assert checked_count(1e6, "n") == 1_000_000
    assert checked_count(None, "n", none=True) is None
    assert checked_count(0, "n", low=0) == 0
