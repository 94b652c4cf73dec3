"""The verdict rule on constructed paired errors (comparisons.studies.paired_verdict): each
of the four verdicts, the small-class rule, failures, and the statistics against scipy."""

import math

import numpy as np
import pytest
from scipy.stats import wilcoxon

from comparisons.studies.paired_verdict import (
    NO_DIFFERENCE,
    PIM_BETTER,
    SCENE_BETTER,
    TOO_FEW,
    bootstrap_median,
    compare_paired,
    decide,
    minimum_tests,
)

PIM = np.array([1.0, 1.2, 0.8, 1.5, 0.9, 1.1, 1.3, 0.7])


def test_decide_is_the_rule():
    assert minimum_tests(4) == 6
    assert decide(5, 4, 0.001, True) == TOO_FEW            # fewer than parameters + 2
    assert decide(6, 4, None, True) == TOO_FEW
    assert decide(6, 4, 0.01, True) == SCENE_BETTER
    assert decide(6, 4, 0.01, False) == PIM_BETTER
    assert decide(6, 4, 0.05, False) == NO_DIFFERENCE.format(p="0.05")   # p < alpha only
    assert decide(40, 4, 0.6712, True) == "no significant difference (p = 0.67)"


def test_pim_predicts_better():
    c = compare_paired(PIM, PIM + 0.5, 4)
    assert c.verdict == PIM_BETTER and c.p_value == pytest.approx(2 / 2**8)
    assert c.median_difference == pytest.approx(0.5) and not c.scene_better
    assert c.interval[0] <= 0.5 <= c.interval[1]


def test_the_scene_predicts_better():
    c = compare_paired(PIM, PIM * 0.5, 4)
    assert c.verdict == SCENE_BETTER and c.scene_better and c.median_difference < 0


def test_no_significant_difference_states_p():
    rng = np.random.default_rng(1)
    scene = PIM + rng.normal(0.0, 0.3, PIM.size)
    c = compare_paired(PIM, scene, 4)
    p = wilcoxon(scene - PIM).pvalue
    assert p > 0.05 and c.p_value == pytest.approx(p)
    assert c.verdict == f"no significant difference (p = {p:.2g})"


def test_too_few_tests_gets_no_verdict_however_large_the_difference():
    """Three tests and four parameters (the RICSAC class): no verdict, no p-value."""
    c = compare_paired([1.0, 1.0, 1.0], [9.0, 9.0, 9.0], 4)
    assert c.verdict == TOO_FEW and c.p_value is None and c.n == 3
    assert compare_paired(PIM[:5], PIM[:5] + 1, 4).verdict == TOO_FEW
    assert compare_paired(PIM[:6], PIM[:6] + 1, 4).verdict == PIM_BETTER


def test_a_failed_prediction_is_the_worst():
    scene = PIM + 0.5
    scene[2] = math.nan                                # the scene failed on one test
    c = compare_paired(PIM, scene, 4)
    assert c.verdict == PIM_BETTER and c.n == PIM.size
    both = scene.copy()
    pim = PIM.copy()
    pim[2] = math.nan                                  # both failed: the pair is dropped
    assert compare_paired(pim, both, 4).n == PIM.size - 1
    with pytest.raises(ValueError, match="paired errors"):
        compare_paired(PIM, PIM[:-1], 4)


def test_bootstrap_is_seeded_and_brackets_the_median():
    d = np.random.default_rng(2).normal(0.2, 1.0, 30)
    a, b = bootstrap_median(d, seed=5), bootstrap_median(d, seed=5)
    assert a == b and a[0] < np.median(d) < a[1]
