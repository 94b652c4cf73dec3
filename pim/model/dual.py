"""Forward-mode automatic differentiation of the one formula (:mod:`pim.model.formula`).

A :class:`Dual` carries a value and its gradient with respect to k seeded inputs; the
formula, being plain arithmetic, runs on duals unchanged and so gives exact derivatives (to
round-off, no step size) of every output with respect to any input. :func:`motion_jacobian`
differentiates the post-impact motion of a case with respect to epsilon, beta, Gamma, C,
the pre-impact velocities and yaw rates, the CG positions, masses and yaw inertias
(:data:`MOTION_INPUTS`); :func:`motion_of_inputs` does the same from a plain array of those
inputs, which is what a fit of any inputs iterates on. The hand-derived derivatives in the
test oracle ``tests/closed_form.py`` are tested against it. The other impact laws
(friction-capped Brach, Kudlich-Slibar) run the same formula with their impulse ratio on
these duals (:func:`pim.model.impact_laws.motion_of_law`; :func:`where` selects a cap's side).
"""

from __future__ import annotations

import numpy as np

from . import formula
from .case import Case

__all__ = ["Dual", "cos_sin", "sqrt", "hypot", "where", "value_of", "seed_inputs",
           "motion_jacobian", "motion_inputs", "motion_of_inputs", "MOTION_OUTPUTS",
           "MOTION_INPUTS"]


class Dual:
    """A number (or array) with its gradient: ``value`` shape S, ``grad`` shape S + (k,)."""

    __slots__ = ("value", "grad")
    __array_ufunc__ = None   # numpy arrays and scalars defer to the reflected operators below

    def __init__(self, value, grad) -> None:
        self.value = np.asarray(value, dtype=float)
        self.grad = np.asarray(grad, dtype=float)

    @classmethod
    def _new(cls, value, grad):
        """A dual from arrays already of float dtype (no conversion: the arithmetic's path)."""
        d = object.__new__(cls)
        d.value = value
        d.grad = grad
        return d

    @staticmethod
    def _split(x):
        if isinstance(x, Dual):
            return x.value, x.grad
        return np.asarray(x, dtype=float), 0.0

    def __add__(self, other):
        if isinstance(other, Dual):
            return Dual._new(self.value + other.value, self.grad + other.grad)
        return Dual._new(self.value + other, self.grad + 0.0)

    __radd__ = __add__

    def __sub__(self, other):
        if isinstance(other, Dual):
            return Dual._new(self.value - other.value, self.grad - other.grad)
        return Dual._new(self.value - other, self.grad + 0.0)

    def __rsub__(self, other):
        return Dual._new(other - self.value, -self.grad)

    def __mul__(self, other):
        if isinstance(other, Dual):
            return Dual._new(self.value * other.value,
                             self.grad * other.value[..., None]
                             + self.value[..., None] * other.grad)
        v = np.asarray(other, dtype=float)
        if v.ndim == 0:
            return Dual._new(self.value * v, self.grad * v)
        return Dual._new(self.value * v, self.grad * v[..., None]
                         + np.zeros_like(self.value)[..., None])

    __rmul__ = __mul__

    def __truediv__(self, other):
        if isinstance(other, Dual):
            q = self.value / other.value
            return Dual._new(q, (self.grad - q[..., None] * other.grad) / other.value[..., None])
        v = np.asarray(other, dtype=float)
        q = self.value / v
        if v.ndim == 0:
            return Dual._new(q, self.grad / v)
        return Dual._new(q, self.grad / v[..., None] + np.zeros_like(q)[..., None])

    def __rtruediv__(self, other):
        v = np.asarray(other, dtype=float)
        q = v / self.value
        return Dual._new(q, -q[..., None] * self.grad / self.value[..., None])

    def __neg__(self):
        return Dual._new(-self.value, -self.grad)

    def __abs__(self):
        return Dual._new(np.abs(self.value), np.sign(self.value)[..., None] * self.grad)

    # comparisons act on the values (the branch flags of the formula)
    def __lt__(self, other):
        return self.value < self._split(other)[0]

    def __le__(self, other):
        return self.value <= self._split(other)[0]

    def __gt__(self, other):
        return self.value > self._split(other)[0]

    def __ge__(self, other):
        return self.value >= self._split(other)[0]


def cos_sin(x):
    """(cos x, sin x) of a number, an array or a :class:`Dual` (with d cos = -sin dx,
    d sin = cos dx)."""
    if not isinstance(x, Dual):
        return np.cos(x), np.sin(x)
    c, s = np.cos(x.value), np.sin(x.value)
    return Dual(c, -s[..., None] * x.grad), Dual(s, c[..., None] * x.grad)


