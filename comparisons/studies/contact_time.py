"""What the crash tests say about the contact time T of the tuned scene (issue 34).

**The profile** (:func:`profile_contact_time`): the class fit of the Coulomb scene
(:data:`~comparisons.studies.tuned_scene.SCENE_MODEL`) with T held at each value of
:data:`PROFILE_TIMES` (20-250 ms) and epsilon, mu_c and mu_tyre refitted in their boxes at
each (:func:`~comparisons.studies.tuned_scene.fit_held`: a Sobol screen, the best
:data:`PROFILE_STARTS` refined, every T in one batch), on the class fit's inputs.

Its confidence threshold is the likelihood-ratio test of one parameter (Wilks): with the
residual variance unknown and profiled out of a Gaussian likelihood, -2 log Lambda =
n_r log(S(T) / S_min) for the class's n_r scaled residuals and sum of squares S, which is
chi-square(1) under the hypothesis that T is the true contact time. A T is excluded at
:data:`LEVEL` when n_r log(S(T) / S_min) > chi2_1(:data:`LEVEL`) (3.84), i.e. its rms
score lies above rms_min exp(3.84 / (2 n_r)) (:func:`lr_threshold`). Why this one: the
residuals are scaled by 1 mph and 10 deg/s, a tolerance, not a measured error, so the
variance is estimated from the fit rather than assumed (the threshold then depends only on
the count of residuals); S_min is the smaller of the free fit's (T free) and the profile's
least sum of squares. It is asymptotic and treats the residuals as independent (the three
of one test are not quite), so it is read as the tests' resolving power, not an exact
interval.

**The mechanisms** (:func:`mechanism_study`, :data:`MECHANISMS`): on one class, each of the
scene's three ways of depending on T switched off alone against the full scene, as the
assumption ladder changes one assumption per rung:

* the geometry change during contact (the bodies turn and the contact point moves):
  frozen at the start (``CompliantSettings.geometry_change=False``,
  :func:`sim.compliant_formula.frozen_point`);
* the tyre forces during contact: mu_tyre held at 0;
* the crush's energy split between what it keeps and what it returns tangentially (the
  friction spring's recovery r = eps^2, the share of its energy the crush returns): r = 0,
  the tangential compliance as plastic as the crush.

With the geometry frozen and no tyres the scene does not depend on T at all (time scales
out: ``tests/sim/test_compliant_batch.py``), so only the first two can push T; the third
changes what the fit trades against them. Each configuration gets its free fit and a
coarse profile (:data:`MECHANISM_TIMES`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.stats import chi2

from .crash_records import CLASS_KEYS, NON_SIDESWIPE, InputVariant, crash_classes, fitted_radii
from .tuned_scene import (
    CLASS_STARTS,
    COARSE_STEPS,
    SCENE_MODEL,
    SCREEN,
    ClassStudy,
    Model,
    MultiStartFit,
    fit_held,
    study_class,
)

__all__ = ["PROFILE_TIMES", "MECHANISM_TIMES", "PROFILE_STARTS", "PROFILE_SCREEN", "LEVEL",
           "PHYSICAL_TIMES", "T_INDEX", "TYRE_INDEX", "lr_threshold", "Profile",
           "profile_contact_time", "Mechanism", "MECHANISMS", "MechanismResult",
           "mechanism_study", "THRESHOLD_RULE", "MECHANISM_CLASS", "study_classes"]

#: Contact times of the profile [s]: 20-250 ms.
PROFILE_TIMES = (0.02, 0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.25)
#: The coarser grid of each mechanism's profile [s].
MECHANISM_TIMES = (0.02, 0.05, 0.1, 0.15, 0.25)
#: Full-scale crash pulses' contact times [s] (docs/pulses.md, NHTSA 10146: 90 ms).
PHYSICAL_TIMES = (0.07, 0.15)
#: Starts refined per held value, and the Sobol screen of the free parameters.
PROFILE_STARTS = 8
PROFILE_SCREEN = 64
#: Level of the likelihood-ratio threshold.
LEVEL = 0.95
#: The class the mechanisms are studied on.
MECHANISM_CLASS = NON_SIDESWIPE
#: Index of T and of mu_tyre among the Coulomb scene's parameters.
T_INDEX, TYRE_INDEX = 2, 3
THRESHOLD_RULE = ("likelihood ratio of one parameter with the residual variance profiled "
                  "out: T excluded where n_r ln(S(T) / S_min) > chi2_1(0.95) = 3.84, i.e. "
                  "rms(T) > rms_min exp(3.84 / (2 n_r)), n_r the class's scaled residuals")


def lr_threshold(rms_min: float, n_residuals: int, level: float = LEVEL) -> float:
    """The largest rms score [-] the likelihood-ratio test of one parameter keeps at
    ``level`` (module notes): rms_min exp(chi2_1(level) / (2 n_r))."""
    return float(rms_min * math.exp(chi2.ppf(level, 1) / (2.0 * int(n_residuals))))


@dataclass(frozen=True)
class Profile:
    """The class-fit score over held contact times, and its threshold.

    Attributes
    ----------
    times : tuple of float
        The held contact times [s].
    fits : tuple of MultiStartFit
        The class fit at each (every parameter, T included).
    free : MultiStartFit
        The class fit with T free.
    n_residuals : int
        Scaled residuals of the class (n_r).
    threshold : float
        :func:`lr_threshold` of the least rms [-].
    """

    times: tuple
    fits: tuple
    free: MultiStartFit
    n_residuals: int
    threshold: float

    @property
    def rms(self) -> np.ndarray:
        """The class-fit rms at each held time [-]."""
        return np.array([f.rms for f in self.fits])

    @property
    def best_rms(self) -> float:
        """The least rms, T free or held [-]."""
        return float(min(self.free.rms, self.rms.min()))

    @property
    def kept(self) -> tuple:
        """The held times [s] whose rms the threshold keeps."""
        return tuple(t for t, r in zip(self.times, self.rms, strict=True)
                     if r <= self.threshold)

    def physical_excluded(self) -> bool:
        """Every held time in :data:`PHYSICAL_TIMES` lies above the threshold."""
        lo, hi = PHYSICAL_TIMES
        inside = [r for t, r in zip(self.times, self.rms, strict=True) if lo <= t <= hi]
        return bool(inside and min(inside) > self.threshold)

    def at(self, time: float) -> float:
        """The rms at the held time nearest ``time`` [-]."""
        return float(self.rms[int(np.argmin(np.abs(np.array(self.times) - time)))])


def profile_contact_time(records: list, variant: InputVariant, *, model: Model = SCENE_MODEL,
                         times=PROFILE_TIMES, held: dict | None = None, steps: int = COARSE_STEPS,
                         bar=None) -> Profile:
    """The profile of ``model``'s class fit over the contact times ``times`` (module notes),
    with ``held`` (index -> one value) held besides at every point."""
    held = dict(held or {})
    times = tuple(float(t) for t in times)
    grid = {T_INDEX: np.array(times)} | {i: np.full(len(times), v) for i, v in held.items()}
    fits = fit_held(model, records, variant, grid, starts=PROFILE_STARTS,
                    screen=PROFILE_SCREEN, steps=steps, bar=bar)
    free = fit_held(model, records, variant, {i: np.array([v]) for i, v in held.items()},
                    starts=CLASS_STARTS[SCENE_MODEL.name], screen=SCREEN, steps=steps,
                    bar=bar)[0]
    n_r = len(records[0].observed) * len(records)
    best = min(free.rms, min(f.rms for f in fits))
    return Profile(times, tuple(fits), free, n_r, lr_threshold(best, n_r))


@dataclass(frozen=True)
class Mechanism:
    """One way the scene depends on T, and how the study switches it off.

    Attributes
    ----------
    name : str
        Short name (tables, JSON).
    label : str
        What is switched off, in prose.
    options : tuple of (str, object)
        :class:`sim.CompliantSettings` fields changed.
    held : tuple of (int, float)
        Parameters held (index, value).
    """

    name: str
    label: str
    options: tuple = ()
    held: tuple = ()

    def model(self) -> Model:
        """The Coulomb scene with this mechanism switched off."""
        if not self.options:
            return SCENE_MODEL
        return replace(SCENE_MODEL, name=f"scene ({self.name})", options=self.options)


MECHANISMS = (
    Mechanism("every mechanism", "nothing (the full scene)"),
    Mechanism("no geometry change", "the geometry change during contact (rotation and the "
              "moving contact point): frozen at the start",
              options=(("geometry_change", False),)),
    Mechanism("no tyre forces", "the tyre forces during contact: mu_tyre held at 0",
              held=((TYRE_INDEX, 0.0),)),
    Mechanism("plastic tangential recovery", "the crush's energy split: the friction "
              "spring returns none of its energy (r = 0) instead of the crush's share eps^2",
              options=(("tangential_recovery", 0.0),)),
)


@dataclass(frozen=True)
class MechanismResult:
    """The scene with one mechanism switched off, fitted to a class.

    Attributes
    ----------
    mechanism : Mechanism
    profile : Profile
        Its free fit (``profile.free``) and its profile over :data:`MECHANISM_TIMES`.
    """

    mechanism: Mechanism
    profile: Profile

    @property
    def rise(self) -> float:
        """How much the class-fit rms rises from its least to T = 100 ms [-]."""
        return self.profile.at(0.1) - self.profile.best_rms


def mechanism_study(records: list, variant: InputVariant, *, steps: int = COARSE_STEPS,
                    bar=None) -> tuple[MechanismResult, ...]:
    """Each of :data:`MECHANISMS` on ``records`` (module notes)."""
    return tuple(MechanismResult(m, profile_contact_time(
        records, variant, model=m.model(), times=MECHANISM_TIMES, held=dict(m.held),
        steps=steps, bar=bar)) for m in MECHANISMS)


def study_classes(max_tests: int | None = None, *, steps: int = COARSE_STEPS, classes=None,
                  bar=None) -> list[ClassStudy]:
    """What ``pim validate-models`` runs: :func:`~comparisons.studies.tuned_scene.study_class`
    on every class of :func:`crash_classes` (or those named in ``classes``, by name or
    :data:`CLASS_KEYS` key), each with its contact-time profile (first input variant), and
    the mechanisms on :data:`MECHANISM_CLASS`; in the report's order."""
    if classes is not None:
        classes = {CLASS_KEYS.get(c, c) for c in classes}
    radii = fitted_radii()
    out = []
    for name, records in crash_classes(max_tests, radii).items():
        if classes is not None and name not in classes:
            continue
        st = study_class(name, records, steps=steps, radii=radii, bar=bar)
        variant = st.variants[0].variant
        profile = profile_contact_time(records, variant, steps=steps, bar=bar)
        mechanisms = (mechanism_study(records, variant, steps=steps, bar=bar)
                      if name == MECHANISM_CLASS else ())
        out.append(replace(st, profile=profile, mechanisms=mechanisms))
    return out
