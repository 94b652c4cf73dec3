"""The finite-duration crush scene's arithmetic, written once.

Every evaluation of the compliant scene runs these functions (as :mod:`pim.model.formula` is
for PIM):

* the pymunk scene (:mod:`sim.compliant`) calls them on Python floats from its velocity
  callback for the contact and tyre forces, while Chipmunk moves the bodies;
* numba compiles the very same Python functions into the parallel batch integrator
  (:mod:`sim.compliant_kernel`), which also runs :func:`drift` and :func:`kick`, Chipmunk's
  own position and velocity updates (``cpBodyUpdatePosition``, ``cpBodyUpdateVelocity``),
  written here in Chipmunk's order of operations;
* :mod:`sim.contact_law` and :mod:`sim.contact_tyres` evaluate the contact law and the tyre
  sum on numbers and arrays for everyone else (the ``solve_ivp`` reference included).

They hold only arithmetic on floats, ``math`` functions, ``min``/``max``/``abs`` and
conditionals, in a fixed order, so the pymunk scene and the compiled integrator step the
same scene to the same numbers (no fast-math, no contraction; ``tests/sim``). They never
divide by zero (Python floats would raise where numba gives inf).

The per-scene data live in flat float sequences indexed by the constants below (a Python
list in the pymunk scene, a row of a 2-D array in the kernel):

* ``par`` (:data:`N_PAR`): masses, inertias, the body-frame arms and normal of the point
  contact, the contact law's parameters, the tyres, the step;
* ``st`` (12): x1, y1, theta1, vx1, vy1, w1, x2, y2, theta2, vx2, vy2, w2 [SI];
* ``mem`` (:data:`N_MEM`): what the contact law remembers from one step to the next;
* ``tal`` (:data:`N_TAL`): what the result reports, summed over the contact steps;
* ``lo`` (6): the loads of the last kick, fx1, fy1, moment1, fx2, fy2, moment2 [N, N m].

Equations and sources: docs/contact-model.md and the module notes of :mod:`sim.contact_law`
(crush hysteresis, elastoplastic friction with tangential recovery) and
:mod:`sim.contact_tyres` (the four-tyre model; the force of one tyre is
:func:`pim.model.tyres.wheel_force`, the project's one tyre law).
"""

from __future__ import annotations

import math

from pim.model.tyres import wheel_force

__all__ = ["loading_force", "loading_work", "unloading_slope", "permanent_crush",
           "normal_force", "normal_stiffness", "tangential_step", "tangential_force",
           "angles", "turn_cos_sin", "turned", "advance_angles", "SMALL_TURN", "TINY_TURN",
           "point_contact", "point_geometry", "place_corners", "clip_polygon",
           "area_centroid", "separating_axis", "outline_overlap", "place_outlines",
           "outline_geometry", "outlines_touch", "outline_start", "free_state",
           "freeze_point", "frozen_point",
           "vehicle_tyre_force", "tyre_loads", "ahead",
           "contact_loads", "total_loads", "half_kick", "drift", "kick", "separation_time",
           "post_velocities", "slip_reversed", "write_outputs", "N_PAR", "N_MEM", "N_TAL",
           "N_OUT", "N_WORK"]

# ---- status of a scene ------------------------------------------------------------------------
#: Status by code: 0 "ok", then the :class:`sim.SimulationError` kinds a stepped scene ends in.
#: "energy_gained" is set after the stepping (:func:`sim.compliant_setup.physics_status`),
#: never by the stepped scene itself.
STATUS_NAMES = ("ok", "no_contact", "never_separated", "tunnelled", "energy_gained")
STATUS_OK, STATUS_NO_CONTACT, STATUS_NEVER_SEPARATED, STATUS_TUNNELLED = 0, 1, 2, 3
STATUS_ENERGY_GAINED = 4

# ---- par: the scene's parameters ---------------------------------------------------------------
P_M1, P_I1, P_M2, P_I2, P_FIXED2 = 0, 1, 2, 3, 4     # [kg], [kg m^2]; fixed2 1.0 or 0.0
P_ARM1 = 5          # P - CG1 at t = 0 in vehicle 1's body frame (2) [m]
P_ARM2 = 7          # Q - CG2 at t = 0 in vehicle 2's body frame (2) [m]
P_NORMAL2 = 9       # the contact normal in vehicle 2's body frame (2) [-]
P_EPS, P_PRELOAD, P_STIFFNESS = 11, 12, 13           # eps [-], a [N], b = k [N/m]
P_FRICTION, P_KT, P_RECOVERY = 14, 15, 16            # mu_c [-], k_t [N/m], r [-]
P_TYRE, P_BRAKING, P_VR = 17, 18, 19                 # mu_tyre [-], f (0 rolling, 1 locked), v_r
P_WHEELS1, P_LOADS1 = 20, 28                         # wheel positions (8), static loads (4)
P_WHEELS2, P_LOADS2 = 32, 40
P_DT, P_START = 44, 45                               # step [s], when the contact starts [s]
P_MAX_STEPS = 46                                     # most steps of the contact
P_OUTLINE = 47                                       # 1.0 for the outline contact
P_SPEED = 48                                         # speed scale [m/s] (tolerances)
P_OUTLINE1 = 49     # vehicle 1's outline corners in its body frame (8) [m]
P_OUTLINE2 = 57     # vehicle 2's (8), or a fixed obstacle's world corners (P_OBSTACLE)
P_OBSTACLE = 65     # 1.0: P_OUTLINE2 holds world corners (a bare barrier's block)
P_INVERSE = 66      # 1 / m1, 1 / I1, 1 / m2, 1 / I2 (Chipmunk's m_inv, i_inv) [1/kg, 1/(kg m^2)]
P_FROZEN = 70       # 1.0: the point contact's geometry frozen at its start (freeze_point)
P_FROZEN_ARMS = 71  # world-frame P - CG1, Q - CG2 and the normal at the start (6) [m, -]
P_FROZEN_HEADINGS = 77  # both headings at the start (2) [rad]
N_PAR = 79

