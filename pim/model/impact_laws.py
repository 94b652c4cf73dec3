"""Impact laws: Brach's PIM, friction-capped Brach, and the Kudlich-Slibar law of PC-Crash.

A case names its law in ``impact.law`` (docs/impact-laws.md); :func:`pim.solve`
(:mod:`pim.model.law`) applies it, with this module's solvers as its parts.
Every law is rigid-body impulse-momentum at one common point C with the contact plane of
normal n (from vehicle 2 toward vehicle 1) and tangent t; they differ only in the two
conditions that fix the impulse P on vehicle 1:

``"brach"`` (default)
    Brach's PIM (:func:`pim.solve`): U_n = -eps u_n and Pt / Pn = mu = beta mu0(eps), where
    mu0(eps) is the impulse ratio that leaves no slip at C *after* the impact (Brach &
    Brach 2011, ch. 6).
``"brach-capped"``
    PIM with the impulse ratio capped at a friction coefficient:
    mu = sign(mu0) min(beta |mu0(eps)|, mu_c) (:mod:`pim.model.friction_cap`). A variant of
    Brach's law, not PC-Crash's: uncapped at beta = 1 it ends with no slip at C.
``"kudlich-slibar"``
    The law of PC-Crash and Virtual CRASH (Kudlich 1966; Slibar; Steffan & Moser, "The
    Collision and Trajectory Models of PC-CRASH", SAE 960886; Virtual CRASH, "Appendix 1 |
    Kudlich-Slibar"; the same two-step rule as pycrash's ``impc_calcs``). The compression
    impulse P_c stops the relative motion of C in both directions,

        K P_c = -u                                     (sticking),

    unless that needs |P_c.t| > mu_c P_c.n; then C slides at the cap,

        P_c = Pn_c (n + sigma mu_c t),  Pn_c = -u_n / (n . K (n + sigma mu_c t)),
        sigma = sign(t . P_c(sticking)).

    The restitution impulse is k times the compression impulse in both directions, so
    P = (1 + k) P_c: U_n = -k u_n, and a sticking contact ends with slip U_t = -k u_t (the
    simulators' standard behaviour, which Brach's admissibility flags as "sliding reverses").

K = (a_1 + a_2) 1 + b_1 s_1 s_1^T + b_2 s_2 s_2^T (s_i = k x r_i) is the effective
inverse-mass matrix of C in the global frame and u the relative velocity of C before the
impact (Brach & Brach 2011, eqs. 6.45-6.47 in vector form).

*Mapping.* Kudlich-Slibar with (k, mu_c) is PIM with eps = k and mu = mu0(0) capped at
mu_c, i.e. beta = sign(mu0(0)) min(|mu0(0)|, mu_c) / mu0(k)
(:func:`kudlich_slibar_as_brach`); a PIM answer (eps, beta) is Kudlich-Slibar with k = eps
and mu_c = |beta mu0(eps)| when its mu has the sign of mu0(0) and |mu| <= |mu0(0)|
(:func:`brach_as_kudlich_slibar`, NaN otherwise). Both assume the sticking compression
impulse pushes (Pn_c > 0). The laws are planar: the impact point's height, pitch and roll
are outside their scope.

*Fits.* :func:`motion_of_law` evaluates every law on dual numbers (:mod:`pim.model.dual`)
through the one formula with the law's impulse ratio (:func:`kudlich_slibar_ratio`,
:func:`pim.model.friction_cap.capped_beta`), so that the fitting engine fits (k, mu_c) with
exact derivatives, one-sided at the cap; :func:`needed_friction` is the friction above
which mu_c no longer matters (a fit then states it as a lower bound).
"""

from __future__ import annotations

import numpy as np

from . import formula
from .case import FRICTION_LAWS, LAWS, Case, checked_case
from .dual import MOTION_INPUTS, motion_of_inputs, seed_inputs, value_of, where
from .friction_cap import capped_beta
from .geometry import contact_velocity, cross, dot, perp, vec
from .numbers import InputError, real_array
from .result import Result
from .solver import APPROACH_TOLERANCE, SINGULAR_TOLERANCE, solve, unknown_hint

__all__ = ["LAWS", "FRICTION_LAWS", "LawResult", "kudlich_slibar_impulse",
           "solve_kudlich_slibar", "law_of", "kudlich_slibar_as_brach",
           "brach_as_kudlich_slibar", "check_restitution", "check_contact_friction",
           "kudlich_slibar_ratio", "LAW_CODES", "LAW_INPUTS", "motion_of_law",
           "needed_friction"]


