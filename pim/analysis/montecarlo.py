"""Monte Carlo uncertainty of a PIM reconstruction: percentiles and variance-based sensitivity.

The inputs of a scalar case are sampled from their distributions (:mod:`pim.model.distributions`,
the case file's ``[uncertainty]`` table), solved by vectorised calls of :func:`pim.solve` (the
compiled fast path for large n; up to :data:`CHUNK_SIZE` samples in one call, more chunk by
chunk on bounded memory, :mod:`pim.analysis.streaming`), and for each output the 5th, 50th
and 95th percentiles are reported with the ranked contribution of each input to its variance.

Sensitivity: first-order indices S_i = Var(E[Y | X_i]) / Var(Y) (Sobol's first-order index),
estimated from the same samples as the percentiles by the correlation ratio: the samples are
binned into B equal-probability bins of X_i (using the uniform variate each sample of X_i was
drawn from, so no sorting is needed) and Var(E[Y | X_i]) is the variance of the bin means
weighted by bin counts. For an input with no influence this ratio is biased upward by about
(B - 1) / (n - 1); that bias is subtracted (and the result floored at 0). We chose this over
Saltelli's pick-freeze estimator because it needs no extra model evaluations (Saltelli needs
n (k + 2) for k inputs) and, for the smooth, low-dimensional maps of PIM, converges as fast;
the price is a binning error (the variance of E[Y | X_i] inside a bin is lost): of order
1/B^2 for uniform inputs, a few 1e-3 for normal ones (wide tail bins) at B = 100. Inputs are
sampled independently, so the first-order indices sum to at most 1; the remainder is the share
of variance due to interactions.

Samples where the impact is inadmissible (no approach, singular q, energy gain, beta outside
[0, 1]) are counted and left out of the statistics.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..model.case import Case, Impact, Vehicle
from ..model.display import DisplayUnits, convert, display_units
from ..model.distributions import UncertaintyTable, nominal_values, sample_inputs
from ..model.notebook import Notebook, Table
from ..model.number_format import format_interval
from ..model.numbers import InputError, check_numbers, checked_count
from ..model.quantities import OUTPUTS as OUTPUT_QUANTITIES
from ..model.solver import solve
from .streaming import StreamingIndices, StreamingPercentiles

__all__ = ["uncertainty", "UncertaintyResult", "OutputStats", "OUTPUTS", "first_order_indices",
           "memory_estimate", "available_memory", "memory_shortfall", "CHUNK_SIZE",
           "sampled_case"]

#: Outputs summarised, by their names in :data:`pim.model.quantities.OUTPUTS` (which gives
#: each one's label and unit kind).
OUTPUTS = ("delta_v1_magnitude", "delta_v2_magnitude", "speed1", "speed2", "yaw_rate1",
           "yaw_rate2", "energy_loss", "pdof1", "pdof2")
PERCENTILES = (5.0, 50.0, 95.0)
#: Samples solved in one vectorised call; larger runs go chunk by chunk.
CHUNK_SIZE = 1 << 19
#: Peak memory per sample of one chunk [bytes], and of the process before the first chunk
#: (Python, numpy, numba) [bytes] (measured: benchmarks/bench_uncertainty.py --memory).
BYTES_PER_SAMPLE = 760
BASELINE_BYTES = 320 * 2**20


@dataclass(frozen=True)
class OutputStats:
    """Summary of one output over the admissible samples [SI unit of the output].

    Attributes
    ----------
    nominal : float
        The output at the nominal inputs.
    p5, p50, p95 : float
        5th, 50th and 95th percentiles (numpy's "linear" method, exact in chunked runs).
    mean, sd : float
        Mean and population standard deviation.
    """

    nominal: float
    p5: float
    p50: float
    p95: float
    mean: float
    sd: float


@dataclass(frozen=True, eq=False)
class UncertaintyResult(Notebook):
    """Result of :func:`uncertainty`.

    In a notebook it shows as a table in the case's units (:meth:`display_table`: each output's
    nominal value and 5-50-95 % percentiles); :meth:`to_dict` and ``to_frame()`` (pandas)
    give its numbers.

    Attributes
    ----------
    case_name : str
    n : int
        Number of samples drawn.
    seed : int or None
        Seed of the random generator (the entropy drawn when None was given).
    n_admissible : int
        Samples used in the statistics (the others are inadmissible impacts).
    problems : list of str
        Why samples were inadmissible (from :meth:`pim.Result.problems`).
    stats : dict
        Output name (:data:`OUTPUTS`) -> :class:`OutputStats` [SI].
    sensitivity : dict
        Output name -> list of (input name, first-order index) sorted by decreasing index.
    varying : tuple of str
        The inputs that vary.
    samples : dict
        Output name -> admissible samples [SI], for histograms: all of them when n is at most
        the chunk size, else those of the first chunk.
    units : DisplayUnits
        The case's display units (what :meth:`display_table` and :meth:`to_dict` show by default).
    """

    case_name: str
    n: int
    seed: int | None
    n_admissible: int
    problems: list
    stats: dict
    sensitivity: dict
    varying: tuple
    samples: dict = field(repr=False)
    units: DisplayUnits = field(default_factory=DisplayUnits, repr=False)

    def __repr__(self) -> str:
        stats = self.stats.get("delta_v1_magnitude")
        spread = ""
        if stats is not None and self.n_admissible:
            (p50, p5, p95), unit = convert([stats.p50, stats.p5, stats.p95], "speed",
                                           self.units)
            spread = f": |delta-V| of vehicle 1 {format_interval(p50, p5, p95)} {unit}"
        return (f"UncertaintyResult({self.case_name or '(unnamed)'!r}, {self.n} samples, "
                f"{self.n_admissible} admissible, seed={self.seed}{spread})")

    def _row(self, name: str, shown) -> tuple:
        s = self.stats[name]
        quantity = OUTPUT_QUANTITIES[name]
        values, unit = convert([s.nominal, s.p5, s.p50, s.p95], quantity.kind, shown)
        return (quantity.label, *map(float, values), unit)

    def display_table(self, units=None) -> Table:
        """Each output's nominal value and 5th, 50th and 95th percentiles in ``units``
        (default the case's), the inputs that drive it most in the notes."""
        shown = display_units(units or self.units)
        notes = [f"{shown}; angles in deg, yaw rates in deg/s",
                 f"{self.n_admissible} of {self.n} samples admissible (seed {self.seed})"]
        notes += [f"inadmissible samples: {p}" for p in self.problems]
        return Table(f"uncertainty of {self.case_name or 'case'}",
                     ("quantity", "nominal", "5 %", "50 %", "95 %", "unit"),
                     tuple(self._row(name, shown) for name in self.stats), tuple(notes))

    def to_dict(self, units=None) -> dict:
        """JSON-ready: the statistics of each output in ``units`` (default the case's), the
        first-order sensitivity indices, the sample counts."""
        shown = display_units(units or self.units)
        outputs = {}
        for name, s in self.stats.items():
            values, unit = convert([s.nominal, s.p5, s.p50, s.p95, s.mean, s.sd],
                                   OUTPUT_QUANTITIES[name].kind, shown)
            outputs[name] = dict(zip(("nominal", "p5", "p50", "p95", "mean", "sd"),
                                     map(float, values), strict=True)) | {"unit": unit}
        return {"case": self.case_name, "units": {"system": shown.system,
                                                  "speed": shown.speed},
                "n": self.n, "seed": self.seed, "n_admissible": self.n_admissible,
                "problems": list(self.problems), "outputs": outputs,
                "sensitivity": {k: [[name, float(v)] for name, v in pairs]
                                for k, pairs in self.sensitivity.items()}}


def _bin_indices(uniforms: dict, bins: int) -> dict:
    return {name: np.minimum((u * bins).astype(np.intp), bins - 1)
            for name, u in uniforms.items()}


def first_order_indices(y: np.ndarray, uniforms: dict, bins: int | None = None,
                        _binned: dict | None = None) -> list:
    """First-order variance-based indices of ``y`` by the correlation ratio (module notes).

    Parameters
    ----------
    y : ndarray (n,)
        Output samples.
    uniforms : dict
        Input name -> uniform variates (n,) in (0, 1) from which that input was drawn by
        inverse CDF (a monotone map, so bins of u are equal-probability bins of the input).
    bins : int, optional
        Number of bins B; default clip(sqrt(n) / 2, 2, 100).

    Returns
    -------
    list of (str, float)
        (input, S_i) sorted by decreasing S_i, with S_i = (eta^2 - b) / (1 - b) floored at 0,
        eta^2 = sum_b n_b (mean_b - mean)^2 / sum (y - mean)^2 and b = (B - 1) / (n - 1).
    """
    n = y.size
    if bins is None:
        bins = int(np.clip(np.sqrt(n) / 2, 2, 100))
    dev = y - y.mean()
    total = float(np.dot(dev, dev))
    binned = _bin_indices(uniforms, bins) if _binned is None else _binned
    out = []
    for name in uniforms:
        if total == 0 or n < 2 * bins:
            out.append((name, 0.0))
            continue
        idx = binned[name]
        counts = np.bincount(idx, minlength=bins)
        sums = np.bincount(idx, weights=dev, minlength=bins)
        with np.errstate(invalid="ignore", divide="ignore"):
            between = float(np.sum(np.where(counts > 0, sums * sums / counts, 0.0)))
        eta2 = between / total
        bias = (bins - 1) / (n - 1)
        out.append((name, max(0.0, (eta2 - bias) / (1.0 - bias))))
    return sorted(out, key=lambda item: -item[1])


def _pair(x, y) -> np.ndarray:
    return np.stack(np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float)), axis=-1)