# ---- wk: scratch of the outline contact --------------------------------------------------------
W_POLY1, W_POLY2 = 0, 8     # both outlines' world corners (4 x, y pairs each)
W_A, W_B = 16, 48           # clipping buffers (16 x, y pairs each)
N_WORK = 80

# ---- mem: the contact law's memory -------------------------------------------------------------
M_ON, M_STARTED, M_SEPARATED = 0, 1, 2               # flags (1.0 / 0.0)
M_DMAX, M_DELTA, M_PREV_DELTA = 3, 4, 5              # [m]
M_Z, M_SLIP = 6, 7                                   # spring stretch [m], last slip [m/s]
M_FFX, M_FFY = 8, 9                                  # friction force of the last step [N]
M_NX, M_NY, M_HAS_NORMAL = 10, 11, 12                # outline: normal of the last overlap
N_MEM = 13

# ---- tal: the tally ----------------------------------------------------------------------------
T_IMPULSE = 0       # sum of F dt (2) [N s]
T_MOMENT = 2        # sum of |F| dt times the point (2) [N s m]
T_NORMAL = 4        # sum of |F| dt times the normal (2) [N s]
T_BODY_POINT = 6    # as T_MOMENT, point - CG1 in vehicle 1's frame (2)
T_BODY_NORMAL = 8   # as T_NORMAL, the normal in vehicle 2's frame (2)
T_WEIGHT, T_PEAK, T_TYRE_WORK = 10, 11, 12           # [N s], [N], [J]
T_STICK, T_CONTACT = 13, 14                          # [s]
T_SLID_POS, T_SLID_NEG = 15, 16                      # slid with z > 0 / z < 0 (flags)
T_INITIAL_SIGN, T_HAS_INITIAL = 17, 18               # sign of the first slip, and whether set
T_LAST_SLIP, T_LAST_SLIP_N = 19, 20                  # [m/s]
N_TAL = 21

# ---- out: one scene's outputs ------------------------------------------------------------------
O_V1, O_V2, O_W1, O_W2 = 0, 2, 4, 5                  # post-impact motion [m/s], [rad/s]
O_DURATION, O_IMPULSE = 6, 7                         # contact time [s], impulse (2) [N s]
O_POINT, O_NORMAL = 9, 11                            # impulse centroid (2) [m], mean normal (2)
O_BODY_POINT, O_BODY_NORMAL = 13, 15                 # the same in the body frames (2 each)
O_PEAK_FORCE, O_PEAK_CRUSH, O_PERMANENT = 17, 18, 19  # [N], [m], [m]
O_TYRE_WORK, O_STICK, O_REVERSED, O_STEPS = 20, 21, 22, 23   # [J], [-], flag, count
O_START = 24                                         # when the contact began [s]
N_OUT = 25


# ---- the contact law (sim.contact_law's module notes) ------------------------------------------
def loading_force(delta, a, b):
    """F_L = a + b delta on the loading curve [N], 0 for delta <= 0."""
    return a + b * max(delta, 0.0) if delta > 0.0 else 0.0


def loading_work(delta_max, a, b):
    """a d + b d^2 / 2 [J], d = max(delta_max, 0): the work of loading up to delta_max."""
    d = max(delta_max, 0.0)
    return a * d + 0.5 * b * d * d


def unloading_slope(delta_max, eps, a, b):
    """s = F_max^2 / (2 eps^2 E_L) [N/m]; inf for eps = 0 or before any crush."""
    f_max = a + b * delta_max
    denom = 2.0 * (eps * eps) * loading_work(delta_max, a, b)
    return f_max * f_max / denom if denom > 0.0 else math.inf


def permanent_crush(delta_max, eps, a, b):
    """delta_p = delta_max - F_max / s [m] (linear spring: delta_max (1 - eps^2))."""
    if not delta_max > 0.0:
        return 0.0
    f_max = a + b * delta_max
    if not f_max > 0.0:
        return delta_max
    return delta_max - 2.0 * (eps * eps) * loading_work(delta_max, a, b) / f_max


def normal_force(delta, delta_max, eps, a, b):
    """F_n [N] >= 0 of the bilinear hysteresis: F_L(delta) loading (delta >= delta_max), the
    straight line from (delta_max, F_max) to (delta_p, 0) unloading, 0 apart."""
    if delta >= delta_max:
        return loading_force(delta, a, b)
    if not delta > 0.0:
        return 0.0
    f_max = a + b * delta_max
    delta_p = permanent_crush(delta_max, eps, a, b)
    span = delta_max - delta_p        # written without s: eps = 0 gives 0 below the peak
    frac = (delta - delta_p) / span if span > 0.0 else 0.0
    return f_max * min(max(frac, 0.0), 1.0)


def normal_stiffness(delta, delta_max, eps, a, b):
    """dF_n / d delta [N/m] of :func:`normal_force`: b loading, s unloading, 0 apart."""
    if delta >= delta_max and delta > 0.0:
        return b
    if delta < delta_max and delta > permanent_crush(delta_max, eps, a, b):
        return unloading_slope(delta_max, eps, a, b)
    return 0.0


def tangential_step(z, slip, dt, z_max, recovery):
    """One implicit step of the elastoplastic friction spring [m]: z + v_t dt loading, at
    1 / r the rate unloading toward 0 (the rest of the slip loads the other way), clipped
    to the cone |z| <= z_max (sim.contact_law, "Tangential recovery")."""
    dz = slip * dt
    z_new = z + dz
    if z * dz < 0.0:                      # unloading toward z = 0
        reach = abs(z) * recovery         # slip that unloads it fully [m]
        if abs(dz) < reach and recovery > 0.0:
            z_new = z + dz / recovery
        else:
            z_new = abs(dz) - reach if dz > 0.0 else -(abs(dz) - reach)
    z_max = max(z_max, 0.0)
    return min(max(z_new, -z_max), z_max)


def tangential_force(z, k_t, limit):
    """F_t = -k_t z [N], clipped to the Coulomb limit mu_c F_n."""
    return -min(max(k_t * z, -limit), limit)


