"""sim/kudlich_slibar.py: the Kudlich-Slibar impact played in pymunk (issue 18, item 1).

Compression by the rigid engine (restitution 0, Coulomb coefficient mu_c), restitution k
times the impulse the engine measured: physical inputs only. It must agree with
pim.model.impact_laws.solve_kudlich_slibar to round-off wherever the engine converges.
"""

import json

import numpy as np
import pytest

import pim
import sim
from pim.model.impact_laws import solve_kudlich_slibar
from pim_cli.main import main
from sim.kudlich_slibar import crosscheck_kudlich_slibar, simulate_kudlich_slibar
from tests.scenes import TWO_CARS_TOML, random_cases


def relative_error(run, r):
    scale = max(float(np.abs(np.r_[r.delta_v1, r.delta_v2]).max()), 1e-12)
    gyration = float(np.sqrt(r.case.vehicle1.yaw_inertia / r.case.vehicle1.mass))
    errors = [np.abs(run.velocity1 - r.velocity1).max(), np.abs(run.velocity2 - r.velocity2).max(),
              gyration * abs(run.yaw_rate1 - float(r.yaw_rate1))]
    return max(errors) / scale


@pytest.mark.parametrize("name", ["ricsac9", "hard-spinning", "hard-barrier", "hard-gamma37",
                                  "hard-car-truck", "hard-grazing"])
@pytest.mark.parametrize("k,mu_c", [(0.1, 0.6), (0.3, 0.2), (0.0, 5.0), (1.0, 0.05)])
def test_two_phase_engine_run_equals_the_law_to_round_off(name, k, mu_c):
    case = pim.load_case(name)
    run = simulate_kudlich_slibar(case, k, mu_c)
    r = solve_kudlich_slibar(case, k, mu_c)
    assert relative_error(run, r) < 1e-7
    np.testing.assert_allclose(run.impulse, (1 + k) * run.compression_impulse)


def test_sticking_engine_run_ends_at_minus_k_times_the_approach():
    case = pim.load_case("ricsac9")
    run = simulate_kudlich_slibar(case, 0.4, 10.0)
    r = solve_kudlich_slibar(case, 0.4, 10.0)     # for the arms and the approach only
    u1 = run.velocity1 + run.yaw_rate1 * np.array([-r.arm1[1], r.arm1[0]])
    u2 = run.velocity2 + run.yaw_rate2 * np.array([-r.arm2[1], r.arm2[0]])
    np.testing.assert_allclose(u1 - u2, -0.4 * np.asarray(r.approach_velocity), atol=1e-9)


def test_random_scenes_agree_or_name_the_engines_limit():
    cases = random_cases(30, seed=11)
    agreed = 0
    for i in range(30):
        v1, v2, imp = cases.vehicle1, cases.vehicle2, cases.impact
        case = pim.Case(pim.Vehicle(v1.mass[i], v1.yaw_inertia[i], v1.cg[i], v1.velocity[i],
                                    v1.yaw_rate[i]),
                        pim.Vehicle(v2.mass[i], v2.yaw_inertia[i], v2.cg[i], v2.velocity[i],
                                    v2.yaw_rate[i]),
                        pim.Impact(imp.point[i], imp.normal_angle[i]))
        r = solve_kudlich_slibar(case, 0.2, 0.5)
        if not bool(r.approaching) or float(r.impulse_n) <= 0:
            continue
        try:
            run = simulate_kudlich_slibar(case, 0.2, 0.5)
        except sim.SimulationError as exc:
            assert exc.kind == "not_converged"      # Chipmunk's named limit, never silent
            continue
        assert relative_error(run, r) < 1e-7
        agreed += 1
    assert agreed >= 10


@pytest.mark.parametrize("k,mu_c,message", [(1.5, 0.5, "restitution k"),
                                            (0.5, -1.0, "contact_friction mu_c"),
                                            (0.5, np.inf, "finite for the simulator")])
def test_bad_parameters_name_the_field(k, mu_c, message):
    with pytest.raises(ValueError, match=message):
        simulate_kudlich_slibar(pim.load_case("ricsac9"), k, mu_c)


CASE = TWO_CARS_TOML + """
[impact]
point = [0, 0]
normal_angle = "0 deg"
law = "{law}"
restitution = 0.2
contact_friction = 0.4
"""


def test_sim_command_cross_checks_the_case_law(tmp_path, capsys):
    path = tmp_path / "ks.toml"
    path.write_text(CASE.format(law="kudlich-slibar"))
    assert main(["sim", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["law"] == "kudlich-slibar" and out["error"] < 1e-9
    check = crosscheck_kudlich_slibar(pim.load_case(path))
    assert check.k == 0.2 and check.mu_c == 0.4 and check.error < 1e-9
    assert main(["sim", str(path), "--eps", "0.3"]) == 2
    assert "--eps and --beta do not apply" in capsys.readouterr().err


def test_sim_command_runs_the_capped_law_at_its_effective_beta(tmp_path, capsys):
    path = tmp_path / "capped.toml"
    path.write_text(CASE.format(law="brach-capped"))
    assert main(["sim", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    capped = pim.solve(pim.load_case(path))
    assert out["beta"] == pytest.approx(float(capped.beta)) and out["error"] < 1e-9


@pytest.mark.parametrize("name,k,mu_c", [("ricsac9", 0.1, 0.6), ("hard-gamma37", 0.3, 0.2),
                                         ("hard-barrier", 0.0, 5.0)])
def test_recorded_trajectory_carries_the_two_phase_state_through_free_motion(name, k, mu_c):
    """The recorded state at t = 0 is the state after both phases (the cross-check's), at
    the impact configuration; afterwards the vehicles move freely with it."""
    case = pim.load_case(name)
    check = simulate_kudlich_slibar(case, k, mu_c)
    run = simulate_kudlich_slibar(case, k, mu_c, sim.Settings(record=True, duration=0.5))
    tr = run.trajectory
    i = tr.impact_index
    assert tr.time[i] == 0.0 and tr.time[-1] == pytest.approx(0.5)
    for j, v in ((1, case.vehicle1), (2, case.vehicle2)):
        vel, w = getattr(run, f"velocity{j}"), getattr(run, f"yaw_rate{j}")
        np.testing.assert_array_equal(vel, getattr(check, f"velocity{j}"))
        np.testing.assert_array_equal(getattr(tr, f"velocity{j}")[i], vel)
        np.testing.assert_array_equal(getattr(tr, f"yaw_rate{j}")[i], w)
        np.testing.assert_allclose(getattr(tr, f"position{j}")[i], v.cg, atol=1e-12)
        # free motion: the final position is the impact configuration plus velocity x time
        expected = np.asarray(v.cg) + (0 if v.fixed else 1) * vel * tr.time[-1]
        np.testing.assert_allclose(getattr(tr, f"position{j}")[-1], expected, atol=1e-9)
    r = solve_kudlich_slibar(case, k, mu_c)
    assert relative_error(run, r) < 1e-7
