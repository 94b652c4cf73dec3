"""`pim assumptions`: the ladder of scenes, one assumption per rung, effects, verdicts, files."""

import math
import re
from dataclasses import replace

import numpy as np
import pytest

import pim
import sim
from comparisons.studies import assumptions as A
from comparisons.report.assumptions import write_assumptions
from pim_cli.main import main
from sim.error_measure import impact_error

COARSE = sim.CompliantSettings(steps_per_contact=100)     # first order: about 1 % per rung
KEYS = ["pim", "law", "duration", "point", "outline", "tyres", "friction"]


@pytest.fixture(scope="module")
def summary():
    case = pim.load_case("ricsac9")
    return A.run_assumptions(case, executor="serial", progress=False, animation_after=None,
                             sweeps=False, settings=COARSE)


@pytest.fixture(scope="module")
def frictionless():
    case = pim.load_case("ricsac9")
    return A.run_assumptions(case, beta=0.0, executor="serial", progress=False,
                             animation_after=None, sweeps=False, settings=COARSE)


def check_one_assumption_per_rung(ladder):
    scenes = {r.key: r.scene for r in ladder.rungs}
    for rung in ladder.rungs[1:]:
        changed = A.changed_assumptions(rung.scene, scenes[rung.baseline])
        assert changed == {rung.key}, (rung.key, changed)
        if rung.key != "duration":          # marginal effects at the same contact time
            assert rung.scene.duration == scenes[rung.baseline].duration


@pytest.mark.parametrize("has_outline", [True, False])
def test_each_rung_differs_from_the_one_below_in_exactly_one_assumption(has_outline):
    scenes = A.ladder_scenes(0.05, has_outline)
    keys = list(scenes)
    assert keys == (KEYS if has_outline else [k for k in KEYS if k not in ("point",
                                                                           "outline")])
    for below, key in zip(keys, keys[1:], strict=False):
        assert A.changed_assumptions(scenes[key], scenes[below]) == {key}


def test_the_one_assumption_check_can_fail():
    scenes = A.ladder_scenes(0.05, True)
    # tyres added together with a longer contact: two assumptions, and the check says so
    both = replace(scenes["tyres"], duration=0.1)
    assert A.changed_assumptions(both, scenes["outline"]) == {"tyres", "duration"}
    bad = A.Ladder(0.05, (A.Rung("pim", None, A.SceneRun.failed(scenes["pim"], ""), 0, 0),
                          A.Rung("law", "pim", A.SceneRun.failed(
                              replace(scenes["law"], tyre_friction=0.7), ""), 0, 0)))
    with pytest.raises(AssertionError):
        check_one_assumption_per_rung(bad)


def test_the_study_ladder_changes_one_assumption_per_rung(summary):
    assert [r.key for r in summary.typical.rungs] == KEYS
    for ladder in summary.ladders:
        check_one_assumption_per_rung(ladder)
    assert all(r.run.failure is None for r in summary.typical.rungs)
    assert summary.beta_pim == 1.0 and summary.eps == pytest.approx(0.3548, abs=1e-3)


def test_effects_are_the_project_error_against_the_rung_below_and_against_pim(summary):
    case = summary.case
    rungs = {r.key: r for r in summary.typical.rungs}
    pim_result = pim.solve(case, summary.eps, summary.beta_pim)
    for key in KEYS[1:]:
        run, below = rungs[key].run, rungs[rungs[key].baseline].run
        args = (run.velocity1, run.velocity2, run.yaw_rate1, run.yaw_rate2)
        assert rungs[key].cumulative == pytest.approx(
            float(impact_error(case, pim_result, *args)), rel=1e-12)
        assert rungs[key].marginal == pytest.approx(
            float(impact_error(case, below, *args)), rel=1e-12)
    assert rungs["law"].marginal == rungs["law"].cumulative


