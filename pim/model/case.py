"""The inputs of a planar impact: vehicles, the impact point and plane, measured motion.

All quantities are SI (kg, m, s, rad) in the global x-y frame, angles counter-clockwise
from +x. Every field may be an array: scalars broadcast against vectors of shape (..., 2),
so one ``Case`` can hold a single collision or a million Monte Carlo samples of it.
Unit strings and Brach's (theta, phi, d) inputs are converted before they reach here
(:mod:`pim.io.casefile`, :mod:`pim.io.brach`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from .geometry import rotate
from .inertia import InputEstimate
from .numbers import InputError, check_type, real_array, unit_text

__all__ = ["Vehicle", "Impact", "ImpactSpec", "Case", "Measured", "LAWS", "MASS_RANGE", "INERTIA_RANGE",
           "MAX_ARM_RATIO", "SPEED_UNITS", "checked_case", "BETA_RANGE_TEXT"]

#: The impact laws a case may name (``impact.law``); see :mod:`pim.model.impact_laws`.
#: "brach": Brach's PIM (eps, beta); "brach-capped": PIM with |mu| capped at a friction
#: coefficient; "kudlich-slibar": the PC-Crash / Virtual CRASH law (k, mu_c).
LAWS = ("brach", "brach-capped", "kudlich-slibar")
#: The laws that take a contact friction coefficient (``impact.contact_friction``).
FRICTION_LAWS = ("brach-capped", "kudlich-slibar")
#: The units results may give speeds in (``Case.speed_unit``; pint's names of km/h, mph,
#: m/s and ft/s; :mod:`pim.io.units` converts).
SPEED_UNITS = ("km/h", "mph", "m/s", "ft/s")

#: Allowed mass [kg] and yaw inertia [kg m^2] of a moving body (inf: a fixed obstacle): where
#: the arithmetic holds, not where vehicles lie (a case file is held to the tighter
#: :data:`pim.io.units.LIMITS`). Every product the solver forms (1/m, 1/I, the 2x2
#: determinant ~ (1/m)^2, m v^2 with v <= 1e4 m/s) then stays within 1e-140 ... 1e140, far
#: from float overflow and underflow; a mass of 1e-300 kg made 1/m^2 overflow to inf and
#: the answer NaN. Mass ratios are no problem: 1/m1 + 1/m2 adds positive terms (a ratio of
#: 1e12 keeps the energy loss to 1e-9, tests/pim/model/test_case_validation.py).
MASS_RANGE = (1e-60, 1e60)
INERTIA_RANGE = (1e-60, 1e60)

#: Largest m |r|^2 / I (r = C - CG, I = m k^2: the squared ratio of the arm to the radius of
#: gyration k) of a moving body. The effective-mass matrix adds (r x n)^2 / I to 1/m, so its
#: solution loses about log10 of this ratio in significant digits: measured against exact
#: rational arithmetic (tests/exact.py, RICSAC 9 with k shrunk), the velocities' relative
#: error is 1e-14 at a ratio of 2e4, 3e-10 at 2e8, 1e-6 at 2e12 and 2e-3 at 2e15 (k = 1e-7 ft),
#: and k = 1e-9 ft divides by zero. The bound 1e8 keeps the error below about 1e-10; a real
#: vehicle has a ratio near 1-10 (k of 1-1.5 m, arms of 1-3 m), a thin pole struck at
#: 1 m with k = 1 mm a ratio of 1e6.
MAX_ARM_RATIO = 1e8


#: What beta may be, in words (every message refusing a beta says it). Brach's law defines
#: mu = beta mu0 with beta in [0, 1] (the design sheet: "the fraction of mu0 used"; its fit
#: is constrained to beta <= 1). beta < 0 would make the tangential impulse drive the sliding
#: at C instead of resisting it, which no contact does: refused. beta > 1 (the slip at C
#: reverses: tangential restitution, the Kudlich-Slibar law's standard) is accepted and its
#: answer flagged inadmissible under Brach's law (:mod:`pim.model.admissibility`).
BETA_RANGE_TEXT = ("(fraction of mu0) must be a finite number >= 0: Brach's law takes beta in "
                   "[0, 1] (above 1 the answer is flagged inadmissible: the slip at C "
                   "reverses)")


#: The types of a plain Python number (bool excluded: ``type(True) is bool``).
_PLAIN = (float, int)


def _plain_pair(value) -> bool:
    """A tuple or list of two finite plain Python numbers (the fast path of one case)."""
    return ((type(value) is tuple or type(value) is list) and len(value) == 2
            and type(value[0]) in _PLAIN and type(value[1]) in _PLAIN
            and -math.inf < value[0] < math.inf and -math.inf < value[1] < math.inf)


def _scalar(value, name: str, unit: str = "SI") -> np.ndarray:
    if type(value) is float or type(value) is int:    # the common single case, fast
        if value != value:
            raise InputError(f"{name} is NaN; it must be a finite number in [{unit}]")
        return np.float64(value)
    arr = real_array(value, name, unit)
    if np.isnan(arr).any():
        raise InputError(f"{name} is NaN; it must be a finite number in [{unit}]")
    return arr


def _vector(value, name: str, unit: str) -> np.ndarray:
    if _plain_pair(value):   # fast path: a finite [x, y] of plain numbers
        return np.array(value, dtype=float)
    arr = real_array(value, name, unit)
    if arr.ndim == 0 or arr.shape[-1] != 2:
        raise InputError(f"{name} must be an [x, y] pair in [{unit}], got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise InputError(f"{name} must be finite [x, y] values in [{unit}]")
    return arr


def _one_number(value, name: str) -> float:
    arr = real_array(value, name)
    if arr.size != 1:
        raise InputError(f"{name} must be a single number (the case's default), "
                         f"got shape {arr.shape}")
    return float(arr.reshape(()))


def _finite(arr: np.ndarray, name: str, unit: str) -> np.ndarray:
    if type(arr) is np.float64:   # a scalar from _scalar's fast path
        if not math.isfinite(arr):
            raise InputError(f"{name} must be a finite number in [{unit}]")
        return arr
    if not np.isfinite(arr).all():
        raise InputError(f"{name} must be a finite number in [{unit}]")
    return arr


def _within(value, scalar: bool, bounds: tuple, name: str, unit: str) -> None:
    """InputError unless every finite ``value`` lies in ``bounds`` (inf: a fixed obstacle)."""
    low, high = bounds
    if scalar:
        bad = not (low <= value <= high or math.isinf(value))
    else:
        bad = bool(((value < low) | ((value > high) & np.isfinite(value))).any())
    if bad:
        raise InputError(f"{name} must be in [{low:g}, {high:g}] [{unit}] (or inf for a fixed "
                         f"obstacle), got {float(value) if np.size(value) == 1 else 'others'}")


def _single(v1, v2, imp) -> bool:
    """Every input of the case a numpy scalar or one [x, y] pair: a single case, known
    without broadcasting shapes."""
    f64 = np.float64
    return (type(v1.mass) is f64 and type(v1.yaw_inertia) is f64 and type(v1.yaw_rate) is f64
            and type(v2.mass) is f64 and type(v2.yaw_inertia) is f64
            and type(v2.yaw_rate) is f64 and type(imp.normal_angle) is f64
            and v1.cg.shape == v1.velocity.shape == v2.cg.shape == v2.velocity.shape
            == imp.point.shape == (2,))


def _check_conditioning(case, single: bool = False) -> None:
    """InputError when a moving body's m |C - CG|^2 / I exceeds :data:`MAX_ARM_RATIO`
    (``single``: the case is known to hold scalars and [x, y] pairs only, :func:`_single`)."""
    point = case.impact.point
    if single:
        px, py = point.tolist()
        v1, v2 = case.vehicle1, case.vehicle2
        (c1x, c1y), (c2x, c2y) = v1.cg.tolist(), v2.cg.tolist()
        m1, m2 = float(v1.mass), float(v2.mass)     # finite for vehicle1 (checked before)
        if m1 * ((px - c1x) ** 2 + (py - c1y) ** 2) <= MAX_ARM_RATIO * float(v1.yaw_inertia) and (
                m2 == math.inf or m2 * ((px - c2x) ** 2 + (py - c2y) ** 2)
                <= MAX_ARM_RATIO * float(v2.yaw_inertia)):
            return
    px, py = point.tolist() if point.shape == (2,) else (None, None)
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        if (px is not None and type(v.mass) is np.float64 and type(v.yaw_inertia) is np.float64
                and v.cg.shape == (2,)):
            mass, (cx, cy) = float(v.mass), v.cg.tolist()     # the single case, in floats
            if mass == math.inf or mass * ((px - cx) ** 2 + (py - cy) ** 2) <= (
                    MAX_ARM_RATIO * float(v.yaw_inertia)):
                continue
        arm = point - v.cg
        with np.errstate(invalid="ignore", over="ignore"):
            ratio = v.mass * (arm[..., 0] ** 2 + arm[..., 1] ** 2) / v.yaw_inertia
        if not bool(np.any(ratio > MAX_ARM_RATIO)):     # NaN (a fixed body, inf/inf) passes
            continue
        worst = int(np.nanargmax(np.ravel(np.where(np.isnan(ratio), 0.0, ratio))))
        r = float(np.sqrt(np.ravel(np.broadcast_to(arm[..., 0] ** 2 + arm[..., 1] ** 2,
                                                   np.shape(ratio)))[worst]))
        k = float(np.ravel(np.broadcast_to(np.sqrt(v.yaw_inertia / v.mass),
                                           np.shape(ratio)))[worst])
        raise InputError(
            f"vehicle{i}.yaw_inertia: the radius of gyration sqrt(I/m) = "
            f"{unit_text(k, 'length', '.3g')} is too small for the arm |C - CG| = "
            f"{unit_text(r, 'length', '.3g')} (m arm^2 / I = {r * r / (k * k):.3g} > "
            f"{MAX_ARM_RATIO:g}): the impulse would lose more than 10 significant digits; "
            f"the radius of gyration must be at least "
            f"{unit_text(r / math.sqrt(MAX_ARM_RATIO), 'length', '.3g')}")


@dataclass(frozen=True, eq=False)
class Vehicle:
    """One body of the impact, rigid in the plane.

    Parameters
    ----------
    mass : array_like
        Mass [kg], > 0; ``inf`` (with ``yaw_inertia = inf``) makes a fixed obstacle.
    yaw_inertia : array_like
        Yaw moment of inertia about the CG [kg m^2], > 0; ``inf`` for a fixed obstacle.
    cg : array_like, shape (..., 2)
        Position of the centre of gravity [m].
    velocity : array_like, shape (..., 2)
        Pre-impact velocity of the CG [m/s].
    yaw_rate : array_like
        Pre-impact yaw rate [rad/s], counter-clockwise positive.
    heading : array_like
        Direction the vehicle's nose points [rad] from +x; used for PDOF and drawing only.
    length, width : float, optional
        Outline of the vehicle [m], a rectangle along the heading; used for drawing and
        for the optional outline contact of the simulator, never by the impact equations.
    cg_to_front : float, optional
        Distance [m] from the CG forward to the front of the OUTLINE (the bumper), in
        [0, length]; default ``length / 2`` (the outline centred on the CG). Needs
        ``length``. Not the CG to the front axle (the run-out's
        :attr:`pim.model.evidence.VehicleEvidence.cg_to_front_axle`).
    reversing : bool
        The vehicle is known to move backwards (velocity more than 90 deg from the heading):
        silences the plausibility warning that asks whether it is (default False). Never
        used by the impact equations.
    sliding : bool
        The vehicle is known to slide sideways into the impact (its velocity more than
        :data:`pim.model.plausibility.SLIDING_ANGLE` off its fore-aft axis): silences the
        plausibility warning that asks whether it is (default False). Never used by the
        impact equations.
    """

    mass: np.ndarray
    yaw_inertia: np.ndarray
    cg: np.ndarray
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    yaw_rate: np.ndarray = 0.0
    heading: np.ndarray = 0.0
    length: float | None = None
    width: float | None = None
    cg_to_front: float | None = None
    reversing: bool = False
    sliding: bool = False

    def __post_init__(self) -> None:
        if not self._set_plain():
            self._set_checked()
        self._check_outline()
        for name in ("reversing", "sliding"):
            if type(getattr(self, name)) is not bool:
                raise InputError(f"{name} must be true or false, got {getattr(self, name)!r}")

    def _set_plain(self) -> bool:
        """The single moving body given as plain Python floats (or ints): every check of
        :meth:`_set_checked` holds by the conditions tested here (masses within their ranges,
        so finite and > 0; finite yaw rate, heading and [x, y] pairs), so the fields are
        converted directly. False, with nothing set, when any field needs the full checks."""
        mass, inertia, yaw_rate, heading = self.mass, self.yaw_inertia, self.yaw_rate, self.heading
        cg, velocity = self.cg, self.velocity
        if not (type(mass) in _PLAIN and MASS_RANGE[0] <= mass <= MASS_RANGE[1]
                and type(inertia) in _PLAIN and INERTIA_RANGE[0] <= inertia <= INERTIA_RANGE[1]
                and type(yaw_rate) in _PLAIN and -math.inf < yaw_rate < math.inf
                and type(heading) in _PLAIN and -math.inf < heading < math.inf
                and _plain_pair(cg) and _plain_pair(velocity)):
            return False
        f64 = np.float64
        self.__dict__.update(   # the frozen fields, set once (as object.__setattr__ would)
            mass=f64(mass), yaw_inertia=f64(inertia), cg=np.array(cg, dtype=float),
            velocity=np.array(velocity, dtype=float), yaw_rate=f64(yaw_rate),
            heading=f64(heading))
        return True

    def _set_checked(self) -> None:
        """Every field checked and converted (arrays, obstacles, any input)."""
        set_ = object.__setattr__
        mass = _scalar(self.mass, "mass", "kg")
        inertia = _scalar(self.yaw_inertia, "yaw_inertia", "kg m^2")
        scalars = type(mass) is np.float64 and type(inertia) is np.float64
        if not (mass > 0 if scalars else (mass > 0).all()):
            raise InputError("mass must be > 0 [kg] (or inf for a fixed obstacle)")
        if not (inertia > 0 if scalars else (inertia > 0).all()):
            raise InputError("yaw_inertia must be > 0 [kg m^2] (or inf for a fixed obstacle)")
        if (math.isinf(mass) != math.isinf(inertia) if scalars
                else (np.isinf(mass) != np.isinf(inertia)).any()):
            raise InputError("mass and yaw_inertia must both be inf for a fixed obstacle")
        _within(mass, scalars, MASS_RANGE, "mass", "kg")
        _within(inertia, scalars, INERTIA_RANGE, "yaw_inertia", "kg m^2")
        set_(self, "mass", mass)
        set_(self, "yaw_inertia", inertia)
        set_(self, "cg", _vector(self.cg, "cg", "m"))
        set_(self, "velocity", _vector(self.velocity, "velocity", "m/s"))
        set_(self, "yaw_rate", _finite(_scalar(self.yaw_rate, "yaw_rate", "rad/s"), "yaw_rate",
                                        "rad/s"))
        set_(self, "heading", _finite(_scalar(self.heading, "heading", "rad"), "heading", "rad"))
        fixed = math.isinf(mass) if scalars else np.isinf(mass)
        if fixed if scalars else fixed.any():   # only when there is an obstacle
            fixed, moving = np.broadcast_arrays(
                fixed, np.abs(self.velocity).sum(-1) + np.abs(self.yaw_rate))
            if (fixed & (moving != 0)).any():
                raise InputError("velocity and yaw_rate of a fixed obstacle must be 0")

    def _check_outline(self) -> None:
        """length, width and cg_to_front: single positive numbers, the CG inside the outline."""
        set_ = object.__setattr__
        for name in ("length", "width"):
            value = getattr(self, name)
            if value is not None:
                value = _one_number(value, name)
                if not (np.isfinite(value) and value > 0):
                    raise InputError(f"{name} must be > 0 [m], got {value}")
                set_(self, name, value)
        if self.cg_to_front is not None:
            a = _one_number(self.cg_to_front, "cg_to_front")
            if self.length is None:
                raise InputError("cg_to_front needs length (the outline it places the CG in)")
            if not 0.0 <= a <= self.length:
                raise InputError(f"cg_to_front must be in [0, length = {self.length:g}] [m], "
                                 f"got {a:g}")
            set_(self, "cg_to_front", a)

    @classmethod
    def obstacle(cls, cg=(0.0, 0.0), heading=0.0, length=None, width=None,
                 cg_to_front=None) -> Vehicle:
        """A fixed barrier or pole: infinite mass and yaw inertia, at rest.

        Its ``cg`` [m] and ``heading`` [rad] do not change the impact (its arm is multiplied
        by a zero inverse inertia); they only place an outline in drawings.
        """
        return cls(mass=np.inf, yaw_inertia=np.inf, cg=cg, velocity=(0.0, 0.0),
                   yaw_rate=0.0, heading=heading, length=length, width=width,
                   cg_to_front=cg_to_front)

    @property
    def fixed(self) -> np.ndarray:
        """True where the body is a fixed obstacle (infinite mass)."""
        return np.isinf(self.mass)

    @property
    def inverse_mass(self) -> np.ndarray:
        """1 / mass [1/kg], 0 for a fixed obstacle."""
        return 1.0 / self.mass

    @property
    def inverse_inertia(self) -> np.ndarray:
        """1 / yaw_inertia [1/(kg m^2)], 0 for a fixed obstacle."""
        return 1.0 / self.yaw_inertia


@dataclass(frozen=True, eq=False)
class Impact:
    """The common impact point C and the contact plane.

    Parameters
    ----------
    point : array_like, shape (..., 2)
        Position of C [m].
    normal_angle : array_like
        Gamma [rad]: direction of the unit normal n = (cos Gamma, sin Gamma), which points
        from vehicle 2 toward vehicle 1. The tangent is t = (-sin Gamma, cos Gamma).
    restitution : float, optional
        Default coefficient of restitution epsilon [-] for :func:`pim.solve`.
    beta : float, optional
        Default fraction beta [-] of the critical impulse ratio mu0 (Brach's laws only).
    law : {"brach", "brach-capped", "kudlich-slibar"}, optional
        The impact law :func:`pim.solve` applies (None: "brach").
        For "kudlich-slibar" ``restitution`` is PC-Crash's k.
    contact_friction : float, optional
        Friction coefficient mu_c [-] >= 0 between the vehicles (inf: always stick), for
        the laws of :data:`FRICTION_LAWS`.
    """

    point: np.ndarray
    normal_angle: np.ndarray
    restitution: float | None = None
    beta: float | None = None
    law: str | None = None
    contact_friction: float | None = None

    def __post_init__(self) -> None:
        point, angle = self.point, self.normal_angle
        if _plain_pair(point) and type(angle) in _PLAIN and -math.inf < angle < math.inf:
            self.__dict__.update(point=np.array(point, dtype=float),   # one case, fast
                                 normal_angle=np.float64(angle))
        else:
            object.__setattr__(self, "point", _vector(point, "point", "m"))
            angle = _finite(_scalar(angle, "normal_angle", "rad"), "normal_angle", "rad")
            object.__setattr__(self, "normal_angle", angle)
        if self.restitution is not None:
            eps = _one_number(self.restitution, "restitution")
            if not 0.0 <= eps <= 1.0:
                raise InputError(f"restitution must be in [0, 1], got {eps}")
            object.__setattr__(self, "restitution", eps)
        if self.beta is not None:
            beta = _one_number(self.beta, "beta")
            if not beta >= 0 or not np.isfinite(beta):
                raise InputError(f"beta {BETA_RANGE_TEXT}, got {beta:g}")
            object.__setattr__(self, "beta", beta)
        if self.law is not None or self.contact_friction is not None:
            self._check_law()        # nothing to check for Brach's law without mu_c

    def _check_law(self) -> None:
        """The law is known, and takes the parameters given."""
        law = self.law
        if law is not None and (not isinstance(law, str) or law not in LAWS):
            raise InputError(f"law must be one of {', '.join(map(repr, LAWS))}, got {law!r}")
        if self.contact_friction is not None:
            mu_c = _one_number(self.contact_friction, "contact_friction")
            if not mu_c >= 0.0:
                raise InputError(f"contact_friction must be >= 0 (a friction coefficient; inf: "
                                 f"always stick), got {mu_c}")
            if law not in FRICTION_LAWS:
                raise InputError(f"contact_friction needs law = 'kudlich-slibar' or "
                                 f"'brach-capped' (law is {law or 'brach'!r})")
            object.__setattr__(self, "contact_friction", mu_c)
        if law == "kudlich-slibar" and self.beta is not None:
            raise InputError("beta does not apply to law 'kudlich-slibar' (its parameters "
                             "are restitution k and contact_friction mu_c)")

    @property
    def normal(self) -> np.ndarray:
        """Unit normal n, shape (..., 2)."""
        g = self.normal_angle
        return np.stack([np.cos(g), np.sin(g)], axis=-1)

    @property
    def tangent(self) -> np.ndarray:
        """Unit tangent t = n rotated +90 deg, shape (..., 2)."""
        g = self.normal_angle
        return np.stack([-np.sin(g), np.cos(g)], axis=-1)


@dataclass(frozen=True, eq=False)
class ImpactSpec:
    """The law and coefficients of one of an event's further impacts (a ``[[impacts]]``
    entry of a case file; :func:`pim.event`).

    Parameters
    ----------
    law : {"brach", "brach-capped", "kudlich-slibar"}
    restitution : float, optional
        eps (Brach's laws) or k (Kudlich-Slibar) [-] in [0, 1].
    beta : float, optional
        Fraction of mu0 [-] >= 0 (Brach's laws; default 1).
    contact_friction : float, optional
        mu_c [-] >= 0: the cap of "brach-capped", the contact friction of
        "kudlich-slibar".

    A coefficient left out takes the event's stated default
    (:func:`pim.analysis.event.impact_spec`).
    point : array_like (2,), optional
        C [m], global frame, instead of the outlines' contact point.
    normal_angle : float, optional
        Gamma [rad] instead of the penetrated edge's normal.
    where : str
        The table named in error messages (e.g. ``impacts[0]``).
    """

    law: str = "brach"
    restitution: float | None = None
    beta: float | None = None
    contact_friction: float | None = None
    point: np.ndarray | None = None
    normal_angle: float | None = None
    where: str = "impacts"

    def __post_init__(self) -> None:
        w = self.where
        if self.law not in LAWS:
            raise InputError(f"{w}.law must be one of {', '.join(map(repr, LAWS))}, got "
                             f"{self.law!r}")
        if self.restitution is not None and not 0.0 <= float(self.restitution) <= 1.0:
            raise InputError(f"{w}.restitution must be in [0, 1], got {self.restitution!r}")
        if self.beta is not None and not (math.isfinite(self.beta) and self.beta >= 0):
            raise InputError(f"{w}.beta {BETA_RANGE_TEXT}, got {self.beta!r}")
        if self.law == "kudlich-slibar" and self.beta is not None:
            raise InputError(f"{w}.beta does not apply to law 'kudlich-slibar'")
        mu_c = self.contact_friction
        if mu_c is not None and not float(mu_c) >= 0.0:
            raise InputError(f"{w}.contact_friction must be >= 0, got {mu_c!r}")
        if self.law == "brach" and mu_c is not None:
            raise InputError(f"{w}.contact_friction needs law 'brach-capped' or "
                             f"'kudlich-slibar'")
        if self.point is not None:
            object.__setattr__(self, "point", _vector(self.point, f"{w}.point", "m"))
        if self.normal_angle is not None and not math.isfinite(self.normal_angle):
            raise InputError(f"{w}.normal_angle must be a finite angle [rad]")


@dataclass(frozen=True, eq=False)
class Measured:
    """Measured post-impact motion (the target of :func:`pim.fit`). Any field may be None.

    Parameters
    ----------
    velocity1, velocity2 : array_like, shape (2,), optional
        Post-impact CG velocities [m/s].
    yaw_rate1, yaw_rate2 : float, optional
        Post-impact yaw rates [rad/s].
    velocity1_sigma, velocity2_sigma : array_like, shape (2,), optional
        Standard deviations of the measured velocity components [m/s], > 0.
    yaw_rate1_sigma, yaw_rate2_sigma : float, optional
        Standard deviations of the measured yaw rates [rad/s], > 0.
    delta_v1, delta_v2 : array_like, shape (2,), optional
        Recorded delta-V (event data recorder), [longitudinal, lateral] in the vehicle frame
        at impact: x forward along the heading, y to the left [m/s]
        (:mod:`pim.model.evidence_terms`).
    delta_v1_sigma, delta_v2_sigma : array_like, shape (2,), optional
        Their standard deviations [m/s], > 0 (required with the delta-V).
    pre_crash_speed1, pre_crash_speed2 : float, optional
        Recorded pre-impact speed |V_i| [m/s], >= 0.
    pre_crash_speed1_sigma, pre_crash_speed2_sigma : float, optional
        Their standard deviations [m/s], > 0 (required with the speed).
    energy_loss : float, optional
        Kinetic energy lost in the impact (e.g. from a crush analysis) [J], > 0.
    energy_loss_sigma : float, optional
        Its standard deviation [J], > 0 (required with the energy loss).
    """

    velocity1: np.ndarray | None = None
    velocity2: np.ndarray | None = None
    yaw_rate1: float | None = None
    yaw_rate2: float | None = None
    velocity1_sigma: np.ndarray | None = None
    velocity2_sigma: np.ndarray | None = None
    yaw_rate1_sigma: float | None = None
    yaw_rate2_sigma: float | None = None
    delta_v1: np.ndarray | None = None
    delta_v2: np.ndarray | None = None
    delta_v1_sigma: np.ndarray | None = None
    delta_v2_sigma: np.ndarray | None = None
    pre_crash_speed1: float | None = None
    pre_crash_speed2: float | None = None
    pre_crash_speed1_sigma: float | None = None
    pre_crash_speed2_sigma: float | None = None
    energy_loss: float | None = None
    energy_loss_sigma: float | None = None

    def __post_init__(self) -> None:
        self._check_motion()
        self._check_recorded()

    @property
    def has_post_impact_motion(self) -> bool:
        """Whether a post-impact velocity or yaw rate is measured."""
        return any(getattr(self, f) is not None for f in
                   ("velocity1", "velocity2", "yaw_rate1", "yaw_rate2"))

    def _check_recorded(self) -> None:
        """The recorder's delta-V and pre-crash speed and the energy loss: finite, speeds
        >= 0, energy > 0, each with its sigma > 0."""
        for name, unit in (("delta_v1", "m/s"), ("delta_v2", "m/s"), ("pre_crash_speed1", "m/s"),
                           ("pre_crash_speed2", "m/s"), ("energy_loss", "J")):
            value, sigma = getattr(self, name), getattr(self, name + "_sigma")
            if value is None:
                if sigma is not None:
                    raise InputError(f"{name}_sigma is given but {name} is not measured")
                continue
            value = (_vector(value, name, unit) if name.startswith("delta_v")
                     else _one_number(value, name))
            if not np.all(np.isfinite(value)):
                raise InputError(f"{name} must be finite [{unit}], got {value}")
            if name.startswith("pre_crash_speed") and value < 0:
                raise InputError(f"{name} must be >= 0 [{unit}] (a speed), got {value:g}")
            if name == "energy_loss" and value <= 0:
                raise InputError(f"{name} must be > 0 [{unit}] (energy absorbed in the "
                                 f"impact), got {value:g}")
            if sigma is None:
                raise InputError(f"{name}_sigma is required with {name} (its standard "
                                 f"deviation [{unit}], > 0)")
            sigma = (_vector(sigma, name + "_sigma", unit) if name.startswith("delta_v")
                     else _one_number(sigma, name + "_sigma"))
            if not np.all(np.isfinite(sigma)) or np.any(np.asarray(sigma) <= 0):
                raise InputError(f"{name}_sigma must be finite and > 0 [{unit}], got {sigma}")
            object.__setattr__(self, name, value)
            object.__setattr__(self, name + "_sigma", sigma)

    def _check_motion(self) -> None:
        """The post-impact velocities and yaw rates and their sigmas."""
        for name, unit in (("velocity1", "m/s"), ("velocity2", "m/s")):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _vector(value, name, unit))
        for name in ("yaw_rate1", "yaw_rate2"):
            value = getattr(self, name)
            if value is not None:
                value = _one_number(value, name)
                if not np.isfinite(value):
                    raise InputError(f"{name} must be a finite number in [rad/s]")
                object.__setattr__(self, name, value)
        for name, unit in (("velocity1", "m/s"), ("velocity2", "m/s"), ("yaw_rate1", "rad/s"),
                           ("yaw_rate2", "rad/s")):
            sigma = getattr(self, name + "_sigma")
            if sigma is None:
                continue
            if getattr(self, name) is None:
                raise InputError(f"{name}_sigma is given but {name} is not measured")
            sigma = (_vector(sigma, name + "_sigma", unit) if name.startswith("velocity")
                     else _one_number(sigma, name + "_sigma"))
            if not np.all(np.isfinite(sigma)) or np.any(np.asarray(sigma) <= 0):
                raise InputError(f"{name}_sigma must be finite and > 0 [{unit}], got {sigma}")
            object.__setattr__(self, name + "_sigma", sigma)


@dataclass(frozen=True, eq=False)
class Case:
    """A two-body planar impact: the inputs of :func:`pim.solve`.

    Parameters
    ----------
    vehicle1, vehicle2 : Vehicle
        The bodies; ``vehicle2`` may be a fixed obstacle (:meth:`Vehicle.obstacle`).
    impact : Impact
        Point C and contact-plane angle Gamma (n points from vehicle 2 toward vehicle 1).
    measured : Measured, optional
        Measured post-impact motion, for fitting.
    name, description : str
        Labels for reports.
    uncertainty : pim.model.distributions.UncertaintyTable, optional
        Distributions of uncertain inputs (the case file's ``[uncertainty]`` table, and for
        each estimated input the table leaves out a normal distribution with the estimate's
        sd), used by :func:`pim.uncertainty` and the reconstruction's Monte Carlo.
    units : {"si", "us"}
        The unit system the case was written in (its file's units, or its ``[units] system``);
        results are presented in it unless asked otherwise.
    speed_unit : {"km/h", "mph", "m/s", "ft/s"}, optional
        The unit results give speeds and delta-V in (the case file's ``[units] speed``);
        default the system's field unit, km/h for "si" and mph for "us"
        (:class:`pim.io.units.DisplayUnits`).
    notes : tuple of str
        Warnings about the inputs that whoever built the case wants printed with its
        findings (:func:`pim.model.plausibility.findings`), before the checks' own.
    evidence : pim.model.evidence.Evidence, optional
        Rest positions, wheel states, friction (the ``[evidence]`` table), for
        :mod:`pim.analysis.reconstruction`.
    unknown : dict, optional
        Dotted key -> (low, high) bounds [SI] of what a reconstruction solves for.
    estimates : tuple of pim.model.inertia.InputEstimate
        Inputs the case file left out and the program estimated (e.g. a yaw inertia from
        mass and wheelbase), with their scatter and source, for notes and reports.
    impacts : tuple of ImpactSpec
        The law and coefficients of the event's further impacts, in order (the case file's
        ``[[impacts]]``; entry k is the event's impact k + 2, the last entry also any
        later one), for :func:`pim.event`; empty: the stated defaults.
    """

    vehicle1: Vehicle
    vehicle2: Vehicle
    impact: Impact
    measured: Measured | None = None
    name: str = ""
    description: str = ""
    uncertainty: object | None = None  # pim.model.distributions.UncertaintyTable
    units: str = "si"
    notes: tuple = ()
    evidence: object | None = None  # pim.model.evidence.Evidence (post-impact evidence)
    unknown: dict | None = None  # dotted key -> (low, high) SI bounds, the [unknown] table
    estimates: tuple = ()  # pim.model.inertia.InputEstimate: inputs the program estimated
    speed_unit: str | None = None   # one of SPEED_UNITS; None: the system's field unit
    impacts: tuple = ()    # ImpactSpec per further impact of the event ([[impacts]])

    def __post_init__(self) -> None:
        if not (type(self.vehicle1) is Vehicle and type(self.vehicle2) is Vehicle
                and type(self.impact) is Impact):   # else subclasses, or an error
            self._check_types()
        if not (self.measured is None and self.uncertainty is None and self.evidence is None
                and self.unknown is None):
            self._check_tables()
        if self.units not in ("si", "us"):
            raise InputError(f"units must be 'si' or 'us', got {self.units!r}")
        if self.estimates and not (isinstance(self.estimates, tuple) and all(
                isinstance(e, InputEstimate) for e in self.estimates)):
            raise InputError("estimates must be a tuple of pim.model.inertia.InputEstimate")
        if self.impacts and not (isinstance(self.impacts, tuple) and all(
                isinstance(i, ImpactSpec) for i in self.impacts)):
            raise InputError("impacts must be a tuple of pim.model.case.ImpactSpec")
        if self.speed_unit is not None and self.speed_unit not in SPEED_UNITS:
            raise InputError(f"speed_unit must be one of {', '.join(SPEED_UNITS)}, got "
                             f"{self.speed_unit!r}")
        single = _single(self.vehicle1, self.vehicle2, self.impact)
        if self.vehicle1.mass == math.inf if single else self.vehicle1.fixed.any():
            raise InputError("vehicle1.mass must be finite: only vehicle2 may be a fixed obstacle")
        _check_conditioning(self, single)
        if single:
            self.__dict__["is_scalar"] = True    # the cached property, known already

    def _check_types(self) -> None:
        """vehicle1 and vehicle2 are Vehicles, impact an Impact."""
        for name, kind in (("vehicle1", Vehicle), ("vehicle2", Vehicle), ("impact", Impact)):
            check_type(getattr(self, name), name, kind, f"a pim.{kind.__name__}")

    def _check_tables(self) -> None:
        """measured, uncertainty, evidence and unknown: None or their types (a string
        there would fail deep inside a fit or a Monte Carlo). The uncertainty table and the
        evidence are recognised by what they hold (their modules import this one)."""
        for name, kind, what in (("measured", Measured, "a pim.Measured"),
                                 ("unknown", dict, "a dict of dotted key -> (low, high) bounds")):
            check_type(getattr(self, name), name, kind, what, none=True)
        for name, holds, what in (
                ("uncertainty", isinstance(getattr(self.uncertainty, "inputs", None), dict),
                 "a pim.model.distributions.UncertaintyTable"),
                ("evidence", hasattr(self.evidence, "has_runout"),
                 "a pim.model.evidence.Evidence")):
            if getattr(self, name) is not None and not holds:
                check_type(getattr(self, name), name, (), what, none=True)

    @cached_property
    def shape(self) -> tuple:
        """Broadcast shape of the case's inputs: () for a single case, (n,) for n samples."""
        v1, v2, imp = self.vehicle1, self.vehicle2, self.impact
        return np.broadcast_shapes(
            np.shape(v1.mass), np.shape(v1.yaw_inertia), np.shape(v1.cg)[:-1],
            np.shape(v1.velocity)[:-1], np.shape(v1.yaw_rate), np.shape(v2.mass),
            np.shape(v2.yaw_inertia), np.shape(v2.cg)[:-1], np.shape(v2.velocity)[:-1],
            np.shape(v2.yaw_rate), np.shape(imp.point)[:-1], np.shape(imp.normal_angle))

    @cached_property
    def is_scalar(self) -> bool:
        """True for a single case (every input a scalar or one [x, y] pair)."""
        if _single(self.vehicle1, self.vehicle2, self.impact):
            return True   # the common single case, without broadcasting shapes
        return self.shape == ()

    def transformed(self, rotation: float = 0.0, translation=(0.0, 0.0)) -> Case:
        """The same scene rotated by ``rotation`` [rad] about the origin, then translated [m]."""
        shift = np.asarray(translation, dtype=float)

        def move(v: Vehicle) -> Vehicle:
            return replace(v, cg=rotate(v.cg, rotation) + shift,
                           velocity=rotate(v.velocity, rotation), heading=v.heading + rotation)

        measured = self.measured
        if measured is not None:
            def turn(v):
                return None if v is None else rotate(v, rotation)

            measured = replace(measured, velocity1=turn(measured.velocity1),
                               velocity2=turn(measured.velocity2))
        impact = replace(self.impact, point=rotate(self.impact.point, rotation) + shift,
                         normal_angle=self.impact.normal_angle + rotation)
        return replace(self, vehicle1=move(self.vehicle1), vehicle2=move(self.vehicle2),
                       impact=impact, measured=measured)

    def swapped(self) -> Case:
        """The same scene with the vehicles' roles exchanged (n flips: Gamma + pi)."""
        if self.vehicle2.fixed.any():
            raise InputError("vehicle2 is a fixed obstacle; it cannot become vehicle1")
        measured = self.measured
        if measured is not None:
            measured = Measured(measured.velocity2, measured.velocity1,
                                measured.yaw_rate2, measured.yaw_rate1)
        impact = replace(self.impact, normal_angle=self.impact.normal_angle + np.pi)
        other = {"vehicle1": "vehicle2", "vehicle2": "vehicle1"}
        estimates = tuple(replace(e, name=".".join(other.get(p, p) if i == 0 else p
                                                   for i, p in enumerate(e.name.split("."))))
                          for e in self.estimates)
        return replace(self, vehicle1=self.vehicle2, vehicle2=self.vehicle1, impact=impact,
                       measured=measured, estimates=estimates)


def checked_case(case, name: str = "case") -> Case:
    """``case`` if it is a :class:`Case`; else an
    :class:`~pim.model.numbers.ArgumentTypeError` naming ``name`` and how to get one
    (a case name or path is loaded by :func:`pim.load_case`)."""
    return check_type(case, name, Case, "a pim.Case (a case name or file is read by "
                                        "pim.load_case(...))")
