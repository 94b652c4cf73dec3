"""Test oracle: the linear single-track ("bicycle") model, in closed form.

Independent of the project's four-wheel run-out (no tyre law, no load transfer, no track):
two axles with linear cornering stiffnesses at constant forward speed ``u``, small angles.
Body-frame lateral velocity ``v`` and yaw rate ``r`` (Gillespie, *Fundamentals of Vehicle
Dynamics*, 1992, ch. 6; Rajamani, *Vehicle Dynamics and Control*, 2nd ed., 2012, sec. 2.3):

    m (dv/dt + u r) = F_f + F_r,        I dr/dt = a F_f - b F_r,
    F_f = C_f (delta - (v + a r) / u),  F_r = -C_r (v - b r) / u,

``C_f``, ``C_r`` per axle [N/rad], ``a``, ``b`` CG to front / rear axle. As ``x' = A x + B
delta``, the response to a ramp ``delta = t`` from rest is, exactly,

    x(t) = A^-2 (e^(A t) - I) B - A^-1 B t,

and a piecewise-linear steer table is a sum of such ramps (superposition), so the response to
any driver table is closed-form (matrix exponentials, no integrator). Steady state: yaw-rate
gain ``r / delta = u / (L + K u^2)`` with the understeer gradient
``K = m / L (b / C_f - a / C_r)`` [rad s^2/m] (Gillespie eq. 6-15).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm


def matrices(mass, yaw_inertia, cg_to_front, wheelbase, c_front, c_rear, speed):
    """``(A, B)`` of the linear bicycle model, state ``(v [m/s], r [rad/s])``, input
    ``delta`` [rad]; ``c_front``, ``c_rear`` per axle [N/rad]."""
    a, b, u = cg_to_front, wheelbase - cg_to_front, speed
    A = np.array([[-(c_front + c_rear) / (mass * u), (b * c_rear - a * c_front) / (mass * u) - u],
                  [(b * c_rear - a * c_front) / (yaw_inertia * u),
                   -(a * a * c_front + b * b * c_rear) / (yaw_inertia * u)]])
    B = np.array([c_front / mass, a * c_front / yaw_inertia])
    return A, B


def ramp_response(A, B, t) -> np.ndarray:
    """State (len(t), 2) after a unit ramp ``delta = t`` from rest (zero for ``t <= 0``);
    ``e^(A t) B`` through A's eigenvectors (checked against ``scipy.linalg.expm``)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    inv = np.linalg.inv(A)
    values, vectors = np.linalg.eig(A)
    modal = np.linalg.solve(vectors, B)
    tau = np.maximum(t, 0.0)
    exp_b = np.real((np.exp(np.outer(tau, values)) * modal) @ vectors.T)    # e^(A t) B
    return (exp_b - B) @ (inv @ inv).T - np.outer(tau, inv @ B)


def table_response(A, B, times, steer, t) -> np.ndarray:
    """State (len(t), 2) under a piecewise-linear steer table (held beyond its ends,
    starting from rest at ``steer[0] = 0``): the sum of the ramps where the slope changes."""
    times, steer = np.asarray(times, dtype=float), np.asarray(steer, dtype=float)
    if steer[0] != 0:
        raise ValueError("table_response: the table must start from zero steer")
    slopes = np.diff(steer) / np.diff(times)
    changes = np.diff(np.concatenate([[0.0], slopes, [0.0]]))
    t = np.asarray(t, dtype=float)
    return sum(c * ramp_response(A, B, t - t0) for c, t0 in zip(changes, times, strict=True)
               if c != 0)


def ramp_response_expm(A, B, t) -> np.ndarray:
    """:func:`ramp_response` by ``scipy.linalg.expm`` at each time (the slow reference)."""
    inv = np.linalg.inv(A)
    out = np.zeros((np.size(t), 2))
    for i, ti in enumerate(np.atleast_1d(t)):
        if ti > 0:
            out[i] = inv @ inv @ (expm(A * ti) - np.eye(2)) @ B - inv @ B * ti
    return out


def understeer_gradient(mass, cg_to_front, wheelbase, c_front, c_rear) -> float:
    """``K = m / L (b / C_f - a / C_r)`` [rad s^2/m], ``C`` per axle (Gillespie eq. 6-15)."""
    b = wheelbase - cg_to_front
    return mass / wheelbase * (b / c_front - cg_to_front / c_rear)


def yaw_rate_gain(mass, cg_to_front, wheelbase, c_front, c_rear, speed) -> float:
    """Steady-state ``r / delta = u / (L + K u^2)`` [1/s]."""
    k = understeer_gradient(mass, cg_to_front, wheelbase, c_front, c_rear)
    return speed / (wheelbase + k * speed * speed)