def check_restitution(k, name: str = "restitution k") -> np.ndarray:
    """k as an array, checked to lie in [0, 1]; the error names ``name``."""
    k = real_array(k, name)
    if np.isnan(k).any() or ((k < 0) | (k > 1)).any():
        raise InputError(f"{name} must be in [0, 1], got {_show(k)}")
    return k


def check_contact_friction(mu_c, name: str = "contact_friction mu_c") -> np.ndarray:
    """mu_c as an array, checked to be >= 0 (inf allowed: always stick)."""
    mu_c = real_array(mu_c, name)
    if np.isnan(mu_c).any() or (mu_c < 0).any():
        raise InputError(f"{name} must be >= 0 (inf: always stick), got {_show(mu_c)}")
    return mu_c


def _show(x: np.ndarray) -> str:
    return f"{float(x):g}" if x.size == 1 else f"values in [{np.nanmin(x):g}, {np.nanmax(x):g}]"


def _matrix(a1, b1, r1, a2, b2, r2):
    """K = (a_1 + a_2) 1 + b_1 s_1 s_1^T + b_2 s_2 s_2^T, s_i = k x r_i: (K_xx, K_xy, K_yy)."""
    s1, s2 = perp(r1), perp(r2)
    a = a1 + a2
    kxx = a + b1 * s1[..., 0] ** 2 + b2 * s2[..., 0] ** 2
    kxy = b1 * s1[..., 0] * s1[..., 1] + b2 * s2[..., 0] * s2[..., 1]
    kyy = a + b1 * s1[..., 1] ** 2 + b2 * s2[..., 1] ** 2
    return kxx, kxy, kyy


def _apply(k, p):
    """K p for K = (K_xx, K_xy, K_yy) and vectors p (..., 2)."""
    kxx, kxy, kyy = k
    return vec(kxx * p[..., 0] + kxy * p[..., 1], kxy * p[..., 0] + kyy * p[..., 1])


def _solve(k, v):
    """K^-1 v (K is symmetric positive definite where a_1 + a_2 > 0)."""
    kxx, kxy, kyy = k
    det = kxx * kyy - kxy * kxy
    return vec((kyy * v[..., 0] - kxy * v[..., 1]) / det, (kxx * v[..., 1] - kxy * v[..., 0]) / det)


def kudlich_slibar_impulse(k_matrix, approach, normal, k, mu_c):
    """Compression impulse P_c and total impulse P = (1 + k) P_c of the Kudlich-Slibar law.

    Parameters
    ----------
    k_matrix : tuple of ndarray
        (K_xx, K_xy, K_yy), the effective inverse-mass matrix of C in x-y [1/kg].
    approach : ndarray (..., 2)
        Relative velocity u = u_1 - u_2 of C before the impact [m/s].
    normal : ndarray (..., 2)
        Unit normal n of the contact plane, from vehicle 2 toward vehicle 1 [-].
    k : array_like
        Restitution k [-] in [0, 1]: the restitution impulse is k times the compression
        impulse.
    mu_c : array_like
        Contact friction mu_c [-] >= 0: the compression impulse keeps |P_c.t| <= mu_c P_c.n.

    Returns
    -------
    compression, impulse : ndarray (..., 2)
        P_c and P on vehicle 1 [N s] (vehicle 2 receives the opposite).
    sticking : ndarray of bool
        The compression impulse stops the relative motion of C in both directions.
    denominator : ndarray
        n . K (n + sigma mu_c t) [1/kg] of the sliding normal impulse (where sliding).

    Notes
    -----
    Kudlich (1966), Slibar; Steffan & Moser, SAE 960886; see the module docstring.
    """
    tangent = perp(normal)
    stick = -_solve(k_matrix, approach)                      # K P_c = -u
    pn, pt = dot(stick, normal), dot(stick, tangent)
    with np.errstate(invalid="ignore"):
        sticking = (pn > 0) & (np.abs(pt) <= mu_c * pn)
    direction = normal + (np.sign(pt) * np.where(sticking, 0.0, mu_c))[..., None] * tangent
    denominator = dot(normal, _apply(k_matrix, direction))
    with np.errstate(divide="ignore", invalid="ignore"):
        slide = (-dot(approach, normal) / denominator)[..., None] * direction
    compression = np.where(sticking[..., None], stick, slide)
    return compression, (1.0 + np.asarray(k))[..., None] * compression, sticking, denominator


