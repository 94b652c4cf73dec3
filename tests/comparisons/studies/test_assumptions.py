"""`pim assumptions`: the ladder's runs, effects against each rung's baseline and against
PIM, in % and in physical terms; where C is beside the ladder; the legacy view."""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import pim
import sim
from comparisons.studies import assumptions as A
from comparisons.studies.assumption_configs import (
    DURATIONS,
    RANGE_DURATIONS,
    RUNGS,
    changed_assumptions,
    changed_inputs,
    ladder_configs,
)
from comparisons.studies.assumption_legacy import LEGACY_KEYS, outcome_errors
from sim.error_measure import impact_error

COARSE = sim.CompliantSettings(steps_per_contact=100)     # first order: about 1 % per rung
KEYS = ["pim", "law", "duration", "outline", "tyres", "tyres_locked", "friction"]


@pytest.fixture(scope="module")
def summary():
    case = pim.load_case("ricsac9")
    return A.run_assumptions(case, executor="serial", progress=False, animation_after=None,
                             sweeps=False, settings=COARSE)


def check_ladder(ladder, has_outline=True):
    """Every rung changes its one assumption against its baseline, at the same contact
    time and the same input C."""
    configs = ladder_configs(ladder.duration, has_outline)
    for rung in ladder.rungs[1:]:
        base = configs[rung.baseline]
        assert changed_assumptions(rung.config, base) == {RUNGS[rung.key].assumption}
        assert changed_inputs(rung.config, base) == set()
        if rung.key != "duration":
            assert rung.config.duration == base.duration


def test_the_study_ladder_changes_one_assumption_per_rung(summary):
    assert [r.key for r in summary.typical.rungs] == KEYS
    for ladder in summary.ladders:
        check_ladder(ladder)
    assert all(r.run.failure is None for r in summary.typical.rungs)
    assert summary.beta_pim == 1.0 and summary.eps == pytest.approx(0.3548, abs=1e-3)
    assert [lad.duration for lad in summary.ladders] == list(RANGE_DURATIONS)


def _pim_at(case, eps, beta, config, probe):
    where = case if config.point == "C" else A.contact_case(case, probe)
    return where, pim.solve(where, eps, beta)


def test_effects_are_the_project_error_against_the_baseline_and_pim_at_its_c(summary):
    case, lad = summary.case, summary.typical
    configs = ladder_configs(lad.duration, True)
    probe = lad.rung("outline").run     # its centroid is near the probe's: any for C's frame
    runs = {r.key: r.run for r in lad.rungs}
    runs["centroid"] = lad.shift.at_centroid
    for rung in lad.rungs[1:]:
        run, below = rung.run, runs[rung.baseline]
        args = (run.velocity1, run.velocity2, run.yaw_rate1, run.yaw_rate2)
        assert rung.marginal == pytest.approx(float(impact_error(case, below, *args)),
                                              rel=1e-12)
        if rung.config.point == "C":
            ref = pim.solve(case, summary.eps, summary.beta_pim)
            assert rung.cumulative == pytest.approx(float(impact_error(case, ref, *args)),
                                                    rel=1e-12)
    assert configs["outline"].point == "centroid" and probe.failure is None
    assert lad.rung("law").marginal == lad.rung("law").cumulative


def test_physical_change_is_the_delta_v_and_yaw_rate_difference(summary):
    case = summary.case
    rung = summary.typical.rung("duration")
    below = summary.typical.rung("law").run
    c = rung.change
    assert c.delta_v1 == pytest.approx(np.hypot(*(rung.run.velocity1 - below.velocity1)))
    assert c.delta_v2 == pytest.approx(np.hypot(*(rung.run.velocity2 - below.velocity2)))
    assert c.yaw_rate1 == pytest.approx(abs(rung.run.yaw_rate1 - below.yaw_rate1))
    assert c.delta_v == max(c.delta_v1, c.delta_v2) > 0
    # delta-V differences: a 5 % error of a ~9 m/s impact is a fraction of a m/s
    assert 0.05 < c.delta_v < 3.0
    assert A.change(case, below, below).delta_v == 0.0


def test_where_c_is_beside_the_ladder_not_a_rung(summary):
    assert "point" not in {r.key for lad in summary.ladders for r in lad.rungs}
    shift = summary.input_shift
    assert shift is not None and 0.05 < shift.distance < 1.0        # [m] on vehicle 1
    assert math.isfinite(shift.pim_error) and shift.pim_error > 0
    for lad in summary.ladders:
        assert lad.shift is not None
        assert changed_inputs(lad.shift.at_centroid.config, lad.shift.at_c.config) == {"point"}
        assert changed_assumptions(lad.shift.at_centroid.config, lad.shift.at_c.config) == set()


