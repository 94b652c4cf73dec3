"""Statistics of a sample that arrives in chunks, on bounded memory: exact percentiles, mean
and standard deviation, first-order variance-based indices.

Percentiles (exact, numpy's default "linear" method): the first chunk (the pilot, a random
subsample of the same distribution) sets ``bins`` bin edges at its own quantiles; every chunk
adds its counts per bin, and the values that fall in the few bins around the pilot's estimate
of each percentile (``window`` bins either side) are kept. At the end the cumulative counts
say which bin holds each order statistic the percentile needs; when that bin was kept (the
usual case) the percentile is exact; otherwise :meth:`StreamingPercentiles.missing` names the
bins to collect in a second pass over the same chunks (:meth:`StreamingPercentiles.collect`).

Why it rarely needs that pass: with a pilot of m values the pilot's p-quantile lies within
sqrt(p (1 - p) / m) of p in probability (one standard error); with m = 2^19, 2048 bins
(1/2048 = 4.9e-4 of probability each) and 4 bins either side kept, the true quantile is
outside the kept window only beyond 4 bins = 9 standard errors at p = 0.05.
Memory: counts of ``bins`` + 2 bins and about (2 window + 1) / bins of the values per
percentile (1.3 % of the samples for three percentiles, 8 bytes each).

Indices: the correlation ratio of :func:`pim.analysis.montecarlo.first_order_indices`, from
per-bin counts and sums accumulated chunk by chunk (values shifted by the pilot's mean so the
sums of squares do not cancel).
"""

from __future__ import annotations

import numpy as np

__all__ = ["StreamingPercentiles", "StreamingIndices", "numpy_percentile"]


def _ranks(n: int, q: float) -> tuple[int, int, float]:
    """The order statistics (0-based) and weight of numpy's "linear" percentile q [%] of n."""
    virtual = (n - 1) * np.true_divide(q, 100)
    below = int(np.floor(virtual))
    return below, min(below + 1, n - 1), float(virtual - below)


def numpy_percentile(order: callable, n: int, q: float) -> float:
    """numpy's "linear" percentile q [%] of n sorted values, from a function that returns the
    k-th smallest value (0-based): the same arithmetic as :func:`numpy.percentile`."""
    below, above, gamma = _ranks(n, q)
    a, b = order(below), order(above)
    diff = b - a
    return float(b - diff * (1 - gamma) if gamma >= 0.5 else a + diff * gamma)