class LawResult(Result):
    """A :class:`pim.Result` of a law other than Brach's (see :func:`solve_kudlich_slibar`).

    ``eps`` is the law's normal restitution, ``beta`` the PIM fraction giving the same
    answer (Pt / Pn over mu0(eps)); ``law`` names the law and ``contact_friction`` its mu_c.
    Brach's flags "|mu| > |mu0|" and "tangential impulse along the remaining slip" do not
    apply: a sticking Kudlich-Slibar contact ends with slip -k u_t by definition.
    """

    def __init__(self, case, eps, beta, fields, *, law: str, contact_friction) -> None:
        super().__init__(case, eps, beta, fields)
        self.__dict__.update(law=law, contact_friction=contact_friction)

    @property
    def mu(self) -> np.ndarray:
        """Impulse ratio Pt / Pn [-]."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.impulse_t / self.impulse_n

    @property
    def within_critical(self) -> np.ndarray:
        """True: the law's tangential restitution may reverse the slip (its standard)."""
        return np.ones(np.shape(self.impulse_n), bool)

    @property
    def friction_opposes_sliding(self) -> np.ndarray:
        """True: the law's tangential restitution may leave Pt along the slip (its standard)."""
        return np.ones(np.shape(self.impulse_n), bool)

    def admissibility_checks(self) -> list:
        """Brach's checks without the two on tangential restitution (see the class)."""
        skip = ("reverses", "along", "drives")
        return [c for c in super().admissibility_checks() if c[2] not in skip]


def _fields(case: Case, k, mu_c, approach_tol, singular_tol) -> tuple[dict, np.ndarray]:
    """The core fields of a Kudlich-Slibar result, and the equivalent PIM beta."""
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    a1, b1, a2, b2 = v1.inverse_mass, v1.inverse_inertia, v2.inverse_mass, v2.inverse_inertia
    r1, r2 = imp.point - v1.cg, imp.point - v2.cg
    n = vec(np.cos(imp.normal_angle), np.sin(imp.normal_angle))
    t = perp(n)
    kmat = _matrix(a1, b1, r1, a2, b2, r2)
    u = contact_velocity(v1.velocity, v1.yaw_rate, r1) - contact_velocity(v2.velocity,
                                                                          v2.yaw_rate, r2)
    u_n, u_t = dot(u, n), dot(u, t)
    _, p, sticking, denom = kudlich_slibar_impulse(kmat, u, n, k, mu_c)
    approaching = u_n < -approach_tol * (np.abs(u_n) + np.abs(u_t))
    k_nn, k_nt = dot(n, _apply(kmat, n)), dot(t, _apply(kmat, n))
    with np.errstate(invalid="ignore"):
        singular = approaching & ~sticking & ~(np.abs(denom) > singular_tol * (
            np.abs(k_nn) + np.asarray(mu_c) * np.abs(k_nt)))
    p = np.where(approaching[..., None], p, 0.0)
    p = np.where(singular[..., None], np.nan, p)
    # Brach's critical impulse at eps = k (for mu0 and the sheet's notation)
    critical = -_solve(kmat, ((1.0 + np.asarray(k)) * u_n)[..., None] * n + u_t[..., None] * t)
    pn, pt = dot(p, n), dot(p, t)
    c_n, c_t = dot(critical, n), dot(critical, t)
    with np.errstate(divide="ignore", invalid="ignore"):
        beta = np.where(pt == 0, 1.0, pt * c_n / (pn * c_t))
    shape = np.shape(pn)
    fields = {
        "velocity1": v1.velocity + np.asarray(a1)[..., None] * p,
        "velocity2": v2.velocity - np.asarray(a2)[..., None] * p,
        "yaw_rate1": v1.yaw_rate + b1 * cross(r1, p), "yaw_rate2": v2.yaw_rate - b2 * cross(r2, p),
        "impulse": p, "impulse_n": pn, "impulse_t": pt, "critical_impulse_n": c_n,
        "critical_impulse_t": c_t, "normal": n, "tangent": t, "arm1": r1, "arm2": r2,
        "approach_velocity": u, "approach_n": u_n, "approach_t": u_t, "k_nn": k_nn,
        "k_nt": k_nt, "k_tt": dot(t, _apply(kmat, t)),
        "approaching": np.broadcast_to(approaching, shape),
        "q_singular": np.broadcast_to(singular, shape),
    }
    return fields, beta


