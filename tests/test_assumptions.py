"""`pim assumptions`: the study's scenes, errors, effective coefficients, verdicts, files."""

import math
import re
from dataclasses import replace

import numpy as np
import pytest

import pim
import sim
from comparisons import assumptions as A
from pim.cli import main


@pytest.fixture(scope="module")
def summary():
    case = pim.load_case("ricsac9")
    return A.run_assumptions(case, executor="serial", progress=False, animation_after=None,
                             sweeps=False)


def test_summary_has_every_assumption_at_its_typical_value(summary):
    keys = [s.key for s in summary.sweeps]
    assert keys == list(A.ASSUMPTIONS)
    assert summary.eps == pytest.approx(0.3548, abs=1e-3)          # the case's fit
    by = {s.key: s.typical for s in summary.sweeps}
    assert by["instantaneous"].value == 100.0
    assert by["no_external_forces"].value == pytest.approx(0.7)
    assert all(o.failure is None for o in by.values())


def test_verdicts_are_one_sentence_each_and_consistent_with_the_errors(summary):
    for s in summary.sweeps:
        text = s.verdict()
        name, worst = s.typical.worst
        assert text.endswith(".") and text.count(". ") == 0
        if worst < A.HOLDS:
            assert "holds within 5 %" in text
        elif worst >= A.ROUGHLY:
            assert "does not hold" in text
        assert f"{100 * worst:.1f} %" in text


def test_tyres_add_to_the_error_and_outline_moves_the_impact_point(summary):
    inst = summary.sweep("instantaneous").typical
    tyres = summary.sweep("no_external_forces").typical
    assert tyres.energy_loss > inst.energy_loss
    one = summary.sweep("one_point").typical
    assert one.point_distance > 0.01                  # the impulse centroid is not C


def test_errors_are_measured_against_the_simulated_delta_v():
    case = pim.load_case("ricsac9")
    result = pim.solve(case, 0.3, 0.0)
    errors, yaw = A.outcome_errors(case, result, result.velocity1, result.velocity2,
                                   result.yaw_rate1, result.yaw_rate2)
    assert max(errors.values()) == 0.0 and yaw == (0.0, 0.0)
    v1 = np.asarray(result.velocity1) + np.array([0.1, 0.0])
    errors, _ = A.outcome_errors(case, result, v1, result.velocity2, result.yaw_rate1,
                                 result.yaw_rate2)
    dv = np.hypot(*(v1 - case.vehicle1.velocity))
    assert errors["speed1"] == pytest.approx(
        abs(np.hypot(*result.velocity1) - np.hypot(*v1)) / dv, rel=1e-12)


def test_nearly_instantaneous_frictionless_scene_fits_back_to_eps_and_beta0():
    # 5 ms, no friction: the effective coefficients are the physical eps and beta = 0
    case = pim.load_case("hard-barrier")
    problem = sim.compliant_setup.build_problem(case, 0.3, sim.DEFAULT_STIFFNESS)
    k = float(sim.contact_law.stiffness_for_duration(0.002, problem.k_nn, 0.3))
    r = sim.simulate_compliant(case, 0.3, k)
    measured = pim.Measured(r.velocity1, None, r.yaw_rate1, None)
    fitted = pim.fit(replace(case, measured=measured), include_yaw=True)
    assert fitted.eps == pytest.approx(0.3, abs=0.02)
    assert fitted.beta < 0.05


def test_tables_and_plots(summary, tmp_path):
    table = A.assumption_table(summary)
    assert len(table.rows) == 4 and "eps_eff [-]" in table.columns
    assert all(math.isfinite(v) for v in table.column("beta_eff [-]"))
    fig = A.plot_overview(summary)
    assert len([ax for ax in fig.axes if ax.get_visible()]) == 4
    files = A.write_assumptions(summary, tmp_path, animation=False)
    text = (tmp_path / "assumptions.md").read_text()
    assert "## Verdicts" in text and "eps_eff" in text
    assert {f.name for f in files} >= {"assumptions.md", "assumptions.csv", "assumptions.png",
                                       "assumptions.html"}
    page = (tmp_path / "assumptions.html").read_text()
    assert len(re.findall(r'<table id="table-assumptions-\d"', page)) == 4   # split
    assert page.count("data:image/png;base64,") == 5 and "<video" not in page


def test_cli_bad_eps_is_one_line_and_exit_code_2(tmp_path, capsys):
    assert main(["assumptions", "ricsac9", "--eps", "-1", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "eps" in err and "Traceback" not in err and err.count("\n") == 1


@pytest.mark.slow
def test_cli_writes_the_whole_study(tmp_path):
    assert main(["assumptions", "ricsac9", "--out", str(tmp_path), "--no-progress"]) == 0
    assert (tmp_path / "assumptions.mp4").stat().st_size > 10_000
    assert len(list(tmp_path.glob("assumption-*.png"))) == 4
