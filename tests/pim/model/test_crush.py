"""Crush energy from crush profiles (pim.model.crush): CRASH3's closed forms, Campbell's
barrier identity, the force-balance factor (also on duals), the crush-energy delta-V against
one-dimensional impact mechanics, and the profile's checks."""

import math
from functools import cached_property

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pim.model.crush import (
    FORCE_BALANCE_CAP,
    PARTITIONS,
    CrushProfile,
    compared_energy,
    crush_delta_v,
    crush_energy,
    crush_impulse,
    effective_mass,
    equivalent_energy_speed,
    force_balance_factor,
    moment_arm,
    sqrt_of,
)
from pim.model.dual import Dual
from pim.model.result import Result

A, B = 52538.0, 689476.0          # 300 lbf/in, 10 lbf/in^2 in N/m, N/m^2
G = A * A / (2 * B)
depth = st.floats(0.0, 1.0)


def crash3_six_point(L, c, a, b):
    """CRASH3 Technical Manual eq. 2.48 (six stations), written out as published."""
    c1, c2, c3, c4, c5, c6 = c
    return L / 5 * (a / 2 * (c1 + 2 * c2 + 2 * c3 + 2 * c4 + 2 * c5 + c6)
                    + b / 6 * (c1**2 + 2 * c2**2 + 2 * c3**2 + 2 * c4**2 + 2 * c5**2 + c6**2
                               + c1 * c2 + c2 * c3 + c3 * c4 + c4 * c5 + c5 * c6)
                    + 5 * a**2 / (2 * b))


def crash3_four_point(L, c, a, b):
    c1, c2, c3, c4 = c
    return L / 3 * (a / 2 * (c1 + 2 * c2 + 2 * c3 + c4)
                    + b / 6 * (c1**2 + 2 * c2**2 + 2 * c3**2 + c4**2 + c1 * c2 + c2 * c3
                               + c3 * c4)
                    + 3 * a**2 / (2 * b))


def crash3_two_point(L, c, a, b):
    c1, c2 = c
    return L * (a / 2 * (c1 + c2) + b / 6 * (c1**2 + c1 * c2 + c2**2) + a**2 / (2 * b))


@pytest.mark.parametrize("n", [2, 3, 4, 6, 9])
def test_uniform_crush_closed_form(n):
    width, c = 1.5, 0.3
    assert crush_energy(width, [c] * n, A, B) == pytest.approx(
        width * (A * c + B * c * c / 2 + G), rel=1e-13)


@pytest.mark.parametrize("form, n", [(crash3_two_point, 2), (crash3_four_point, 4),
                                     (crash3_six_point, 6)])
def test_crash3_closed_forms_equal_the_piecewise_linear_integral(form, n):
    rng = np.random.default_rng(n)
    for _ in range(20):
        c, L = rng.uniform(0, 0.6, n), rng.uniform(0.3, 2.0)
        a, b = rng.uniform(2e4, 2e5), rng.uniform(1e5, 3e6)
        assert crush_energy(L, c, a, b) == pytest.approx(form(L, c, a, b), rel=1e-12)


def test_dense_trapezoid_of_the_interpolated_profile_converges_to_the_exact_integral():
    """The exact integral of the piecewise-linear profile; the trapezoid rule on its
    stations alone over-counts the B term by B d sum (dC)^2 / 12."""
    L, c = 1.524, np.array([0.254, 0.305, 0.356, 0.305, 0.229, 0.127])
    x = np.linspace(0, L, 200001)
    profile = np.interp(x, np.linspace(0, L, 6), c)
    dense = np.trapezoid(A * profile + B * profile**2 / 2 + G, x)
    exact = crush_energy(L, c, A, B)
    assert exact == pytest.approx(dense, rel=1e-9)
    coarse = np.trapezoid(A * c + B * c**2 / 2 + G, np.linspace(0, L, 6))
    assert coarse - exact == pytest.approx(B * (L / 5) * np.sum(np.diff(c) ** 2) / 12, rel=1e-9)


def test_campbell_barrier_identity_gives_the_test_speed_back():
    """Campbell (1974): a barrier test at speed V with uniform crush C on a vehicle of mass m
    and width L, with the no-damage speed b0, gives V = b0 + b1 C and A = m b0 b1 / L,
    B = m b1^2 / L, G = m b0^2 / (2 L); the crush energy of that profile is m V^2 / 2, so
    the EES is V (independent of the program: algebra of the definitions)."""
    m, L, V, b0, C = 1500.0, 1.7, 35 * 0.44704, 5 * 0.44704, 0.55
    b1 = (V - b0) / C
    a, b = m * b0 * b1 / L, m * b1**2 / L
    energy = crush_energy(L, [C] * 6, a, b)
    assert energy == pytest.approx(m * V**2 / 2, rel=1e-12)
    assert equivalent_energy_speed(energy, m) == pytest.approx(V, rel=1e-12)


