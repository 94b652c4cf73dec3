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
- C is the centroid of the corners of either outline that lie inside the other and close
  along the normal (their velocity on vehicle 1 relative to vehicle 2, ``u . n < 0``): the
  penetrating corner in the usual corner-into-edge contact, the middle of the shared
  stretch when two edges meet flat (a side slap of parallel sides); corners of an earlier
  overlap (the crush of the first impact) that part do not count; the deepest corner along
  the normal when no corner lies inside (two edges crossing).

The contact is new when the depth grows by more than a tolerance above its least value
since the last impact (the outlines of a case may overlap at PIM's impact configuration by
the crush, and part), and it is solved when a corner inside closes.

**The secondary impact** (:func:`further_impact`), under any law a case may give it
(:data:`pim.model.impact_laws.LAW_CODES`), each PIM's formula (:mod:`pim.model.formula`) at
C and Gamma with the law's impulse ratio (docs/impact-laws.md):

- :func:`capped_impact`: restitution ``eps`` and ``mu = sign(mu0) min(beta |mu0|, cap)``,
  the friction-capped Brach law of :mod:`pim.model.friction_cap` ("brach-capped"; ``cap =
  inf`` is Brach's own law, "brach"), which carries the same two coefficients (restitution
  and a Coulomb cap on the inter-vehicle friction) as pymunk's polygon contact;
- :func:`kudlich_slibar_impact`: the Kudlich-Slibar law of
  :mod:`pim.model.impact_laws` ("kudlich-slibar"), PIM at ``eps = k`` with the ratio of
  the compression impulse (sticking, or sliding at ``mu_c``).
