"""The finite-duration scene tuned to crash tests, and leave-one-out prediction against PIM.

Two models of the same test (the same :class:`pim.Case`: masses, inertias, pre-impact motion,
impact point C and contact plane from the dataset):

* **PIM** (:func:`pim.solve`) with parameters (epsilon, beta), both in [0, 1];
* **the scene**: the finite-duration point contact stepped by pymunk
  (:func:`sim.simulate_compliant`), with restitution of the crush epsilon in [0, 1], friction
  between the vehicles mu_c in [0, :data:`MU_MAX`], contact duration T in
  [:data:`T_BOUNDS`] s (the linear stiffness whose frictionless contact lasts T,
  :func:`sim.contact_law.stiffness_for_duration`, so one T suits cars of any mass) and tyre
  friction mu_tyre in [0, 1.2] acting during the contact. The geometry (C, Gamma) is the
  dataset's and is not fitted.

Both are fitted by ``scipy.optimize.least_squares`` (trust region, bounds) to the measured
post-impact velocity vectors and yaw rates of every moving vehicle, residuals scaled by 1 mph
and 10 deg/s (:data:`pim.analysis.validation.SPEED_TOLERANCE`, ``YAW_TOLERANCE``):

* per test (descriptive): PIM's (epsilon, beta); the scene's (epsilon, mu_c, T) at the
  default tyre friction :data:`TYRE_DEFAULT` (a barrier test measures three numbers);
* per class: one parameter set for every test of the class;
* leave-one-out (predictive): for each test of a class, the class parameters refitted on
  the *other* tests, started from the median of the other tests' per-test parameters (the
  held-out test's data enter neither the fit nor its start: the per-test fits start from the
  model's default and hold no class value), then the held-out test
  predicted. Its delta-V, post-impact velocity and yaw-rate errors are the honest measure.

Classes (:func:`crash_classes`): the IIHS small-overlap barrier tests, non-sideswipe and
sideswipe (Brach, Welsh & Brach, SAE 2014-01-0469; each car at its vehicle type's class
radius of gyration, the same case for both models), and the RICSAC tests whose measured
motion balances linear momentum (:func:`pim.analysis.consistency.check_ricsac`),
on the crush-edge geometry of :func:`pim.analysis.validation.ricsac_case` (3, 6 and 11: the
vector measure flags RICSAC 9), and RICSAC 9 as the design sheet gives it (the bundled case
``ricsac9``, its measured post-impact motion; a class of one: per-test fits only). The
IIHS car-to-car table gives no masses, inertias or impact geometry, so neither model can be
run on it (:data:`UNRUNNABLE`).

The scene runs coarse (:data:`COARSE_STEPS` steps per estimated contact time);
:func:`coarse_check` measures the coarse prediction against a fine one at the fitted
parameters.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from scipy.optimize import least_squares

import pim
import sim
from pim.analysis.consistency import check_ricsac
from pim.analysis.validation import (
    SPEED_TOLERANCE,
    YAW_TOLERANCE,
    barrier_case,
    class_radius_of_gyration,
    reproduce_barrier,
    ricsac_case,
)
from pim.io.datasets import load_barrier, load_ricsac
from sim.contact_law import stiffness_for_duration

__all__ = ["TestCase", "Model", "PIM_MODEL", "SCENE_MODEL", "crash_classes", "FitResult",
           "fit_parameters", "Prediction", "ClassStudy", "study_class", "leave_one_out",
           "predict", "coarse_check", "COARSE_STEPS", "FINE_STEPS", "MU_MAX", "T_BOUNDS",
           "UNRUNNABLE", "FAILED_RESIDUAL", "scene_settings", "TYRE_DEFAULT", "LOO_NFEV"]

#: Steps per estimated contact time of the fitted scene, and of the check against it.
COARSE_STEPS = 20
FINE_STEPS = 200
MU_MAX = 3.0
#: Tyre friction of the per-test scene fits [-] (dry asphalt, about 0.7-0.8).
TYRE_DEFAULT = 0.7
T_BOUNDS = (0.02, 0.3)
#: Residual evaluations of each leave-one-out refit (Gauss-Newton steps from a start near
#: its optimum; each also costs a Jacobian, one evaluation per parameter).
LOO_NFEV = 4
#: Scaled residual of a scene that fails (no contact, never separates).
FAILED_RESIDUAL = 50.0
#: Datasets with measured motion that neither model can run, and why.
UNRUNNABLE = {"iihs-car-to-car": "the table gives no masses, yaw inertias or impact geometry "
                                 "(coefficient statistics only)"}


@dataclass(frozen=True, eq=False)
class TestCase:
    """One crash test as both models see it.

    Attributes
    ----------
    crash_class : str
        The crash class it belongs to.
    name : str
        The test's name.
    case : pim.Case
        The test as a case, with ``measured`` post-impact motion [SI].
    """

    crash_class: str
    name: str
    case: pim.Case

    __test__ = False      # not a pytest class

    @property
    def moving(self) -> tuple[int, ...]:
        """The vehicles that move (1, or 1 and 2)."""
        return (1,) if bool(self.case.vehicle2.fixed) else (1, 2)

    def observed(self) -> np.ndarray:
        """Measured (vx, vy, omega) of each moving vehicle [m/s, m/s, rad/s], flat."""
        m = self.case.measured
        return _flat(self.moving, m.velocity1, m.yaw_rate1, m.velocity2, m.yaw_rate2)

    @cached_property
    def k_nn(self) -> float:
        """K_nn of the contact [1/kg] (geometry only), for the stiffness of a duration."""
        return float(pim.solve(self.case, 0.5, 1.0).k_nn)

    def scale(self) -> np.ndarray:
        return np.tile([SPEED_TOLERANCE, SPEED_TOLERANCE, YAW_TOLERANCE], len(self.moving))


def _flat(moving, v1, w1, v2, w2) -> np.ndarray:
    parts = [np.r_[np.asarray(v1, float), float(w1)]]
    if 2 in moving:
        parts.append(np.r_[np.asarray(v2, float), float(w2)])
    return np.concatenate(parts)


def scene_settings(steps: int = COARSE_STEPS) -> sim.CompliantSettings:
    """Settings of the fitted scene: ``steps`` per estimated contact time, no recording."""
    return sim.CompliantSettings(record=False, steps_per_contact=int(steps),
                                 min_steps=min(10, int(steps)))


@dataclass(frozen=True)
class Model:
    """A model's parameters and its prediction function.

    Attributes
    ----------
    name : str
        The model's name.
    parameters : tuple of str
        Names of its parameters.
    lower, upper : tuple of float
        Bounds of the parameters [their units].
    start : tuple of float
        Default start of a fit [their units].
    run : callable
        ``run(test, x, steps) -> (v1, w1, v2, w2)``: the predicted post-impact velocities
        [m/s] and yaw rates [rad/s].
    """

    name: str
    parameters: tuple[str, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    start: tuple[float, ...]
    run: object = field(repr=False)


def _run_pim(test: TestCase, x, steps=None):
    r = pim.solve(test.case, float(x[0]), float(x[1]))
    return r.velocity1, float(r.yaw_rate1), r.velocity2, float(r.yaw_rate2)


def _run_scene(test: TestCase, x, steps=COARSE_STEPS):
    eps, mu, duration, tyre = (float(v) for v in x)
    k = float(stiffness_for_duration(duration, test.k_nn, eps))
    r = sim.simulate_compliant(test.case, eps, k, friction=mu, tyre_friction=tyre,
                               settings=scene_settings(steps), engine="pymunk")
    return r.velocity1, float(r.yaw_rate1), r.velocity2, float(r.yaw_rate2)


PIM_MODEL = Model("PIM", ("epsilon", "beta"), (0.0, 0.0), (1.0, 1.0), (0.3, 0.8), _run_pim)
SCENE_MODEL = Model("scene", ("epsilon", "mu_c", "T [s]", "mu_tyre"), (0.0, 0.0, T_BOUNDS[0], 0.0),
                    (1.0, MU_MAX, T_BOUNDS[1], 1.2), (0.2, 0.8, 0.1, TYRE_DEFAULT),
                    _run_scene)


def predict(model: Model, test: TestCase, x, steps=COARSE_STEPS) -> np.ndarray | None:
    """Predicted (vx, vy, omega) of each moving vehicle, flat; None if the scene fails."""
    try:
        v1, w1, v2, w2 = model.run(test, x, steps)
    except sim.SimulationError:
        return None
    return _flat(test.moving, v1, w1, v2, w2)


def _residuals(model, tests, x, steps):
    out = []
    for t in tests:
        p = predict(model, t, x, steps)
        out.append(np.full(3 * len(t.moving), FAILED_RESIDUAL) if p is None
                   else (p - t.observed()) / t.scale())
    return np.concatenate(out)


@dataclass(frozen=True)
class FitResult:
    """A least-squares fit of a model's parameters.

    Attributes
    ----------
    x : tuple of float
        Fitted parameters, all of the model's (the fixed ones included) [their units].
    rms : float
        Root-mean-square scaled residual [-].
    evaluations : int
        Function evaluations.
    wall_time : float
        Wall time of the fit [s].
    """

    x: tuple
    rms: float
    evaluations: int
    wall_time: float


def fit_parameters(model: Model, tests, start=None, fixed: dict | None = None,
                   steps: int = COARSE_STEPS, max_nfev: int | None = None,
                   bar=None) -> FitResult:
    """Least-squares fit of ``model``'s parameters to the measured motion of ``tests``.

    Parameters
    ----------
    model : Model
    tests : sequence of TestCase
    start : sequence of float, optional
        Start (default ``model.start``), clipped into the bounds.
    fixed : dict, optional
        Parameter index -> value held fixed.
    steps : int
        Scene steps per contact time.
    max_nfev : int, optional
        Residual evaluations allowed (``least_squares``; its default if None).
    bar : tqdm, optional
        Advanced by one per model run (a scene or a PIM solve).
    """
    fixed = dict(fixed or {})
    x0 = np.array(model.start if start is None else start, float)
    lo, hi = np.array(model.lower), np.array(model.upper)
    free = [i for i in range(len(x0)) if i not in fixed]
    for i, v in fixed.items():
        x0[i] = v
    x0 = np.clip(x0, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
    count = [0]

    def full(z):
        x = x0.copy()
        x[free] = z
        return x

    def fun(z):
        count[0] += 1
        if bar is not None:
            bar.update(len(tests))
        return _residuals(model, tests, full(z), steps)

    wall = time.perf_counter()
    sol = least_squares(fun, x0[free], bounds=(lo[free], hi[free]), x_scale=hi[free] - lo[free],
                        diff_step=1e-3, max_nfev=max_nfev, xtol=1e-4, ftol=1e-4)
    x = full(sol.x)
    return FitResult(tuple(float(v) for v in x), float(np.sqrt(np.mean(sol.fun**2))),
                     count[0], time.perf_counter() - wall)


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
        The model's name.
    kind : str
        "per-test fit", "class fit" or "leave-one-out".
    x : tuple of float
        The parameters used [their units].
    delta_v_error : float
        |dV predicted| - |dV measured|, signed, of the vehicle where it is largest [m/s].
    velocity_error : float
        Length of the post-impact velocity error vector [m/s].
    yaw_error : float
        |omega predicted - omega measured| [rad/s].
    wall_time : float
        One prediction's cost [s].
    """

    crash_class: str
    test: str
    model: str
    kind: str
    x: tuple
    delta_v_error: float
    velocity_error: float
    yaw_error: float
    wall_time: float