def sqrt(x):
    """Square root of a number, an array or a :class:`Dual` (d sqrt x = dx / (2 sqrt x))."""
    if not isinstance(x, Dual):
        return np.sqrt(x)
    root = np.sqrt(x.value)
    with np.errstate(divide="ignore", invalid="ignore"):
        return Dual(root, x.grad / (2.0 * root)[..., None])


def hypot(x, y):
    """sqrt(x^2 + y^2) of arrays or :class:`Dual` numbers (gradient (x dx + y dy) / r, 0 at
    r = 0)."""
    if not isinstance(x, Dual) and not isinstance(y, Dual):
        return np.hypot(x, y)
    (xv, xg), (yv, yg) = Dual._split(x), Dual._split(y)
    r = np.hypot(xv, yv)
    safe = np.where(r > 0, r, 1.0)
    return Dual(r, (xv / safe)[..., None] * xg + (yv / safe)[..., None] * yg)


def value_of(x) -> np.ndarray:
    """The value of a :class:`Dual`, or ``x`` as a float array."""
    return x.value if isinstance(x, Dual) else np.asarray(x, dtype=float)


def where(condition, a, b):
    """``np.where(condition, a, b)`` for numbers, arrays and :class:`Dual` s: the value and
    the gradient of the branch selected (a kink's derivative is that of the side taken)."""
    if not isinstance(a, Dual) and not isinstance(b, Dual):
        return np.where(condition, a, b)
    (av, ag), (bv, bg) = Dual._split(a), Dual._split(b)
    cond = np.asarray(condition, dtype=bool)
    value = np.where(cond, av, bv)
    width = (a if isinstance(a, Dual) else b).grad.shape[-1]
    grad = np.where(cond[..., None], ag, bg)
    return Dual(value, np.broadcast_to(grad, value.shape + (width,)))


#: Inputs :func:`motion_jacobian` differentiates with respect to, in column order [SI].
MOTION_INPUTS = ("impact.restitution", "impact.beta", "impact.normal_angle", "impact.point_x",
                 "impact.point_y", "vehicle1.velocity_x", "vehicle1.velocity_y",
                 "vehicle1.yaw_rate", "vehicle2.velocity_x", "vehicle2.velocity_y",
                 "vehicle2.yaw_rate", "vehicle1.cg_x", "vehicle1.cg_y", "vehicle2.cg_x",
                 "vehicle2.cg_y", "vehicle1.mass", "vehicle1.yaw_inertia", "vehicle2.mass",
                 "vehicle2.yaw_inertia")
#: Outputs of :func:`motion_jacobian`, in row order [SI].
MOTION_OUTPUTS = ("impulse_n", "impulse_t", "impulse_x", "impulse_y", "velocity1_x",
                  "velocity1_y", "velocity2_x", "velocity2_y", "yaw_rate1", "yaw_rate2")


def motion_inputs(case: Case, eps, beta) -> np.ndarray:
    """The values of :data:`MOTION_INPUTS` of ``case`` [SI], shape S + (19,).

    A fixed obstacle's mass and yaw inertia are ``inf`` (zero inverse mass and inertia).
    """
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    cols = (eps, beta, imp.normal_angle, imp.point[..., 0], imp.point[..., 1],
            v1.velocity[..., 0], v1.velocity[..., 1], v1.yaw_rate, v2.velocity[..., 0],
            v2.velocity[..., 1], v2.yaw_rate, v1.cg[..., 0], v1.cg[..., 1], v2.cg[..., 0],
            v2.cg[..., 1], v1.mass, v1.yaw_inertia, v2.mass, v2.yaw_inertia)
    cols = [np.asarray(c, dtype=float) for c in cols]
    shape = np.broadcast_shapes(*(c.shape for c in cols))
    return np.stack([np.broadcast_to(c, shape) for c in cols], axis=-1)


