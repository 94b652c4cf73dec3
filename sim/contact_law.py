"""The finite-duration contact law: bilinear crush hysteresis and elastoplastic friction.

Pure, vectorised functions (numpy broadcasting, no state, no I/O) shared by the pymunk
stepping of :mod:`sim.compliant`, the compiled batch integrator of
:mod:`sim.compliant_kernel` and the independent ``solve_ivp`` integration of
:mod:`sim.reference`: they *are* the model under test, the integrators are not. The law
itself is written once, on floats, in :mod:`sim.compliant_formula`; the functions here
evaluate it element by element over broadcasting arrays.

Normal crush force (docs/contact-model.md)
------------------------------------------
Loading (delta >= delta_max, the largest crush so far), Campbell's per-width form times the
contact width w, or a plain linear spring (a = 0, b = k):

    F_L(delta) = a + b delta,        a = A w [N],  b = B w [N/m]   (k = b when a = 0)

Unloading and reloading below delta_max run along a straight line of slope s from the peak
(delta_max, F_max = F_L(delta_max)) down to the permanent crush delta_p:

    F_U(delta) = F_max + s (delta - delta_max)   for delta > delta_p,  0 below,
    s = F_max^2 / (2 eps^2 E_L),  E_L = a delta_max + b delta_max^2 / 2,
    delta_p = delta_max - F_max / s.

The unloading line returns eps^2 of the loading work, so a point mass rebounds with
exactly epsilon times its approach speed. For the linear spring s = k / eps^2 and
delta_p = delta_max (1 - eps^2), the bilinear model of the issue. epsilon = 0: no
rebound (s infinite, F = 0 as soon as delta < delta_max).

Tangential force
----------------
Coulomb friction mu_c |F_n| against the slip, regularised by a tangential spring of
stiffness k_t (an elastoplastic, "bristle" model): the elastic tangential displacement z
follows the slip while |k_t z| < mu_c F_n (sticking: the contact stores tangential
energy and gives back the share r of it, below), and is held on the Coulomb
cone |z| <= z_max = mu_c F_n / k_t while the slip pushes outward (sliding: the force is
mu_c F_n against the elastic displacement). The force is F_t = -k_t z. In continuous
time z obeys the sweeping process

    dz/dt = v_t                                if |z| < z_max or z v_t <= 0  (r = 1),
    dz/dt = sign(z) min(|v_t|, dz_max/dt)      on the cone, pushed outward,

(and follows a shrinking cone; :mod:`sim.reference` integrates it as sticking and sliding
modes with events); its implicit ("catching-up") step is
z_{n+1} = clip(z_n + v_t dt, -z_max,n+1, z_max,n+1), which the fixed-step integrator uses.

Tangential recovery
-------------------
How much of the stored tangential energy the contact gives back is a physical parameter,
the tangential recovery r in [0, 1]. While |z| grows (loading) z follows the slip at rate
v_t; while it shrinks (the slip has turned back, unloading) it follows at v_t / r, so the
force falls along a line of slope k_t / r and the contact returns r k_t z^2 / 2 of the
k_t z^2 / 2 it stored (the tangential analogue of the crush's unloading line, which returns
eps^2 of the loading work). Past z = 0 the rest of the slip loads the other way at v_t.

    dz/dt = v_t          if z v_t >= 0 (loading),
    dz/dt = v_t / r      if z v_t < 0 (unloading; r = 0: z drops to 0 at once),

inside the cone. r = 1 is the elastic spring (Maw, Barber and Fawcett), r = 0 a plastic
tangential crush that gives nothing back; :data:`tangential_recovery_default` ties it to
the restitution, r = eps^2 (docs/contact-model.md has the source).
"""

from __future__ import annotations

import math

import numpy as np

from pim.model.numbers import InputError

from . import compliant_formula as formula

__all__ = ["check_positive", "check_fraction", "loading_force", "loading_work",
           "unloading_slope", "permanent_crush", "normal_force", "normal_stiffness",
           "tangential_step", "tangential_force", "tangential_recovery_default",
           "contact_frequency",
           "contact_duration_estimate", "stiffness_for_duration"]


