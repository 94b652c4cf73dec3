"""How fast Chipmunk's sequential impulses converge on one contact, and how many to run.

Chipmunk solves a contact by Gauss-Seidel sweeps: in each sweep it sets the normal impulse
so that the normal row meets its Newton target, then the tangential impulse so that the
tangential row does (clamped to the friction cone). On PIM's single contact with the
effective inverse-mass matrix K (n-t components, :func:`pim.model.solver.effective_mass_matrix`):

* sticking (beta = 1, clamp inactive): plain Gauss-Seidel on the 2x2 system; its iteration
  matrix has the eigenvalue rho = K_nt^2 / (K_nn K_tt) < 1, so the error shrinks like rho^N;
* sliding (beta < 1, clamp active, Pt = +-u Pn): each sweep maps the normal-impulse error
  e -> -(u K_nt / K_nn) e, so rho = |u K_nt| / K_nn. When rho >= 1 -- the tangential
  impulse changes the normal velocity more than the normal impulse itself -- the sweeps
  diverge and the engine cannot reproduce PIM's sliding impulse at any iteration count.

Measured on random scenes (benchmarks/bench_sim.py), the velocity error after N sweeps is
below rho^(N/2) in both regimes; :func:`auto_iterations` uses that bound.
"""

from __future__ import annotations

import math

__all__ = ["contraction_rate", "auto_iterations", "MIN_ITERATIONS", "MAX_ITERATIONS",
           "TARGET_ERROR"]

#: Fewest and most sweeps :func:`auto_iterations` returns.
MIN_ITERATIONS, MAX_ITERATIONS = 20, 20_000
#: Relative error the automatic iteration count aims at (round-off is about 1e-15).
TARGET_ERROR = 1e-13


def contraction_rate(k_nn: float, k_nt: float, k_tt: float, friction: float,
                     sticking: bool) -> float:
    """Error reduction factor rho [-] of one Chipmunk sweep on a single contact.

    Parameters
    ----------
    k_nn, k_nt, k_tt : float
        Effective inverse-mass matrix of the contact [1/kg].
    friction : float
        Coulomb coefficient u of the contact [-].
    sticking : bool
        True for a sticking contact (beta = 1), False for sliding (beta < 1).

    Returns
    -------
    float
        rho = K_nt^2 / (K_nn K_tt) when sticking, |u K_nt| / K_nn when sliding.
    """
    if sticking:
        return k_nt * k_nt / (k_nn * k_tt)
    return abs(friction * k_nt) / k_nn


def auto_iterations(rho: float) -> int:
    """Sweeps that bring the error bound rho^(N/2) below :data:`TARGET_ERROR`.

    Clipped to [MIN_ITERATIONS, MAX_ITERATIONS]; a diverging contact (rho >= 1) gets the
    minimum (more sweeps would not help; the run's convergence check reports it).
    """
    if not (rho > 0.0):
        return MIN_ITERATIONS
    if rho >= 1.0:
        return MIN_ITERATIONS
    n = math.ceil(2.0 * math.log(TARGET_ERROR) / math.log(rho))
    return int(min(max(n, MIN_ITERATIONS), MAX_ITERATIONS))
