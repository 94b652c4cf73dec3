"""The crush scene's arithmetic written once: Chipmunk's integration reproduced bit for bit,
the one source behind pymunk, the compiled kernel and the array API."""

import math

import numpy as np
import pymunk
import pytest

import sim.compliant as compliant
from sim import compliant_formula as f
from sim import contact_law, contact_tyres
from sim.compliant_kernel import compile_module

pytestmark = pytest.mark.xdist_group("compliant_kernel")


def test_drift_and_kick_are_chipmunks_own_updates():
    # a pymunk body pushed by a changing force and torque, against the formula's drift and
    # kick on the same numbers: equal to the last bit (Chipmunk's cpBodyUpdatePosition and
    # cpBodyUpdateVelocity, gravity 0, damping 1)
    rng = np.random.default_rng(3)
    space = pymunk.Space()
    space.damping = 1.0
    body = pymunk.Body(1234.5, 2345.6)
    body.position, body.angle = (0.3, -1.7), 0.4
    body.velocity, body.angular_velocity = (12.3, -4.5), 0.7
    loads = iter(rng.normal(0.0, 1e5, (200, 3)))

    def velocity(b, gravity, damping, dt):
        fx, fy, t = next(loads)
        b.force, b.torque = (float(fx), float(fy)), float(t)
        pymunk.Body.update_velocity(b, gravity, damping, dt)

    body.velocity_func = velocity
    space.add(body)
    par = [0.0] * f.N_PAR
    par[f.P_M1], par[f.P_I1], par[f.P_FIXED2] = 1234.5, 2345.6, 1.0
    par[f.P_INVERSE], par[f.P_INVERSE + 1] = 1.0 / 1234.5, 1.0 / 2345.6   # as Chipmunk
    st = [0.3, -1.7, 0.4, 12.3, -4.5, 0.7] + [0.0] * 6
    replay = iter(rng.__class__(np.random.PCG64(3)).normal(0.0, 1e5, (200, 3)))
    dt = 1.37e-4
    for _ in range(200):
        space.step(dt)
        f.drift(par, st, dt)
        fx, fy, t = next(replay)
        f.kick(par, st, [float(fx), float(fy), float(t), 0.0, 0.0, 0.0], dt)
    p, v = body.position, body.velocity
    assert [p.x, p.y, body.angle, v.x, v.y, body.angular_velocity] == st[:6]


def test_the_compiled_functions_are_the_formulas_source():
    compiled = compile_module(f)
    for name in ("normal_force", "tangential_step", "point_contact", "contact_loads",
                 "vehicle_tyre_force", "drift", "kick"):
        assert getattr(compiled, name).py_func.__code__ is getattr(f, name).__code__
    # and one evaluation each way agrees bitwise
    args = (0.12, 0.15, 0.4, 2e4, 7.5e5)
    assert compiled.normal_force(*args) == f.normal_force(*args)


def test_pymunk_and_the_array_api_call_the_formula():
    # no second copy of the law: the pymunk scene and sim.contact_law evaluate these
    assert compliant.contact_loads is f.contact_loads
    assert compliant.total_loads is f.total_loads
    assert contact_law.normal_force.__doc__ == f.normal_force.__doc__
    assert contact_tyres.vehicle_tyre_force is f.vehicle_tyre_force


@pytest.mark.parametrize("delta, dmax, eps, a, b, expected", [
    (0.1, 0.1, 0.5, 0.0, 1e6, 1e5),                          # loading
    (0.5 * (1 - 0.25) + 0.01, 0.5, 0.5, 0.0, 1e6, 1e6 / 0.25 * 0.01),   # unloading, k / eps^2
    (0.3, 0.5, 0.5, 0.0, 1e6, 0.0),                          # below delta_p
    (0.2999, 0.3, 0.0, 0.0, 1e6, 0.0),                       # eps = 0: nothing back
    (-0.1, 0.0, 0.5, 0.0, 1e6, 0.0),                         # apart
])
def test_normal_force_on_floats(delta, dmax, eps, a, b, expected):
    assert f.normal_force(delta, dmax, eps, a, b) == pytest.approx(expected, rel=1e-9, abs=1e-6)


def test_tangential_step_recovery_and_cone():
    assert f.tangential_step(0.0, 2.0, 1e-3, 0.01, 1.0) == pytest.approx(2e-3)
    assert f.tangential_step(0.004, 20.0, 1e-3, 0.01, 1.0) == 0.01          # on the cone
    # unloading at 1 / r the rate: r = 0.5 takes back twice the slip
    assert f.tangential_step(0.004, -1.0, 1e-3, 0.01, 0.5) == pytest.approx(0.002)
    # r = 0: released at once, the rest of the slip loads the other way
    assert f.tangential_step(0.004, -1.0, 1e-3, 0.01, 0.0) == pytest.approx(-1e-3)