def _number(value):
    """A 0-d numeric numpy array as its scalar (``np.array(7.5e5)`` is one number)."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        return value[()]
    return value


def check_positive(value, name: str, unit: str, allow_zero: bool = False) -> float:
    """``value`` as a float, or a ValueError naming ``name`` and the allowed range.

    Accepts Python and numpy numbers and 0-d numeric arrays; rejects NaN, infinities,
    booleans, strings, other arrays and values <= 0 (< 0 with ``allow_zero``).
    """
    value = _number(value)
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise InputError(f"{name} must be a number [{unit}], got {value!r}")
    value = float(value)
    ok = math.isfinite(value) and (value >= 0 if allow_zero else value > 0)
    if not ok:
        bound = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be a finite number {bound} [{unit}], got {value!r}")
    return value


def check_fraction(value, name: str) -> float:
    """``value`` as a float in [0, 1], or a ValueError naming ``name`` (numbers and 0-d
    numeric arrays, as :func:`check_positive`)."""
    value = _number(value)
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise InputError(f"{name} must be a number in [0, 1], got {value!r}")
    value = float(value)
    if not (math.isfinite(value) and 0.0 <= value <= 1.0):
        raise InputError(f"{name} must be in [0, 1], got {value!r}")
    return value


def _on_arrays(scalar, name: str):
    """:mod:`sim.compliant_formula`'s ``scalar`` law evaluated element by element over
    broadcasting arrays (the one source, for the callers that hold arrays)."""
    vectorised = np.vectorize(scalar, otypes=[float])

    def law(*args):
        return vectorised(*args)

    law.__name__ = law.__qualname__ = name
    law.__doc__ = scalar.__doc__
    return law


#: Crush force on the loading curve F_L = a + b delta [N] (0 for delta <= 0); arguments
#: delta [m], a [N] (Campbell's A times the contact width; 0 for a linear spring), b [N/m].
loading_force = _on_arrays(formula.loading_force, "loading_force")
#: Work done along the loading curve up to ``delta_max``: a d + b d^2 / 2 [J].
loading_work = _on_arrays(formula.loading_work, "loading_work")
#: Slope s [N/m] of the unloading line from the peak, s = F_max^2 / (2 eps^2 E_L); infinite
#: for eps = 0 (no rebound) or before any crush (delta_max = 0).
unloading_slope = _on_arrays(formula.unloading_slope, "unloading_slope")
#: Permanent (residual) crush delta_p = delta_max - F_max / s [m]; linear spring:
#: delta_max (1 - eps^2).
permanent_crush = _on_arrays(formula.permanent_crush, "permanent_crush")
#: Normal crush force F_n [N] >= 0 of the bilinear hysteresis, arguments (delta [m],
#: delta_max [m] (loading when delta >= delta_max), eps [-], a [N], b [N/m]): F_L(delta) on
#: loading, F_max + s (delta - delta_max) clipped at 0 on unloading, 0 for delta <= 0.
normal_force = _on_arrays(formula.normal_force, "normal_force")
#: dF_n/d delta [N/m] of :func:`normal_force` (b on loading, s unloading, 0 apart).
normal_stiffness = _on_arrays(formula.normal_stiffness, "normal_stiffness")
_tangential_step = _on_arrays(formula.tangential_step, "tangential_step")
#: Tangential force F_t = -k_t z [N], clipped to the Coulomb limit mu_c F_n (arguments z
#: [m], k_t [N/m], limit [N]).
tangential_force = _on_arrays(formula.tangential_force, "tangential_force")


def tangential_step(z, slip, dt, z_max, recovery=1.0):
    """One implicit step of the elastoplastic tangential spring [m].

    z_{n+1} = clip(z_n + dz, -z_max, z_max) with z_max = mu_c F_n / k_t at the new state:
    sticking while inside the cone, sliding (and following a shrinking cone) on it. The
    slip v_t dt loads the spring (dz = v_t dt) while it pushes |z| outward and unloads it at
    1 / r the rate while it pulls |z| back to 0 (module notes, "Tangential recovery"); the
    slip left over past z = 0 loads the other way (:func:`sim.compliant_formula.tangential_step`).

    Parameters
    ----------
    z : array_like
        Elastic tangential displacement [m].
    slip : array_like
        Tangential relative velocity v_t [m/s].
    dt : float
        Step [s].
    z_max : array_like
        Cone radius mu_c F_n / k_t [m].
    recovery : array_like
        Tangential recovery r [-] in [0, 1] (1: elastic, today's spring; 0: plastic).
    """
    return _tangential_step(z, slip, dt, z_max, recovery)


def tangential_recovery_default(eps):
    """The default tangential recovery r = eps^2 [-]: the contact gives back the same share
    of its stored tangential energy as the crush gives back of its loading work (Stronge's
    energetic restitution, docs/contact-model.md)."""
    eps = np.asarray(eps, float)
    return eps * eps      # not ** 2: numpy's power of a 0-d array can differ by an ulp


def contact_frequency(k, k_nn):
    """Natural circular frequency sqrt(k K_nn) [rad/s] of the contact on the loading spring.

    Parameters
    ----------
    k : array_like
        Loading stiffness [N/m].
    k_nn : array_like
        Normal-normal entry of the contact's effective inverse mass matrix K [1/kg]
        (1/m1 + 1/m2 + (n x r1)^2/I1 + (n x r2)^2/I2; ``pim.Result.k_nn``).
    """
    return np.sqrt(np.asarray(k, float) * np.asarray(k_nn, float))


def contact_duration_estimate(k, k_nn, eps):
    """Contact duration [s] of the linear law for a frictionless point contact.

    A quarter period pi / (2 omega) loading and a quarter period eps pi / (2 omega) of the
    stiffer unloading spring (frequency omega / eps): T = pi (1 + eps) / (2 omega).
    """
    return 0.5 * np.pi * (1.0 + np.asarray(eps, float)) / contact_frequency(k, k_nn)


def stiffness_for_duration(duration, k_nn, eps):
    """The linear stiffness k [N/m] whose frictionless contact lasts ``duration`` [s].

    Inverse of :func:`contact_duration_estimate`: k = (pi (1 + eps) / (2 T))^2 / K_nn.
    """
    duration = np.asarray(duration, float)
    if np.any(~np.isfinite(duration)) or np.any(duration <= 0):
        raise InputError(f"duration must be a finite number > 0 [s], got {duration!r}")
    rate = 0.5 * np.pi * (1.0 + np.asarray(eps, float)) / duration
    return rate * rate / np.asarray(k_nn, float)    # not ** 2 (as tangential_recovery_default)
