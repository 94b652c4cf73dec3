"""The event's contact geometry and secondary impact, written once.

The analytic event (:mod:`pim.analysis.event`) watches the two vehicles' rectangular
outlines during the run-out and, at a new contact that is closing, solves a further impact.
The functions here hold that arithmetic on numbers (floats, ``numpy`` scalar functions and
conditionals only), so Python evaluates them for one event and numba compiles the very same
functions into the event kernel (:mod:`pim.model.event_kernel`), as
:mod:`pim.model.formula` is for PIM and :mod:`pim.model.runout_formula` for the run-out.

An outline travels as a ``box`` tuple ``(cx, cy, c, s, hx, hy)``: the rectangle's centre
[m], the cosine and sine of its heading [-] and its half-length and half-width [m]
(:func:`box`).

**The contact rule** (:func:`contact_geometry`), that of rigid polygon contact (the
separating-axis test with a reference face, as Box2D and pymunk's polygon contact, Catto
2007; Ericson, *Real-Time Collision Detection*, 2005, sec. 4.4):

- the overlap depth is the least overlap of the two rectangles' projections over their four
  edge normals (the separating-axis test, :func:`pim.model.geometry.outline_penetration`);
- Gamma is the normal of the penetrated edge: the edge normal of least overlap, pointing
  from vehicle 2 toward vehicle 1 (PIM's convention);
- C is the centroid of the corners of either outline that lie inside the other: the
  penetrating corner in the usual corner-into-edge contact, the middle of the shared
  stretch when two edges meet flat (a side slap of parallel sides); the deepest corner along
  the normal when no corner lies inside (two edges crossing).

The contact is new when the depth grows by more than a tolerance above its least value
since the last impact (the outlines of a case may overlap at PIM's impact configuration by
the crush, and part), and it is solved when C closes (``u_n < 0``).

**The secondary impact** (:func:`capped_impact`): PIM's formula (:mod:`pim.model.formula`)
at C and Gamma with restitution ``eps`` and ``mu = sign(mu0) min(beta |mu0|, cap)``: the
friction-capped Brach law of :mod:`pim.model.friction_cap` ("brach-capped"; ``cap = inf``
is Brach's own law), which carries the same two coefficients (restitution and a Coulomb
cap on the inter-vehicle friction) as pymunk's polygon contact.
"""

from __future__ import annotations

import numpy as np

from .formula import contact, post_impact

#: Fixed step of the event's run-out [s] (the run-out's,
#: :data:`pim.model.runout_kernel.RUNOUT_STEP`).
EVENT_STEP = 0.004
#: Most impacts after the first one an event may have; more is a contact without end
#: (refused: status "impacts").
MAX_IMPACTS = 12
#: Growth of the overlap depth [m] above its least value since the last impact that makes a
#: new contact (and the most a sample may penetrate beyond it, to the bisection's 1 us).
CONTACT_TOLERANCE = 0.01
#: Largest fraction of the smallest outline dimension that any outline point may move
#: toward the other vehicle in one step while their bounding circles overlap.
TUNNEL_FRACTION = 0.25
#: Smallest step of the contact bisection [s].
BISECTION_STEP = 1e-6

#: The law of an impact found by the outlines where the case states none: the friction-capped
#: Brach law, whose two coefficients mean what pymunk's polygon contact's elasticity and
#: friction mean (docs/event.md).
SECONDARY_LAW = "brach-capped"
#: Its restitution [-]: low-speed vehicle contacts restitute 0.1-0.3 of the closing speed
#: (Brach & Brach 2011, ch. 6: restitution falls with the closing speed, toward 0.1-0.2 at
#: 30-50 km/h); side slaps and re-contacts close slowly, so the lower end.
SECONDARY_RESTITUTION = 0.1
#: Its fraction of mu0 [-]: 1, the contact sticks where the cap allows.
SECONDARY_BETA = 1.0
#: Its cap on |Pt / Pn| [-]: sheet metal sliding on sheet metal (steel on steel, dry,
#: 0.4-0.6; Brach & Brach 2011 take 0.5 for vehicle-to-vehicle sliding).
SECONDARY_CONTACT_FRICTION = 0.5