def test_stiff_limit_of_the_frictionless_crush_law_is_pim(frictionless):
    law = frictionless.typical.rung("law")
    assert frictionless.beta_pim == 0.0
    assert law.scene.duration is None and law.run.contact_duration < 3e-3
    assert law.marginal < 0.01          # first order in the 2 ms contact time
    # the finite duration matters far more than that at 100 ms
    assert frictionless.typical.rung("duration").marginal > 10 * law.marginal


def test_outline_rung_separates_where_the_impulse_acts_from_distribution(summary):
    point, outline = summary.typical.rung("point"), summary.typical.rung("outline")
    assert point.scene.point == "centroid" and not point.scene.distributed
    assert outline.scene.distributed
    assert summary.centroid_distance > 0.01
    assert math.isfinite(point.marginal) and math.isfinite(outline.marginal)
    # both start where the outlines first touch (RICSAC 9: 71 ms before PIM's instant): the
    # point scene there, on the outlines' line of impulse, and the outline scene
    assert outline.run.contact_start == pytest.approx(-0.0708, abs=1e-3)
    assert point.run.contact_start == 0.0 and point.run.failure is None


def test_verdicts_name_their_assumption_and_state_both_effects(summary):
    words = {"law": "Newton's restitution", "duration": "instantaneous impulse",
             "point": "PIM's impact configuration", "outline": "One contact point",
             "tyres": "No external forces", "friction": "tangential law"}
    texts = summary.verdicts()
    assert len(texts) == len(KEYS) - 1
    for rung, text in zip(summary.typical.rungs[1:], texts, strict=True):
        assert text.startswith(words[rung.key]) or words[rung.key] in text
        assert f"{100 * rung.marginal:.1f} %" in text
        assert f"{100 * rung.cumulative:.1f} %" in text
        assert text.endswith(".") and text.count(". ") == 0
    assert "tangential recovery" in texts[-1]
    assert sorted({r for _, r, _, _ in summary.recovery_map}) == pytest.approx(
        [0.0, summary.eps ** 2, 1.0])


def test_typical_values_are_written_once(monkeypatch):
    # the typical contact time picks the verdicts' ladder: change it and the study follows
    monkeypatch.setitem(A.TYPICAL, "duration", 0.02)
    case = pim.load_case("hard-barrier")
    study = A.run_assumptions(case, 0.3, 0.0, executor="serial", progress=False,
                              animation_after=None, sweeps=False, settings=COARSE)
    assert study.typical.duration == 0.02
    assert study.typical.rung("duration").scene.duration == 0.02
    assert "20 ms" in study.verdicts()[1]


def test_errors_are_measured_against_the_simulated_delta_v():
    case = pim.load_case("ricsac9")
    result = pim.solve(case, 0.3, 0.0)
    errors, yaw = A.outcome_errors(case, result, result.velocity1, result.velocity2,
                                   result.yaw_rate1, result.yaw_rate2)
    assert max(errors.values()) == 0.0 and yaw == (0.0, 0.0)


def test_nearly_instantaneous_frictionless_scene_fits_back_to_eps_and_beta0():
    case = pim.load_case("hard-barrier")
    problem = sim.compliant_setup.build_problem(case, 0.3, sim.DEFAULT_STIFFNESS)
    k = float(sim.contact_law.stiffness_for_duration(0.002, problem.k_nn, 0.3))
    r = sim.simulate_compliant(case, 0.3, k)
    measured = pim.Measured(r.velocity1, None, r.yaw_rate1, None)
    fitted = pim.fit(replace(case, measured=measured), include_yaw=True)
    assert fitted.eps == pytest.approx(0.3, abs=0.02)
    assert fitted.beta < 0.05


def test_table_and_verdicts_speak_the_case_units(summary):
    assert summary.case.units == "us"                    # ricsac9.toml is written in US units
    assert "C_eff x [ft]" in A.assumption_table(summary).columns
    assert "C_eff x [m]" in A.assumption_table(summary, units="si").columns
    assert f"{summary.centroid_distance / 0.3048:.2f} ft from C" in summary.verdicts()[2]