# ---- kinematics of the point contact (sim.compliant_setup's module notes) ----------------------
def angles(st):
    """cos and sin of both headings of the state ``st``: (c1, s1, c2, s2) (the C library's;
    at the start of a contact: each step turns them on by :func:`advance_angles`)."""
    return math.cos(st[2]), math.sin(st[2]), math.cos(st[8]), math.sin(st[8])


#: Largest |turn| [rad] whose cos and sin :func:`turn_cos_sin` takes from its polynomials.
SMALL_TURN = 0.25
#: Largest |turn| [rad] for its short polynomials (a step's w dt is usually below 0.01).
TINY_TURN = 1.0 / 32.0
# 1 / k! for the Taylor polynomials of cos and sin (Python and LLVM round them alike)
_F2, _F3, _F4, _F5, _F6, _F7 = 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0, \
    1.0 / 5040.0
_F8, _F9, _F10, _F11 = 1.0 / 40320.0, 1.0 / 362880.0, 1.0 / 3628800.0, 1.0 / 39916800.0
_F12, _F13 = 1.0 / 479001600.0, 1.0 / 6227020800.0


def turn_cos_sin(d):
    """cos d and sin d of a turn d [rad] (one step's w dt) without the C library's range
    reduction: their Taylor polynomials in Horner form, to d^6 and d^7 for |d| <=
    :data:`TINY_TURN`, to d^12 and d^13 for |d| <= :data:`SMALL_TURN` (the first term left
    out is below 2.5e-17 of the value in either range, so the result is within a few ulp of
    the C library's), beyond it the C library's."""
    x = d * d
    if abs(d) <= TINY_TURN:
        return 1.0 - x * (_F2 - x * (_F4 - x * _F6)), d - d * x * (_F3 - x * (_F5 - x * _F7))
    if not abs(d) <= SMALL_TURN:
        return math.cos(d), math.sin(d)
    cos = 1.0 - x * (_F2 - x * (_F4 - x * (_F6 - x * (_F8 - x * (_F10 - x * _F12)))))
    sin = d - d * x * (_F3 - x * (_F5 - x * (_F7 - x * (_F9 - x * (_F11 - x * _F13)))))
    return cos, sin


def turned(c, s, d):
    """(cos, sin) of theta + d [-] from c = cos theta, s = sin theta: the rotation by d."""
    cd, sd = turn_cos_sin(d)
    return c * cd - s * sd, s * cd + c * sd


def _unit_pair(c, s):
    """(c, s) scaled back onto the unit circle by one Newton step of 1 / |(c, s)| (the error
    of a norm within a few ulp of 1 squared away: no drift over the steps)."""
    g = 1.5 - 0.5 * (c * c + s * s)
    return c * g, s * g


def advance_angles(par, trig, st, dt):
    """cos and sin of both headings (:func:`angles`) turned on by the step :func:`drift`
    has just made, w dt each (a fixed vehicle 2 stays), renormalised: no sine or cosine per
    step. They follow the headings ``st[2]``, ``st[8]`` to round-off (a few ulp per step,
    a random walk; the headings themselves add an ulp of theta per step)."""
    c1, s1 = turned(trig[0], trig[1], st[5] * dt)
    c1, s1 = _unit_pair(c1, s1)
    if par[P_FIXED2] != 0.0:
        return c1, s1, trig[2], trig[3]
    c2, s2 = turned(trig[2], trig[3], st[11] * dt)
    c2, s2 = _unit_pair(c2, s2)
    return c1, s1, c2, s2


def point_contact(a1x, a1y, a2x, a2y, n2x, n2y, x1, y1, c1, s1, vx1, vy1, w1, x2, y2, c2, s2,
                  vx2, vy2, w2):
    """P (on vehicle 1), the normal n carried by vehicle 2, the crush delta = -(P - Q) . n,
    and the relative velocity of P along n and t = n turned +90 deg; (c1, s1), (c2, s2) the
    cos and sin of the headings.

    Returns (px, py, nx, ny, delta, slip_n, slip_t) [m, -, m, m/s].
    """
    px = x1 + (c1 * a1x - s1 * a1y)
    py = y1 + (s1 * a1x + c1 * a1y)
    qx = x2 + (c2 * a2x - s2 * a2y)
    qy = y2 + (s2 * a2x + c2 * a2y)
    nx = c2 * n2x - s2 * n2y
    ny = s2 * n2x + c2 * n2y
    d1x, d1y = px - x1, py - y1
    d2x, d2y = px - x2, py - y2
    relx = vx1 + w1 * -d1y - vx2 - w2 * -d2y
    rely = vy1 + w1 * d1x - vy2 - w2 * d2x
    delta = -((px - qx) * nx + (py - qy) * ny)
    return px, py, nx, ny, delta, relx * nx + rely * ny, relx * -ny + rely * nx


def _point(par, x1, y1, c1, s1, vx1, vy1, w1, x2, y2, c2, s2, vx2, vy2, w2):
    return point_contact(par[P_ARM1], par[P_ARM1 + 1], par[P_ARM2], par[P_ARM2 + 1],
                         par[P_NORMAL2], par[P_NORMAL2 + 1], x1, y1, c1, s1, vx1, vy1, w1, x2,
                         y2, c2, s2, vx2, vy2, w2)


def freeze_point(par, st):
    """Store the point contact's geometry at the start ``st`` in ``par`` (the study switch
    "no geometry change during contact", ``par[P_FROZEN]`` = 1): the world-frame arms
    P - CG1 and Q - CG2, the normal and both headings (:func:`frozen_point` uses them)."""
    c1, s1, c2, s2 = angles(st)
    a = P_FROZEN_ARMS
    par[a] = c1 * par[P_ARM1] - s1 * par[P_ARM1 + 1]
    par[a + 1] = s1 * par[P_ARM1] + c1 * par[P_ARM1 + 1]
    par[a + 2] = c2 * par[P_ARM2] - s2 * par[P_ARM2 + 1]
    par[a + 3] = s2 * par[P_ARM2] + c2 * par[P_ARM2 + 1]
    par[a + 4] = c2 * par[P_NORMAL2] - s2 * par[P_NORMAL2 + 1]
    par[a + 5] = s2 * par[P_NORMAL2] + c2 * par[P_NORMAL2 + 1]
    par[P_FROZEN_HEADINGS] = st[2]
    par[P_FROZEN_HEADINGS + 1] = st[8]


