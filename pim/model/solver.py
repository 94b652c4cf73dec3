"""Brach's Planar Impact Mechanics in vector form: the closed-form post-impact state.

Derivation (global x-y frame; Brach & Brach 2011, ch. 6, eqs. 6.45-6.62 in n-t components)
-----------------------------------------------------------------------------------------
Body i has inverse mass a_i, inverse yaw inertia b_i, CG G_i, velocity v_i and yaw rate w_i.
The arm from its CG to the common point C is r_i = C - G_i, and the velocity of C on body i
is u_i = v_i + w_i k x r_i. The impulse P acts on body 1 at C, -P on body 2, so

    V_1 = v_1 + a_1 P,    W_1 = w_1 + b_1 (r_1 x P),
    V_2 = v_2 - a_2 P,    W_2 = w_2 - b_2 (r_2 x P),

and the relative velocity of C, u = u_1 - u_2, changes by K P with the symmetric positive
definite 2x2 effective-inverse-mass matrix

    K = (a_1 + a_2) 1 + b_1 s_1 s_1^T + b_2 s_2 s_2^T,   s_i = k x r_i.

In the contact frame (n at Gamma, pointing from vehicle 2 toward vehicle 1; t = n rotated
+90 deg) write P = Pn n + Pt t, u_n = u.n < 0 on approach. The two constraints are Newton's
kinematic restitution at C, U_n = -epsilon u_n, and the impulse ratio Pt = mu Pn.

*Critical impulse (mu0).* The impulse that satisfies restitution and leaves no tangential
relative velocity (U_t = 0) solves K [Pn0, Pt0] = -[(1 + eps) u_n, u_t]; mu0 = Pt0 / Pn0.
This 2x2 solve stays finite for grazing impacts, where Brach's r = u_t / u_n form (eq. 6.60)
divides by u_n -> 0.

*Impulse for mu = beta mu0.* The normal row of K P = dU gives
Pn (K_nn + mu K_nt) = -(1 + eps) u_n. Written with (Pn0, Pt0) instead of mu0,

    P = s (Pn0, beta Pt0),   s = -(1 + eps) u_n / (K_nn Pn0 + beta K_nt Pt0),

which never divides by Pn0. The denominator is evaluated as -(1 + eps) u_n + (beta - 1)
K_nt Pt0 (the normal row of the critical solve), so that s = 1 exactly at beta = 1 and no
digits cancel for grazing impacts, where A - mu B -> 0 and q -> infinity. Brach's coefficients are
A = m_c K_nn, B = -m_c K_nt, C = m_c K_tt - 1 with m_c = 1 / (a_1 + a_2), and
q = 1 / (A - mu B) (eq. 6.55); the denominator above is zero exactly when q is singular.

*Energy.* The kinetic energy lost is -P.(u + U)/2, whose n and t parts are the normal and
tangential crush energies (Brach & Welsh, SAE 2007-01-0737); Brach's closed form T_L is
evaluated separately as a check.
"""

from __future__ import annotations

import numpy as np

from .case import Case, as_number
from .geometry import contact_velocity, cross, dot, vec
from .result import Result

__all__ = ["solve", "constraints", "effective_mass_matrix", "APPROACH_TOLERANCE",
           "SINGULAR_TOLERANCE", "FAST_PATH_MIN_SIZE"]

#: A normal approach u_n smaller than this fraction of |u_n| + |u_t| is round-off, not an
#: impact: at beta = 1 an infinitesimal approach would stop the whole tangential slip, so the
#: sign of a rounding error would decide between no impulse and a finite one.
#: pim.kernel compiles this in as a constant: after changing it, delete pim/__pycache__'s
#: numba cache files (*.nbi, *.nbc), which are keyed on kernel.py alone.
APPROACH_TOLERANCE = 1e-12
#: |K_nn Pn0 + beta K_nt Pt0| below this fraction of its terms' size counts as singular q.
SINGULAR_TOLERANCE = 1e-12


def effective_mass_matrix(inv_mass1, inv_inertia1, arm1, inv_mass2, inv_inertia2, arm2,
                          normal, tangent):
    """Effective inverse-mass matrix K of the contact, in n-t components.

    Parameters
    ----------
    inv_mass1, inv_mass2 : array_like
        Inverse masses [1/kg] (0 for a fixed obstacle).
    inv_inertia1, inv_inertia2 : array_like
        Inverse yaw inertias [1/(kg m^2)].
    arm1, arm2 : array_like, shape (..., 2)
        Arms C - G_i [m].
    normal, tangent : array_like, shape (..., 2)
        Unit vectors n and t.

    Returns
    -------
    k_nn, k_nt, k_tt : ndarray
        Entries of K [1/kg] such that the change of relative velocity at C is K P.
    """
    s1n, s1t = cross(arm1, normal), cross(arm1, tangent)
    s2n, s2t = cross(arm2, normal), cross(arm2, tangent)
    a = inv_mass1 + inv_mass2
    k_nn = a + inv_inertia1 * s1n * s1n + inv_inertia2 * s2n * s2n
    k_nt = inv_inertia1 * s1n * s1t + inv_inertia2 * s2n * s2t
    k_tt = a + inv_inertia1 * s1t * s1t + inv_inertia2 * s2t * s2t
    return k_nn, k_nt, k_tt


