"""Residuals of measured post-impact motion against PIM, and the fit's goodness of fit.

The residual terms (:class:`pim.model.motion.Term`) are the measured velocity components,
V - V_measured [m/s], and yaw rates, k (Omega - Omega_measured) [m/s], with k = sqrt(I / m)
the vehicle's radius of gyration (the speed that spin gives a point at distance k from the
CG). With the ``[measured]`` standard deviations each residual is divided by its sigma
(k sigma for a yaw rate): the sum of squares is then a chi-square [-], and
:func:`goodness_of_fit` says whether the data fit the model at the stated sigmas.

Evidence on the model's inputs and outputs beyond the post-impact motion (a recorder's
delta-V and pre-crash speed, the energy loss: :class:`pim.model.evidence_terms.EvidenceTerm`)
joins as further terms, value - measured [m/s or J], always with its sigma; the residuals
are ordered motion terms first, then evidence terms.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.case import Case
from ..model.dual import MOTION_OUTPUTS
from ..model.evidence_terms import (
    CrushEnergyTerm,
    EvidenceTerm,
    as_residual_terms,
    evidence_terms_of,
    result_quantities,
)
from ..model.geometry import radius_of_gyration
from ..model.motion import Term
from ..model.numbers import InputError
from ..model.result import Result

__all__ = ["measured_terms", "has_measured_terms", "fitted_yaw_rates", "residuals",
           "residual_terms", "model_value", "measured_value", "crush_terms",
           "measured_weights", "GoodnessOfFit", "goodness_of_fit", "P_INCONSISTENT",
           "P_CONTRADICTED", "cost_label", "contradiction"]

#: p-value below which the measurements are called inconsistent with PIM at their sigmas
#: (a warning).
P_INCONSISTENT = 0.01

#: p-value below which the evidence contradicts itself and a command refuses the answer
#: (``pim reconstruct`` exits 1 after its output unless told to accept it). One in a
#: thousand: evidence that is right, with the right sigmas, under a model that holds,
#: crosses it once in 1000 cases (one degree of freedom: a residual beyond 3.3 sigma), ten
#: times more rarely than the warning at :data:`P_INCONSISTENT`, because an exit code stops
#: a script and a false alarm costs more there; the sigmas of a run-out fit are linearised,
#: so the refusal leaves them that margin. Evidence in real conflict is far below it (a
#: recorded delta-V 20 km/h off the rest positions' at 1 km/h: p = 1e-173).
P_CONTRADICTED = 1e-3


def fitted_yaw_rates(measured, include_yaw: bool | None) -> tuple[int, ...]:
    """The vehicles whose measured yaw rate is fitted: every measured one with
    ``include_yaw`` True, none with False, and with None (the default of :func:`pim.fit`)
    those given a standard deviation (``yaw_rate_sigma``): every measured quantity that has
    a sigma enters the fit."""
    if measured is None or include_yaw is False:
        return ()
    return tuple(i for i in (1, 2) if getattr(measured, f"yaw_rate{i}") is not None and (
        include_yaw or getattr(measured, f"yaw_rate{i}_sigma") is not None))


def measured_terms(case: Case, include_yaw: bool | None
                   ) -> tuple[Term | EvidenceTerm | CrushEnergyTerm, ...]:
    """The terms ``case.measured`` holds: velocities, the yaw rates of
    :func:`fitted_yaw_rates` (``include_yaw``: True every measured one, False none, None
    those with a sigma), then the evidence terms (recorded delta-V and pre-crash speed,
    energy loss), then the crush energy of the case's crush profiles.

    Raises
    ------
    ValueError
        Nothing measured to fit, with a hint when only yaw rates are measured.
    """
    m = case.measured
    terms: list = []
    if m is not None:
        for i in (1, 2):
            if getattr(m, f"velocity{i}") is not None:
                terms += [Term(i, "vx"), Term(i, "vy")]
        terms += [Term(i, "omega") for i in fitted_yaw_rates(m, include_yaw)]
        terms += evidence_terms_of(m)
    terms += crush_terms(case)
    if not terms:
        has_yaw = m is not None and (m.yaw_rate1 is not None or m.yaw_rate2 is not None)
        hint = (" (only yaw rates are measured, without a sigma: give yaw_rate_sigma, or "
                "include_yaw=True / --include-yaw)" if has_yaw and not include_yaw else "")
        raise InputError(
            f"case {case.name or '(unnamed)'}: nothing to fit; case.measured needs a "
            f"post-impact velocity1 or velocity2 [m/s], a recorded delta_v or "
            f"pre_crash_speed, or an energy_loss{hint}")
    return tuple(terms)


def crush_terms(case: Case) -> tuple[CrushEnergyTerm, ...]:
    """The crush-energy term of the case's crush profiles (``[evidence.vehicleN.crush]``),
    or none: energies E_i and their sigmas from :class:`pim.model.crush.CrushProfile`."""
    ev = case.evidence
    if ev is None or not ev.crush:
        return ()
    profiles = ev.crush
    return (CrushEnergyTerm(
        energies=tuple(profiles[i].energy if i in profiles else 0.0 for i in (1, 2)),
        profiles=tuple(profiles.get(i) for i in (1, 2)),
        sigma=float(np.sqrt(sum(p.energy_sigma ** 2 for p in profiles.values()))),
        partition=ev.crush_partition),)


def _gyration(case: Case, term: Term) -> float:
    v = getattr(case, f"vehicle{term.vehicle}")
    return float(radius_of_gyration(v.mass, v.yaw_inertia))


def _scale(case: Case, term) -> float:
    """k_i for a yaw-rate term (its residual is k_i (Omega - Omega_m) [m/s]), else 1."""
    return _gyration(case, term) if isinstance(term, Term) and not term.is_velocity else 1.0


def measured_weights(case: Case, terms) -> np.ndarray | None:
    """Weights that turn the residuals into standardised ones, or None when unweighted.

    With the ``[measured]`` standard deviations (``Measured.velocity1_sigma`` [m/s],
    ``yaw_rate1_sigma`` [rad/s] ...), the velocity residual V - V_m is divided by its sigma
    and the yaw residual k (Omega - Omega_m) by k sigma, so that sum (w r)^2 is a chi-square.
    Either every fitted term has a sigma or none has: a mix is an error naming what is missing
    (evidence terms always have one, so with them every motion term needs one too).
    """
    terms = as_residual_terms(terms)
    sigmas = [t.sigma_of(case.measured) for t in terms]
    missing = [t.name for t, s in zip(terms, sigmas, strict=True) if s is None]
    if len(missing) == len(terms):
        return None
    if missing:
        raise InputError(f"measured: standard deviations are given for some fitted terms but "
                         f"not for {', '.join(missing)}; give a *_sigma for every measured "
                         f"quantity that is fitted, or for none")
    return np.array([1.0 / (_scale(case, t) * s) for t, s in zip(terms, sigmas, strict=True)])


def residual_terms(case: Case, terms) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows of :data:`pim.model.dual.MOTION_OUTPUTS` of the motion terms among ``terms``, and
    the measured targets and factors of every term (motion terms first, then evidence terms,
    :func:`pim.model.evidence_terms.as_residual_terms`): residual = (value - target) *
    factor, the factor being 1 for a velocity or an evidence term and k_i for a yaw rate,
    times the ``[measured]`` weight 1/sigma when standard deviations are given
    (:func:`measured_weights`)."""
    terms = as_residual_terms(terms)
    rows = np.array([MOTION_OUTPUTS.index(t.name) for t in terms if isinstance(t, Term)],
                    dtype=int)
    target = np.array([float(t.of(case.measured)) if isinstance(t, Term)
                       else t.target_of(case.measured) for t in terms])
    scale = np.array([_scale(case, t) for t in terms])
    w = measured_weights(case, terms)
    return rows, target, scale * (1.0 if w is None else w)


