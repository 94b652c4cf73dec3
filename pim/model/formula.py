"""The closed-form PIM arithmetic, written once.

Every evaluation of Brach's Planar Impact Mechanics in the project runs these two functions:

* numpy evaluates them on arrays (the reference path of :func:`pim.solve`, any shapes that
  broadcast);
* numba compiles the very same Python functions into the fused parallel batch kernel
  (:mod:`pim.model.kernel`);
* plain Python evaluates them on floats for a single case (the fast scalar path of
  :func:`pim.solve`);
* :mod:`pim.model.dual` evaluates them on dual numbers for exact derivatives with respect to
  any input.

They hold only arithmetic (``+ - * /``, ``abs`` and comparisons), in a fixed order, so the
numpy and numba evaluations agree bitwise (no fast-math, no contraction). What is not
arithmetic stays with the caller: the sine and cosine of Gamma, and the two selections
``scale = drive / denom`` where the vehicles approach (else 0) and NaN where q is singular,
which numpy does with ``np.where``, numba and Python with a conditional.

Derivation (global x-y frame; Brach & Brach 2011, ch. 6, eqs. 6.45-6.62 in n-t components)
-----------------------------------------------------------------------------------------
Body i has inverse mass a_i, inverse yaw inertia b_i, CG velocity v_i and yaw rate w_i; the
arm from its CG to the common point C is r_i = C - G_i, and the velocity of C on body i is
u_i = v_i + w_i k x r_i (k x r = (-r_y, r_x)). The impulse P acts on body 1 at C, -P on
body 2:

    V_1 = v_1 + a_1 P,    W_1 = w_1 + b_1 (r_1 x P),
    V_2 = v_2 - a_2 P,    W_2 = w_2 - b_2 (r_2 x P),

so the relative velocity of C, u = u_1 - u_2, changes by K P with the 2x2 effective
inverse-mass matrix (in n-t components, s_i = k x r_i)

    K = (a_1 + a_2) 1 + b_1 s_1 s_1^T + b_2 s_2 s_2^T.

n = (cos Gamma, sin Gamma) points from vehicle 2 toward vehicle 1, t = (-sin Gamma,
cos Gamma); u_n = u.n < 0 on approach. The critical impulse (sticking, mu = mu0) solves
K [Pn0, Pt0] = -[(1 + eps) u_n, u_t] (restitution U_n = -eps u_n and U_t = 0); it stays
finite for grazing impacts where Brach's r = u_t / u_n (eq. 6.60) diverges. For
mu = beta mu0 the normal row gives P = s (Pn0, beta Pt0) with

    s = -(1 + eps) u_n / (-(1 + eps) u_n + (beta - 1) K_nt Pt0)         (= drive / denom),

exact at beta = 1 and free of cancellation as A - mu B -> 0 (q -> infinity), where the
denominator vanishes: Brach's A = m_c K_nn, B = -m_c K_nt, C = m_c K_tt - 1,
q = 1 / (A - mu B) (eq. 6.55), m_c = 1 / (a_1 + a_2).
"""

from __future__ import annotations

__all__ = ["contact", "post_impact", "CONTACT_OUTPUTS", "POST_IMPACT_OUTPUTS"]

#: Names of :func:`contact`'s return values, in order.
CONTACT_OUTPUTS = ("ux", "uy", "u_n", "u_t", "k_nn", "k_nt", "k_tt", "pn0", "pt0", "drive",
                   "denom", "approaching", "singular")
#: Names of :func:`post_impact`'s return values, in order.
POST_IMPACT_OUTPUTS = ("p_n", "p_t", "px", "py", "vx1", "vy1", "vx2", "vy2", "w1", "w2")


