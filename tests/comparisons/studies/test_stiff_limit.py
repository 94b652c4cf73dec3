"""k -> infinity: the frictionless finite-duration contact converges to PIM (beta = 0) at
first order in the contact time (the expected order, 1, is the test's independent value)."""

import pytest

import pim
from comparisons.studies.stiff_limit import plot_stiff_limit, stiff_limit


@pytest.fixture(scope="module")
def ricsac9():
    return pim.load_case("ricsac9")


def test_frictionless_stiff_limit_is_pim_beta0_at_first_order(ricsac9):
    # the error against PIM (beta = 0, same eps) falls in proportion to the contact time
    limit = stiff_limit(ricsac9, 0.355, durations=(0.04, 0.02, 0.01, 0.005))
    assert limit.order == pytest.approx(1.0, rel=0.10)
    assert limit.errors[-1] < limit.errors[0] / 6
    assert len(plot_stiff_limit(limit).axes) == 1
