"""The finite-duration scene tuned to crash tests, and leave-one-out prediction against PIM.

Models of the same test (:mod:`comparisons.studies.crash_records`: masses, inertias,
pre-impact motion, impact point C and contact plane; the geometry is the record's, not
fitted):

* **PIM** (:func:`pim.solve`): epsilon and beta in [0, 1], mu = beta mu0 (:data:`PIM_MODEL`);
* **the scene**, the finite-duration point contact on the compiled integrator
  (:func:`sim.simulate_compliant`, ``engine="numba"``) with the crush's restitution epsilon,
  the contact time T in [:data:`T_BOUNDS`] s (the linear stiffness whose frictionless contact
  lasts T, so one T suits cars of any mass), tyre friction mu_tyre in [0, 1.2] during the
  contact, and one of two tangential laws with one parameter each, a stated choice:

  - Coulomb friction mu_c in [0, :data:`MU_MAX`] between the vehicles (:data:`SCENE_MODEL`);
  - mu_c = b |mu0|, b in [0, :data:`B_MAX`], with mu0 PIM's critical impulse ratio of the
    test (:func:`pim.solve` on the test's own inputs at the scene's epsilon; never its
    outcome) (:data:`SCENE_MU0_MODEL`): PIM's mu = beta mu0 follows mu0 from test to test,
    which one Coulomb mu_c cannot;

* **the scene in physical ranges** (:data:`SCENE_PHYSICAL_MODEL`): the Coulomb scene with its
  parameters boxed to :data:`PHYSICAL_RANGES` (T, mu_c, mu_tyre) and its outputs held inside
  them (the contact's duration and its peak crush, :data:`OUTPUT_RANGES`: every
  :data:`PENALTY_STEP` outside a range adds one to a fitted test's residuals, so a fit leaves
  a range only where the data outweigh that) -- the scene as the crash tests could be, not
  as the fit would make it (issue 34).

**Fits.** Least squares of the residuals of every observed value scaled by 1 mph and
10 deg/s, on the project's one engine (:func:`pim.analysis.least_squares_batch.least_squares_batch`,
batched Levenberg-Marquardt in a box, the Jacobian by forward differences,
:func:`~pim.analysis.least_squares_batch.with_forward_differences`), every start and every
fold of a class in one batch:

* the class fit: :data:`CLASS_STARTS` starts, a scrambled Sobol sample of the box (seed
  :data:`SOBOL_SEED`), each refined to convergence; the best is reported with how many
  starts reached it (rms within :data:`AGREEMENT` of the best's);
* leave-one-out: for each test, the class parameters refitted on the *other* tests from
  :data:`LOO_STARTS` Sobol starts (the same for every fold: independent of the held-out
  test), on the fold's own inputs (:class:`~comparisons.studies.crash_records.InputVariant`:
  no input fitted on the held-out test's outcome), then the held-out test predicted.

Every fit runs to the engine's convergence tests (no evaluation cap short of
:data:`MAX_ITERATIONS`, which the report counts if reached). The fitted scene is checked
against physical ranges (:data:`PHYSICAL_RANGES`: contact time, peak crush, friction between
the vehicles, tyre friction) and flagged outside them.

The scene steps :data:`COARSE_STEPS` per estimated contact time; :func:`coarse_check`
measures it against a 10x finer run at the class parameters.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np
from scipy.stats import qmc

import pim
import sim
from pim.analysis.least_squares_batch import least_squares_batch, with_forward_differences

from .crash_records import (
    CLASS_KEYS,
    MAGNITUDES,
    CrashRecord,
    InputVariant,
    crash_classes,
    fitted_radii,
    input_variants,
)
from .paired_verdict import PairedComparison, compare_paired

__all__ = ["Model", "PIM_MODEL", "SCENE_MODEL", "SCENE_MU0_MODEL", "SCENE_PHYSICAL_MODEL",
           "MODELS", "SCENE_MODELS", "UNCONSTRAINED_MODELS", "OUTPUT_RANGES", "PENALTY_STEP",
           "fit_held",
           "Motion", "run_model", "MultiStartFit", "Prediction", "predict", "VariantStudy",
           "ClassStudy", "fit_class", "study_class", "study_all", "loo_comparisons",
           "coarse_check", "scene_settings", "output_penalty", "sobol_starts", "COARSE_STEPS",
           "FINE_STEPS",
           "MU_MAX", "B_MAX", "T_BOUNDS",
           "TYRE_MAX", "FAILED_RESIDUAL", "SCREEN", "CLASS_STARTS", "LOO_STARTS", "AGREEMENT",
           "SOBOL_SEED", "MAX_ITERATIONS", "PHYSICAL_RANGES", "MEASURES"]

#: Steps per estimated contact time of the fitted scene, and of the check against it.
COARSE_STEPS = 20
FINE_STEPS = 200
MU_MAX = 3.0
B_MAX = 1.5
TYRE_MAX = 1.2
T_BOUNDS = (0.02, 0.3)
#: Scaled residual of each observed value of a scene that fails (no contact, no separation).
FAILED_RESIDUAL = 50.0
#: Points of the Sobol sample every fit screens (the residuals at each, no derivative).
SCREEN = 128
#: Starts refined of a class fit and of each leave-one-out refit, per model: the best
#: points of the screen.
CLASS_STARTS = {"pim": 8, "scene": 16, "scene-mu0": 16, "scene-physical": 16}
LOO_STARTS = {"pim": 4, "scene": 8, "scene-mu0": 8, "scene-physical": 8}
#: A start reached the best when its rms is within this fraction of the best rms.
AGREEMENT = 0.01
SOBOL_SEED = 26
#: Iteration limit of the engine (each iteration one batch); reached: counted, reported.
MAX_ITERATIONS = 200
#: Convergence tests of the engine: relative cost decrease of an accepted step, its length
#: in box-scaled parameters.
FTOL, XTOL = 1e-6, 1e-4
#: Starts closer than this (box-scaled) to a converged start of their fold stop as its copy.
MERGE = 1e-3
#: Physical ranges of the fitted scene (quantity -> (low, high, unit, why)); outside: flagged.
PHYSICAL_RANGES = {
    "contact time": (0.05, 0.25, "s", "full-scale crash pulses last about 70-150 ms, NHTSA "
                                      "10146's 90 ms (docs/pulses.md)"),
    "peak crush": (0.05, 1.2, "m", "the deepest crush of full-scale tests is about 0.75 m "
                                   "frontal (NHTSA 10146) to 1 m in small overlap"),
    "friction": (0.0, 1.0, "-", "sliding friction of sheet metal on sheet metal or a rigid "
                                "barrier is below 1; more is snagging, not friction"),
    "tyre friction": (0.1, 1.0, "-", "dry asphalt peaks at about 0.8-1.0"),
}
#: Outputs of the physical scene held inside :data:`PHYSICAL_RANGES`: Motion attribute ->
#: range name.
OUTPUT_RANGES = (("contact_time", "contact time"), ("peak_crush", "peak crush"))
#: How far outside its range an output of the physical scene goes per unit of added residual
#: (Motion attribute -> [its unit]): 1 ms of contact time, 1 mm of crush weigh as 1 mph.
PENALTY_STEP = {"contact_time": 1e-3, "peak_crush": 1e-3}
#: Per-test error measures of the statistics: name -> Prediction attribute.
MEASURES = {"score": "score", "velocity": "velocity_error", "yaw": "yaw_error"}


@dataclass(frozen=True)
class Model:
    """A model's parameters, their box and its tangential law.

    Attributes
    ----------
    name : str
        Key in reports and JSON ("pim", "scene", "scene-mu0").
    label : str
        Name in prose.
    parameters : tuple of str
        Names of its parameters.
    lower, upper : tuple of float
        Bounds of the parameters [their units].
    law : str
        Its tangential law.
    step : float
        Forward-difference step in box-scaled parameters.
    outputs : tuple
        Outputs held inside their physical ranges while fitting (:data:`OUTPUT_RANGES`
        rows; empty: none).
    options : tuple of (str, object)
        :class:`sim.CompliantSettings` fields the scene runs with changed (a switched-off
        mechanism of :mod:`comparisons.studies.contact_time`; empty: none).
    """

    name: str
    label: str
    parameters: tuple[str, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    law: str
    step: float
    outputs: tuple = ()
    options: tuple = ()


PIM_MODEL = Model("pim", "PIM", ("epsilon", "beta"), (0.0, 0.0), (1.0, 1.0),
                  "mu = beta mu0", 1e-6)
SCENE_MODEL = Model("scene", "the scene (Coulomb mu_c)", ("epsilon", "mu_c", "T [s]", "mu_tyre"),
                    (0.0, 0.0, T_BOUNDS[0], 0.0), (1.0, MU_MAX, T_BOUNDS[1], TYRE_MAX),
                    "Coulomb mu_c", 1e-3)
SCENE_MU0_MODEL = Model("scene-mu0", "the scene (mu_c = b |mu0|)",
                        ("epsilon", "b", "T [s]", "mu_tyre"), (0.0, 0.0, T_BOUNDS[0], 0.0),
                        (1.0, B_MAX, T_BOUNDS[1], TYRE_MAX), "mu_c = b |mu0|", 1e-3)
_RANGE = {name: PHYSICAL_RANGES[label][:2] for name, label in
          (("T", "contact time"), ("mu", "friction"), ("tyre", "tyre friction"))}
SCENE_PHYSICAL_MODEL = Model(
    "scene-physical", "the scene in physical ranges (Coulomb mu_c)",
    ("epsilon", "mu_c", "T [s]", "mu_tyre"),
    (0.0, _RANGE["mu"][0], _RANGE["T"][0], _RANGE["tyre"][0]),
    (1.0, _RANGE["mu"][1], _RANGE["T"][1], _RANGE["tyre"][1]), "Coulomb mu_c", 1e-3,
    outputs=OUTPUT_RANGES)
MODELS = (PIM_MODEL, SCENE_MODEL, SCENE_MU0_MODEL, SCENE_PHYSICAL_MODEL)
#: The scenes compared with PIM; the first two are fitted in their wide boxes.
SCENE_MODELS = (SCENE_MODEL, SCENE_MU0_MODEL, SCENE_PHYSICAL_MODEL)
UNCONSTRAINED_MODELS = (SCENE_MODEL, SCENE_MU0_MODEL)


def scene_settings(steps: int = COARSE_STEPS) -> sim.CompliantSettings:
    """Settings of the fitted scene: ``steps`` per estimated contact time, no recording."""
    return sim.CompliantSettings(record=False, steps_per_contact=int(steps),
                                 min_steps=min(10, int(steps)))


@dataclass(frozen=True)
class Motion:
    """A model's post-impact motion of a batch of cases [SI].

    Attributes
    ----------
    velocity1, velocity2 : ndarray (..., 2)
        Post-impact CG velocities [m/s].
    yaw_rate1, yaw_rate2 : ndarray
        Post-impact yaw rates [rad/s].
    ok : ndarray of bool
        The model ran (the scene separated).
    contact_time : ndarray
        Duration of the contact [s] (NaN for PIM).
    peak_crush : ndarray
        Deepest crush [m] (NaN for PIM).
    friction : ndarray
        Friction between the vehicles [-]: mu_c of the scene, mu = beta mu0 of PIM.
    """

    velocity1: np.ndarray
    yaw_rate1: np.ndarray
    velocity2: np.ndarray
    yaw_rate2: np.ndarray
    ok: np.ndarray
    contact_time: np.ndarray
    peak_crush: np.ndarray
    friction: np.ndarray


def _mu0(case: pim.Case, eps) -> np.ndarray:
    """PIM's critical impulse ratio of ``case`` at restitution ``eps`` (inputs only)."""
    return np.asarray(pim.solve(case, eps, 1.0, backend="numpy").mu0, dtype=float)


