"""Plausibility warnings: inputs and answers that are admissible but probably not meant.

PIM's admissibility flags (:meth:`pim.Result.problems`) say when an answer breaks the
model's own physics. These warnings are softer: an answer may be physically admissible and
still ask more of the contact than vehicle sheet metal can give, or come from an input that
was probably mistyped.
"""

from __future__ import annotations

import numpy as np

from .result import Result

__all__ = ["plausibility_warnings", "no_impact_message", "bare_angle_warning", "warnings_of"]

#: Largest |mu0| at beta = 1 taken as plausible: above it the sticking impulse would need a
#: tangential impulse larger than the normal one, a friction coefficient above 1.
PLAUSIBLE_MU0 = 1.0


def bare_angle_warning(field: str, value) -> str | None:
    """A warning when a non-zero bare number is given for an angle: it reads as radians,
    which a reader may not expect (the case file refuses bare angles beyond 2 pi)."""
    if isinstance(value, bool) or not isinstance(value, int | float) or value == 0:
        return None
    return (f"{field} = {value} has no unit and is read as {value} rad "
            f"({np.degrees(value):.4g} deg); write \"{np.degrees(value):.4g} deg\" or "
            f"\"{value} rad\" to say so")


def no_impact_message(result: Result, speed_unit: str = "m/s",
                      speed_scale: float = 1.0) -> str | None:
    """"no impact: ..." when the vehicles do not approach at C (a single case), else None.

    The approach velocity u_n [m/s] is printed times ``speed_scale`` in ``speed_unit`` (the
    case's units, converted at the edge), with a hint for the commonest cause, a normal
    drawn the wrong way round.
    """
    if bool(np.all(result.approaching)):
        return None
    u_n = float(np.max(result.approach_n)) * speed_scale
    gamma = float(np.degrees(np.max(result.case.impact.normal_angle)))
    hint = (f"; n = (cos Gamma, sin Gamma) must point from vehicle 2 toward vehicle 1 "
            f"(impact.normal_angle = {gamma:.4g} deg): if the vehicles do collide, "
            f"the normal may be flipped (try {(gamma + 180) % 360:.4g} deg)")
    if u_n > 0:
        return f"no impact: the vehicles separate at C (u_n = {u_n:.4g} {speed_unit} > 0){hint}"
    return f"no impact: the vehicles do not approach at C (u_n = 0){hint}"


def plausibility_warnings(result: Result, friction_limit: float | None = None) -> list[str]:
    """Warnings for a single solved case: friction beyond a limit, implausible grazing.

    Parameters
    ----------
    result : Result
        A solved case (size 1).
    friction_limit : float, optional
        Largest plausible |mu| [-] (None: no limit checked).

    Returns
    -------
    list of str
        Empty when nothing looks implausible.
    """
    out = []
    mu = float(np.asarray(result.mu).reshape(()))
    mu0 = float(np.asarray(result.mu0).reshape(()))
    beta = float(np.asarray(result.beta).reshape(()))
    if friction_limit is not None and np.isfinite(mu) and abs(mu) > friction_limit:
        out.append(f"|mu| = {abs(mu):.3g} exceeds the friction limit {friction_limit:g}: the "
                   f"contact would have to transmit more tangential impulse than friction "
                   f"allows (--cap-friction caps it)")
    if beta == 1.0 and np.isfinite(mu0) and abs(mu0) > PLAUSIBLE_MU0:
        out.append(f"|mu0| = {abs(mu0):.3g} > {PLAUSIBLE_MU0:g} at beta = 1: stopping the "
                   f"sliding at C needs more tangential than normal impulse, implausible "
                   f"friction for a grazing impact (try beta < 1 or --friction-limit)")
    return out


def warnings_of(case, result, friction_limit=None) -> list[str]:
    """Every warning a command or report prints: the case file's notes, the answer's
    admissibility problems and the plausibility warnings."""
    return [*case.notes, *result.problems(), *plausibility_warnings(result, friction_limit)]