def test_vectorised_over_samples_and_first_axis_over_stations():
    depths = np.array([[0.1, 0.2], [0.3, 0.3], [0.2, 0.0]])    # 3 stations x 2 samples
    out = crush_energy(np.array([1.0, 2.0]), depths, A, B)
    assert out.shape == (2,)
    assert out[1] == pytest.approx(crush_energy(2.0, [0.2, 0.3, 0.0], A, B))


@settings(max_examples=60, deadline=None)
@given(st.lists(depth, min_size=2, max_size=10), st.integers(0, 9), st.floats(1e-4, 0.3))
def test_energy_increases_with_every_depth(depths, index, step):
    index %= len(depths)
    deeper = list(depths)
    deeper[index] += step
    assert crush_energy(1.2, deeper, A, B) > crush_energy(1.2, depths, A, B)


@settings(max_examples=60, deadline=None)
@given(st.lists(depth, min_size=2, max_size=10))
def test_reversed_profile_absorbs_the_same_energy(depths):
    assert crush_energy(1.2, depths[::-1], A, B) == pytest.approx(
        crush_energy(1.2, depths, A, B), rel=1e-12)


@settings(max_examples=100, deadline=None)
@given(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4), st.floats(0, 2 * math.pi),
       st.floats(1.0, 5.0))
def test_force_balance_factor_lies_within_one_and_the_cap(px, py, side_angle, cap):
    f = force_balance_factor(px, py, math.cos(side_angle), math.sin(side_angle), cap)
    assert 1.0 - 1e-12 <= f <= cap * (1 + 1e-12)


@pytest.mark.parametrize("alpha_deg, expected", [(0, 1.0), (30, 4 / 3), (45, 2.0), (60, 2.0),
                                                 (90, 2.0), (150, 4 / 3), (180, 1.0)])
def test_force_balance_factor_is_one_plus_tan_squared_capped_at_45_degrees(alpha_deg, expected):
    a = math.radians(alpha_deg)
    assert force_balance_factor(3e3 * math.cos(a), 3e3 * math.sin(a), 1.0, 0.0) == (
        pytest.approx(expected, rel=1e-12))
    assert FORCE_BALANCE_CAP == 2.0


def test_force_balance_factor_of_zero_impulse_is_one_and_cap_below_one_is_refused():
    assert force_balance_factor(0.0, 0.0, 0.0, 1.0) == 1.0
    with pytest.raises(ValueError, match="cap = 0.5 must be at least 1"):
        force_balance_factor(1.0, 0.0, 1.0, 0.0, cap=0.5)


def test_force_balance_factor_on_duals_matches_finite_differences():
    x = np.array([1200.0, 700.0, 0.6, 0.8])      # Px, Py, nx, ny: alpha ~ 22 deg, uncapped
    for cap in (2.0, 1.05):                         # uncapped and capped branches
        duals = [Dual(v, np.eye(4)[i]) for i, v in enumerate(x)]
        f = force_balance_factor(*duals, cap=cap)
        h = 1e-6 * np.maximum(abs(x), 1.0)
        fd = [(force_balance_factor(*(x + h[i] * np.eye(4)[i]), cap=cap)
               - force_balance_factor(*(x - h[i] * np.eye(4)[i]), cap=cap)) / (2 * h[i])
              for i in range(4)]
        assert float(f.value) == pytest.approx(force_balance_factor(*x, cap=cap))
        np.testing.assert_allclose(f.grad, fd, rtol=1e-6, atol=1e-8)


def test_crush_energy_on_duals_matches_finite_differences():
    x = np.array([1.4, 0.2, 0.35, 0.1, A, B])
    duals = [Dual(v, np.eye(6)[i]) for i, v in enumerate(x)]

    def energy(v):
        return crush_energy(v[0], v[1:4], v[4], v[5])

    e = energy(duals)
    for i in range(6):
        h = 1e-6 * abs(x[i])
        fd = (energy(x + h * np.eye(6)[i]) - energy(x - h * np.eye(6)[i])) / (2 * h)
        assert e.grad[i] == pytest.approx(fd, rel=1e-6)


def test_sqrt_of_dual():
    d = sqrt_of(Dual(4.0, [1.0, 2.0]))
    assert float(d.value) == 2.0 and d.grad.tolist() == [0.25, 0.5]


def _collinear(m1, m2, v, e):
    """1-D impact of m1 at v on m2 at rest with restitution e: impulse, energy lost, and
    the energy at maximum compression (common velocity), from momentum alone."""
    reduced = m1 * m2 / (m1 + m2)
    impulse = (1 + e) * reduced * v
    return impulse, 0.5 * reduced * v * v * (1 - e * e), 0.5 * reduced * v * v