def run_model(model: Model, case: pim.Case, x, steps: int = COARSE_STEPS) -> Motion:
    """``model`` on ``case`` at parameters ``x`` (..., n), broadcast with the case's shape."""
    x = np.asarray(x, dtype=float)
    if model is PIM_MODEL or model.name == "pim":
        r = pim.solve(case, x[..., 0], x[..., 1], backend="numpy")
        nan = np.full(np.shape(r.yaw_rate1), np.nan)
        return Motion(r.velocity1, r.yaw_rate1, r.velocity2, r.yaw_rate2,
                      np.isfinite(r.yaw_rate1), nan, nan, x[..., 1] * np.abs(r.mu0))
    eps = x[..., 0]
    mu = x[..., 1] if model.law == SCENE_MODEL.law else x[..., 1] * np.abs(_mu0(case, eps))
    settings = scene_settings(steps)
    if model.options:
        settings = replace(settings, **dict(model.options))
    b = sim.simulate_compliant(case, eps, friction=mu, tyre_friction=x[..., 3],
                               contact_time=x[..., 2], settings=settings, engine="numba")
    return Motion(b.velocity1, b.yaw_rate1, b.velocity2, b.yaw_rate2, b.ok,
                  b.contact_duration, b.peak_crush, np.broadcast_to(mu, b.status.shape))