__all__ = ["EVENT_STEP", "MAX_IMPACTS", "CONTACT_TOLERANCE", "TUNNEL_FRACTION",
           "BISECTION_STEP", "SECONDARY_LAW", "SECONDARY_RESTITUTION", "SECONDARY_BETA",
           "SECONDARY_CONTACT_FRICTION", "box", "axis_overlap", "inside_depth",
           "contact_geometry", "capped_impact", "closing_speed", "bound_radius"]


def box(x, y, psi, front, length, width):
    """The outline of a vehicle at CG ``(x, y)`` [m] and heading ``psi`` [rad] as a box tuple
    ``(cx, cy, c, s, hx, hy)`` (module notes); ``front`` [m] is the CG to the front of the
    outline, ``length`` and ``width`` [m] the outline's."""
    c = np.cos(psi)
    s = np.sin(psi)
    shift = front - 0.5 * length
    return x + shift * c, y + shift * s, c, s, 0.5 * length, 0.5 * width


def bound_radius(front, length, width):
    """Radius [m] of the circle about the CG that holds the whole outline (the far corner)."""
    along = np.maximum(front, length - front)
    return np.sqrt(along * along + 0.25 * width * width)


def axis_overlap(b1, b2, ux, uy):
    """Overlap [m] of the two boxes' projections on the unit axis ``(ux, uy)`` and the signed
    distance of their centres along it (box 1 minus box 2) [m]."""
    r1 = b1[4] * abs(b1[2] * ux + b1[3] * uy) + b1[5] * abs(-b1[3] * ux + b1[2] * uy)
    r2 = b2[4] * abs(b2[2] * ux + b2[3] * uy) + b2[5] * abs(-b2[3] * ux + b2[2] * uy)
    d = (b1[0] - b2[0]) * ux + (b1[1] - b2[1]) * uy
    return r1 + r2 - abs(d), d


def inside_depth(px, py, b):
    """How far the point ``(px, py)`` [m] lies outside box ``b`` along its nearer axis [m]:
    < 0 inside (minus the depth below its nearest side), > 0 outside."""
    rx, ry = px - b[0], py - b[1]
    qx = abs(rx * b[2] + ry * b[3]) - b[4]
    qy = abs(-rx * b[3] + ry * b[2]) - b[5]
    return max(qx, qy)


def contact_geometry(b1, b2):
    """The contact of two boxes (module notes: the rule and why).

    Returns
    -------
    depth, cx, cy, nx, ny
        The overlap depth [m] (<= 0: apart), the impact point C [m] and the unit normal of
        the penetrated edge ``(cos Gamma, sin Gamma)``, pointing from vehicle 2 toward
        vehicle 1.
    """
    depth, nx, ny = np.inf, 1.0, 0.0
    for k in range(4):
        b = b1 if k < 2 else b2
        ux, uy = (b[2], b[3]) if k % 2 == 0 else (-b[3], b[2])
        overlap, d = axis_overlap(b1, b2, ux, uy)
        if overlap < depth:
            sign = 1.0 if d >= 0.0 else -1.0
            depth, nx, ny = overlap, sign * ux, sign * uy
    sx = sy = 0.0
    count = 0
    deepest, dx, dy = np.inf, 0.0, 0.0
    for k in range(8):
        own, other = (b1, b2) if k < 4 else (b2, b1)
        m = k % 4
        ex = 1.0 if (m == 0 or m == 3) else -1.0
        ey = 1.0 if m < 2 else -1.0
        px = own[0] + ex * own[4] * own[2] - ey * own[5] * own[3]
        py = own[1] + ex * own[4] * own[3] + ey * own[5] * own[2]
        if inside_depth(px, py, other) < 0.0:
            sx, sy, count = sx + px, sy + py, count + 1
        # how far the corner reaches toward the other body along the normal
        reach = (px * nx + py * ny) * (1.0 if k < 4 else -1.0)
        if reach < deepest:
            deepest, dx, dy = reach, px, py
    if count > 0:
        return depth, sx / count, sy / count, nx, ny
    return depth, dx, dy, nx, ny


