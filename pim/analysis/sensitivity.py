"""Sensitivity of the fitted (epsilon, beta) and of delta-V to the uncertain inputs.

*With respect to the uncertain inputs* (:func:`sensitivity`): the point C, Gamma, masses,
yaw inertias, pre-impact velocities and yaw rates, and the measured post-impact motion. For
each input the derivative of the fitted (epsilon, beta) follows from the implicit-function
theorem at the optimum of :func:`pim.fit` (a bound that is active stays active: its
parameter does not move), and delta-V is differentiated both at fixed (epsilon, beta) and
with the refit. All perturbed cases are evaluated in one broadcast call of the solver.

Each input's sigma comes from the case where it states one (:data:`SOURCES`): its
``[uncertainty]`` distribution (its standard deviation, :meth:`Distribution.sd`: a normal's
sd, a uniform's width / sqrt(12), +- b as b / sqrt(3), 0 for a fixed value), the scatter of
an estimated input (a yaw inertia from the wheelbase), the ``[measured]`` sigma of a measured
value; the typical uncertainties (:class:`TypicalUncertainty`) fill in the rest, and those
named in ``prefer`` (the command line's ``--sigma``) take precedence over the case.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..model.case import Case, checked_case
from ..model.dual import MOTION_OUTPUTS, motion_jacobian
from ..model.evidence_terms import as_residual_terms, split_terms
from ..model.geometry import radius_of_gyration
from ..model.motion import Term
from ..model.numbers import InputError, check_numbers, check_type
from ..model.quantities import INPUTS as QUANTITY_INPUTS
from ..model.quantities import MEASURED, OUTPUTS, Quantity
from ..model.solver import defaults, solve
from .fitting import FitResult
from .fitting import fit as fit_case
from .free_fit import free_residuals
from .free_inputs import STATE, case_state
from .residuals import has_measured_terms, measured_value, residual_terms

__all__ = ["sensitivity", "Sensitivity", "TypicalUncertainty", "TYPICAL_KINDS", "INPUTS",
           "SENSITIVITY_OUTPUTS", "SOURCES"]

#: Where an input's sigma comes from: the case file ([uncertainty] or [measured]), the
#: scatter of an input the program estimated, the typical value, or an option (--sigma).
SOURCES = ("case", "estimate", "typical", "option")

#: The unit kind of each field of :class:`TypicalUncertainty` (for parsing an override).
TYPICAL_KINDS = {"point": "length", "normal_angle": "angle", "mass_fraction": "dimensionless",
                 "inertia_fraction": "dimensionless", "velocity": "velocity",
                 "yaw_rate": "angular_velocity", "measured_velocity": "velocity",
                 "measured_yaw_rate": "angular_velocity"}


@dataclass(frozen=True)
class TypicalUncertainty:
    """Typical (one-standard-deviation) uncertainty of each input, SI units.

    The defaults are what a reconstruction from scene evidence typically achieves; override
    any of them (``TypicalUncertainty(point=0.2)``) to match the case at hand.

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
                raise InputError(f"uncertainty.{name} must be a finite number > 0, got {value}")
            object.__setattr__(self, name, value)


#: The inputs whose uncertainty moves the answers: dotted name -> Quantity (a subset of
#: :data:`pim.model.quantities.INPUTS`, and the measured motion).
INPUTS: dict[str, Quantity] = {
    **{k: QUANTITY_INPUTS[k] for k in ("impact.point_x", "impact.point_y",
                                       "impact.normal_angle")},
    **{f"vehicle{i}.{f}": QUANTITY_INPUTS[f"vehicle{i}.{f}"] for i in (1, 2)
       for f in ("mass", "yaw_inertia", "velocity_x", "velocity_y", "yaw_rate")},
    **MEASURED,
}

