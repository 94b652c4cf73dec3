"""Statistics of a sample that arrives in chunks, on bounded memory: exact percentiles, mean
and standard deviation, first-order variance-based indices.

Percentiles (exact, numpy's default "linear" method): the first chunk (the pilot, a random
subsample of the same distribution) gives, for each percentile p, a window of values around
its own p-quantile, z = 8 standard errors wide either side in probability (a pilot of m
values puts its p-quantile within sqrt(p (1 - p) / m) of p, one standard error); every chunk
adds its count of values below the window and keeps the values inside. At the end the
counts say whether the order statistics the percentile needs lie inside the kept values
(then it is exact); otherwise (a pilot far from the whole: probability about 1e-15 per
window at z = 8) :meth:`StreamingPercentiles.refine` finds them by passes over the same
chunks, each narrowing an interval 1365-fold on a histogram, still exact.
Memory: about 2 z sqrt(p (1 - p) / m) of the values per percentile, 8 bytes each: with
m = 2^19, 1.1 % of the samples at p = 0.5 and 0.5 % at p = 0.05 or 0.95.

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
    z : float
        Half-width of each kept window in standard errors of the pilot's percentile.
    budget : int
        Most values a refinement pass keeps for one order statistic.
    """

    def __init__(self, percentiles, z: float = 8.0, budget: int = 1 << 22):
        self.percentiles = tuple(float(q) for q in percentiles)
        self.z, self.budget = float(z), int(budget)
        self.windows = None         # [low, high, values below low, kept values]
        self.n, self.nan, self.low, self.high = 0, 0, np.inf, -np.inf
        self.found: dict = {}       # order statistic (0-based) -> value

    def _start(self, pilot: np.ndarray) -> None:
        ordered, m = np.sort(pilot), pilot.size
        self.windows = []
        for q in self.percentiles:
            p = q / 100
            half = self.z * np.sqrt(p * (1 - p) / m) + 2 / m
            lo, hi = (int(np.clip(np.floor(x * (m - 1)), 0, m - 1)) for x in (p - half, p + half))
            self.windows.append([ordered[lo], ordered[min(hi + 1, m - 1)], 0, []])

    def add(self, y: np.ndarray) -> None:
        """Count a chunk of values (the first non-empty chunk is the pilot)."""
        y = np.asarray(y, float).ravel()
        finite = ~np.isnan(y)
        if not finite.all():
            self.nan += int(y.size - np.count_nonzero(finite))
            y = y[finite]
        if y.size == 0:
            return
        if self.windows is None:
            self._start(y)
        self.n += y.size
        self.low, self.high = min(self.low, float(y.min())), max(self.high, float(y.max()))
        for window in self.windows:
            lo, hi = window[0], window[1]
            window[2] += int(np.count_nonzero(y < lo))
            if not isinstance(window[3], list):     # sorted by missing(); more values came
                window[3] = [window[3]]
            window[3].append(y[(y >= lo) & (y <= hi)])

    def _needed(self) -> set:
        return {k for q in self.percentiles for k in _ranks(self.n, q)[:2]}

    def missing(self) -> list:
        """Order statistics (0-based) not yet known; empty: :meth:`result` is exact."""
        if self.n == 0 or self.nan:
            return []
        for window in self.windows:
            if isinstance(window[3], list):
                window[3] = np.sort(np.concatenate(window[3]))
            below, kept = window[2], window[3]
            for k in self._needed():
                if below <= k < below + kept.size:
                    self.found[k] = float(kept[k - below])
        return sorted(self._needed() - set(self.found))

    def refine(self, passes) -> None:
        """Find the missing order statistics by passes over the same chunks.

        ``passes`` is a function returning a fresh iterator of the chunks of values. Each
        pass counts, for every unknown order statistic, the values below its interval [a, b]
        and those inside in 4096 equal bins, keeping the inside values while they number at
        most ``budget``; if they were kept the statistic is read off, else the interval
        narrows to the bin holding it and one bin either side (a margin for rounding).
        """
        todo = {k: (self.low, self.high) for k in self.missing()}
        while todo:
            below = dict.fromkeys(todo, 0)
            hists = {k: np.zeros(4098, np.int64) for k in todo}
            kept = {k: [] for k in todo}
            for y in passes():
                y = np.asarray(y, float).ravel()
                y = y[~np.isnan(y)]
                for k, (a, b) in todo.items():
                    j = _bin(y, a, b)
                    below[k] += int(np.count_nonzero(j == 0))
                    hists[k] += np.bincount(j, minlength=4098)
                    if kept[k] is not None:
                        kept[k].append(y[(j >= 1) & (j <= 4096)])
                        if sum(v.size for v in kept[k]) > self.budget:
                            kept[k] = None
            for k in list(todo):
                a, b = todo.pop(k)
                if kept[k] is not None:
                    self.found[k] = float(np.sort(np.concatenate(kept[k]))[k - below[k]])
                    continue
                j = int(np.searchsorted(below[k] + np.cumsum(hists[k][1:4097]), k,
                                        side="right")) + 1
                width = (b - a) / 4096
                todo[k] = (max(a, a + (j - 2) * width), min(b, a + (j + 1) * width))
                if todo[k] == (a, b):   # no narrower float interval: keep them all next time
                    self.budget = max(self.budget, int(hists[k][1:4097].sum()))

    def result(self) -> tuple:
        """The percentiles [same unit as the values]; NaN if any value was NaN or none came."""
        if self.n == 0 or self.nan:
            return tuple(np.nan for _ in self.percentiles)
        if self.missing():
            raise RuntimeError("order statistics not found: call refine() first")
        return tuple(numpy_percentile(self.found.__getitem__, self.n, q)
                     for q in self.percentiles)


def _bin(y: np.ndarray, a: float, b: float) -> np.ndarray:
    """Bin of each value for 4096 equal bins of [a, b]: 0 below a, 4097 above b, the top bin
    closed."""
    if a == b:
        return np.where(y < a, 0, np.where(y > b, 4097, 1))
    j = np.floor((y - a) * (4096 / (b - a))).astype(np.int64) + 1
    j = np.where(y == b, 4096, np.clip(j, 0, 4097))
    return np.where(y < a, 0, np.where(y > b, 4097, j))


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

    def add(self, y: np.ndarray, binned: dict, counts: dict | None = None) -> None:
        """Add values y (n,) and each input's bin index (n,) in [0, bins) (``counts``: the
        bin counts of ``binned``, if already known)."""
        dev = np.asarray(y, float) - self.shift
        self.n += dev.size
        self.sum += float(dev.sum())
        self.sum2 += float(np.dot(dev, dev))
        for k in self.names:
            self.counts[k] += (np.bincount(binned[k], minlength=self.bins) if counts is None
                               else counts[k])
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