def _failed(r: np.ndarray, ok) -> np.ndarray:
    """``r`` with :data:`FAILED_RESIDUAL` where the model failed or gave no finite value."""
    bad = ~np.asarray(ok, dtype=bool)[..., None] | ~np.isfinite(r)
    return np.where(bad, FAILED_RESIDUAL, r)


def output_penalty(model: Model, motion: Motion) -> np.ndarray:
    """The residuals (..., j) that hold ``model``'s outputs inside their physical ranges:
    per output of ``model.outputs``, its distance outside the range [low, high] of
    :data:`PHYSICAL_RANGES` over :data:`PENALTY_STEP` (0 inside; 0 where the scene failed,
    which :data:`FAILED_RESIDUAL` charges already)."""
    parts = []
    for attr, name in model.outputs:
        low, high = PHYSICAL_RANGES[name][:2]
        v = np.asarray(getattr(motion, attr), dtype=float)
        out = np.maximum(low - v, 0.0) + np.maximum(v - high, 0.0)
        parts.append(np.where(np.isfinite(out) & np.asarray(motion.ok, bool), out, 0.0)
                     / PENALTY_STEP[attr])
    shape = np.shape(motion.ok)
    return np.stack(parts, axis=-1) if parts else np.zeros(shape + (0,))


def _residuals(record: CrashRecord, case: pim.Case, motion: Motion,
               model: Model | None = None) -> np.ndarray:
    """Scaled residuals (..., k) of a record; :data:`FAILED_RESIDUAL` where the model failed;
    with ``model``, its :func:`output_penalty` after them."""
    obs = record.observe(case, motion.velocity1, motion.yaw_rate1, motion.velocity2,
                         motion.yaw_rate2)
    r = _failed((obs - record.observed) / record.scale, motion.ok)
    if model is None or not model.outputs:
        return r
    return np.concatenate([r, output_penalty(model, motion)], axis=-1)