#: Output key -> (label, kind of quantity for display units; None = dimensionless).
SENSITIVITY_OUTPUTS: dict[str, Quantity] = {
    "eps": Quantity(None, "fitted epsilon"),
    "beta": Quantity(None, "fitted beta"),
    "delta_v1_magnitude": OUTPUTS["delta_v1_magnitude"],
    "delta_v2_magnitude": OUTPUTS["delta_v2_magnitude"],
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
    sources : tuple of str
        Where each input's sigma comes from, one of :data:`SOURCES` (module notes).
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
    sources: tuple[str, ...] = ()

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
                            "source": self.sources[i] if self.sources else "typical",
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
        p = f"vehicle{i}."
        return replace(v, mass=v.mass + delta[p + "mass"],
                       yaw_inertia=v.yaw_inertia + delta[p + "yaw_inertia"],
                       velocity=vec(v.velocity, delta[p + "velocity_x"], delta[p + "velocity_y"]),
                       yaw_rate=v.yaw_rate + delta[p + "yaw_rate"])

    impact = replace(case.impact, point=vec(case.impact.point, delta["impact.point_x"],
                                            delta["impact.point_y"]),
                     normal_angle=case.impact.normal_angle + delta["impact.normal_angle"])
    return replace(case, vehicle1=vehicle(case.vehicle1, 1), vehicle2=vehicle(case.vehicle2, 2),
                   impact=impact)


def _typical_rows(case: Case, unc: TypicalUncertainty, terms) -> list[tuple]:
    """(input key, nominal [SI], typical sigma [SI], its field of TypicalUncertainty, the
    case's stated sigma [SI] or None, its source) of every input, fixed bodies left out."""
    v1, v2, imp, m = case.vehicle1, case.vehicle2, case.impact, case.measured
    rows = [("impact.point_x", imp.point[0], unc.point, "point"),
            ("impact.point_y", imp.point[1], unc.point, "point"),
            ("impact.normal_angle", imp.normal_angle, unc.normal_angle, "normal_angle")]
    moving = [(i, v) for i, v in ((1, v1), (2, v2)) if not v.fixed.all()]
    for i, v in moving:
        rows += [(f"vehicle{i}.mass", v.mass, unc.mass_fraction * v.mass, "mass_fraction"),
                 (f"vehicle{i}.yaw_inertia", v.yaw_inertia, unc.inertia_fraction * v.yaw_inertia,
                  "inertia_fraction")]
    for i, v in moving:
        rows += [(f"vehicle{i}.velocity_x", v.velocity[0], unc.velocity, "velocity"),
                 (f"vehicle{i}.velocity_y", v.velocity[1], unc.velocity, "velocity"),
                 (f"vehicle{i}.yaw_rate", v.yaw_rate, unc.yaw_rate, "yaw_rate")]
    table = case.uncertainty.inputs if case.uncertainty is not None else {}
    estimated = {e.name for e in case.estimates}
    out = []
    for key, nominal, typical, name in rows:
        dist = table.get(key)
        stated = None if dist is None else dist.sd(float(nominal))
        out.append((key, float(nominal), float(typical), name, stated,
                    "estimate" if key in estimated else "case"))
    for term in terms:
        name = "measured_velocity" if term.is_velocity else "measured_yaw_rate"
        out.append((f"measured.{term.name}", measured_value(m, term), getattr(unc, name), name,
                    term.sigma_of(m), "case"))
    return out


def _nominal_and_sigma(case: Case, unc: TypicalUncertainty, terms,
                       prefer=()) -> tuple[list, list, list, list, list]:
    """Input keys, nominal values [SI], sigmas [SI], their sources (:data:`SOURCES`) and the
    scale of each finite-difference step [SI]: the case's stated sigma where it gives one
    (``[uncertainty]``, an estimate's scatter, a ``[measured]`` sigma), else the typical
    one; a field of TypicalUncertainty named in ``prefer`` wins over the case. The step
    scale is the sigma, or the typical one where the case fixes the input (sigma 0)."""
    unknown = sorted(set(prefer) - set(TYPICAL_KINDS))
    if unknown:
        raise InputError(f"prefer: {unknown[0]!r} is no typical uncertainty (allowed: "
                         f"{', '.join(TYPICAL_KINDS)})")
    keys, nominal, sigma, sources, scale = [], [], [], [], []
    for key, value, typical, name, stated, source in _typical_rows(case, unc, terms):
        if name in prefer or stated is None:
            stated, source = typical, ("option" if name in prefer else "typical")
        keys.append(key)
        nominal.append(value)
        sigma.append(float(stated))
        sources.append(source)
        scale.append(float(stated) if stated > 0 else typical)
    return keys, nominal, sigma, sources, scale


_EPS_BETA = ("impact.restitution", "impact.beta")


def _cost_gradient(cases: Case, terms, eps, beta, fit_case_: Case) -> tuple:
    """d S / d (eps, beta) = 2 J^T r of the fit's (weighted) cost, shape (m, 2), for the
    cases (any batch, flattened to m rows) at the parameters (eps, beta) (shape (m,) or
    scalar), with exact derivatives (dual numbers); and J (m, k, 2).

    The targets and weights are those of ``fit_case_`` (the measured motion is not moved)."""
    state = case_state(cases).reshape(-1, len(STATE))
    e, b = np.broadcast_arrays(np.asarray(eps, dtype=float), np.asarray(beta, dtype=float))
    m = max(state.shape[0], e.size)
    state = np.broadcast_to(state, (m, len(STATE)))
    x = np.stack([np.broadcast_to(e, (m,)), np.broadcast_to(b, (m,))], axis=-1)
    rows, target, factor = residual_terms(fit_case_, terms)
    # a yaw term's factor is k_i = sqrt(I_i / m_i) of the (perturbed) case itself
    terms = as_residual_terms(terms)
    factor = np.broadcast_to(factor, (m, len(terms))).copy()
    for col, term in enumerate(terms):
        if isinstance(term, Term) and not term.is_velocity:
            v0, v = (getattr(c, f"vehicle{term.vehicle}") for c in (fit_case_, cases))
            k0 = float(radius_of_gyration(v0.mass, v0.yaw_inertia))
            ratio = radius_of_gyration(v.mass, v.yaw_inertia) / k0 if k0 > 0 else np.ones(1)
            factor[:, col] *= np.broadcast_to(ratio.reshape(-1), (m,))
    r, j = free_residuals(state, _EPS_BETA, x, rows, target, factor,
                          evidence=split_terms(terms)[1])
    return 2.0 * np.einsum("pk,pkn->pn", r, j), j, factor


def _delta_v_by_parameters(case: Case, eps: float, beta: float) -> tuple:
    """|delta-V_1|, |delta-V_2| [m/s] and their exact derivatives w.r.t. (eps, beta), (2, 2)."""
    values, jac = motion_jacobian(case, eps, beta)
    out, grad = [], []
    for i in (1, 2):
        rows = [MOTION_OUTPUTS.index(f"velocity{i}_{a}") for a in "xy"]
        dv = values[rows] - np.asarray(getattr(case, f"vehicle{i}").velocity, dtype=float)
        size = float(np.hypot(*dv))
        out.append(size)
        grad.append(dv @ jac[rows][:, :2] / size if size > 0 else np.zeros(2))
    return out, np.array(grad)


def sensitivity(case: Case, fit_result=None, *, eps=None, beta=None, uncertainty=None,
                include_yaw: bool | None = None, prefer=()) -> Sensitivity:
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
    uncertainty : TypicalUncertainty, optional
        Typical uncertainties, for the inputs the case gives no sigma (module notes).
    include_yaw : bool, optional
        Passed to :func:`pim.fit` when the fit is made here (default as its).
    prefer : iterable of str
        Fields of ``uncertainty`` that win over the case's own sigmas (``--sigma``).

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
    checked_case(case)
    check_numbers(eps=eps, beta=beta)
    check_type(uncertainty, "uncertainty", TypicalUncertainty,
               "a pim.analysis.sensitivity.TypicalUncertainty", none=True)
    if np.size(case.vehicle1.mass) != 1 or np.shape(case.impact.point) != (2,):
        raise InputError("sensitivity needs a single case, not a batch of cases")
    unc = TypicalUncertainty() if uncertainty is None else uncertainty
    if fit_result is None and eps is None and beta is None and has_measured_terms(case,
                                                                                   include_yaw):
        fit_result = fit_case(case, include_yaw=include_yaw)
    if fit_result is not None:
        if not isinstance(fit_result, FitResult):
            raise InputError("fit_result must be a FitResult from pim.fit")
        eps, beta = fit_result.eps, fit_result.beta
        terms = fit_result.terms or as_residual_terms(fit_result.residual_names)
    else:
        terms = ()
        eps, beta = defaults(case, eps, beta)
    eps, beta = float(eps), float(beta)

    keys, nominal, sigma, sources, scale = _nominal_and_sigma(case, unc, terms, prefer)
    n_model = sum(not k.startswith("measured.") for k in keys)
    steps = INPUT_STEP * np.array(scale[:n_model])
    # one broadcast solve over all +/- perturbations of the model inputs
    moved = _perturbed_case(case, keys[:n_model], steps)
    batch = solve(moved, eps, beta)
    dv = np.stack([batch.delta_v1_magnitude, batch.delta_v2_magnitude])       # (2, 2K)
    partial = np.zeros((2, len(keys)))
    partial[:, :n_model] = (dv[:, 0::2] - dv[:, 1::2]) / (2 * steps)
    values, dv_dtheta = _delta_v_by_parameters(case, eps, beta)
    outputs = ("delta_v1_magnitude", "delta_v2_magnitude")
    derivative = partial.copy()
    active: tuple[str, ...] = ()
    if fit_result is not None:
        active = tuple(p for p in ("eps", "beta") if p in fit_result.on_bound)
        held = set(active) | set(fit_result.fixed)
        dtheta = _parameter_derivative(case, moved, terms, keys, steps, eps, beta,
                                       [i for i, p in enumerate(("eps", "beta"))
                                        if p not in held])
        derivative = np.vstack([dtheta, partial + dv_dtheta @ dtheta])
        outputs = ("eps", "beta", *outputs)
        values = [eps, beta, *values]
    return Sensitivity(case=case, eps=eps, beta=beta, fit=fit_result, inputs=tuple(keys),
                       nominal=np.array(nominal), sigma=np.array(sigma), outputs=outputs,
                       values=np.array(values), derivative=derivative,
                       partial_delta_v=partial, active_bounds=active, sources=tuple(sources))


def _parameter_derivative(case: Case, moved: Case, terms, keys, steps, eps: float,
                          beta: float, idx: list[int]) -> np.ndarray:
    """d (eps, beta) / d input (2, n_inputs) by the implicit-function theorem at the optimum
    of the (weighted) cost; rows not in ``idx`` (fixed or on a bound) are 0."""
    dtheta = np.zeros((2, len(keys)))
    if not idx:
        return dtheta
    n_model = len(steps)
    # dg/dx for the model inputs (central differences of the exact gradient)
    g, _, _ = _cost_gradient(moved, terms, eps, beta, case)                   # (2K, 2)
    dg = np.zeros((2, len(keys)))
    dg[:, :n_model] = ((g[0::2] - g[1::2]) / (2 * steps[:, None])).T
    # measured values: r_i = (model - y_i) f_i, so dg/dy_i = -2 f_i J_i exactly
    _, j0, factor = _cost_gradient(case, terms, eps, beta, case)
    names = [t.name for t in terms]
    for col, key in enumerate(keys[n_model:], start=n_model):
        term = names.index(key[len("measured."):])
        dg[:, col] = -2.0 * factor[0, term] * j0[0, term]
    # Hessian of the cost over (eps, beta) by central differences of the exact gradient
    h = PARAMETER_STEP
    e_pts = np.clip([eps + h, eps - h], 0.0, 1.0)
    gh, _, _ = _cost_gradient(case, terms, np.array([e_pts[0], e_pts[1], eps, eps]),
                              np.array([beta, beta, beta + h, beta - h]), case)   # (4, 2)
    hess = np.stack([(gh[0] - gh[1]) / (e_pts[0] - e_pts[1]),
                     (gh[2] - gh[3]) / (2 * h)], axis=1)  # H[i, j] = dg_i / dtheta_j
    hess = 0.5 * (hess + hess.T)
    h_ff = hess[np.ix_(idx, idx)]
    if not np.all(np.isfinite(h_ff)) or np.linalg.cond(h_ff) > 1e12:
        raise InputError("the cost is flat at the optimum (singular Hessian): the "
                         "fitted parameters are not determined by the measurements")
    dtheta[idx] = -np.linalg.solve(h_ff, dg[idx])
    return dtheta