def solve_kudlich_slibar(case: Case, k=None, mu_c=None, approach_tol: float = APPROACH_TOLERANCE,
                         singular_tol: float = SINGULAR_TOLERANCE) -> LawResult:
    """Post-impact motion under the Kudlich-Slibar law (PC-Crash, Virtual CRASH).

    Parameters
    ----------
    case : Case
        Vehicles, impact point C and contact plane (normal angle Gamma); fields may be arrays.
    k : array_like, optional
        Restitution k [-] in [0, 1] (default ``case.impact.restitution``).
    mu_c : array_like, optional
        Contact friction mu_c [-] >= 0 between the vehicles (default
        ``case.impact.contact_friction``; inf: always stick).
    approach_tol, singular_tol : float
        As for :func:`pim.solve`.

    Returns
    -------
    LawResult
        Post-impact velocities, yaw rates, impulse and every derived output of
        :class:`pim.Result` (delta-V, PDOF, energies), broadcast over all inputs.

    Raises
    ------
    ValueError
        k missing or outside [0, 1], mu_c missing or < 0.

    Notes
    -----
    P = (1 + k) P_c with the compression impulse of :func:`kudlich_slibar_impulse`
    (Kudlich 1966; Slibar; Steffan & Moser, SAE 960886). Where the vehicles do not approach
    at C the impulse is 0; where the sliding normal impulse is unbounded (n . K (n + sigma
    mu_c t) = 0) the outputs are NaN and ``q_singular`` is True.
    """
    checked_case(case)
    k = case.impact.restitution if k is None else k
    mu_c = case.impact.contact_friction if mu_c is None else mu_c
    if k is None:
        raise InputError("restitution k is required for law 'kudlich-slibar': give it or set "
                         f"impact.restitution in the case{unknown_hint(case)}")
    if mu_c is None:
        raise InputError("contact_friction mu_c is required for law 'kudlich-slibar': give it "
                         f"or set impact.contact_friction in the case{unknown_hint(case)}")
    k, mu_c = check_restitution(k), check_contact_friction(mu_c)
    fields, beta = _fields(case, k, mu_c, approach_tol, singular_tol)
    return LawResult(case, k, beta, fields, law="kudlich-slibar", contact_friction=mu_c)


def law_of(case: Case, law: str | None = None) -> str:
    """The law to apply: ``law`` if given, else the case's ``impact.law``, else "brach"."""
    law = law or case.impact.law or "brach"
    if law not in LAWS:
        raise InputError(f"law must be one of {', '.join(map(repr, LAWS))}, got {law!r}")
    return law


def _mu0(case: Case, eps) -> np.ndarray:
    return solve(case, eps, 1.0, backend="numpy").mu0


def kudlich_slibar_as_brach(case: Case, k, mu_c) -> tuple[np.ndarray, np.ndarray]:
    """The PIM constraints (eps, beta) that give the Kudlich-Slibar answer for (k, mu_c).

    eps = k and beta = sign(mu0(0)) min(|mu0(0)|, mu_c) / mu0(k): PIM's mu is the
    compression phase's sticking ratio mu0(0), capped at mu_c. Valid where the sticking
    compression impulse pushes (Pn_c > 0).

    Returns
    -------
    eps, beta : ndarray
        [-]; beta is 1 where mu0(k) = 0 and mu0(0) = 0, inf where only mu0(k) = 0.
    """
    k, mu_c = check_restitution(k), check_contact_friction(mu_c)
    mu0_0, mu0_k = _mu0(case, 0.0), _mu0(case, k)
    mu = kudlich_slibar_ratio(mu0_0, mu_c)
    with np.errstate(divide="ignore", invalid="ignore"):
        beta = np.where(mu == 0, np.where(mu0_k == 0, 1.0, 0.0), mu / mu0_k)
    return np.broadcast_to(k, np.shape(beta)).astype(float), beta


def brach_as_kudlich_slibar(case: Case, eps, beta) -> tuple[np.ndarray, np.ndarray]:
    """The Kudlich-Slibar parameters (k, mu_c) that give PIM's answer at (eps, beta).

    k = eps and mu_c = |beta mu0(eps)|, where PIM's mu = beta mu0(eps) has the sign of
    mu0(0) (or is 0) and |mu| <= |mu0(0)|: the law can only cap the compression phase's
    sticking ratio. Elsewhere no (k, mu_c) gives PIM's answer: NaN.

    Returns
    -------
    k, mu_c : ndarray
        [-]; NaN where PIM's answer is not a Kudlich-Slibar answer.
    """
    eps = check_restitution(eps, "eps (coefficient of restitution)")
    mu0_0 = _mu0(case, 0.0)
    mu = np.asarray(beta, float) * _mu0(case, eps)
    ok = (mu == 0) | ((np.sign(mu) == np.sign(mu0_0))
                      & (np.abs(mu) <= np.abs(mu0_0) * (1 + 1e-12)))
    mu_c = np.where(ok, np.abs(mu), np.nan)
    return np.where(ok, eps, np.nan), mu_c