def sampled_case(case: Case, v: dict) -> Case:
    """``case`` with its inputs set to the sampled values ``v`` (dotted names of
    :data:`pim.model.distributions.INPUTS` -> arrays [SI]; outlines kept)."""
    def vehicle(i: int, base: Vehicle) -> Vehicle:
        p = f"vehicle{i}."
        if base.fixed.any():
            return Vehicle.obstacle(cg=_pair(v[p + "cg_x"], v[p + "cg_y"]),
                                    heading=v[p + "heading"], length=base.length,
                                    width=base.width, cg_to_front=base.cg_to_front)
        return Vehicle(mass=v[p + "mass"], yaw_inertia=v[p + "yaw_inertia"],
                       cg=_pair(v[p + "cg_x"], v[p + "cg_y"]),
                       velocity=_pair(v[p + "velocity_x"], v[p + "velocity_y"]),
                       yaw_rate=v[p + "yaw_rate"], heading=v[p + "heading"],
                       length=base.length, width=base.width, cg_to_front=base.cg_to_front)

    impact = Impact(point=_pair(v["impact.point_x"], v["impact.point_y"]),
                    normal_angle=v["impact.normal_angle"])
    return Case(vehicle(1, case.vehicle1), vehicle(2, case.vehicle2), impact, name=case.name)