def closing_speed(cx, cy, nx, ny, s1, s2):
    """The normal velocity of C on vehicle 1 relative to vehicle 2, ``u . n`` [m/s]
    (< 0: closing), of the states ``s = (x, y, psi, v_x, v_y, omega)``."""
    ux = (s1[3] - s1[5] * (cy - s1[1])) - (s2[3] - s2[5] * (cy - s2[1]))
    uy = (s1[4] + s1[5] * (cx - s1[0])) - (s2[4] + s2[5] * (cx - s2[0]))
    return ux * nx + uy * ny


def capped_impact(cx, cy, nx, ny, s1, s2, inverse, coefficients, tolerances):
    """A secondary impact at C with normal n: PIM with the friction-capped impulse ratio.

    Parameters
    ----------
    cx, cy : float
        The impact point C [m].
    nx, ny : float
        cos Gamma, sin Gamma: the contact normal from vehicle 2 toward vehicle 1 [-].
    s1, s2 : tuples
        The vehicles' states ``(x, y, psi, v_x, v_y, omega)`` just before [SI].
    inverse : (a1, b1, a2, b2)
        Inverse masses [1/kg] and yaw inertias [1/(kg m^2)] (0 for a fixed obstacle).
    coefficients : (eps, beta, cap)
        Restitution [-], fraction of mu0 [-] and the cap on |mu| [-] (inf: Brach's law).
    tolerances : (approach_tol, singular_tol)
        As :func:`pim.model.formula.contact`.

    Returns
    -------
    px, py, vx1, vy1, w1, vx2, vy2, w2
        The impulse on vehicle 1 [N s] and the post-impact velocities [m/s] and yaw rates
        [rad/s] (the pre-impact ones with no impulse when C does not close).

    Notes
    -----
    Brach & Brach (2011) eqs. 6.45-6.62 (:mod:`pim.model.formula`), with beta replaced by
    ``min(beta, cap / |mu0|)`` (:func:`pim.model.friction_cap.capped_beta`), mu0 =
    Pt0 / Pn0 the critical impulse ratio at ``eps``.
    """
    a1, b1, a2, b2 = inverse
    eps, beta, cap = coefficients
    r1x, r1y, r2x, r2y = cx - s1[0], cy - s1[1], cx - s2[0], cy - s2[1]
    v1x, v1y, w1, v2x, v2y, w2 = s1[3], s1[4], s1[5], s2[3], s2[4], s2[5]
    first = contact(nx, ny, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2,
                    eps, 1.0, tolerances[0], tolerances[1])
    pn0, pt0 = first[7], first[8]
    mu0 = abs(pt0 / pn0) if pn0 != 0.0 else 0.0
    if beta * mu0 > cap:
        beta = cap / mu0
    out = contact(nx, ny, a1, b1, r1x, r1y, v1x, v1y, w1, a2, b2, r2x, r2y, v2x, v2y, w2,
                  eps, beta, tolerances[0], tolerances[1])
    drive, denom, approaching = out[9], out[10], out[11]
    scale = drive / denom if approaching and denom != 0.0 else 0.0
    res = post_impact(scale, out[7], out[8], beta, nx, ny, a1, b1, r1x, r1y, v1x, v1y, w1,
                      a2, b2, r2x, r2y, v2x, v2y, w2)
    return res[2], res[3], res[4], res[5], res[8], res[6], res[7], res[9]