def frozen_point(par, st):
    """The point contact with its geometry frozen at the start (:func:`freeze_point`): the
    arms r1 = P - CG1, r2 = Q - CG2 and the normal n stay as they were, the crush follows
    the displacement of both points to first order, delta = -((dx1 + dtheta1 z x r1) -
    (dx2 + dtheta2 z x r2)) . n (so d delta / dt = -slip_n exactly), and the slip is the
    relative velocity v1 + w1 z x r1 - v2 - w2 z x r2 along n and t. The rigid-body
    impact's geometry (Brach's, PIM's) held through a finite contact: what the contact's
    duration changes then is only what acts besides it (the tyres).

    Returns (px, py, nx, ny, delta, slip_n, slip_t), P = CG1 + r1.
    """
    a = P_FROZEN_ARMS
    r1x, r1y, r2x, r2y, nx, ny = par[a], par[a + 1], par[a + 2], par[a + 3], par[a + 4], \
        par[a + 5]
    d1 = st[2] - par[P_FROZEN_HEADINGS]
    d2 = st[8] - par[P_FROZEN_HEADINGS + 1]
    gx = (st[0] + r1x - d1 * r1y) - (st[6] + r2x - d2 * r2y)
    gy = (st[1] + r1y + d1 * r1x) - (st[7] + r2y + d2 * r2x)
    relx = st[3] - st[5] * r1y - st[9] + st[11] * r2y
    rely = st[4] + st[5] * r1x - st[10] - st[11] * r2x
    return (st[0] + r1x, st[1] + r1y, nx, ny, -(gx * nx + gy * ny), relx * nx + rely * ny,
            -relx * ny + rely * nx)


def point_geometry(par, st, trig, dt):
    """The point contact at the end of the step, its tangential slip at the middle.

    In the velocity callback the bodies have moved from t_n to t_{n+1} with the velocities
    they hold (those of the middle of the step); the slip the friction spring integrates is
    taken at the state those velocities go with, the positions moved back half a step (a
    second-order slip; docs/contact-model.md, "Integration"). ``trig``: :func:`angles` of
    ``st``.

    Returns (px, py, nx, ny, delta, slip_n, slip_t); :func:`frozen_point` when
    ``par[P_FROZEN]`` is set.
    """
    if par[P_FROZEN] != 0.0:
        return frozen_point(par, st)
    px, py, nx, ny, delta, slip_n, slip_t = _point(
        par, st[0], st[1], trig[0], trig[1], st[3], st[4], st[5], st[6], st[7], trig[2],
        trig[3], st[9], st[10], st[11])
    if dt > 0.0:
        h = 0.5 * dt
        c1, s1 = turned(trig[0], trig[1], -(st[5] * h))
        c2, s2 = turned(trig[2], trig[3], -(st[11] * h))
        slip_t = _point(par, st[0] - st[3] * h, st[1] - st[4] * h, c1, s1, st[3], st[4],
                        st[5], st[6] - st[9] * h, st[7] - st[10] * h, c2, s2, st[9], st[10],
                        st[11])[6]
    return px, py, nx, ny, delta, slip_n, slip_t


# ---- tyres (sim.contact_tyres) -----------------------------------------------------------------
def vehicle_tyre_force(data, wheels, loads, vx, vy, w, c, s, mu, braking, vr):
    """Sum of the four tyre forces [N] and their moment about the CG [N m] on one vehicle.

    ``data[wheels:wheels + 8]``: the body-frame wheel positions x0, y0, ..., x3, y3 [m];
    ``data[loads:loads + 4]`` their loads [N]; (c, s) cos and sin of the heading;
    ``braking`` 0 free-rolling, 1 locked; each tyre :func:`pim.model.tyres.wheel_force`.
    """
    fx = 0.0
    fy = 0.0
    moment = 0.0
    for k in range(4):
        a, b, m = wheel_force(c, s, vx, vy, w, data[wheels + 2 * k], data[wheels + 2 * k + 1],
                              c, s, data[loads + k], mu, braking, vr)
        fx += a
        fy += b
        moment += m
    return fx, fy, moment


def tyre_loads(par, vx1, vy1, w1, vx2, vy2, w2, trig):
    """Tyre forces and moments on both vehicles and their power [W] (zeros without tyres);
    ``trig``: cos and sin of both headings (:func:`angles`).

    Returns (fx1, fy1, m1, fx2, fy2, m2, power).
    """
    mu = par[P_TYRE]
    if not mu > 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    f1x, f1y, m1 = vehicle_tyre_force(par, P_WHEELS1, P_LOADS1, vx1, vy1, w1, trig[0],
                                      trig[1], mu, par[P_BRAKING], par[P_VR])
    power = f1x * vx1 + f1y * vy1 + m1 * w1
    f2x, f2y, m2 = 0.0, 0.0, 0.0
    if par[P_FIXED2] == 0.0:
        f2x, f2y, m2 = vehicle_tyre_force(par, P_WHEELS2, P_LOADS2, vx2, vy2, w2, trig[2],
                                          trig[3], mu, par[P_BRAKING], par[P_VR])
        power += f2x * vx2 + f2y * vy2 + m2 * w2
    return f1x, f1y, m1, f2x, f2y, m2, power


def ahead(par, st, lo, h):
    """The velocities of ``st`` moved on by ``h`` [s] of the last kick's accelerations
    (``lo``): from the middle of the step, where the leapfrog's velocities belong, to where
    the velocity-dependent tyre force is wanted. Returns (vx1, vy1, w1, vx2, vy2, w2)."""
    vx1 = st[3] + lo[0] * par[P_INVERSE] * h
    vy1 = st[4] + lo[1] * par[P_INVERSE] * h
    w1 = st[5] + lo[2] * par[P_INVERSE + 1] * h
    if par[P_FIXED2] != 0.0:
        return vx1, vy1, w1, st[9], st[10], st[11]
    return (vx1, vy1, w1, st[9] + lo[3] * par[P_INVERSE + 2] * h,
            st[10] + lo[4] * par[P_INVERSE + 2] * h, st[11] + lo[5] * par[P_INVERSE + 3] * h)