def model_value(result: Result, term) -> np.ndarray:
    """The model's value of a residual term in a solved ``result`` [SI]."""
    if not isinstance(term, Term):
        return np.asarray(term.value(result_quantities(result)), dtype=float)
    return term.of(result)


def measured_value(measured, term) -> float:
    """The measured value of a residual term [SI]."""
    return float(term.of(measured)) if isinstance(term, Term) else term.target_of(measured)


def residuals(result: Result, terms, *, weighted: bool = False) -> np.ndarray:
    """Residuals of the fit, shape (..., len(terms)).

    Parameters
    ----------
    result : Result
        Solve of a single case (any shape of eps, beta); its ``case.measured`` holds the
        targets.
    terms : sequence of Term, EvidenceTerm or str
        ``velocity{1,2}_{x,y}`` -> V - V_measured [m/s], ``yaw_rate{1,2}`` ->
        k (Omega - Omega_measured) [m/s] with k = sqrt(I / m) the radius of gyration;
        evidence terms -> value - measured [m/s or J].
    weighted : bool
        Divide by the ``[measured]`` standard deviations (when given): residuals [-] whose
        sum of squares is the chi-square.
    """
    terms = as_residual_terms(terms)
    case = result.case
    scale = np.array([_scale(case, t) for t in terms])
    if weighted:
        w = measured_weights(case, terms)
        scale = scale * (1.0 if w is None else w)
    values = np.stack(np.broadcast_arrays(*(model_value(result, t) for t in terms)), axis=-1)
    target = np.array([measured_value(case.measured, t) for t in terms])
    return (values - target) * scale


def has_measured_terms(case: Case, include_yaw: bool | None = None) -> bool:
    """Whether the case has anything to fit: a measured post-impact velocity, evidence, or
    a fitted yaw rate (:func:`fitted_yaw_rates`)."""
    m = case.measured
    if crush_terms(case):
        return True
    if m is None:
        return False
    if m.velocity1 is not None or m.velocity2 is not None or evidence_terms_of(m):
        return True
    return bool(fitted_yaw_rates(m, include_yaw))