def _wrap_about(angle: np.ndarray, centre: float) -> np.ndarray:
    """Angles [rad] unwrapped to within pi of ``centre`` (so percentiles do not straddle +-pi)."""
    return centre + np.pi - np.mod(np.pi - (angle - centre), 2 * np.pi)


def _outputs(result, nominal=None) -> dict:
    out = {name: getattr(result, name) for name in OUTPUTS}
    if nominal is not None:
        for k in ("pdof1", "pdof2"):
            if np.isfinite(nominal[k]):
                out[k] = _wrap_about(out[k], nominal[k])
    return out


def memory_estimate(n: int, chunk_size: int = CHUNK_SIZE) -> int:
    """Peak memory of :func:`uncertainty` with n samples [bytes], an upper estimate.

    The process (:data:`BASELINE_BYTES`), one chunk's inputs, results and statistics
    (:data:`BYTES_PER_SAMPLE` each), plus the values the streaming percentiles keep (2.5 % of
    the samples per output for the three windows, 8 bytes each); measured by
    ``benchmarks/bench_uncertainty.py --memory`` (1e6 samples: 675 MiB; 1e8: 879 MiB).
    """
    n = int(n)
    kept = 0 if n <= chunk_size else int(0.025 * n) * 8 * len(OUTPUTS)
    return BASELINE_BYTES + min(n, int(chunk_size)) * BYTES_PER_SAMPLE + kept


