"""A verdict on two models from their paired per-test prediction errors.

The rule (docs/validation.md, "Verdicts"):

* a class with fewer tests than the larger model's parameters + 2 gets no verdict: "too few
  tests to decide" (:data:`TOO_FEW`);
* otherwise the paired Wilcoxon signed-rank test (``scipy.stats.wilcoxon``, two-sided) of the
  differences d_i = e_scene,i - e_PIM,i decides at level :data:`ALPHA`: "PIM predicts better"
  (:data:`PIM_BETTER`) or "the scene predicts better" (:data:`SCENE_BETTER`) by the side
  holding the larger rank sum, else "no significant difference (p = ...)";
* the median of d comes with a seeded percentile-bootstrap interval (:data:`CONFIDENCE`,
  :data:`RESAMPLES` resamples of the pairs).

A prediction that failed (NaN error: the scene did not separate) is worse than any finite
one: its error counts as +inf in the ranks; a pair where both failed is dropped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.stats import rankdata, wilcoxon

__all__ = ["ALPHA", "CONFIDENCE", "RESAMPLES", "PIM_BETTER", "SCENE_BETTER", "TOO_FEW",
           "NO_DIFFERENCE", "minimum_tests", "decide", "PairedComparison", "compare_paired",
           "bootstrap_median"]

#: Level of the signed-rank test.
ALPHA = 0.05
#: Confidence of the bootstrap interval of the median difference.
CONFIDENCE = 0.95
#: Bootstrap resamples.
RESAMPLES = 4000
PIM_BETTER = "PIM predicts better"
SCENE_BETTER = "the scene predicts better"
TOO_FEW = "too few tests to decide"
#: Template of the fourth verdict (its p-value to two significant digits).
NO_DIFFERENCE = "no significant difference (p = {p})"


def minimum_tests(n_parameters: int) -> int:
    """The fewest tests a class needs for a verdict: the parameters + 2."""
    return int(n_parameters) + 2


def _p_text(p: float) -> str:
    return f"{p:.2g}" if p >= 0.01 else "< 0.01"


def decide(n_tests: int, n_parameters: int, p_value: float | None,
           scene_better: bool, alpha: float = ALPHA) -> str:
    """The verdict from the test's outcome (module notes): a pure function.

    Parameters
    ----------
    n_tests : int
        Paired tests of the class.
    n_parameters : int
        Parameters of the larger model.
    p_value : float or None
        Two-sided p-value of the signed-rank test (None when it could not run).
    scene_better : bool
        The scene's errors hold the smaller rank sum (it errs less).
    alpha : float
        Level of the test.
    """
    if n_tests < minimum_tests(n_parameters) or p_value is None or math.isnan(p_value):
        return TOO_FEW
    if p_value < alpha:
        return SCENE_BETTER if scene_better else PIM_BETTER
    return NO_DIFFERENCE.format(p=_p_text(p_value))


@dataclass(frozen=True)
class PairedComparison:
    """Two models compared on paired per-test errors (module notes).

    Attributes
    ----------
    verdict : str
        One of the four verdicts.
    p_value : float or None
        Two-sided p-value of the Wilcoxon signed-rank test (None below the class size).
    n : int
        Pairs compared (both failed: dropped).
    n_parameters : int
        Parameters of the larger model.
    median_difference : float
        Median of e_scene - e_PIM [units of the errors] (negative: the scene errs less).
    interval : tuple of float
        Bootstrap interval of the median difference (:data:`CONFIDENCE`).
    scene_better : bool
        The scene holds the smaller rank sum.
    """

    verdict: str
    p_value: float | None
    n: int
    n_parameters: int
    median_difference: float
    interval: tuple
    scene_better: bool


def _differences(errors_pim, errors_scene) -> np.ndarray:
    """e_scene - e_PIM with failures (NaN) as +inf errors; pairs where both failed dropped."""
    a = np.asarray(errors_pim, dtype=float)
    b = np.asarray(errors_scene, dtype=float)
    if a.shape != b.shape or a.ndim != 1:
        raise ValueError(f"paired errors need two 1-d arrays of one length, got {a.shape} "
                         f"and {b.shape}")
    keep = ~(np.isnan(a) & np.isnan(b))
    a = np.where(np.isnan(a), np.inf, a)[keep]
    b = np.where(np.isnan(b), np.inf, b)[keep]
    with np.errstate(invalid="ignore"):
        d = b - a
    return np.where(np.isnan(d), 0.0, d)        # inf - inf cannot occur (dropped above)


def bootstrap_median(d, confidence: float = CONFIDENCE, resamples: int = RESAMPLES,
                     seed: int = 0) -> tuple[float, float]:
    """Percentile-bootstrap interval of the median of ``d`` (pairs resampled with
    replacement, ``numpy.random.default_rng(seed)``): (low, high)."""
    d = np.asarray(d, dtype=float)
    if d.size == 0:
        return (math.nan, math.nan)
    rng = np.random.default_rng(seed)
    medians = np.median(d[rng.integers(0, d.size, size=(int(resamples), d.size))], axis=1)
    tail = 50.0 * (1.0 - confidence)
    low, high = np.percentile(medians, [tail, 100.0 - tail])
    return (float(low), float(high))


def compare_paired(errors_pim, errors_scene, n_parameters: int, *, alpha: float = ALPHA,
                   seed: int = 0) -> PairedComparison:
    """The verdict, p-value and bootstrap interval of paired errors (module notes).

    Parameters
    ----------
    errors_pim, errors_scene : array_like (n,)
        Each test's prediction error of PIM and of the scene, in one order [any unit,
        >= 0; NaN: the prediction failed].
    n_parameters : int
        Parameters of the larger model (the class-size rule).
    alpha : float
        Level of the signed-rank test.
    seed : int
        Seed of the bootstrap.
    """
    d = _differences(errors_pim, errors_scene)
    n = int(d.size)
    median = float(np.median(d)) if n else math.nan
    interval = bootstrap_median(d, seed=seed)
    nonzero = d[d != 0]
    ranks = rankdata(np.abs(nonzero)) if nonzero.size else np.zeros(0)
    scene_better = bool(ranks[nonzero < 0].sum() > ranks[nonzero > 0].sum())
    p = None
    if n >= minimum_tests(n_parameters):
        p = 1.0 if nonzero.size == 0 else float(wilcoxon(_finite_ranks(d)).pvalue)
    return PairedComparison(decide(n, n_parameters, p, scene_better, alpha), p, n,
                            int(n_parameters), median, interval, scene_better)


def _finite_ranks(d: np.ndarray) -> np.ndarray:
    """``d`` with each infinite difference replaced by a finite one larger than every other
    |d| and of its sign: the signed-rank test sees the same ranks."""
    finite = np.abs(d[np.isfinite(d)])
    big = 2.0 * (finite.max() if finite.size else 1.0) + 1.0
    return np.where(np.isfinite(d), d, np.sign(d) * big)
