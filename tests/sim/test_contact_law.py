"""The contact law alone: hysteresis, restitution of a point mass, friction spring, inputs."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy.integrate import quad

from sim import contact_law as law

finite = dict(allow_nan=False, allow_infinity=False)


def test_linear_law_is_the_bilinear_model_of_the_issue():
    # F = k delta loading; (k / eps^2)(delta - delta_p) unloading; delta_p = dmax (1 - eps^2)
    k, eps, dmax = 7.5e5, 0.4, 0.5
    dp = dmax * (1 - eps ** 2)
    assert law.permanent_crush(dmax, eps, 0.0, k) == pytest.approx(dp, rel=1e-15)
    assert law.unloading_slope(dmax, eps, 0.0, k) == pytest.approx(k / eps ** 2, rel=1e-14)
    delta = np.array([0.1, 0.5, 0.49, 0.45, dp + 1e-3, dp - 1e-3, -0.1])
    dm = np.array([0.1, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5])
    expected = [k * 0.1, k * 0.5, k / eps ** 2 * (0.49 - dp), k / eps ** 2 * (0.45 - dp),
                k / eps ** 2 * 1e-3, 0.0, 0.0]
    assert law.normal_force(delta, dm, eps, 0.0, k) == pytest.approx(expected, rel=1e-9)


def test_campbell_preload_with_high_eps_returns_less_than_eps_squared():
    # the unloading line would end below zero crush; the force is zero there (documented)
    a, b, dmax, eps = 2e5, 1e5, 0.2, 0.95
    assert law.permanent_crush(dmax, eps, a, b) < 0
    back, _ = quad(lambda d: float(law.normal_force(d, dmax, eps, a, b)), 0.0, dmax)
    assert back / float(law.loading_work(dmax, a, b)) < eps ** 2


def test_eps_zero_gives_no_rebound_force():
    f = law.normal_force([0.3, 0.299999, 0.1], 0.3, 0.0, 0.0, 1e6)
    assert f[0] == pytest.approx(3e5)
    assert f[1] == 0.0 and f[2] == 0.0
    assert law.permanent_crush(0.3, 0.0, 0.0, 1e6) == 0.3


@given(eps=st.floats(0.01, 1.0, **finite), dmax=st.floats(1e-3, 2.0, **finite),
       a=st.floats(0.0, 5e5, **finite), b=st.floats(1e4, 5e6, **finite))
def test_unloading_returns_eps_squared_of_the_loading_work(eps, dmax, a, b):
    # energy returned / energy absorbed = eps^2, i.e. a point mass rebounds at eps times
    # its approach speed (Campbell's form a + b delta included, while the unloading line
    # ends at a crush >= 0; beyond that see the next test)
    dp = float(law.permanent_crush(dmax, eps, a, b))
    assume(dp >= 1e-9 * dmax)
    back, _ = quad(lambda d: float(law.normal_force(d, dmax, eps, a, b)), dp, dmax,
                   epsabs=0, epsrel=1e-12)
    work = float(law.loading_work(dmax, a, b))
    assert back / work == pytest.approx(eps ** 2, rel=1e-9)
    assert 0.0 <= dp <= dmax


def test_point_mass_rebounds_at_exactly_eps():
    # a 1-DOF mass integrated in closed form phase by phase: loading is a harmonic quarter
    # period (delta_max = v0 / omega), unloading a quarter period of the stiffer spring from
    # rest at delta_max: speed at delta_p = (F_max / s) sqrt(s / m) = eps v0
    m, k, v0 = 1500.0, 7.5e5, 15.0
    for eps in (0.0, 0.1, 0.355, 1.0):
        dmax = v0 / math.sqrt(k / m)
        s = float(law.unloading_slope(dmax, eps, 0.0, k))
        f_max = float(law.normal_force(dmax, dmax, eps, 0.0, k))
        rebound = 0.0 if eps == 0 else f_max / s * math.sqrt(s / m)
        assert rebound == pytest.approx(eps * v0, rel=1e-12, abs=1e-12)


def test_friction_spring_sticks_inside_the_cone_and_slides_on_it():
    z = law.tangential_step(0.0, 2.0, 1e-3, 0.01)        # inside: follows the slip
    assert z == pytest.approx(2e-3)
    z = law.tangential_step(z, 20.0, 1e-3, 0.01)         # pushed beyond: on the cone
    assert z == pytest.approx(0.01)
    z = law.tangential_step(z, -1.0, 1e-3, 0.01)         # reversal: back inside at once
    assert z == pytest.approx(0.009)
    z = law.tangential_step(z, 0.0, 1e-3, 0.004)         # shrinking cone drags it along
    assert z == pytest.approx(0.004)
    assert law.tangential_force(0.004, 1e6, 1e3) == pytest.approx(-1e3)
    assert law.tangential_force(-0.0001, 1e6, 1e3) == pytest.approx(100.0)


def test_duration_and_stiffness_are_inverse():
    k_nn = 1 / 1500 + 1 / 1800
    for eps in (0.0, 0.3, 1.0):
        k = law.stiffness_for_duration(0.1, k_nn, eps)
        assert law.contact_duration_estimate(k, k_nn, eps) == pytest.approx(0.1, rel=1e-14)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "7e5", True, None])
def test_bad_stiffness_and_duration_are_clear_errors(bad):
    with pytest.raises(ValueError, match="stiffness"):
        law.check_positive(bad, "stiffness", "N/m")
    if not isinstance(bad, str | bool | type(None)):
        with pytest.raises(ValueError, match="duration"):
            law.stiffness_for_duration(bad, 1e-3, 0.3)


@pytest.mark.parametrize("recovery", [0.0, 0.25, 0.6, 1.0])
def test_tangential_step_gives_back_r_of_the_stored_energy(recovery):
    # load the spring (k_t = 1) by slip 1 mm at 1 m/s, then slip back until the force is 0:
    # stored k z^2 / 2, returned = work of the force over the backward slip = r of it
    dt, z, z_max = 1e-6, 0.0, 1.0
    for _ in range(1000):
        z = float(law.tangential_step(z, 1.0, dt, z_max, recovery))
    stored = 0.5 * z * z
    returned, steps = 0.0, 0
    while z > 0.0 and steps < 10_000:
        new = float(law.tangential_step(z, -1.0, dt, z_max, recovery))
        returned += 0.5 * (z + max(new, 0.0)) * min(dt, z * recovery)   # force x slip
        z, steps = new, steps + 1
    assert z <= 0.0
    assert returned == pytest.approx(recovery * stored, abs=2e-3 * stored)


def test_tangential_step_with_full_recovery_is_the_elastic_spring():
    rng = np.random.default_rng(1)
    z, slip, z_max = rng.normal(size=(3, 1000))
    z_max = np.abs(z_max)
    got = law.tangential_step(z, slip, 0.3, z_max, 1.0)
    assert np.array_equal(got, np.clip(z + 0.3 * slip, -z_max, z_max))
    assert np.array_equal(law.tangential_step(z, slip, 0.3, z_max), got)
    assert law.tangential_recovery_default(0.3) == pytest.approx(0.09)