def available_memory() -> int | None:
    """Memory the system can still give [bytes] (MemAvailable of /proc/meminfo), or None."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def memory_shortfall(n: int, available: int | None = None) -> str | None:
    """Why a Monte Carlo of ``n`` samples does not fit in memory, or None when it does.

    Parameters
    ----------
    n : int
        Samples.
    available : int, optional
        Memory the system can give [bytes] (default :func:`available_memory`; None when
        unknown: no shortfall).

    Returns
    -------
    str or None
        "needs about X GiB of memory and Y GiB are available" when :func:`memory_estimate`
        exceeds ``available``.
    """
    need = memory_estimate(n)
    free = available_memory() if available is None else available
    if free is None or need <= free:
        return None
    return (f"needs about {need / 2**30:.1f} GiB of memory and {free / 2**30:.1f} GiB are "
            f"available")


@dataclass
class _Setup:
    """What every chunk of a Monte Carlo shares."""

    case: Case
    dists: UncertaintyTable
    nominal_in: dict
    nominal_out: dict
    seed: np.random.SeedSequence
    n: int
    chunk_size: int

    def chunks(self):
        """(outputs, ok mask, uniforms, problem counts) chunk by chunk; the same every time."""
        rng = np.random.default_rng(self.seed)
        for start in range(0, self.n, self.chunk_size):
            m = min(self.chunk_size, self.n - start)
            values, uniforms = sample_inputs(self.dists, self.nominal_in, m, rng)
            result = solve(sampled_case(self.case, values), values["impact.restitution"],
                           values["impact.beta"])
            ok = np.broadcast_to(result.admissible, (m,))
            outputs = {k: np.broadcast_to(v, (m,)) for k, v in
                       _outputs(result, self.nominal_out).items()}
            yield outputs, ok, uniforms, result.problem_counts()


def _setup(case, n, seed, distributions, eps, beta, chunk_size) -> _Setup:
    check_numbers(eps=eps, beta=beta)
    dists = case.uncertainty if distributions is None else distributions
    if dists is None:
        raise InputError("uncertainty: the case has no [uncertainty] table and no "
                         "distributions were given")
    if not isinstance(dists, UncertaintyTable):
        raise InputError("distributions must be a pim.model.distributions.UncertaintyTable")
    n = checked_count(n, "n (samples)", low=10)
    chunk_size = checked_count(chunk_size, "chunk_size", low=10)
    seed = checked_count(seed, "seed", low=0, none=True)
    nominal_in = nominal_values(case, eps, beta)
    # evidence inputs (run-out friction) do not act on the impact: pim reconstruct samples them
    dists = UncertaintyTable({k: d for k, d in dists.inputs.items() if k in nominal_in})
    nominal_result = solve(case, nominal_in["impact.restitution"], nominal_in["impact.beta"],
                           backend="numpy")
    nominal_out = {k: float(np.asarray(v).reshape(())) for k, v in _outputs(nominal_result).items()}
    return _Setup(case, dists, nominal_in, nominal_out, np.random.SeedSequence(seed), n,
                  int(chunk_size))


def _merge_problems(counts: dict, n: int) -> list:
    return [text if n == 1 else f"{text} ({bad} of {n} cases)" for text, bad in counts.items()]


def _in_memory(setup: _Setup, progress) -> UncertaintyResult:
    """All samples in one chunk: percentiles by :func:`numpy.percentile`."""
    outputs, ok, uniforms, problems = next(setup.chunks())
    if progress is not None:
        progress(setup.n)
    n, n_ok = setup.n, int(np.count_nonzero(ok))
    all_ok = n_ok == n
    u_ok = {k: (u if all_ok else u[ok]) for k, u in uniforms.items()}
    bins = int(np.clip(np.sqrt(n_ok) / 2, 2, 100))
    binned = _bin_indices(u_ok, bins)
    stats, sens, samples = {}, {}, {}
    for name, y in outputs.items():
        y = y if all_ok else y[ok]
        samples[name] = y
        if n_ok:
            p5, p50, p95 = np.percentile(y, PERCENTILES)
            stats[name] = OutputStats(setup.nominal_out[name], float(p5), float(p50),
                                      float(p95), float(y.mean()), float(y.std()))
        else:
            stats[name] = OutputStats(setup.nominal_out[name], *([np.nan] * 5))
        sens[name] = first_order_indices(y, u_ok, bins, binned) if n_ok > 1 else []
    return _result(setup, n_ok, _merge_problems({t: b for t, b, _ in problems}, n), stats,
                   sens, tuple(uniforms), samples)


def _result(setup, n_ok, problems, stats, sens, varying, samples) -> UncertaintyResult:
    return UncertaintyResult(case_name=setup.case.name, n=setup.n, seed=setup.seed.entropy,
                             n_admissible=n_ok, problems=problems, stats=stats,
                             sensitivity=sens, varying=varying, samples=samples,
                             units=display_units(case=setup.case))


def _streamed(setup: _Setup, progress) -> UncertaintyResult:
    """Chunk by chunk on bounded memory (:mod:`pim.analysis.streaming`)."""
    quantiles = {k: StreamingPercentiles(PERCENTILES) for k in OUTPUTS}
    moments, samples, problems, n_ok, varying = None, {}, {}, 0, ()
    for outputs, ok, uniforms, counts in setup.chunks():
        for text, bad, _ in counts:
            problems[text] = problems.get(text, 0) + bad
        y_ok = {k: y[ok] for k, y in outputs.items()}
        u_ok = {k: u[ok] for k, u in uniforms.items()}
        if moments is None:     # the first chunk: the pilot of the bins and the histograms
            varying, samples = tuple(uniforms), y_ok
            share = max(np.count_nonzero(ok), 1) / ok.size
            bins = int(np.clip(np.sqrt(setup.n * share) / 2, 2, 100))
            moments = {k: StreamingIndices(varying, bins, float(np.mean(y)) if y.size else 0.0)
                       for k, y in y_ok.items()}
        binned = _bin_indices(u_ok, moments[OUTPUTS[0]].bins)
        counts = {k: np.bincount(b, minlength=moments[OUTPUTS[0]].bins) for k, b in binned.items()}
        for k, y in y_ok.items():
            quantiles[k].add(y)
            moments[k].add(y, binned, counts)
        n_ok += int(np.count_nonzero(ok))
        if progress is not None:
            progress(ok.size)
    for k, q in quantiles.items():
        if q.missing():     # a pilot far from the whole: passes over the same chunks (rare)
            q.refine(lambda k=k: (out[k][ok] for out, ok, _, _ in setup.chunks()))
    stats, sens = {}, {}
    for k in OUTPUTS:
        mean, sd = moments[k].mean_sd()
        stats[k] = OutputStats(setup.nominal_out[k], *quantiles[k].result(), mean, sd)
        sens[k] = moments[k].indices()
    return _result(setup, n_ok, _merge_problems(problems, setup.n), stats, sens, varying,
                   samples)


def uncertainty(case: Case, n: int = 100_000, seed: int | None = 0,
                distributions: UncertaintyTable | None = None, eps=None,
                beta=None, chunk_size: int = CHUNK_SIZE, progress=None) -> UncertaintyResult:
    """Monte Carlo of a scalar case's inputs: percentiles and first-order sensitivity indices.

    Up to ``chunk_size`` samples are solved in one vectorised call; more are drawn, solved
    and summarised chunk by chunk on bounded memory (:func:`memory_estimate`), with the same
    statistics: exact percentiles (:class:`pim.analysis.streaming.StreamingPercentiles`),
    mean, standard deviation and first-order indices accumulated by chunk.

    Parameters
    ----------
    case : Case
        One scene (scalar fields), with nominal eps in ``impact.restitution`` or ``eps``.
    n : int
        Number of samples (>= 10).
    seed : int or None
        Seed of numpy's default generator (None: fresh entropy).
    distributions : UncertaintyTable, optional
        Input distributions; default ``case.uncertainty`` (the case file's table).
    eps, beta : float, optional
        Nominal eps and beta [-], overriding the case's.
    chunk_size : int
        Samples per chunk (>= 10). With n <= chunk_size the result is that of one call
        (unchanged from the in-memory implementation); above it the samples are drawn chunk
        by chunk from the same generator, so they differ from a one-chunk run of the same
        seed (the statistics agree within their sampling error).
    progress : callable, optional
        Called with the number of samples just finished after each chunk (e.g. a tqdm
        bar's ``update``).

    Returns
    -------
    UncertaintyResult
        Its ``samples`` (for histograms) are all admissible samples when n <= chunk_size,
        else those of the first chunk (a random subsample).

    Raises
    ------
    ValueError
        No distributions, a non-scalar case, n < 10, or a distribution outside an input's
        admissible range.
    """
    setup = _setup(case, n, seed, distributions, eps, beta, chunk_size)
    if setup.n <= setup.chunk_size:
        return _in_memory(setup, progress)
    return _streamed(setup, progress)