def test_cumulative_above_the_outline_holds_no_input_shift(summary):
    # PIM is evaluated where the outlines' impulse acts: the outline rung's cumulative
    # effect is not the C shift (13 % on RICSAC 9) plus the assumptions
    lad = summary.typical
    outline = lad.rung("outline")
    at_c = float(impact_error(summary.case, pim.solve(summary.case, summary.eps, 1.0),
                              outline.run.velocity1, outline.run.velocity2,
                              outline.run.yaw_rate1, outline.run.yaw_rate2))
    assert outline.cumulative != pytest.approx(at_c, rel=1e-3)


def test_ranges_over_contact_time_and_recovery(summary):
    er = summary.over_range("duration")
    assert er.settings == ("50 ms", "75 ms", "100 ms", "125 ms", "150 ms")
    lo, hi = er.extremes("marginal")
    assert lo < hi                         # the duration effect grows with the contact time
    assert er.setting_of("marginal") == "150 ms"
    fr = summary.friction_over()
    assert len(fr.settings) == 5 * 4                     # 5 contact times x 4 recoveries
    assert {s.split(", r ")[1] for s in fr.settings} == {"0", "0.126", "0.5", "1"}


def test_tyres_rolling_and_locked_are_both_measured(summary):
    rolling, locked = summary.typical.rung("tyres"), summary.typical.rung("tyres_locked")
    assert rolling.config.tyre_mode == "rolling" and locked.config.tyre_mode == "locked"
    assert rolling.baseline == locked.baseline == "outline"
    assert locked.marginal != pytest.approx(rolling.marginal, rel=0.05)
    assert {mode for mode, _ in summary.tyre_curves} == {"rolling", "locked"}


def test_stiff_limit_of_the_frictionless_crush_law_is_pim():
    study = A.run_assumptions(pim.load_case("ricsac9"), beta=0.0, executor="serial",
                              progress=False, animation_after=None, sweeps=False,
                              settings=COARSE)
    law = study.typical.rung("law")
    assert study.beta_pim == 0.0
    assert law.config.duration is None and law.run.contact_duration < 3e-3
    assert law.marginal < 0.01          # first order in the 2 ms contact time
    # the finite duration matters far more than that at 100 ms
    assert study.typical.rung("duration").marginal > 10 * law.marginal


def test_outline_rung_starts_where_the_outlines_touch(summary):
    outline = summary.typical.rung("outline")
    assert outline.config.distributed and outline.baseline == "centroid"
    # RICSAC 9: the outlines first touch 71 ms before PIM's instant; the point scene at
    # the centroid is placed there
    assert outline.run.contact_start == pytest.approx(-0.0708, abs=1e-3)
    assert summary.typical.shift.at_centroid.contact_start == 0.0


def test_typical_values_are_written_once(monkeypatch):
    # the typical contact time picks the table's ladder: change it and the study follows
    monkeypatch.setitem(A.TYPICAL, "duration", 0.05)
    study = A.run_assumptions(pim.load_case("hard-barrier"), 0.3, 0.0, executor="serial",
                              progress=False, animation_after=None, sweeps=False,
                              settings=COARSE)
    assert study.typical.duration == 0.05
    assert study.typical.rung("duration").config.duration == 0.05


def test_nearly_instantaneous_frictionless_scene_fits_back_to_eps_and_beta0():
    case = pim.load_case("hard-barrier")
    problem = sim.compliant_setup.build_problem(case, 0.3, sim.DEFAULT_STIFFNESS)
    k = float(sim.contact_law.stiffness_for_duration(0.002, problem.k_nn, 0.3))
    r = sim.simulate_compliant(case, 0.3, k, engine="pymunk")
    measured = pim.Measured(r.velocity1, None, r.yaw_rate1, None)
    fitted = pim.fit(replace(case, measured=measured), include_yaw=True)
    assert fitted.eps == pytest.approx(0.3, abs=0.02)
    assert fitted.beta < 0.05


def test_legacy_view_for_the_baseline_sections(summary):
    # comparisons.regression.sections (pim baseline --with assumptions) reads study.sweeps
    legacy = {s.key: s.typical for s in summary.sweeps}
    assert set(legacy) == set(LEGACY_KEYS.values())
    o = legacy["instantaneous"]
    assert set(o.errors) == {"delta_v1", "delta_v2", "speed1", "speed2", "yaw1", "yaw2"}
    assert o.failure is None and math.isfinite(o.fit_rms) and o.point_distance > 0
    run = summary.typical.rung("duration").run
    errors, _ = outcome_errors(summary.case, pim.solve(summary.case, summary.eps, 1.0),
                               run.velocity1, run.velocity2, run.yaw_rate1, run.yaw_rate2)
    assert o.errors == errors


