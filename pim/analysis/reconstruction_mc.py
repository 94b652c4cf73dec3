"""Monte Carlo of a reconstruction: the stated uncertainties -> each unknown's 5/50/95 % and
which input drives its spread.

Each sample draws, by inverse CDF from one uniform variate per quantity (common random
numbers, as :mod:`pim.analysis.montecarlo`):

- the case's inputs from its ``[uncertainty]`` table (masses, C, Gamma, ...;
  :func:`pim.model.distributions.sample_inputs`);
- the measured post-impact motion, normal about the measured value with the ``[measured]``
  standard deviations (or, where the case states none, the residual standard error of the
  nominal fit, s = sqrt(cost / (k - n)) for k data and n unknowns: the classic estimate of an
  unstated measurement error, said in the report);
- with ``[evidence]``, the post-impact motion comes instead from the run-out inverse of each
  sample's rest position and heading (normal with the evidence's sigmas) and friction,
  solved for all samples at once (:func:`post_impact_samples`).

Then every sample's inverse PIM is solved at once
(:func:`pim.analysis.inverse_pim.inverse_pim_many`)
from the nominal solution. The percentiles are over the samples whose fit converged (and whose
run-outs reached their evidence) to an admissible impact under the case's law
(:func:`admissible_samples`; the others are counted, with their reasons, in the messages);
the first-order indices (correlation ratio,
:func:`pim.analysis.montecarlo.first_order_indices`) over the same samples rank the inputs.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..model.crush import crush_energy
from ..model.distributions import Distribution, UncertaintyTable, nominal_values, sample_inputs
from ..model.evidence_terms import (
    DELTA_V_SCALE,
    CrushEnergyTerm,
    EvidenceTerm,
    as_residual_terms,
    split_terms,
)
from ..model.law import solve as solve_under_law
from ..model.numbers import InputError, checked_count, speed_text
from .fitting import FitResult
from .free_inputs import STATE, fields_set_by, free_inputs, friction_floor, law_values
from .inverse_pim import inverse_pim_many
from .montecarlo import PERCENTILES, first_order_indices, sampled_case
from .residuals import measured_terms, residual_terms

__all__ = ["UnknownStats", "ReconstructionSamples", "reconstruction_samples",
           "residual_standard_error", "SampleBlock", "solve_samples", "summarise",
           "admissible_samples", "rest_draws", "through_event_counts"]


@dataclass(frozen=True)
class UnknownStats:
    """One unknown over the Monte Carlo samples [SI].

    Attributes
    ----------
    name : str
        The unknown's key (e.g. "vehicle1.speed").
    nominal : float
        Its value in the nominal fit [SI: the unknown's unit, m/s, m, rad or -].
    p5, p50, p95 : float
        5th, 50th and 95th percentiles over the used samples [SI] (NaN when none).
    mean, std : float
        Mean and standard deviation (population, ddof 0) over the used samples [SI].
    drivers : list of (str, float)
        (input, first-order index [-]) by decreasing index
        (:func:`pim.analysis.montecarlo.first_order_indices`).
    """

    name: str
    nominal: float
    p5: float
    p50: float
    p95: float
    mean: float
    std: float
    drivers: list


@dataclass(frozen=True)
class ReconstructionSamples:
    """Outcome of :func:`reconstruction_samples`.

    Attributes
    ----------
    n : int
        Samples drawn.
    n_used : int
        Samples whose fit converged (and, with evidence, whose run-out reached the rest
        evidence and stopped).
    stats : dict
        Unknown key -> :class:`UnknownStats`.
    samples : dict
        Unknown key -> its values over the used samples [SI].
    varying : tuple of str
        The quantities that varied (inputs, measured components, evidence).
    measured_sigma_source : str
        "stated" or "residual standard error".
    messages : list of str
    through_event : dict or None
        When each sample's post-impact motion was fitted through the event
        (:func:`pim.analysis.event_samples.event_sampler`): how many samples were fitted,
        ``converged`` (``fast``: by secant steps from the nominal fit, ``refitted``: by the
        full fit) and ``unconverged`` (left out); None otherwise.
    """

    n: int
    n_used: int
    stats: dict
    samples: dict
    varying: tuple
    measured_sigma_source: str
    messages: list
    through_event: dict | None = None

    def to_dict(self) -> dict:
        """JSON-ready: samples drawn and used, where the measured values' sigmas come from,
        and the fits through the event's counts (None without)."""
        return {"samples": self.n, "used": self.n_used,
                "sigma_source": self.measured_sigma_source,
                "through_event": self.through_event}


def residual_standard_error(fit_result: FitResult) -> float:
    """s = sqrt(cost / (k - n)) of an unweighted fit [m/s] (NaN without degrees of freedom)."""
    k = len(fit_result.residual_names)
    n = len(fit_result.fitted_keys)
    return float(np.sqrt(fit_result.cost / (k - n))) if k > n else float("nan")


def _measured_sigmas(case, names, fit_result) -> tuple[np.ndarray, str]:
    """Per residual term: the sigma of the measured value [m/s or rad/s] and its source."""
    sig = [t.sigma_of(case.measured) for t in as_residual_terms(names)]
    if all(s is not None for s in sig):
        return np.array(sig), "stated"
    s = residual_standard_error(fit_result)
    if not np.isfinite(s):
        raise InputError("measured: no standard deviations are stated and the fit has no "
                         "degrees of freedom to estimate them; give *_sigma in [measured]")
    _, _, scale = residual_terms(case, names)      # 1 for velocities, k_i for yaw rates
    return s / scale, "residual standard error"


def reconstruction_samples(case, fit_result: FitResult, unknown: dict, n: int = 10_000,
                           seed: int = 0, *,
                           distributions: UncertaintyTable | None = None,
                           include_yaw: bool = True, post_impact=None,
                           extra_nominal: dict | None = None) -> ReconstructionSamples:
    """Monte Carlo of the inverse PIM over the stated uncertainties (module notes).

    Parameters
    ----------
    case : Case
        Single case with ``measured`` (the nominal post-impact motion).
    fit_result : FitResult
        The nominal inverse PIM (:func:`pim.analysis.inverse_pim.inverse_pim`) of ``case``.
    unknown : dict
        The unknowns' bounds [SI], as given to the nominal fit.
    n : int
        Number of samples (>= 10).
    seed : int
        Seed of numpy's default generator.
    distributions : UncertaintyTable, optional
        Default ``case.uncertainty`` (may be None: then only the measured motion varies).
    include_yaw : bool
        As in the nominal fit.
    post_impact : callable, optional
        ``post_impact(values, uniforms, rng, n) -> (targets (n, k), ok (n,), uniforms)``:
        the post-impact motion per sample from the evidence (the run-out inverse,
        :func:`pim.analysis.reconstruction.evidence_sampler`); default: the measured motion
        drawn with its sigmas. A fourth item, when returned, is a dict of counts (the fits
        through the event's, :attr:`SampleBlock.counts`).
    extra_nominal : dict, optional
        Nominal values of the evidence inputs (``evidence.vehicleN.friction``) that the
        ``[uncertainty]`` table may vary.
    """
    n = checked_count(n, "n (samples)", low=10)
    block = solve_samples(case, fit_result, unknown, n, np.random.default_rng(seed),
                          distributions=distributions, include_yaw=include_yaw,
                          post_impact=post_impact, extra_nominal=extra_nominal)
    return summarise(fit_result, [block])


@dataclass(frozen=True)
class SampleBlock:
    """Raw Monte Carlo samples of a reconstruction (one block; blocks concatenate).

    Attributes
    ----------
    x : ndarray (n, n_unknowns)
        Each sample's solved unknowns, in the order of the nominal fit's ``values`` [SI:
        each unknown's own unit, m/s, m, rad or -]; an unreached ``impact.mu_c`` is
        replaced by its lower bound.
    ok : ndarray of bool (n,)
        The samples used (fit converged, finite, an admissible impact under the case's law,
        and with a post-impact model, its run-out reaching the evidence).
    uniforms : dict of str to ndarray (n,)
        Varying quantity -> the uniform variate in (0, 1) it was drawn from [-].
    source : str
        Where the measured values' sigmas come from: "stated", "residual standard error",
        or "evidence" (drawn by a post-impact model).
    messages : list of str
        Notes on the sampling, in words.
    floored : ndarray of bool (n,) or None
        The samples whose ``impact.mu_c`` is only a lower bound (None: none).
    inadmissible : dict of str to int
        Why solved samples were left out as inadmissible impacts: reason
        (:meth:`pim.Result.problem_counts`) -> how many (a sample may fail several).
    n_inadmissible : int
        How many solved samples were left out as inadmissible impacts.
    counts : dict of str to int
        The post-impact model's counts (the fits through the event's:
        :attr:`pim.analysis.event_samples.EventSamples.counts`); empty without.
    """

    x: np.ndarray
    ok: np.ndarray
    uniforms: dict
    source: str
    messages: list
    floored: np.ndarray | None = None
    inadmissible: dict = field(default_factory=dict)
    n_inadmissible: int = 0
    counts: dict = field(default_factory=dict)


def solve_samples(case, fit_result: FitResult, unknown: dict, n: int, rng, *,
                  distributions: UncertaintyTable | None = None, include_yaw: bool = True,
                  post_impact=None, extra_nominal: dict | None = None) -> SampleBlock:
    """Draw ``n`` samples with ``rng`` and solve their inverse problems (module notes; the
    parameters are those of :func:`reconstruction_samples`)."""
    n = int(n)
    dists = case.uncertainty if distributions is None else distributions
    keys = tuple(fit_result.values)
    eps0 = fit_result.eps
    beta0 = fit_result.beta
    names = measured_terms(case, include_yaw)
    evidence = split_terms(names)[1]
    scales = _delta_v_scales(dists, evidence)
    nominal = {**nominal_values(case, eps0, beta0), **(extra_nominal or {}),
               **law_values(fit_result.law, fit_result.contact_friction),
               **dict.fromkeys(scales, 1.0), **crush_nominal(case)}
    solved = {f for k in keys for f in fields_set_by(k)}
    uncertain = UncertaintyTable({**{k: d for k, d in (dists.inputs.items() if dists else ())
                                     if k not in solved and k in nominal}, **scales})
    values, uniforms = sample_inputs(uncertain, nominal, n, rng)
    rows, target, factor = residual_terms(case, names)
    names = tuple(crush_sampled(t, case, values, rng, n) if isinstance(t, CrushEnergyTerm)
                  else t for t in names)
    evidence = split_terms(names)[1]
    messages, counts = [], {}
    if post_impact is None:
        targets, source = _draw_measured(case, names, fit_result, target, rng, uniforms, n,
                                         messages)
        ok_post = np.ones(n, dtype=bool)
    else:
        targets, ok_post, extra, *more = post_impact(values, uniforms, rng, n)
        counts = dict(more[0]) if more else {}
        uniforms.update(extra)
        first = len(names) - len(evidence)        # the evidence terms beside the run-outs
        targets[:, first:] = _draw_measured(case, evidence, fit_result, target[first:], rng,
                                            uniforms, n, messages)[0]
        source = "evidence"
    targets, factor = _recorder_scale(names, targets, factor, values, n)
    base = np.stack([np.broadcast_to(np.asarray(values[name], dtype=float), (n,))
                     for name in STATE], axis=-1)
    bounds = [unknown[k] for k in keys]
    x0 = np.array([fit_result.values[k] for k in keys])
    out = inverse_pim_many(base, keys, bounds, x0, rows, targets, factor, evidence=evidence)
    ok = out.converged & ok_post & np.all(np.isfinite(out.x), axis=1)
    x, floored = friction_floor(base, keys, out.x)     # an unreached mu_c: its lower bound
    solved = np.flatnonzero(ok)
    admissible, reasons = admissible_samples(case, free_inputs(base[solved], keys, x[solved])[0],
                                             fit_result.law)
    ok[solved[~admissible]] = False
    return SampleBlock(x, ok, uniforms, source, messages, floored,
                       {text: bad for text, bad, _ in reasons}, int(np.size(admissible)
                                                                    - np.count_nonzero(admissible)),
                       counts=counts)


def admissible_samples(case, state, law: str) -> tuple[np.ndarray, list]:
    """Whether each solved sample is an admissible impact under ``law``, and why not.

    Parameters
    ----------
    case : Case
        The case sampled (its outlines, and which vehicle is a fixed obstacle).
    state : ndarray (m, 23)
        The samples' full states (:data:`pim.analysis.free_inputs.STATE`) with the solved
        unknowns put in [SI].
    law : str
        The impact law the inverse PIM applied.

    Returns
    -------
    admissible : ndarray of bool (m,)
        :attr:`pim.Result.admissible` of each sample's answer.
    counts : list of (str, int, int)
        :meth:`pim.Result.problem_counts` of the samples.
    """
    state = np.asarray(state, dtype=float)
    if not len(state):
        return np.ones(0, bool), []
    v = {name: state[:, k] for k, name in enumerate(STATE)}
    beta = None if law == "kudlich-slibar" else v["impact.beta"]
    friction = None if law == "brach" else v["impact.contact_friction"]
    result = solve_under_law(sampled_case(case, v), v["impact.restitution"], beta, law=law,
                             mu_c=friction)
    return np.broadcast_to(result.admissible, (len(state),)), result.problem_counts()


def rest_draws(ev, i: int, rng, n: int) -> tuple:
    """Vehicle ``i``'s rest position (n, 2) [m] and heading (n,) [rad] drawn normal about its
    evidence ``ev`` (:class:`pim.model.evidence.VehicleEvidence`) with its sigmas, by inverse
    CDF from one uniform variate each (for the driver attribution); returns them and the
    variates by name (``evidence.vehicleN.rest_position_x``, ``_y``, ``rest_heading``)."""
    from scipy.special import ndtri

    u = {f"evidence.vehicle{i}.{key}": rng.random(n) + 2.0**-54
         for key in ("rest_position_x", "rest_position_y", "rest_heading")}
    x, y, h = u.values()
    rest = np.stack([ev.rest_position[0] + ev.position_sigma * ndtri(x),
                     ev.rest_position[1] + ev.position_sigma * ndtri(y)], axis=-1)
    return rest, ev.rest_heading + ev.heading_sigma * ndtri(h), u


def _draw_measured(case, names, fit_result, target, rng, uniforms, n, messages):
    """The measured values of ``names`` per sample, normal about ``target`` with their
    sigmas (stated, or the residual standard error of the nominal fit, said in
    ``messages``); the uniform variates go into ``uniforms``. Returns (targets (n, k),
    source)."""
    from scipy.special import ndtri

    sigma, source = _measured_sigmas(case, names, fit_result)
    targets = np.empty((n, len(names)))
    for j, term in enumerate(names):
        if isinstance(term, CrushEnergyTerm):     # its energies are drawn inside it
            targets[:, j] = target[j]
            continue
        u = rng.random(n) + 2.0**-54
        uniforms[f"measured.{term.name}"] = u
        targets[:, j] = target[j] + sigma[j] * ndtri(u)
    if source != "stated":
        messages.append(f"measured: no standard deviations stated; the residual standard "
                        f"error of the nominal fit "
                        f"({speed_text(residual_standard_error(fit_result), '.3g')}) stands "
                        f"for them")
    return targets, source


#: The crush inputs an ``[uncertainty]`` table may vary (``evidence.vehicleN.crush.<key>``).
CRUSH_INPUTS = ("stiffness_a", "stiffness_b", "width", "depth_scale")


def crush_nominal(case) -> dict:
    """Nominal values of the crush inputs of :data:`CRUSH_INPUTS` [SI] (depth_scale 1)."""
    ev = case.evidence
    out = {}
    for i, p in ({} if ev is None else ev.crush).items():
        key = f"evidence.vehicle{i}.crush."
        out.update({key + "stiffness_a": p.stiffness_a, key + "stiffness_b": p.stiffness_b,
                    key + "width": p.width, key + "depth_scale": 1.0})
    return out


def crush_sampled(term: CrushEnergyTerm, case, values: dict, rng, n: int) -> CrushEnergyTerm:
    """The crush term with each vehicle's energy per sample: from the sampled crush inputs
    where the ``[uncertainty]`` table varies any of them (:func:`pim.model.crush.crush_energy`),
    else drawn with the profile's own standard deviations
    (:meth:`pim.model.crush.CrushProfile.sample_energy`)."""
    energies = list(term.energies)
    for i, p in case.evidence.crush.items():
        key = {k: f"evidence.vehicle{i}.crush.{k}" for k in CRUSH_INPUTS}
        if any(np.ndim(values[k]) for k in key.values()):
            scale = values[key["depth_scale"]]
            energy = crush_energy(values[key["width"]], [c * scale for c in p.depths],
                                  values[key["stiffness_a"]], values[key["stiffness_b"]],
                                  p.stiffness_g)
            energies[i - 1] = np.broadcast_to(np.asarray(energy, dtype=float), (n,))
        else:
            energies[i - 1] = p.sample_energy(rng, n)
    return replace(term, energies=tuple(energies))


def _delta_v_scales(dists, evidence) -> dict:
    """``measured.vehicleN.delta_v_scale`` -> its distribution for every vehicle with a
    recorded delta-V: the ``[uncertainty]`` table's, else uniform on
    :data:`pim.model.evidence_terms.DELTA_V_SCALE`."""
    given = dists.inputs if dists else {}
    out = {}
    for t in evidence:
        if t.kind == "delta_v":
            key = f"measured.vehicle{t.vehicle}.delta_v_scale"
            out[key] = given.get(key, Distribution("uniform", *DELTA_V_SCALE))
    return out


def _recorder_scale(names, targets, factor, values, n) -> tuple:
    """The recorder sees scale x the true delta-V: the residual (s dV - recorded) / sigma is
    (dV - recorded / s) * (s / sigma), so each sample's target is divided and its factor
    multiplied by its scale s."""
    factor = np.broadcast_to(np.asarray(factor, dtype=float), (n, len(names))).copy()
    for j, term in enumerate(names):
        if isinstance(term, EvidenceTerm) and term.kind == "delta_v":
            s = np.broadcast_to(np.asarray(
                values[f"measured.vehicle{term.vehicle}.delta_v_scale"], dtype=float), (n,))
            targets[:, j] = targets[:, j] / s
            factor[:, j] = factor[:, j] * s
    return targets, factor


def through_event_counts(blocks, messages: list) -> dict | None:
    """The fits through the event's counts summed over ``blocks`` (None when no block's
    samples went through the event), and what they say appended to ``messages``."""
    counts = [b.counts for b in blocks if b.counts]
    if not counts:
        return None
    total = {k: sum(int(c.get(k, 0)) for c in counts) for k in counts[0]}
    n = total["samples"]
    messages.append(
        f"Monte Carlo through the event: each sample's post-impact motion was fitted so that "
        f"its event, further impacts included, ends at its own draw of the rest evidence; "
        f"{total['converged']} of {n} fits converged ({total['fast']} by secant steps from "
        f"the nominal fit, {total['refitted']} by the full fit), "
        f"{total['unconverged']} did not and are left out of the percentiles")
    return total


def summarise(fit_result: FitResult, blocks) -> ReconstructionSamples:
    """Percentiles and drivers of each unknown over the pooled ``blocks`` (SampleBlock)."""
    keys = tuple(fit_result.values)
    x0 = np.array([fit_result.values[k] for k in keys])
    x = np.concatenate([b.x for b in blocks])
    ok = np.concatenate([b.ok for b in blocks])
    uniforms = {k: np.concatenate([b.uniforms[k] for b in blocks]) for k in blocks[0].uniforms}
    messages = list(dict.fromkeys(m for b in blocks for m in b.messages))
    n = len(ok)
    n_used = int(ok.sum())
    through = through_event_counts(blocks, messages)
    bad = sum(b.n_inadmissible for b in blocks)
    if n_used + bad < n:
        messages.append(f"{n - n_used - bad} of {n} samples left out (fit not converged or no "
                        f"post-impact motion reaching the evidence)")
    if bad:
        reasons = {}
        for b in blocks:
            for text, count in b.inadmissible.items():
                reasons[text] = reasons.get(text, 0) + count
        messages.append(f"{bad} of {n} samples ({100 * bad / n:.3g} %) are inadmissible "
                        f"impacts, left out of the percentiles and the drivers: " + "; ".join(
                            f"{text} ({count})" for text, count in reasons.items()))
    floored = np.concatenate([np.zeros(len(b.ok), bool) if b.floored is None else b.floored
                              for b in blocks])[ok]
    if floored.any():
        messages.append(f"impact.mu_c only has a lower bound in {int(floored.sum())} of "
                        f"{n_used} samples (the contact sticks); its percentiles are those "
                        "of that bound")
    u_ok = {k: u[ok] for k, u in uniforms.items()}
    stats, samples = {}, {}
    for j, key in enumerate(keys):
        y = x[ok, j]
        samples[key] = y
        if n_used:
            p5, p50, p95 = np.percentile(y, PERCENTILES)
            drivers = first_order_indices(y, u_ok) if n_used > 1 else []
            stats[key] = UnknownStats(key, float(x0[j]), float(p5), float(p50), float(p95),
                                      float(y.mean()), float(y.std()), drivers)
        else:
            stats[key] = UnknownStats(key, float(x0[j]), *([np.nan] * 5), [])
    return ReconstructionSamples(n=n, n_used=n_used, stats=stats, samples=samples,
                                 varying=tuple(uniforms), measured_sigma_source=blocks[0].source,
                                 messages=messages, through_event=through)
