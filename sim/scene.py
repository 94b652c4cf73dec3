"""Build a pymunk Space that recreates one PIM case.

What PIM assumes, and how the scene reproduces it (default settings)
--------------------------------------------------------------------
* Two rigid bodies with the case's mass and yaw inertia about the CG (pymunk's centre of
  gravity is the body origin), at the CGs, headings, velocities and yaw rates of the case;
  a fixed obstacle (infinite mass) is a static body. No gravity, no damping, no tyre forces.
* One contact point at C with normal n = (cos Gamma, sin Gamma): a small circle on vehicle 1
  that touches C from the n side, against a segment through C along the tangent on
  vehicle 2. Circle-segment contacts always give exactly one point, with the segment's
  normal.
* Restitution: Chipmunk's contact target is the kinematic (Newton) one, vn_after =
  -e vn_before, with e = product of the shapes' elasticities; the circle gets epsilon, the
  segment 1.
* Friction: a Coulomb clamp |Pt| <= u Pn with u = product of the shapes' frictions. For
  beta = 1 u is set to :data:`STICK_MARGIN` x |mu0| (at least 1), so the contact sticks
  (U_t = 0); for beta < 1 u = beta |mu0|, so the contact slides with Pt = mu Pn,
  mu = beta mu0 (mu0 from :func:`pim.solve`).
* Placement: Chipmunk integrates positions *before* it detects collisions in a step, so
  with ``start="exact"`` the bodies start one step back along their free paths (p - v dt,
  angle - w dt) and reach the impact configuration exactly when the contact is found;
  the pre-solve callback of :mod:`sim.run` also pins both contact points to C, which
  removes the lever-arm error of the circle's small overlap.

The vehicles' length x width rectangles are only drawn in this default; ``contact =
"outline"`` makes them the colliding shapes instead.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pymunk

import pim
from pim.model import geometry
from pim.model.numbers import InputError
from pim.model.solver import constraints

from .convergence import auto_iterations, contraction_rate
from .settings import Settings

__all__ = ["Scene", "build_scene", "resolve_coefficients", "outline_corners", "footprint_lever",
           "STICK_MARGIN", "TYPE1", "TYPE2"]

#: For beta = 1 the contact friction is this many times |mu0| (and at least 1): sticking.
STICK_MARGIN = 10.0
#: In exact placement the contact circle overlaps the segment by this fraction of its radius,
#: so that the engine detects it; the contact points are then pinned to C.
EXACT_OVERLAP = 1e-3
#: Collision types of vehicle 1's and vehicle 2's shapes.
TYPE1, TYPE2 = 1, 2


def _scalar_case(case: pim.Case) -> None:
    sizes = [np.size(x) for x in (case.vehicle1.mass, case.vehicle1.yaw_inertia,
                                  case.vehicle1.yaw_rate, case.vehicle1.heading,
                                  case.vehicle2.mass, case.vehicle2.yaw_inertia,
                                  case.vehicle2.yaw_rate, case.vehicle2.heading,
                                  case.impact.normal_angle)]
    sizes += [np.size(x) // 2 for x in (case.vehicle1.cg, case.vehicle1.velocity,
                                        case.vehicle2.cg, case.vehicle2.velocity,
                                        case.impact.point)]
    if max(sizes) != 1:
        raise InputError("sim.simulate needs a single case (every field a scalar or one "
                         "[x, y] pair); use sim.simulate_many for arrays of cases")


def resolve_coefficients(case: pim.Case, eps=None, beta=None) -> tuple[float, float]:
    """epsilon and beta as :func:`pim.solve` would take them, checked for the simulator.

    Raises
    ------
    ValueError
        eps outside [0, 1], or beta outside [0, 1]: Coulomb friction can neither exceed the
        sticking impulse ratio (beta > 1) nor push the sliding the wrong way (beta < 0).
    """
    eps, beta = (float(x) for x in constraints(case, eps, beta))
    if not 0.0 <= beta <= 1.0:
        raise InputError(f"beta must be in [0, 1] for the simulator (Coulomb friction cannot "
                         f"reverse sliding or push it the wrong way), got {beta:g}")
    return eps, beta


def outline_corners(vehicle: pim.Vehicle) -> np.ndarray | None:
    """Corners of the vehicle's length x width rectangle in its body frame [m], or None."""
    if vehicle.length is None or vehicle.width is None:
        return None
    return geometry.outline_corners(vehicle.length, vehicle.width, vehicle.cg_to_front)