@pytest.mark.parametrize("e", [0.0, 0.1, 0.3])
def test_crush_delta_v_reproduces_collinear_impact_mechanics(e):
    m1, m2, v = 1400.0, 1900.0, 15.0
    impulse, lost, absorbed = _collinear(m1, m2, v, e)
    dv1, dv2 = crush_delta_v(absorbed, m1, m2, e, "absorbed")
    assert (dv1, dv2) == pytest.approx((impulse / m1, impulse / m2), rel=1e-12)
    dv1, dv2 = crush_delta_v(lost, m1, m2, e, "dissipated")
    assert (dv1, dv2) == pytest.approx((impulse / m1, impulse / m2), rel=1e-12)


def test_crash3_delta_v_without_restitution():
    """CRASH3: delta-V1 = sqrt(2 E_T m2 / (m1 (m1 + m2))) for a central impact."""
    m1, m2, energy = 1200.0, 1600.0, 90e3
    dv1, dv2 = crush_delta_v(energy, m1, m2)
    assert dv1 == pytest.approx(math.sqrt(2 * energy * m2 / (m1 * (m1 + m2))), rel=1e-12)
    assert m1 * dv1 == pytest.approx(m2 * dv2, rel=1e-12)
    assert crush_delta_v(energy, m1, m2, 0.2)[0] == pytest.approx(1.2 * dv1, rel=1e-12)
    with pytest.raises(ValueError, match="energy_is = 'maximum'"):
        crush_impulse(energy, m1, m2, energy_is="maximum")


def test_effective_mass_and_moment_arm():
    m, inertia = 1500.0, 2500.0
    assert effective_mass(m, inertia, 0.0) == m
    h = moment_arm(2.0, 0.5, -1.0, 0.0)                    # frontal centroid 0.5 m left
    assert h == pytest.approx(0.5)
    k2 = inertia / m
    assert effective_mass(m, inertia, h) == pytest.approx(m * k2 / (k2 + h * h), rel=1e-12)
    gamma = k2 / (k2 + h * h)
    dv1, _ = crush_delta_v(1e5, m, m, gamma1=gamma, gamma2=1.0)
    point = crush_impulse(1e5, gamma * m, m) / (gamma * m)
    assert dv1 == pytest.approx(gamma * point, rel=1e-12)


def test_partitions_name_the_compared_pim_energy():
    assert compared_energy().attribute == "energy_loss" and compared_energy().force_balance
    normal = compared_energy("normal")
    assert normal.attribute == "crush_energy_normal" and not normal.force_balance
    assert set(PARTITIONS) == {"total", "normal"}
    for comparison in PARTITIONS.values():      # the named energies exist on a PIM result
        assert isinstance(getattr(Result, comparison.attribute), cached_property)
    with pytest.raises(ValueError, match=r"partition = 'shear' is not known \(allowed: total, "
                                         r"normal\)"):
        compared_energy("shear")


def _profile(**kw):
    base = dict(side="front", width=1.524, depths=(0.254, 0.305, 0.356, 0.305, 0.229, 0.127),
                stiffness_a=A, stiffness_b=B, where="evidence.vehicle1.crush")
    base.update(kw)
    return CrushProfile(**base)


def test_profile_energy_normal_and_centroid():
    p = _profile(offset=0.2)
    assert p.energy == pytest.approx(crash3_six_point(p.width, p.depths, A, B), rel=1e-12)
    assert p.normal_body.tolist() == [1.0, 0.0]
    assert p.centroid_body.tolist() == [0.0, 0.2]
    assert _profile(side="right", offset=-0.3).centroid_body.tolist() == [-0.3, 0.0]
    assert {s: _profile(side=s).normal_body.tolist() for s in ("rear", "left", "right")} == {
        "rear": [-1.0, 0.0], "left": [0.0, 1.0], "right": [0.0, -1.0]}
    assert _profile(stiffness_g=0.0).energy < p.energy


def test_energy_sigma_first_order_matches_sampling():
    p = _profile(depth_sigma=0.005, width_sigma=0.02, stiffness_a_sigma=2e3,
                 stiffness_b_sigma=2e4, energy_sigma_relative=0.05)
    samples = p.sample_energy(np.random.default_rng(1), 200_000)
    assert np.std(samples) == pytest.approx(p.energy_sigma, rel=0.03)
    assert np.mean(samples) == pytest.approx(p.energy, rel=0.01)
    assert _profile().energy_sigma == 0.0
    single = _profile(depth_sigma=0.01)
    n = len(single.depths)
    eps = 1e-7
    grads = [(_profile(depths=tuple(c + eps * (j == i) for j, c in enumerate(single.depths)))
              .energy - single.energy) / eps for i in range(n)]
    assert single.energy_sigma == pytest.approx(0.01 * math.sqrt(sum(g * g for g in grads)),
                                                rel=1e-5)