def _prediction(model, test, x, kind, steps=COARSE_STEPS) -> Prediction:
    wall = time.perf_counter()
    p = predict(model, test, x, steps)
    wall = time.perf_counter() - wall
    if p is None:
        return Prediction(test.crash_class, test.name, model.name, kind, tuple(x), math.nan,
                          math.nan, math.nan, wall)
    obs = test.observed().reshape(-1, 3)
    p = p.reshape(-1, 3)
    pre = [test.case.vehicle1.velocity, test.case.vehicle2.velocity]
    dv = [float(np.hypot(*(p[i, :2] - pre[i])) - np.hypot(*(obs[i, :2] - pre[i])))
          for i in range(len(obs))]
    return Prediction(test.crash_class, test.name, model.name, kind, tuple(x),
                      max(dv, key=abs), float(np.max(np.hypot(*(p[:, :2] - obs[:, :2]).T))),
                      float(np.max(np.abs(p[:, 2] - obs[:, 2]))), wall)


def leave_one_out(model: Model, tests, per_test: dict, fixed: dict | None = None,
                  steps: int = COARSE_STEPS, max_nfev: int | None = None,
                  bar=None) -> list[Prediction]:
    """For each test, the class parameters refitted on the others and the test predicted.

    ``per_test`` maps a test name to its own fitted parameters; the start of each refit is
    the median of the *other* tests' (module notes), so the held-out test enters neither the
    fit nor its start. ``fixed``: parameter index -> value held fixed (default none).
    """
    out = []
    for i, held in enumerate(tests):
        train = [t for j, t in enumerate(tests) if j != i]
        start = np.median([per_test[t.name] for t in train], axis=0)
        fit = fit_parameters(model, train, start, fixed, steps, max_nfev, bar)
        out.append(_prediction(model, held, fit.x, "leave-one-out", steps))
    return out