def sobol_starts(model: Model, count: int, seed: int = SOBOL_SEED) -> np.ndarray:
    """``count`` starts (count, n) in the model's box: a scrambled Sobol sample."""
    lo, hi = np.array(model.lower), np.array(model.upper)
    u = qmc.Sobol(len(lo), scramble=True, seed=seed).random(int(count))
    return lo + u * (hi - lo)


@dataclass(frozen=True)
class MultiStartFit:
    """The best of a multi-start least-squares fit (one class fit or one fold's refit).

    Attributes
    ----------
    x : tuple of float
        The best parameters [their units].
    rms : float
        Its root-mean-square scaled residual [-].
    starts : int
        Starts run.
    agreeing : int
        Starts whose rms came within :data:`AGREEMENT` of the best's.
    converged : int
        Starts that met the engine's convergence tests (the rest hit :data:`MAX_ITERATIONS`).
    on_bound : tuple of str
        Parameters of the best that sit on a bound.
    """

    x: tuple
    rms: float
    starts: int
    agreeing: int
    converged: int
    on_bound: tuple


def _summaries(names, fit, folds, residual_counts) -> dict:
    """fold -> :class:`MultiStartFit` of the rows of ``fit`` in that fold (``names``: the
    parameters' names)."""
    out = {}
    for f in np.unique(folds):
        rows = np.flatnonzero(folds == f)
        rms = np.sqrt(fit.cost[rows] / residual_counts[f])
        best = rows[int(np.argmin(rms))]
        out[int(f)] = MultiStartFit(
            tuple(float(v) for v in fit.x[best]), float(rms.min()), int(rows.size),
            int(np.sum(rms <= rms.min() * (1.0 + AGREEMENT) + 1e-12)),
            int(fit.converged[rows].sum()),
            tuple(p for p, b in zip(names, fit.on_bound[best], strict=True) if b))
    return out


_VEHICLE_ARRAYS = ("mass", "yaw_inertia", "cg", "velocity", "yaw_rate", "heading")


