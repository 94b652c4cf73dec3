"""Monte Carlo uncertainty of a PIM reconstruction: percentiles and variance-based sensitivity.

The inputs of a scalar case are sampled from their distributions (:mod:`pim.model.distributions`,
the case file's ``[uncertainty]`` table), all samples are solved in one vectorised call of
:func:`pim.solve` (the compiled fast path for large n), and for each output the 5th, 50th and
95th percentiles are reported with the ranked contribution of each input to its variance.

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
from ..model.distributions import UncertaintyTable, nominal_values, sample_inputs
from ..model.numbers import InputError, check_numbers, checked_count
from ..model.solver import solve

__all__ = ["uncertainty", "UncertaintyResult", "OutputStats", "OUTPUTS", "first_order_indices"]

#: Outputs summarised, by their names in :data:`pim.model.quantities.OUTPUTS` (which gives
#: each one's label and unit kind).
OUTPUTS = ("delta_v1_magnitude", "delta_v2_magnitude", "speed1", "speed2", "yaw_rate1",
           "yaw_rate2", "energy_loss", "pdof1", "pdof2")
PERCENTILES = (5.0, 50.0, 95.0)


@dataclass(frozen=True)
class OutputStats:
    """Summary of one output over the admissible samples [SI unit of the output]."""

    nominal: float
    p5: float
    p50: float
    p95: float
    mean: float
    sd: float


@dataclass(frozen=True, eq=False)
class UncertaintyResult:
    """Result of :func:`uncertainty`.

    Attributes
    ----------
    case_name : str
    n : int
        Number of samples drawn.
    seed : int or None
        Seed of the random generator.
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
        Output name -> admissible samples [SI], for histograms.
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

    def interaction_share(self, output: str) -> float:
        """1 - sum of first-order indices: the variance share of interactions [-]."""
        return max(0.0, 1.0 - sum(s for _, s in self.sensitivity[output]))


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


def _sampled_case(case: Case, v: dict) -> Case:
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


def uncertainty(case: Case, n: int = 100_000, seed: int | None = 0,
                distributions: UncertaintyTable | None = None, eps=None,
                beta=None) -> UncertaintyResult:
    """Monte Carlo of a scalar case's inputs: percentiles and first-order sensitivity indices.

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

    Returns
    -------
    UncertaintyResult

    Raises
    ------
    ValueError
        No distributions, a non-scalar case, n < 10, or a distribution outside an input's
        admissible range.
    """
    check_numbers(eps=eps, beta=beta)
    dists = case.uncertainty if distributions is None else distributions
    if dists is None:
        raise InputError("uncertainty: the case has no [uncertainty] table and no "
                         "distributions were given")
    if not isinstance(dists, UncertaintyTable):
        raise InputError("distributions must be a pim.model.distributions.UncertaintyTable")
    n = checked_count(n, "n (samples)", low=10)
    nominal_in = nominal_values(case, eps, beta)
    rng = np.random.default_rng(seed)
    # evidence inputs (run-out friction) do not act on the impact: pim reconstruct samples them
    dists = UncertaintyTable({k: d for k, d in dists.inputs.items() if k in nominal_in})
    values, uniforms = sample_inputs(dists, nominal_in, n, rng)

    nominal_result = solve(case, nominal_in["impact.restitution"], nominal_in["impact.beta"],
                           backend="numpy")
    nominal_out = {k: float(np.asarray(v).reshape(())) for k, v in _outputs(nominal_result).items()}
    sampled = _sampled_case(case, values)
    result = solve(sampled, values["impact.restitution"], values["impact.beta"])
    outputs = _outputs(result, nominal_out)

    ok = np.broadcast_to(result.admissible, np.shape(result.impulse_n))
    if ok.shape != (n,):
        ok = np.broadcast_to(ok, (n,))
    n_ok = int(np.count_nonzero(ok))
    all_ok = n_ok == n
    u_ok = {k: (u if all_ok else u[ok]) for k, u in uniforms.items()}
    bins = int(np.clip(np.sqrt(n_ok) / 2, 2, 100))
    binned = _bin_indices(u_ok, bins)
    stats, sens, samples = {}, {}, {}
    for name, y in outputs.items():
        y = np.broadcast_to(y, (n,))
        y = y if all_ok else y[ok]
        samples[name] = y
        if n_ok:
            p5, p50, p95 = np.percentile(y, PERCENTILES)
            stats[name] = OutputStats(nominal_out[name], float(p5), float(p50), float(p95),
                                      float(y.mean()), float(y.std()))
        else:
            stats[name] = OutputStats(nominal_out[name], *([np.nan] * 5))
        sens[name] = first_order_indices(y, u_ok, bins, binned) if n_ok > 1 else []
    return UncertaintyResult(case_name=case.name, n=n, seed=seed, n_admissible=n_ok,
                             problems=result.problems(), stats=stats, sensitivity=sens,
                             varying=tuple(uniforms), samples=samples)
