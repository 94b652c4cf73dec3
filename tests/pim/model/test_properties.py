"""Invariants of the impact equations on thousands of random scenes (hypothesis).

Any Gamma, spinning vehicles, mass ratios up to 400:1. Conservation laws are checked to
relative 1e-12 of the momenta involved.
"""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import pim
from tests.scenes import random_cases, scenes

MANY = settings(max_examples=400, deadline=None)   # derandomized under the "ci" profile
unit = st.floats(0.0, 1.0, allow_nan=False)


def cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def approaching(case) -> bool:
    r = pim.solve(case, 0.5, 0.0)
    speed = np.abs(r.approach_velocity).sum()
    return bool(r.approach_n < -1e-6 * (1.0 + speed))


def momenta(case, v1, w1, v2, w2, origin):
    a, b = case.vehicle1, case.vehicle2
    linear = a.mass * v1 + b.mass * v2
    angular = (a.mass * cross(a.cg - origin, v1) + a.yaw_inertia * w1
               + b.mass * cross(b.cg - origin, v2) + b.yaw_inertia * w2)
    return linear, angular


@MANY
@given(scenes(), unit, unit, st.tuples(st.floats(-50, 50), st.floats(-50, 50)))
def test_momentum_conserved(case, eps, beta, origin):
    r = pim.solve(case, eps, beta)
    origin = np.array(origin)
    a, b = case.vehicle1, case.vehicle2
    lin0, ang0 = momenta(case, a.velocity, a.yaw_rate, b.velocity, b.yaw_rate, origin)
    lin1, ang1 = momenta(case, r.velocity1, r.yaw_rate1, r.velocity2, r.yaw_rate2, origin)
    scale_lin = a.mass * np.abs(a.velocity).sum() + b.mass * np.abs(b.velocity).sum()
    scale_lin += np.abs(r.impulse).sum()
    arm = np.abs(case.impact.point - origin).sum() + np.abs(a.cg - origin).sum()
    arm += np.abs(b.cg - origin).sum()
    scale_ang = scale_lin * arm + a.yaw_inertia * abs(a.yaw_rate) + b.yaw_inertia * abs(b.yaw_rate)
    np.testing.assert_allclose(lin1, lin0, rtol=0, atol=1e-12 * scale_lin)
    np.testing.assert_allclose(ang1, ang0, rtol=0, atol=1e-12 * scale_ang)


@MANY
@given(scenes(), unit, unit)
def test_restitution_and_sticking_at_c(case, eps, beta):
    assume(approaching(case))
    r = pim.solve(case, eps, beta)
    sticking = pim.solve(case, eps, 1.0)
    # Round-off scale: the terms summed in U = u + K P, and the CG velocities and spin terms
    # whose differences make u_1 - u_2 (2 m/s - 2 m/s leaves ~4e-16 m/s of round-off).
    k = abs(r.k_nn) + abs(r.k_nt) + abs(r.k_tt)
    motion = sum(np.abs(x).sum() for x in (r.velocity1, r.velocity2, case.vehicle1.velocity,
                                           case.vehicle2.velocity))
    spin = sum(abs(float(w)) * np.abs(arm).sum() for w, arm in (
        (r.yaw_rate1, r.arm1), (r.yaw_rate2, r.arm2), (case.vehicle1.yaw_rate, r.arm1),
        (case.vehicle2.yaw_rate, r.arm2)))
    u = (np.abs(r.approach_velocity).sum() + motion + spin
         + k * np.abs(np.r_[r.impulse, sticking.impulse]).sum())
    assert r.separation_n == pytest.approx(-eps * r.approach_n, abs=1e-11 * u)
    assert r.impulse_t == pytest.approx(r.mu * r.impulse_n, abs=1e-11 * abs(r.impulse).sum())
    assert sticking.separation_t == pytest.approx(0.0, abs=1e-11 * u)


@MANY
@given(scenes(), unit, unit)
def test_energy_split_and_closed_form(case, eps, beta):
    assume(approaching(case))
    r = pim.solve(case, eps, beta)
    assume(not r.q_singular)
    work = np.abs(r.impulse).sum() * np.abs(r.approach_velocity).sum()
    ke = float(r.kinetic_energy_before) + float(work) + abs(float(r.energy_loss))
    # Delta KE (difference of the kinetic energies) = normal + tangential crush (the work of
    # the impulse, which is what energy_loss reports) = Brach's closed-form T_L.
    delta_ke = r.kinetic_energy_before - r.kinetic_energy_after
    assert r.crush_energy_normal + r.crush_energy_tangential == pytest.approx(
        delta_ke, abs=1e-10 * ke)
    assert r.energy_loss == pytest.approx(r.crush_energy_normal + r.crush_energy_tangential,
                                          abs=1e-10 * ke)
    assert r.total_loss_brach == pytest.approx(r.energy_loss, abs=1e-9 * ke)
    # The normal part never adds energy when the contact pushes.
    if r.impulse_n > 0:
        assert r.crush_energy_normal >= -1e-10 * ke
    assert bool(r.energy_not_gained) == bool(r.energy_loss >= -1e-9 * r.kinetic_energy_before)


