"""Reconstruction chain: evidence at rest -> post-impact motion -> impact speeds.

Step 1 (this module, :func:`post_impact_motion`): for each vehicle with ``[evidence]``,
the run-out inverse (:func:`pim.analysis.runout_fit.fit_runout`) from its separation state
to its measured rest state gives the post-impact CG velocity and yaw rate, with standard
deviations from the fit's Jacobian and the evidence's sigmas. PIM's impact is
instantaneous, so each vehicle separates from its impact position and heading (the case's
``cg`` and ``heading``).

Step 2: the post-impact motion becomes the case's ``measured`` data; the pre-impact
speeds, restitution and beta named in ``[unknown]`` are then fitted by ``pim.fit`` with
``free=case.unknown`` (the inverse PIM, see /work/notes/fit-api.md). Beside it, the
linear-momentum two-equation solve (:func:`pim.analysis.momentum.momentum_speeds`) is
reported as a check.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..model.case import Case, Measured
from .free_inputs import approach_direction
from .momentum import MomentumSpeeds, momentum_speeds
from .runout_fit import RunoutFit, fit_runout

__all__ = ["PostImpact", "post_impact_motion", "approach_direction"]


@dataclass(frozen=True)
class PostImpact:
    """Post-impact motion reconstructed from the evidence (SI).

    Attributes
    ----------
    case : Case, the input case with ``measured`` replaced by the run-out fits' motion
    runouts : dict vehicle number (1, 2) -> RunoutFit (only vehicles with evidence)
    velocity_sigma : dict vehicle number -> (2, 2) covariance of the post-impact velocity
    yaw_rate_sigma : dict vehicle number -> standard deviation of the yaw rate [rad/s]
    momentum : MomentumSpeeds or None (needs both vehicles' evidence)
    messages : list of plain-language warnings (unreachable rest, no stop, several minima)
    """

    case: Case
    runouts: dict
    velocity_sigma: dict
    yaw_rate_sigma: dict
    momentum: MomentumSpeeds | None
    messages: list


def _velocity_covariance(fit: RunoutFit) -> tuple[np.ndarray, float]:
    """Covariance of (v_x, v_y) and sigma of omega from the polar (V, theta, omega) one."""
    c, s = np.cos(fit.direction), np.sin(fit.direction)
    jac = np.array([[c, -fit.speed * s, 0.0], [s, fit.speed * c, 0.0], [0.0, 0.0, 1.0]])
    cov = jac @ fit.covariance @ jac.T
    return cov[:2, :2], float(np.sqrt(max(cov[2, 2], 0.0)))


def post_impact_motion(case: Case, *, speed_bounds=(0.0, 60.0),
                       yaw_rate_bounds=(-15.0, 15.0), **fit_options) -> PostImpact:
    """Fit each vehicle's post-impact motion to its rest evidence (step 1 of the chain).

    Parameters
    ----------
    case : Case
        With ``evidence`` (the ``[evidence]`` table) for one or both vehicles.
    speed_bounds, yaw_rate_bounds : (float, float)
        [m/s], [rad/s] bounds of the post-impact motion searched.
    **fit_options
        Passed to :func:`pim.analysis.runout_fit.fit_runout`.

    Raises
    ------
    ValueError
        The case has no evidence.
    """
    evidence = case.evidence
    if evidence is None or (evidence.vehicle1 is None and evidence.vehicle2 is None):
        raise ValueError("evidence: the case has no [evidence] table (rest positions, "
                         "friction, wheelbase and track of at least one vehicle)")
    runouts, vel_cov, yaw_sigma, measured, messages = {}, {}, {}, {}, []
    for i in (1, 2):
        ev = getattr(evidence, f"vehicle{i}")
        if ev is None:
            continue
        vehicle = getattr(case, f"vehicle{i}")
        fit = fit_runout(ev.runout_vehicle(float(vehicle.mass), float(vehicle.yaw_inertia)),
                         vehicle.cg, float(vehicle.heading), ev.rest_position,
                         ev.rest_heading, path_points=ev.path_points if len(ev.path_points)
                         else None, position_sigma=ev.position_sigma,
                         heading_sigma=ev.heading_sigma, speed_bounds=speed_bounds,
                         yaw_rate_bounds=yaw_rate_bounds, **fit_options)
        runouts[i] = fit
        vel_cov[i], yaw_sigma[i] = _velocity_covariance(fit)
        measured[f"velocity{i}"] = fit.velocity
        measured[f"yaw_rate{i}"] = fit.yaw_rate
        if fit.message:
            messages.append(f"vehicle{i}: {fit.message}")
    momentum = None
    if len(runouts) == 2:
        momentum = momentum_speeds(float(case.vehicle1.mass), float(case.vehicle2.mass),
                                   approach_direction(case.vehicle1),
                                   approach_direction(case.vehicle2), runouts[1].velocity,
                                   runouts[2].velocity, vel_cov[1], vel_cov[2])
        if momentum.message:
            messages.append(f"linear momentum: {momentum.message}")
    return PostImpact(replace(case, measured=Measured(**measured)), runouts, vel_cov,
                      yaw_sigma, momentum, messages)
