"""Each measured quantity against the model, in sigmas (pim.analysis.misfit).

Independent references: the RICSAC 9 measurements (Brach & Brach 2011, the case file) and
the model's values at the sheet's optimum (epsilon = 0.355, beta = 1; spec ricsac9.md: vehicle
2's yaw rate 87.3 deg/s), with the published tolerances 1 mph and 10 deg/s (SAE
2014-01-0469) as the sigmas the case does not state.
"""

from dataclasses import replace

import numpy as np
import pytest

import pim
from pim.analysis.misfit import NOMINAL_SIGMAS, POOR, misfit

MPH = 0.44704


def test_ricsac9_vehicle_2_yaw_rate_is_the_worst_miss():
    case = pim.load_case("ricsac9")
    found = misfit(pim.solve(case, 0.355, 1.0))
    assert [r.name for r in found.rows] == ["velocity1_x", "velocity1_y", "velocity2_x",
                                            "velocity2_y", "yaw_rate1", "yaw_rate2"]
    yaw2 = found.rows[-1]
    assert np.degrees(yaw2.measured) == pytest.approx(45.0)
    assert np.degrees(yaw2.model) == pytest.approx(87.3, abs=0.05)
    assert yaw2.sigma == pytest.approx(np.radians(10.0)) and not yaw2.stated
    assert yaw2.z == pytest.approx((87.3 - 45.0) / 10.0, abs=0.01)
    assert found.poor and found.poor_rows[0] is yaw2
    assert all(abs(r.z) > POOR for r in found.poor_rows)
    v1y = found.rows[1]
    assert v1y.z == pytest.approx((12.79 - 17.6) * 0.3048 / MPH, abs=0.02)


def test_stated_sigmas_are_used():
    case = pim.load_case("ricsac9")
    m = replace(case.measured, velocity1_sigma=[0.3, 0.3], velocity2_sigma=[0.3, 0.3],
                yaw_rate1_sigma=0.5, yaw_rate2_sigma=0.5)
    found = misfit(pim.solve(replace(case, measured=m), 0.355, 1.0))
    assert found.stated and all(r.stated for r in found.rows)
    assert [r.sigma for r in found.rows] == [0.3] * 4 + [0.5] * 2


def test_an_exact_fit_is_not_poor_and_nothing_measured_is_no_rows():
    case = pim.load_case("ricsac9")
    exact = pim.solve(case, 0.355, 1.0)
    measured = pim.Measured(velocity1=exact.velocity1, velocity2=exact.velocity2,
                            yaw_rate1=float(exact.yaw_rate1), yaw_rate2=float(exact.yaw_rate2))
    found = misfit(pim.solve(replace(case, measured=measured), 0.355, 1.0))
    assert not found.poor and max(abs(r.z) for r in found.rows) < 1e-9
    assert misfit(pim.solve(replace(case, measured=None), 0.355, 1.0)).rows == ()
    assert NOMINAL_SIGMAS["velocity"] == pytest.approx(MPH)
