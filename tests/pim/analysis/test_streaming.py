"""Statistics of chunked samples (pim.analysis.streaming) against numpy on the whole sample.

Expected values: numpy.percentile, mean and std of the concatenated chunks, and
pim.analysis.montecarlo.first_order_indices on them (an independent, in-memory computation).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pim.analysis.montecarlo import first_order_indices
from pim.analysis.streaming import StreamingIndices, StreamingPercentiles

QS = (5.0, 50.0, 95.0)


def streamed(chunks, qs=QS, **kw):
    sp = StreamingPercentiles(qs, **kw)
    for c in chunks:
        sp.add(c)
    if sp.missing():
        sp.refine(lambda: iter(chunks))
    return sp.result()


@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 3000), parts=st.integers(1, 9), seed=st.integers(0, 2**32 - 1),
       decimals=st.sampled_from([None, 0, 1]), scale=st.floats(1e-6, 1e6))
def test_percentiles_equal_numpy_on_the_whole_sample(n, parts, seed, decimals, scale):
    rng = np.random.default_rng(seed)
    y = rng.standard_normal(n) * scale
    if decimals is not None:        # ties
        y = np.round(y / scale, decimals) * scale
    qs = (0.0, 5.0, 33.3, 50.0, 95.0, 100.0)
    assert streamed(np.array_split(y, parts), qs) == tuple(np.percentile(y, qs))


def test_a_pilot_far_from_the_whole_is_refined_exactly():
    """The first chunk (the pilot) sees none of the bulk: every window misses."""
    rng = np.random.default_rng(3)
    y = np.concatenate([np.arange(1000) * 1e-3, rng.standard_normal(60_000) + 5])
    chunks = np.array_split(y, 12)
    sp = StreamingPercentiles(QS)
    for c in chunks:
        sp.add(c)
    assert sp.missing()     # the refinement path is taken
    assert streamed(chunks) == tuple(np.percentile(y, QS))
    # with a budget far below the bins' contents, several narrowing passes
    assert streamed(chunks, budget=50) == tuple(np.percentile(y, QS))


def test_ties_closer_than_the_histogram_can_split():
    y = np.concatenate([np.zeros(1000), np.full(5000, 3.0), np.full(5000, np.nextafter(3, 4))])
    assert streamed(np.array_split(y, 11), budget=10) == tuple(np.percentile(y, QS))


def test_nan_and_empty():
    assert all(np.isnan(streamed([np.array([1.0, np.nan])])))
    assert all(np.isnan(streamed([np.array([])])))


def test_kept_values_are_a_small_share():
    rng = np.random.default_rng(0)
    sp = StreamingPercentiles(QS)
    for _ in range(20):
        sp.add(rng.standard_normal(1 << 16))
    kept = sum(sum(v.size for v in w[3]) for w in sp.windows)
    # 2 z sqrt(p (1 - p) / m) + 4/m per window, z = 8, m = 2^16: 0.1 in all (module notes)
    assert kept / sp.n < 0.1


def test_moments_and_indices_equal_the_in_memory_computation():
    rng = np.random.default_rng(5)
    n, bins = 50_000, 40
    u = {"a": rng.random(n), "b": rng.random(n), "c": rng.random(n)}
    y = 3 * u["a"] + np.sin(6 * u["b"]) + 0.1 * rng.standard_normal(n) + 1e3
    acc = StreamingIndices(tuple(u), bins, shift=1e3)
    for part in np.array_split(np.arange(n), 7):
        acc.add(y[part], {k: np.minimum((v[part] * bins).astype(np.intp), bins - 1)
                          for k, v in u.items()})
    mean, sd = acc.mean_sd()
    assert mean == pytest.approx(y.mean(), rel=1e-13)
    assert sd == pytest.approx(y.std(), rel=1e-10)
    expected = dict(first_order_indices(y, u, bins))
    for name, value in acc.indices():
        assert value == pytest.approx(expected[name], abs=1e-10), name
