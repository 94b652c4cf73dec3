"""Why the engine cannot reproduce a PIM answer, decided before or without simulating.

Chipmunk's contact is Newton restitution plus Coulomb friction solved by sequential
impulses. PIM's beta-parametrised impulse ratio is not always a Coulomb law, and the
sequential impulses do not always converge; :func:`limitations` names those cases so that a
cross-check can tell a model difference from a simulator bug.
"""

from __future__ import annotations

import numpy as np

import pim
from pim.model.numbers import speed_text

from .convergence import contraction_rate
from .scene import STICK_MARGIN

__all__ = ["limitations"]


def _f(x) -> float:
    return float(np.asarray(x).reshape(()))


def limitations(case: pim.Case, eps: float, beta: float) -> list[str]:
    """Plain-language reasons why the simulator cannot match ``pim.solve(case, eps, beta)``.

    Parameters
    ----------
    case : pim.Case
        A single case.
    eps, beta : float
        Restitution [-] and fraction of mu0 [-].

    Returns
    -------
    list of str
        Empty when the engine can reproduce PIM (then the default settings agree to
        relative 1e-6). Reasons:

        * beta outside [0, 1] (Coulomb friction can neither reverse sliding nor exceed
          the sticking ratio);
        * PIM inadmissible (no approach, pulling normal impulse, energy gain, singular q);
        * sliding (beta < 1) with PIM's tangential impulse pointing *along* the remaining
          sliding at C (Pt U_t > 0): Coulomb friction always opposes the sliding, so the
          engine's impulse ratio is -mu there;
        * sliding with |mu K_nt| >= K_nn: the sequential impulses diverge
          (:mod:`sim.convergence`).
    """
    out = []
    if not 0.0 <= beta <= 1.0:
        out.append(f"beta = {beta:g} is outside [0, 1]: Coulomb friction cannot give it")
        return out
    result = pim.solve(case, eps, beta, law="brach")
    out += [f"PIM: {text}" for text in result.problems()]
    if out or beta >= 1.0:
        return out
    p_t, u_t = _f(result.impulse_t), _f(result.separation_t)
    scale = max(abs(_f(result.approach_n)), abs(_f(result.approach_t)), 1e-300)
    if p_t * u_t > 0 and abs(u_t) > 1e-9 * scale:
        out.append(f"PIM's tangential impulse (mu = beta mu0 = {_f(result.mu):.4g}) points "
                   f"along the remaining sliding at C (U_t = {speed_text(u_t)}): Coulomb "
                   f"friction opposes sliding, so the engine cannot reproduce it")
    mu0 = abs(_f(result.mu0))
    friction = max(STICK_MARGIN * mu0, 1.0) if beta >= 1.0 else beta * mu0
    rho = contraction_rate(_f(result.k_nn), _f(result.k_nt), _f(result.k_tt), friction, False)
    if rho >= 1.0:
        out.append(f"sliding with |mu K_nt| / K_nn = {rho:.4g} >= 1: Chipmunk's sequential "
                   f"impulses diverge, so the engine cannot converge to PIM's impulse")
    return out
