"""Hard cases of issue 2: each answers correctly (against an exact reference) or flags clearly.

The reference is tests/exact.py: Brach's scalar equations in exact rational arithmetic, for
scenes whose normal is along an axis (rotated onto Gamma = 0 by an exact quarter turn).
"""

from dataclasses import replace

import numpy as np
import pytest

import pim
from tests.exact import brach_exact

# Exact rotations by quarter turns: Gamma = 0, 90, 180, 270 deg onto Gamma = 0.
QUARTER = {0: np.array([[1, 0], [0, 1]]), 90: np.array([[0, 1], [-1, 0]]),
           180: np.array([[-1, 0], [0, -1]]), 270: np.array([[0, -1], [1, 0]])}


def reference(case, eps, beta):
    """Exact Brach solution of a case whose Gamma is a multiple of 90 deg, in its own frame."""
    gamma = round(float(np.degrees(case.impact.normal_angle))) % 360
    assert np.isclose(np.degrees(case.impact.normal_angle) % 360, gamma)
    rot = QUARTER[gamma]                       # maps the scene onto Gamma = 0, exactly
    back = rot.T
    a, b = case.vehicle1, case.vehicle2
    fixed = bool(b.fixed)
    out = brach_exact(
        float(a.mass), float(a.yaw_inertia), rot @ a.cg, rot @ a.velocity, float(a.yaw_rate),
        None if fixed else float(b.mass), None if fixed else float(b.yaw_inertia),
        rot @ b.cg, rot @ b.velocity, float(b.yaw_rate), rot @ case.impact.point, eps, beta)
    as_float = {k: np.array(v, dtype=float) for k, v in out.items()}
    for key in ("velocity1", "velocity2", "impulse"):
        if key != "impulse":
            as_float[key] = back @ as_float[key]
    return as_float


def assert_matches_reference(result, ref, rtol):
    scale_v = np.abs(ref["velocity1"]).max() + np.abs(ref["velocity2"]).max()
    np.testing.assert_allclose(result.velocity1, ref["velocity1"], rtol=0, atol=rtol * scale_v)
    np.testing.assert_allclose(result.velocity2, ref["velocity2"], rtol=0, atol=rtol * scale_v)
    scale_w = abs(ref["yaw_rate1"]) + abs(ref["yaw_rate2"]) + 1e-300
    np.testing.assert_allclose(result.yaw_rate1, ref["yaw_rate1"], rtol=0, atol=rtol * scale_w)
    np.testing.assert_allclose(result.yaw_rate2, ref["yaw_rate2"], rtol=0, atol=rtol * scale_w)
    np.testing.assert_allclose([result.impulse_n, result.impulse_t], ref["impulse"],
                               rtol=0, atol=rtol * np.abs(ref["impulse"]).max())
    np.testing.assert_allclose(result.mu0, ref["mu0"], rtol=rtol)


AXIS_CASES = ["hard-eps0", "hard-eps1-frictionless", "hard-beta0", "hard-car-truck",
              "hard-spinning", "hard-c-near-cg", "hard-high-speed", "hard-grazing",
              "hard-barrier", "hard-pole", "ricsac9"]


@pytest.mark.parametrize("name", AXIS_CASES)
def test_bundled_hard_case_matches_exact_brach(name):
    case = pim.load_case(name)
    eps, beta = case.impact.restitution, case.impact.beta
    result = pim.solve(case)
    assert_matches_reference(result, reference(case, eps, beta), rtol=1e-12)
    assert result.problems() == []


def test_near_singular_q_stays_accurate():
    # A - mu B ~ 2e-6, q ~ 5e5: Brach's form multiplies a huge q by a tiny v_rn. The 2x2
    # solve never forms q, so the impulse is still accurate to round-off of the inputs.
    case = pim.load_case("hard-near-singular-q")
    result = pim.solve(case)
    assert float(result.q) > 1e5
    assert_matches_reference(result, reference(case, 0.1, 1.0), rtol=1e-9)
    assert np.isfinite(result.velocity1).all() and result.problems() == []


def test_grazing_limit_is_finite():
    # As u_n -> 0 at beta = 1, mu0 -> -K_nn / K_nt (finite) while r = u_t / u_n -> infinity.
    case = pim.load_case("hard-grazing")
    grazing = []
    for vn in (1e-2, 1e-6, 1e-10):
        v1 = replace(case.vehicle1, velocity=(20.0, -vn / 2))
        v2 = replace(case.vehicle2, velocity=(-20.0, vn / 2))
        r = pim.solve(replace(case, vehicle1=v1, vehicle2=v2))
        assert np.isfinite([r.mu0, r.impulse_n, r.impulse_t]).all()
        assert abs(r.r) > 1e3
        grazing.append(float(r.mu0))
    assert grazing[-1] == pytest.approx(float(-r.k_nn / r.k_nt), rel=1e-8)
    # Exactly no normal approach: no impact, flagged, and still no NaN in the motion.
    v1 = replace(case.vehicle1, velocity=(20.0, 0.0))
    v2 = replace(case.vehicle2, velocity=(-20.0, 0.0))
    r = pim.solve(replace(case, vehicle1=v1, vehicle2=v2))
    assert not r.approaching and np.isfinite(r.velocity1).all()
    np.testing.assert_array_equal(r.impulse, 0.0)