def test_a_failed_outline_scene_leaves_the_point_ladder_and_says_why():
    # hard-pole: the pole's outline is crossed by the car's (tunnelled) in the longer
    # contacts; the ladder there goes on without the outline rung, tyres and friction on
    # the point contact at C
    study = A.run_assumptions(pim.load_case("hard-pole"), executor="serial", progress=False,
                              animation_after=None, sweeps=False, settings=COARSE)
    assert [r.key for r in study.typical.rungs] == ["pim", "law", "duration", "tyres",
                                                    "tyres_locked", "friction"]
    check_ladder(study.typical, has_outline=False)
    assert study.outline_note.startswith("the outline scene failed at ")
    assert "100" in study.outline_note and "tunnelled" in study.outline_note
    assert study.typical.shift is None
    assert all(r.run.failure is None for r in study.typical.rungs)


@pytest.mark.parametrize("beta_pim", [0.0, 1.0])
def test_the_compiled_and_the_pymunk_scene_agree_on_every_point_configuration(beta_pim):
    """The ladder's point contacts run compiled in batches (grouped by case and tangential
    stiffness); pymunk, the cross-check, steps them alike: the same motion to round-off."""
    case = pim.load_case("ricsac9")
    context = A.Context(case, 0.355, beta_pim, replace(COARSE, record=False, duration=0.0))
    configs = [c for d in (0.05, 0.1) for k, c in ladder_configs(d, False).items()
               if k != "pim"]
    configs += [replace(configs[-1], mu_c=1.0, recovery=r) for r in (0.0, 1.0)]
    compiled = A.run_configs(context, configs, {}, engine="numba")
    pymunk = A.run_configs(context, configs, {}, engine="pymunk", executor="serial")
    scale = float(np.hypot(*case.vehicle1.velocity))
    for c in configs:
        a, b = compiled[c], pymunk[c]
        assert a.failure is None and b.failure is None
        for x, y in ((a.velocity1, b.velocity1), (a.velocity2, b.velocity2)):
            assert np.max(np.abs(x - y)) < 1e-12 * scale, c
        assert abs(a.yaw_rate1 - b.yaw_rate1) < 1e-12 and a.stick_fraction == b.stick_fraction


def test_the_ladder_starts_from_the_cases_own_beta():
    """Issue 33 point 8: PIM is compared at the case's beta (here 0.4), not the nearer of 0
    and 1, and the "law" rung emulates it: a stiff friction spring sliding at beta |mu0|,
    which at a nearly instantaneous contact is PIM at that beta."""
    case = pim.load_case("ricsac9")
    study = A.run_assumptions(case, 0.355, 0.4, executor="serial", progress=False,
                              animation_after=None, sweeps=False, settings=COARSE)
    assert study.beta == study.beta_pim == 0.4
    pim_rung = study.typical.rung("pim").run
    expected = pim.solve(case, 0.355, 0.4)
    assert pim_rung.velocity1 == pytest.approx(np.asarray(expected.velocity1), abs=1e-12)
    mu0 = abs(float(expected.mu0))
    context = A.Context(case, 0.355, 0.4, COARSE)
    law = study.typical.rung("law")
    assert A.simulation_inputs(context, law.config, None).friction == pytest.approx(0.4 * mu0)
    assert law.marginal < 0.02                # the emulation is PIM's law at beta 0.4
    assert law.beta_eff == pytest.approx(0.4, abs=0.03)


def test_a_failure_beyond_the_verdicts_range_is_not_named_beside_it():
    assert A.outline_note({0.2: "tunnelled: x"}, True) == ""
    note = A.outline_note({0.1: "tunnelled: a", 0.2: "tunnelled: b"}, True)
    assert "100" in note and "200" not in note and note.endswith("tunnelled: a")


def test_no_rung_of_a_sideswipe_passes_through_an_outline_at_any_swept_contact_time():
    """Issue 33 point 8: on an opposite-direction sideswipe (beta 0.18) the ladder run at
    beta 0 -- the nearer of 0 and 1 -- had the frictionless outlines slide through each
    other at the longer contacts; at the case's own beta every rung, the outline rung
    among them, holds at every contact time of the sweep."""
    case = pim.load_case(str(Path(__file__).resolve().parents[2] / "data"
                             / "sideswipe-ladder.toml"))
    study = A.run_assumptions(case, executor="serial", progress=False, animation_after=None,
                              sweeps=True, settings=COARSE)
    assert study.beta_pim == pytest.approx(0.18)
    assert [lad.duration for lad in study.ladders] == list(DURATIONS)
    for ladder in study.ladders:
        assert [r.key for r in ladder.rungs] == KEYS, ladder.duration
        for rung in ladder.rungs:
            assert rung.run.failure is None, (ladder.duration, rung.key, rung.run.failure)
    assert study.outline_note == ""