@MANY
@given(scenes(), unit, unit)
def test_energy_never_rises_where_friction_dissipates(case, eps, beta):
    """Energy loss >= 0 for 0 <= eps <= 1, 0 <= beta <= 1 in every regime where it is provable.

    Kinematic restitution with an imposed impulse ratio can gain energy (Kane's paradox): when
    the normal impulse, through the n-t coupling K_nt, reverses the tangential slip, mu0 points
    along the slip and friction does positive work; and at beta = 1 for eps^2 above
    det K / (K_nn K_tt). Those results are flagged (``energy_not_gained``), see
    test_hard_cases.py. Everywhere else the loss must be non-negative:
    frictionless (beta = 0), sticking with eps^2 <= det K / (K_nn K_tt), and any beta where
    friction opposes the slip before and after (Pt u_t <= 0 and Pt U_t <= 0).
    """
    assume(approaching(case))
    r = pim.solve(case, eps, beta)
    assume(r.impulse_n > 0 and not r.q_singular)
    tol = -1e-10 * float(r.kinetic_energy_before + abs(r.impulse_n * r.approach_n))
    frictionless = pim.solve(case, eps, 0.0)
    assert frictionless.energy_loss >= tol
    det = r.k_nn * r.k_tt - r.k_nt ** 2
    if eps ** 2 <= det / (r.k_nn * r.k_tt):
        assert pim.solve(case, eps, 1.0).energy_loss >= tol
    if r.impulse_t * r.approach_t <= 0 and r.impulse_t * r.separation_t <= 0:
        assert r.energy_loss >= tol
        assert r.crush_energy_tangential >= tol


def test_energy_is_dissipated_in_most_admissible_scenes():
    """Guard against a property test that passes by assuming everything away."""
    case = random_cases(20000, seed=3)
    rng = np.random.default_rng(4)
    r = pim.solve(case, rng.uniform(0, 1, 20000), rng.uniform(0, 1, 20000))
    admissible = r.approaching & r.normal_impulse_positive
    assert admissible.mean() > 0.4
    # Nearly all admissible scenes lose energy; the rest are flagged, never silent.
    assert (r.energy_loss[admissible] >= 0).mean() > 0.9
    np.testing.assert_array_equal(r.energy_not_gained,
                                  r.energy_loss >= -1e-9 * r.kinetic_energy_before)


@MANY
@given(scenes(), unit, unit, st.floats(-np.pi, np.pi), st.floats(-20, 20), st.floats(-20, 20))
def test_rotating_and_translating_the_scene(case, eps, beta, angle, dx, dy):
    r = pim.solve(case, eps, beta)
    # A nearly grazing approach (|u_n| below 1e-6 of |u|) is ill-conditioned: rotating the
    # scene changes u_n by round-off, ~1e-16 |u|, which moves the impulse by that much
    # relative to u_n (derandomized CI found u_n = -1.1e-10 m/s against u_t = 3 m/s, an
    # answer good to 7e-7). Grazing impacts are tested on their own in test_hard_cases.py.
    assume(not r.approaching or abs(float(r.approach_n))
           > 1e-6 * float(np.abs(r.approach_velocity).sum()))
    moved = pim.solve(case.transformed(angle, (dx, dy)), eps, beta)
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    scale = 1e-9 * (1 + np.abs(case.vehicle1.velocity).sum() + np.abs(case.vehicle2.velocity).sum()
                    + 10 * (abs(case.vehicle1.yaw_rate) + abs(case.vehicle2.yaw_rate)))
    np.testing.assert_allclose(moved.velocity1, rot @ r.velocity1, atol=scale)
    np.testing.assert_allclose(moved.velocity2, rot @ r.velocity2, atol=scale)
    np.testing.assert_allclose(moved.yaw_rate1, r.yaw_rate1, atol=scale)
    np.testing.assert_allclose(moved.yaw_rate2, r.yaw_rate2, atol=scale)
    np.testing.assert_allclose(moved.energy_loss, r.energy_loss,
                               atol=1e-9 * (1 + float(r.kinetic_energy_before)))
    if np.abs(r.impulse).sum() > 1e-6 * (1 + r.k_nn ** -1 * np.abs(r.approach_velocity).sum()):
        # PDOF is relative to the heading, which rotates with the scene: the full angle,
        # compared on the circle (a cosine alone would accept the mirrored direction)
        assert_same_angle(moved.pdof1, r.pdof1, 1e-6)
        assert_same_angle(moved.pdof2, r.pdof2, 1e-6)
    if abs(r.approach_n) > 1e-9 * (1 + np.abs(r.approach_velocity).sum()):
        assert bool(moved.approaching) == bool(r.approaching)


