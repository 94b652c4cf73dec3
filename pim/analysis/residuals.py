"""Residuals of measured post-impact motion against PIM, and their Jacobian in (eps, beta).

The residual terms are ``velocity{1,2}_{x,y}`` -> V - V_measured [m/s] and
``yaw_rate{1,2}`` -> k (Omega - Omega_measured) [m/s], with k = sqrt(I / m) the vehicle's
radius of gyration (the speed that spin gives a point at distance k from the CG).
"""

from __future__ import annotations

import numpy as np

from ..model.case import Case
from ..model.geometry import radius_of_gyration
from ..model.numbers import InputError
from ..model.result import Result
from .derivatives import motion_derivatives

__all__ = ["measured_terms", "has_measured_terms", "residuals", "residuals_and_jacobian",
           "measured_weights"]


def measured_terms(case: Case, include_yaw: bool) -> tuple[str, ...]:
    m = case.measured
    names: list[str] = []
    if m is not None:
        for i, vel in ((1, m.velocity1), (2, m.velocity2)):
            if vel is not None:
                names += [f"velocity{i}_x", f"velocity{i}_y"]
        if include_yaw:
            for i, w in ((1, m.yaw_rate1), (2, m.yaw_rate2)):
                if w is not None:
                    names.append(f"yaw_rate{i}")
    if not names:
        has_yaw = m is not None and (m.yaw_rate1 is not None or m.yaw_rate2 is not None)
        hint = (" (only yaw rates are measured: use include_yaw=True / --include-yaw)"
                if has_yaw and not include_yaw else "")
        raise InputError(
            f"case {case.name or '(unnamed)'}: nothing to fit; case.measured needs a "
            f"post-impact velocity1 or velocity2 [m/s]{hint}")
    return tuple(names)


def residuals(result: Result, names: tuple[str, ...]) -> np.ndarray:
    """Residuals of the fit [m/s], shape (..., len(names)).

    Parameters
    ----------
    result : Result
        Solve of the case (any shape); its ``case.measured`` holds the targets.
    names : tuple of str
        Terms: ``velocity{1,2}_{x,y}`` -> V - V_measured, ``yaw_rate{1,2}`` ->
        k (Omega - Omega_measured) with k = sqrt(I / m) the radius of gyration.
    """
    return residuals_and_jacobian(result, names, jacobian=False)[0]


def residuals_and_jacobian(result: Result, names, jacobian: bool = True):
    case = result.case
    m = case.measured
    md = motion_derivatives(result) if jacobian else None
    res, jac = [], []
    for name in names:
        if name.startswith("velocity"):
            i, axis = int(name[8]), "xy".index(name[-1])
            target = (m.velocity1 if i == 1 else m.velocity2)[axis]
            value = (result.velocity1 if i == 1 else result.velocity2)[..., axis]
            res.append(value - target)
            if jacobian:
                jac.append([getattr(d, f"velocity{i}")[..., axis] for d in md])
        else:
            i = int(name[-1])
            v = case.vehicle1 if i == 1 else case.vehicle2
            k = radius_of_gyration(v.mass, v.yaw_inertia)
            target = m.yaw_rate1 if i == 1 else m.yaw_rate2
            res.append(k * ((result.yaw_rate1 if i == 1 else result.yaw_rate2) - target))
            if jacobian:
                jac.append([k * getattr(d, f"yaw_rate{i}") for d in md])
    r = np.stack(np.broadcast_arrays(*res), axis=-1)
    if not jacobian:
        return r, None
    # shape (..., n_terms, 2): d r_i / d (eps, beta)
    j = np.stack([np.stack(np.broadcast_arrays(*row), axis=-1) for row in jac], axis=-2)
    return r, j


def measured_weights(case: Case, names: tuple[str, ...]) -> np.ndarray | None:
    """Weights that turn the residuals into standardised ones, or None when unweighted.

    With the ``[measured]`` standard deviations (``Measured.velocity1_sigma`` [m/s],
    ``yaw_rate1_sigma`` [rad/s] ...), the velocity residual V - V_m is divided by its sigma
    and the yaw residual k (Omega - Omega_m) by k sigma, so that sum (w r)^2 is a chi-square.
    Either every fitted term has a sigma or none has: a mix is an error naming what is missing.
    """
    m = case.measured
    w, missing = [], []
    for name in names:
        if name.startswith("velocity"):
            i, axis = int(name[8]), "xy".index(name[-1])
            sigma = getattr(m, f"velocity{i}_sigma")
            w.append(None if sigma is None else 1.0 / sigma[axis])
        else:
            i = int(name[-1])
            sigma = getattr(m, f"yaw_rate{i}_sigma")
            v = case.vehicle1 if i == 1 else case.vehicle2
            w.append(None if sigma is None
                     else 1.0 / (radius_of_gyration(v.mass, v.yaw_inertia) * sigma))
        if w[-1] is None:
            missing.append(name)
    if len(missing) == len(names):
        return None
    if missing:
        raise InputError(f"measured: standard deviations are given for some fitted terms but "
                         f"not for {', '.join(missing)}; give a *_sigma for every measured "
                         f"quantity that is fitted, or for none")
    return np.array([float(np.asarray(x).reshape(())) for x in w])


def has_measured_terms(case: Case, include_yaw: bool = False) -> bool:
    """Whether the case has anything to fit: a measured post-impact velocity (or, with
    ``include_yaw``, a measured yaw rate)."""
    m = case.measured
    if m is None:
        return False
    if m.velocity1 is not None or m.velocity2 is not None:
        return True
    return include_yaw and (m.yaw_rate1 is not None or m.yaw_rate2 is not None)
