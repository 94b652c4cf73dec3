"""Test oracle: closed-form derivatives of every PIM output with respect to (epsilon, beta).

Hand-derived, independent of the dual numbers (:mod:`pim.model.dual`) through which the
fits differentiate the one formula: the tests check each against the other and against
finite differences. (It was ``pim/analysis/derivatives.py``; the library no longer uses it.)

Every output of
:func:`pim.solve` is differentiated in closed form with respect to the coefficient of
restitution epsilon and the fraction beta of the critical impulse ratio (mu = beta mu0).
All outputs are functions of the impulse P, which :mod:`pim.model.formula` writes as

    P = s (Pn0 n + beta Pt0 t),    s = -(1 + eps) u_n / (K_nn Pn0 + beta K_nt Pt0),

with (Pn0, Pt0) = K^-1 [-(1 + eps) u_n, -u_t] (the critical impulse, affine in eps). Hence

    dPn0/deps = -u_n K_tt / det K,     dPt0/deps = u_n K_nt / det K,
    D = K_nn Pn0 + beta K_nt Pt0,      dD/deps = K_nn dPn0 + beta K_nt dPt0,  dD/dbeta = K_nt Pt0,
    ds/deps = -u_n / D - s dD/deps / D,   ds/dbeta = -s dD/dbeta / D,

and the derivatives of the velocities, yaw rates, energies and angles follow by the chain
rule (each formula is next to its output in :func:`derivatives`). The closed form is tested
against automatic differentiation of the one formula (:mod:`pim.model.dual`, forward-mode
dual numbers; ``tests/pim/model/test_dual.py``) on random scenes, and against central finite
differences of :func:`pim.solve` (``tests/pim/analysis/test_sensitivity.py``). For derivatives with
respect to the other inputs (Gamma, C, the pre-impact motion) use
:func:`pim.model.dual.motion_jacobian`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pim.model.geometry import cross, dot
from pim.model.result import Result, output_values

__all__ = ["derivatives", "Derivatives", "output_values", "motion_derivatives",
           "MotionDerivative"]


def _impulse_derivatives(r: Result):
    """dPn, dPt [N s] with respect to eps and beta: ((dPn_e, dPt_e), (dPn_b, dPt_b)).

    Implements the chain rule of the module docstring; zero where the vehicles do not
    approach (no impulse).
    """
    e1 = 1.0 + r.eps
    u_n = r.approach_n
    k_nn, k_nt, k_tt = r.k_nn, r.k_nt, r.k_tt
    pn0, pt0 = r.critical_impulse_n, r.critical_impulse_t
    beta = r.beta
    det = k_nn * k_tt - k_nt * k_nt
    dpn0 = -u_n * k_tt / det
    dpt0 = u_n * k_nt / det
    with np.errstate(divide="ignore", invalid="ignore"):
        d = k_nn * pn0 + beta * k_nt * pt0
        s = -e1 * u_n / d
        ds_e = -u_n / d - s * (k_nn * dpn0 + beta * k_nt * dpt0) / d
        ds_b = -s * k_nt * pt0 / d
    dpn_e = ds_e * pn0 + s * dpn0
    dpt_e = beta * (ds_e * pt0 + s * dpt0)
    dpn_b = ds_b * pn0
    dpt_b = s * pt0 + beta * ds_b * pt0
    on = r.approaching
    out = [np.where(on, x, 0.0) for x in (dpn_e, dpt_e, dpn_b, dpt_b)]
    return (out[0], out[1]), (out[2], out[3])


@dataclass(frozen=True, eq=False)
class MotionDerivative:
    """Derivative of the post-impact motion with respect to one parameter.

    Attributes
    ----------
    impulse_n, impulse_t : ndarray
        d Pn, d Pt [N s per unit of the parameter].
    impulse : ndarray (..., 2)
        d P, impulse on vehicle 1 [N s].
    velocity1, velocity2 : ndarray (..., 2)
        d V1 = a1 dP, d V2 = -a2 dP [m/s].
    yaw_rate1, yaw_rate2 : ndarray
        d W1 = b1 (r1 x dP), d W2 = -b2 (r2 x dP) [rad/s].
    """

    impulse_n: np.ndarray
    impulse_t: np.ndarray
    impulse: np.ndarray
    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: np.ndarray
    yaw_rate2: np.ndarray


def motion_derivatives(result: Result) -> tuple[MotionDerivative, MotionDerivative]:
    """Closed-form derivatives of impulse, velocities and yaw rates w.r.t. (eps, beta).

    Parameters
    ----------
    result : Result
        Output of :func:`pim.solve` (any shape).

    Returns
    -------
    (MotionDerivative, MotionDerivative)
        d/d epsilon and d/d beta. The motion is linear in the impulse (V1 = v1 + P / m1,
        W1 = w1 + (r1 x P) / I1, and the opposite on vehicle 2), so only dP is needed.
    """
    c = result.case
    a1, b1 = c.vehicle1.inverse_mass, c.vehicle1.inverse_inertia
    a2, b2 = c.vehicle2.inverse_mass, c.vehicle2.inverse_inertia
    out = []
    for dpn, dpt in _impulse_derivatives(result):
        dp = dpn[..., None] * result.normal + dpt[..., None] * result.tangent
        out.append(MotionDerivative(
            impulse_n=dpn, impulse_t=dpt, impulse=dp,
            velocity1=a1[..., None] * dp, velocity2=-a2[..., None] * dp,
            yaw_rate1=b1 * cross(result.arm1, dp), yaw_rate2=-b2 * cross(result.arm2, dp)))
    return out[0], out[1]


@dataclass(frozen=True, eq=False)
class Derivatives:
    """Outputs of one solve and their derivatives with respect to epsilon and beta.

    Attributes
    ----------
    result : Result
        The solve they belong to.
    values, d_eps, d_beta : dict of str -> ndarray
        Output (see :data:`pim.model.quantities.OUTPUTS`) in SI units, its derivative per unit
        epsilon and
        per unit beta.
    """

    result: Result
    values: dict = field(repr=False)
    d_eps: dict = field(repr=False)
    d_beta: dict = field(repr=False)

    def __getitem__(self, name: str):
        """(value, d/d eps, d/d beta) of one output."""
        return self.values[name], self.d_eps[name], self.d_beta[name]


def _safe_ratio(num, den):
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den != 0, num / np.where(den != 0, den, 1.0), 0.0)


def _kinetic_derivative(mass, inertia, velocity, yaw_rate, dv, dw):
    """d KE = m V.dV + I W dW [J]; 0 for a fixed obstacle."""
    with np.errstate(invalid="ignore"):
        d = mass * dot(velocity, dv) + inertia * yaw_rate * dw
    return np.where(np.isinf(mass), 0.0, d)


def derivatives(result: Result) -> Derivatives:
    """Closed-form derivatives of every output of :func:`pim.solve` w.r.t. epsilon and beta.

    Parameters
    ----------
    result : Result
        Output of :func:`pim.solve`, any shape.

    Returns
    -------
    Derivatives
        ``values``, ``d_eps`` and ``d_beta`` for every key of
        :data:`pim.model.quantities.OUTPUTS`, each
        broadcast to the shape of the result (read-only views).

    Notes
    -----
    The impulse derivatives are those of the module docstring; the other outputs follow by
    the chain rule:
    |V|' = V.V'/|V|;  angle(P)' = (Px Py' - Py Px') / |P|^2 (PDOF' = -angle' for both
    vehicles, as PDOF = heading - direction the impulse comes from);
    mu0' = (Pt0' Pn0 - Pt0 Pn0') / Pn0^2, mu = beta mu0;  q' = q^2 B mu';
    U' = K P' (U = u + K P, the relative velocity of C after impact);
    KE_after' = sum m V.V' + I W W';  loss' = -KE_after';
    E_n' = -(Pn' (u_n + U_n) + Pn U_n') / 2 and likewise tangentially.
    Where a denominator vanishes (zero speed, zero impulse) the derivative is set to 0.
    """
    r = result
    c = r.case
    v1, v2 = c.vehicle1, c.vehicle2
    values = output_values(r)
    # d mu0 / d eps from the critical impulse, affine in eps
    det = r.k_nn * r.k_tt - r.k_nt * r.k_nt
    dpn0 = -r.approach_n * r.k_tt / det
    dpt0 = r.approach_n * r.k_nt / det
    with np.errstate(divide="ignore", invalid="ignore"):
        pn0, pt0 = r.critical_impulse_n, r.critical_impulse_t
        dmu0_e = (dpt0 * pn0 - pt0 * dpn0) / pn0 ** 2
    dmu0 = {"eps": dmu0_e, "beta": np.zeros_like(dmu0_e)}

    d_eps, d_beta = {}, {}
    for name, md, target in (("eps", motion_derivatives(r)[0], d_eps),
                             ("beta", motion_derivatives(r)[1], d_beta)):
        dp = md.impulse
        p = r.impulse
        dmu = r.beta * dmu0[name] + (r.mu0 if name == "beta" else 0.0)
        du_n = r.k_nn * md.impulse_n + r.k_nt * md.impulse_t
        du_t = r.k_nt * md.impulse_n + r.k_tt * md.impulse_t
        dke = (_kinetic_derivative(v1.mass, v1.yaw_inertia, r.velocity1, r.yaw_rate1,
                                   md.velocity1, md.yaw_rate1)
               + _kinetic_derivative(v2.mass, v2.yaw_inertia, r.velocity2, r.yaw_rate2,
                                     md.velocity2, md.yaw_rate2))
        dcn = -0.5 * (md.impulse_n * (r.approach_n + r.separation_n) + r.impulse_n * du_n)
        dct = -0.5 * (md.impulse_t * (r.approach_t + r.separation_t) + r.impulse_t * du_t)
        cn, ct = r.crush_energy_normal, r.crush_energy_tangential
        dangle = _safe_ratio(cross(p, dp), dot(p, p))
        mag = np.hypot(p[..., 0], p[..., 1])
        target.update({
            "velocity1_x": md.velocity1[..., 0], "velocity1_y": md.velocity1[..., 1],
            "velocity2_x": md.velocity2[..., 0], "velocity2_y": md.velocity2[..., 1],
            "yaw_rate1": md.yaw_rate1, "yaw_rate2": md.yaw_rate2,
            "speed1": _safe_ratio(dot(r.velocity1, md.velocity1), r.speed1),
            "speed2": _safe_ratio(dot(r.velocity2, md.velocity2), r.speed2),
            "delta_v1_x": md.velocity1[..., 0], "delta_v1_y": md.velocity1[..., 1],
            "delta_v2_x": md.velocity2[..., 0], "delta_v2_y": md.velocity2[..., 1],
            "delta_v1_magnitude": _safe_ratio(dot(r.delta_v1, md.velocity1),
                                              r.delta_v1_magnitude),
            "delta_v2_magnitude": _safe_ratio(dot(r.delta_v2, md.velocity2),
                                              r.delta_v2_magnitude),
            "impulse_x": dp[..., 0], "impulse_y": dp[..., 1],
            "impulse_magnitude": _safe_ratio(dot(p, dp), mag),
            "impulse_n": md.impulse_n, "impulse_t": md.impulse_t,
            "impulse_angle": dangle, "pdof1": -dangle, "pdof2": -dangle,
            "mu0": dmu0[name], "mu": dmu, "q": r.q * r.q * r.B * dmu,
            "separation_n": du_n, "separation_t": du_t,
            "restitution_check": _safe_ratio(-du_n, r.approach_n),
            "kinetic_energy_after": dke, "energy_loss": -dke,
            "energy_loss_percent": _safe_ratio(-100.0 * dke, r.kinetic_energy_before),
            "total_loss_brach": -dke,
            "crush_energy_normal": dcn, "crush_energy_tangential": dct,
            "tangential_share": _safe_ratio(dct * (cn + ct) - ct * (dcn + dct), (cn + ct) ** 2),
        })
    shape = np.shape(r.impulse_n)
    values, d_eps, d_beta = ({k: np.broadcast_to(v, shape) for k, v in d.items()}
                             for d in (values, d_eps, d_beta))
    return Derivatives(result=r, values=values, d_eps=d_eps, d_beta=d_beta)