def footprint_lever(vehicle: pim.Vehicle) -> float:
    """Mean distance [m] of a uniformly loaded length x width footprint from its CG.

    Sets the yaw deceleration of the tyre-friction model (midpoint rule on a 32 x 32 grid);
    the radius of gyration when the vehicle has no outline.
    """
    if vehicle.length is None or vehicle.width is None:
        return float(geometry.radius_of_gyration(vehicle.mass, vehicle.yaw_inertia))
    g = (np.arange(32) + 0.5) / 32 * 2 - 1
    x, y = np.meshgrid(g * vehicle.length / 2, g * vehicle.width / 2)
    return float(np.mean(np.hypot(x, y)))


@dataclass(eq=False)
class Scene:
    """A built pymunk scene and what the runner needs to know about it.

    Attributes
    ----------
    space : pymunk.Space
        The space, bodies and contact shapes added (no collision handler yet).
    body1, body2 : pymunk.Body
        The vehicles (``body2`` static when fixed).
    contact_shapes : list of pymunk.Shape
        The colliding shapes: circle on 1 and segment on 2 (point contact), or the outlines.
    fixed2 : bool
        Vehicle 2 is a fixed obstacle.
    eps : float
        Restitution epsilon [-].
    beta : float
        Fraction of mu0 [-].
    friction : float
        Coulomb coefficient u of the contact [-]: STICK_MARGIN |mu0| (at least 1) for
        beta = 1, beta |mu0| below (mu_c in a Kudlich-Slibar scene).
    start_time : float
        Time at which the bodies start [s] (<= 0; t = 0 is PIM's impact instant).
    point : ndarray (2,)
        The impact point C [m].
    normal : ndarray (2,)
        The contact normal n = (cos Gamma, sin Gamma) [-].
    approach_n : float
        Normal approach velocity u_n at C before the impact [m/s] (negative: approaching).
    speed_scale : float
        Largest of |u| and the pre-impact speeds [m/s] (at least 1e-6), for tolerances.
    energy_before : float
        Kinetic energy of both vehicles before the impact [J].
    outline1, outline2 : ndarray (4, 2) or None
        Corners of each length x width outline in its body frame [m] (None without length
        and width).
    lever1, lever2 : float
        Mean distance of each footprint from its CG [m] (:func:`footprint_lever`; for tyre
        friction after separation; ``lever2`` 0 when fixed).
    iterations : int
        Solver sweeps per step in use [-].
    contraction_rate : float
        Predicted error factor per sweep rho [-] (:mod:`sim.convergence`).
    k : tuple of float
        K_nn, K_nt, K_tt of PIM's contact [1/kg].
    """

    space: pymunk.Space
    body1: pymunk.Body
    body2: pymunk.Body
    contact_shapes: list = field(default_factory=list)
    fixed2: bool = False
    eps: float = 0.0
    beta: float = 1.0
    friction: float = 0.0
    start_time: float = 0.0        # [s], t = 0 is PIM's impact instant
    point: np.ndarray = None       # C [m]
    normal: np.ndarray = None      # n [-]
    approach_n: float = 0.0        # u_n at C before impact [m/s]
    speed_scale: float = 1.0       # [m/s], for tolerances
    energy_before: float = 0.0     # [J]
    outline1: np.ndarray | None = None
    outline2: np.ndarray | None = None
    lever1: float = 0.0            # footprint_lever of each vehicle [m] (tyre friction)
    lever2: float = 0.0
    iterations: int = 0            # solver sweeps per step in use
    contraction_rate: float = 0.0  # predicted error factor per sweep (sim.convergence)
    k: tuple = (0.0, 0.0, 0.0)     # K_nn, K_nt, K_tt of PIM's contact [1/kg]


