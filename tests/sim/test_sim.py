"""pymunk cross-check of the PIM solver (issue 4): agreement, switches, failure reports."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

import pim
import sim
from pim_cli.main import main as pim_main
from sim.sampling import random_scenes

FT = 0.3048
DEG = np.pi / 180
TOL = 1e-6


def assert_agrees(case, eps, beta, settings=None, tol=TOL):
    """Simulated velocities and yaw rates match pim.solve to ``tol`` relative."""
    a = pim.solve(case, eps, beta)
    r = sim.simulate(case, eps, beta, settings)
    speed = max(np.abs(a.velocity1).max(), np.abs(a.velocity2).max())
    spin = max(abs(float(a.yaw_rate1)), abs(float(a.yaw_rate2)))
    np.testing.assert_allclose(r.velocity1, a.velocity1, rtol=0, atol=tol * speed)
    np.testing.assert_allclose(r.velocity2, a.velocity2, rtol=0, atol=tol * speed)
    np.testing.assert_allclose([r.yaw_rate1, r.yaw_rate2],
                               [float(a.yaw_rate1), float(a.yaw_rate2)], rtol=0, atol=tol * spin)
    return a, r


@pytest.fixture(scope="module")
def ricsac():
    return pim.load_case("ricsac9")


def barrier_case():
    """A car hitting a fixed barrier obliquely with its right-front corner."""
    car = pim.Vehicle(mass=1400.0, yaw_inertia=2100.0, cg=(-2.2, 0.6), velocity=(15.0, -3.0),
                      yaw_rate=0.0, heading=0.0, length=4.4, width=1.8)
    wall = pim.Vehicle.obstacle(cg=(1.0, 0.0), heading=np.pi / 2)
    return pim.Case(car, wall, pim.Impact(point=(0.0, -0.3), normal_angle=np.pi), name="barrier")


def spinning_case():
    """Both vehicles yawing before the impact; contact plane at Gamma = 37 deg."""
    g = 37 * DEG
    n = np.array([np.cos(g), np.sin(g)])
    t = np.array([-n[1], n[0]])
    c = np.array([1.0, 2.0])
    v1 = pim.Vehicle(mass=1200.0, yaw_inertia=1800.0, cg=c + 2.1 * n - 0.8 * t,
                     velocity=(-9.0, -6.0), yaw_rate=1.3, heading=200 * DEG, length=4.2, width=1.7)
    v2 = pim.Vehicle(mass=1900.0, yaw_inertia=3500.0, cg=c - 1.4 * n + 1.1 * t,
                     velocity=(4.0, 7.5), yaw_rate=-2.2, heading=60 * DEG, length=4.9, width=1.9)
    return pim.Case(v1, v2, pim.Impact(point=c, normal_angle=g), name="spinning-37")


# ---- the named cases of the issue ---------------------------------------------------------
@pytest.mark.parametrize("beta", [1.0, 0.5])
def test_ricsac9_agrees(ricsac, beta):
    assert_agrees(ricsac, 0.355, beta)


def test_ricsac9_simulation_matches_published_values(ricsac):
    # Brach's worksheet (ricsac9.md), printed to 4-5 digits: the engine alone reproduces them
    r = sim.simulate(ricsac, 0.355, 1.0)
    np.testing.assert_allclose(r.velocity1 / FT, [-6.126, 12.79], rtol=2e-3)
    np.testing.assert_allclose(r.velocity2 / FT, [-11.498, 25.199], rtol=2e-3)
    np.testing.assert_allclose(np.degrees([r.yaw_rate1, r.yaw_rate2]), [-199.702, 87.322],
                               rtol=2e-3)
    lbs = 4.4482216152605  # lbf s -> N s
    np.testing.assert_allclose(r.impulse / lbs, [1749.993, 896.544], rtol=2e-3)


def test_barrier_agrees():
    case = barrier_case()
    for eps, beta in [(0.2, 1.0), (0.1, 0.6), (0.0, 0.3)]:
        a, r = assert_agrees(case, eps, beta)
        assert r.velocity2.tolist() == [0.0, 0.0] and r.yaw_rate2 == 0.0


@pytest.mark.parametrize("eps,beta", [(0.4, 1.0), (0.25, 0.7), (0.0, 1.0), (1.0, 0.0)])
def test_spinning_gamma37_agrees(eps, beta):
    assert_agrees(spinning_case(), eps, beta)


def test_impulse_is_the_momentum_change_and_pim_impulse(ricsac):
    a, r = assert_agrees(ricsac, 0.355, 0.5)
    m1 = float(ricsac.vehicle1.mass)
    np.testing.assert_allclose(r.impulse, m1 * (r.velocity1 - ricsac.vehicle1.velocity),
                               rtol=1e-12)
    np.testing.assert_allclose(r.impulse, a.impulse, rtol=1e-9)
    assert r.contact_steps == 1 and r.contact_points == 1
    assert r.energy_after <= r.energy_before
    np.testing.assert_allclose(r.energy_after, float(a.kinetic_energy_after), rtol=1e-9)


def test_rotated_scene_rotates_the_simulation():
    case = spinning_case()
    base = sim.simulate(case, 0.3, 0.8)
    turned = sim.simulate(case.transformed(rotation=1.1, translation=(5.0, -3.0)), 0.3, 0.8)
    c, s = np.cos(1.1), np.sin(1.1)
    rot = np.array([[c, -s], [s, c]])
    np.testing.assert_allclose(turned.velocity1, rot @ base.velocity1, atol=1e-9)
    np.testing.assert_allclose(turned.yaw_rate2, base.yaw_rate2, atol=1e-9)


# ---- randomized -----------------------------------------------------------------------------
def test_random_scenes_agree_or_report_why():
    scenes = random_scenes(220, seed=20240604)
    agreed = reported = 0
    for case, eps, beta in scenes:
        reasons = sim.limitations(case, eps, beta)
        try:
            a = pim.solve(case, eps, beta)
            r = sim.simulate(case, eps, beta)
        except sim.SimulationError as exc:
            assert exc.kind == "not_converged" and reasons, (str(exc), reasons)
            reported += 1
            continue
        speed = max(np.abs(a.velocity1).max(), np.abs(a.velocity2).max())
        spin = max(abs(float(a.yaw_rate1)), abs(float(a.yaw_rate2)))
        err = max(np.abs(np.r_[r.velocity1 - a.velocity1, r.velocity2 - a.velocity2]).max() / speed,
                  abs(r.yaw_rate1 - float(a.yaw_rate1)) / spin,
                  abs(r.yaw_rate2 - float(a.yaw_rate2)) / spin)
        if err > TOL:
            assert reasons, f"disagreement {err:.3g} without a stated limitation"
            reported += 1
        else:
            agreed += 1
    assert agreed + reported == 220
    assert agreed >= 200          # most scenes are reproducible; the rest say why not


def test_simulate_many_matches_simulate():
    scenes = random_scenes(5, seed=3, barrier_fraction=0.0)
    cases = [c for c, _, _ in scenes]
    eps = [e for _, e, _ in scenes]
    beta = [b for _, _, b in scenes]
    batch = sim.simulate_many(cases, eps, beta)
    for i, (c, e, b) in enumerate(scenes):
        try:
            one = sim.simulate(c, e, b)
        except sim.SimulationError as exc:
            assert batch.failure[i] == exc.kind
            continue
        np.testing.assert_array_equal(batch.velocity1[i], one.velocity1)
        np.testing.assert_array_equal(batch.yaw_rate2[i], one.yaw_rate2)
    # an array-valued case: one scene per element
    ricsac = pim.load_case("ricsac9")
    speeds = np.array([8.0, 9.5, 11.0])
    v1 = replace(ricsac.vehicle1, velocity=np.stack([-speeds, 0 * speeds], -1))
    many = sim.simulate_many(replace(ricsac, vehicle1=v1), 0.355, 1.0)
    a = pim.solve(replace(ricsac, vehicle1=v1), 0.355, 1.0)
    assert many.ok.all()
    np.testing.assert_allclose(many.velocity1, a.velocity1, atol=1e-9)


# ---- switches -------------------------------------------------------------------------------
def test_detected_start_error_shrinks_with_dt(ricsac):
    a = pim.solve(ricsac, 0.355, 1.0)
    errs = []
    for dt in (4e-3, 1e-3, 2.5e-4):
        r = sim.simulate(ricsac, 0.355, 1.0, sim.Settings(start="detected", dt=dt))
        errs.append(np.abs(r.velocity1 - a.velocity1).max())
    assert errs[0] > errs[1] > errs[2] > 0
    assert errs[0] / errs[2] > 8          # about first order in dt (16x for 16x smaller dt)


def test_outline_contact_is_a_patch_and_differs(ricsac):
    r = sim.simulate(ricsac, 0.355, 1.0, sim.Settings(contact="outline", start="detected"))
    a = pim.solve(ricsac, 0.355, 1.0)
    assert r.contact_steps >= 1
    assert np.abs(r.velocity1 - a.velocity1).max() > 1e-3    # another contact geometry
    assert r.energy_after <= r.energy_before * (1 + 1e-6)


def test_trajectory_recording_and_tyre_friction(ricsac):
    settings = sim.Settings(record=True, duration=3.0, tyre_friction=True, dt=2e-3)
    r = sim.simulate(ricsac, 0.355, 1.0, settings)
    tr = r.trajectory
    assert tr.impact_time == 0.0 and tr.time[0] < 0
    np.testing.assert_allclose(tr.position1[tr.impact_index], ricsac.vehicle1.cg, atol=1e-12)
    np.testing.assert_allclose(tr.angle2[tr.impact_index], ricsac.vehicle2.heading, atol=1e-12)
    assert np.all(np.diff(tr.time) > 0) and len(tr) == len(tr.angle1)
    # tyre friction 0.7 g stops ~2 m/s within 3 s; the impact result is unaffected
    np.testing.assert_allclose(r.velocity1, pim.solve(ricsac, 0.355, 1.0).velocity1, atol=1e-9)
    assert np.all(r.final_velocity1 == 0) and r.final_yaw_rate1 == 0
    speed = np.hypot(*tr.velocity1[tr.impact_index + 1:].T)
    assert np.all(np.diff(speed) <= 1e-12)
    # without friction the bodies fly on freely
    free = sim.simulate(ricsac, 0.355, 1.0, sim.Settings(duration=0.5))
    np.testing.assert_allclose(free.final_velocity1, free.velocity1)


def test_exact_run_without_record_keeps_start_impact_end(ricsac):
    r = sim.simulate(ricsac, 0.355, 1.0)
    assert r.steps == 1 and len(r.trajectory) == 2 and r.trajectory.impact_index == 1


# ---- failures -------------------------------------------------------------------------------
def test_no_contact_when_tunnelling(ricsac):
    with pytest.raises(sim.SimulationError) as exc:
        sim.simulate(ricsac, 0.355, 1.0, sim.Settings(start="detected", dt=0.05))
    assert exc.value.kind == "no_contact" and "tunnel" in str(exc.value)
    # the same scene is found at a small dt
    sim.simulate(ricsac, 0.355, 1.0, sim.Settings(start="detected", dt=1e-3))


def test_no_contact_when_not_approaching(ricsac):
    v1 = replace(ricsac.vehicle1, velocity=-ricsac.vehicle1.velocity)
    v2 = replace(ricsac.vehicle2, velocity=-ricsac.vehicle2.velocity)
    with pytest.raises(sim.SimulationError) as exc:
        sim.simulate(replace(ricsac, vehicle1=v1, vehicle2=v2), 0.355, 1.0)
    assert exc.value.kind == "no_contact" and "approach" in str(exc.value)


def test_never_separated():
    # an eps = 0 sliding scene (beta 0.089, |mu0| 1.84) whose contact keeps pushing for ~11
    # steps when the engine finds it itself; with a 10 ms limit the run must say so
    case = pim.Case(
        pim.Vehicle(1252.5381171759987, 601.0965912910239, (-4.133293748202192, -7.054374953431136),
                    (7.562804794900693, 3.1264662058272847), 1.593994770591629,
                    -3.06985763697762, length=5.930747347793366, width=1.7181475915831779),
        pim.Vehicle(2555.4558225626674, 5923.617724571249,
                    (-1.5530300430901534, -8.595814935734962),
                    (0.6513460889254361, -7.428539038552355), 1.4080187486834337,
                    -2.4861768215914113, length=5.561096391063549, width=1.640273432287679),
        pim.Impact((-3.0760347785200555, -7.647909038208553), 2.949178726717245))
    eps, beta = 0.0, 0.08936835835602008
    assert abs(float(pim.solve(case, eps, 1.0).mu0)) > 1   # sliding: |mu| < |mu0|
    with pytest.raises(sim.SimulationError) as exc:
        sim.simulate(case, eps, beta, sim.Settings(start="detected", max_contact_time=0.01))
    assert exc.value.kind == "never_separated"


def test_multiple_contacts_face_on_barrier():
    car = pim.Vehicle(mass=1400.0, yaw_inertia=2100.0, cg=(-2.2, 0.0), velocity=(12.0, 0.0),
                      heading=0.0, length=4.4, width=1.8)
    wall = pim.Vehicle.obstacle(cg=(1.0, 0.0))
    case = pim.Case(car, wall, pim.Impact(point=(0.0, 0.0), normal_angle=np.pi))
    settings = sim.Settings(contact="outline", start="detected", max_contact_points=1)
    with pytest.raises(sim.SimulationError) as exc:
        sim.simulate(case, 0.2, 1.0, settings)
    assert exc.value.kind == "multiple_contacts"
    r = sim.simulate(case, 0.2, 1.0, replace(settings, max_contact_points=None))
    assert r.contact_points == 2


def test_energy_gained_with_one_iteration():
    # one sequential-impulse sweep on a strongly coupled contact (K_nt / K_nn = 0.26, a car
    # spinning into a barrier at eps 0.61) overshoots
    case = pim.Case(
        pim.Vehicle(562.8327670438205, 388.53480418316957,
                    (-3.357945403512984, -3.8841995266005562),
                    (-9.630833095442398, -4.313924563970158), 2.7422737732487823,
                    -0.9064370029997773, length=5.20947909812832, width=2.031540182873399),
        pim.Vehicle.obstacle(cg=(-5.060696111211796, -1.9340433564179897),
                             heading=0.10183775106374472),
        pim.Impact((-4.499354806280767, -0.9813882666314981), 0.10183775106374472))
    eps, beta = 0.6053947014299166, 1.0
    settings = sim.Settings(iterations=1, convergence_tolerance=None)
    with pytest.raises(sim.SimulationError) as exc:
        sim.simulate(case, eps, beta, settings)
    assert exc.value.kind == "energy_gained"
    assert_agrees(case, eps, beta)              # default settings are fine


def test_not_converged_reports_why():
    scenes = random_scenes(400, seed=1)
    diverging = [s for s in scenes if any("diverge" in t for t in sim.limitations(*s))]
    assert diverging
    with pytest.raises(sim.SimulationError) as exc:
        sim.simulate(*diverging[0])
    assert exc.value.kind == "not_converged" and "diverge" in str(exc.value)
    # too few iterations on a converging contact is reported too
    with pytest.raises(sim.SimulationError) as exc:
        sim.simulate(pim.load_case("ricsac9"), 0.355, 1.0, sim.Settings(iterations=2))
    assert exc.value.kind == "not_converged"


# ---- input checks ---------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs,field", [
    ({"dt": 0.0}, "dt"), ({"dt": float("nan")}, "dt"), ({"iterations": 0}, "iterations"),
    ({"iterations": 2.5}, "iterations"), ({"contact": "box"}, "contact"),
    ({"start": "late"}, "start"), ({"tyre_friction": -1.0}, "tyre_friction"),
    ({"duration": -1.0}, "duration"), ({"record": 1}, "record"),
    ({"max_contact_time": 0.0}, "max_contact_time"), ({"lead_steps": 0.5}, "lead_steps"),
    ({"contact_radius": 0.0}, "contact_radius"), ({"max_contact_points": 0}, "max_contact_points"),
])
def test_settings_validation(kwargs, field):
    with pytest.raises(ValueError, match=field):
        sim.Settings(**kwargs)


def test_bad_coefficients_and_array_case(ricsac):
    with pytest.raises(ValueError, match="beta"):
        sim.simulate(ricsac, 0.355, 1.2)
    with pytest.raises(ValueError, match="eps"):
        sim.simulate(ricsac, -0.1, 1.0)
    v1 = replace(ricsac.vehicle1, mass=np.array([1000.0, 1100.0]))
    with pytest.raises(ValueError, match="single case"):
        sim.simulate(replace(ricsac, vehicle1=v1), 0.355, 1.0)
    car = replace(ricsac.vehicle1, length=None)
    with pytest.raises(ValueError, match="length"):
        sim.simulate(replace(ricsac, vehicle1=car), 0.355, 1.0, sim.Settings(contact="outline"))


# ---- command line ---------------------------------------------------------------------------
def test_cli_table_json_and_exit_codes(capsys):
    assert pim_main(["sim", "ricsac9"]) == 0
    out = capsys.readouterr().out
    assert "vehicle 1 yaw rate" in out and "wall time" in out and "rel error" in out
    assert pim_main(["sim", "ricsac9", "--beta", "0.5", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["beta"] == 0.5 and data["error"] < TOL
    assert {r["key"] for r in data["rows"]} >= {"velocity1_x", "yaw_rate2", "impulse_x"}
    assert pim_main(["sim", "ricsac9", "--start", "detected", "--dt", "0.05"]) == 1
    assert "no_contact" in capsys.readouterr().err
    assert pim_main(["sim", "ricsac9", "--eps", "1.5"]) == 2
    assert pim_main(["sim", "ricsac9", "--iterations", "0"]) == 2


def test_simulate_names_the_argument_given_a_string():
    """Issue 28: sim.simulate(case, settings='fast') and sim.simulate_many([case, 'x'])
    failed deep inside with an AttributeError."""
    case = pim.load_case("ricsac9")
    with pytest.raises(TypeError, match=r"^settings must be a sim.Settings \(e.g. "
                                        r"sim.Settings\(dt=1e-4\)\) or None, got 'fast'$"):
        sim.simulate(case, settings="fast")
    with pytest.raises(TypeError, match=r"^cases\[1\] must be a pim.Case .*got 'x'$"):
        sim.simulate_many([case, "x"])
    with pytest.raises(TypeError, match=r"^settings must be a sim.Settings or None"):
        sim.simulate_many([case], settings="fast")
