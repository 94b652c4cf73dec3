"""pim/model/impact_laws.py: Brach, friction-capped Brach and Kudlich-Slibar (issue 18, item 1).

Expected values come from closed forms (the central collision of two point masses), from the
law's defining conditions (sticking: U = -k u; sliding: Pt = sigma mu_c Pn, U_n = -k u_n),
from an independent scalar derivation in n-t components (Carpenter & Welcher's form, as
pycrash's ``impc_calcs`` writes it), and from the mapping to Brach's PIM in both directions.
"""

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import pim
from pim.model.dual import MOTION_OUTPUTS, motion_inputs
from pim.model.friction_cap import solve_capped
from pim.model.impact_laws import (
    LAW_INPUTS,
    brach_as_kudlich_slibar,
    kudlich_slibar_as_brach,
    motion_of_law,
    needed_friction,
    solve_kudlich_slibar,
)
from pim_cli.main import main
from tests.scenes import TWO_CARS_TOML, random_cases, scenes

KS = "kudlich-slibar"
ANY_SCENE = st.one_of(scenes(), scenes(fixed=True))    # two vehicles, or a fixed obstacle
SETTINGS = dict(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def motion(r):
    """Post-impact motion as one vector [m/s, m/s, rad/s ...]."""
    return np.concatenate([np.ravel(r.velocity1), np.ravel(r.velocity2),
                           np.ravel(r.yaw_rate1), np.ravel(r.yaw_rate2)])


def close(a, b, scale):
    np.testing.assert_allclose(motion(a), motion(b), rtol=1e-9, atol=1e-9 * scale)


def scale_of(case):
    return 1.0 + float(np.abs(case.vehicle1.velocity).sum() + np.abs(case.vehicle2.velocity).sum()
                       + 10 * (abs(case.vehicle1.yaw_rate) + abs(case.vehicle2.yaw_rate)))


def compression_pushes(case):
    """The sticking compression impulse pushes (Pn_c > 0) and the vehicles approach."""
    r0 = pim.solve(case, 0.0, 1.0, backend="numpy")
    return bool(r0.approaching) and float(r0.critical_impulse_n) > 0


# ---- closed forms --------------------------------------------------------------------------
@pytest.mark.parametrize("k", [0.0, 0.3, 1.0])
def test_central_frictionless_collision_all_laws_agree_with_the_closed_form(k):
    # Two point-like bodies (arms along n), head on: no tangential effect in any law.
    m1, m2, v1, v2 = 1500.0, 1000.0, 12.0, -5.0
    car1 = pim.Vehicle(m1, 2000.0, (1.0, 0.0), (-v1, 0.0))
    car2 = pim.Vehicle(m2, 1500.0, (-1.0, 0.0), (-v2, 0.0))
    case = pim.Case(car1, car2, pim.Impact((0.0, 0.0), 0.0))
    closing = v1 - v2
    expected1 = -v1 + (1 + k) * m2 / (m1 + m2) * closing     # 1-D Newton restitution
    expected2 = -v2 - (1 + k) * m1 / (m1 + m2) * closing
    results = [pim.solve(case, k, 1.0), pim.solve(case, k, 0.0), solve_capped(case, k, 1.0, 0.3),
               solve_kudlich_slibar(case, k, 0.0), solve_kudlich_slibar(case, k, 0.6)]
    for r in results:
        assert float(r.velocity1[0]) == pytest.approx(expected1, rel=1e-12)
        assert float(r.velocity2[0]) == pytest.approx(expected2, rel=1e-12)
        assert float(r.yaw_rate1) == pytest.approx(0.0, abs=1e-12)


def check_tolerance(r) -> float:
    """Tolerance of ``restitution_check`` = -U_n / u_n: U_n carries round-off of the order of
    1e-16 times the relative velocity |u| at C, so the ratio carries that divided by |u_n|
    (a scene that barely approaches along n, |u_n| = 1e-7 |u|, gives 1e-9 of it)."""
    scale = float(np.hypot(*r.approach_velocity))
    return 1e-9 + 1e-12 * scale / abs(float(r.approach_n))


@given(ANY_SCENE, st.floats(0.0, 1.0))
@settings(**SETTINGS)
def test_sticking_ends_at_minus_k_times_the_approach_in_both_directions(case, k):
    assume(compression_pushes(case))
    r = solve_kudlich_slibar(case, k, np.inf)
    scale = float(np.hypot(*r.approach_velocity)) + 1e-9
    np.testing.assert_allclose(r.separation_velocity, -k * r.approach_velocity,
                               atol=1e-9 * scale)
    assert float(r.restitution_check) == pytest.approx(k, abs=check_tolerance(r))
    assert bool(r.energy_not_gained)


@given(scenes(), st.floats(0.0, 1.0), st.floats(0.0, 0.999))
@settings(**SETTINGS)
def test_sliding_transmits_exactly_mu_c_times_the_normal_impulse(case, k, share):
    assume(compression_pushes(case))
    sticking = pim.solve(case, 0.0, 1.0, backend="numpy")
    mu_c = share * abs(float(sticking.mu0))         # below what sticking needs: the contact slides
    r = solve_kudlich_slibar(case, k, mu_c)
    assume(not bool(r.q_singular))
    pn, pt = float(r.impulse_n), float(r.impulse_t)
    # round-off relative to Pt itself: near grazing mu_c (a share of |mu0|) runs to
    # thousands, and Pt = mu_c Pn carries Pt's own last digits (3.9e-13 of Pt was a failure
    # against 1e-9 Pn alone)
    assert pt == pytest.approx(np.sign(float(sticking.mu0)) * mu_c * pn, rel=1e-9,
                               abs=1e-9 * abs(pn) + 1e-300)
    assert float(r.restitution_check) == pytest.approx(k, abs=check_tolerance(r))


def _pycrash_form(m1, i1, d1, m2, i2, d2, u_n, u_t, k, mu_c):
    """Independent scalar derivation in n-t components (Carpenter & Welcher's equations as
    pycrash's impc_calcs writes them): d_i = (d_n, d_t) arms in n-t, u = u_1 - u_2 at C."""
    a11 = 1 / m1 + 1 / m2 + d1[1] ** 2 / i1 + d2[1] ** 2 / i2       # n-n
    a12 = -(d1[0] * d1[1] / i1 + d2[0] * d2[1] / i2)                # n-t
    a22 = 1 / m1 + 1 / m2 + d1[0] ** 2 / i1 + d2[0] ** 2 / i2       # t-t
    det = a11 * a22 - a12 * a12
    # sticking total impulse: K P = -(1 + k) u
    pn = -(1 + k) * (a22 * u_n - a12 * u_t) / det
    pt = -(1 + k) * (a11 * u_t - a12 * u_n) / det
    if abs(pt) > mu_c * pn:
        s = math.copysign(1.0, pt)
        pn = -(1 + k) * u_n / (a11 + s * mu_c * a12)
        pt = s * mu_c * pn
    return pn, pt


@pytest.mark.parametrize("name,k,mu_c", [("ricsac9", 0.1, 0.6), ("ricsac9", 0.3, 0.2),
                                          ("hard-grazing", 0.2, 0.5), ("hard-spinning", 0.0, 0.4),
                                          ("hard-barrier", 0.15, 0.3)])
def test_kudlich_slibar_matches_an_independent_n_t_derivation(name, k, mu_c):
    case = pim.load_case(name)
    r = solve_kudlich_slibar(case, k, mu_c)
    n, t = np.asarray(r.normal), np.asarray(r.tangent)
    d1 = np.asarray(r.arm1) @ n, np.asarray(r.arm1) @ t
    d2 = np.asarray(r.arm2) @ n, np.asarray(r.arm2) @ t
    v1, v2 = case.vehicle1, case.vehicle2
    pn, pt = _pycrash_form(float(v1.mass), float(v1.yaw_inertia), d1, float(v2.mass),
                           float(v2.yaw_inertia), d2, float(r.approach_n), float(r.approach_t),
                           k, mu_c)
    assert float(r.impulse_n) == pytest.approx(pn, rel=1e-10)
    assert float(r.impulse_t) == pytest.approx(pt, rel=1e-10, abs=1e-10 * abs(pn))


# ---- the mapping to Brach's PIM, both directions --------------------------------------------
@given(ANY_SCENE, st.floats(0.0, 1.0), st.floats(0.0, 3.0))
@settings(**SETTINGS)
def test_kudlich_slibar_is_pim_at_eps_k_and_mu0_at_eps_0_capped(case, k, mu_c):
    assume(compression_pushes(case))
    ks = solve_kudlich_slibar(case, k, mu_c)
    assume(not bool(ks.q_singular))
    eps, beta = kudlich_slibar_as_brach(case, k, mu_c)
    assume(np.isfinite(beta))
    brach = pim.solve(case, eps, beta, backend="numpy")
    assume(not bool(brach.q_singular))
    close(ks, brach, scale_of(case))
    # the same through the friction-capped Brach law: beta = mu0(0)/mu0(k), capped at mu_c
    mu0_0 = float(pim.solve(case, 0.0, 1.0).mu0)
    mu0_k = float(pim.solve(case, k, 1.0).mu0)
    if mu0_k != 0 and mu0_0 / mu0_k >= 0:
        close(ks, solve_capped(case, k, mu0_0 / mu0_k, mu_c), scale_of(case))


@given(ANY_SCENE, st.floats(0.0, 1.0), st.floats(0.0, 1.0))
@settings(**SETTINGS)
def test_pim_answers_within_the_compression_ratio_are_kudlich_slibar_answers(case, eps, frac):
    assume(compression_pushes(case))
    mu0_0 = float(pim.solve(case, 0.0, 1.0).mu0)
    mu0_eps = float(pim.solve(case, eps, 1.0).mu0)
    assume(mu0_eps != 0 and np.sign(mu0_eps) == np.sign(mu0_0))
    beta = frac * mu0_0 / mu0_eps            # |mu| = frac |mu0(0)|, the sign of mu0(0)
    brach = pim.solve(case, eps, beta, backend="numpy")
    assume(not bool(brach.q_singular))
    k, mu_c = brach_as_kudlich_slibar(case, eps, beta)
    assert float(k) == eps
    assert float(mu_c) == pytest.approx(frac * abs(mu0_0), rel=1e-12)
    ks = solve_kudlich_slibar(case, k, mu_c)
    assume(not bool(ks.q_singular))
    close(ks, brach, scale_of(case))
    # and back again
    eps2, beta2 = kudlich_slibar_as_brach(case, k, mu_c)
    assert float(eps2) == eps and float(beta2) == pytest.approx(beta, rel=1e-9, abs=1e-12)


def test_pim_beyond_the_compression_ratio_has_no_kudlich_slibar_equivalent():
    case = pim.load_case("ricsac9")
    mu0_0 = float(pim.solve(case, 0.0, 1.0).mu0)
    mu0_eps = float(pim.solve(case, 0.5, 1.0).mu0)
    k, mu_c = brach_as_kudlich_slibar(case, 0.5, [1.1 * mu0_0 / mu0_eps, -0.5])
    assert np.isnan(k).all() and np.isnan(mu_c).all()


def test_the_capped_brach_law_is_not_pc_crashs_law():
    # The corrected claim: capping PIM's mu = mu0(k) is not Kudlich-Slibar when the contact
    # sticks (the slip ends at 0 instead of -k u_t).
    case = pim.load_case("ricsac9")
    capped = solve_capped(case, 0.3, 1.0, 10.0)
    ks = solve_kudlich_slibar(case, 0.3, 10.0)
    assert float(capped.separation_t) == pytest.approx(0.0, abs=1e-9)
    assert float(ks.separation_t) == pytest.approx(-0.3 * float(ks.approach_t), rel=1e-9)
    assert abs(float(ks.yaw_rate2) / float(capped.yaw_rate2) - 1) > 1e-3


# ---- vectorised, Result-compatible, flags --------------------------------------------------
def test_vectorised_equals_one_by_one_and_outputs_are_results():
    cases = random_cases(40, seed=3)
    k, mu_c = np.linspace(0, 1, 40), np.linspace(0.05, 1.5, 40)
    batch = solve_kudlich_slibar(cases, k, mu_c)
    assert isinstance(batch, pim.Result) and batch.delta_v1.shape == (40, 2)
    for i in range(0, 40, 7):
        v1, v2, imp = cases.vehicle1, cases.vehicle2, cases.impact
        one = pim.Case(pim.Vehicle(v1.mass[i], v1.yaw_inertia[i], v1.cg[i], v1.velocity[i],
                                   v1.yaw_rate[i], v1.heading[i]),
                       pim.Vehicle(v2.mass[i], v2.yaw_inertia[i], v2.cg[i], v2.velocity[i],
                                   v2.yaw_rate[i], v2.heading[i]),
                       pim.Impact(imp.point[i], imp.normal_angle[i]))
        r = solve_kudlich_slibar(one, k[i], mu_c[i])
        np.testing.assert_allclose(r.velocity1, batch.velocity1[i], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(r.pdof1, batch.pdof1[i], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(r.energy_loss, batch.energy_loss[i], rtol=1e-12, atol=1e-6)


def test_sticking_kudlich_slibar_is_not_flagged_but_its_pim_twin_says_why():
    case = pim.load_case("ricsac9")
    ks = solve_kudlich_slibar(case, 0.3, 10.0)
    assert ks.problems() == [] and bool(ks.admissible)
    eps, beta = kudlich_slibar_as_brach(case, 0.3, 10.0)
    twin = pim.solve(case, float(eps), float(beta))
    text = " ".join(twin.problems())
    assert "Kudlich-Slibar" in text and "not Coulomb friction" not in text


def test_no_approach_means_no_impulse():
    case = pim.load_case("ricsac9")
    away = case.transformed()
    away = pim.Case(away.vehicle1, away.vehicle2, pim.Impact(away.impact.point, np.pi))
    r = solve_kudlich_slibar(away, 0.2, 0.5)
    assert not bool(r.approaching) and float(r.impulse_n) == 0.0


# ---- parameters, case files, command line ---------------------------------------------------
@pytest.mark.parametrize("k,mu_c,field", [(1.5, 0.5, "restitution k"), (-0.1, 0.5, "restitution k"),
                                          (0.2, -0.1, "contact_friction mu_c"),
                                          (float("nan"), 0.5, "restitution k")])
def test_bad_parameters_name_the_field(k, mu_c, field):
    with pytest.raises(ValueError, match=field):
        solve_kudlich_slibar(pim.load_case("ricsac9"), k, mu_c)


def test_solve_follows_the_law_and_refuses_what_a_law_does_not_take():
    case = pim.load_case("ricsac9")
    close(pim.solve(case, law="brach-capped", eps=0.355, beta=1.0, mu_c=0.3),
          solve_capped(case, 0.355, 1.0, 0.3), 1.0)
    close(pim.solve(case, law=KS, k=0.1, mu_c=0.6), solve_kudlich_slibar(case, 0.1, 0.6), 1.0)
    close(pim.solve(case, 0.1, law=KS, mu_c=0.6), solve_kudlich_slibar(case, 0.1, 0.6), 1.0)
    with pytest.raises(ValueError, match="beta does not apply"):
        pim.solve(case, 0.1, 1.0, law=KS, mu_c=0.6)
    with pytest.raises(ValueError, match="does not apply to law 'brach'"):
        pim.solve(case, 0.1, 1.0, law="brach", mu_c=0.6)
    with pytest.raises(ValueError, match=r"mu_c \(the contact friction\) is required for law"):
        pim.solve(case, 0.1, law=KS)
    with pytest.raises(ValueError, match="law must be one of"):
        pim.solve(case, law="pc-crash")


KS_IMPACT = """
[impact]
point = [0, 0]
normal_angle = "0 deg"
{impact}
"""


def write_case(tmp_path, impact: str):
    path = tmp_path / "ks.toml"
    path.write_text(TWO_CARS_TOML + KS_IMPACT.format(impact=impact))
    return path


def test_case_file_names_the_law_and_its_parameters(tmp_path):
    path = write_case(tmp_path, 'law = "kudlich-slibar"\nrestitution = 0.1\n'
                                'contact_friction = 0.6')
    case = pim.load_case(path)
    assert case.impact.law == KS and case.impact.contact_friction == 0.6
    close(pim.solve(case), solve_kudlich_slibar(case, 0.1, 0.6), 1.0)


@pytest.mark.parametrize("impact,message", [
    ('law = "kudlich-slibar"\nrestitution = 1.2\ncontact_friction = 0.6',
     "impact.restitution must be in"),
    ('law = "kudlich-slibar"\nrestitution = 0.1\ncontact_friction = -0.6',
     "impact.contact_friction must be >= 0"),
    ('law = "pc-crash"\nrestitution = 0.1', "impact.law must be one of"),
    ('law = "kudlich-slibar"\nrestitution = 0.1\nbeta = 1\ncontact_friction = 0.6',
     "impact.beta does not apply"),
    ('restitution = 0.1\ncontact_friction = 0.6', "impact.contact_friction needs law"),
])
def test_case_file_errors_name_the_field(tmp_path, capsys, impact, message):
    path = write_case(tmp_path, impact)
    with pytest.raises(ValueError, match=message):
        pim.load_case(path)
    assert main(["solve", str(path)]) == 2
    assert message in capsys.readouterr().err


def test_solve_command_applies_the_case_law_and_the_options(tmp_path, capsys):
    path = write_case(tmp_path, 'law = "kudlich-slibar"\nrestitution = 0.1\n'
                                'contact_friction = 0.6')
    assert main(["solve", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["law"] == KS
    ks = solve_kudlich_slibar(pim.load_case(path), 0.1, 0.6)
    yaw2 = out["results"]["yaw_rate"]["vehicle2"]
    assert yaw2 == pytest.approx(math.degrees(float(ks.yaw_rate2)))
    assert main(["solve", "ricsac9", "--law", KS, "--k", "0.2", "--mu-c", "0.5"]) == 0
    assert "Kudlich-Slibar law, k = 0.2, mu_c = 0.5" in capsys.readouterr().out


@pytest.mark.parametrize("args,message", [
    (["--law", KS, "--k", "1.5", "--mu-c", "0.5"], "--k (restitution) must be in [0, 1]"),
    (["--law", KS, "--k", "0.5", "--mu-c", "-1"], "--mu-c (contact friction) must be >= 0"),
    (["--k", "0.5"], "--k is the restitution of law kudlich-slibar"),
    (["--mu-c", "0.5"], "--mu-c needs --law"),
    (["--law", KS, "--k", "0.5", "--mu-c", "0.5", "--beta", "1"], "--beta does not apply"),
    (["--law", KS, "--cap-friction", "--friction-limit", "0.5"], "contradicts"),
])
def test_solve_command_errors(capsys, args, message):
    assert main(["solve", "ricsac9", *args]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("command", ["uncertainty", "sensitivity", "assumptions"])
def test_commands_that_cannot_use_the_law_yet_say_so(tmp_path, capsys, command):
    path = write_case(tmp_path, 'law = "kudlich-slibar"\nrestitution = 0.1\n'
                                'contact_friction = 0.6')
    assert main([command, str(path)]) == 2
    err = capsys.readouterr().err
    assert f"pim {command} cannot use impact law 'kudlich-slibar' yet" in err
    assert "`pim reconstruct` and `pim event` apply the law itself" in err
    # the Brach equivalent of this case, by the mapping
    eps, beta = kudlich_slibar_as_brach(pim.load_case(str(path)), 0.1, 0.6)
    assert f"restitution = {float(eps):.6g}, beta = {float(beta):.6g}" in err


# ---- the laws on dual numbers (motion_of_law): values and exact one-sided derivatives ------
def law_row(case, restitution, beta, mu_c):
    """The inputs of motion_of_law (LAW_INPUTS) of a scalar case."""
    return np.concatenate([motion_inputs(case, restitution, beta), [mu_c]])


def as_outputs(r):
    """A Result as the vector of MOTION_OUTPUTS [SI]."""
    return np.array([r.impulse_n, r.impulse_t, *r.impulse, *r.velocity1, *r.velocity2,
                     r.yaw_rate1, r.yaw_rate2], dtype=float)


def central_differences(x, law, h_rel=1e-6):
    """d output / d input by central differences of the plain (no dual) evaluation."""
    fd = np.zeros((len(MOTION_OUTPUTS), len(x)))
    for i in range(len(x)):
        h = h_rel * max(1.0, abs(x[i]))
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        fd[:, i] = (motion_of_law(xp, law, jacobian=False)[0]
                    - motion_of_law(xm, law, jacobian=False)[0]) / (2 * h)
    return fd


# RICSAC 9 needs mu0(0) = 0.634 to stick: mu_c = 0.4 slides, 0.9 sticks; capped Brach at
# eps = 0.3, beta = 0.8 needs beta |mu0(0.3)| (about 0.42): 0.2 is capped, 2 is not.
@pytest.mark.parametrize("law, restitution, beta, mu_c, side", [
    (KS, 0.355, 1.0, 0.4, "sliding"), (KS, 0.355, 1.0, 0.9, "sticking"),
    (KS, 0.1, 1.0, 0.0, "sliding"), (KS, 0.8, 1.0, np.inf, "sticking"),
    ("brach-capped", 0.3, 0.8, 0.2, "sliding"), ("brach-capped", 0.3, 0.8, 2.0, "sticking")])
def test_law_motion_and_its_jacobian_on_both_sides_of_the_cap(law, restitution, beta, mu_c,
                                                              side):
    case = pim.load_case("ricsac9")
    x = law_row(case, restitution, beta, mu_c)
    assert (needed_friction(x, law) > mu_c) == (side == "sliding")
    values, jac = motion_of_law(x, law)
    # values: the vector-form solver (solve_kudlich_slibar; solve_capped), an independent path
    ref = as_outputs(pim.solve(case, restitution, None if law == KS else beta, law=law,
                               mu_c=mu_c))
    np.testing.assert_allclose(values, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    finite = np.isfinite(x)
    fd = central_differences(np.where(finite, x, 1e6), law)     # mu_c = inf: a huge one
    np.testing.assert_allclose(jac[:, finite], fd[:, finite], rtol=1e-5,
                               atol=1e-6 * np.abs(jac).max())
    mu = LAW_INPUTS.index("impact.contact_friction")
    if side == "sticking":                      # the cap is not reached: mu_c does nothing
        assert np.all(jac[:, mu] == 0.0)
    else:
        assert np.abs(jac[:, mu]).max() > 0


def test_at_the_cap_the_derivative_is_the_sticking_sides():
    """The kink: at mu_c = mu0(0) exactly the Jacobian is the sticking side's (one-sided)."""
    case = pim.load_case("ricsac9")
    x = law_row(case, 0.355, 1.0, 0.0)
    x[-1] = needed_friction(x, KS)
    _, at = motion_of_law(x, KS)
    above = x.copy()
    above[-1] *= 1.0 + 1e-9
    _, stick = motion_of_law(above, KS)
    np.testing.assert_allclose(at, stick, rtol=1e-6, atol=1e-9 * np.abs(at).max())
    below = x.copy()
    below[-1] *= 1.0 - 1e-6
    _, slide = motion_of_law(below, KS)
    assert np.abs(slide[:, -1]).max() > 0 and np.all(at[:, -1] == 0.0)


@given(ANY_SCENE, st.floats(0.0, 1.0), st.floats(0.0, 3.0))
@settings(**SETTINGS)
def test_law_motion_is_the_vector_solver_on_random_scenes(case, k, mu_c):
    assume(compression_pushes(case))
    ks = solve_kudlich_slibar(case, k, mu_c)
    assume(not bool(ks.q_singular))
    values, _ = motion_of_law(law_row(case, k, 1.0, mu_c), KS, jacobian=False)
    ref = as_outputs(ks)
    np.testing.assert_allclose(values, ref, rtol=1e-8, atol=1e-8 * (1 + np.abs(ref).max()))