def _stacked(cases: list, shape: tuple) -> pim.Case | None:
    """The cases, each broadcast to ``shape``, stacked along a new first axis, or None when
    their outlines differ (``length``, ``width``, ``cg_to_front`` are one number per case):
    one batch for the simulator instead of one call per case."""

    def stack(get, vector=False):
        tail = (2,) if vector else ()
        return np.stack([np.broadcast_to(np.asarray(get(c), float), shape + tail)
                         for c in cases])

    vehicles = []
    for which in ("vehicle1", "vehicle2"):
        first = getattr(cases[0], which)
        outline = (first.length, first.width, first.cg_to_front)
        if any((getattr(c, which).length, getattr(c, which).width,
                getattr(c, which).cg_to_front) != outline for c in cases):
            return None
        vehicles.append(replace(first, **{f: stack(lambda c, f=f, w=which:
                                                   getattr(getattr(c, w), f),
                                                    f in ("cg", "velocity"))
                                           for f in _VEHICLE_ARRAYS}))
    impact = replace(cases[0].impact, point=stack(lambda c: c.impact.point, True),
                     normal_angle=stack(lambda c: c.impact.normal_angle))
    return replace(cases[0], vehicle1=vehicles[0], vehicle2=vehicles[1], impact=impact,
                   measured=None)


def _fold_residuals(model, records, variant, steps, bar):
    """``residuals(x, folds)``: the scaled residuals (p, q, n k) of ``model`` at the points
    ``x`` (p, q, n), row i in fold ``folds[i]`` (the held-out test's residuals zeroed); the
    tests of a class run as one batch where their cases stack (:func:`_stacked`)."""
    n = len(records)
    observed = np.array([r.observed for r in records])[:, None, None, :]
    scale = np.array([r.scale for r in records])[:, None, None, :]

    def residuals(x, folds):
        cases = [variant.case(t, rec, folds[:, None]) for t, rec in enumerate(records)]
        stacked = _stacked(cases, (len(folds), 1))
        if stacked is None:
            r = np.stack([_residuals(rec, case, run_model(model, case, x, steps), model)
                          for rec, case in zip(records, cases, strict=True)])
        else:
            m = run_model(model, stacked, x[None], steps)
            obs = records[0].observe(stacked, m.velocity1, m.yaw_rate1, m.velocity2,
                                     m.yaw_rate2)
            r = np.concatenate([_failed((obs - observed) / scale, m.ok),
                                output_penalty(model, m)], axis=-1)
        r = r * (folds[None, :] != np.arange(n)[:, None])[:, :, None, None]
        if bar is not None:
            bar.update(x.shape[0] * x.shape[1] * n)
        return np.moveaxis(r, 0, 2).reshape(x.shape[0], x.shape[1], -1)

    return residuals


def _screened_starts(residuals, model, folds_run, counts) -> tuple[np.ndarray, np.ndarray]:
    """The starts of each fold: its ``counts[fold]`` best points of a :data:`SCREEN`-point
    Sobol sample (the same sample for every fold). Returns (folds (m,), starts (m, n))."""
    sample = sobol_starts(model, SCREEN)
    x = np.broadcast_to(sample, (len(folds_run),) + sample.shape)
    cost = np.sum(residuals(x, np.asarray(folds_run)) ** 2, axis=-1)      # (F, SCREEN)
    folds, starts = [], []
    for i, f in enumerate(folds_run):
        best = np.argsort(cost[i], kind="stable")[:counts[f]]
        folds += [f] * len(best)
        starts.append(sample[best])
    return np.array(folds, dtype=int), np.concatenate(starts)


def fit_class(model: Model, records: list, variant: InputVariant, *, loo: bool = True,
              steps: int = COARSE_STEPS, bar=None) -> dict:
    """The class fit and (``loo``) every leave-one-out refit of ``model``, in one batch.

    Returns fold -> :class:`MultiStartFit`: fold f < n the refit without test f, fold n
    (``len(records)``) the class fit on every test (module notes).
    """
    n = len(records)
    residuals = _fold_residuals(model, records, variant, steps, bar)
    folds_run = [n] + (list(range(n)) if loo else [])
    counts = {f: LOO_STARTS[model.name] for f in range(n)} | {n: CLASS_STARTS[model.name]}
    folds, starts = _screened_starts(residuals, model, folds_run, counts)
    lo, hi = np.array(model.lower), np.array(model.upper)
    fun = with_forward_differences(lambda x, idx: residuals(x, folds[idx]), lo, hi, model.step)
    fit = least_squares_batch(fun, starts, lo, hi, max_iter=MAX_ITERATIONS, ftol=FTOL,
                              xtol=XTOL, merge=MERGE, groups=folds)
    k = len(records[0].observed)
    return _summaries(model.parameters, fit, folds,
                      {f: k * (n - 1) for f in range(n)} | {n: k * n})