# ---- one step of the contact -------------------------------------------------------------------
def plastic_release(recovery, z, slip0, slip1, ffx, ffy):
    """Correction [N] for a friction force released inside the last kick (r = 0).

    With r = 0 the friction force drops to zero the moment the slip turns back against z.
    The last kick applied the force (ffx, ffy) over the whole of [t_{n-1/2}, t_{n+1/2}]
    (where the slips ``slip0`` and ``slip1`` belong); the slip, interpolated linearly, turned
    at t* inside it, so the share s_1 / (s_1 - s_0) of that impulse is taken back in this
    step (docs/contact-model.md, "Convergence of pymunk to the reference").
    """
    if recovery > 0.0 or not (z * slip1 < 0.0 and slip0 * slip1 < 0.0):
        return 0.0, 0.0
    share = slip1 / (slip1 - slip0)
    return -ffx * share, -ffy * share


def contact_law(par, mem, delta, slip_t, tx, ty, dt):
    """One step of the contact law: updates ``mem``; the normal and friction force.

    Implicit in the memory: delta_max = max(delta_max, delta), the friction spring by
    :func:`tangential_step`; separation (``mem[M_ON]`` = 0) when the normal force has
    returned to zero on unloading. Returns (on, fn, ft, sticking, z, release_x, release_y).
    """
    started = mem[M_STARTED] != 0.0 or delta > 0.0
    delta_max = mem[M_DMAX]
    on = mem[M_ON] != 0.0
    fn = 0.0
    if started:
        delta_max = max(delta_max, delta)
        fn = normal_force(delta, delta_max, par[P_EPS], par[P_PRELOAD], par[P_STIFFNESS])
        if fn <= 0.0 and delta < delta_max:
            on = False
            fn = 0.0
    z, ft, sticking = 0.0, 0.0, False
    mu = par[P_FRICTION]
    if mu > 0.0 and on:
        kt = par[P_KT]
        limit = mu * fn / kt
        z = tangential_step(mem[M_Z], slip_t, dt, limit, par[P_RECOVERY])
        ft = tangential_force(z, kt, mu * fn)
        sticking = abs(z) < limit * (1 - 1e-9)
    rx, ry = plastic_release(par[P_RECOVERY], mem[M_Z], mem[M_SLIP], slip_t, mem[M_FFX],
                             mem[M_FFY])
    mem[M_ON] = 1.0 if on else 0.0
    mem[M_STARTED] = 1.0 if started else 0.0
    mem[M_SEPARATED] = 0.0 if on else 1.0
    mem[M_DMAX] = delta_max
    mem[M_PREV_DELTA] = mem[M_DELTA]
    mem[M_DELTA] = delta
    mem[M_Z] = z
    mem[M_SLIP] = slip_t
    mem[M_FFX] = ft * tx
    mem[M_FFY] = ft * ty
    return on, fn, ft, sticking, z, rx, ry


def _tally(par, tal, st, trig, px, py, nx, ny, fx, fy, sticking, z, dt):
    """Account for one step in contact (impulse, centroids, peak, stick time, directions)."""
    size = math.sqrt(fx * fx + fy * fy)     # not hypot: numba's and the C library's differ
    w = size * dt
    tal[T_IMPULSE] += fx * dt
    tal[T_IMPULSE + 1] += fy * dt
    tal[T_MOMENT] += w * px
    tal[T_MOMENT + 1] += w * py
    tal[T_NORMAL] += w * nx
    tal[T_NORMAL + 1] += w * ny
    c, s = trig[0], trig[1]                 # turned back by -theta1 into vehicle 1's frame
    dx, dy = px - st[0], py - st[1]
    tal[T_BODY_POINT] += w * (c * dx + s * dy)
    tal[T_BODY_POINT + 1] += w * (c * dy - s * dx)
    c, s = trig[2], trig[3]                 # by -theta2 into vehicle 2's
    tal[T_BODY_NORMAL] += w * (c * nx + s * ny)
    tal[T_BODY_NORMAL + 1] += w * (c * ny - s * nx)
    tal[T_WEIGHT] += w
    tal[T_CONTACT] += dt
    if sticking:
        tal[T_STICK] += dt
    tal[T_PEAK] = max(tal[T_PEAK], size)
    if par[P_FRICTION] > 0.0 and not sticking and z != 0.0:
        if z > 0.0:
            tal[T_SLID_POS] = 1.0
        else:
            tal[T_SLID_NEG] = 1.0


def contact_loads(par, mem, tal, st, trig, dt, px, py, nx, ny, delta, slip_n, slip_t, overlap):
    """The contact force of one step at the geometry (px .. slip_t, ``overlap``): the law,
    the plastic release and the tally (``trig``: :func:`angles` of ``st``).

    Returns (applied, fx, fy, m1, m2, fn, ft, sticking): the force on vehicle 1 (-F on
    vehicle 2) at P and its moments about each CG; zeros unless the contact is on and has
    started.
    """
    if mem[M_STARTED] != 0.0 or delta > 0.0:
        if tal[T_HAS_INITIAL] == 0.0:
            tal[T_HAS_INITIAL] = 1.0
            tal[T_INITIAL_SIGN] = math.copysign(1.0, slip_t) if slip_t != 0.0 else 0.0
        tal[T_LAST_SLIP] = slip_t
    if par[P_OUTLINE] != 0.0 and overlap:
        tal[T_LAST_SLIP_N] = slip_n
    tx, ty = -ny, nx
    on, fn, ft, sticking, z, rx, ry = contact_law(par, mem, delta, slip_t, tx, ty, dt)
    if overlap:
        mem[M_NX] = nx
        mem[M_NY] = ny
        mem[M_HAS_NORMAL] = 1.0
    if not (on and mem[M_STARTED] != 0.0):
        return False, 0.0, 0.0, 0.0, 0.0, fn, ft, sticking
    fx = fn * nx + ft * tx + rx
    fy = fn * ny + ft * ty + ry
    _tally(par, tal, st, trig, px, py, nx, ny, fx, fy, sticking, z, dt)
    d1x, d1y = px - st[0], py - st[1]
    d2x, d2y = px - st[6], py - st[7]
    if par[P_FROZEN] != 0.0:                # the arms of the frozen geometry
        d1x, d1y = par[P_FROZEN_ARMS], par[P_FROZEN_ARMS + 1]
        d2x, d2y = par[P_FROZEN_ARMS + 2], par[P_FROZEN_ARMS + 3]
    return (True, fx, fy, d1x * fy - d1y * fx, -(d2x * fy - d2y * fx), fn, ft, sticking)