"""

from __future__ import annotations

import numpy as np

from .evidence_terms import impulse_work
from .formula import contact, post_impact
from .impact_laws import LAW_CODES

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
           "contact_geometry", "separating_axis", "capped_impact", "kudlich_slibar_impact", "further_impact",
           "closing_speed", "bound_radius", "energy_change", "KUDLICH_SLIBAR", "slip_speed",
           "relative_velocity", "energy_loss"]

#: The law code of "kudlich-slibar" in :func:`further_impact`'s coefficients
#: (:data:`pim.model.impact_laws.LAW_CODES`; "brach" and "brach-capped" are both
#: :func:`capped_impact`, Brach's own law at an infinite cap).
KUDLICH_SLIBAR = LAW_CODES["kudlich-slibar"]


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


def contact_geometry(b1, b2, s1, s2):
    """The contact of two boxes (module notes: the rule and why).

    Parameters
    ----------
    b1, b2 : box tuples (:func:`box`)
    s1, s2 : the vehicles' states ``(x, y, psi, v_x, v_y, omega)`` [SI]

    Returns
    -------
    depth, cx, cy, nx, ny, closing
        The overlap depth [m] (<= 0: apart), the impact point C [m], the unit normal of the
        penetrated edge ``(cos Gamma, sin Gamma)`` pointing from vehicle 2 toward vehicle
        1, and how many corners inside the other outline close along it (a float; 0: none,
        C is then the centroid of all inside corners, or the deepest corner).
    """
    depth, nx, ny = separating_axis(b1, b2)
    sx = sy = ax = ay = 0.0
    count = closing = 0
    deepest, dx, dy = np.inf, 0.0, 0.0
    for k in range(8):
        own, other = (b1, b2) if k < 4 else (b2, b1)
        m = k % 4
        ex = 1.0 if (m == 0 or m == 3) else -1.0
        ey = 1.0 if m < 2 else -1.0
        px = own[0] + ex * own[4] * own[2] - ey * own[5] * own[3]
        py = own[1] + ex * own[4] * own[3] + ey * own[5] * own[2]
        if inside_depth(px, py, other) < 0.0:
            ax, ay, count = ax + px, ay + py, count + 1
            if closing_speed(px, py, nx, ny, s1, s2) < 0.0:
                sx, sy, closing = sx + px, sy + py, closing + 1
        # how far the corner reaches toward the other body along the normal
        reach = (px * nx + py * ny) * (1.0 if k < 4 else -1.0)
        if reach < deepest:
            deepest, dx, dy = reach, px, py
    if closing > 0:
        return depth, sx / closing, sy / closing, nx, ny, 1.0 * closing
    if count > 0:
        return depth, ax / count, ay / count, nx, ny, 0.0
    return depth, dx, dy, nx, ny, 1.0 if closing_speed(dx, dy, nx, ny, s1, s2) < 0.0 else 0.0


def separating_axis(b1, b2):
    """The overlap depth [m] of two boxes (<= 0: apart) and the unit normal ``(nx, ny)`` of
    the penetrated edge from box 2 toward box 1: the least overlap of their projections
    over their four edge normals (the separating-axis test; :func:`contact_geometry`'s
    first part, all the outline watch needs between contacts)."""
    depth, nx, ny = np.inf, 1.0, 0.0
    for k in range(4):
        b = b1 if k < 2 else b2
        ux, uy = (b[2], b[3]) if k % 2 == 0 else (-b[3], b[2])
        overlap, d = axis_overlap(b1, b2, ux, uy)
        if overlap < depth:
            sign = 1.0 if d >= 0.0 else -1.0
            depth, nx, ny = overlap, sign * ux, sign * uy
    return depth, nx, ny


def relative_velocity(cx, cy, s1, s2):
    """The velocity of C on vehicle 1 relative to vehicle 2, ``u = (v_1 + w_1 k x r_1) -
    (v_2 + w_2 k x r_2)`` [m/s] (``r_i = C - G_i``; Brach & Brach 2011, eq. 6.45), of the
    states ``s = (x, y, psi, v_x, v_y, omega)``."""
    ux = (s1[3] - s1[5] * (cy - s1[1])) - (s2[3] - s2[5] * (cy - s2[1]))
    uy = (s1[4] + s1[5] * (cx - s1[0])) - (s2[4] + s2[5] * (cx - s2[0]))
    return ux, uy


def closing_speed(cx, cy, nx, ny, s1, s2):
    """The normal velocity of C on vehicle 1 relative to vehicle 2, ``u . n`` [m/s]
    (< 0: closing), of the states ``s = (x, y, psi, v_x, v_y, omega)``."""
    ux, uy = relative_velocity(cx, cy, s1, s2)
    return ux * nx + uy * ny


def energy_loss(cx, cy, s1, s2, out):
    """Kinetic energy lost [J] in an impact at C whose answer is ``out``
    (:func:`capped_impact`'s: the impulse on vehicle 1, then both vehicles' velocities and
    yaw rates after) on the states ``s1``, ``s2`` before: ``-P . (u + U) / 2``
    (:func:`pim.model.evidence_terms.impulse_work`, the formula of
    :attr:`pim.Result.energy_loss`, exact where a kinetic-energy difference loses the
    loss to round-off)."""
    ux, uy = relative_velocity(cx, cy, s1, s2)
    bx, by = relative_velocity(cx, cy, (s1[0], s1[1], s1[2], out[2], out[3], out[4]),
                               (s2[0], s2[1], s2[2], out[5], out[6], out[7]))
    return impulse_work(out[0], out[1], ux, uy, bx, by)


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
    px, py, vx1, vy1, w1, vx2, vy2, w2, beta
        The impulse on vehicle 1 [N s], the post-impact velocities [m/s] and yaw rates
        [rad/s] (the pre-impact ones with no impulse when C does not close), and the
        effective fraction of mu0 [-] (``result.beta`` of :func:`pim.solve`).

    Notes
    -----
    Brach & Brach (2011) eqs. 6.45-6.62 (:mod:`pim.model.formula`), with beta replaced by
    ``min(beta, cap / |mu0|)`` (:func:`pim.model.friction_cap.capped_beta`), mu0 =
    Pt0 / Pn0 the critical impulse ratio at ``eps``. Where that answer gains energy
    (Newton's restitution with a tangential impulse on a grazing contact: Kane and
    Levinson's paradox, Stronge, *Impact Mechanics*, 2000, sec. 4.4), the impact is solved
    frictionless (beta = 0: the normal impulse alone, which loses
    ``(1 - eps^2) m_eff u_n^2 / 2 >= 0``). :func:`pim.analysis.event.event` applies the
    same rule to :func:`pim.solve`'s answer.
    """
    out = _capped(cx, cy, nx, ny, s1, s2, inverse, coefficients, tolerances)
    if energy_change(inverse, s1, s2, out) > 0.0:
        out = _capped(cx, cy, nx, ny, s1, s2, inverse, (coefficients[0], 0.0, coefficients[2]),
                      tolerances)
    return out


