"""Forward-mode automatic differentiation of the one formula (:mod:`pim.model.formula`).

A :class:`Dual` carries a value and its gradient with respect to k seeded inputs; the
formula, being plain arithmetic, runs on duals unchanged and so gives exact derivatives (to
round-off, no step size) of every output with respect to any input. :func:`motion_jacobian`
differentiates the post-impact motion of a case with respect to epsilon, beta, Gamma, C and
the pre-impact velocities and yaw rates. The hand-derived derivatives in
:mod:`pim.analysis.derivatives` are tested against it.
"""

from __future__ import annotations

import numpy as np

from . import formula
from .case import Case

__all__ = ["Dual", "motion_jacobian", "MOTION_OUTPUTS", "MOTION_INPUTS"]


class Dual:
    """A number (or array) with its gradient: ``value`` shape S, ``grad`` shape S + (k,)."""

    __slots__ = ("value", "grad")
    __array_ufunc__ = None   # numpy arrays and scalars defer to the reflected operators below

    def __init__(self, value, grad) -> None:
        self.value = np.asarray(value, dtype=float)
        self.grad = np.asarray(grad, dtype=float)

    @staticmethod
    def _split(x):
        if isinstance(x, Dual):
            return x.value, x.grad
        return np.asarray(x, dtype=float), 0.0

    def __add__(self, other):
        v, g = self._split(other)
        return Dual(self.value + v, self.grad + g)

    __radd__ = __add__

    def __sub__(self, other):
        v, g = self._split(other)
        return Dual(self.value - v, self.grad - g)

    def __rsub__(self, other):
        v, g = self._split(other)
        return Dual(v - self.value, g - self.grad)

    def __mul__(self, other):
        v, g = self._split(other)
        return Dual(self.value * v, self.grad * v[..., None] + self.value[..., None] * g)

    __rmul__ = __mul__

    def __truediv__(self, other):
        v, g = self._split(other)
        q = self.value / v
        return Dual(q, (self.grad - q[..., None] * g) / v[..., None])

    def __rtruediv__(self, other):
        v, g = self._split(other)
        q = v / self.value
        return Dual(q, (g - q[..., None] * self.grad) / self.value[..., None])

    def __neg__(self):
        return Dual(-self.value, -self.grad)

    def __abs__(self):
        return Dual(np.abs(self.value), np.sign(self.value)[..., None] * self.grad)

    # comparisons act on the values (the branch flags of the formula)
    def __lt__(self, other):
        return self.value < self._split(other)[0]

    def __le__(self, other):
        return self.value <= self._split(other)[0]

    def __gt__(self, other):
        return self.value > self._split(other)[0]

    def __ge__(self, other):
        return self.value >= self._split(other)[0]


#: Inputs :func:`motion_jacobian` differentiates with respect to, in column order [SI].
MOTION_INPUTS = ("impact.restitution", "impact.beta", "impact.normal_angle", "impact.point_x",
                 "impact.point_y", "vehicle1.velocity_x", "vehicle1.velocity_y",
                 "vehicle1.yaw_rate", "vehicle2.velocity_x", "vehicle2.velocity_y",
                 "vehicle2.yaw_rate")
#: Outputs of :func:`motion_jacobian`, in row order [SI].
MOTION_OUTPUTS = ("impulse_n", "impulse_t", "impulse_x", "impulse_y", "velocity1_x",
                  "velocity1_y", "velocity2_x", "velocity2_y", "yaw_rate1", "yaw_rate2")


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
    jacobian : ndarray, shape S + (10, 11)
        d output / d input for the inputs of :data:`MOTION_INPUTS` [SI per SI]; zero where
        the vehicles do not approach, NaN where q is singular.

    Notes
    -----
    Gamma enters through its sine and cosine, seeded with their derivatives (cos, -sin).
    """
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    eps, beta = np.asarray(eps, float), np.asarray(beta, float)
    shape = np.broadcast_shapes(case.shape, eps.shape, beta.shape)
    k = len(MOTION_INPUTS)

    def seed(value, index):
        value = np.broadcast_to(np.asarray(value, float), shape)
        grad = np.zeros(shape + (k,))
        grad[..., index] = 1.0
        return Dual(value, grad)

    gamma = np.broadcast_to(imp.normal_angle, shape)
    cs_grad = np.zeros(shape + (k,))
    sn_grad = np.zeros(shape + (k,))
    cs_grad[..., 2] = -np.sin(gamma)
    sn_grad[..., 2] = np.cos(gamma)
    cs, sn = Dual(np.cos(gamma), cs_grad), Dual(np.sin(gamma), sn_grad)
    px, py = seed(imp.point[..., 0], 3), seed(imp.point[..., 1], 4)
    r1x, r1y = px - v1.cg[..., 0], py - v1.cg[..., 1]
    r2x, r2y = px - v2.cg[..., 0], py - v2.cg[..., 1]
    v1x, v1y, w1 = seed(v1.velocity[..., 0], 5), seed(v1.velocity[..., 1], 6), seed(v1.yaw_rate, 7)
    v2x, v2y, w2 = seed(v2.velocity[..., 0], 8), seed(v2.velocity[..., 1], 9), seed(v2.yaw_rate, 10)
    e, b = seed(eps, 0), seed(beta, 1)
    a1, b1 = v1.inverse_mass, v1.inverse_inertia
    a2, b2 = v2.inverse_mass, v2.inverse_inertia
    (_, _, _, _, _, _, _, pn0, pt0, drive, denom, appr, sing) = formula.contact(
        cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2, e, b,
        approach_tol, singular_tol)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = drive / denom
    nan = np.where(sing, np.nan, 1.0)
    scale = Dual(np.where(appr, s.value, 0.0) * nan,
                 np.where(appr[..., None], s.grad, 0.0) * nan[..., None])
    out = formula.post_impact(scale, pn0, pt0, b, cs, sn, a1, b1, r1x, r1y, v1x, v1y, w1,
                              a2, b2, r2x, r2y, v2x, v2y, w2)
    values = np.stack([np.broadcast_to(o.value, shape) for o in out], axis=-1)
    jac = np.stack([np.broadcast_to(o.grad, shape + (k,)) for o in out], axis=-2)
    return values, jac
