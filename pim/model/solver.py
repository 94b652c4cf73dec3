"""Brach's Planar Impact Mechanics: :func:`solve`, the closed-form post-impact state.

The arithmetic is :mod:`pim.model.formula` (derivation and equations there); this module
checks the inputs, chooses the path that evaluates it and wraps the answer in a
:class:`pim.Result`:

* one scalar case: plain Python floats (a few microseconds);
* small batches, or ``backend="numpy"``: numpy over broadcast arrays (the reference path);
* batches of :data:`FAST_PATH_MIN_SIZE` cases and more: the fused parallel numba kernel
  (:mod:`pim.model.kernel`), which compiles the same formula.

The Python and numpy paths agree bitwise (same operations in the same order, the C library's
sine and cosine; ``tests/pim/model/test_solver.py``). The kernel takes its own sine and cosine
(within
1 ulp) by default, which lets it run near the memory-copy bound, and agrees with numpy within
:data:`pim.model.kernel.ULP_BOUND` ulp of each output's scale times the condition number of q;
``fast_trig=False`` makes it bitwise equal to numpy at about 0.35 of the copy bound
(``tests/pim/model/test_kernel.py``, ``benchmarks/bench_solve.py``).

*Energy.* The kinetic energy lost is -P.(u + U)/2, whose n and t parts are the normal and
tangential crush energies (Brach & Welsh, SAE 2007-01-0737); Brach's closed form T_L is
evaluated separately as a check.
"""

from __future__ import annotations

import math

import numpy as np

from . import formula
from .case import Case, checked_case
from .geometry import vec
from .numbers import InputError, checked_number, real_array
from .result import Result

__all__ = ["solve", "constraints", "unknown_hint", "APPROACH_TOLERANCE", "SINGULAR_TOLERANCE",
           "FAST_PATH_MIN_SIZE"]

#: A normal approach u_n smaller than this fraction of |u_n| + |u_t| is round-off, not an
#: impact: at beta = 1 an infinitesimal approach would stop the whole tangential slip, so the
#: sign of a rounding error would decide between no impulse and a finite one.
APPROACH_TOLERANCE = 1e-12
#: |K_nn Pn0 + beta K_nt Pt0| below this fraction of its terms' size counts as singular q.
SINGULAR_TOLERANCE = 1e-12
#: Batches of at least this many cases take the compiled kernel under backend="auto".
FAST_PATH_MIN_SIZE = 20_000


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
        eps missing everywhere, outside [0, 1] or NaN; beta not finite; a string, boolean or
        complex value for either.
    """
    eps, beta = defaults(case, eps, beta)
    return _check_eps(eps), _check_beta(beta)


def defaults(case: Case, eps=None, beta=None):
    """eps and beta as given, else the case's ``impact.restitution`` and ``impact.beta``,
    else (beta only) 1: the one place where beta defaults to 1.

    Raises
    ------
    ValueError
        eps is None and the case has no restitution.
    """
    if eps is None:
        eps = case.impact.restitution
        if eps is None:
            raise InputError("eps is required: give it or set impact.restitution in the "
                             f"case{unknown_hint(case)}")
    if beta is None:
        beta = 1.0 if case.impact.beta is None else case.impact.beta
    return eps, beta


def unknown_hint(case: Case) -> str:
    """What to run when a case's missing coefficient is one of its ``[unknown]``s ("" else)."""
    return ("; this case names unknowns in [unknown]: `pim reconstruct` solves them"
            if getattr(case, "unknown", None) else "")


def _check_eps(eps) -> np.ndarray:
    eps = real_array(eps, "eps (coefficient of restitution)")
    if np.isnan(eps).any() or ((eps < 0) | (eps > 1)).any():
        raise InputError("eps (coefficient of restitution) must be in [0, 1]")
    return eps


def _check_beta(beta) -> np.ndarray:
    beta = real_array(beta, "beta (fraction of mu0)")
    if not np.isfinite(beta).all():
        raise InputError("beta (fraction of mu0) must be a finite number, usually in [0, 1]")
    return beta


_FLOATS = frozenset((float, int, np.float64))


def _is_float(x) -> bool:
    """A plain real number (not a bool, string or array): the scalar path takes it."""
    return type(x) in _FLOATS