@dataclass(frozen=True)
class GoodnessOfFit:
    """Chi-square test of a fit with stated measurement sigmas.

    Attributes
    ----------
    chi_square : float
        Sum of the squared standardised residuals, ((model - measured) / sigma)^2 [-].
    dof : int
        Degrees of freedom: measured terms minus fitted parameters.
    p_value : float
        Probability of a chi-square at least this large if the model holds and the sigmas
        are right (``scipy.stats.chi2.sf``); NaN when ``dof`` is 0 or less.
    largest : tuple of (str, float)
        The terms with the largest standardised residuals (model - measured) / sigma [-],
        largest first (at most :data:`LARGEST`): where the evidence conflicts.
    """

    chi_square: float
    dof: int
    p_value: float
    largest: tuple = ()

    @property
    def consistent(self) -> bool | None:
        """False when p < :data:`P_INCONSISTENT`; None when the test has no degree of freedom."""
        if not np.isfinite(self.p_value):
            return None
        return bool(self.p_value >= P_INCONSISTENT)

    @property
    def contradicted(self) -> bool:
        """True when p < :data:`P_CONTRADICTED`: the evidence contradicts itself beyond the
        refusal threshold (never with no degree of freedom)."""
        return bool(np.isfinite(self.p_value) and self.p_value < P_CONTRADICTED)

    def refusal(self) -> str:
        """Why the answer is refused, one line (meaningful when :attr:`contradicted`)."""
        worst = ", ".join(f"{name} {z:+.2g} sigma" for name, z in self.largest)
        return (f"the evidence contradicts itself: chi-square = {self.chi_square:.4g} with "
                f"{self.dof} degrees of freedom, p = {self.p_value:.2g} < {P_CONTRADICTED:g} "
                f"(the refusal threshold): the measurements, their sigmas or the model are "
                f"wrong" + (f"; the evidence in conflict: {worst}" if worst else ""))

    def verdict(self) -> str:
        """One plain sentence on whether the measurements fit PIM at their sigmas."""
        if self.consistent is None:
            return ("no degree of freedom left (as many fitted parameters as measured "
                    "terms): the fit cannot test the model")
        if not self.consistent:
            worst = ", ".join(f"{name} {z:+.2g} sigma" for name, z in self.largest)
            return (f"the measurements are inconsistent with PIM at the stated sigmas "
                    f"(p = {self.p_value:.2g} < {P_INCONSISTENT:g}): the model, the inputs "
                    f"or the sigmas are wrong"
                    + (f"; the evidence in conflict: {worst}" if worst else ""))
        return f"the measurements are consistent with PIM at the stated sigmas (p = " \
               f"{self.p_value:.2g})"

    def summary(self) -> str:
        """One line: chi-square, degrees of freedom, p-value and the verdict."""
        p = f"p = {self.p_value:.3g}" if self.dof > 0 else "p undefined"
        return (f"chi-square = {self.chi_square:.4g} with {self.dof} degrees of freedom "
                f"({p}): {self.verdict()}")

    def to_dict(self) -> dict:
        return {"chi_square": self.chi_square, "dof": self.dof,
                "p_value": None if not np.isfinite(self.p_value) else self.p_value,
                "consistent": self.consistent, "contradicted": self.contradicted,
                "refusal_p": P_CONTRADICTED, "verdict": self.verdict(),
                "largest_standardised_residuals": dict(self.largest)}


def contradiction(goodness: GoodnessOfFit | None) -> str | None:
    """Why an answer fitted to evidence is refused: :meth:`GoodnessOfFit.refusal` when the
    evidence contradicts itself beyond :data:`P_CONTRADICTED`, else None (also for no test:
    no sigmas, or no degree of freedom)."""
    return goodness.refusal() if goodness is not None and goodness.contradicted else None


#: Standardised residuals below this [-] are the fit's round-off (a term it meets exactly,
#: e.g. 3e-11 sigma): not named among the evidence in conflict.
ROUND_OFF_SIGMA = 1e-6

#: How many terms :class:`GoodnessOfFit` names as the largest standardised residuals.
LARGEST = 3


def goodness_of_fit(chi_square: float, n_data: int, n_parameters: int,
                    standardised=None, names=()) -> GoodnessOfFit:
    """The chi-square test of a weighted fit: dof = n_data - n_parameters, p = chi2.sf;
    with the ``standardised`` residuals (w r, one per term of ``names``) it names the
    :data:`LARGEST` largest."""
    from scipy.stats import chi2

    dof = int(n_data) - int(n_parameters)
    p = float(chi2.sf(chi_square, dof)) if dof > 0 else float("nan")
    largest = ()
    if standardised is not None and len(names):
        z = np.asarray(standardised, dtype=float)
        largest = tuple((str(names[j]), float(z[j]))
                        for j in np.argsort(-np.abs(z), kind="stable")[:LARGEST]
                        if not abs(z[j]) < ROUND_OFF_SIGMA)
    return GoodnessOfFit(float(chi_square), dof, p, largest)


def cost_label(weighted: bool, velocity_unit: str) -> str:
    """What the fit's cost is: ``chi-square`` [-] with sigmas, else a sum of squares in
    ``(velocity_unit)^2``."""
    return "chi-square" if weighted else f"sum of squares ({velocity_unit})^2"