def kudlich_slibar_ratio(mu0_0, mu_c):
    """PIM's impulse ratio mu = Pt / Pn of the Kudlich-Slibar law [-]:
    sign(mu0(0)) min(|mu0(0)|, mu_c).

    Parameters
    ----------
    mu0_0 : array_like or Dual
        The compression phase's sticking ratio mu0 at eps = 0 [-].
    mu_c : array_like or Dual
        Contact friction [-] >= 0 (inf: always stick).

    Returns
    -------
    ndarray or Dual
        mu [-]. On dual numbers the derivative is the sticking side's (d mu0(0)) where
        |mu0(0)| <= mu_c, ties included, and the sliding side's (sign(mu0(0)) d mu_c)
        beyond: the cap is a kink, its derivative one-sided.

    Notes
    -----
    Kudlich (1966), Slibar; Steffan & Moser, SAE 960886: the compression impulse sticks
    unless that needs |Pt| > mu_c Pn, then slides at the cap (module docstring).
    """
    with np.errstate(invalid="ignore"):
        return where(abs(mu0_0) <= mu_c, mu0_0, np.sign(value_of(mu0_0)) * mu_c)


#: Codes of the impact laws in a numeric state row (:data:`LAW_INPUTS`' last column).
LAW_CODES = {"brach": 0.0, "brach-capped": 1.0, "kudlich-slibar": 2.0}
#: Inputs of :func:`motion_of_law`: :data:`pim.model.dual.MOTION_INPUTS` (restitution is
#: eps or k, beta is unused by "kudlich-slibar"), then the contact friction mu_c (the cap of
#: "brach-capped"; unused by "brach").
LAW_INPUTS = MOTION_INPUTS + ("impact.contact_friction",)


def _contact(seed, inverse, cs, sn, eps, beta, approach_tol, singular_tol):
    """:func:`pim.model.formula.contact` of the seeded inputs (the arms, inverse masses and
    motion of :data:`MOTION_INPUTS`) at ``eps`` and ``beta``, and those inputs."""
    px, py = seed(3), seed(4)
    args = (inverse(15), inverse(16), px - seed(11), py - seed(12), seed(5), seed(6), seed(7),
            inverse(17), inverse(18), px - seed(13), py - seed(14), seed(8), seed(9), seed(10))
    return formula.contact(cs, sn, *args, eps, beta, approach_tol,
                           singular_tol), args


def _ratio_and_contact(x, law, approach_tol, singular_tol, jacobian, tangent):
    """The law's contact at its restitution, the tangential impulse per unit scale
    mu Pn0 [N s], the formula's other inputs and the gradient width."""
    seed, inverse, cs, sn, width = seed_inputs(x, tangent, jacobian)
    restitution, mu_c = seed(0), seed(len(MOTION_INPUTS))
    with np.errstate(divide="ignore", invalid="ignore"):
        if law == "brach-capped":       # mu = sign(mu0) min(beta |mu0(eps)|, mu_c)
            c, args = _contact(seed, inverse, cs, sn, restitution, 1.0, approach_tol,
                               singular_tol)
            tangential = capped_beta(c[8] / c[7], seed(1), mu_c) * c[8]
        else:                           # mu = sign(mu0(0)) min(|mu0(0)|, mu_c), eps = k
            c0, _ = _contact(seed, inverse, cs, sn, 0.0, 1.0, approach_tol, singular_tol)
            c, args = _contact(seed, inverse, cs, sn, restitution, 1.0, approach_tol,
                               singular_tol)
            tangential = kudlich_slibar_ratio(c0[8] / c0[7], mu_c) * c[7]
    return c, tangential, args, cs, sn, width


