"""How far the model's answer is from each measured quantity, in standard deviations.

A fit's rms residual says how well it does on average; a report must also say *where* it
misses: each measured post-impact velocity component and yaw rate (fitted or not: a fit of
the velocities alone leaves the yaw rates as a check) and each piece of recorded evidence
(delta-V, pre-crash speed, energy loss, crush energy; :mod:`pim.analysis.residuals`), with
the model's value at the answer, the difference and that difference in sigmas: the
``[measured]`` standard deviation where the case states one, else the reproduction tolerance
of Brach, Welsh & Brach (SAE 2014-01-0469): 1 mph per velocity component, 10 deg/s per yaw
rate (:data:`pim.analysis.validation.SPEED_TOLERANCE`, ``YAW_TOLERANCE``). A quantity more
than :data:`POOR` sigmas off makes the fit poor (:attr:`Misfit.poor`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.evidence_terms import CrushEnergyTerm, EvidenceTerm
from ..model.motion import Term
from ..model.numbers import InputError
from ..model.result import Result
from .residuals import measured_terms, measured_value, model_value
from .validation import SPEED_TOLERANCE, YAW_TOLERANCE

__all__ = ["MisfitRow", "Misfit", "misfit", "POOR", "NOMINAL_SIGMAS"]

#: A measured quantity further than this many sigmas from the model makes the fit poor.
POOR = 3.0
#: The sigma of a quantity the case states none for, per unit kind [SI]: the reproduction
#: tolerances of Brach, Welsh & Brach (SAE 2014-01-0469), 1 mph and 10 deg/s.
NOMINAL_SIGMAS = {"velocity": SPEED_TOLERANCE, "angular_velocity": float(YAW_TOLERANCE)}


@dataclass(frozen=True)
class MisfitRow:
    """One measured quantity against the model.

    Attributes
    ----------
    name : str
        The term's name (``velocity1_x``, ``yaw_rate2``, ``delta_v1_long``, ...).
    label : str
        In words ("vehicle 2 yaw rate").
    kind : str
        Unit kind (:mod:`pim.io.units`) of the values.
    measured : float
        The measured value [SI] (0 for the crush-energy term, whose model value is the
        energy loss minus the crush energies).
    model : float
        The model's value at the answer [SI].
    sigma : float
        Its standard deviation [SI].
    stated : bool
        Whether the case states ``sigma`` (else the nominal tolerance).
    """

    name: str
    label: str
    kind: str
    measured: float
    model: float
    sigma: float
    stated: bool

    @property
    def residual(self) -> float:
        """Model minus measured [SI]."""
        return self.model - self.measured

    @property
    def z(self) -> float:
        """Model minus measured in sigmas [-]."""
        return self.residual / self.sigma


@dataclass(frozen=True)
class Misfit:
    """Every measured quantity of a case against the model's answer.

    Attributes
    ----------
    rows : tuple of MisfitRow
        Motion terms (vehicle 1 then 2: x, y, yaw rate), then the evidence terms.
    """

    rows: tuple[MisfitRow, ...]

    @property
    def poor_rows(self) -> tuple[MisfitRow, ...]:
        """The rows more than :data:`POOR` sigmas off, worst first."""
        return tuple(sorted((r for r in self.rows if abs(r.z) > POOR),
                            key=lambda r: -abs(r.z)))

    @property
    def poor(self) -> bool:
        """Whether some measured quantity is more than :data:`POOR` sigmas off."""
        return bool(self.poor_rows)

    @property
    def stated(self) -> bool:
        """Whether every sigma is stated by the case."""
        return all(r.stated for r in self.rows)


def _label(term) -> str:
    if isinstance(term, Term):
        what = {"vx": "velocity x", "vy": "velocity y", "omega": "yaw rate"}[term.quantity]
        return f"vehicle {term.vehicle} {what}"
    if isinstance(term, CrushEnergyTerm):
        return "energy loss minus the crush energies"
    if isinstance(term, EvidenceTerm) and term.kind == "delta_v":
        return f"{term.group}, {('longitudinal', 'lateral')[term.axis]}"
    return term.group


def _kind(term) -> str:
    return term.kind if isinstance(term, Term) else term.kind_of_unit


def misfit(result: Result) -> Misfit:
    """Each measured quantity of ``result.case`` against ``result`` (a solve of one case at
    the answer's coefficients); no rows when nothing is measured.

    Examples
    --------
    >>> import pim
    >>> case = pim.load_case("ricsac9")
    >>> worst = misfit(pim.solve(case, 0.3548, 1.0)).poor_rows[0]
    >>> worst.label, round(worst.z, 1)
    ('vehicle 2 yaw rate', 4.2)
    """
    case = result.case
    try:
        terms = measured_terms(case, include_yaw=True)
    except InputError:
        return Misfit(())
    rows = []
    for term in terms:
        sigma = term.sigma_of(case.measured)
        kind = _kind(term)
        rows.append(MisfitRow(
            name=term.name, label=_label(term), kind=kind,
            measured=float(measured_value(case.measured, term)),
            model=float(np.asarray(model_value(result, term), dtype=float).reshape(())),
            sigma=float(NOMINAL_SIGMAS[kind] if sigma is None else sigma),
            stated=sigma is not None))
    return Misfit(tuple(rows))
