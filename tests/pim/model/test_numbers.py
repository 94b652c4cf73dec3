"""pim/model/numbers.py: numbers are numbers; strings, booleans and complex values are not."""

import numpy as np
import pytest

import pim
import sim
from pim.analysis.reconstruction import reconstruct
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


@pytest.mark.parametrize("call", [
    lambda case: pim.solve(case, 0.3, 1.0, approach_tol=-1),
    lambda case: pim.solve(case, 0.3, 1.0, approach_tol=float("nan")),
    lambda case: pim.solve(case, "0.3", 1.0),
    lambda case: pim.fit(case, max_starts=0),
    lambda case: pim.fit(case, samples=0),
    lambda case: pim.fit(case, eps="0.3"),
    lambda case: pim.sensitivity(case, eps="0.3", beta=1.0),
    lambda case: pim.uncertainty(case, n="100", eps=0.3, beta=1.0),
    lambda case: pim.uncertainty(case, n=100, eps=0.3, beta=float("nan")),
    lambda case: reconstruct(case, samples="100"),
    lambda case: reconstruct(case, blocks=0),
    lambda case: sim.simulate_many([case], 0.3, 1.0, max_workers=0),
    lambda case: sim.simulate_many([case], 0.3, 1.0, chunksize=-1),
])
def test_public_entry_points_check_their_numeric_arguments(ricsac9, call):
    """Issue 22: each of these was accepted (or failed with a TypeError) before."""
    with pytest.raises(InputError, match=r"approach_tol|eps|beta|max_starts|samples|n \(|"
                                         r"blocks|max_workers|chunksize"):
        call(ricsac9)


def test_a_wrong_type_is_a_type_error_and_an_input_error_naming_the_argument():
    from pim.model.numbers import ArgumentTypeError, check_type

    with pytest.raises(ArgumentTypeError) as info:
        check_type("x", "settings", int, "an int")
    assert isinstance(info.value, TypeError) and isinstance(info.value, InputError)
    assert str(info.value) == "settings must be an int, got 'x'"
    with pytest.raises(TypeError, match=r"^n must be an int or None, got a float$"):
        check_type(1.5, "n", int, "an int", none=True)
    assert check_type(None, "n", int, "an int", none=True) is None


def test_did_you_mean_names_the_closest_choice_only_when_close():
    from pim.model.numbers import did_you_mean

    assert did_you_mean("yawrate", ["mass", "yaw_rate", "cg"]) == "; did you mean 'yaw_rate'?"
    assert did_you_mean("colour", ["mass", "yaw_rate", "cg"]) == ""