@pytest.mark.parametrize("kw, message", [
    ({"side": "top"}, r"evidence\.vehicle1\.crush\.side = 'top' is not a side \(allowed: "
                      r"front, rear, left, right\)"),
    ({"depths": (0.1,)}, r"crush\.depths: 1 depth given; at least 2"),
    ({"depths": (0.1, -0.02)}, r"crush\.depths\[1\] = -0.02 m: a crush depth must be finite "
                               r"and >= 0"),
    ({"width": 0.0}, r"crush\.width = 0 m must be finite and > 0"),
    ({"stiffness_a": -1.0}, r"crush\.stiffness_a = -1 N/m must be finite and > 0"),
    ({"stiffness_b": 0.0}, r"crush\.stiffness_b = 0 N/m\^2 must be finite and > 0"),
    ({"depth_sigma": -0.1}, r"crush\.depth_sigma = -0.1 m must be finite and >= 0"),
    ({"stiffness_g": -1.0}, r"crush\.stiffness_g = -1 N must be finite and >= 0"),
    ({"energy_sigma_relative": float("inf")}, r"crush\.energy_sigma_relative = inf - must be "
                                               r"finite and >= 0"),
    ({"offset": float("nan")}, r"crush\.offset = nan must be finite"),
])
def test_bad_profiles_name_the_field(kw, message):
    with pytest.raises(ValueError, match=message):
        _profile(**kw)


def test_crush_energy_needs_two_depths():
    with pytest.raises(ValueError, match="1 given, at least 2"):
        crush_energy(1.0, [0.1], A, B)


# CRASH3 User's Guide and Technical Manual (NHTSA DOT-HS-805-732), Section 5 sample run,
# damage summary (manual p. 73), as quoted in the public documentation of the Locus crash
# tool (docs/methods/crash-stiffness.md): category 4 stiffnesses of Table 8-2 in lb/in,
# lb/in^2 and lb (G as listed, not A^2/2B), inputs printed to 0.1 in, energies in ft-lb.
CRASH3_SAMPLE_RUN = [
    # A, B, G, L [in], depths [in], force-balance factor, printed energy [ft-lb]
    (356.0, 34.0, 1874.0, 73.0, (2.7, 3.6), 1.0, 19245.3),        # vehicle 1, front
    (143.0, 50.0, 203.0, 84.5, (6.2, 8.3, 9.2, 5.9, 4.4, 0.8), 2.0, 31220.8),  # 2, side, 45 deg
]


@pytest.mark.parametrize("a, b, g, width, depths, factor, printed", CRASH3_SAMPLE_RUN)
def test_crash3_manual_sample_run_energies(a, b, g, width, depths, factor, printed):
    """Each printed energy lies within the energies of the inputs rounded by +-0.05 in (the
    energy grows with every depth and the width, so the bounds are the all-low and all-high
    inputs); the nominal inputs give it to 0.5 %."""
    inch, lbf, ft_lbf = 0.0254, 4.4482216152605, 1.3558179483314

    def energy(shift):
        cs = [(c + shift) * inch for c in depths]
        e = crush_energy((width + shift) * inch, cs, a * lbf / inch, b * lbf / inch**2, g * lbf)
        return factor * e / ft_lbf

    assert energy(-0.05) < printed < energy(0.05)
    assert energy(0.0) == pytest.approx(printed, rel=5e-3)
    alpha = math.radians(45.0)
    assert force_balance_factor(math.cos(alpha), math.sin(alpha), 0.0, 1.0) == (
        pytest.approx(2.0))


def test_global_normal_and_corrected_energy_follow_the_heading():
    p = _profile(side="left")
    nx, ny = p.normal(np.radians(90.0))
    assert (nx, ny) == pytest.approx((-1.0, 0.0), abs=1e-15)   # left of a car heading +y
    # impulse along the global normal: no correction; at 30 deg to it: 1 + tan^2 30
    assert p.corrected_energy(-5e3, 0.0, np.radians(90.0)) == pytest.approx(p.energy)
    a = np.radians(30.0)
    assert p.corrected_energy(math.cos(a), math.sin(a), np.radians(90.0)) == pytest.approx(
        p.energy * 4 / 3, rel=1e-12)
    h = Dual(np.radians(100.0), [1.0])
    e = p.corrected_energy(1.0, 0.3, h)
    step = 1e-7
    fd = (p.corrected_energy(1.0, 0.3, np.radians(100.0) + step)
          - p.corrected_energy(1.0, 0.3, np.radians(100.0) - step)) / (2 * step)
    assert e.grad[0] == pytest.approx(fd, rel=1e-6)
