"""The former per-assumption view of the ladder (``pim baseline --with assumptions``)."""

import math
from types import SimpleNamespace

import pim
from comparisons.studies.assumption_legacy import LEGACY_KEYS, legacy_sweeps, outcome_errors
from comparisons.studies.assumptions import ConfigRun, Ladder, Rung


def test_errors_are_measured_against_the_simulated_delta_v():
    case = pim.load_case("ricsac9")
    result = pim.solve(case, 0.3, 0.0)
    errors, yaw = outcome_errors(case, result, result.velocity1, result.velocity2,
                                 result.yaw_rate1, result.yaw_rate2)
    assert max(errors.values()) == 0.0 and yaw == (0.0, 0.0)


def test_each_legacy_rung_reads_its_rung_of_the_typical_ladder():
    # a ladder whose every "scene" is PIM itself: PIM's errors against each are zero
    case = pim.load_case("ricsac9")
    run = ConfigRun.of_pim(case, pim.solve(case, 0.3, 1.0))
    rungs = tuple(Rung(key, None, run, 0.0, 0.0) for key in
                  ("pim", "law", "duration", "outline", "tyres", "tyres_locked", "friction"))
    study = SimpleNamespace(case=case, eps=0.3, beta_pim=1.0, typical=Ladder(0.1, rungs))
    legacy = {s.key: s.typical for s in legacy_sweeps(study)}
    assert set(legacy) == set(LEGACY_KEYS.values())
    for outcome in legacy.values():
        assert max(outcome.errors.values()) == 0.0 and outcome.value == 0.1
        assert outcome.point_distance == 0.0 and math.isnan(outcome.eps_eff)