def _make_body(vehicle: pim.Vehicle, lead: float) -> pymunk.Body:
    """A pymunk body for ``vehicle``, started ``lead`` [s] before the impact pose (static if
    fixed)."""
    cg = np.asarray(vehicle.cg, float).reshape(2)
    heading = float(vehicle.heading)
    if vehicle.fixed:
        body = pymunk.Body(body_type=pymunk.Body.STATIC)
        body.position = (float(cg[0]), float(cg[1]))
        body.angle = heading
        return body
    vel = np.asarray(vehicle.velocity, float).reshape(2)
    w = float(vehicle.yaw_rate)
    body = pymunk.Body(float(vehicle.mass), float(vehicle.yaw_inertia))
    start = cg - vel * lead
    body.position = (float(start[0]), float(start[1]))
    body.angle = heading - w * lead
    body.velocity = (float(vel[0]), float(vel[1]))
    body.angular_velocity = w
    return body


def _local(vehicle: pim.Vehicle, world) -> tuple[float, float]:
    """World point at the impact configuration -> the vehicle's body frame."""
    p = geometry.rotate(np.asarray(world, float) - np.asarray(vehicle.cg, float).reshape(2),
                        -float(vehicle.heading))
    return float(p[0]), float(p[1])


def _contact_shapes(case: pim.Case, body1: pymunk.Body, body2: pymunk.Body, *, point, n, t,
                    u, lead: float, settings: Settings, eps: float, friction: float) -> list:
    """The contact shapes (a point: a circle on 1 and a segment on 2; an outline: the two
    boxes or a barrier face), with their collision types, restitution and friction: C at
    ``point`` with the normal ``n`` and tangent ``t``, the approach velocity ``u``, the
    bodies ``lead`` [s] before the impact."""
    v1, v2 = case.vehicle1, case.vehicle2
    fixed2 = bool(v2.fixed)
    shapes = []
    rc = settings.contact_radius
    if settings.contact == "point":
        overlap = EXACT_OVERLAP * rc if settings.start == "exact" else 0.0
        circle = pymunk.Circle(body1, rc, _local(v1, point + (rc - overlap) * n))
        reach = abs(float(u @ t)) * (lead + settings.dt) + 4.0 * rc
        half = max(1.0, 2.0 * reach)
        segment = pymunk.Segment(body2, _local(v2, point - half * t), _local(v2, point + half * t),
                                 0.0)
        pairs = [(circle, TYPE1, eps, friction), (segment, TYPE2, 1.0, 1.0)]
    else:
        corners1, corners2 = outline_corners(v1), outline_corners(v2)
        if corners1 is None:
            raise InputError("contact='outline' needs vehicle1.length and vehicle1.width")
        if corners2 is None and not fixed2:
            raise InputError("contact='outline' needs vehicle2.length and vehicle2.width")
        box1 = pymunk.Poly(body1, [tuple(c) for c in corners1])
        if corners2 is not None:
            box2 = pymunk.Poly(body2, [tuple(c) for c in corners2])
        else:  # a barrier without dimensions: a long straight face through C along t
            half = max(100.0, 10.0 * float(np.hypot(*(np.asarray(v1.cg).reshape(2) - point))))
            box2 = pymunk.Segment(body2, _local(v2, point - half * t), _local(v2, point + half * t),
                                  0.0)
        pairs = [(box1, TYPE1, eps, friction), (box2, TYPE2, 1.0, 1.0)]
    for shape, kind, elasticity, mu in pairs:
        shape.collision_type = kind
        shape.elasticity = elasticity
        shape.friction = mu
        shapes.append(shape)
    return shapes


