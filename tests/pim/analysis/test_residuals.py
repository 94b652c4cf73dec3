"""pim/analysis/residuals.py: residuals are V - V_measured and k (W - W_measured); with
sigmas they are standardised and their sum of squares is tested as a chi-square."""

from dataclasses import replace

import numpy as np
import pytest

import pim
from pim.analysis.residuals import (
    goodness_of_fit,
    has_measured_terms,
    measured_terms,
    measured_weights,
    residuals,
)
from pim.model.motion import Term


@pytest.fixture()
def ricsac9():
    return pim.load_case("ricsac9")


def test_residuals_by_hand(ricsac9):
    r = pim.solve(ricsac9, 0.3, 0.8)
    m = ricsac9.measured
    names = measured_terms(ricsac9, include_yaw=True)
    got = dict(zip((t.name for t in names), residuals(r, names), strict=True))
    assert got["velocity1_x"] == pytest.approx(r.velocity1[0] - m.velocity1[0])
    assert got["velocity2_y"] == pytest.approx(r.velocity2[1] - m.velocity2[1])
    k1 = np.sqrt(float(ricsac9.vehicle1.yaw_inertia) / float(ricsac9.vehicle1.mass))
    assert got["yaw_rate1"] == pytest.approx(k1 * (float(r.yaw_rate1) - m.yaw_rate1))


def test_terms_are_typed(ricsac9):
    terms = measured_terms(ricsac9, include_yaw=True)
    assert terms == (Term(1, "vx"), Term(1, "vy"), Term(2, "vx"), Term(2, "vy"),
                     Term(1, "omega"), Term(2, "omega"))
    assert [t.name for t in terms][-1] == "yaw_rate2"


def test_weighted_residuals_divide_by_sigma(ricsac9):
    m = replace(ricsac9.measured, velocity1_sigma=[0.2, 0.4], velocity2_sigma=[1.0, 1.0],
                yaw_rate1_sigma=0.5, yaw_rate2_sigma=0.25)
    case = replace(ricsac9, measured=m)
    r = pim.solve(case, 0.3, 0.8)
    terms = measured_terms(case, include_yaw=True)
    plain, weighted = residuals(r, terms), residuals(r, terms, weighted=True)
    k1 = np.sqrt(float(case.vehicle1.yaw_inertia) / float(case.vehicle1.mass))
    np.testing.assert_allclose(weighted[:2], plain[:2] / [0.2, 0.4])
    assert weighted[4] == pytest.approx(plain[4] / (k1 * 0.5))
    np.testing.assert_allclose(measured_weights(case, terms), 1 / np.array(
        [0.2, 0.4, 1.0, 1.0, k1 * 0.5, 0.25 * np.sqrt(float(case.vehicle2.yaw_inertia)
                                                      / float(case.vehicle2.mass))]))
    with pytest.raises(ValueError, match="velocity2_x"):
        measured_weights(replace(case, measured=replace(m, velocity2_sigma=None)), terms)


def test_goodness_of_fit_p_values():
    # closed forms: 2 dof sf = exp(-x/2); the chi-square's mean is its dof
    g = goodness_of_fit(3.0, 5, 3)
    assert g.dof == 2 and g.p_value == pytest.approx(np.exp(-1.5), rel=1e-12)
    assert g.consistent and "consistent" in g.verdict()
    bad = goodness_of_fit(30.0, 6, 2)
    assert bad.consistent is False and "inconsistent with PIM" in bad.verdict()
    none = goodness_of_fit(0.0, 2, 2)
    assert none.consistent is None and np.isnan(none.p_value)
    assert none.to_dict()["p_value"] is None


def test_nothing_measured(ricsac9):
    bare = replace(ricsac9, measured=None)
    assert not has_measured_terms(bare) and has_measured_terms(ricsac9)
    only_yaw = replace(ricsac9, measured=pim.Measured(yaw_rate1=-3.0))
    assert not has_measured_terms(only_yaw) and has_measured_terms(only_yaw, include_yaw=True)
    with pytest.raises(ValueError, match="--include-yaw"):
        measured_terms(only_yaw, include_yaw=False)


def test_goodness_names_the_largest_standardised_residuals():
    from pim.analysis.residuals import goodness_of_fit

    g = goodness_of_fit(50.0, 5, 2, np.array([0.1, -6.5, 2.0, 0.3, -3.1]),
                        ["a", "b", "c", "d", "e"])
    assert g.largest == (("b", -6.5), ("e", -3.1), ("c", 2.0))
    assert g.consistent is False and "the evidence in conflict: b -6.5 sigma" in g.summary()
    assert g.to_dict()["largest_standardised_residuals"] == {"b": -6.5, "e": -3.1, "c": 2.0}
