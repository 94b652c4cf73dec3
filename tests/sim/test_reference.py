"""The solve_ivp reference of the point contact: methods agree, invariants, PIM's limits."""

import math
from dataclasses import replace

import numpy as np
import pytest

import pim
import sim
from sim import CompliantSettings
from sim.contact_law import contact_duration_estimate, stiffness_for_duration

K = sim.DEFAULT_STIFFNESS

def cross2(a, b):
    """z of a x b for planar vectors (..., 2), written out (np.cross on 2D is deprecated)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]



@pytest.fixture(scope="module")
def ricsac9():
    return pim.load_case("ricsac9")


def post(r):
    return np.r_[r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2]


def offset_barrier_case():
    """A car hits a wall with C 0.8 m off its line of motion: no initial slip, K_nt != 0."""
    v1 = pim.Vehicle(1500.0, 2500.0, (-1.0, 0.8), (15.0, 0.0), 0.0, 0.0)
    return pim.Case(v1, pim.Vehicle.obstacle((1.0, 0.0)), pim.Impact((0.0, 0.0), math.pi))


@pytest.mark.parametrize("friction", [0.0, 0.8])
def test_explicit_and_implicit_methods_agree(ricsac9, friction):
    a = sim.reference_compliant(ricsac9, 0.355, K, friction=friction,
                                settings=CompliantSettings(method="DOP853", rtol=1e-10,
                                                           record=False))
    b = sim.reference_compliant(ricsac9, 0.355, K, friction=friction,
                                settings=CompliantSettings(method="Radau", rtol=1e-10,
                                                           record=False))
    assert np.abs(post(a) - post(b)).max() < 1e-6
    assert a.contact_duration == pytest.approx(b.contact_duration, rel=1e-7)


@pytest.mark.parametrize("method", ["DOP853", "Radau"])
def test_momentum_conserved(ricsac9, method):
    r = sim.reference_compliant(ricsac9, 0.355, K, friction=0.8,
                                settings=CompliantSettings(method=method, rtol=1e-11,
                                                           record=False))
    v1, v2 = ricsac9.vehicle1, ricsac9.vehicle2
    lin0 = v1.mass * v1.velocity + v2.mass * v2.velocity
    lin = v1.mass * r.velocity1 + v2.mass * r.velocity2
    # Runge-Kutta and collocation methods keep linear invariants exactly: round-off
    assert np.abs(lin - lin0).max() < 1e-10 * np.linalg.norm(lin0)
    # angular momentum about the origin is quadratic in the state: kept to the tolerance
    tr = r.trajectory
    i = tr.impact_index

    def angular(p1, u1, w1, p2, u2, w2):
        return (v1.mass * cross2(p1, u1) + v1.yaw_inertia * w1
                + v2.mass * cross2(p2, u2) + v2.yaw_inertia * w2)

    before = angular(v1.cg, v1.velocity, v1.yaw_rate, v2.cg, v2.velocity, v2.yaw_rate)
    after = angular(tr.position1[i], tr.velocity1[i], tr.yaw_rate1[i], tr.position2[i],
                    tr.velocity2[i], tr.yaw_rate2[i])
    scale = float(v1.mass * np.linalg.norm(v1.velocity) * np.linalg.norm(v1.cg)
                  + v2.mass * np.linalg.norm(v2.velocity) * np.linalg.norm(v2.cg))
    assert abs(after - before) < 1e-8 * scale


def test_point_mass_restitution_is_exactly_eps():
    v1 = pim.Vehicle(1500.0, 2500.0, (-1.0, 0.0), (15.0, 0.0), 0.0, 0.0)
    case = pim.Case(v1, pim.Vehicle.obstacle((1.0, 0.0)), pim.Impact((0.0, 0.0), math.pi))
    for eps in (0.0, 0.165, 0.5, 1.0):
        r = sim.reference_compliant(case, eps, K,
                                    settings=CompliantSettings(rtol=1e-12, record=False))
        assert -r.velocity1[0] / 15.0 == pytest.approx(eps, rel=1e-8, abs=1e-9)
        expected = contact_duration_estimate(K, 1 / 1500, eps)
        if eps > 0:
            assert r.contact_duration == pytest.approx(expected, rel=1e-8)


def test_sticking_stiff_limit_is_pim_beta1_where_slip_does_not_reverse():
    case = offset_barrier_case()
    pim1 = pim.solve(case, 0.3, 1.0)
    k_nn = float(pim1.k_nn)
    scale = np.array([1, 1, math.sqrt(2500 / 1500)])

    def error(duration, ratio):
        k = float(stiffness_for_duration(duration, k_nn, 0.3))
        r = sim.reference_compliant(case, 0.3, k, friction=2.0, settings=CompliantSettings(
            rtol=1e-10, record=False, tangential_stiffness=ratio * k,
            tangential_recovery=1.0))
        diff = np.r_[r.velocity1 - pim1.velocity1, r.yaw_rate1 - pim1.yaw_rate1] * scale
        return np.abs(diff).max() / 15.0, r

    coarse, r1 = error(0.02, 1000.0)
    fine, r2 = error(0.005, 1000.0)
    assert not r1.slip_reversed and not r2.slip_reversed
    assert r2.stick_fraction > 0.99
    assert fine < 0.005 and fine < coarse / 2
    # a soft friction spring gives its energy back: the slip reverses, which is reported
    soft, r3 = error(0.005, 1.0)
    assert r3.slip_reversed and soft > 0.1


def test_no_outline_reference(ricsac9):
    with pytest.raises(ValueError, match="point"):
        sim.reference_compliant(ricsac9, 0.3, K, geometry="outline")


def test_history_is_recorded(ricsac9):
    r = sim.reference_compliant(ricsac9, 0.355, K, friction=0.5)
    h = r.history
    assert len(h.time) >= 100
    assert (h.normal_force >= 0).all()
    stepped = sim.simulate_compliant(ricsac9, 0.355, K, friction=0.5, engine="pymunk")
    assert r.peak_force == pytest.approx(stepped.peak_force, rel=0.01)
    assert r.peak_crush == pytest.approx(stepped.peak_crush, rel=1e-3)


@pytest.mark.parametrize("recovery", [0.0, 0.5])
def test_tangential_recovery_modes_agree_with_the_stepper(ricsac9, recovery):
    # sticking contact (mu_c = 3): sticking, unloading at v_t / r and sliding as modes with
    # events, against pymunk's implicit step at 400 steps per contact (second order):
    # measured 7.0e-5 (r = 0) and 1.1e-5 (r = 0.5); 6.7e-3 and 7.8e-5 before the r = 0
    # release was located inside the step and the slip taken at the middle of the step
    settings = CompliantSettings(tangential_recovery=recovery, record=False)
    ref = sim.reference_compliant(ricsac9, 0.355, K, friction=3.0,
                                  settings=CompliantSettings(tangential_recovery=recovery,
                                                             record=False, rtol=1e-8))
    got = sim.simulate_compliant(ricsac9, 0.355, K, friction=3.0, settings=settings,
                                 engine="pymunk")
    assert np.abs(post(ref) - post(got)).max() < 2e-4
    assert ref.stick_fraction > 0.9 and got.stick_fraction > 0.9
    assert ref.tangential_recovery == recovery


def test_phase_cap_stops_a_switching_contact(ricsac9):
    # mu_c = 3 on RICSAC 9 takes 5 phases (loading, sticking to unloading...): a cap of 2
    # stands for a chattering stick/slip switch and must stop it, naming the cap
    with pytest.raises(sim.SimulationError, match="max_phases = 2") as err:
        sim.reference_compliant(ricsac9, 0.355, K, friction=3.0,
                                settings=CompliantSettings(record=False, max_phases=2))
    assert err.value.kind == "not_converged"
    assert "CompliantSettings(max_phases=" in str(err.value)


def test_step_cap_counts_the_accepted_steps_exactly(ricsac9):
    settings = CompliantSettings(record=False)
    free = sim.reference_compliant(ricsac9, 0.355, K, friction=0.5, settings=settings)
    # the cap counts what the result reports: exactly enough passes, one fewer stops it
    same = sim.reference_compliant(ricsac9, 0.355, K, friction=0.5,
                                   settings=replace(settings, max_steps=free.steps))
    assert np.array_equal(post(same), post(free))
    with pytest.raises(sim.SimulationError, match=f"max_steps = {free.steps - 1}") as err:
        sim.reference_compliant(ricsac9, 0.355, K, friction=0.5,
                                settings=replace(settings, max_steps=free.steps - 1))
    assert err.value.kind == "not_converged"
    assert "CompliantSettings(max_steps=" in str(err.value)


def test_default_caps_are_far_above_the_bundled_cases():
    # measured over every bundled case (mu_c 0, 0.5, 3; r default, 0, 1; tyres 0.7): at
    # most 8 phases (hard-barrier), and 24 502 steps at rtol 1e-9 (hard-near-singular-q)
    # (docs/contact-model.md, "Caps of the reference")
    settings = CompliantSettings()
    assert settings.max_phases >= 100 * 8
    assert settings.max_steps >= 40 * 24_502