def test_plastic_sticking_leaves_no_relative_velocity_at_c():
    r = pim.solve(pim.load_case("hard-eps0"))
    scale = abs(float(r.approach_n)) + abs(float(r.approach_t))
    assert abs(r.separation_n) < 1e-13 * scale and abs(r.separation_t) < 1e-13 * scale


def test_elastic_frictionless_conserves_energy():
    r = pim.solve(pim.load_case("hard-eps1-frictionless"))
    assert float(r.impulse_t) == 0.0
    assert abs(float(r.energy_loss)) < 1e-12 * float(r.kinetic_energy_before)
    assert float(r.restitution_check) == pytest.approx(1.0, rel=1e-13)


def test_beta_zero_has_no_tangential_impulse():
    r = pim.solve(pim.load_case("hard-beta0"))
    assert float(r.impulse_t) == 0.0 and float(r.crush_energy_tangential) == 0.0
    assert float(r.mu) == 0.0 and float(r.energy_loss) > 0


@pytest.mark.parametrize("ratio", [1e-3, 1e3])
def test_extreme_mass_ratios(ratio):
    case = pim.load_case("hard-eps0")
    m2 = float(case.vehicle1.mass) * ratio
    k2 = np.sqrt(float(case.vehicle2.yaw_inertia / case.vehicle2.mass))
    case = replace(case, vehicle2=replace(case.vehicle2, mass=m2, yaw_inertia=m2 * k2 ** 2))
    r = pim.solve(case, 0.2, 0.7)
    assert_matches_reference(r, reference(case, 0.2, 0.7), rtol=1e-12)
    momentum = case.vehicle1.mass * r.delta_v1 + case.vehicle2.mass * r.delta_v2
    np.testing.assert_allclose(momentum, 0.0, atol=1e-12 * float(np.abs(r.impulse).sum()))


def test_heavy_vehicle_tends_to_the_barrier():
    wall = pim.load_case("hard-barrier")
    rigid = pim.solve(wall)
    for mass, tol in ((1e8, 1e-4), (1e12, 1e-8)):
        heavy = replace(wall.vehicle2, mass=mass, yaw_inertia=mass * 10.0)
        r = pim.solve(replace(wall, vehicle2=heavy))
        np.testing.assert_allclose(r.velocity1, rigid.velocity1, atol=tol * 15)
        np.testing.assert_allclose(r.yaw_rate1, rigid.yaw_rate1, atol=tol * 15)


@pytest.mark.parametrize("name", ["hard-barrier", "hard-pole"])
def test_obstacles_do_not_move(name):
    r = pim.solve(pim.load_case(name))
    np.testing.assert_array_equal(r.velocity2, 0.0)
    assert float(r.yaw_rate2) == 0.0 and float(r.energy_loss) > 0
    assert float(r.kinetic_energy_before) > 0 and np.isfinite(float(r.energy_loss_percent))


def test_impact_at_the_cg_does_not_change_yaw():
    case = pim.load_case("hard-c-near-cg")
    exact_cg = replace(case.vehicle2, cg=case.impact.point)
    r = pim.solve(replace(case, vehicle2=exact_cg))
    assert float(r.yaw_rate2) == float(case.vehicle2.yaw_rate)
    near = pim.solve(case)
    assert abs(float(near.yaw_rate2)) < 0.1 * abs(float(near.yaw_rate1))


def test_collinear_central_impact_is_the_textbook_1d_collision():
    m1, m2, u1, u2, eps = 1200.0, 1900.0, 17.0, -6.0, 0.35
    case = pim.Case(
        pim.Vehicle(m1, m1 * 1.4, cg=(-2.0, 0.0), velocity=(u1, 0.0), yaw_rate=0.0),
        pim.Vehicle(m2, m2 * 1.7, cg=(2.5, 0.0), velocity=(u2, 0.0), yaw_rate=0.0, heading=np.pi),
        pim.Impact(point=(0.0, 0.0), normal_angle=np.pi))
    for beta in (0.0, 0.5, 1.0):
        r = pim.solve(case, eps, beta)
        # Newton's 1-D impact: V1 = v1 - m2 (1 + e)(v1 - v2) / (m1 + m2), and symmetric.
        v1 = u1 - m2 * (1 + eps) * (u1 - u2) / (m1 + m2)
        v2 = u2 + m1 * (1 + eps) * (u1 - u2) / (m1 + m2)
        np.testing.assert_allclose(r.velocity1, [v1, 0.0], atol=1e-12 * 20)
        np.testing.assert_allclose(r.velocity2, [v2, 0.0], atol=1e-12 * 20)
        # cos(pi) and sin(pi) are not exact in floating point: rotation stays at round-off.
        assert abs(r.yaw_rate1) < 1e-13 and abs(r.yaw_rate2) < 1e-13