def total_loads(par, st, trig, lo, tal, dt, fx, fy, m1, m2):
    """The loads of this step's kick into ``lo``: the contact force (fx, fy) on vehicle 1 at
    moments m1, m2 (-F on vehicle 2) plus the tyre forces at the end of the step
    (:func:`ahead` of the last kick); adds the tyres' work to the tally."""
    vx1, vy1, w1, vx2, vy2, w2 = ahead(par, st, lo, 0.5 * dt)
    t1x, t1y, n1, t2x, t2y, n2, power = tyre_loads(par, vx1, vy1, w1, vx2, vy2, w2, trig)
    tal[T_TYRE_WORK] += power * dt
    lo[0] = fx + t1x
    lo[1] = fy + t1y
    lo[2] = m1 + n1
    lo[3] = -fx + t2x
    lo[4] = -fy + t2y
    lo[5] = m2 + n2


def half_kick(par, st, lo):
    """Start the leapfrog: the tyre loads at t = 0 into ``lo`` (the contact force is zero
    there) and the velocities half a step on, (vx1, vy1, w1, vx2, vy2, w2); the velocities
    of ``st`` unchanged without tyres."""
    if not par[P_TYRE] > 0.0:
        return st[3], st[4], st[5], st[9], st[10], st[11]
    t1x, t1y, n1, t2x, t2y, n2, _ = tyre_loads(par, st[3], st[4], st[5], st[9], st[10],
                                               st[11], angles(st))
    lo[0], lo[1], lo[2], lo[3], lo[4], lo[5] = t1x, t1y, n1, t2x, t2y, n2
    return ahead(par, st, lo, 0.5 * par[P_DT])


# ---- the outline contact (sim.overlap's module notes) ------------------------------------------
def place_corners(par, corners, x, y, c, s, wk, out):
    """Body-frame corners ``par[corners:corners + 8]`` placed at (x, y), turned by the angle
    of cos ``c`` and sin ``s``, into ``wk[out:out + 8]`` (world x, y pairs)."""
    for k in range(4):
        bx, by = par[corners + 2 * k], par[corners + 2 * k + 1]
        wk[out + 2 * k] = x + c * bx - s * by
        wk[out + 2 * k + 1] = y + s * bx + c * by


def clip_polygon(wk, subject, m, clipper, k, buf_a, buf_b):
    """Sutherland-Hodgman: the convex counter-clockwise polygon ``wk[subject:]`` (m x, y
    pairs) clipped by the convex counter-clockwise ``wk[clipper:]`` (k pairs), ping-ponging
    between the buffers ``wk[buf_a:]`` and ``wk[buf_b:]`` (m + k pairs each).

    Returns (offset, count) of the intersection in ``wk`` (count 0: apart).
    """
    src, dst = buf_a, buf_b
    for j in range(2 * m):
        wk[src + j] = wk[subject + j]
    count = m
    for i in range(k):
        if count == 0:
            break
        i2 = (i + 1) % k
        ax, ay = wk[clipper + 2 * i], wk[clipper + 2 * i + 1]
        ex, ey = wk[clipper + 2 * i2] - ax, wk[clipper + 2 * i2 + 1] - ay
        out = 0
        for j in range(count):
            j2 = (j + 1) % count
            xj, yj = wk[src + 2 * j], wk[src + 2 * j + 1]
            xn, yn = wk[src + 2 * j2], wk[src + 2 * j2 + 1]
            side = ex * (yj - ay) - ey * (xj - ax)       # inside >= 0 (left of the edge)
            side_next = ex * (yn - ay) - ey * (xn - ax)
            if side >= 0:
                wk[dst + 2 * out], wk[dst + 2 * out + 1] = xj, yj
                out += 1
            if (side >= 0) != (side_next >= 0):
                f = side / (side - side_next)
                wk[dst + 2 * out] = xj + f * (xn - xj)
                wk[dst + 2 * out + 1] = yj + f * (yn - yj)
                out += 1
        src, dst = dst, src
        count = out
    return src, count


def area_centroid(wk, poly, m):
    """Shoelace area [m^2] (>= 0) and centroid of ``wk[poly:]`` (m pairs, counter-clockwise);
    (0, nan, nan) for fewer than 3 corners, the mean corner for a zero area."""
    if m < 3:
        return 0.0, math.nan, math.nan
    total, sx, sy, mx, my = 0.0, 0.0, 0.0, 0.0, 0.0
    for j in range(m):
        j2 = (j + 1) % m
        x, y = wk[poly + 2 * j], wk[poly + 2 * j + 1]
        xn, yn = wk[poly + 2 * j2], wk[poly + 2 * j2 + 1]
        cross = x * yn - xn * y
        total += cross
        sx += (x + xn) * cross
        sy += (y + yn) * cross
        mx += x
        my += y
    area = 0.5 * total
    if area == 0.0:
        return 0.0, mx / m, my / m
    return abs(area), sx / (6.0 * area), sy / (6.0 * area)