def constraints(case: Case, eps=None, beta=None) -> tuple[np.ndarray, np.ndarray]:
    """The two PIM constraints as :func:`solve` takes them: given, else the case's defaults.

    Parameters
    ----------
    case : Case
        Supplies ``impact.restitution`` and ``impact.beta`` where eps or beta is None.
    eps, beta : array_like, optional
        Coefficient of restitution [-] and fraction of mu0 [-]; beta defaults to 1.

    Returns
    -------
    eps, beta : ndarray
        Checked: eps in [0, 1], beta finite.

    Raises
    ------
    ValueError
        eps missing everywhere, outside [0, 1] or NaN; beta not finite.
    """
    eps, beta = _defaults(case, eps, beta)
    return _check_eps(eps), _check_beta(beta)


def _defaults(case: Case, eps, beta):
    if not isinstance(case, Case):
        raise ValueError(f"case must be a pim.Case, got {type(case).__name__}")
    if eps is not None:
        eps = as_number(eps, "eps")
    if beta is not None:
        beta = as_number(beta, "beta")
    if eps is not None and beta is not None:
        try:
            np.broadcast_shapes(np.shape(eps), np.shape(beta))
        except ValueError:
            raise ValueError(f"eps (shape {np.shape(eps)}) and beta (shape {np.shape(beta)}) "
                             "do not broadcast together") from None
    if eps is None:
        eps = case.impact.restitution
        if eps is None:
            raise ValueError("eps is required: give it or set impact.restitution in the case")
    if beta is None:
        beta = 1.0 if case.impact.beta is None else case.impact.beta
    return eps, beta


def _check_eps(eps) -> np.ndarray:
    eps = as_number(eps, "eps")
    if np.isnan(eps).any() or ((eps < 0) | (eps > 1)).any():
        raise ValueError("eps (coefficient of restitution) must be in [0, 1]")
    return eps


def _check_beta(beta) -> np.ndarray:
    beta = as_number(beta, "beta")
    if not np.isfinite(beta).all():
        raise ValueError("beta (fraction of mu0) must be a finite number, usually in [0, 1]")
    return beta


#: Batches of at least this many cases take the compiled kernel under backend="auto".
FAST_PATH_MIN_SIZE = 20_000


def _use_kernel(case: Case, eps, beta, backend: str) -> bool:
    """Whether :func:`solve` should run :mod:`pim.kernel` (imports numba only if so)."""
    if backend not in ("auto", "numpy", "numba"):
        raise ValueError(f"backend must be 'auto', 'numpy' or 'numba', got {backend!r}")
    if backend == "numpy":
        return False
    if backend == "auto":
        v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
        shape = np.broadcast_shapes(
            np.shape(v1.mass), np.shape(v1.yaw_inertia), np.shape(v1.cg)[:-1],
            np.shape(v1.velocity)[:-1], np.shape(v1.yaw_rate), np.shape(v2.mass),
            np.shape(v2.yaw_inertia), np.shape(v2.cg)[:-1], np.shape(v2.velocity)[:-1],
            np.shape(v2.yaw_rate), np.shape(imp.point)[:-1], np.shape(imp.normal_angle),
            np.shape(eps), np.shape(beta))
        if int(np.prod(shape, dtype=np.int64)) < FAST_PATH_MIN_SIZE:
            return False
    try:
        import numba  # noqa: F401
    except ImportError:
        if backend == "numba":
            raise ValueError("backend='numba' needs numba installed (pip install numba)") from None
        return False
    return True


def _solve_kernel(case: Case, eps, beta, fast_trig: bool) -> Result:
    """:func:`solve` on the fused numba kernel (:mod:`pim.kernel`); same results."""
    from .kernel import solve_case

    return solve_case(case, np.asarray(eps, dtype=float), np.asarray(beta, dtype=float),
                      SINGULAR_TOLERANCE, fast_trig=fast_trig)