def test_plastic_release_takes_back_the_share_after_the_turn():
    # slip 1 m/s then -3 m/s: it turned a quarter of the way through, so 3/4 of the last
    # kick's friction force is taken back
    assert f.plastic_release(0.0, 0.01, 1.0, -3.0, 100.0, -40.0) == (-75.0, 30.0)
    assert f.plastic_release(0.5, 0.01, 1.0, -3.0, 100.0, -40.0) == (0.0, 0.0)


def test_point_contact_of_a_turning_plane():
    # vehicle 2 turned 90 deg: its body-frame normal (1, 0) points along +y
    c2, s2 = math.cos(math.pi / 2), math.sin(math.pi / 2)
    px, py, nx, ny, delta, slip_n, slip_t = f.point_contact(
        1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -2.0, 0.5, 1.0, 0.5, c2, s2,
        0.0, 0.0, 0.0)
    assert (px, py) == (1.0, 0.0)
    assert nx == pytest.approx(0.0, abs=1e-16) and ny == 1.0
    assert delta == pytest.approx(0.5)                      # P 0.5 m below the plane at Q
    assert slip_n == pytest.approx(-2.0 + 0.5 * 1.0)        # v_y + w x r_x
    assert slip_t == pytest.approx(0.0, abs=1e-15)


def test_a_turn_is_within_an_ulp_of_the_c_librarys_cos_and_sin():
    # the polynomials of turn_cos_sin against math.cos / math.sin in both ranges, at the
    # range ends, at tiny turns and beyond SMALL_TURN (the C library's there)
    rng = np.random.default_rng(5)
    turns = np.r_[rng.uniform(-f.TINY_TURN, f.TINY_TURN, 20000),
                  rng.uniform(-f.SMALL_TURN, f.SMALL_TURN, 20000), 10 ** rng.uniform(-15, -2, 2000),
                  f.TINY_TURN, -f.TINY_TURN, f.SMALL_TURN, np.nextafter(f.SMALL_TURN, 1.0), 0.0,
                  rng.uniform(-4.0, 4.0, 200)]
    for d in turns.tolist():
        c, s = f.turn_cos_sin(d)
        assert abs(c - math.cos(d)) <= math.ulp(math.cos(d)), d
        assert abs(s - math.sin(d)) <= max(math.ulp(math.sin(d)), 5e-324), d


def test_the_turned_headings_follow_the_drifted_angles():
    # 20 000 steps of varying yaw rates (a turn of several radians): the cos and sin turned
    # on step by step stay on the unit circle and within 1e-12 of cos and sin of the heading
    # drift() integrates; a fixed vehicle 2 does not turn
    rng = np.random.default_rng(6)
    for fixed in (0.0, 1.0):
        par = [0.0] * f.N_PAR
        par[f.P_FIXED2] = fixed
        st = [0.0, 0.0, 2.9, 0.0, 0.0, 0.0, 0.0, 0.0, -1.3, 0.0, 0.0, 0.0]
        trig = f.angles(st)
        dt = 2.5e-4
        for _ in range(20000):
            st[5], st[11] = rng.normal(0.0, 8.0, 2).tolist()
            f.drift(par, st, dt)
            trig = f.advance_angles(par, trig, st, dt)
        exact = f.angles(st)
        assert max(abs(a - b) for a, b in zip(trig, exact, strict=True)) < 1e-12
        assert abs(trig[0] ** 2 + trig[1] ** 2 - 1.0) < 1e-15
        if fixed:
            assert trig[2:] == (math.cos(-1.3), math.sin(-1.3))


def test_the_compiled_turn_is_the_formulas_to_the_last_bit():
    # numba compiles turn_cos_sin and advance_angles from the same source: the same bits as
    # Python floats (no fast-math, no contraction), as the pymunk engine needs
    g = compile_module(f)
    rng = np.random.default_rng(7)
    par = [0.0] * f.N_PAR
    for d in np.r_[rng.uniform(-0.3, 0.3, 300), 10 ** rng.uniform(-9, -1, 100)].tolist():
        assert g.turn_cos_sin(d) == f.turn_cos_sin(d)
        st = [0.0, 0.0, 0.3, 0.0, 0.0, d, 0.0, 0.0, 1.1, 0.0, 0.0, -d]
        trig = f.angles(st)
        assert g.advance_angles(np.array(par), trig, np.array(st), 1e-3) == \
            f.advance_angles(par, trig, st, 1e-3)
