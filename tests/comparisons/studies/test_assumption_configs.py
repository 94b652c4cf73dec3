"""The ladder's configurations: each rung changes one assumption against its baseline, the
input C is never a rung, the unmeasured parameters are ranges."""

from dataclasses import replace

import pytest

from comparisons.studies import assumption_configs as C

KEYS = ["pim", "law", "duration", "centroid", "outline", "tyres", "tyres_locked", "friction"]
RUNG_KEYS = ["law", "duration", "outline", "tyres", "tyres_locked", "friction"]


@pytest.mark.parametrize("has_outline", [True, False])
def test_the_ladder_holds_every_rung_and_the_centroid_input(has_outline):
    configs = C.ladder_configs(0.05, has_outline)
    assert list(configs) == (KEYS if has_outline else
                             [k for k in KEYS if k not in ("centroid", "outline")])
    assert set(C.RUNGS) == set(RUNG_KEYS)
    assert "centroid" not in C.RUNGS and "point" not in C.RUNGS


@pytest.mark.parametrize("has_outline", [True, False])
@pytest.mark.parametrize("key", RUNG_KEYS)
def test_each_rung_changes_only_its_assumption_against_its_baseline(key, has_outline):
    configs = C.ladder_configs(0.075, has_outline)
    if key not in configs:
        pytest.skip("no outline rung without outlines")
    config, base = configs[key], configs[C.baseline_of(key, has_outline)]
    assert C.changed_assumptions(config, base) == {C.RUNGS[key].assumption}
    assert C.changed_inputs(config, base) == set()          # never the input C with it
    if key != "duration":                                    # the same contact time
        assert config.duration == base.duration


def test_the_one_assumption_check_can_fail():
    configs = C.ladder_configs(0.05, True)
    # tyres added together with a longer contact: two assumptions, and the check says so
    both = replace(configs["tyres"], duration=0.1)
    assert C.changed_assumptions(both, configs["outline"]) == {"tyres", "duration"}
    # the outline rung against the scene at C would move the input C with it
    assert C.changed_inputs(configs["outline"], configs["duration"]) == {"point"}
    assert C.changed_assumptions(configs["outline"], configs["duration"]) == {"outline"}


def test_where_c_is_an_input_not_an_assumption():
    configs = C.ladder_configs(0.1, True)
    shift = C.changed_inputs(configs["centroid"], configs["duration"])
    assert shift == {"point"} and C.changed_assumptions(configs["centroid"],
                                                        configs["duration"]) == set()
    assert "point" in C.INPUT_FIELDS
    assert not any("point" in names for names in C.ASSUMPTION_FIELDS.values())


def test_tyres_rolling_and_locked_are_both_rungs():
    configs = C.ladder_configs(0.1, True)
    assert configs["tyres"].tyre_mode == "rolling"
    assert configs["tyres_locked"].tyre_mode == "locked"
    assert configs["tyres"].tyre_friction == configs["tyres_locked"].tyre_friction > 0
    assert "rolling" in C.RUNGS["tyres"].title and "locked" in C.RUNGS["tyres_locked"].title


def test_contact_time_and_recovery_are_ranges():
    assert C.CONTACT_RANGE == (0.05, 0.15)
    assert min(C.RANGE_DURATIONS) == 0.05 and max(C.RANGE_DURATIONS) == 0.15
    assert C.TYPICAL["duration"] in C.RANGE_DURATIONS
    rs = C.recoveries(0.3)
    assert rs[0] == 0.0 and rs[-1] == 1.0 and 0.09 == pytest.approx(rs[1])
    full, summary = C.plan(0.3, True), C.plan(0.3, False)
    assert set(full.range_durations) <= set(full.durations)
    assert summary.range_durations == summary.durations == C.RANGE_DURATIONS


def test_the_plan_simulates_the_friction_rung_over_r_in_the_range():
    p = C.plan(0.3, False)
    configs = p.configs(set(p.durations))
    friction = [c for c in configs if c.friction == "coulomb"]
    assert {c.duration for c in friction} == set(p.range_durations)
    assert {p.recovery(r) for r in p.recoveries} == {c.recovery for c in friction}
    assert None in {c.recovery for c in friction}            # eps^2: the ladder's own rung
    assert len(configs) == len(set(configs))                 # each simulated once