@MANY
@given(scenes(), unit, unit)
def test_swapping_the_vehicles(case, eps, beta):
    r = pim.solve(case, eps, beta)
    # Exactly grazing scenes (u_n = 0) sit on the approach/no-impact boundary, where the
    # rounding of cos(Gamma + pi) decides; keep clear of it.
    assume(abs(r.approach_n) > 1e-9 * (1 + np.abs(r.approach_velocity).sum()))
    s = pim.solve(case.swapped(), eps, beta)
    scale = 1e-9 * (1 + np.abs(r.velocity1).sum() + np.abs(r.velocity2).sum())
    np.testing.assert_allclose(s.velocity1, r.velocity2, atol=scale)
    np.testing.assert_allclose(s.velocity2, r.velocity1, atol=scale)
    np.testing.assert_allclose(s.yaw_rate1, r.yaw_rate2, atol=scale * 10)
    np.testing.assert_allclose(s.yaw_rate2, r.yaw_rate1, atol=scale * 10)
    # mu0 = Pt0 / Pn0 is ill-conditioned for grazing scenes; compare its parts.
    critical = np.array([r.critical_impulse_n, r.critical_impulse_t])
    np.testing.assert_allclose([s.critical_impulse_n, s.critical_impulse_t], critical,
                               atol=1e-9 * np.abs(critical).sum())


@settings(max_examples=300, deadline=None)
@given(scenes(fixed=True), unit, unit)
def test_fixed_obstacle_keeps_vehicle1_momentum_about_c(case, eps, beta):
    r = pim.solve(case, eps, beta)
    a = case.vehicle1
    c = case.impact.point
    before = a.mass * cross(a.cg - c, a.velocity) + a.yaw_inertia * a.yaw_rate
    after = a.mass * cross(a.cg - c, r.velocity1) + a.yaw_inertia * r.yaw_rate1
    scale = a.mass * np.abs(a.cg - c).sum() * (np.abs(a.velocity).sum() + np.abs(r.velocity1).sum())
    tol = 1e-12 * (scale + a.yaw_inertia * abs(a.yaw_rate)) + 1e-300
    assert after == pytest.approx(before, abs=tol)
    np.testing.assert_array_equal(r.velocity2, 0.0)
    np.testing.assert_array_equal(r.yaw_rate2, 0.0)


def test_vectorised_equals_elementwise():
    case = random_cases(64, seed=11)
    eps = np.linspace(0, 1, 64)
    beta = np.linspace(1, 0, 64)
    whole = pim.solve(case, eps, beta)
    for i in range(0, 64, 7):
        v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
        one = pim.Case(
            pim.Vehicle(v1.mass[i], v1.yaw_inertia[i], v1.cg[i], v1.velocity[i], v1.yaw_rate[i]),
            pim.Vehicle(v2.mass[i], v2.yaw_inertia[i], v2.cg[i], v2.velocity[i], v2.yaw_rate[i]),
            pim.Impact(imp.point[i], imp.normal_angle[i]))
        r = pim.solve(one, eps[i], beta[i])
        np.testing.assert_array_equal(r.velocity1, whole.velocity1[i])
        np.testing.assert_array_equal(r.yaw_rate2, whole.yaw_rate2[i])
        np.testing.assert_array_equal(r.energy_loss, whole.energy_loss[i])


def test_grid_of_eps_and_beta_broadcasts():
    case = pim.load_case("ricsac9")
    eps = np.linspace(0, 1, 11)[:, None]
    beta = np.linspace(0, 1, 6)[None, :]
    r = pim.solve(case, eps, beta)
    assert r.velocity1.shape == (11, 6, 2)
    assert r.energy_loss.shape == (11, 6) and r.pdof2.shape == (11, 6)
    single = pim.solve(case, 0.4, 0.6)
    np.testing.assert_allclose(r.velocity1[4, 3], single.velocity1, rtol=1e-14)


def assert_same_angle(a, b, tol):
    """|a - b| wrapped to (-pi, pi] is within tol [rad] (NaN where both are NaN)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
    d = np.angle(np.exp(1j * (a - b)))
    assert np.all(np.abs(d[~np.isnan(d)]) <= tol), d


def test_angle_check_sees_the_whole_angle():
    """The old check compared cos(pdof1) only, which a mirrored PDOF (-pdof) passes."""
    assert_same_angle(np.pi - 1e-9, -np.pi + 1e-9, 1e-6)          # across the cut
    with pytest.raises(AssertionError):
        assert_same_angle(-0.7, 0.7, 1e-6)      # cos equal, angle not
    np.testing.assert_allclose(np.cos(-0.7), np.cos(0.7), atol=1e-6)   # the old check passed