def _with_held(x, held: dict, groups, n: int) -> np.ndarray:
    """The free parameters ``x`` (p, q, f) completed with the held ones (index -> values per
    group) into (p, q, n), row i taking the values of group ``groups[i]``."""
    out = np.empty(x.shape[:-1] + (n,))
    free = [i for i in range(n) if i not in held]
    out[..., free] = x
    for i, values in held.items():
        out[..., i] = np.asarray(values, dtype=float)[groups][:, None]
    return out


def fit_held(model: Model, records: list, variant: InputVariant, held: dict, *,
             starts: int = 4, screen: int = 64, steps: int = COARSE_STEPS,
             bar=None) -> list[MultiStartFit]:
    """Class fits of ``model`` with parameters held: ``held`` maps a parameter's index to its
    values, one per fit (every entry of one length g; empty: one fit, nothing held);
    returns the g fits in that order.

    Each fit screens the same ``screen``-point Sobol sample of the free parameters' box and
    refines its best ``starts`` on the batched engine, every fit in one batch (the class
    fit's inputs, fold n of ``variant``); the profile of a parameter is the held fits over
    a grid of its values.
    """
    n, n_par = len(records), len(model.parameters)
    g = len(next(iter(held.values()))) if held else 1
    residuals = _fold_residuals(model, records, variant, steps, bar)
    free = [i for i in range(n_par) if i not in held]
    lo, hi = np.array(model.lower)[free], np.array(model.upper)[free]

    def fun(x, groups):
        return residuals(_with_held(x, held, groups, n_par), np.full(len(groups), n))

    sample = lo + qmc.Sobol(len(free), scramble=True, seed=SOBOL_SEED).random(screen) * (hi - lo)
    cost = np.sum(fun(np.broadcast_to(sample, (g,) + sample.shape), np.arange(g)) ** 2, -1)
    best = np.argsort(cost, axis=1, kind="stable")[:, :starts]
    groups = np.repeat(np.arange(g), best.shape[1])
    fit = least_squares_batch(
        with_forward_differences(lambda x, idx: fun(x, groups[idx]), lo, hi, model.step),
        sample[best.reshape(-1)], lo, hi, max_iter=MAX_ITERATIONS, ftol=FTOL, xtol=XTOL,
        merge=MERGE, groups=groups)
    full = _with_held(fit.x[:, None, :], held, groups, n_par)[:, 0, :]
    bound = np.zeros(full.shape, dtype=fit.on_bound.dtype)
    bound[:, free] = fit.on_bound
    fits = _summaries(model.parameters, replace(fit, x=full, on_bound=bound), groups,
                      dict.fromkeys(range(g), len(records[0].observed) * n))
    return [fits[j] for j in range(g)]


@dataclass(frozen=True)
class Prediction:
    """One model's prediction of one test with one parameter set, and its errors [SI].

    Errors are per moving vehicle, the largest kept; NaN when the scene failed.

    Attributes
    ----------
    crash_class : str
        The test's crash class.
    test : str
        The test's name.
    model : str
        The model's name (:class:`Model`).
    kind : str
        "class fit" or "leave-one-out".
    variant : str
        The input variant (:class:`~comparisons.studies.crash_records.InputVariant`).
    x : tuple of float
        The parameters used [their units].
    score : float
        Root-mean-square of the test's residuals scaled by 1 mph and 10 deg/s [-]: the
        fits' objective, and the statistics' main measure.
    delta_v_error : float
        |dV predicted| - |dV measured|, signed, of the vehicle where it is largest [m/s].
    velocity_error : float
        Length of the post-impact velocity error vector [m/s] (the |dV| error where the
        test gives magnitudes only).
    yaw_error : float
        |omega predicted - omega measured| [rad/s].
    contact_time, peak_crush, friction, tyre_friction : float
        The scene's contact time [s], deepest crush [m], friction between the vehicles and
        tyre friction [-] (NaN, or PIM's mu = beta mu0, for PIM).
    flags : tuple of str
        The quantities outside :data:`PHYSICAL_RANGES`.
    """

    crash_class: str
    test: str
    model: str
    kind: str
    variant: str
    x: tuple
    score: float
    delta_v_error: float
    velocity_error: float
    yaw_error: float
    contact_time: float
    peak_crush: float
    friction: float
    tyre_friction: float
    flags: tuple


