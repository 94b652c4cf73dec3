"""pim/model/numbers.py: numbers are numbers; strings, booleans and complex values are not."""

import numpy as np
import pytest

from pim.model.numbers import real_array


@pytest.mark.parametrize("value", [1, 2.5, [1, 2], np.arange(3), np.float32(1.5)])
def test_real_numbers_pass_as_float_arrays(value):
    assert real_array(value, "x").dtype == float


@pytest.mark.parametrize("value", ["1000", b"1", True, np.bool_(False), None, 1j,
                                   [1, "a"], np.array([1 + 0j]), [[1, 2], [3]]])
def test_everything_else_names_the_field(value):
    with pytest.raises(ValueError, match="vehicle1.mass"):
        real_array(value, "vehicle1.mass", "kg")