def energy_change(inverse, s1, s2, out):
    """Kinetic energy after minus before [J] of an impact's answer ``out``
    (:func:`capped_impact`'s) on the states ``s1``, ``s2``; a fixed obstacle (inverse mass
    0) counts nothing."""
    change = 0.0
    for v in range(2):
        a, b = inverse[2 * v], inverse[2 * v + 1]
        s = s1 if v == 0 else s2
        if a > 0.0:
            vx, vy, w = out[2 + 3 * v], out[3 + 3 * v], out[4 + 3 * v]
            change += 0.5 * ((vx * vx + vy * vy - s[3] * s[3] - s[4] * s[4]) / a
                             + (w * w - s[5] * s[5]) / b)
    return change


def _capped(cx, cy, nx, ny, s1, s2, inverse, coefficients, tolerances):
    """:func:`capped_impact` without its energy check."""
    eps, beta, cap = coefficients
    first = _contact_at(cx, cy, nx, ny, s1, s2, inverse, eps, 1.0, tolerances)
    pn0, pt0 = first[7], first[8]
    mu0 = abs(pt0 / pn0) if pn0 != 0.0 else 0.0
    if beta * mu0 > cap:
        beta = cap / mu0
    out = _contact_at(cx, cy, nx, ny, s1, s2, inverse, eps, beta, tolerances)
    drive, denom, approaching = out[9], out[10], out[11]
    scale = drive / denom if approaching and denom != 0.0 else 0.0
    return _answer(scale, out[7], out[8], beta, cx, cy, nx, ny, s1, s2, inverse, beta)


def _contact_at(cx, cy, nx, ny, s1, s2, inverse, restitution, beta, tolerances):
    """:func:`pim.model.formula.contact` of the states ``s1``, ``s2`` at C with normal n."""
    a1, b1, a2, b2 = inverse
    return contact(nx, ny, a1, b1, cx - s1[0], cy - s1[1], s1[3], s1[4], s1[5], a2, b2,
                   cx - s2[0], cy - s2[1], s2[3], s2[4], s2[5], restitution, beta,
                   tolerances[0], tolerances[1])


def _answer(scale, pn0, pt0, beta, cx, cy, nx, ny, s1, s2, inverse, ratio):
    """The impulse ``s (Pn0 n + beta Pt0 t)`` at C (:func:`pim.model.formula.post_impact`)
    and the motion after it, in :func:`capped_impact`'s order, ``ratio`` last."""
    a1, b1, a2, b2 = inverse
    res = post_impact(scale, pn0, pt0, beta, nx, ny, a1, b1, cx - s1[0], cy - s1[1], s1[3],
                      s1[4], s1[5], a2, b2, cx - s2[0], cy - s2[1], s2[3], s2[4], s2[5])
    return res[2], res[3], res[4], res[5], res[8], res[6], res[7], res[9], ratio


