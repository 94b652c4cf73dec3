"""The one comparison error (sim.error_measure) on constructed answers."""

import numpy as np
import pytest

import pim
from sim.error_measure import compare_results, impact_error


def test_zero_for_the_analytic_answer_and_linear_in_a_perturbation():
    case = pim.load_case("ricsac9")
    r = pim.solve(case, 0.355, 1.0)
    v1, v2 = np.asarray(r.velocity1), np.asarray(r.velocity2)
    w1, w2 = float(r.yaw_rate1), float(r.yaw_rate2)
    assert float(impact_error(case, r, v1, v2, w1, w2)) == 0.0
    # e = largest change error / largest change, yaw changes times k = sqrt(I / m), each
    # velocity change by its largest component (the maximum norm)
    def k(v):
        return float(np.sqrt(v.yaw_inertia / v.mass))

    scale = max(float(np.max(np.abs(v1 - case.vehicle1.velocity))),
                float(np.max(np.abs(v2 - case.vehicle2.velocity))),
                k(case.vehicle1) * abs(w1 - float(case.vehicle1.yaw_rate)),
                k(case.vehicle2) * abs(w2 - float(case.vehicle2.yaw_rate)))
    e = float(impact_error(case, r, v1 + [0.05, 0.0], v2, w1, w2))
    assert e == pytest.approx(0.05 / scale, rel=1e-9)
    e = float(impact_error(case, r, v1, v2, w1, w2 + 0.1))
    assert e == pytest.approx(k(case.vehicle2) * 0.1 / scale, rel=1e-9)
    assert np.isnan(impact_error(case, r, v1 * np.nan, v2, w1, w2))


def test_rows_cover_the_post_impact_quantities():
    import sim

    case = pim.load_case("ricsac9")
    r = pim.solve(case, 0.355, 1.0)
    rows = compare_results(case, r, sim.simulate(case, 0.355, 1.0))
    assert len(rows) >= 6 and all(np.isfinite(row.absolute) for row in rows)