def test_tables_and_plots(summary, tmp_path):
    table = A.assumption_table(summary)
    assert len(table.rows) == len(KEYS) - 1
    assert "marginal effect [-]" in table.columns and "cumulative (PIM's error) [-]" in \
        table.columns
    assert all(math.isfinite(v) for v in table.column("beta_eff [-]"))
    every = A.sweep_table(summary)
    assert len(every.rows) >= len(table.rows) + 3
    files = write_assumptions(summary, tmp_path, animation=False)
    text = (tmp_path / "assumptions.md").read_text()
    assert "## Verdicts" in text and "marginal" in text and "cumulative" in text
    assert {f.name for f in files} >= {"assumptions.md", "assumptions.csv", "assumptions.png",
                                       "assumption_sweeps.csv", "assumptions.html"}
    page = (tmp_path / "assumptions.html").read_text()
    assert len(re.findall(r'<table id="table-assumptions-\d"', page)) == 4   # split
    pngs = [f for f in files if f.suffix == ".png"]
    assert page.count("data:image/png;base64,") == len(pngs) and "<video" not in page


def test_cli_bad_eps_is_one_line_and_exit_code_2(tmp_path, capsys):
    assert main(["assumptions", "ricsac9", "--eps", "-1", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "eps" in err and "Traceback" not in err and err.count("\n") == 1


@pytest.mark.slow
def test_cli_writes_the_whole_study(tmp_path):
    assert main(["assumptions", "ricsac9", "--out", str(tmp_path), "--no-progress"]) == 0
    assert (tmp_path / "assumptions.mp4").stat().st_size > 10_000
    study_csv = (tmp_path / "assumption_sweeps.csv").read_text()
    assert "tyre effect" in study_csv and "friction effect" in study_csv
    assert np.isfinite(1.0)


@pytest.mark.slow
def test_cli_json_lists_every_ladder(tmp_path, capsys):
    import json
    assert main(["assumptions", "ricsac9", "--out", str(tmp_path), "--no-progress",
                 "--no-animation", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [lad["contact_time_ms"] for lad in data["ladders"]] == [10, 25, 50, 100, 200]
    assert [r["key"] for r in data["ladders"][0]["rungs"]] == KEYS[1:]


def test_legacy_view_for_the_baseline_sections(summary):
    # comparisons.regression.sections (pim baseline --with assumptions) reads study.sweeps
    legacy = {s.key: s.typical for s in summary.sweeps}
    assert set(legacy) == set(A.LEGACY_KEYS.values())
    o = legacy["instantaneous"]
    assert set(o.errors) == {"delta_v1", "delta_v2", "speed1", "speed2", "yaw1", "yaw2"}
    assert o.failure is None and math.isfinite(o.fit_rms) and o.point_distance > 0
    run = summary.typical.rung("duration").run
    errors, _ = A.outcome_errors(summary.case, pim.solve(summary.case, summary.eps, 1.0),
                                 run.velocity1, run.velocity2, run.yaw_rate1, run.yaw_rate2)
    assert o.errors == errors


def test_a_failed_outline_scene_leaves_the_point_ladder_and_says_why():
    # hard-pole: the pole's outline is crossed by the car's (tunnelled); the ladder goes on
    # without the outline rungs, tyres and friction on the point contact at C
    study = A.run_assumptions(pim.load_case("hard-pole"), executor="serial", progress=False,
                              animation_after=None, sweeps=False, settings=COARSE)
    assert [r.key for r in study.typical.rungs] == ["pim", "law", "duration", "tyres",
                                                    "friction"]
    check_one_assumption_per_rung(study.typical)
    assert "not assessed (the outline scene failed: tunnelled" in study.verdicts()[2]
    assert all(r.run.failure is None for r in study.typical.rungs)