@pytest.mark.parametrize("gamma", [37.0, 90.0])
def test_rotated_contact_plane(gamma):
    # The T-bone has Gamma = 180 deg; turned by gamma - 180 it must give the turned answer.
    base = pim.load_case("hard-spinning")
    turn = np.radians(gamma - 180.0)
    turned = base.transformed(turn)
    assert np.degrees(turned.impact.normal_angle) == pytest.approx(gamma)
    ref = reference(base, 0.3, 1.0)
    r = pim.solve(turned)
    c, s = np.cos(turn), np.sin(turn)
    rot = np.array([[c, -s], [s, c]])
    np.testing.assert_allclose(r.velocity1, rot @ ref["velocity1"], atol=1e-12 * 30)
    np.testing.assert_allclose(r.velocity2, rot @ ref["velocity2"], atol=1e-12 * 30)
    np.testing.assert_allclose([r.yaw_rate1, r.yaw_rate2], [ref["yaw_rate1"], ref["yaw_rate2"]],
                               atol=1e-12 * 30)


def test_bundled_gamma37_case_is_the_turned_t_bone():
    ref_case = pim.load_case("hard-spinning")
    ref_case = replace(ref_case, vehicle1=replace(ref_case.vehicle1, yaw_rate=1.5),
                       vehicle2=replace(ref_case.vehicle2, yaw_rate=-1.0))
    expected = pim.solve(ref_case.transformed(np.radians(-143.0)))
    r = pim.solve(pim.load_case("hard-gamma37"))
    # The case file gives the turned inputs to 9 significant digits.
    np.testing.assert_allclose(r.velocity1, expected.velocity1, rtol=1e-7)
    np.testing.assert_allclose(r.yaw_rate2, expected.yaw_rate2, rtol=1e-7)


def singular_beta(case, eps):
    """The beta at which A - mu B = 0 (q singular) for this scene."""
    r = pim.solve(case, eps, 1.0)
    drive = -(1 + eps) * r.approach_n
    return float(1.0 - drive / (r.k_nt * r.critical_impulse_t))


def test_singular_q_is_flagged_not_silent():
    case = pim.load_case("hard-eps0")
    beta = singular_beta(case, 0.0)
    r = pim.solve(case, 0.0, beta)
    assert bool(r.q_singular) and not bool(r.admissible)
    assert np.isnan(r.velocity1).all()
    assert any("singular" in p for p in r.problems())
    near = pim.solve(case, 0.0, beta * (1 + 1e-6))
    assert not near.q_singular and abs(float(near.q)) > 1e4


def test_separating_vehicles_have_no_impact():
    case = pim.load_case("hard-eps0")
    apart = replace(case, vehicle1=replace(case.vehicle1, velocity=(-15.0, 0.0)))
    r = pim.solve(apart)
    assert not bool(r.approaching) and not bool(r.admissible)
    np.testing.assert_array_equal(r.impulse, 0.0)
    np.testing.assert_array_equal(r.velocity1, apart.vehicle1.velocity)
    assert float(r.energy_loss) == 0.0
    assert any("do not approach" in p for p in r.problems())


def test_energy_gain_is_flagged():
    # Strong n-t coupling (C far out on a long lever arm) with eps = 1 at beta = 1: Newton's
    # kinematic restitution with sticking friction gains energy (eps^2 > det K/(K_nn K_tt)).
    case = pim.Case(
        pim.Vehicle(1000.0, 200.0, cg=(-2.0, -2.0), velocity=(10.0, -5.0), yaw_rate=0.0),
        pim.Vehicle.obstacle(cg=(1.0, 0.0)),
        pim.Impact(point=(0.0, 0.0), normal_angle=np.pi))
    r = pim.solve(case, 1.0, 1.0)
    det = r.k_nn * r.k_tt - r.k_nt ** 2
    assert 1.0 > det / (r.k_nn * r.k_tt)
    assert float(r.energy_loss) < 0 and not bool(r.energy_not_gained)
    assert any("energy is gained" in p for p in r.problems())


def test_round_off_approach_is_no_impact_in_every_frame():
    # u_n = -1e-41 against a 1 m/s slip is rounding, not an impact: at beta = 1 it would
    # otherwise stop the whole slip in one frame and do nothing in a rotated one.
    case = pim.Case(pim.Vehicle(100.0, 100.0, (0.0, 0.0), (-1e-41, 1.0)),
                    pim.Vehicle(100.0, 100.0, (0.0, 0.0), (0.0, 0.0)),
                    pim.Impact((0.0, 0.0), 0.0))
    for angle in (0.0, 1.0, 2.5):
        r = pim.solve(case.transformed(angle), 0.0, 1.0)
        assert not bool(r.approaching)
        np.testing.assert_array_equal(r.impulse, 0.0)