def _extent(wk, poly, m, ax, ay):
    """Smallest and largest projection of the corners of ``wk[poly:]`` on (ax, ay)."""
    low, high = math.inf, -math.inf
    for j in range(m):
        p = wk[poly + 2 * j] * ax + wk[poly + 2 * j + 1] * ay
        low = min(low, p)
        high = max(high, p)
    return low, high


def separating_axis(wk, p1, m1, p2, m2):
    """The edge normal of either polygon along which they overlap least, from polygon 2
    toward polygon 1, and that overlap [m] (negative: apart along it); the first such edge
    (polygon 1's edges first, each polygon's in order)."""
    best, bx, by = math.inf, math.nan, math.nan
    for q in range(m1 + m2):
        poly, m, e = (p1, m1, q) if q < m1 else (p2, m2, q - m1)
        e2 = (e + 1) % m
        ex = wk[poly + 2 * e2] - wk[poly + 2 * e]
        ey = wk[poly + 2 * e2 + 1] - wk[poly + 2 * e + 1]
        norm = math.sqrt(ey * ey + ex * ex)
        ax, ay = ey / norm, -ex / norm                   # outward for counter-clockwise
        low1, high1 = _extent(wk, p1, m1, ax, ay)
        low2, high2 = _extent(wk, p2, m2, ax, ay)
        forward, backward = high2 - low1, high1 - low2
        depth = min(forward, backward)
        if depth < best:
            best = depth
            bx, by = (ax, ay) if forward <= backward else (-ax, -ay)
    return bx, by, best


def outline_overlap(wk, p1, m1, p2, m2, buf_a, buf_b):
    """The overlap of two convex counter-clockwise polygons (``wk[p1:]``, ``wk[p2:]``):
    (area [m^2], centroid x, y [m], normal x, y (separating axis of least overlap, from 2
    toward 1), width along the tangent [m], mean crush area / width [m], overlap along the
    normal [m])."""
    region, m = clip_polygon(wk, p1, m1, p2, m2, buf_a, buf_b)
    area, cx, cy = area_centroid(wk, region, m)
    nx, ny, axis_depth = separating_axis(wk, p1, m1, p2, m2)
    if area <= 0.0:
        return 0.0, cx, cy, nx, ny, 0.0, 0.0, axis_depth
    low, high = _extent(wk, region, m, -ny, nx)
    width = high - low
    return area, cx, cy, nx, ny, width, area / width if width > 0 else 0.0, axis_depth


def place_outlines(par, x1, y1, c1, s1, x2, y2, c2, s2, wk):
    """Both outlines' world corners into ``wk[W_POLY1:]`` and ``wk[W_POLY2:]`` (a fixed
    obstacle's block as it is)."""
    place_corners(par, P_OUTLINE1, x1, y1, c1, s1, wk, W_POLY1)
    if par[P_OBSTACLE] != 0.0:
        for j in range(8):
            wk[W_POLY2 + j] = par[P_OUTLINE2 + j]
    else:
        place_corners(par, P_OUTLINE2, x2, y2, c2, s2, wk, W_POLY2)


def outline_geometry(par, mem, st, trig, wk):
    """The outline contact at ``st``: (px, py, nx, ny, delta, slip_n, slip_t, overlap,
    flipped) as :func:`point_geometry` gives the point contact's (docs/contact-model.md):
    the force acts at the overlap's centroid along the separating axis, with the mean crush
    area / width; apart, the crush is 0 and the normal that of the last overlap (``mem``).
    ``flipped``: the normal turned against the last one (the outlines passed through each
    other)."""
    place_outlines(par, st[0], st[1], trig[0], trig[1], st[6], st[7], trig[2], trig[3], wk)
    area, cx, cy, nx, ny, _, depth, _ = outline_overlap(wk, W_POLY1, 4, W_POLY2, 4, W_A, W_B)
    has_normal = mem[M_HAS_NORMAL] != 0.0
    if area <= 0.0:
        if has_normal:
            nx, ny = mem[M_NX], mem[M_NY]
        return 0.0, 0.0, nx, ny, 0.0, 0.0, 0.0, False, False
    flipped = has_normal and nx * mem[M_NX] + ny * mem[M_NY] < 0.0
    d1x, d1y, d2x, d2y = cx - st[0], cy - st[1], cx - st[6], cy - st[7]
    relx = st[3] + st[5] * -d1y - st[9] - st[11] * -d2y
    rely = st[4] + st[5] * d1x - st[10] - st[11] * d2x
    return (cx, cy, nx, ny, depth, relx * nx + rely * ny, relx * -ny + rely * nx, True,
            flipped)


def outlines_touch(par, s0, t, wk):
    """Whether the outlines overlap at time ``t`` [s] along the free paths from ``s0``."""
    th1, th2 = s0[2] + s0[5] * t, s0[8] + s0[11] * t
    place_outlines(par, s0[0] + s0[3] * t, s0[1] + s0[4] * t, math.cos(th1), math.sin(th1),
                   s0[6] + s0[9] * t, s0[7] + s0[10] * t, math.cos(th2), math.sin(th2), wk)
    region, m = clip_polygon(wk, W_POLY1, 4, W_POLY2, 4, W_A, W_B)
    return area_centroid(wk, region, m)[0] > 0.0


def outline_start(par, s0, wk):
    """When the outlines first touch [s] along the free pre-impact paths (<= 0; 0 when
    apart at t = 0): stepping back 10 ms at a time, then 60 bisections. NaN when they
    overlap along the whole 10 s back (they never approach: "tunnelled")."""
    if not outlines_touch(par, s0, 0.0, wk):
        return 0.0
    step = 0.01
    back = step
    while outlines_touch(par, s0, -back, wk):
        back += step
        if back > 10.0:
            return math.nan
    low, high = -back, -back + step       # apart at low, overlapping at high
    for _ in range(60):
        mid = 0.5 * (low + high)
        if outlines_touch(par, s0, mid, wk):
            high = mid
        else:
            low = mid
    return low


