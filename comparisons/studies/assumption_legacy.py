"""The former per-assumption view of ``pim assumptions``, for callers written for it.

``comparisons.regression.sections`` (``pim baseline --with assumptions``) records, per rung
of the typical ladder under the former study's name (:data:`LEGACY_KEYS`), PIM's
per-vehicle errors against the rung's scene (:func:`outcome_errors`, PIM at the sheet's C)
and the rung's effective coefficients. The study proper measures its effects with
:func:`sim.error_measure.impact_error` (:mod:`comparisons.studies.assumptions`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import pim

__all__ = ["LEGACY_KEYS", "LegacyOutcome", "LegacySweep", "legacy_sweeps", "outcome_errors"]

#: The former study's assumption keys of the rungs that relax the same assumption.
LEGACY_KEYS = {"duration": "instantaneous", "tyres": "no_external_forces",
               "outline": "one_point", "friction": "restitution_friction"}


@dataclass(frozen=True)
class LegacyOutcome:
    """PIM's per-vehicle errors against one rung's scene (:func:`outcome_errors`) and the
    rung's effective coefficients, named as the former study named them.

    Attributes
    ----------
    value : float
        The swept value: the contact time of the typical ladder [s].
    errors : dict
        Per-vehicle relative errors of PIM (:func:`outcome_errors`) [-].
    eps_eff, beta_eff : float
        Coefficients :func:`pim.fit` finds for the simulated motion [-].
    fit_rms : float
        RMS residual of that fit [m/s].
    energy_loss : float
        Simulated kinetic energy lost, as a share of the energy before [-].
    pim_energy_loss : float
        PIM's kinetic energy lost, as a share of the energy before [-].
    stick_fraction : float
        Share of the contact time the contact stuck [-].
    point_distance : float
        Distance from the impulse centroid to the case's impact point C [m].
    failure : str or None
        Why the simulation failed; None when it ran.
    """

    value: float
    errors: dict
    eps_eff: float
    beta_eff: float
    fit_rms: float
    energy_loss: float
    pim_energy_loss: float
    stick_fraction: float
    point_distance: float
    failure: str | None


@dataclass(frozen=True)
class LegacySweep:
    """One rung under the former study's name.

    Attributes
    ----------
    key : str
        The former study's name of the rung.
    typical : LegacyOutcome
        Its outcome at the typical contact time.
    """

    key: str
    typical: LegacyOutcome


def legacy_sweeps(study) -> tuple:
    """The typical ladder of ``study`` (an :class:`comparisons.studies.assumptions.
    AssumptionStudy`) as :data:`LEGACY_KEYS` rung -> :class:`LegacySweep`."""
    case = study.case
    result = pim.solve(case, study.eps, study.beta_pim)
    e0 = float(np.asarray(result.kinetic_energy_before))
    pim_loss = float(np.asarray(result.energy_loss)) / e0 if e0 > 0 else math.nan
    point = np.asarray(case.impact.point, float).reshape(2)
    out = []
    for rung in study.typical.rungs:
        if rung.key not in LEGACY_KEYS:
            continue
        run = rung.run
        errors, _ = outcome_errors(case, result, run.velocity1, run.velocity2, run.yaw_rate1,
                                   run.yaw_rate2)
        out.append(LegacySweep(LEGACY_KEYS[rung.key], LegacyOutcome(
            value=study.typical.duration, errors=errors, eps_eff=rung.eps_eff,
            beta_eff=rung.beta_eff, fit_rms=rung.fit_rms, energy_loss=run.energy_loss,
            pim_energy_loss=pim_loss, stick_fraction=run.stick_fraction,
            point_distance=float(np.hypot(*(run.impact_point - point))),
            failure=run.failure)))
    return tuple(out)


def outcome_errors(case: pim.Case, result: pim.Result, velocity1, velocity2, yaw_rate1,
                   yaw_rate2) -> tuple[dict, tuple]:
    """Per-vehicle relative errors of PIM against a simulated outcome (benchmarks only; the
    study uses :func:`sim.error_measure.impact_error`) and the yaw-rate errors [deg/s]."""
    out, yaw_deg = {}, []
    sims = ((case.vehicle1, velocity1, yaw_rate1, result.velocity1, result.yaw_rate1),
            (case.vehicle2, velocity2, yaw_rate2, result.velocity2, result.yaw_rate2))
    for i, (vehicle, v_sim, w_sim, v_pim, w_pim) in enumerate(sims, start=1):
        if bool(vehicle.fixed):
            out.update({f"delta_v{i}": math.nan, f"speed{i}": math.nan, f"yaw{i}": math.nan})
            yaw_deg.append(math.nan)
            continue
        v0 = np.asarray(vehicle.velocity, float).reshape(2)
        v_sim, v_pim = np.asarray(v_sim, float), np.asarray(v_pim, float).reshape(2)
        dv_sim = max(float(np.hypot(*(v_sim - v0))), 1e-12)
        out[f"delta_v{i}"] = abs(float(np.hypot(*(v_pim - v0))) - dv_sim) / dv_sim
        out[f"speed{i}"] = abs(float(np.hypot(*v_pim)) - float(np.hypot(*v_sim))) / dv_sim
        dw = abs(float(np.asarray(w_pim)) - float(w_sim))
        out[f"yaw{i}"] = float(np.sqrt(vehicle.yaw_inertia / vehicle.mass)) * dw / dv_sim
        yaw_deg.append(math.degrees(dw))
    names = ("delta_v1", "delta_v2", "speed1", "speed2", "yaw1", "yaw2")
    return {k: out[k] for k in names}, tuple(yaw_deg)


