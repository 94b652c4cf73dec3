"""pim/model/formula.py: the one formula, evaluated on floats and on arrays.

The same function runs on plain Python floats (the scalar path), on numpy arrays (the
reference path) and compiled by numba (tests/pim/model/test_kernel.py); on one input the float and
array evaluations must agree bitwise, and both must match Brach's scalar equations in exact
rational arithmetic (tests/exact.py, an independent derivation) to round-off.
"""

import math

import numpy as np
import pytest

from pim.model import formula
from tests.exact import brach_exact

APPROACH, SINGULAR = 1e-12, 1e-12


def _inputs(rng):
    m1, m2 = rng.uniform(500, 3000, 2)
    return dict(a1=1 / m1, b1=1 / (m1 * rng.uniform(0.8, 2) ** 2), r1x=rng.uniform(-3, 3),
                r1y=rng.uniform(-3, 3), v1x=rng.uniform(-30, 30), v1y=rng.uniform(-30, 30),
                w1=rng.uniform(-3, 3), a2=1 / m2, b2=1 / (m2 * rng.uniform(0.8, 2) ** 2),
                r2x=rng.uniform(-3, 3), r2y=rng.uniform(-3, 3), v2x=rng.uniform(-30, 30),
                v2y=rng.uniform(-30, 30), w2=rng.uniform(-3, 3))


def _evaluate(gamma, eps, beta, x, cos=math.cos, sin=math.sin, where=None):
    cs, sn = cos(gamma), sin(gamma)
    out = formula.contact(cs, sn, x["a1"], x["b1"], x["r1x"], x["r1y"], x["v1x"], x["v1y"],
                          x["w1"], x["a2"], x["b2"], x["r2x"], x["r2y"], x["v2x"], x["v2y"],
                          x["w2"], eps, beta, APPROACH, SINGULAR)
    c = dict(zip(formula.CONTACT_OUTPUTS, out, strict=True))
    if where is None:
        scale = math.nan if c["singular"] else (c["drive"] / c["denom"] if c["approaching"]
                                                else 0.0)
    else:
        scale = where(c["approaching"], c["drive"] / c["denom"], 0.0)
    post = formula.post_impact(scale, c["pn0"], c["pt0"], beta, cs, sn, x["a1"], x["b1"],
                               x["r1x"], x["r1y"], x["v1x"], x["v1y"], x["w1"], x["a2"],
                               x["b2"], x["r2x"], x["r2y"], x["v2x"], x["v2y"], x["w2"])
    c.update(zip(formula.POST_IMPACT_OUTPUTS, post, strict=True))
    return c


def test_floats_and_arrays_agree_bitwise():
    rng = np.random.default_rng(11)
    for _ in range(300):
        x = _inputs(rng)
        gamma, eps, beta = rng.uniform(-np.pi, np.pi), rng.uniform(0, 1), rng.uniform(0, 1)
        scalar = _evaluate(gamma, eps, beta, x)
        arrays = _evaluate(np.array([gamma]), np.array([eps]), np.array([beta]),
                           {k: np.array([v]) for k, v in x.items()}, cos=np.cos, sin=np.sin,
                           where=np.where)
        for name, value in scalar.items():
            assert np.array_equal(np.asarray(value, float), np.asarray(arrays[name], float)[0],
                                  equal_nan=True), name


@pytest.mark.parametrize("beta", [0.0, 0.4, 1.0])
def test_formula_matches_brach_exact_at_gamma_zero(beta):
    """Gamma = 0: Brach's eqs. 6.45-6.60 in exact fractions (tests/exact.py)."""
    rng = np.random.default_rng(12)
    checked = 0
    for _ in range(200):
        m1, m2 = rng.uniform(500, 3000, 2)
        i1, i2 = m1 * rng.uniform(0.8, 2) ** 2, m2 * rng.uniform(0.8, 2) ** 2
        g1, g2, c = rng.uniform(-3, 3, 2), rng.uniform(-3, 3, 2), rng.uniform(-1, 1, 2)
        v1, v2, w1, w2 = rng.uniform(-30, 30, 2), rng.uniform(-30, 30, 2), *rng.uniform(-2, 2, 2)
        eps = rng.uniform(0, 1)
        x = dict(a1=1 / m1, b1=1 / i1, r1x=c[0] - g1[0], r1y=c[1] - g1[1], v1x=v1[0],
                 v1y=v1[1], w1=w1, a2=1 / m2, b2=1 / i2, r2x=c[0] - g2[0], r2y=c[1] - g2[1],
                 v2x=v2[0], v2y=v2[1], w2=w2)
        got = _evaluate(0.0, eps, beta, x)
        if not got["approaching"]:
            continue
        ref = brach_exact(m1, i1, g1, v1, w1, m2, i2, g2, v2, w2, c, eps, beta)
        scale = max(abs(float(ref["velocity1"][0])), abs(float(ref["velocity1"][1])), 1.0)
        for name, want in (("vx1", ref["velocity1"][0]), ("vy1", ref["velocity1"][1]),
                           ("vx2", ref["velocity2"][0]), ("vy2", ref["velocity2"][1])):
            assert abs(got[name] - float(want)) <= 1e-9 * scale, name
        assert got["w1"] == pytest.approx(float(ref["yaw_rate1"]), rel=1e-9, abs=1e-9)
        assert got["p_n"] == pytest.approx(float(ref["impulse"][0]), rel=1e-9)
        checked += 1
    assert checked > 50


def test_no_approach_gives_no_impulse_and_singular_q_is_flagged():
    x = _inputs(np.random.default_rng(13))
    x.update(v1x=5.0, v1y=0.0, v2x=-5.0, v2y=0.0, w1=0.0, w2=0.0)   # separating along n
    away = _evaluate(0.0, 0.5, 1.0, x)
    assert not away["approaching"] and away["p_n"] == 0.0 and away["vx1"] == 5.0
    toward = _evaluate(np.pi, 0.5, 1.0, x)      # the same motion, n reversed: approaching
    assert toward["approaching"] and toward["p_n"] > 0
    # beta that zeroes K_nn Pn0 + beta K_nt Pt0: q = 1/(A - mu B) singular
    c = toward
    beta = -(c["k_nn"] * c["pn0"]) / (c["k_nt"] * c["pt0"])
    sing = _evaluate(np.pi, 0.5, beta, x)
    assert sing["singular"] and math.isnan(sing["vx1"])