def solve(case: Case, eps=None, beta=None, backend: str = "auto",
          fast_trig: bool = False) -> Result:
    """Post-impact motion of a planar two-body impact (Brach's PIM).

    Parameters
    ----------
    case : Case
        Vehicles, impact point C and normal angle Gamma; every field may be an array.
    eps : array_like, optional
        Coefficient of restitution epsilon [-] in [0, 1]; defaults to
        ``case.impact.restitution``.
    beta : array_like, optional
        Fraction of the critical impulse ratio, mu = beta mu0 [-]; defaults to
        ``case.impact.beta``, else 1. Values outside [0, 1] are computed and flagged.
    backend : {"auto", "numpy", "numba"}
        "numpy" is the reference implementation below; "numba" runs the fused parallel
        kernel of :mod:`pim.kernel`: the same values to round-off, every field at the full
        broadcast shape, the auxiliary fields (arms, K, approach velocity, n-t impulse
        components) computed on first read; "auto" takes the kernel for batches of at least
        ``FAST_PATH_MIN_SIZE`` cases when numba is installed.
    fast_trig : bool
        On the kernel only: take sin and cos of Gamma from the kernel's own branch-free
        fdlibm polynomials (within 1 ulp of the C library's, about 20 % faster) instead of the
        C library, so results agree with the numpy path to round-off instead of bitwise.
        Ignored on the numpy path.

    Returns
    -------
    Result
        Post-impact velocities, yaw rates and impulse, broadcast over all inputs, with the
        derived quantities (energies, crush, PDOF, admissibility flags) computed on first use.

    Notes
    -----
    Implements Brach & Brach (2011) eqs. 6.45-6.62 in vector form; see the module docstring.
    Where the vehicles do not approach at C (u_n >= 0, to round-off) no impact takes place:
    the impulse is zero and ``approaching`` is False. Where q is singular (A - mu B = 0) the
    impulse is unbounded: outputs are NaN and ``q_singular`` is True.
    """
    eps, beta = _defaults(case, eps, beta)
    if _use_kernel(case, eps, beta, backend):
        return _solve_kernel(case, eps, beta, fast_trig)  # checks eps, beta in the kernel
    eps, beta = _check_eps(eps), _check_beta(beta)
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact

    a1, b1 = v1.inverse_mass, v1.inverse_inertia
    a2, b2 = v2.inverse_mass, v2.inverse_inertia
    gamma = imp.normal_angle
    n = vec(np.cos(gamma), np.sin(gamma))
    t = vec(-np.sin(gamma), np.cos(gamma))
    r1 = imp.point - v1.cg
    r2 = imp.point - v2.cg
    u = (contact_velocity(v1.velocity, v1.yaw_rate, r1)
         - contact_velocity(v2.velocity, v2.yaw_rate, r2))
    u_n, u_t = dot(u, n), dot(u, t)
    k_nn, k_nt, k_tt = effective_mass_matrix(a1, b1, r1, a2, b2, r2, n, t)

    e1 = 1.0 + eps
    det = k_nn * k_tt - k_nt * k_nt
    pn0 = (-e1 * u_n * k_tt + u_t * k_nt) / det
    pt0 = (-u_t * k_nn + e1 * u_n * k_nt) / det
    # K_nn Pn0 + beta K_nt Pt0, using K_nn Pn0 + K_nt Pt0 = -(1 + eps) u_n (normal row of the
    # critical solve): exact at beta = 1 and free of cancellation for grazing impacts.
    drive = -e1 * u_n
    excess = (beta - 1.0) * k_nt * pt0
    denom = drive + excess
    size = np.abs(drive) + np.abs(excess)
    approaching = u_n < -APPROACH_TOLERANCE * (np.abs(u_n) + np.abs(u_t))
    singular = approaching & (np.abs(denom) <= SINGULAR_TOLERANCE * size)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(approaching, drive / denom, 0.0)
    scale = np.where(singular, np.nan, scale)
    p_n = scale * pn0
    p_t = scale * beta * pt0
    impulse = p_n[..., None] * n + p_t[..., None] * t

    return Result(
        case=case, eps=eps, beta=beta,
        velocity1=v1.velocity + a1[..., None] * impulse,
        velocity2=v2.velocity - a2[..., None] * impulse,
        yaw_rate1=v1.yaw_rate + b1 * cross(r1, impulse),
        yaw_rate2=v2.yaw_rate - b2 * cross(r2, impulse),
        impulse=impulse, impulse_n=p_n, impulse_t=p_t,
        critical_impulse_n=pn0, critical_impulse_t=pt0,
        normal=n, tangent=t, arm1=r1, arm2=r2,
        approach_velocity=u, approach_n=u_n, approach_t=u_t,
        k_nn=k_nn, k_nt=k_nt, k_tt=k_tt,
        approaching=np.broadcast_to(approaching, p_n.shape),
        q_singular=np.broadcast_to(singular, p_n.shape),
    )