def _errors(record: CrashRecord, case: pim.Case, motion: Motion) -> dict:
    """score, delta_v_error, velocity_error, yaw_error of one scalar prediction."""
    if not bool(motion.ok):
        return dict.fromkeys(("score", "delta_v_error", "velocity_error", "yaw_error"),
                             math.nan)
    pred = record.observe(case, motion.velocity1, motion.yaw_rate1, motion.velocity2,
                          motion.yaw_rate2)
    score = float(np.sqrt(np.mean(((pred - record.observed) / record.scale) ** 2)))
    if record.observable == MAGNITUDES:          # (|dV|, |dw|) per vehicle
        d = (pred - record.observed).reshape(-1, 2)
        dv = d[:, 0]
        return {"score": score, "delta_v_error": float(dv[np.argmax(np.abs(dv))]),
                "velocity_error": float(np.max(np.abs(dv))),
                "yaw_error": float(np.max(np.abs(d[:, 1])))}
    obs, p = record.observed.reshape(-1, 3), pred.reshape(-1, 3)
    pre = [np.asarray(case.vehicle1.velocity, float), np.asarray(case.vehicle2.velocity, float)]
    dv = [float(np.hypot(*(p[i, :2] - pre[i])) - np.hypot(*(obs[i, :2] - pre[i])))
          for i in range(len(obs))]
    return {"score": score, "delta_v_error": max(dv, key=abs),
            "velocity_error": float(np.max(np.hypot(*(p[:, :2] - obs[:, :2]).T))),
            "yaw_error": float(np.max(np.abs(p[:, 2] - obs[:, 2])))}


def _flags(values: dict) -> tuple:
    out = []
    for name, (low, high, _, _) in PHYSICAL_RANGES.items():
        v = values.get(name, math.nan)
        if math.isfinite(v) and not low <= v <= high:
            out.append(name)
    return tuple(out)


def predict(model: Model, record: CrashRecord, case: pim.Case, x, labels: tuple,
            steps: int = COARSE_STEPS) -> Prediction:
    """``model``'s :class:`Prediction` of ``record`` (its inputs ``case``) at parameters
    ``x``, its errors and physical-range flags; ``labels`` = (kind, variant name)."""
    m = run_model(model, case, x, steps)
    scalar = {k: float(np.asarray(getattr(m, k)).reshape(-1)[0])
              for k in ("contact_time", "peak_crush", "friction")}
    tyre = float(x[3]) if model is not PIM_MODEL else math.nan
    checks = {"contact time": scalar["contact_time"], "peak crush": scalar["peak_crush"],
              "friction": scalar["friction"] if model is not PIM_MODEL else math.nan,
              "tyre friction": tyre}
    return Prediction(record.crash_class, record.name, model.name, *labels,
                      tuple(float(v) for v in x), **_errors(record, case, m), **scalar,
                      tyre_friction=tyre, flags=_flags(checks) if model is not PIM_MODEL
                      else ())


@dataclass(frozen=True, eq=False)
class VariantStudy:
    """One class under one input variant: every model's fits, predictions and the
    statistics of the leave-one-out errors.

    Attributes
    ----------
    variant : InputVariant
        The inputs of every fold.
    predictions : tuple of Prediction
        "class fit" and "leave-one-out" rows of every model.
    class_fits : dict
        Model name -> :class:`MultiStartFit` of the class fit.
    loo_fits : dict
        Model name -> tuple of :class:`MultiStartFit`, one per held-out test (empty below
        three tests).
    comparisons : dict
        Scene model name -> measure (:data:`MEASURES`) -> :class:`PairedComparison` of PIM
        against it on the leave-one-out errors.
    """

    variant: InputVariant
    predictions: tuple
    class_fits: dict
    loo_fits: dict
    comparisons: dict

    def rows(self, model: str, kind: str) -> list[Prediction]:
        """The predictions of one model and kind, in the class's test order."""
        return [p for p in self.predictions if p.model == model and p.kind == kind]

    @property
    def verdict(self) -> PairedComparison:
        """PIM against the scene with Coulomb friction, on the score: the class's verdict."""
        return self.comparisons[SCENE_MODEL.name]["score"]


@dataclass(frozen=True, eq=False)
class ClassStudy:
    """One crash class studied under each of its input variants.

    Attributes
    ----------
    crash_class : str
        The class's name.
    tests : tuple of str
        Names of its tests.
    observable : str
        What the models are fitted to and judged on.
    outcome_origin : str
        Where the observed outcome comes from (measured, or a published PIM analysis).
    n_parameters : int
        Parameters of the larger model (the class-size rule of the verdict).
    variants : tuple of VariantStudy
        One per input variant.
    coarse_check : tuple of float
        Largest difference of the coarse scene from a 10x finer one at the class parameters
        (first variant, Coulomb scene, first three tests): (speed [m/s], yaw rate [rad/s]).
    wall_time : float
        Wall time of the study [s].
    profile : object
        The class fit over held contact times
        (:class:`comparisons.studies.contact_time.Profile`, first variant), or None.
    mechanisms : tuple
        :class:`comparisons.studies.contact_time.MechanismResult` of each mechanism
        switched off (the class :func:`comparisons.studies.contact_time.study_classes`
        studies them on; empty for the others).
    """

    crash_class: str
    tests: tuple
    observable: str
    outcome_origin: str
    n_parameters: int
    variants: tuple
    coarse_check: tuple
    wall_time: float
    profile: object = None
    mechanisms: tuple = ()


