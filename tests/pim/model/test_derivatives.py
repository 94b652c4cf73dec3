"""tests/closed_form.py (the hand-derived d/d(eps, beta) oracle) against central
finite differences of pim.solve (and, in tests/pim/model/test_dual.py, against dual numbers)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import pim
from pim.model.quantities import OUTPUTS
from pim.model.result import output_values
from tests.closed_form import derivatives


def _central(case, eps, beta, param, h=1e-6):
    """Central finite difference of every output of pim.solve (independent of derivatives)."""
    if param == "eps":
        plus, minus = pim.solve(case, eps + h, beta), pim.solve(case, eps - h, beta)
    else:
        plus, minus = pim.solve(case, eps, beta + h), pim.solve(case, eps, beta - h)
    vp, vm = output_values(plus), output_values(minus)
    return {k: (vp[k] - vm[k]) / (2 * h) for k in vp}


@pytest.mark.parametrize("which", ["ricsac9", "spinning"])
@pytest.mark.parametrize("eps, beta", [(0.355, 1.0), (0.2, 0.6), (0.7, 0.3), (0.5, 1.3)])
def test_derivatives_match_finite_differences(request, which, eps, beta):
    case = request.getfixturevalue(which)
    d = derivatives(pim.solve(case, eps, beta))
    assert set(d.d_eps) == set(d.d_beta) == set(d.values) == set(OUTPUTS)
    for param, closed in (("eps", d.d_eps), ("beta", d.d_beta)):
        fd = _central(case, eps, beta, param)
        for key in OUTPUTS:
            scale = max(abs(float(d.values[key])), 1.0)
            expected = pytest.approx(float(fd[key]), rel=1e-5, abs=1e-7 * scale)
            assert float(closed[key]) == expected, (param, key)


def test_derivatives_broadcast(ricsac9):
    eps = np.linspace(0.05, 0.95, 7)[:, None]
    beta = np.linspace(0.1, 1.0, 5)[None, :]
    d = derivatives(pim.solve(ricsac9, eps, beta))
    assert d.d_eps["velocity1_x"].shape == (7, 5)
    single = derivatives(pim.solve(ricsac9, eps[3, 0], beta[0, 2]))
    for key in OUTPUTS:
        assert d.d_beta[key][3, 2] == pytest.approx(float(single.d_beta[key]), rel=1e-12, abs=1e-15)


def test_no_approach_has_zero_derivatives(ricsac9):
    away = replace(ricsac9, vehicle1=replace(ricsac9.vehicle1, velocity=(10.0, 0.0)))
    d = derivatives(pim.solve(away, 0.3, 0.5))
    assert not d.result.approaching
    assert d.d_eps["velocity1_x"] == 0 and d.d_beta["impulse_n"] == 0
