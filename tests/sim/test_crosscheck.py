"""PIM against the pymunk simulation of one case (sim.crosscheck)."""

import pytest

import pim
from sim.crosscheck import CrossCheck, crosscheck


def test_ricsac9_crosscheck_agrees_and_tabulates():
    check = crosscheck(pim.load_case("ricsac9"), eps=0.355, beta=1.0)
    assert isinstance(check, CrossCheck) and check.limitations == []
    assert (check.eps, check.beta) == (0.355, 1.0)
    # sticking contact (beta = 1) on the fixed-step engine: agreement to 1e-6 of the change
    # (docs/sim.md), the one error measure of sim.error_measure
    assert check.error < 1e-6
    assert "velocity" in check.format_table()


def test_bad_input_is_a_value_error():
    with pytest.raises(ValueError):
        crosscheck(pim.load_case("ricsac9"), eps=2.0, beta=1.0)