class StreamingPercentiles:
    """Exact percentiles of values added chunk by chunk (module notes).

    Parameters
    ----------
    percentiles : sequence of float
        Percentiles wanted [%].
    bins : int
        Number of pilot-quantile bins.
    window : int
        Bins kept on either side of the pilot's estimate of each percentile.
    """

    def __init__(self, percentiles, bins: int = 2048, window: int = 4):
        self.percentiles = tuple(float(q) for q in percentiles)
        self.bins, self.window = int(bins), int(window)
        self.edges = None
        self.counts = None
        self.keep = None
        self.kept: list = []
        self.nan = 0

    def _start(self, pilot: np.ndarray) -> None:
        levels = np.linspace(0.0, 100.0, self.bins + 1)
        self.edges = np.unique(np.percentile(pilot, levels))
        # bin j holds edges[j - 1] <= y < edges[j]; bins 0 and len(edges) are the open ends
        self.counts = np.zeros(self.edges.size + 1, np.int64)
        self.keep = np.zeros(self.edges.size + 1, bool)
        for q in self.percentiles:
            j = int(np.searchsorted(self.edges, np.percentile(pilot, q), side="right"))
            self.keep[max(0, j - self.window):j + self.window + 1] = True

    def add(self, y: np.ndarray) -> None:
        """Count a chunk of values (the first non-empty chunk is the pilot)."""
        y = np.asarray(y, float).ravel()
        finite = ~np.isnan(y)
        if not finite.all():
            self.nan += int(y.size - np.count_nonzero(finite))
            y = y[finite]
        if y.size == 0:
            return
        if self.edges is None:
            self._start(y)
        index = np.searchsorted(self.edges, y, side="right")
        self.counts += np.bincount(index, minlength=self.counts.size)
        mask = self.keep[index]
        if mask.any():
            self.kept.append((index[mask], y[mask]))

    @property
    def n(self) -> int:
        """Values counted (NaN excluded)."""
        return 0 if self.counts is None else int(self.counts.sum())

    def _needed_bins(self) -> set:
        n, cum, out = self.n, np.cumsum(self.counts), set()
        for q in self.percentiles:
            for k in _ranks(n, q)[:2]:
                out.add(int(np.searchsorted(cum, k, side="right")))
        return out

    def missing(self) -> set:
        """Bins holding a needed order statistic whose values were not kept (empty: exact)."""
        if self.n == 0 or self.nan:
            return set()
        return {j for j in self._needed_bins() if not self.keep[j]}

    def collect(self, y: np.ndarray, bins: set) -> None:
        """Second pass: keep the values of ``bins`` (counts are not added again)."""
        y = np.asarray(y, float).ravel()
        y = y[~np.isnan(y)]
        index = np.searchsorted(self.edges, y, side="right")
        mask = np.isin(index, list(bins)) & ~self.keep[index]
        if mask.any():
            self.kept.append((index[mask], y[mask]))

    def mark_collected(self, bins: set) -> None:
        """Record that a second pass kept ``bins`` (after every chunk was collected)."""
        self.keep[list(bins)] = True

    def result(self) -> tuple:
        """The percentiles [same unit as the values]; NaN if any value was NaN or none came."""
        if self.n == 0 or self.nan:
            return tuple(np.nan for _ in self.percentiles)
        if self.missing():
            raise RuntimeError("percentile bins not kept: run collect() over the chunks first")
        index = np.concatenate([i for i, _ in self.kept])
        values = np.concatenate([v for _, v in self.kept])
        cum = np.cumsum(self.counts)
        sorted_bins: dict = {}

        def order(k: int) -> float:
            j = int(np.searchsorted(cum, k, side="right"))
            if j not in sorted_bins:
                sorted_bins[j] = np.sort(values[index == j])
            return sorted_bins[j][k - (cum[j - 1] if j else 0)]

        return tuple(numpy_percentile(order, self.n, q) for q in self.percentiles)


class StreamingIndices:
    """Mean, standard deviation and first-order indices of values added chunk by chunk.

    Parameters
    ----------
    names : sequence of str
        The varying inputs.
    bins : int
        Equal-probability bins B of each input's uniform variate.
    shift : float
        A value near the mean (the sums are of y - shift).
    """

    def __init__(self, names, bins: int, shift: float = 0.0):
        self.names, self.bins, self.shift = tuple(names), int(bins), float(shift)
        self.n, self.sum, self.sum2 = 0, 0.0, 0.0
        self.counts = {k: np.zeros(self.bins, np.int64) for k in self.names}
        self.sums = {k: np.zeros(self.bins) for k in self.names}

    def add(self, y: np.ndarray, binned: dict) -> None:
        """Add values y (n,) and each input's bin index (n,) in [0, bins)."""
        dev = np.asarray(y, float) - self.shift
        self.n += dev.size
        self.sum += float(dev.sum())
        self.sum2 += float(np.dot(dev, dev))
        for k in self.names:
            self.counts[k] += np.bincount(binned[k], minlength=self.bins)
            self.sums[k] += np.bincount(binned[k], weights=dev, minlength=self.bins)

    def mean_sd(self) -> tuple[float, float]:
        """Mean and population standard deviation (numpy's ``std``)."""
        if self.n == 0:
            return np.nan, np.nan
        m = self.sum / self.n
        return self.shift + m, float(np.sqrt(max(0.0, self.sum2 / self.n - m * m)))

    def indices(self) -> list:
        """(input, S_i) by decreasing S_i, as :func:`pim.analysis.montecarlo.first_order_indices`
        computes them."""
        n, out = self.n, []
        if n < 2:
            return []
        total = self.sum2 - self.sum * self.sum / n
        bias = (self.bins - 1) / (n - 1)
        for k in self.names:
            if total <= 0 or n < 2 * self.bins:
                out.append((k, 0.0))
                continue
            c, s = self.counts[k], self.sums[k]
            with np.errstate(invalid="ignore", divide="ignore"):
                between = float(np.sum(np.where(c > 0, s * s / c, 0.0))) - self.sum**2 / n
            eta2 = between / total
            out.append((k, max(0.0, (eta2 - bias) / (1.0 - bias))))
        return sorted(out, key=lambda item: -item[1])