@dataclass(frozen=True, eq=False)
class ClassStudy:
    """One crash class: both models' per-test fits, class fits and leave-one-out
    predictions, and the fits' parameters.

    Attributes
    ----------
    crash_class : str
        The class's name.
    tests : tuple of str
        Names of its tests.
    predictions : tuple of Prediction
        Per-test fit, class fit and leave-one-out rows of both models.
    class_fits : dict
        Model name -> :class:`FitResult` of the class fit.
    wall_time : float
        Wall time of the study [s].
    """

    crash_class: str
    tests: tuple
    predictions: tuple
    class_fits: dict         # model name -> FitResult
    wall_time: float

    def rows(self, model: str, kind: str) -> list[Prediction]:
        return [p for p in self.predictions if p.model == model and p.kind == kind]


def study_class(name: str, tests, *, steps: int = COARSE_STEPS, loo_nfev: int | None = LOO_NFEV,
                bar=None) -> ClassStudy:
    """Per-test fits, class fits and leave-one-out prediction of both models on ``tests``.

    The scene's tyre friction (index 3) is fitted per class and in leave-one-out, and held
    at :data:`TYRE_DEFAULT` in the per-test fits. ``loo_nfev`` bounds each leave-one-out
    refit's evaluations (it starts near its optimum).
    """
    wall = time.perf_counter()
    preds, class_fits = [], {}
    for model in (PIM_MODEL, SCENE_MODEL):
        cfit = fit_parameters(model, tests, steps=steps, bar=bar)
        class_fits[model.name] = cfit
        fixed = {3: TYRE_DEFAULT} if model is SCENE_MODEL else None
        per_test = {}
        for t in tests:
            f = fit_parameters(model, [t], None, fixed, steps, bar=bar)
            per_test[t.name] = f.x
            preds.append(_prediction(model, t, f.x, "per-test fit", steps))
            preds.append(_prediction(model, t, cfit.x, "class fit", steps))
        if len(tests) > 2:
            preds += leave_one_out(model, tests, per_test, None, steps, loo_nfev, bar)
    return ClassStudy(name, tuple(t.name for t in tests), tuple(preds), class_fits,
                      time.perf_counter() - wall)


