"""What both integrators of the finite-duration contact share: settings, the validated
physical problem, the point-contact kinematics, and the typed result.

The problem takes only physical inputs (masses, inertias, pre-impact motion, C and Gamma of
the case; the crush stiffness, restitution epsilon, friction mu_c between the vehicles and
tyre friction) and never a PIM output (no mu0, no impulse, no fitted coefficient). The
stepping itself is not shared: :mod:`sim.compliant` steps pymunk, :mod:`sim.reference`
integrates the same equations with ``scipy.integrate.solve_ivp``.

Point contact (docs/contact-model.md)
-------------------------------------
A material point P of vehicle 1, at C when the contact begins (t = 0), against the contact
plane carried by vehicle 2 through its own material point Q (at C at t = 0) that turns with
vehicle 2: n(t) = R(theta_2(t) - theta_2(0)) n_0, t(t) = n(t) turned +90 deg. The crush is
the depth of P below the plane, delta = -(P - Q) . n, and d delta / dt = -v_rel . n exactly,
with v_rel the velocity of P on vehicle 1 minus that of the coincident point of vehicle 2.
The force F = F_n n + F_t t acts on vehicle 1 at P and -F on vehicle 2 at the same point, so
linear momentum and angular momentum about any fixed point are conserved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

import pim
from pim.model import geometry
from pim.model.geometry import cross, radius_of_gyration, rotate_by
from pim.model.numbers import InputError
from pim.model.tyres import STANDARD_GRAVITY

from . import compliant_formula as formula
from .contact_law import (
    check_fraction,
    check_positive,
    contact_duration_estimate,
    tangential_recovery_default,
)
from .contact_tyres import SLIP_REGULARISATION, TYRE_MODES, wheel_loads, wheels_from_outline
from .overlap import place
from .result import Trajectory
from .scene import outline_corners

__all__ = ["CompliantSettings", "CompliantProblem", "CompliantResult", "ContactHistory",
           "build_problem", "point_contact", "rotate", "GEOMETRIES", "DEFAULT_STIFFNESS",
           "kinetic_energy", "placed_outlines", "reversal", "refuse_frozen",
           "ENERGY_TOLERANCE", "ESTIMATE_MARGIN", "physics_status", "physics_refusal",
           "endless_contact"]

GEOMETRIES = ("point", "outline")
#: Default linear crush stiffness of a car [N/m] (NHTSA test 10146: 750-780 kN/m).
DEFAULT_STIFFNESS = 7.5e5
#: Kinetic energy a contact may end with above its start, relative [-], before the result
#: is refused ("energy_gained"): the contact only loses energy (hysteresis, friction, tyres),
#: and the fixed step's own error stays far below this (an elastic eps = 1 contact on every
#: bundled case at 1e4-1e8 N/m, with and without friction: at most 3.3e-5 gained).
ENERGY_TOLERANCE = 1e-3
#: A scene whose estimated contact duration exceeds ``settings.max_contact_time`` this many
#: times is refused before any step ("never_separated"). The estimate is the frictionless
#: point contact's; tyres and friction shorten a real one (RICSAC 9 at 1e3 N/m: 1.5 s
#: estimated, 0.78 s stepped), so the margin keeps such scenes for the stepping, whose
#: duration then meets the bound itself, and refuses only the absurd (1e-6 N/m: 4.7e4 s).
ESTIMATE_MARGIN = 10.0


@dataclass(frozen=True)
class CompliantSettings:
    """Numerics and model switches of the finite-duration contact.

    Parameters
    ----------
    dt : float or None
        pymunk's fixed step [s] in (0, 1]; None: the estimated contact duration divided by
        ``steps_per_contact``.
    steps_per_contact : int
        Steps per estimated contact duration when ``dt`` is None, >= ``min_steps``.
    min_steps : int
        Fewest steps per estimated contact duration accepted, >= 2; a coarser ``dt`` is
        reported as "tunnelled" (the contact would be crossed in a few steps).
    method : str
        ``solve_ivp`` method of the reference: "DOP853" (explicit, 8th order), "RK45",
        "Radau" or "BDF" (implicit), "LSODA".
    rtol : float
        Relative tolerance of the reference, in (0, 0.1].
    tangential_stiffness : float or None
        k_t [N/m] of the elastoplastic friction spring, > 0; None: equal to the normal
        stiffness k.
    tangential_recovery : float or None
        Share r [-] in [0, 1] of the stored tangential (elastic) energy the contact gives
        back (:mod:`sim.contact_law`, "Tangential recovery"); None: tied to the restitution,
        r = eps^2 (:func:`sim.contact_law.tangential_recovery_default`); 1: the fully
        elastic friction spring; 0: plastic.
    preload : float
        Force at zero crush a [N] >= 0 of the loading curve F = a + k delta (Campbell's A
        times the contact width; k is then Campbell's B times the width); default 0.
    tyre_mode : {"rolling", "locked"}
        Free-rolling wheels (lateral tyre force only) or locked wheels.
    max_contact_time : float
        Longest contact accepted [s], > 0; longer is "never_separated".
    max_phases : int
        Most smooth phases (between two crush or friction mode switches) the reference
        :func:`sim.reference_compliant` integrates, >= 1; more is "not_converged" (a
        chattering stick/slip switch). The bundled cases need at most 8
        (docs/contact-model.md, "Caps of the reference").
    max_steps : int
        Most accepted ``solve_ivp`` steps of the reference over all phases, >= 1; more is
        "not_converged" (a stiff scene on an explicit method, or a tolerance near round-off).
        The bundled cases need at most 24 502 at the default rtol.
    max_fixed_steps : int
        Most fixed steps of the stepped scene (pymunk or compiled), >= 1, fixed before it
        starts: the contact stops at min(max_contact_time / dt + 1, max_fixed_steps) steps
        ("never_separated"), and a free motion of ``duration`` that would need more steps is
        refused up front (ValueError naming ``settings.duration``). The default bounds a
        pymunk run to about 10 s; the default step takes 400 per contact.
    duration : float
        Free motion simulated after separation [s], >= 0 (animation, secondary impacts);
        tyre forces keep acting in it when tyre friction is on.
    record : bool
        Keep the contact history (force, crush, slip per step) and the trajectory.
    gravity : float
        g [m/s^2] for the tyres' static load, > 0.
    geometry_change : bool
        True (the physics): the point contact's arms and normal turn and move with the
        bodies during the contact. False, a study switch of the compiled engine only (the
        point contact; issue 34): they stay as at the start
        (:func:`sim.compliant_formula.frozen_point`), the rigid impact's geometry held
        through a finite contact.
    """

    dt: float | None = None
    steps_per_contact: int = 400
    min_steps: int = 10
    method: str = "DOP853"
    rtol: float = 1e-9
    tangential_stiffness: float | None = None
    tangential_recovery: float | None = None
    preload: float = 0.0
    tyre_mode: str = "rolling"
    max_contact_time: float = 1.0
    max_phases: int = 1000
    max_steps: int = 1_000_000
    max_fixed_steps: int = 200_000
    duration: float = 0.0
    record: bool = True
    gravity: float = STANDARD_GRAVITY
    geometry_change: bool = True

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if self.dt is not None:
            dt = check_positive(self.dt, "settings.dt", "s")
            if dt > 1.0:
                raise InputError(f"settings.dt must be in (0, 1] [s], got {dt!r}")
            set_(self, "dt", dt)
        for name, low in (("min_steps", 2), ("steps_per_contact", 2), ("max_phases", 1),
                          ("max_steps", 1), ("max_fixed_steps", 1)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                raise InputError(f"settings.{name} must be an integer >= {low}, got {value!r}")
        if self.steps_per_contact < self.min_steps:
            raise InputError(f"settings.steps_per_contact must be >= settings.min_steps "
                             f"({self.min_steps}), got {self.steps_per_contact}")
        methods = ("DOP853", "RK45", "Radau", "BDF", "LSODA")
        if self.method not in methods:
            raise InputError(f"settings.method must be one of {methods}, got {self.method!r}")
        rtol = check_positive(self.rtol, "settings.rtol", "-")
        if rtol > 0.1:
            raise InputError(f"settings.rtol must be in (0, 0.1], got {rtol!r}")
        set_(self, "rtol", rtol)
        if self.tangential_stiffness is not None:
            set_(self, "tangential_stiffness", check_positive(
                self.tangential_stiffness, "settings.tangential_stiffness", "N/m"))
        if self.tangential_recovery is not None:
            set_(self, "tangential_recovery", check_fraction(
                self.tangential_recovery, "settings.tangential_recovery"))
        set_(self, "preload", check_positive(self.preload, "settings.preload", "N",
                                             allow_zero=True))
        if self.tyre_mode not in TYRE_MODES:
            raise InputError(f"settings.tyre_mode must be one of {TYRE_MODES}, "
                             f"got {self.tyre_mode!r}")
        set_(self, "max_contact_time", check_positive(self.max_contact_time,
                                                      "settings.max_contact_time", "s"))
        set_(self, "duration", check_positive(self.duration, "settings.duration", "s",
                                              allow_zero=True))
        for name in ("record", "geometry_change"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"settings.{name} must be True or False, got "
                                 f"{getattr(self, name)!r}")
        set_(self, "gravity", check_positive(self.gravity, "settings.gravity", "m/s^2"))

    def as_dict(self) -> dict:
        """The settings as plain values (for JSON)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


def rotate(vec, angle: float) -> np.ndarray:
    """``vec`` (2,) turned counter-clockwise by ``angle`` [rad]
    (:func:`pim.model.geometry.rotate`)."""
    return geometry.rotate(vec, angle)


def kinetic_energy(mass, inertia, velocity, yaw_rate) -> float:
    """Translational plus rotational kinetic energy [J] of one body (0 if fixed), as a float
    (:func:`pim.model.geometry.kinetic_energy`)."""
    return float(geometry.kinetic_energy(mass, inertia, velocity, yaw_rate))


@dataclass(frozen=True, eq=False)
class CompliantProblem:
    """The validated inputs of one finite-duration impact (SI, global frame).

    ``state0`` is the state at t = 0 (point contact: first contact at C), 12 numbers:
    x1, y1, theta1, vx1, vy1, w1, x2, y2, theta2, vx2, vy2, w2.

    Attributes
    ----------
    case : pim.Case
        The (single) case.
    eps : float
        Restitution epsilon [-], in [0, 1].
    stiffness : float
        Loading stiffness b (k) of the loading curve F = a + b delta [N/m].
    preload : float
        Force at zero crush a of the loading curve [N] (``settings.preload``).
    friction : float
        Coulomb coefficient mu_c between the vehicles [-].
    tangential_stiffness : float
        k_t of the elastoplastic friction spring [N/m] (``stiffness`` unless set).
    tangential_recovery : float
        Share r of the stored tangential energy given back [-] (eps^2 unless set).
    geometry : str
        Contact geometry, "point" or "outline".
    tyre_friction : float
        Tyre friction coefficient during the contact [-] (0: no tyre forces).
    tyre_mode : str
        "rolling" (lateral tyre force only) or "locked" wheels.
    mass1, mass2 : float
        Masses [kg].
    inertia1, inertia2 : float
        Yaw inertias about the CGs [kg m^2].
    fixed2 : bool
        Vehicle 2 is a fixed obstacle.
    state0 : ndarray (12,)
        The state at t = 0 [m, m, rad, m/s, m/s, rad/s per vehicle] (order above).
    arm1_body : ndarray (2,)
        P - CG1 at t = 0, in vehicle 1's body frame [m].
    arm2_body : ndarray (2,)
        Q - CG2 at t = 0, in vehicle 2's body frame [m].
    normal2_body : ndarray (2,)
        The contact normal n, a unit vector in vehicle 2's body frame [-].
    wheels1 : ndarray (4, 2)
        Vehicle 1's wheel positions in its body frame [m] (front left, front right, rear
        left, rear right).
    wheels2 : ndarray (4, 2) or None
        Vehicle 2's, as ``wheels1`` (None when fixed).
    load1, load2 : float
        Static load per tyre, m g / 4 [N] (``load2`` 0 when fixed).
    outline1, outline2 : ndarray (4, 2) or None
        Corners of each length x width outline in its body frame [m] (None without length
        and width).
    k_nn : float
        K_nn = 1/m1 + 1/m2 + (r1 x n)^2 / I1 + (r2 x n)^2 / I2 of the contact at t = 0
        [1/kg] (vehicle 2's terms left out when fixed).
    duration_estimate : float
        Contact time of the frictionless linear law [s]
        (:func:`sim.contact_law.contact_duration_estimate`).
    speed_scale : float
        Largest pre-impact speed of the two vehicles [m/s] (at least 1e-6), for tolerances.
    energy_before : float
        Kinetic energy of both vehicles before the impact [J].
    settings : CompliantSettings
        The numerical settings used.
    """

    case: pim.Case
    eps: float
    stiffness: float            # b of the loading curve [N/m]
    preload: float              # a [N]
    friction: float             # mu_c [-]
    tangential_stiffness: float  # k_t [N/m]
    tangential_recovery: float  # r [-]
    geometry: str
    tyre_friction: float
    tyre_mode: str
    mass1: float
    inertia1: float
    mass2: float
    inertia2: float
    fixed2: bool
    state0: np.ndarray
    arm1_body: np.ndarray       # P in vehicle 1's body frame [m]
    arm2_body: np.ndarray       # Q in vehicle 2's body frame [m]
    normal2_body: np.ndarray    # n in vehicle 2's body frame
    wheels1: np.ndarray
    wheels2: np.ndarray | None
    load1: np.ndarray           # static loads of the four tyres [N]
    load2: np.ndarray | float
    outline1: np.ndarray | None
    outline2: np.ndarray | None
    k_nn: float                 # K_nn of the contact at t = 0 [1/kg]
    duration_estimate: float    # frictionless linear-law contact time [s]
    speed_scale: float          # [m/s]
    energy_before: float        # [J]
    settings: CompliantSettings


def _scalar(case: pim.Case) -> None:
    if np.size(case.vehicle1.mass) != 1 or np.shape(case.impact.point) != (2,) \
            or np.size(case.vehicle2.mass) != 1 or np.shape(case.vehicle1.cg) != (2,) \
            or np.shape(case.vehicle2.cg) != (2,) or np.size(case.impact.normal_angle) != 1:
        raise InputError("the finite-duration contact needs a single case (scalar fields), "
                         "not a batch of cases")


def refuse_frozen(settings: CompliantSettings | None, engine: str) -> None:
    """ValueError unless ``settings`` keep the geometry change (``geometry_change``: the
    frozen geometry is a study switch of the compiled engine's point contact only)."""
    if settings is not None and not settings.geometry_change:
        raise InputError(f"settings.geometry_change=False (the frozen contact geometry) runs "
                         f"on the compiled engine's point contact only, not on {engine}")


def build_problem(case: pim.Case, eps, stiffness, friction=0.0, geometry="point",
                  tyre_friction=0.0, settings: CompliantSettings | None = None
                  ) -> CompliantProblem:
    """Validate the physical inputs and set up the initial state (both integrators).

    Raises
    ------
    ValueError
        eps outside [0, 1]; stiffness zero, negative, NaN or infinite; friction or
        tyre_friction negative or NaN; an unknown geometry; outline geometry without
        outlines; a batch of cases.
    """
    settings = settings or CompliantSettings()
    if not isinstance(case, pim.Case):
        raise InputError(f"case must be a pim.Case, got {type(case).__name__}")
    _scalar(case)
    eps = check_fraction(eps, "eps")
    stiffness = check_positive(stiffness, "stiffness", "N/m")
    friction = check_positive(friction, "friction", "-", allow_zero=True)
    tyre_friction = check_positive(tyre_friction, "tyre_friction", "-", allow_zero=True)
    if geometry not in GEOMETRIES:
        raise InputError(f"geometry must be one of {GEOMETRIES}, got {geometry!r}")
    v1, v2 = case.vehicle1, case.vehicle2
    outline1, outline2 = outline_corners(v1), outline_corners(v2)
    fixed2 = bool(v2.fixed)
    if geometry == "outline":
        if outline1 is None:
            raise InputError("geometry='outline' needs vehicle1.length and vehicle1.width")
        if outline2 is None and not fixed2:
            raise InputError("geometry='outline' needs vehicle2.length and vehicle2.width")
    arr = setup_arrays(case, (), settings.gravity)
    m1, i1, m2, i2 = (float(arr[k][0]) for k in ("mass1", "inertia1", "mass2", "inertia2"))
    k_nn = float(arr["k_nn"][0])
    kt = settings.tangential_stiffness or stiffness
    recovery = (float(tangential_recovery_default(eps)) if settings.tangential_recovery is None
                else settings.tangential_recovery)
    return CompliantProblem(
        case=case, eps=eps, stiffness=stiffness, preload=settings.preload, friction=friction,
        tangential_stiffness=kt, tangential_recovery=recovery, geometry=geometry,
        tyre_friction=tyre_friction,
        tyre_mode=settings.tyre_mode, mass1=m1, inertia1=i1, mass2=m2, inertia2=i2,
        fixed2=fixed2, state0=arr["state0"][0], arm1_body=arr["arm1"][0],
        arm2_body=arr["arm2"][0], normal2_body=arr["normal2"][0], wheels1=arr["wheels1"][0],
        wheels2=None if fixed2 else arr["wheels2"][0], load1=arr["loads1"][0],
        load2=0.0 if fixed2 else arr["loads2"][0], outline1=outline1, outline2=outline2,
        k_nn=k_nn, duration_estimate=float(contact_duration_estimate(stiffness, k_nn, eps)),
        speed_scale=float(arr["speed_scale"][0]),
        energy_before=float(arr["energy_before"][0]), settings=settings)


def _flat_field(value, shape: tuple, vector: bool = False) -> np.ndarray:
    """A case field broadcast to ``shape`` and flattened: (n,) or (n, 2) for vectors."""
    full = shape + (2,) if vector else shape
    arr = np.broadcast_to(np.asarray(value, dtype=float), full)
    return arr.reshape((-1, 2) if vector else (-1,))


def _flat_cos_sin(angle, shape: tuple, sign: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """:func:`libm_cos_sin` of ``sign`` times a case's angle field, taken on the field's own
    elements and then broadcast to ``shape`` and flattened like :func:`_flat_field` (the
    same bits: one C-library call per element of the case, not per scene of the batch)."""
    cos, sin = libm_cos_sin(sign * np.asarray(angle, dtype=float))
    return _flat_field(cos, shape), _flat_field(sin, shape)


def _wheels(vehicle: pim.Vehicle, mass, inertia, gravity, fixed):
    """Wheel positions (n, 4, 2) and static loads (n, 4) of one vehicle (0 where fixed)."""
    n = mass.shape[0]
    if fixed.all():
        return np.zeros((n, 4, 2)), np.zeros((n, 4))
    moving = ~fixed
    k = np.where(moving, radius_of_gyration(np.where(moving, mass, 1.0),
                                            np.where(moving, inertia, 1.0)), 1.0)
    wheels = np.broadcast_to(wheels_from_outline(vehicle.length, vehicle.width, k,
                                                 vehicle.cg_to_front), (n, 4, 2))
    loads = wheel_loads(np.where(moving, mass, 0.0), wheels, gravity)
    return (np.where(moving[:, None, None], wheels, 0.0),
            np.where(moving[:, None], loads, 0.0))


_COS, _SIN = np.frompyfunc(math.cos, 1, 1), np.frompyfunc(math.sin, 1, 1)


def libm_cos_sin(angle) -> tuple[np.ndarray, np.ndarray]:
    """cos and sin of ``angle`` [rad] from the C library (Python's ``math``), element by
    element: what the stepping formulas use (numba calls the same library), and the same in
    the last bit for a batch as for each of its scenes alone (numpy's vectorised cos and sin
    can differ by an ulp between long arrays and one element)."""
    angle = np.asarray(angle, dtype=float)
    return np.asarray(_COS(angle), dtype=float), np.asarray(_SIN(angle), dtype=float)


def obstacle_corners(point, normal) -> np.ndarray:
    """A bare barrier's outline (..., 4, 2) [m]: a 200 m x 10 m block behind the contact
    plane through C with normal n (counter-clockwise: its face along t through C, 10 m deep
    on the -n side)."""
    point, n = np.asarray(point, dtype=float), np.asarray(normal, dtype=float)
    t = np.stack([-n[..., 1], n[..., 0]], axis=-1)
    return np.stack([point + 100 * t, point + 100 * t - 10 * n, point - 100 * t - 10 * n,
                     point - 100 * t], axis=-2)


def _outlines(v1: pim.Vehicle, v2: pim.Vehicle, fixed2, point, normal):
    """Both outlines' corners (n, 8) in the body frames (zeros without an outline), with a
    bare barrier's block in world coordinates instead (flag (n,) 1.0) where vehicle 2 is
    fixed and has no outline."""
    count = point.shape[0]
    corners = [outline_corners(v) for v in (v1, v2)]
    out1, out2 = (np.broadcast_to(np.zeros(8) if c is None else c.reshape(8), (count, 8))
                  for c in corners)
    bare = fixed2 & (corners[1] is None)
    if bare.any():
        out2 = np.where(bare[:, None], obstacle_corners(point, normal).reshape(count, 8), out2)
    return out1, out2, bare.astype(float)


def setup_arrays(case: pim.Case, shape: tuple, gravity: float) -> dict:
    """The scene quantities of every case in ``case`` broadcast to ``shape`` (flattened to
    n = prod(shape) scenes): what both integrators and the pymunk scene start from.

    Returns
    -------
    dict
        ``mass1, inertia1, mass2, inertia2, k_nn, speed_scale, energy_before`` (n,),
        ``fixed2`` (n,) bool, ``outline1, outline2`` (n, 8) and ``obstacle`` (n,) (the
        outlines of :func:`_outlines`), ``state0`` (n, 12), ``arm1, arm2, normal2`` (n, 2) (P -
        CG1 in
        vehicle 1's frame, Q - CG2 and the normal in vehicle 2's), ``wheels1, wheels2``
        (n, 4, 2) and ``loads1, loads2`` (n, 4) (zeros for a fixed vehicle 2); SI, see
        :class:`CompliantProblem`.
    """
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    m1, i1 = _flat_field(v1.mass, shape), _flat_field(v1.yaw_inertia, shape)
    m2, i2 = _flat_field(v2.mass, shape), _flat_field(v2.yaw_inertia, shape)
    cg1, cg2 = _flat_field(v1.cg, shape, True), _flat_field(v2.cg, shape, True)
    h1, h2 = _flat_field(v1.heading, shape), _flat_field(v2.heading, shape)
    vel1, vel2 = _flat_field(v1.velocity, shape, True), _flat_field(v2.velocity, shape, True)
    w1, w2 = _flat_field(v1.yaw_rate, shape), _flat_field(v2.yaw_rate, shape)
    point = _flat_field(imp.point, shape, True)
    fixed2 = np.isinf(m2)
    n = np.stack(_flat_cos_sin(imp.normal_angle, shape), axis=-1)
    r1, r2 = point - cg1, point - cg2
    # K_nn = 1/m1 + 1/m2 + (r1 x n)^2 / I1 + (r2 x n)^2 / I2 (the frequency of the contact)
    c1, c2 = cross(r1, n), cross(r2, n)
    k_nn = 1.0 / m1 + c1 * c1 / i1
    with np.errstate(invalid="ignore"):
        k_nn = np.where(fixed2, k_nn, k_nn + (1.0 / m2 + c2 * c2 / i2))
    state0 = np.concatenate([cg1, h1[:, None], vel1, w1[:, None], cg2, h2[:, None], vel2,
                             w2[:, None]], axis=1)
    wheels1, loads1 = _wheels(v1, m1, i1, gravity, np.zeros(m1.shape, bool))
    wheels2, loads2 = _wheels(v2, m2, i2, gravity, fixed2)
    speed = np.maximum(np.hypot(vel1[:, 0], vel1[:, 1]),
                       np.where(fixed2, 0.0, np.hypot(vel2[:, 0], vel2[:, 1])))
    out1, out2, obstacle = _outlines(v1, v2, fixed2, point, n)
    back2 = _flat_cos_sin(v2.heading, shape, -1.0)
    return dict(
        outline1=out1, outline2=out2, obstacle=obstacle,
        mass1=m1, inertia1=i1, mass2=m2, inertia2=i2, fixed2=fixed2, k_nn=k_nn,
        state0=state0, arm1=rotate_by(r1, *_flat_cos_sin(v1.heading, shape, -1.0)),
        arm2=rotate_by(r2, *back2), normal2=rotate_by(n, *back2),
        wheels1=wheels1, loads1=loads1, wheels2=wheels2, loads2=loads2,
        speed_scale=np.maximum(speed, 1e-6),
        energy_before=(geometry.kinetic_energy(m1, i1, vel1, w1)
                       + geometry.kinetic_energy(m2, i2, vel2, w2)))


def contact_step_limit(settings: CompliantSettings, dt):
    """Most steps of the contact at step ``dt`` [s] (a number or an array), fixed before it
    starts: min(ceil(max_contact_time / dt) + 1, max_fixed_steps)."""
    return np.minimum(np.ceil(settings.max_contact_time / np.asarray(dt, dtype=float)) + 1,
                      settings.max_fixed_steps)


def problem_arrays(problem: CompliantProblem) -> dict:
    """The one scene of ``problem`` as the arrays of :func:`setup_arrays` (n = 1), the very
    values ``problem`` was built from."""
    return setup_arrays(problem.case, (), problem.settings.gravity)


#: The contact law's inputs of :func:`parameter_rows`, one value or one per scene.
LAW_INPUTS = ("eps", "preload", "stiffness", "friction", "tangential_stiffness",
              "tangential_recovery", "tyre_friction", "braking", "dt", "start", "max_steps",
              "outline", "frozen")


def case_rows(arrays: dict) -> np.ndarray:
    """The ``par`` rows (n, N_PAR) of :mod:`sim.compliant_formula` with the case's columns
    filled (masses, inertias, arms, normal, wheels, loads, speed scale, v_r) from the scene
    quantities of :func:`setup_arrays` (or :func:`problem_arrays`), the law's columns 0."""
    f = formula
    n = arrays["mass1"].shape[0]
    par = np.zeros((n, f.N_PAR))
    for column, name in ((f.P_M1, "mass1"), (f.P_I1, "inertia1"), (f.P_M2, "mass2"),
                         (f.P_I2, "inertia2"), (f.P_FIXED2, "fixed2"),
                         (f.P_SPEED, "speed_scale")):
        par[:, column] = arrays[name]
    for column, name, width in ((f.P_ARM1, "arm1", 2), (f.P_ARM2, "arm2", 2),
                                (f.P_NORMAL2, "normal2", 2), (f.P_WHEELS1, "wheels1", 8),
                                (f.P_LOADS1, "loads1", 4), (f.P_WHEELS2, "wheels2", 8),
                                (f.P_LOADS2, "loads2", 4), (f.P_OUTLINE1, "outline1", 8),
                                (f.P_OUTLINE2, "outline2", 8)):
        par[:, column:column + width] = arrays[name].reshape(n, width)
    par[:, f.P_OBSTACLE] = arrays["obstacle"]
    for k, name in enumerate(("mass1", "inertia1", "mass2", "inertia2")):
        par[:, f.P_INVERSE + k] = 1.0 / arrays[name]        # 0 for a fixed vehicle 2
    par[:, f.P_VR] = SLIP_REGULARISATION
    return par


#: The ``par`` column of each of :data:`LAW_INPUTS`.
LAW_COLUMNS = dict(eps=formula.P_EPS, preload=formula.P_PRELOAD,
                   stiffness=formula.P_STIFFNESS, friction=formula.P_FRICTION,
                   tangential_stiffness=formula.P_KT, tangential_recovery=formula.P_RECOVERY,
                   tyre_friction=formula.P_TYRE, braking=formula.P_BRAKING, dt=formula.P_DT,
                   start=formula.P_START, max_steps=formula.P_MAX_STEPS,
                   outline=formula.P_OUTLINE, frozen=formula.P_FROZEN)


def parameter_rows(arrays: dict, law: dict, rows: np.ndarray | None = None) -> np.ndarray:
    """The ``par`` rows (n, N_PAR) of :mod:`sim.compliant_formula`: every scene's parameters.

    Parameters
    ----------
    arrays : dict
        The scene quantities of :func:`setup_arrays` (or :func:`problem_arrays`).
    law : dict
        :data:`LAW_INPUTS`, each a number or an array (n,): eps [-], preload a [N],
        stiffness b [N/m], friction mu_c [-], tangential_stiffness k_t [N/m],
        tangential_recovery r [-], tyre_friction [-], braking (0 rolling, 1 locked), dt [s],
        start [s], max_steps (of the contact), outline (1 for the outline contact), frozen
        (1: the point contact's geometry frozen at its start).
    rows : ndarray, optional
        :func:`case_rows` of ``arrays`` made already (copied, not changed).
    """
    par = case_rows(arrays) if rows is None else rows.copy()
    for name, column in LAW_COLUMNS.items():
        par[:, column] = law[name]
    return par


def point_contact(problem: CompliantProblem, kin: tuple):
    """Kinematics of the point contact (module notes) at one state
    (:func:`sim.compliant_formula.point_contact`).

    Parameters
    ----------
    problem : CompliantProblem
        The scene.
    kin : tuple
        Both vehicles' state, ``(position1, angle1, velocity1, yaw_rate1, position2, angle2,
        velocity2, yaw_rate2)`` [m, rad, m/s, rad/s].

    Returns
    -------
    point : ndarray (2,)
        P, the material point of vehicle 1 [m], where the force acts.
    normal, tangent : ndarray (2,)
        n(t) and t(t), carried by vehicle 2.
    delta : float
        Crush, the depth of P below the plane [m].
    slip_n, slip_t : float
        v_rel . n (= -d delta / dt) and v_rel . t [m/s].
    """
    position1, angle1, velocity1, yaw_rate1, position2, angle2, velocity2, yaw_rate2 = kin
    a1, a2, n2 = problem.arm1_body, problem.arm2_body, problem.normal2_body
    angle1, angle2 = float(angle1), float(angle2)
    px, py, nx, ny, delta, slip_n, slip_t = formula.point_contact(
        float(a1[0]), float(a1[1]), float(a2[0]), float(a2[1]), float(n2[0]), float(n2[1]),
        float(position1[0]), float(position1[1]), math.cos(angle1), math.sin(angle1),
        float(velocity1[0]), float(velocity1[1]), float(yaw_rate1), float(position2[0]),
        float(position2[1]), math.cos(angle2), math.sin(angle2), float(velocity2[0]),
        float(velocity2[1]), float(yaw_rate2))
    return (np.array([px, py]), np.array([nx, ny]), np.array([-ny, nx]), delta, slip_n,
            slip_t)


@dataclass(frozen=True, eq=False)
class ContactHistory:
    """The contact as it happened, one row per recorded instant (SI).

    Attributes
    ----------
    time : ndarray (N,)
        [s] from the start of the contact (t = 0 is PIM's impact instant for the point
        geometry; the outline contact may begin earlier).
    crush : ndarray (N,)
        delta [m].
    force : ndarray (N, 2)
        Contact force on vehicle 1 [N], global frame.
    normal_force, tangential_force : ndarray (N,)
        F_n, F_t [N].
    slip : ndarray (N,)
        Tangential relative velocity v_t at the contact [m/s].
    sticking : ndarray (N,) of bool
        The friction spring is inside the Coulomb cone.
    point : ndarray (N, 2)
        Where the force acts [m].
    """

    time: np.ndarray
    crush: np.ndarray
    force: np.ndarray
    normal_force: np.ndarray
    tangential_force: np.ndarray
    slip: np.ndarray
    sticking: np.ndarray
    point: np.ndarray


@dataclass(frozen=True, eq=False)
class CompliantResult:
    """Outcome of :func:`sim.simulate_compliant` or :func:`sim.reference_compliant`.

    Attributes
    ----------
    velocity1, velocity2 : ndarray (2,)
        CG velocities at separation [m/s].
    yaw_rate1, yaw_rate2 : float
        Yaw rates at separation [rad/s].
    contact_duration : float
        Time from first contact to separation [s].
    contact_start : float
        When the contact began [s] (0 for the point geometry; the outline contact starts
        when the outlines first touch, moved back along the free paths).
    impulse : ndarray (2,)
        Contact impulse on vehicle 1 [N s] (time integral of the contact force).
    impact_point : ndarray (2,)
        Impulse centroid [m]: the contact points weighted by |F| dt, the effective impact
        point (C for the point geometry, to within the motion of P during the contact).
    peak_force : float
        Largest |F| [N].
    peak_crush, permanent_crush : float
        delta_max and delta_p [m].
    energy_before, energy_after : float
        Kinetic energy at first contact and at separation [J].
    tyre_work : float
        Work of the tyre forces during the contact [J] (<= 0).
    stick_fraction : float
        Share of the contact time the friction spring stuck [-].
    slip_reversed : bool
        The tangential slip reversed (:func:`reversal`): the contact slid both ways, or
        left with a tangential velocity opposite to the one it met with (tangential rebound
        of the friction spring).
    steps : int
        Integrator steps (pymunk steps; accepted steps of solve_ivp).
    wall_time : float
        [s].
    integrator : str
        "pymunk" or the solve_ivp method.
    eps, stiffness, friction, tyre_friction : float
        The physical inputs.
    geometry : str
    settings : CompliantSettings
    history : ContactHistory or None
    trajectory : sim.Trajectory or None
        Motion of both bodies (pymunk with ``settings.record``), including ``duration``
        after separation; ``impact_index`` marks separation.
    secondary_impact : float or None
        First time [s] after separation at which the outlines overlap again (a second
        impact PIM does not model), within the recorded ``duration``.
    problems : tuple of str
        Flags: e.g. a crush deeper than the vehicle (the outlines would pass through).
    tangential_recovery : float
        The tangential recovery r [-] the contact used (``settings.tangential_recovery``).
    impulse_normal : ndarray (2,)
        The contact normal weighted like ``impact_point`` (|F| dt), unit length: the mean
        normal of the outline contact (pymunk only; NaN from the reference).
    impact_point_body1 : ndarray (2,)
        ``impact_point`` in vehicle 1's body frame [m] (each contact point taken in the frame
        of its instant; pymunk only).
    impulse_normal_body2 : ndarray (2,)
        ``impulse_normal`` in vehicle 2's body frame (pymunk only).
    """

    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: float
    yaw_rate2: float
    contact_duration: float
    contact_start: float
    impulse: np.ndarray
    impact_point: np.ndarray
    peak_force: float
    peak_crush: float
    permanent_crush: float
    energy_before: float
    energy_after: float
    tyre_work: float
    stick_fraction: float
    slip_reversed: bool
    steps: int
    wall_time: float
    integrator: str
    eps: float
    stiffness: float
    friction: float
    tyre_friction: float
    geometry: str
    settings: CompliantSettings
    history: ContactHistory | None = None
    trajectory: Trajectory | None = None
    secondary_impact: float | None = None
    problems: tuple = ()
    tangential_recovery: float = math.nan
    impulse_normal: np.ndarray = field(default_factory=lambda: np.full(2, math.nan))
    impact_point_body1: np.ndarray = field(default_factory=lambda: np.full(2, math.nan))
    impulse_normal_body2: np.ndarray = field(default_factory=lambda: np.full(2, math.nan))

    @property
    def energy_loss(self) -> float:
        """Kinetic energy lost during the contact [J] (crush and friction and tyres)."""
        return self.energy_before - self.energy_after

    def measured(self) -> pim.Measured:
        """The post-impact motion as a :class:`pim.Measured` (to fit PIM to it)."""
        return pim.Measured(self.velocity1, self.velocity2, self.yaw_rate1, self.yaw_rate2)


def result_from_row(row, problem: CompliantProblem, records: tuple = (None, None, None),
                    wall: float = 0.0, integrator: str = "pymunk") -> CompliantResult:
    """The typed result of one stepped scene from its output row
    (:func:`sim.compliant_formula.write_outputs`) and the records (trajectory, history,
    secondary impact time) of the pymunk scene."""
    f = formula
    v1, v2 = row[f.O_V1:f.O_V1 + 2].copy(), row[f.O_V2:f.O_V2 + 2].copy()
    w1, w2 = float(row[f.O_W1]), float(row[f.O_W2])
    trajectory, history, secondary = records
    peak_crush = float(row[f.O_PEAK_CRUSH])
    return CompliantResult(
        velocity1=v1, velocity2=v2, yaw_rate1=w1, yaw_rate2=w2,
        contact_duration=float(row[f.O_DURATION]), contact_start=float(problem_start(row)),
        impulse=row[f.O_IMPULSE:f.O_IMPULSE + 2].copy(),
        impact_point=row[f.O_POINT:f.O_POINT + 2].copy(), peak_force=float(row[f.O_PEAK_FORCE]),
        peak_crush=peak_crush, permanent_crush=float(row[f.O_PERMANENT]),
        energy_before=problem.energy_before,
        energy_after=(kinetic_energy(problem.mass1, problem.inertia1, v1, w1)
                      + kinetic_energy(problem.mass2, problem.inertia2, v2, w2)),
        tyre_work=float(row[f.O_TYRE_WORK]), stick_fraction=float(row[f.O_STICK]),
        slip_reversed=bool(row[f.O_REVERSED]), steps=int(row[f.O_STEPS]), wall_time=wall,
        integrator=integrator, eps=problem.eps, stiffness=problem.stiffness,
        friction=problem.friction, tyre_friction=problem.tyre_friction,
        geometry=problem.geometry, settings=problem.settings, history=history,
        trajectory=trajectory, secondary_impact=secondary,
        problems=crush_problems(problem.case, peak_crush),
        tangential_recovery=problem.tangential_recovery,
        impulse_normal=row[f.O_NORMAL:f.O_NORMAL + 2].copy(),
        impact_point_body1=row[f.O_BODY_POINT:f.O_BODY_POINT + 2].copy(),
        impulse_normal_body2=row[f.O_BODY_NORMAL:f.O_BODY_NORMAL + 2].copy())


def problem_start(row) -> float:
    """When the contact began [s], from an output row (0 for the point contact)."""
    return float(row[formula.O_START])


def crush_problems(case: pim.Case, peak_crush: float) -> tuple:
    """Flags of an inadmissible outcome (never hidden): a crush deeper than half the shorter
    moving vehicle's length."""
    out = []
    lengths = [v.length for v in (case.vehicle1, case.vehicle2)
               if v.length is not None and not bool(np.all(v.fixed))]
    if lengths and peak_crush > 0.5 * min(lengths):
        out.append(f"peak crush {peak_crush:.3g} m exceeds half the shorter vehicle's length "
                   f"({0.5 * min(lengths):.3g} m): the vehicles would pass through each other")
    return tuple(out)


def reversal(initial_sign: float, final_slip: float, speed_scale: float,
             directions) -> bool:
    """Whether the tangential slip reversed during the contact.

    True when the contact slid in both directions (``directions`` holds +1 and -1), or when
    the tangential relative velocity at separation, ``final_slip`` [m/s], opposes the one
    at first contact (sign ``initial_sign``) by more than 1e-6 of the speed scale.
    """
    directions = set(directions)
    return bool(formula.slip_reversed(initial_sign, final_slip, speed_scale, 1 in directions,
                                      -1 in directions))


def placed_outlines(problem: CompliantProblem, state) -> tuple[np.ndarray, np.ndarray | None]:
    """World corners of both outlines at ``state`` (None for an obstacle without one)."""
    poly1 = place(problem.outline1, state[0:2], state[2])
    poly2 = None if problem.outline2 is None else place(problem.outline2, state[6:8], state[8])
    return poly1, poly2



def endless_contact(estimate, settings: CompliantSettings):
    """True where the estimated contact duration ``estimate`` [s]
    (:func:`sim.contact_law.contact_duration_estimate`, pi (1 + eps) / (2 sqrt(k K_nn)))
    exceeds :data:`ESTIMATE_MARGIN` times ``settings.max_contact_time``: a contact without
    end (a stiffness far too low), refused before any step."""
    bound = ESTIMATE_MARGIN * settings.max_contact_time
    return ~(np.asarray(estimate, dtype=float) <= bound)


def physics_status(energy_before, energy_after, duration, settings: CompliantSettings):
    """The status of stepped scenes by the physics they must keep (arrays broadcast):
    "energy_gained" where the kinetic energy at separation exceeds the start's by more than
    :data:`ENERGY_TOLERANCE` (or is not finite), "never_separated" where the contact lasted
    longer than ``settings.max_contact_time``, else "ok" (codes of
    :data:`sim.compliant_formula.STATUS_NAMES`)."""
    before = np.asarray(energy_before, dtype=float)
    after = np.asarray(energy_after, dtype=float)
    gained = ~(after <= before * (1.0 + ENERGY_TOLERANCE) + 1e-12)
    endless = ~(np.asarray(duration, dtype=float) <= settings.max_contact_time)
    return np.where(gained, formula.STATUS_ENERGY_GAINED,
                    np.where(endless, formula.STATUS_NEVER_SEPARATED,
                             formula.STATUS_OK)).astype(np.int8)


def physics_refusal(energy_before: float, energy_after: float, duration: float,
                    settings: CompliantSettings) -> tuple[str, str] | None:
    """One stepped scene's refusal by :func:`physics_status`: (kind, message with its
    numbers), or None when it keeps its physics."""
    code = int(physics_status(energy_before, energy_after, duration, settings))
    if code == formula.STATUS_ENERGY_GAINED:
        gain = energy_after - energy_before
        return ("energy_gained",
                f"kinetic energy rose from {energy_before:.6g} J to {energy_after:.6g} J in the "
                f"contact (+{gain:.3g} J, beyond the {ENERGY_TOLERANCE:g} tolerance): the "
                f"contact only loses energy; refused")
    if code == formula.STATUS_NEVER_SEPARATED:
        return ("never_separated",
                f"the contact lasted {duration:.3g} s, beyond settings.max_contact_time = "
                f"{settings.max_contact_time:g} s; refused")
    return None