def loo_comparisons(predictions, n_parameters: int) -> dict:
    """Scene model -> measure -> PIM against it on the leave-one-out rows."""
    def errors(model, attr):
        return [getattr(p, attr) for p in predictions
                if p.model == model and p.kind == "leave-one-out"]

    return {s.name: {m: compare_paired(errors("pim", a), errors(s.name, a), n_parameters)
                     for m, a in MEASURES.items()} for s in SCENE_MODELS}


def _study_variant(records, variant, steps, bar) -> VariantStudy:
    n, preds, class_fits, loo_fits = len(records), [], {}, {}
    for model in MODELS:
        fits = fit_class(model, records, variant, loo=n >= 3, steps=steps, bar=bar)
        class_fits[model.name] = fits[n]
        loo_fits[model.name] = tuple(fits[f] for f in range(n) if f in fits)
        for t, rec in enumerate(records):
            case = variant.case(t, rec, n)
            preds.append(predict(model, rec, case, fits[n].x, ("class fit", variant.name),
                                  steps))
            if t in fits:
                preds.append(predict(model, rec, variant.case(t, rec, t), fits[t].x,
                                      ("leave-one-out", variant.name), steps))
    n_parameters = max(len(m.parameters) for m in MODELS)
    return VariantStudy(variant, tuple(preds), class_fits, loo_fits,
                        loo_comparisons(preds, n_parameters))


def coarse_check(record: CrashRecord, case: pim.Case, x, steps: int = COARSE_STEPS):
    """Largest |coarse - fine| scene prediction of ``record`` at parameters ``x`` of the
    Coulomb scene: (speed difference [m/s], yaw-rate difference [rad/s]); the fine run takes
    10x the steps."""
    a, b = (run_model(SCENE_MODEL, case, x, s) for s in (steps, 10 * steps))
    if not (bool(a.ok) and bool(b.ok)):
        return math.nan, math.nan
    dv = max(float(np.max(np.abs(a.velocity1 - b.velocity1))),
             float(np.max(np.abs(a.velocity2 - b.velocity2))))
    dw = max(abs(float(a.yaw_rate1 - b.yaw_rate1)), abs(float(a.yaw_rate2 - b.yaw_rate2)))
    return dv, dw


def study_class(name: str, records: list, *, steps: int = COARSE_STEPS, radii=None,
                bar=None) -> ClassStudy:
    """Class fits, leave-one-out refits and predictions of every model on ``records`` under
    each input variant, with the statistics (module notes)."""
    wall = time.perf_counter()
    variants = input_variants(records, radii)
    studies = tuple(_study_variant(records, v, steps, bar) for v in variants)
    first = studies[0]
    x = first.class_fits[SCENE_MODEL.name].x
    checks = [coarse_check(r, first.variant.case(t, r, len(records)), x, steps)
              for t, r in enumerate(records[:3])]
    check = max(checks, key=lambda c: c[0] if math.isfinite(c[0]) else -1.0)
    return ClassStudy(name, tuple(r.name for r in records), records[0].observable,
                      records[0].outcome_origin, max(len(m.parameters) for m in MODELS),
                      studies, check, time.perf_counter() - wall)


def study_all(max_tests: int | None = None, *, steps: int = COARSE_STEPS,
              classes=None, bar=None) -> list[ClassStudy]:
    """:func:`study_class` on every class of :func:`crash_classes` (or those named in
    ``classes``, by name or :data:`~comparisons.studies.crash_records.CLASS_KEYS` key), in
    the report's order."""
    if classes is not None:
        classes = {CLASS_KEYS.get(c, c) for c in classes}
    radii = fitted_radii()
    out = []
    for name, records in crash_classes(max_tests, radii).items():
        if classes is None or name in classes:
            out.append(study_class(name, records, steps=steps, radii=radii, bar=bar))
    return out