def free_state(s0, t, st):
    """``s0`` moved along the free paths to time ``t`` [s], into ``st``."""
    for j in range(12):
        st[j] = s0[j]
    for k in range(2):
        j = 6 * k
        st[j] = s0[j] + s0[j + 3] * t
        st[j + 1] = s0[j + 1] + s0[j + 4] * t
        st[j + 2] = s0[j + 2] + s0[j + 5] * t


# ---- Chipmunk's integration (what pymunk does in C) --------------------------------------------
def drift(par, st, dt):
    """cpBodyUpdatePosition of both bodies: p += (v + v_bias) dt, a += (w + w_bias) dt
    (the biases are zero: no collision shapes); a fixed body does not move."""
    for k in range(2):
        if k == 1 and par[P_FIXED2] != 0.0:
            break
        j = 6 * k
        st[j] = st[j] + (st[j + 3] + 0.0) * dt
        st[j + 1] = st[j + 1] + (st[j + 4] + 0.0) * dt
        st[j + 2] = st[j + 2] + (st[j + 5] + 0.0) * dt


def kick(par, st, lo, dt):
    """cpBodyUpdateVelocity of both bodies (gravity 0, damping 1): v = v + f m_inv dt,
    w = w + t i_inv dt, with m_inv = 1 / m and i_inv = 1 / I as Chipmunk stores them
    (``par[P_INVERSE:]``, computed once as Chipmunk does)."""
    for k in range(2):
        if k == 1 and par[P_FIXED2] != 0.0:
            break
        m_inv = par[P_INVERSE + 2 * k]
        i_inv = par[P_INVERSE + 2 * k + 1]
        j = 6 * k
        st[j + 3] = st[j + 3] * 1.0 + (0.0 + lo[3 * k] * m_inv) * dt
        st[j + 4] = st[j + 4] * 1.0 + (0.0 + lo[3 * k + 1] * m_inv) * dt
        st[j + 5] = st[j + 5] * 1.0 + lo[3 * k + 2] * i_inv * dt


# ---- after the contact -------------------------------------------------------------------------
def separation_time(mem, start, steps, dt, delta_p):
    """The separation instant [s], interpolated between the last two crushes."""
    frac = 1.0
    prev, now = mem[M_PREV_DELTA], mem[M_DELTA]
    if prev != now:
        frac = min(max((prev - delta_p) / (prev - now), 0.0), 1.0)
    return start + (steps - 1 + frac) * dt


def post_velocities(par, st, lo, now, t_end):
    """(vx1, vy1, w1, vx2, vy2, w2) at the separation instant ``t_end`` [s].

    The leapfrog's velocities after the last step belong half a step past its end (``now``);
    without tyres nothing acts after separation and they are the answer; with tyres they are
    taken back to ``t_end`` along the last kick's (tyre) accelerations.
    """
    if not par[P_TYRE] > 0.0:
        return st[3], st[4], st[5], st[9], st[10], st[11]
    return ahead(par, st, lo, -(0.5 * par[P_DT] + now - t_end))


def slip_reversed(initial_sign, final_slip, speed_scale, slid_pos, slid_neg):
    """Whether the tangential slip reversed: the contact slid both ways, or left with a
    tangential velocity opposite to the one it met with (beyond 1e-6 of the speed scale)."""
    rebound = initial_sign != 0.0 and final_slip * initial_sign < -1e-6 * speed_scale
    return (slid_pos and slid_neg) or rebound


def _centroid(total_x, total_y, weight):
    return (total_x / weight, total_y / weight) if weight > 0.0 else (math.nan, math.nan)


def _unit(total_x, total_y, weight):
    size = math.sqrt(total_x * total_x + total_y * total_y)
    if weight > 0.0 and size > 0.0:
        return total_x / size, total_y / size
    return math.nan, math.nan


def write_outputs(par, mem, tal, out, steps, t_end, post):
    """One scene's outputs into ``out`` (:data:`N_OUT`, indices ``O_*``): the post-impact
    motion ``post`` (:func:`post_velocities`), the contact time, the tally's impulse,
    centroids (NaN without contact force), peak force, crushes, tyre work, stick fraction,
    slip reversal (1.0 / 0.0) and the step count."""
    out[O_V1], out[O_V1 + 1], out[O_W1] = post[0], post[1], post[2]
    out[O_V2], out[O_V2 + 1], out[O_W2] = post[3], post[4], post[5]
    out[O_DURATION] = t_end - par[P_START]
    out[O_IMPULSE], out[O_IMPULSE + 1] = tal[T_IMPULSE], tal[T_IMPULSE + 1]
    weight = tal[T_WEIGHT]
    out[O_POINT], out[O_POINT + 1] = _centroid(tal[T_MOMENT], tal[T_MOMENT + 1], weight)
    out[O_NORMAL], out[O_NORMAL + 1] = _unit(tal[T_NORMAL], tal[T_NORMAL + 1], weight)
    out[O_BODY_POINT], out[O_BODY_POINT + 1] = _centroid(tal[T_BODY_POINT],
                                                         tal[T_BODY_POINT + 1], weight)
    out[O_BODY_NORMAL], out[O_BODY_NORMAL + 1] = _unit(tal[T_BODY_NORMAL],
                                                       tal[T_BODY_NORMAL + 1], weight)
    out[O_PEAK_FORCE] = tal[T_PEAK]
    out[O_PEAK_CRUSH] = mem[M_DMAX]
    out[O_PERMANENT] = permanent_crush(mem[M_DMAX], par[P_EPS], par[P_PRELOAD],
                                       par[P_STIFFNESS])
    out[O_TYRE_WORK] = tal[T_TYRE_WORK]
    out[O_STICK] = tal[T_STICK] / max(tal[T_CONTACT], 1e-300)
    initial = tal[T_INITIAL_SIGN] if tal[T_HAS_INITIAL] != 0.0 else 0.0
    out[O_REVERSED] = 1.0 if slip_reversed(initial, tal[T_LAST_SLIP], par[P_SPEED],
                                           tal[T_SLID_POS] != 0.0,
                                           tal[T_SLID_NEG] != 0.0) else 0.0
    out[O_STEPS] = steps
    out[O_START] = par[P_START]