def contact(cos_g, sin_g, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2,
            eps, beta, approach_tol, singular_tol):
    """Approach velocity, effective inverse mass and critical impulse at C.

    Parameters
    ----------
    cos_g, sin_g : float or ndarray
        cos Gamma and sin Gamma of the contact-plane angle [-].
    a1, a2 : float or ndarray
        Inverse masses [1/kg] (0 for a fixed obstacle).
    b1, b2 : float or ndarray
        Inverse yaw inertias [1/(kg m^2)].
    r1x, r1y, r2x, r2y : float or ndarray
        Arms C - G_i [m].
    v1x, v1y, v2x, v2y : float or ndarray
        Pre-impact CG velocities [m/s].
    w1, w2 : float or ndarray
        Pre-impact yaw rates [rad/s].
    eps, beta : float or ndarray
        Coefficient of restitution [-] and fraction of mu0 [-].
    approach_tol : float
        u_n counts as an approach only below ``-approach_tol (|u_n| + |u_t|)``.
    singular_tol : float
        q is singular where ``|denom| <= singular_tol (|drive| + |excess|)``.

    Returns
    -------
    tuple
        ``ux, uy`` relative velocity of C before impact [m/s]; ``u_n, u_t`` its n-t
        components [m/s]; ``k_nn, k_nt, k_tt`` entries of K [1/kg]; ``pn0, pt0`` the
        critical impulse [N s]; ``drive, denom`` numerator and denominator of the impulse
        scale s [m/s]; ``approaching`` and ``singular`` flags (see :data:`CONTACT_OUTPUTS`).

    Notes
    -----
    Brach & Brach (2011) eqs. 6.45-6.60 in vector form; see the module docstring.
    """
    nx = cos_g
    ny = sin_g
    tx = -sin_g
    ty = cos_g
    # u = (v1 + w1 k x r1) - (v2 + w2 k x r2), with k x r = (-r_y, r_x)
    ux = (v1x + w1 * -r1y) - (v2x + w2 * -r2y)
    uy = (v1y + w1 * r1x) - (v2y + w2 * r2x)
    u_n = ux * nx + uy * ny
    u_t = ux * tx + uy * ty
    s1n = r1x * ny - r1y * nx
    s1t = r1x * ty - r1y * tx
    s2n = r2x * ny - r2y * nx
    s2t = r2x * ty - r2y * tx
    a = a1 + a2
    k_nn = a + b1 * s1n * s1n + b2 * s2n * s2n
    k_nt = b1 * s1n * s1t + b2 * s2n * s2t
    k_tt = a + b1 * s1t * s1t + b2 * s2t * s2t
    e1 = 1.0 + eps
    det = k_nn * k_tt - k_nt * k_nt
    pn0 = (-e1 * u_n * k_tt + u_t * k_nt) / det
    pt0 = (-u_t * k_nn + e1 * u_n * k_nt) / det
    # K_nn Pn0 + beta K_nt Pt0 = -(1 + eps) u_n + (beta - 1) K_nt Pt0
    drive = -e1 * u_n
    excess = (beta - 1.0) * k_nt * pt0
    denom = drive + excess
    approaching = u_n < -approach_tol * (abs(u_n) + abs(u_t))
    singular = approaching & (abs(denom) <= singular_tol * (abs(drive) + abs(excess)))
    return ux, uy, u_n, u_t, k_nn, k_nt, k_tt, pn0, pt0, drive, denom, approaching, singular


def post_impact(scale, pn0, pt0, beta, cos_g, sin_g, a1, b1, r1x, r1y, v1x, v1y, w1,
                a2, b2, r2x, r2y, v2x, v2y, w2):
    """Impulse and post-impact motion for the impulse scale s.

    Parameters
    ----------
    scale : float or ndarray
        s = drive / denom where the vehicles approach, 0 where they do not, NaN where q is
        singular [-].
    pn0, pt0 : float or ndarray
        Critical impulse [N s] from :func:`contact`.
    beta : float or ndarray
        Fraction of mu0 [-].
    cos_g, sin_g, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2
        As in :func:`contact`.

    Returns
    -------
    tuple
        ``p_n, p_t`` the impulse on vehicle 1 in n-t components [N s], ``px, py`` in x-y
        [N s]; ``vx1, vy1, vx2, vy2`` post-impact CG velocities [m/s]; ``w1, w2``
        post-impact yaw rates [rad/s] (see :data:`POST_IMPACT_OUTPUTS`).

    Notes
    -----
    P = s (Pn0 n + beta Pt0 t); V_1 = v_1 + a_1 P, W_1 = w_1 + b_1 (r_1 x P), and the
    opposite on vehicle 2 (Brach & Brach 2011, eqs. 6.61-6.62).
    """
    p_n = scale * pn0
    p_t = scale * beta * pt0
    px = p_n * cos_g + p_t * -sin_g
    py = p_n * sin_g + p_t * cos_g
    return (p_n, p_t, px, py, v1x + a1 * px, v1y + a1 * py, v2x - a2 * px, v2y - a2 * py,
            w1 + b1 * (r1x * py - r1y * px), w2 - b2 * (r2x * py - r2y * px))
