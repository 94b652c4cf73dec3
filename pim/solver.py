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

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .case import Case

__all__ = ["solve", "Result", "constraints", "effective_mass_matrix", "contact_velocity"]

#: A normal approach u_n smaller than this fraction of |u_n| + |u_t| is round-off, not an
#: impact: at beta = 1 an infinitesimal approach would stop the whole tangential slip, so the
#: sign of a rounding error would decide between no impulse and a finite one.
#: pim.kernel compiles this in as a constant: after changing it, delete pim/__pycache__'s
#: numba cache files (*.nbi, *.nbc), which are keyed on kernel.py alone.
APPROACH_TOLERANCE = 1e-12
#: |K_nn Pn0 + beta K_nt Pt0| below this fraction of its terms' size counts as singular q.
SINGULAR_TOLERANCE = 1e-12


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z-component of a x b for vectors of shape (..., 2)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def _perp(a: np.ndarray) -> np.ndarray:
    """k x a: the vector rotated +90 deg."""
    return np.stack([-a[..., 1], a[..., 0]], axis=-1)


def _vec(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    x, y = np.broadcast_arrays(x, y)
    return np.stack([x, y], axis=-1)


def contact_velocity(velocity, yaw_rate, arm) -> np.ndarray:
    """Velocity of the material point at ``cg + arm`` of a rigid body in planar motion.

    Parameters
    ----------
    velocity : array_like, shape (..., 2)
        CG velocity [m/s].
    yaw_rate : array_like
        Yaw rate [rad/s].
    arm : array_like, shape (..., 2)
        Vector from the CG to the point [m].

    Returns
    -------
    ndarray, shape (..., 2)
        v + w k x r [m/s] (Brach & Brach 2011, eq. 6.45 in vector form).
    """
    arm = np.asarray(arm, dtype=float)
    return np.asarray(velocity) + np.asarray(yaw_rate)[..., None] * _perp(arm)


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
    s1n, s1t = _cross(arm1, normal), _cross(arm1, tangent)
    s2n, s2t = _cross(arm2, normal), _cross(arm2, tangent)
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
    if eps is None:
        eps = case.impact.restitution
        if eps is None:
            raise ValueError("eps is required: give it or set impact.restitution in the case")
    if beta is None:
        beta = 1.0 if case.impact.beta is None else case.impact.beta
    return eps, beta


def _check_eps(eps) -> np.ndarray:
    eps = np.asarray(eps, dtype=float)
    if np.isnan(eps).any() or ((eps < 0) | (eps > 1)).any():
        raise ValueError("eps (coefficient of restitution) must be in [0, 1]")
    return eps


def _check_beta(beta) -> np.ndarray:
    beta = np.asarray(beta, dtype=float)
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
    n = _vec(np.cos(gamma), np.sin(gamma))
    t = _vec(-np.sin(gamma), np.cos(gamma))
    r1 = imp.point - v1.cg
    r2 = imp.point - v2.cg
    u = (contact_velocity(v1.velocity, v1.yaw_rate, r1)
         - contact_velocity(v2.velocity, v2.yaw_rate, r2))
    u_n, u_t = _dot(u, n), _dot(u, t)
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
        yaw_rate1=v1.yaw_rate + b1 * _cross(r1, impulse),
        yaw_rate2=v2.yaw_rate - b2 * _cross(r2, impulse),
        impulse=impulse, impulse_n=p_n, impulse_t=p_t,
        critical_impulse_n=pn0, critical_impulse_t=pt0,
        normal=n, tangent=t, arm1=r1, arm2=r2,
        approach_velocity=u, approach_n=u_n, approach_t=u_t,
        k_nn=k_nn, k_nt=k_nt, k_tt=k_tt,
        approaching=np.broadcast_to(approaching, p_n.shape),
        q_singular=np.broadcast_to(singular, p_n.shape),
    )


def _wrap(angle: np.ndarray) -> np.ndarray:
    """Wrap angles [rad] into (-pi, pi]."""
    return np.pi - np.mod(np.pi - angle, 2 * np.pi)


def _pdof(impulse: np.ndarray, heading: np.ndarray) -> np.ndarray:
    """Principal direction of force [rad] of an impulse on a vehicle.

    The direction from which the impulse comes (that of -P), measured from the vehicle's
    heading clockwise, as in SAE J224's clock convention: 0 = from straight ahead (frontal),
    +pi/2 = from the right side, -pi/2 = from the left, pi = from behind. Wrapped to (-pi, pi].
    NaN where there is no impulse (no impact; see ``Result.approaching``).
    """
    came_from = np.arctan2(-impulse[..., 1], -impulse[..., 0])
    none = (impulse[..., 0] == 0) & (impulse[..., 1] == 0)
    return np.where(none, np.nan, _wrap(heading - came_from))