def kudlich_slibar_impact(cx, cy, nx, ny, s1, s2, inverse, coefficients, tolerances):
    """A secondary impact at C with normal n under the Kudlich-Slibar law.

    Parameters
    ----------
    cx, cy, nx, ny, s1, s2, inverse, tolerances
        As :func:`capped_impact`.
    coefficients : (k, mu_c)
        Restitution k [-] and contact friction mu_c [-] (inf: always stick).

    Returns
    -------
    px, py, vx1, vy1, w1, vx2, vy2, w2, mu
        As :func:`capped_impact`, the last the impulse ratio Pt / Pn [-].

    Notes
    -----
    :func:`pim.model.impact_laws.solve_kudlich_slibar`'s law as PIM (the mapping of
    :mod:`pim.model.impact_laws`): ``eps = k`` and the impulse ratio ``mu`` of the
    compression impulse, the critical impulse at ``eps = 0`` ``(Pn0(0), Pt0(0))`` (``K P_c =
    -u``): it sticks, ``mu = Pt0(0) / Pn0(0)``, where it pushes (``Pn0(0) > 0``) within the
    cap (``|Pt0(0)| <= mu_c Pn0(0)``), else it slides at the cap, ``mu = sigma mu_c``,
    ``sigma = sign(Pt0(0))``; the normal row ``K_nn Pn + K_nt Pt = -(1 + k) u_n`` with
    ``Pt = mu Pn`` gives ``Pn = s Pn0(k)``, ``s = drive / (drive + K_nt (mu Pn0(k) -
    Pt0(k)))`` (Kudlich 1966; Steffan & Moser, SAE 960886; Brach & Brach 2011, eqs.
    6.55-6.62). No impulse where C does not close.
    """
    k, mu_c = coefficients
    stick = _contact_at(cx, cy, nx, ny, s1, s2, inverse, 0.0, 1.0, tolerances)
    pn_c, pt_c = stick[7], stick[8]
    if pn_c > 0.0 and abs(pt_c) <= mu_c * pn_c:
        mu = pt_c / pn_c
    else:
        mu = mu_c if pt_c > 0.0 else -mu_c if pt_c < 0.0 else 0.0
    out = _contact_at(cx, cy, nx, ny, s1, s2, inverse, k, 1.0, tolerances)
    tangential = mu * out[7]
    denom = out[9] + out[5] * (tangential - out[8])
    scale = out[9] / denom if out[11] and denom != 0.0 else 0.0
    return _answer(scale, out[7], tangential, 1.0, cx, cy, nx, ny, s1, s2, inverse, mu)


def further_impact(cx, cy, nx, ny, s1, s2, inverse, coefficients, tolerances):
    """A secondary impact at C with normal n under the law its coefficients name.

    Parameters
    ----------
    cx, cy, nx, ny, s1, s2, inverse, tolerances
        As :func:`capped_impact`.
    coefficients : (restitution, beta, cap, law)
        Restitution (eps, or k) [-], fraction of mu0 [-] (Brach's laws), the cap on |mu|
        or the contact friction mu_c [-] (inf: Brach's law, or always stick), and the law's
        code (:data:`pim.model.impact_laws.LAW_CODES`).

    Returns
    -------
    tuple
        :func:`capped_impact`'s ("brach", "brach-capped": with its frictionless answer
        where the capped one gains energy) or :func:`kudlich_slibar_impact`'s
        ("kudlich-slibar", as :func:`pim.solve` gives it).
    """
    if coefficients[3] == KUDLICH_SLIBAR:
        return kudlich_slibar_impact(cx, cy, nx, ny, s1, s2, inverse,
                                     (coefficients[0], coefficients[2]), tolerances)
    return capped_impact(cx, cy, nx, ny, s1, s2, inverse,
                         (coefficients[0], coefficients[1], coefficients[2]), tolerances)


def slip_speed(c, s, vx, vy, omega, px, py, cw, sw, braking):
    """The slip speed a tyre resists [m/s]: ``f |s| + (1 - f) |s . e_t|``, the weights of
    :func:`pim.model.tyres.wheel_force` (``f`` the braking fraction, ``s`` the contact
    point's slip velocity, ``e_t = (-sw, cw)`` the wheel's lateral unit vector); where it
    passes :data:`pim.analysis.event.SLIDE_SPEED` the wheel slides (leaves marks).

    Parameters as :func:`pim.model.tyres.wheel_force` (numbers or broadcasting arrays); a
    locked wheel given as the number 1.0 skips the lateral term it weights by 0 (the same
    number)."""
    ax = c * px - s * py
    ay = s * px + c * py
    sx = vx - omega * ay
    sy = vy + omega * ax
    full = np.hypot(sx, sy)
    if isinstance(braking, float) and braking == 1.0:
        return full
    return braking * full + (1.0 - braking) * np.abs(-sw * sx + cw * sy)