def _use_kernel(case: Case, eps, beta, backend: str) -> bool:
    """Whether :func:`solve` should run :mod:`pim.model.kernel` (imports numba only if so)."""
    if backend not in ("auto", "numpy", "numba"):
        raise InputError(f"backend must be 'auto', 'numpy' or 'numba', got {backend!r}")
    if backend == "numpy":
        return False
    if backend == "auto":
        shape = np.broadcast_shapes(case.shape, np.shape(eps), np.shape(beta))
        if math.prod(shape) < FAST_PATH_MIN_SIZE:
            return False
    try:
        import numba  # noqa: F401
    except ImportError:
        if backend == "numba":
            raise InputError("backend='numba' needs numba installed (pip install numba)") from None
        return False
    return True


def _check_tolerances(approach_tol, singular_tol) -> None:
    if approach_tol is not APPROACH_TOLERANCE:
        checked_number(approach_tol, "approach_tol", low=0.0)
    if singular_tol is not SINGULAR_TOLERANCE:
        checked_number(singular_tol, "singular_tol", low=0.0)


def solve(case: Case, eps=None, beta=None, backend: str = "auto", fast_trig: bool = True,
          approach_tol: float = APPROACH_TOLERANCE,
          singular_tol: float = SINGULAR_TOLERANCE) -> Result:
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
        "numpy" is the reference path (numpy over broadcast arrays); "numba" runs the fused
        parallel kernel of :mod:`pim.model.kernel`: the same values, every field at the full
        broadcast shape, the auxiliary fields (arms, K, approach velocity, n-t impulse
        components) computed on first read; "auto" takes plain Python floats for a single
        case given as scalars, the kernel for batches of at least ``FAST_PATH_MIN_SIZE``
        cases when numba is installed, numpy otherwise.
    fast_trig : bool
        On the kernel only: take sin and cos of Gamma from the kernel's own branch-free
        fdlibm polynomials (within 1 ulp of the C library's; the default), which lets the
        compiler vectorise the kernel (near the memory-copy bound; ``benchmarks/bench_solve.py``),
        so results agree with the numpy path within :data:`pim.model.kernel.ULP_BOUND` ulp of
        their scale times the condition number of q; False takes the C library's, bitwise
        equal to the numpy path and about 2.5x slower.
    approach_tol : float
        The vehicles approach at C where u_n < -approach_tol (|u_n| + |u_t|) [-].
    singular_tol : float
        q counts as singular where the impulse's denominator is below singular_tol times the
        size of its terms [-].

    Returns
    -------
    Result
        Post-impact velocities, yaw rates and impulse, broadcast over all inputs, with the
        derived quantities (energies, crush, PDOF, admissibility flags) computed on first use.

    Notes
    -----
    Implements Brach & Brach (2011) eqs. 6.45-6.62 in vector form (:mod:`pim.model.formula`).
    Where the vehicles do not approach at C (u_n >= 0, to round-off) no impact takes place:
    the impulse is zero and ``approaching`` is False. Where q is singular (A - mu B = 0) the
    impulse is unbounded: outputs are NaN and ``q_singular`` is True.

    Examples
    --------
    >>> import pim
    >>> r = pim.solve(pim.load_case("ricsac9"), eps=0.355, beta=1.0)
    >>> round(float(r.mu0), 3)          # the sheet prints mu0(0.355) = 0.512
    0.512
    """
    _check_tolerances(approach_tol, singular_tol)
    checked_case(case)
    eps, beta = defaults(case, eps, beta)
    if (backend == "auto" and case.is_scalar and _is_float(eps) and _is_float(beta)):
        return _solve_scalar(case, float(eps), float(beta), approach_tol, singular_tol)
    eps, beta = _check_eps(eps), _check_beta(beta)
    try:
        np.broadcast_shapes(case.shape, eps.shape, beta.shape)
    except ValueError:
        raise InputError(f"the shapes of eps {eps.shape}, beta {beta.shape} and the case's "
                         f"inputs {case.shape} do not broadcast together") from None
    if _use_kernel(case, eps, beta, backend):
        from .kernel import solve_case  # numba loads only for the batch path

        return solve_case(case, eps, beta, approach_tol, singular_tol, fast_trig=fast_trig)
    return _solve_numpy(case, eps, beta, approach_tol, singular_tol)


def _solve_scalar(case: Case, eps: float, beta: float, approach_tol: float,
                  singular_tol: float) -> Result:
    """:mod:`pim.model.formula` on plain floats: one case."""
    if not (0.0 <= eps <= 1.0):
        raise InputError("eps (coefficient of restitution) must be in [0, 1]")
    if not math.isfinite(beta):
        raise InputError("beta (fraction of mu0) must be a finite number, usually in [0, 1]")
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    m1, i1, w1 = float(v1.mass), float(v1.yaw_inertia), float(v1.yaw_rate)
    m2, i2, w2 = float(v2.mass), float(v2.yaw_inertia), float(v2.yaw_rate)
    gamma = float(imp.normal_angle)
    a1, b1, a2, b2 = 1.0 / m1, 1.0 / i1, 1.0 / m2, 1.0 / i2
    px, py = imp.point.tolist()
    g1x, g1y = v1.cg.tolist()
    g2x, g2y = v2.cg.tolist()
    r1x, r1y, r2x, r2y = px - g1x, py - g1y, px - g2x, py - g2y
    v1x, v1y = v1.velocity.tolist()
    v2x, v2y = v2.velocity.tolist()
    cs, sn = math.cos(gamma), math.sin(gamma)
    ux, uy, u_n, u_t, k_nn, k_nt, k_tt, pn0, pt0, drive, denom, appr, sing = formula.contact(
        cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2, eps, beta,
        approach_tol, singular_tol)
    scale = math.nan if sing else (drive / denom if appr else 0.0)
    p_n, p_t, ix, iy, vx1, vy1, vx2, vy2, ww1, ww2 = formula.post_impact(
        scale, pn0, pt0, beta, cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x,
        v2y, w2)
    raw = {"velocity1": (vx1, vy1), "velocity2": (vx2, vy2), "yaw_rate1": ww1,
           "yaw_rate2": ww2, "impulse": (ix, iy), "impulse_n": p_n, "impulse_t": p_t,
           "critical_impulse_n": pn0, "critical_impulse_t": pt0, "normal": (cs, sn),
           "tangent": (-sn, cs), "arm1": (r1x, r1y), "arm2": (r2x, r2y),
           "approach_velocity": (ux, uy), "approach_n": u_n, "approach_t": u_t, "k_nn": k_nn,
           "k_nt": k_nt, "k_tt": k_tt, "approaching": appr, "q_singular": sing}
    return Result(case, np.float64(eps), np.float64(beta), raw=raw, backend="python")


def _solve_numpy(case: Case, eps: np.ndarray, beta: np.ndarray, approach_tol: float,
                 singular_tol: float) -> Result:
    """:mod:`pim.model.formula` on numpy arrays: the reference path."""
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    a1, b1 = v1.inverse_mass, v1.inverse_inertia
    a2, b2 = v2.inverse_mass, v2.inverse_inertia
    gamma = imp.normal_angle
    cs, sn = np.cos(gamma), np.sin(gamma)
    r1 = imp.point - v1.cg
    r2 = imp.point - v2.cg
    r1x, r1y, r2x, r2y = r1[..., 0], r1[..., 1], r2[..., 0], r2[..., 1]
    v1x, v1y = v1.velocity[..., 0], v1.velocity[..., 1]
    v2x, v2y = v2.velocity[..., 0], v2.velocity[..., 1]
    w1, w2 = v1.yaw_rate, v2.yaw_rate
    ux, uy, u_n, u_t, k_nn, k_nt, k_tt, pn0, pt0, drive, denom, appr, sing = formula.contact(
        cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2, eps, beta,
        approach_tol, singular_tol)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(appr, drive / denom, 0.0)
    scale = np.where(sing, np.nan, scale)
    p_n, p_t, ix, iy, vx1, vy1, vx2, vy2, ww1, ww2 = formula.post_impact(
        scale, pn0, pt0, beta, cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x,
        v2y, w2)
    shape = np.shape(p_n)
    fields = {
        "velocity1": vec(vx1, vy1), "velocity2": vec(vx2, vy2), "yaw_rate1": ww1,
        "yaw_rate2": ww2, "impulse": vec(ix, iy), "impulse_n": p_n, "impulse_t": p_t,
        "critical_impulse_n": pn0, "critical_impulse_t": pt0, "normal": vec(cs, sn),
        "tangent": vec(-sn, cs), "arm1": r1, "arm2": r2, "approach_velocity": vec(ux, uy),
        "approach_n": u_n, "approach_t": u_t, "k_nn": k_nn, "k_nt": k_nt, "k_tt": k_tt,
        "approaching": np.broadcast_to(appr, shape), "q_singular": np.broadcast_to(sing, shape),
    }
    return Result(case, eps, beta, fields)