def build_scene(case: pim.Case, eps=None, beta=None, settings: Settings | None = None,
                analytic: pim.Result | None = None) -> Scene:
    """A pymunk Space recreating ``case`` at (eps, beta), ready to step.

    Parameters
    ----------
    case : pim.Case
        A single case (scalar fields).
    eps, beta : float, optional
        Restitution [-] and fraction of mu0 [-], both in [0, 1]; default like
        :func:`pim.solve` (from ``case.impact``).
    settings : Settings, optional
        Switches and numerics; default ``Settings()``.
    analytic : pim.Result, optional
        ``pim.solve(case, eps, 1.0)`` if already computed (it provides mu0 for the friction).

    Returns
    -------
    Scene
        The Space (no collision handler yet; :func:`sim.run.run_scene` adds it), bodies and
        contact data. Time 0 is the impact instant; the bodies start at ``start_time < 0``.
    """
    settings = settings or Settings()
    _scalar_case(case)
    eps, beta = resolve_coefficients(case, eps, beta)
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    if analytic is None:
        analytic = pim.solve(case, eps, 1.0, law="brach")
    mu0 = float(np.asarray(analytic.mu0).reshape(()))
    if not np.isfinite(mu0):
        mu0 = 0.0
    friction = max(STICK_MARGIN * abs(mu0), 1.0) if beta >= 1.0 else beta * abs(mu0)

    point = np.asarray(imp.point, float).reshape(2)
    gamma = float(imp.normal_angle)
    n = np.array([np.cos(gamma), np.sin(gamma)])
    t = np.array([-n[1], n[0]])
    fixed2 = bool(v2.fixed)
    lead = settings.dt if settings.start == "exact" else settings.lead_steps * settings.dt

    k_nn, k_nt, k_tt = (float(np.asarray(getattr(analytic, k)).reshape(()))
                        for k in ("k_nn", "k_nt", "k_tt"))
    rho = contraction_rate(k_nn, k_nt, k_tt, friction, beta >= 1.0)
    iterations = settings.iterations if settings.iterations is not None else auto_iterations(rho)

    space = pymunk.Space()
    space.iterations = iterations
    space.gravity = (0.0, 0.0)
    space.damping = 1.0
    space.collision_slop = 1e-4 * settings.contact_radius

    body1, body2 = _make_body(v1, lead), _make_body(v2, lead)

    u = analytic.approach_velocity
    u = np.asarray(u, float).reshape(2)
    speed_scale = max(float(np.hypot(*u)), float(np.hypot(*np.asarray(v1.velocity).reshape(2))),
                      0.0 if fixed2 else float(np.hypot(*np.asarray(v2.velocity).reshape(2))),
                      1e-6)
    shapes = _contact_shapes(case, body1, body2, point=point, n=n, t=t, u=u, lead=lead,
                             settings=settings, eps=eps, friction=friction)
    space.add(body1, body2, *shapes)

    return Scene(space=space, body1=body1, body2=body2, contact_shapes=shapes, fixed2=fixed2,
                 eps=eps, beta=beta, friction=friction, start_time=-lead, point=point, normal=n,
                 approach_n=float(np.asarray(analytic.approach_n).reshape(())),
                 speed_scale=speed_scale, energy_before=float(
                     geometry.kinetic_energy(v1.mass, v1.yaw_inertia, v1.velocity, v1.yaw_rate)
                     + geometry.kinetic_energy(v2.mass, v2.yaw_inertia, v2.velocity, v2.yaw_rate)),
                 outline1=outline_corners(v1), outline2=outline_corners(v2),
                 lever1=footprint_lever(v1),
                 lever2=0.0 if fixed2 else footprint_lever(v2),
                 iterations=iterations, contraction_rate=rho, k=(k_nn, k_nt, k_tt))