def motion_jacobian(case: Case, eps, beta, approach_tol: float = 1e-12,
                    singular_tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """Post-impact motion and its exact Jacobian, by dual numbers through the formula.

    Parameters
    ----------
    case : Case
        Any shape (inputs broadcast).
    eps, beta : array_like
        Coefficient of restitution and fraction of mu0 [-].
    approach_tol, singular_tol : float
        As in :func:`pim.solve`.

    Returns
    -------
    values : ndarray, shape S + (10,)
        The outputs of :data:`MOTION_OUTPUTS` [N s, m/s, rad/s].
    jacobian : ndarray, shape S + (10, 19)
        d output / d input for the inputs of :data:`MOTION_INPUTS` [SI per SI]; zero where
        the vehicles do not approach, NaN where q is singular.
    """
    return motion_of_inputs(motion_inputs(case, eps, beta), approach_tol, singular_tol)


def seed_inputs(x: np.ndarray, tangent, jacobian: bool):
    """The formula's inputs from the rows ``x`` (:data:`MOTION_INPUTS` first, any further
    columns after them): ``seed(i)`` (input i), ``inverse(i)`` (its inverse, d(1/m) =
    -dm/m^2, zero at infinite mass), cos and sin of Gamma (input 2), and the gradient width;
    dual numbers carrying ``tangent`` (default: the identity) when ``jacobian``, plain
    arrays otherwise."""
    shape, n = x.shape[:-1], x.shape[-1]
    if tangent is None:
        tangent = np.broadcast_to(np.eye(n), shape + (n, n))
    tangent = np.asarray(tangent, dtype=float)

    def seed(index):
        return Dual(x[..., index], tangent[..., index, :]) if jacobian else x[..., index]

    def inverse(index):
        with np.errstate(divide="ignore"):
            inv = 1.0 / x[..., index]
        if not jacobian:
            return inv
        return Dual(inv, np.where(np.isinf(x[..., index]), 0.0, -inv * inv)[..., None]
                    * tangent[..., index, :])

    gamma = x[..., 2]
    if not jacobian:
        return seed, inverse, np.cos(gamma), np.sin(gamma), tangent.shape[-1]
    return (seed, inverse, Dual(np.cos(gamma), -np.sin(gamma)[..., None] * tangent[..., 2, :]),
            Dual(np.sin(gamma), np.cos(gamma)[..., None] * tangent[..., 2, :]),
            tangent.shape[-1])


def motion_of_inputs(x, approach_tol: float = 1e-12, singular_tol: float = 1e-12,
                     jacobian: bool = True, tangent=None) -> tuple[np.ndarray, np.ndarray | None]:
    """Post-impact motion of the inputs ``x`` (:data:`MOTION_INPUTS` order) and its Jacobian.

    Parameters
    ----------
    x : array_like, shape S + (19,)
        Values of :data:`MOTION_INPUTS` [SI] (see :func:`motion_inputs`).
    approach_tol, singular_tol : float
        As in :func:`pim.solve`.
    jacobian : bool
        False: plain arithmetic, no derivatives (the fast path of a coarse search).
    tangent : array_like, shape S + (19, n), optional
        d x / d p for n parameters p: the Jacobian is then d output / d p, shape
        S + (10, n) (the chain rule carried through the dual numbers, n columns wide instead
        of 19: a fit of two parameters differentiates at a fraction of the cost).

    Returns
    -------
    values : ndarray, shape S + (10,)
        The outputs of :data:`MOTION_OUTPUTS` [N s, m/s, rad/s] (formula of
        :mod:`pim.model.formula`, the same as :func:`pim.solve`).
    jacobian : ndarray, shape S + (10, 19) (S + (10, n) with ``tangent``), or None
        d output / d input; zero where the vehicles do not approach, NaN where q is singular.

    Notes
    -----
    Gamma enters through its sine and cosine, seeded with their derivatives (cos, -sin); the
    masses and inertias through their inverses, seeded with d(1/m)/dm = -1/m^2 (zero for a
    fixed obstacle of infinite mass).
    """
    x = np.asarray(x, dtype=float)
    shape = x.shape[:-1]
    seed, inverse, cs, sn, k = seed_inputs(x, tangent if jacobian else None, jacobian)
    e, b = seed(0), seed(1)
    px, py = seed(3), seed(4)
    v1x, v1y, w1 = seed(5), seed(6), seed(7)
    v2x, v2y, w2 = seed(8), seed(9), seed(10)
    r1x, r1y = px - seed(11), py - seed(12)
    r2x, r2y = px - seed(13), py - seed(14)
    a1, b1, a2, b2 = inverse(15), inverse(16), inverse(17), inverse(18)
    (_, _, _, _, _, _, _, pn0, pt0, drive, denom, appr, sing) = formula.contact(
        cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2, e, b,
        approach_tol, singular_tol)
    nan = np.where(sing, np.nan, 1.0)
    if jacobian:
        with np.errstate(divide="ignore", invalid="ignore"):
            s = drive / denom
        scale = Dual(np.where(appr, s.value, 0.0) * nan,
                     np.where(appr[..., None], s.grad, 0.0) * nan[..., None])
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(appr, drive / denom, 0.0) * nan
    out = formula.post_impact(scale, pn0, pt0, b, cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1,
                              a2, b2, r2x, r2y, v2x, v2y, w2)
    if not jacobian:
        return np.stack([np.broadcast_to(o, shape) for o in out], axis=-1), None
    values = np.stack([np.broadcast_to(o.value, shape) for o in out], axis=-1)
    jac = np.stack([np.broadcast_to(o.grad, shape + (k,)) for o in out], axis=-2)
    return values, jac
