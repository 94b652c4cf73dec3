"""The assumption ladder's "one impact" rung: the whole event against PIM's single impact.

PIM models one impact. The rung relaxes exactly that assumption and nothing else: the same
case, the same first impact (PIM at the ladder's eps and beta), the same tyres (the case's
evidence, else :data:`pim.model.event.DEFAULT_TYRE_FRICTION`), run to rest once with the
outlines watched and every further impact solved (:func:`pim.event`) and once without
(``single_impact=True``, PIM's single impact followed by the run-out). What differs is in
the ladder's physical units: the rest positions [m] and headings [rad], and the motion after
the event's last impact against PIM's post-impact motion (the ladder's measures: the length
of the velocities' difference [m/s] and the yaw rates' [rad/s] per vehicle). A case whose event has one impact gets zeros: the assumption
holds for it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import pim

__all__ = ["OneImpactRung", "one_impact_rung"]


@dataclass(frozen=True)
class OneImpactRung:
    """The "one impact" rung of a case (SI).

    Attributes
    ----------
    impacts : int
        Impacts of the whole event (1: PIM's single impact is the whole story).
    further_time : float
        Time of the second impact after the first [s] (NaN without).
    rest_position : ndarray (2,)
        Distance between the event's and the single impact's rest positions per vehicle [m]
        (NaN for a fixed barrier).
    rest_heading : ndarray (2,)
        Absolute difference of the rest headings per vehicle [rad].
    post_delta_v : ndarray (2,)
        Per vehicle, the length of the difference between its velocity after the event's
        last impact and PIM's post-impact velocity [m/s] (NaN for a fixed barrier).
    post_yaw_rate : ndarray (2,)
        The same of the yaw rates [rad/s].
    tyre_friction : float or None
        The tyre friction both runs used (None: the case's evidence or the default).
    refused : str
        Why the event was refused (a contact without end, an impact that would gain
        energy), the other fields then NaN; empty when it ran.
    """

    impacts: int
    further_time: float
    rest_position: np.ndarray
    rest_heading: np.ndarray
    post_delta_v: np.ndarray
    post_yaw_rate: np.ndarray
    tyre_friction: float | None
    refused: str = ""

    @property
    def holds(self) -> bool:
        """True when the event has PIM's single impact only."""
        return self.impacts == 1


def one_impact_rung(case: pim.Case, eps: float | None = None, beta: float | None = None, *,
                    tyre_friction: float | None = None) -> OneImpactRung:
    """The event with its further impacts against PIM's single impact (module notes).

    Parameters
    ----------
    case : pim.Case
        A single case with both outlines.
    eps, beta : float, optional
        The first impact's coefficients (the ladder's; default the case's).
    tyre_friction : float, optional
        As :func:`pim.event`.
    """
    try:
        whole = pim.event(case, eps=eps, beta=beta, tyre_friction=tyre_friction, approach=0.0)
    except pim.InputError as exc:       # the event refused: the rung is not assessed
        nan = np.full(2, math.nan)
        return OneImpactRung(impacts=0, further_time=math.nan, rest_position=nan,
                             rest_heading=nan, post_delta_v=nan, post_yaw_rate=nan,
                             tyre_friction=tyre_friction, refused=str(exc))
    single = pim.event(case, eps=eps, beta=beta, tyre_friction=tyre_friction, approach=0.0,
                       single_impact=True)
    fixed = bool(case.vehicle2.fixed)
    dist = np.hypot(*(whole.rest_position - single.rest_position).T)
    if fixed:
        dist[1] = math.nan
    first, last = whole.impacts[0], whole.impacts[-1]

    def change_of(a, b, i):
        if fixed and i == 1:
            return math.nan, math.nan
        return (float(np.hypot(*(a.velocity_after[i] - b.velocity_after[i]))),
                abs(float(a.yaw_rate_after[i] - b.yaw_rate_after[i])))

    (dv1, w1), (dv2, w2) = change_of(last, first, 0), change_of(last, first, 1)
    return OneImpactRung(
        impacts=len(whole.impacts),
        further_time=whole.impacts[1].time if len(whole.impacts) > 1 else math.nan,
        rest_position=dist, rest_heading=np.abs(whole.rest_heading - single.rest_heading),
        post_delta_v=np.array([dv1, dv2]), post_yaw_rate=np.array([w1, w2]),
        tyre_friction=tyre_friction)