def coarse_check(test: TestCase, x, coarse: int = COARSE_STEPS, fine: int = FINE_STEPS):
    """Largest |coarse - fine| scene prediction over the test's (vx, vy) [m/s] and omega
    [rad/s], at parameters ``x``: (speed difference, yaw-rate difference)."""
    a, b = predict(SCENE_MODEL, test, x, coarse), predict(SCENE_MODEL, test, x, fine)
    if a is None or b is None:
        return math.nan, math.nan
    d = np.abs(a - b).reshape(-1, 3)
    return float(d[:, :2].max()), float(d[:, 2].max())


def crash_classes(max_tests: int | None = None) -> dict[str, list[TestCase]]:
    """The bundled tests with measured motion that both models can run, by crash class
    (module notes); ``max_tests`` keeps the first few of each class (fast checks)."""
    barrier = load_barrier()
    class_k = class_radius_of_gyration(reproduce_barrier([t for t in barrier
                                                          if t.group != "OUTLIER"]))
    out = {}
    for group, label in (("NS", "IIHS barrier, non-sideswipe"),
                         ("SS", "IIHS barrier, sideswipe")):
        out[label] = [TestCase(label, t.test_id, barrier_case(t, class_k[t.vehicle_type]))
                      for t in barrier if t.group == group]
    ricsac = [t for t in load_ricsac() if t.has_motion and t.normal_angle is not None]
    flagged = {c.test.split()[1] for c in check_ricsac(ricsac) if c.flagged}
    label = "RICSAC, momentum-consistent"
    out[label] = [TestCase(label, f"ricsac{t.number}", ricsac_case(t)) for t in ricsac
                  if str(t.number) not in flagged]
    label = "RICSAC 9, design sheet"
    out[label] = [TestCase(label, "ricsac9", pim.load_case("ricsac9"))]
    if max_tests is not None:
        out = {k: v[:max_tests] for k, v in out.items()}
    return out
