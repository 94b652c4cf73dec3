"""Sensitivities: derivatives of PIM outputs w.r.t. (epsilon, beta) and to uncertain inputs.

Two kinds of sensitivity are computed here.

*With respect to the model parameters* (:func:`derivatives`): every output of
:func:`pim.solve` is differentiated in closed form with respect to the coefficient of
restitution epsilon and the fraction beta of the critical impulse ratio (mu = beta mu0).
All outputs are functions of the impulse P, which :mod:`pim.solver` writes as

    P = s (Pn0 n + beta Pt0 t),    s = -(1 + eps) u_n / (K_nn Pn0 + beta K_nt Pt0),

with (Pn0, Pt0) = K^-1 [-(1 + eps) u_n, -u_t] (the critical impulse, affine in eps). Hence

    dPn0/deps = -u_n K_tt / det K,     dPt0/deps = u_n K_nt / det K,
    D = K_nn Pn0 + beta K_nt Pt0,      dD/deps = K_nn dPn0 + beta K_nt dPt0,  dD/dbeta = K_nt Pt0,
    ds/deps = -u_n / D - s dD/deps / D,   ds/dbeta = -s dD/dbeta / D,

and the derivatives of the velocities, yaw rates, energies and angles follow by the chain
rule (each formula is next to its output in :func:`derivatives`). Complex-step does not go
through :func:`pim.solve` (it casts to float), so the closed form is used; the tests compare
it with central finite differences of :func:`pim.solve`.

*With respect to the uncertain inputs* (:func:`sensitivity`): the point C, Gamma, masses,
yaw inertias, pre-impact velocities and yaw rates, and the measured post-impact motion. For
each input the derivative of the fitted (epsilon, beta) follows from the implicit-function
theorem at the optimum of :func:`pim.fit` (a bound that is active stays active: its
parameter does not move), and delta-V is differentiated both at fixed (epsilon, beta) and
with the refit. All perturbed cases are evaluated in one broadcast call of the solver.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .case import Case
from .solver import Result, solve

__all__ = ["derivatives", "Derivatives", "output_values", "OUTPUT_KINDS", "motion_derivatives",
           "sensitivity", "Sensitivity", "Uncertainty", "INPUTS"]


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


#: Output name -> kind of quantity (a key of :data:`pim.units.SI_UNITS`, or None if
#: dimensionless, "percent" for percentages). Vector outputs are split into _x/_y parts.
OUTPUT_KINDS: dict[str, str | None] = {
    "velocity1_x": "velocity", "velocity1_y": "velocity",
    "velocity2_x": "velocity", "velocity2_y": "velocity",
    "yaw_rate1": "angular_velocity", "yaw_rate2": "angular_velocity",
    "speed1": "velocity", "speed2": "velocity",
    "delta_v1_x": "velocity", "delta_v1_y": "velocity",
    "delta_v2_x": "velocity", "delta_v2_y": "velocity",
    "delta_v1_magnitude": "velocity", "delta_v2_magnitude": "velocity",
    "impulse_x": "impulse", "impulse_y": "impulse", "impulse_magnitude": "impulse",
    "impulse_n": "impulse", "impulse_t": "impulse",
    "impulse_angle": "angle", "pdof1": "angle", "pdof2": "angle",
    "mu0": None, "mu": None, "q": None,
    "separation_n": "velocity", "separation_t": "velocity", "restitution_check": None,
    "kinetic_energy_after": "energy", "energy_loss": "energy", "energy_loss_percent": "percent",
    "total_loss_brach": "energy",
    "crush_energy_normal": "energy", "crush_energy_tangential": "energy",
    "tangential_share": None,
}


def output_values(result: Result) -> dict[str, np.ndarray]:
    """The outputs of a :class:`pim.Result` that :func:`derivatives` differentiates.

    Parameters
    ----------
    result : Result
        Output of :func:`pim.solve`.

    Returns
    -------
    dict
        Name (a key of :data:`OUTPUT_KINDS`) -> value in SI units [m/s, rad/s, N s, rad, J, %].
        ``impulse_*`` is the impulse on vehicle 1 (vehicle 2 receives its negative).
    """
    r = result
    p = r.impulse
    return {
        "velocity1_x": r.velocity1[..., 0], "velocity1_y": r.velocity1[..., 1],
        "velocity2_x": r.velocity2[..., 0], "velocity2_y": r.velocity2[..., 1],
        "yaw_rate1": r.yaw_rate1, "yaw_rate2": r.yaw_rate2,
        "speed1": r.speed1, "speed2": r.speed2,
        "delta_v1_x": r.delta_v1[..., 0], "delta_v1_y": r.delta_v1[..., 1],
        "delta_v2_x": r.delta_v2[..., 0], "delta_v2_y": r.delta_v2[..., 1],
        "delta_v1_magnitude": r.delta_v1_magnitude, "delta_v2_magnitude": r.delta_v2_magnitude,
        "impulse_x": p[..., 0], "impulse_y": p[..., 1],
        "impulse_magnitude": np.hypot(p[..., 0], p[..., 1]),
        "impulse_n": r.impulse_n, "impulse_t": r.impulse_t,
        "impulse_angle": r.impulse_angle, "pdof1": r.pdof1, "pdof2": r.pdof2,
        "mu0": r.mu0, "mu": r.mu, "q": r.q,
        "separation_n": r.separation_n, "separation_t": r.separation_t,
        "restitution_check": r.restitution_check,
        "kinetic_energy_after": r.kinetic_energy_after, "energy_loss": r.energy_loss,
        "energy_loss_percent": r.energy_loss_percent, "total_loss_brach": r.total_loss_brach,
        "crush_energy_normal": r.crush_energy_normal,
        "crush_energy_tangential": r.crush_energy_tangential,
        "tangential_share": r.tangential_share,
    }


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
            yaw_rate1=b1 * _cross(result.arm1, dp), yaw_rate2=-b2 * _cross(result.arm2, dp)))
    return out[0], out[1]


@dataclass(frozen=True, eq=False)
class Derivatives:
    """Outputs of one solve and their derivatives with respect to epsilon and beta.

    Attributes
    ----------
    result : Result
        The solve they belong to.
    values, d_eps, d_beta : dict of str -> ndarray
        Output (see :data:`OUTPUT_KINDS`) in SI units, its derivative per unit epsilon and
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
        d = mass * _dot(velocity, dv) + inertia * yaw_rate * dw
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
        ``values``, ``d_eps`` and ``d_beta`` for every key of :data:`OUTPUT_KINDS`, each
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
        dangle = _safe_ratio(_cross(p, dp), _dot(p, p))
        mag = np.hypot(p[..., 0], p[..., 1])
        target.update({
            "velocity1_x": md.velocity1[..., 0], "velocity1_y": md.velocity1[..., 1],
            "velocity2_x": md.velocity2[..., 0], "velocity2_y": md.velocity2[..., 1],
            "yaw_rate1": md.yaw_rate1, "yaw_rate2": md.yaw_rate2,
            "speed1": _safe_ratio(_dot(r.velocity1, md.velocity1), r.speed1),
            "speed2": _safe_ratio(_dot(r.velocity2, md.velocity2), r.speed2),
            "delta_v1_x": md.velocity1[..., 0], "delta_v1_y": md.velocity1[..., 1],
            "delta_v2_x": md.velocity2[..., 0], "delta_v2_y": md.velocity2[..., 1],
            "delta_v1_magnitude": _safe_ratio(_dot(r.delta_v1, md.velocity1),
                                              r.delta_v1_magnitude),
            "delta_v2_magnitude": _safe_ratio(_dot(r.delta_v2, md.velocity2),
                                              r.delta_v2_magnitude),
            "impulse_x": dp[..., 0], "impulse_y": dp[..., 1],
            "impulse_magnitude": _safe_ratio(_dot(p, dp), mag),
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


# ---------------------------------------------------------------------------------------------
# sensitivity to the uncertain inputs
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Uncertainty:
    """Typical (one-standard-deviation) uncertainty of each input, SI units.

    The defaults are what a reconstruction from scene evidence typically achieves; override
    any of them (``Uncertainty(point=0.2)``) to match the case at hand.

    Attributes
    ----------
    point : float
        Each coordinate of the impact point C [m] (default 0.1 m).
    normal_angle : float
        The contact-plane angle Gamma [rad] (default 5 deg).
    mass_fraction : float
        Each mass, as a fraction of its value [-] (default 2 %).
    inertia_fraction : float
        Each yaw inertia, as a fraction of its value [-] (default 10 %).
    velocity : float
        Each component of the pre-impact velocities [m/s] (default 1 m/s).
    yaw_rate : float
        The pre-impact yaw rates [rad/s] (default 5 deg/s).
    measured_velocity : float
        Each component of the measured post-impact velocities [m/s] (default 0.5 m/s).
    measured_yaw_rate : float
        The measured post-impact yaw rates [rad/s] (default 10 deg/s).
    """

    point: float = 0.1
    normal_angle: float = float(np.radians(5.0))
    mass_fraction: float = 0.02
    inertia_fraction: float = 0.10
    velocity: float = 1.0
    yaw_rate: float = float(np.radians(5.0))
    measured_velocity: float = 0.5
    measured_yaw_rate: float = float(np.radians(10.0))

    def __post_init__(self) -> None:
        for name in self.__dataclass_fields__:
            value = float(getattr(self, name))
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"uncertainty.{name} must be a finite number > 0, got {value}")
            object.__setattr__(self, name, value)


#: Input key -> (label, kind of quantity for display units).
INPUTS: dict[str, tuple[str, str]] = {
    "point_x": ("impact point C, x", "length"),
    "point_y": ("impact point C, y", "length"),
    "normal_angle": ("contact-plane angle Gamma", "angle"),
    "mass1": ("mass of vehicle 1", "mass"),
    "mass2": ("mass of vehicle 2", "mass"),
    "yaw_inertia1": ("yaw inertia of vehicle 1", "inertia"),
    "yaw_inertia2": ("yaw inertia of vehicle 2", "inertia"),
    "velocity1_x": ("pre-impact velocity 1, x", "velocity"),
    "velocity1_y": ("pre-impact velocity 1, y", "velocity"),
    "velocity2_x": ("pre-impact velocity 2, x", "velocity"),
    "velocity2_y": ("pre-impact velocity 2, y", "velocity"),
    "yaw_rate1": ("pre-impact yaw rate 1", "angular_velocity"),
    "yaw_rate2": ("pre-impact yaw rate 2", "angular_velocity"),
    "measured_velocity1_x": ("measured post-impact velocity 1, x", "velocity"),
    "measured_velocity1_y": ("measured post-impact velocity 1, y", "velocity"),
    "measured_velocity2_x": ("measured post-impact velocity 2, x", "velocity"),
    "measured_velocity2_y": ("measured post-impact velocity 2, y", "velocity"),
    "measured_yaw_rate1": ("measured post-impact yaw rate 1", "angular_velocity"),
    "measured_yaw_rate2": ("measured post-impact yaw rate 2", "angular_velocity"),
}

#: Output key -> (label, kind of quantity for display units; None = dimensionless).
SENSITIVITY_OUTPUTS: dict[str, tuple[str, str | None]] = {
    "eps": ("fitted epsilon", None),
    "beta": ("fitted beta", None),
    "delta_v1": ("|delta-V| of vehicle 1", "velocity"),
    "delta_v2": ("|delta-V| of vehicle 2", "velocity"),
}

#: Relative finite-difference step (fraction of the typical uncertainty) for the inputs.
INPUT_STEP = 1e-4
#: Finite-difference step in (eps, beta) for the Hessian of the cost.
PARAMETER_STEP = 1e-5


@dataclass(frozen=True, eq=False)
class Sensitivity:
    """How the answers move with the uncertain inputs.

    Attributes
    ----------
    case : Case
        The case analysed.
    eps, beta : float
        The parameters at which it was evaluated (the fitted ones when ``fit`` is set).
    fit : FitResult or None
        The fit whose optimum is differentiated; None when nothing is measured (then only
        delta-V at fixed eps, beta is reported).
    inputs : tuple of str
        Input keys (see :data:`INPUTS`).
    nominal, sigma : ndarray (n_inputs,)
        Nominal value and typical uncertainty of each input [SI].
    outputs : tuple of str
        Output keys (see :data:`SENSITIVITY_OUTPUTS`); "eps", "beta" only with a fit.
    values : ndarray (n_outputs,)
        The outputs at the nominal inputs [SI].
    derivative : ndarray (n_outputs, n_inputs)
        d output / d input [SI units per SI unit]. With a fit, delta-V includes the refit
        of (eps, beta): d dV/dx = partial dV/dx + dV/d(eps, beta) . d(eps, beta)/dx.
    partial_delta_v : ndarray (2, n_inputs)
        d |delta-V_i| / d input at fixed (eps, beta) [SI].
    active_bounds : tuple of str
        Parameters held on an active bound (they do not move: derivative 0).
    """

    case: Case
    eps: float
    beta: float
    fit: object
    inputs: tuple[str, ...]
    nominal: np.ndarray
    sigma: np.ndarray
    outputs: tuple[str, ...]
    values: np.ndarray
    derivative: np.ndarray
    partial_delta_v: np.ndarray
    active_bounds: tuple[str, ...] = ()

    @property
    def effect(self) -> np.ndarray:
        """Change of each output for one typical uncertainty of each input, |d/dx| sigma [SI]."""
        return np.abs(self.derivative) * self.sigma

    def ranked(self, output: str) -> list[int]:
        """Input indices, largest effect on ``output`` first."""
        row = self.effect[self.outputs.index(output)]
        return [int(i) for i in np.argsort(-row, kind="stable")]

    def to_dict(self) -> dict:
        """JSON-ready dict (SI units): per output, the inputs ranked by effect."""
        out = {}
        for k, name in enumerate(self.outputs):
            out[name] = {
                "value": float(self.values[k]),
                "inputs": [{"input": self.inputs[i], "sigma": float(self.sigma[i]),
                            "per_unit": float(self.derivative[k, i]),
                            "per_sigma": float(self.effect[k, i])} for i in self.ranked(name)],
            }
        return {"case": self.case.name, "eps": self.eps, "beta": self.beta,
                "fitted": self.fit is not None, "active_bounds": list(self.active_bounds),
                "units": "SI", "outputs": out}


def _perturbed_case(case: Case, keys, steps) -> Case:
    """A batch of 2 K cases: input k moved by +steps[k] (rows 2k) and -steps[k] (rows 2k+1)."""
    n = 2 * len(keys)
    sign = np.tile([1.0, -1.0], len(keys))
    delta = {key: np.zeros(n) for key in INPUTS}
    for k, key in enumerate(keys):
        delta[key][2 * k:2 * k + 2] = sign[2 * k:2 * k + 2] * steps[k]

    def vec(base, dx, dy):
        return np.broadcast_to(base, (n, 2)) + np.stack([dx, dy], axis=-1)

    def vehicle(v, i):
        if v.fixed.all():
            return v
        return replace(v, mass=v.mass + delta[f"mass{i}"],
                       yaw_inertia=v.yaw_inertia + delta[f"yaw_inertia{i}"],
                       velocity=vec(v.velocity, delta[f"velocity{i}_x"], delta[f"velocity{i}_y"]),
                       yaw_rate=v.yaw_rate + delta[f"yaw_rate{i}"])

    impact = replace(case.impact, point=vec(case.impact.point, delta["point_x"], delta["point_y"]),
                     normal_angle=case.impact.normal_angle + delta["normal_angle"])
    return replace(case, vehicle1=vehicle(case.vehicle1, 1), vehicle2=vehicle(case.vehicle2, 2),
                   impact=impact)


def _nominal_and_sigma(case: Case, unc: Uncertainty, names) -> tuple[list, list, list]:
    v1, v2, imp, m = case.vehicle1, case.vehicle2, case.impact, case.measured
    rows = [("point_x", imp.point[0], unc.point), ("point_y", imp.point[1], unc.point),
            ("normal_angle", imp.normal_angle, unc.normal_angle)]
    for i, v in ((1, v1), (2, v2)):
        if v.fixed.all():
            continue
        rows += [(f"mass{i}", v.mass, unc.mass_fraction * v.mass),
                 (f"yaw_inertia{i}", v.yaw_inertia, unc.inertia_fraction * v.yaw_inertia)]
    for i, v in ((1, v1), (2, v2)):
        if v.fixed.all():
            continue
        rows += [(f"velocity{i}_x", v.velocity[0], unc.velocity),
                 (f"velocity{i}_y", v.velocity[1], unc.velocity),
                 (f"yaw_rate{i}", v.yaw_rate, unc.yaw_rate)]
    for name in names:
        i = int(name[-3] if name.startswith("velocity") else name[-1])
        if name.startswith("velocity"):
            target = (m.velocity1 if i == 1 else m.velocity2)["xy".index(name[-1])]
            rows.append((f"measured_{name}", target, unc.measured_velocity))
        else:
            rows.append((f"measured_{name}", m.yaw_rate1 if i == 1 else m.yaw_rate2,
                         unc.measured_yaw_rate))
    keys = [r[0] for r in rows]
    return keys, [float(r[1]) for r in rows], [float(r[2]) for r in rows]


def _cost_gradient(result: Result, names) -> np.ndarray:
    """d S / d (eps, beta) = 2 J^T r [m^2/s^2], shape (..., 2)."""
    from .fit import _residuals_and_jacobian

    r, j = _residuals_and_jacobian(result, names)
    return 2.0 * np.einsum("...i,...ij->...j", r, j)


def sensitivity(case: Case, fit_result=None, *, eps=None, beta=None, uncertainty=None,
                include_yaw: bool = False) -> Sensitivity:
    """Sensitivity of the fitted (epsilon, beta) and of delta-V to the uncertain inputs.

    Parameters
    ----------
    case : Case
        A single case.
    fit_result : FitResult, optional
        The fit to differentiate. By default the case is fitted with :func:`pim.fit` when it
        has measured values and neither ``eps`` nor ``beta`` is given.
    eps, beta : float, optional
        Evaluate delta-V at these parameters instead of fitting (defaults: the case's).
    uncertainty : Uncertainty, optional
        Typical uncertainties; default :class:`Uncertainty()`.
    include_yaw : bool
        Passed to :func:`pim.fit` when the fit is made here.

    Returns
    -------
    Sensitivity

    Notes
    -----
    At the optimum the projected gradient g(theta, x) = 2 J^T r of the cost over the free
    parameters vanishes, so by the implicit-function theorem
    d theta_f / dx = -H_ff^-1 dg_f/dx, with H = dg/dtheta (central differences of the
    closed-form g, step :data:`PARAMETER_STEP`) and dg/dx by central differences over all
    inputs at once (one broadcast solve, step :data:`INPUT_STEP` times sigma). A parameter
    on an active bound stays there (derivative 0); a fixed parameter does not move. For the
    measured values dr_i/dy_i = -1 (or -k_i for yaw), so dg/dy_i = -2 J_i exactly.
    """
    from .fit import FitResult, _measured_terms
    from .fit import fit as fit_case

    if np.size(case.vehicle1.mass) != 1 or np.shape(case.impact.point) != (2,):
        raise ValueError("sensitivity needs a single case, not a batch of cases")
    unc = Uncertainty() if uncertainty is None else uncertainty
    if fit_result is None and eps is None and beta is None:
        try:
            _measured_terms(case, include_yaw)
        except ValueError:
            pass
        else:
            fit_result = fit_case(case, include_yaw=include_yaw)
    if fit_result is not None:
        if not isinstance(fit_result, FitResult):
            raise ValueError("fit_result must be a FitResult from pim.fit")
        eps, beta = fit_result.eps, fit_result.beta
        names = fit_result.residual_names
    else:
        names = ()
        eps = case.impact.restitution if eps is None else eps
        if eps is None:
            raise ValueError("eps is required: nothing is measured to fit, so give eps "
                             "or set impact.restitution in the case")
        beta = (1.0 if case.impact.beta is None else case.impact.beta) if beta is None else beta
    eps, beta = float(eps), float(beta)

    keys, nominal, sigma = _nominal_and_sigma(case, unc, names)
    model_keys = [k for k in keys if not k.startswith("measured_")]
    n_model = len(model_keys)
    steps = INPUT_STEP * np.array(sigma[:n_model])

    # one broadcast solve over all +/- perturbations of the model inputs
    batch = solve(_perturbed_case(case, model_keys, steps), eps, beta)
    base = derivatives(solve(case, eps, beta))
    dv = np.stack([batch.delta_v1_magnitude, batch.delta_v2_magnitude])       # (2, 2K)
    partial = np.zeros((2, len(keys)))
    partial[:, :n_model] = (dv[:, 0::2] - dv[:, 1::2]) / (2 * steps)
    dv_dtheta = np.array([[base.d_eps[f"delta_v{i}_magnitude"],
                           base.d_beta[f"delta_v{i}_magnitude"]] for i in (1, 2)], dtype=float)

    outputs = ("delta_v1", "delta_v2")
    values = [float(base.values["delta_v1_magnitude"]), float(base.values["delta_v2_magnitude"])]
    derivative = partial.copy()
    active: tuple[str, ...] = ()
    if fit_result is not None:
        free = [p not in fit_result.fixed and p not in fit_result.on_bound for p in ("eps", "beta")]
        active = tuple(p for p in ("eps", "beta") if p in fit_result.on_bound)
        dtheta = np.zeros((2, len(keys)))
        idx = [i for i, f in enumerate(free) if f]
        if idx:
            # dg/dx for the model inputs (finite differences) and measured values (exact)
            g = _cost_gradient(batch, names)                                    # (2K, 2)
            dg = np.zeros((2, len(keys)))
            dg[:, :n_model] = ((g[0::2] - g[1::2]) / (2 * steps[:, None])).T
            from .fit import _residuals_and_jacobian

            _, j0 = _residuals_and_jacobian(base.result, names)                 # (n, 2)
            for col, key in enumerate(keys[n_model:], start=n_model):
                term = names.index(key[len("measured_"):])
                weight = 1.0
                if key.startswith("measured_yaw"):
                    from .fit import _gyration_radius
                    v = case.vehicle1 if key.endswith("1") else case.vehicle2
                    weight = float(_gyration_radius(v))
                dg[:, col] = -2.0 * weight * j0[term]
            # Hessian of the cost over (eps, beta) by central differences of g
            h = PARAMETER_STEP
            e_pts = np.clip([eps + h, eps - h], 0.0, 1.0)
            thetas_e = np.array([e_pts[0], e_pts[1], eps, eps])
            thetas_b = np.array([beta, beta, beta + h, beta - h])
            gh = _cost_gradient(solve(case, thetas_e, thetas_b), names)         # (4, 2)
            hess = np.stack([(gh[0] - gh[1]) / (e_pts[0] - e_pts[1]),
                             (gh[2] - gh[3]) / (2 * h)], axis=1)  # H[i, j] = dg_i / dtheta_j
            hess = 0.5 * (hess + hess.T)
            h_ff = hess[np.ix_(idx, idx)]
            if not np.all(np.isfinite(h_ff)) or np.linalg.cond(h_ff) > 1e12:
                raise ValueError("the cost is flat at the optimum (singular Hessian): the "
                                 "fitted parameters are not determined by the measurements")
            dtheta[idx] = -np.linalg.solve(h_ff, dg[idx])
        derivative = np.vstack([dtheta, partial + dv_dtheta @ dtheta])
        outputs = ("eps", "beta", *outputs)
        values = [eps, beta, *values]
    return Sensitivity(case=case, eps=eps, beta=beta, fit=fit_result, inputs=tuple(keys),
                       nominal=np.array(nominal), sigma=np.array(sigma), outputs=outputs,
                       values=np.array(values), derivative=derivative,
                       partial_delta_v=partial, active_bounds=active)