def motion_of_law(x, law: str = "brach", approach_tol: float = 1e-12,
                  singular_tol: float = 1e-12, jacobian: bool = True, tangent=None):
    """Post-impact motion of the inputs ``x`` under an impact law, and its exact Jacobian.

    Parameters
    ----------
    x : array_like, shape S + (20,)
        Values of :data:`LAW_INPUTS` [SI].
    law : {"brach", "brach-capped", "kudlich-slibar"}
        The impact law (module docstring).
    approach_tol, singular_tol : float
        As in :func:`pim.solve`.
    jacobian : bool
        False: plain arithmetic, no derivatives.
    tangent : array_like, shape S + (20, n), optional
        d x / d p for n parameters p (as in :func:`pim.model.dual.motion_of_inputs`).

    Returns
    -------
    values : ndarray, shape S + (10,)
        :data:`pim.model.dual.MOTION_OUTPUTS` [N s, m/s, rad/s].
    jacobian : ndarray, shape S + (10, 20) (S + (10, n) with ``tangent``), or None
        d output / d input by dual numbers; zero where the vehicles do not approach, NaN
        where the impulse is unbounded.

    Notes
    -----
    Every law is PIM with an impulse ratio mu = Pt / Pn (docs/impact-laws.md): Brach's
    mu = beta mu0(eps) (:func:`pim.model.dual.motion_of_inputs`); friction-capped Brach
    mu = sign(mu0) min(beta |mu0(eps)|, mu_c) (:func:`pim.model.friction_cap.capped_beta`);
    Kudlich-Slibar eps = k and mu = sign(mu0(0)) min(|mu0(0)|, mu_c)
    (:func:`kudlich_slibar_ratio`). With the critical impulse (Pn0, Pt0) at eps, the normal
    row K_nn Pn + K_nt Pt = -(1 + eps) u_n with Pt = mu Pn gives Pn = s Pn0, Pt = s mu Pn0,
    s = drive / (drive + K_nt (mu Pn0 - Pt0)) (drive = -(1 + eps) u_n; Brach & Brach 2011,
    eqs. 6.55-6.62), free of a division by mu0(eps). The caps are kinks: at them the
    Jacobian is the derivative of the side taken (the uncapped one at a tie), one-sided.
    """
    x = np.asarray(x, dtype=float)
    n_in = len(MOTION_INPUTS)
    if law == "brach":
        return motion_of_inputs(x[..., :n_in], approach_tol, singular_tol, jacobian,
                                None if tangent is None else np.asarray(tangent)[..., :n_in, :])
    if law not in LAW_CODES:
        raise InputError(f"law must be one of {', '.join(map(repr, LAWS))}, got {law!r}")
    c, tangential, args, cs, sn, width = _ratio_and_contact(
        x, law, approach_tol, singular_tol, jacobian, tangent if jacobian else None)
    k_nt, pn0, pt0, drive, appr = c[5], c[7], c[8], c[9], c[11]
    excess = k_nt * (tangential - pt0)
    denom = drive + excess
    singular = appr & (abs(value_of(denom)) <= singular_tol * (
        abs(value_of(drive)) + abs(value_of(excess))))
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = where(appr & ~singular, drive / denom, 0.0) * np.where(singular, np.nan, 1.0)
    out = formula.post_impact(scale, pn0, tangential, 1.0, cs, sn, *args)
    shape = x.shape[:-1]
    values = np.stack([np.broadcast_to(value_of(o), shape) for o in out], axis=-1)
    if not jacobian:
        return values, None
    jac = np.stack([np.broadcast_to(o.grad, shape + (width,)) for o in out], axis=-2)
    return values, jac


def needed_friction(x, law: str) -> np.ndarray:
    """The least contact friction that leaves the law's answer uncapped [-].

    "kudlich-slibar": |mu0(0)|, the sticking ratio of the compression phase (any
    mu_c >= it gives the sticking answer); "brach-capped": beta |mu0(eps)|; "brach": 0.

    Parameters
    ----------
    x : array_like, shape S + (20,)
        Values of :data:`LAW_INPUTS` [SI].
    law : str
        The impact law.

    Returns
    -------
    ndarray, shape S
        [-]; NaN where the vehicles do not approach.
    """
    x = np.asarray(x, dtype=float)
    if law == "brach":
        return np.zeros(x.shape[:-1])
    seed, inverse, cs, sn, _ = seed_inputs(x, None, False)
    eps, beta = (0.0, 1.0) if law == "kudlich-slibar" else (seed(0), seed(1))
    c, _ = _contact(seed, inverse, cs, sn, eps, 1.0, 1e-12, 1e-12)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(c[11], np.abs(beta * c[8] / c[7]), np.nan)