def _clock(pdof: np.ndarray) -> np.ndarray:
    """Clock position (1..12, 12 = frontal) of a PDOF [rad], nearest hour; 0 where PDOF is NaN."""
    hours = np.mod(np.rint(np.nan_to_num(np.degrees(pdof)) / 30.0), 12)
    return np.where(np.isnan(pdof), 0, np.where(hours == 0, 12, hours)).astype(int)


def _kinetic(mass, inertia, velocity, yaw_rate) -> np.ndarray:
    """Kinetic energy [J] of a body; 0 for a fixed obstacle (at rest by construction)."""
    with np.errstate(invalid="ignore"):
        energy = 0.5 * mass * _dot(velocity, velocity) + 0.5 * inertia * yaw_rate * yaw_rate
    return np.where(np.isinf(mass), 0.0, energy)


@dataclass(frozen=True, eq=False)
class Result:
    """The outcome of :func:`solve`: post-impact motion and everything derived from it.

    Every array broadcasts over the inputs (vectors carry a trailing axis of 2). The core
    fields are computed by :func:`solve`; the properties below them are computed on first
    access and cached. Units: m/s, rad/s, N s, J, rad.

    Attributes
    ----------
    velocity1, velocity2 : ndarray (..., 2)
        Post-impact CG velocities [m/s].
    yaw_rate1, yaw_rate2 : ndarray
        Post-impact yaw rates [rad/s].
    impulse : ndarray (..., 2)
        Impulse P on vehicle 1 [N s] (vehicle 2 receives -P).
    impulse_n, impulse_t : ndarray
        Its components Pn, Pt along n and t [N s].
    critical_impulse_n, critical_impulse_t : ndarray
        The impulse at mu = mu0 (beta = 1) [N s].
    approaching : ndarray of bool
        u_n < 0 beyond round-off (by more than APPROACH_TOLERANCE of |u_n| + |u_t|): the
        vehicles approach at C. Where False no impulse is applied.
    q_singular : ndarray of bool
        A - mu B = 0: the impulse is unbounded; outputs there are NaN.
    """

    case: Case
    eps: np.ndarray
    beta: np.ndarray
    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: np.ndarray
    yaw_rate2: np.ndarray
    impulse: np.ndarray
    impulse_n: np.ndarray
    impulse_t: np.ndarray
    critical_impulse_n: np.ndarray
    critical_impulse_t: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    arm1: np.ndarray
    arm2: np.ndarray
    approach_velocity: np.ndarray
    approach_n: np.ndarray
    approach_t: np.ndarray
    k_nn: np.ndarray
    k_nt: np.ndarray
    k_tt: np.ndarray
    approaching: np.ndarray
    q_singular: np.ndarray

    # ---- impulse ratio -------------------------------------------------------------------
    @cached_property
    def mu0(self) -> np.ndarray:
        """Critical impulse ratio mu0 = Pt0 / Pn0 [-] (eq. 6.60): no sliding at C after impact."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.critical_impulse_t / self.critical_impulse_n

    @cached_property
    def mu(self) -> np.ndarray:
        """Impulse ratio mu = beta mu0 = Pt / Pn [-]."""
        return self.beta * self.mu0

    # ---- Brach's coefficients ------------------------------------------------------------
    @cached_property
    def reduced_mass(self) -> np.ndarray:
        """m_c = m1 m2 / (m1 + m2) [kg]; m1 for a fixed vehicle 2."""
        return 1.0 / (self.case.vehicle1.inverse_mass + self.case.vehicle2.inverse_mass)

    @cached_property
    def A(self) -> np.ndarray:  # noqa: N802 - Brach's symbol
        """Brach's A = 1 + m_c d_c^2/(m1 k1^2) + m_c d_a^2/(m2 k2^2) [-] (eq. 6.46)."""
        return self.reduced_mass * self.k_nn

    @cached_property
    def B(self) -> np.ndarray:  # noqa: N802
        """Brach's B = m_c d_c d_d/(m1 k1^2) + m_c d_a d_b/(m2 k2^2) [-] (eq. 6.46)."""
        return -self.reduced_mass * self.k_nt

    @cached_property
    def C(self) -> np.ndarray:  # noqa: N802
        """Brach's C = m_c d_d^2/(m1 k1^2) + m_c d_b^2/(m2 k2^2) [-] (eq. 6.46; no leading 1)."""
        return self.reduced_mass * self.k_tt - 1.0

    @cached_property
    def q(self) -> np.ndarray:
        """Brach's q = 1 / (A - mu B) [-] (eq. 6.55)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return 1.0 / (self.A - self.mu * self.B)

    @cached_property
    def r(self) -> np.ndarray:
        """Brach's r = u_t / u_n [-], tangential over normal approach velocity at C (eq. 6.60)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.approach_t / self.approach_n

    # ---- motion --------------------------------------------------------------------------
    @cached_property
    def delta_v1(self) -> np.ndarray:
        """Change of vehicle 1's CG velocity [m/s], shape (..., 2)."""
        return self.velocity1 - self.case.vehicle1.velocity

    @cached_property
    def delta_v2(self) -> np.ndarray:
        """Change of vehicle 2's CG velocity [m/s], shape (..., 2)."""
        return self.velocity2 - self.case.vehicle2.velocity

    @cached_property
    def delta_v1_magnitude(self) -> np.ndarray:
        """|delta-V| of vehicle 1 [m/s]."""
        return np.hypot(self.delta_v1[..., 0], self.delta_v1[..., 1])

    @cached_property
    def delta_v2_magnitude(self) -> np.ndarray:
        """|delta-V| of vehicle 2 [m/s]."""
        return np.hypot(self.delta_v2[..., 0], self.delta_v2[..., 1])

    @cached_property
    def speed1(self) -> np.ndarray:
        """Post-impact speed of vehicle 1 [m/s]."""
        return np.hypot(self.velocity1[..., 0], self.velocity1[..., 1])

    @cached_property
    def speed2(self) -> np.ndarray:
        """Post-impact speed of vehicle 2 [m/s]."""
        return np.hypot(self.velocity2[..., 0], self.velocity2[..., 1])

    @cached_property
    def separation_velocity(self) -> np.ndarray:
        """Relative velocity of C after impact, U = U_1 - U_2 [m/s], shape (..., 2)."""
        return (contact_velocity(self.velocity1, self.yaw_rate1, self.arm1)
                - contact_velocity(self.velocity2, self.yaw_rate2, self.arm2))

    @cached_property
    def separation_n(self) -> np.ndarray:
        """U_n, normal relative velocity at C after impact [m/s]."""
        return _dot(self.separation_velocity, self.normal)

    @cached_property
    def separation_t(self) -> np.ndarray:
        """U_t, tangential relative velocity at C after impact [m/s]."""
        return _dot(self.separation_velocity, self.tangent)

    @cached_property
    def restitution_check(self) -> np.ndarray:
        """-U_n / u_n [-]: equals eps by construction (the sheet's consistency check)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return -self.separation_n / self.approach_n

    # ---- energy --------------------------------------------------------------------------
    @cached_property
    def kinetic_energy_before(self) -> np.ndarray:
        """Total kinetic energy before impact [J]."""
        v1, v2 = self.case.vehicle1, self.case.vehicle2
        return (_kinetic(v1.mass, v1.yaw_inertia, v1.velocity, v1.yaw_rate)
                + _kinetic(v2.mass, v2.yaw_inertia, v2.velocity, v2.yaw_rate))

    @cached_property
    def kinetic_energy_after(self) -> np.ndarray:
        """Total kinetic energy after impact [J]."""
        v1, v2 = self.case.vehicle1, self.case.vehicle2
        return (_kinetic(v1.mass, v1.yaw_inertia, self.velocity1, self.yaw_rate1)
                + _kinetic(v2.mass, v2.yaw_inertia, self.velocity2, self.yaw_rate2))

    @cached_property
    def energy_loss(self) -> np.ndarray:
        """Kinetic energy lost in the impact [J] (negative: energy gained)."""
        return self.kinetic_energy_before - self.kinetic_energy_after

    @cached_property
    def energy_loss_percent(self) -> np.ndarray:
        """Energy lost as a percentage of the kinetic energy before impact [%]."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return 100.0 * self.energy_loss / self.kinetic_energy_before

    @cached_property
    def total_loss_brach(self) -> np.ndarray:
        """Brach's closed-form total impact loss T_L [J], equal to :attr:`energy_loss`.

        T_L = (1/2) m_c q v_rn^2 (1 + eps) [2 + 2 mu r - (1 + eps) q (A - 2 mu B + mu^2 (1 + C))]
        (the sheet's T_L with the m_c d_e^2, d_f^2 sum expanded), written with
        v_rn^2 r = u_n u_t so that it stays finite as u_n -> 0.
        """
        mu, q = self.mu, self.q
        u_n, u_t = self.approach_n, self.approach_t
        e1 = 1.0 + self.eps
        bracket = (2.0 * u_n * u_n + 2.0 * mu * u_n * u_t
                   - e1 * q * u_n * u_n * (self.A - 2.0 * mu * self.B + mu * mu * (1.0 + self.C)))
        loss = 0.5 * self.reduced_mass * q * e1 * bracket
        return np.where(self.approaching, loss, 0.0)

    @cached_property
    def crush_energy_normal(self) -> np.ndarray:
        """Energy lost in the normal direction, -Pn (u_n + U_n) / 2 [J]."""
        return -0.5 * self.impulse_n * (self.approach_n + self.separation_n)

    @cached_property
    def crush_energy_tangential(self) -> np.ndarray:
        """Energy lost in the tangential direction, -Pt (u_t + U_t) / 2 [J]."""
        return -0.5 * self.impulse_t * (self.approach_t + self.separation_t)

    @cached_property
    def tangential_share(self) -> np.ndarray:
        """Tangential crush energy as a fraction of the total loss [-] (0 where nothing is lost)."""
        total = self.crush_energy_normal + self.crush_energy_tangential
        return np.divide(self.crush_energy_tangential, total,
                         out=np.zeros(np.shape(total)), where=total != 0)

    # ---- direction of force ------------------------------------------------------------------
    @cached_property
    def impulse_angle(self) -> np.ndarray:
        """Direction of the impulse on vehicle 1 from +x [rad]."""
        return np.arctan2(self.impulse[..., 1], self.impulse[..., 0])

    @cached_property
    def pdof1(self) -> np.ndarray:
        """PDOF of vehicle 1 [rad], clockwise from its heading; 0 = frontal (see _pdof)."""
        return _pdof(self.impulse, self.case.vehicle1.heading)

    @cached_property
    def pdof2(self) -> np.ndarray:
        """PDOF of vehicle 2 [rad], clockwise from its heading; 0 = frontal."""
        return _pdof(-self.impulse, self.case.vehicle2.heading)

    @cached_property
    def clock1(self) -> np.ndarray:
        """PDOF of vehicle 1 as a clock position, 12 = frontal, 3 = right side."""
        return _clock(self.pdof1)

    @cached_property
    def clock2(self) -> np.ndarray:
        """PDOF of vehicle 2 as a clock position, 12 = frontal, 3 = right side."""
        return _clock(self.pdof2)

    # ---- admissibility -------------------------------------------------------------------
    @cached_property
    def normal_impulse_positive(self) -> np.ndarray:
        """Pn > 0: the contact pushes (a negative Pn would pull the vehicles together)."""
        return self.impulse_n > 0

    @cached_property
    def energy_not_gained(self) -> np.ndarray:
        """Kinetic energy does not rise (loss >= 0 within round-off)."""
        tol = 1e-9 * self.kinetic_energy_before
        return self.energy_loss >= -tol

    @cached_property
    def within_critical(self) -> np.ndarray:
        """|mu| <= |mu0| (0 <= beta <= 1): no reversal of tangential sliding at C."""
        return (self.beta >= 0) & (self.beta <= 1)

    @cached_property
    def friction_opposes_sliding(self) -> np.ndarray:
        """Pt U_t <= 0: the tangential impulse does not point along the slip left at C.

        With beta < 1 and strong n-t coupling, PIM's mu = beta mu0 can push along the
        post-impact sliding, which Coulomb friction cannot (and a simulator will not) do.
        """
        scale = np.abs(self.impulse_t) * (np.abs(self.approach_n) + np.abs(self.approach_t))
        return self.impulse_t * self.separation_t <= 1e-9 * scale

    @cached_property
    def admissible(self) -> np.ndarray:
        """All flags hold: approach, Pn > 0, no energy gain, |mu| <= |mu0|, friction opposing
        the remaining slip, finite q."""
        return (self.approaching & self.normal_impulse_positive & self.energy_not_gained
                & self.within_critical & self.friction_opposes_sliding & ~self.q_singular)

    def problems(self) -> list[str]:
        """Plain-language reasons why any element is inadmissible (empty when all are fine)."""
        checks = [
            (self.approaching, "the vehicles do not approach at C (u_n >= 0): no impact"),
            (~self.q_singular, "q is singular (A - mu B = 0): the impulse is unbounded"),
            (self.normal_impulse_positive | ~self.approaching,
             "the normal impulse is not positive (the contact would pull)"),
            (self.energy_not_gained, "kinetic energy is gained"),
            (self.friction_opposes_sliding | ~self.approaching,
             "the tangential impulse points along the remaining slip at C (not Coulomb friction)"),
            (np.broadcast_to(self.within_critical, np.shape(self.impulse_n)),
             "|mu| > |mu0| (beta outside [0, 1]): tangential sliding at C reverses"),
        ]
        out = []
        for ok, text in checks:
            ok = np.asarray(ok)
            bad = int(np.size(ok) - np.count_nonzero(ok))
            if bad:
                out.append(text if ok.size == 1 else f"{text} ({bad} of {ok.size} cases)")
        return out
