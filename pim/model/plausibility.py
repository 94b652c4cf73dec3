"""What is wrong or doubtful about a case and its answer, in words with the numbers.

Two grades, as a reconstructionist would weigh them:

* **inadmissible** (:func:`inadmissible_reasons`): the answer breaks the law's own physics or
  bounds (:mod:`pim.model.admissibility`): the contact would pull, kinetic energy is gained,
  q is singular, beta outside [0, 1] under Brach's law (the slip at C reverses, or the
  tangential impulse goes along the remaining slip). The command line prints the reasons
  first and exits 1 unless asked (``--allow-inadmissible``).
* **implausible** (:func:`geometry_warnings`, :func:`plausibility_warnings`): admissible, but
  probably not meant -- an input that was likely mistyped, or a contact asking more than
  sheet metal gives. Warnings before the table; the exit code stays 0.

Geometry checks (:func:`geometry_checks`, vectorised over a batch of cases) and their
thresholds, each in the message:

* C against the outlines, when a vehicle has ``length`` and ``width``: C more than
  :data:`C_OUTSIDE_TOLERANCE` outside an outline (the vehicles cannot touch there), or deeper
  inside a moving vehicle's outline than its plausible crush (:func:`crush_limit`);
* without an outline, C farther than :data:`FAR_FROM_CG` times the vehicle's length from its
  CG (the length estimated from the radius of gyration, :func:`reference_length`);
* C nearer a moving vehicle's CG than :data:`NEAR_CG` times its length (a CG or C written in
  mm instead of m puts C millimetres from the CG);
* the velocity more than 90 deg from the heading: the vehicle is reversing, said unless the
  case states it (``reversing = true`` in ``[vehicleN]``); and the reverse contradiction;
* the velocity more than :data:`SLIDING_ANGLE` off the fore-aft axis (ahead or, reversing,
  behind): the vehicle slides sideways into the impact, said unless the case states it
  (``sliding = true``), as a heading or velocity mistyped does it too;
* a pre-impact yaw rate above :data:`PLAUSIBLE_YAW_RATE`, more than a car reaches before an
  impact: rad/s written for deg/s?
* the two outlines overlapping at the impact by more than both plausible crushes together.

Every number reaches the message through ``show(value [SI], kind) -> str`` (kinds
"length", "velocity", "impulse", "energy", "angle", "angular_velocity"), so that the edge prints it in the
case's units (:func:`pim.io.units.quantity_text`); the default :func:`si_text` prints SI.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .geometry import (
    heading_velocity_angle,
    outline_penetration,
    outline_world,
    point_outline_distance,
    radius_of_gyration,
)
from .result import Result

__all__ = ["plausibility_warnings", "no_impact_message", "warnings_of",
           "Findings", "findings", "inadmissible_reasons", "geometry_checks",
           "geometry_findings", "geometry_warnings", "si_text", "IMPOSSIBLE_CHECKS",
           "reference_length", "crush_limit", "C_OUTSIDE_TOLERANCE", "FAR_FROM_CG", "NEAR_CG",
           "PLAUSIBLE_CRUSH", "CRUSH_MARGIN", "GYRATION_PER_LENGTH", "secondary_contact",
           "SECONDARY_DEPTH", "SLIDING_ANGLE", "PLAUSIBLE_YAW_RATE"]

#: How far [m] C may lie outside a vehicle's outline: the outline is a rectangle, the real
#: body rounded, and C is read off a scene drawing; beyond this the vehicles cannot touch at C.
C_OUTSIDE_TOLERANCE = 0.3
#: Without an outline, C farther than this times the vehicle's length from its CG is off the
#: vehicle (the farthest corner of a 4.5 x 1.8 m car is 0.54 lengths from a central CG).
FAR_FROM_CG = 0.75
#: C nearer a moving vehicle's CG than this times its length (0.22 m for a 4.5 m car) puts
#: the crush at the CG: a CG or C written in mm instead of m does it (C 2 mm from the CG).
NEAR_CG = 0.05
#: Deepest crush [m] taken as plausible for a vehicle without a crush profile: the crush of a
#: car at the full NCAP frontal barrier test (56 km/h) is about 0.5-0.7 m.
PLAUSIBLE_CRUSH = 0.75
#: Margin [m] over a measured crush profile's deepest crush (C and the outline are placed by
#: hand).
CRUSH_MARGIN = 0.15
#: Largest angle [rad] between a vehicle's velocity and its fore-aft axis (30 deg) taken as
#: rolling on its wheels: beyond it the vehicle slides or yaws sideways into the impact.
SLIDING_ANGLE = float(np.radians(30.0))
#: Largest |yaw rate| [rad/s] before the impact taken as plausible (one turn a second,
#: 360 deg/s): cars spinning out before a crash turn a fraction of that, and a yaw rate
#: written in rad/s where deg/s was meant is 57 times too large (45 "rad/s": 2578 deg/s).
PLAUSIBLE_YAW_RATE = float(2 * np.pi)
#: Radius of gyration over length, k / L, of a car (RICSAC 9's vehicles: 0.287 and 0.291;
#: a uniform 4.5 x 1.8 m box: 0.311): the length estimated for a vehicle without an outline.
GYRATION_PER_LENGTH = 0.29

#: Geometry checks whose failure makes the case impossible (graded as errors, not warnings).
IMPOSSIBLE_CHECKS = ("unreachable",)
#: Checks about where C lies on a vehicle (left out where C cannot be on it at all).
_ABOUT_C = ("near", "far", "outside", "deep")

#: ``show(value [SI], kind) -> str``: a number with its unit for a message.
Show = Callable[[float, str], str]

_SI_LABELS = {"length": "m", "velocity": "m/s", "impulse": "N s", "energy": "J"}


def si_text(value: float, kind: str) -> str:
    """``value`` [SI] of ``kind`` as "12.3 m" (angles [rad] in degrees): the default
    ``show`` of the messages."""
    if kind == "angle":
        return f"{np.degrees(value):.4g} deg"
    if kind == "angular_velocity":
        return f"{np.degrees(value):.4g} deg/s"
    return f"{value:.4g} {_SI_LABELS[kind]}"

#: Largest |mu0| at beta = 1 taken as plausible: above it the sticking impulse would need a
#: tangential impulse larger than the normal one, a friction coefficient above 1.
PLAUSIBLE_MU0 = 1.0


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


@dataclass(frozen=True)
class Findings:
    """What a command says about a case and its answer before the answer itself.

    Attributes
    ----------
    errors : list of str
        What makes the answer impossible: inadmissible (:func:`inadmissible_reasons`) or an
        impossible geometry (:data:`IMPOSSIBLE_CHECKS`). The command line exits 1 after the
        answer unless told to accept it.
    warnings : list of str
        What is implausible: the case file's notes, the geometry and the plausibility
        warnings.
    """

    errors: list
    warnings: list

    @property
    def all(self) -> list[str]:
        """Errors, then warnings."""
        return [*self.errors, *self.warnings]


def findings(case, result=None, friction_limit=None, show: Show = si_text) -> Findings:
    """The errors and warnings about ``case`` and its answer ``result`` (None: the case
    alone), numbers in ``show``'s units (see :class:`Findings`)."""
    geometry_errors, geometry = geometry_findings(case, show)
    answer = [] if result is None else inadmissible_reasons(result, show)
    soft = [] if result is None else plausibility_warnings(result, friction_limit)
    return Findings([*geometry_errors, *answer], [*case.notes, *geometry, *soft])


def warnings_of(case, result, friction_limit=None, show: Show = si_text) -> list[str]:
    """Every error and warning a command or report prints (:func:`findings`), errors
    first, numbers in ``show``'s units."""
    return findings(case, result, friction_limit, show).all


def _reason_numbers(result: Result, key: str, show: Show) -> str:
    """The numbers behind a failed admissibility check of a single result (key of
    :meth:`pim.Result.admissibility_checks`), in ``show``'s units."""
    def one(name):
        return float(np.asarray(getattr(result, name)).reshape(()))

    if key == "approach":
        return f"u_n = {show(one('approach_n'), 'velocity')}"
    if key == "pull":
        return f"Pn = {show(one('impulse_n'), 'impulse')}"
    if key == "energy":
        gained, before = -one("energy_loss"), one("kinetic_energy_before")
        return (f"{show(gained, 'energy')} gained, {100 * gained / before:.3g} % of the "
                f"{show(before, 'energy')} before the impact")
    if key == "along":
        return (f"Pt = {show(one('impulse_t'), 'impulse')} with the slip left at C "
                f"U_t = {show(one('separation_t'), 'velocity')}")
    if key in ("reverses", "drives"):
        return (f"beta = {one('beta'):.4g}, mu = {one('mu'):.4g}, mu0 = {one('mu0'):.4g}; "
                f"Brach's law takes beta in [0, 1]")
    return ""


def inadmissible_reasons(result: Result, show: Show = si_text) -> list[str]:
    """Why ``result`` is inadmissible (:attr:`pim.Result.admissible` False), one sentence per
    failed check with its numbers in ``show``'s units; empty when it is admissible.

    Parameters
    ----------
    result : Result
        A single answer, or a batch (then each reason says how many of the cases fail it,
        as :meth:`pim.Result.problems` does).
    show : callable
        ``show(value [SI], kind) -> str`` (default :func:`si_text`).

    Returns
    -------
    list of str
        "inadmissible answer: <reason> (<numbers>)" per failed check, in the order of
        :meth:`pim.Result.admissibility_checks`.
    """
    single = np.size(result.impulse_n) == 1
    out = []
    for ok, text, key in result.admissibility_checks():
        ok = np.asarray(ok)
        bad = int(ok.size - np.count_nonzero(ok))
        if not bad:
            continue
        numbers = _reason_numbers(result, key, show) if single else f"{bad} of {ok.size} cases"
        out.append(f"inadmissible answer: {text}" + (f" ({numbers})" if numbers else ""))
    return out


def reference_length(vehicle) -> np.ndarray:
    """A vehicle's length [m] for the geometry checks: its outline's ``length``, else its
    radius of gyration over :data:`GYRATION_PER_LENGTH` (0 for a fixed obstacle)."""
    if vehicle.length is not None:
        return np.asarray(vehicle.length, dtype=float)
    return radius_of_gyration(vehicle.mass, vehicle.yaw_inertia) / GYRATION_PER_LENGTH


def crush_limit(case, i: int) -> tuple[float, float | None]:
    """The deepest plausible crush [m] of vehicle ``i``, and its crush profile's deepest
    crush [m] it comes from (None: no profile, the limit is :data:`PLAUSIBLE_CRUSH`); with a
    profile the limit is that depth plus :data:`CRUSH_MARGIN`."""
    profile = case.evidence.crush.get(i) if case.evidence is not None else None
    if profile is None:
        return PLAUSIBLE_CRUSH, None
    deepest = float(max(profile.depths))
    return deepest + CRUSH_MARGIN, deepest


def _outline(v):
    """(cg, heading, length, width, cg_to_front) of a vehicle with an outline, else None."""
    if v.length is None or v.width is None:
        return None
    return v.cg, v.heading, v.length, v.width, v.cg_to_front


def _vehicle_checks(case, i: int) -> dict:
    """The checks of vehicle ``i`` as {key: (flag, value, limit)} arrays (see the module)."""
    v, point = (case.vehicle1, case.vehicle2)[i - 1], case.impact.point
    moving = ~np.asarray(v.fixed)
    arm = np.hypot(*np.moveaxis(np.asarray(point - v.cg, dtype=float), -1, 0))
    length = reference_length(v)
    out = {f"unreachable{i}": (moving & (arm > length), arm, length),
           f"near{i}": (moving & (arm < NEAR_CG * length), arm, NEAR_CG * length)}
    outline = _outline(v)
    if outline is None:
        out[f"far{i}"] = (moving & (arm > FAR_FROM_CG * length), arm, FAR_FROM_CG * length)
    else:
        distance = point_outline_distance(point, *outline)
        crush = crush_limit(case, i)[0]
        out[f"outside{i}"] = (distance > C_OUTSIDE_TOLERANCE, distance, C_OUTSIDE_TOLERANCE)
        out[f"deep{i}"] = (moving & (-distance > crush), -distance, crush)
    return {**out, **_motion_checks(v, i, moving)}


def _motion_checks(v, i: int, moving) -> dict:
    """The checks of vehicle ``i``'s motion as {key: (flag, value, limit)}: reversing (or
    said to and not), sliding sideways (unless said to, or reversing unsaid, which its own
    check tells), and a yaw rate beyond :data:`PLAUSIBLE_YAW_RATE`."""
    angle = heading_velocity_angle(v.heading, v.velocity)
    with np.errstate(invalid="ignore"):
        backwards, forwards = angle > np.pi / 2, angle <= np.pi / 2
        off_axis = np.minimum(angle, np.pi - angle)
        sideways = np.round(off_axis, 9) > SLIDING_ANGLE
    reversing = moving & backwards & (not v.reversing)
    forward = moving & forwards & v.reversing
    spin = np.abs(np.asarray(v.yaw_rate, dtype=float))
    return {f"reversing{i}": (reversing, angle, np.pi / 2),
            f"forward{i}": (forward, angle, np.pi / 2),
            f"sliding{i}": (moving & sideways & ~reversing & ~forward & (not v.sliding),
                            off_axis, SLIDING_ANGLE),
            f"spin{i}": (moving & (spin > PLAUSIBLE_YAW_RATE), spin, PLAUSIBLE_YAW_RATE)}


def geometry_checks(case) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The geometry checks of a case (single or a batch), vectorised.

    Parameters
    ----------
    case : Case
        Any case; fields may be arrays.

    Returns
    -------
    dict
        Check key -> (flag, value, limit), arrays broadcast over the case: ``near{i}``,
        ``far{i}`` (without an outline) or ``outside{i}`` and ``deep{i}`` (with one):
        |C - CG| or C's signed distance to the outline [m] and the limit [m];
        ``reversing{i}`` and ``forward{i}``: the angle between heading and velocity [rad]
        and pi / 2; ``sliding{i}``: the velocity's angle off the fore-aft axis [rad] and
        :data:`SLIDING_ANGLE`; ``spin{i}``: |yaw rate| [rad/s] and
        :data:`PLAUSIBLE_YAW_RATE`; ``overlap`` (both outlines, vehicle 2 moving): the outlines' overlap
        depth [m] and the sum of both crush limits. ``flag`` is True where the case is
        implausible (module notes).
    """
    out = {**_vehicle_checks(case, 1), **_vehicle_checks(case, 2)}
    o1, o2 = _outline(case.vehicle1), _outline(case.vehicle2)
    if o1 is not None and o2 is not None:
        depth = outline_penetration(o1, o2)
        limit = crush_limit(case, 1)[0] + crush_limit(case, 2)[0]
        out["overlap"] = (~np.asarray(case.vehicle2.fixed) & (depth > limit), depth, limit)
    return out


def _crush_text(case, i: int, show: Show) -> str:
    """Vehicle ``i``'s plausible crush with where it comes from, for a message."""
    limit, deepest = crush_limit(case, i)
    if deepest is None:
        return f"{show(limit, 'length')} (no crush profile given)"
    return (f"{show(limit, 'length')} (its crush profile's deepest {show(deepest, 'length')} "
            f"+ {show(CRUSH_MARGIN, 'length')})")


def _length_text(case, i: int, show: Show, index) -> str:
    """Vehicle ``i``'s length for a message, saying when it is estimated."""
    v = (case.vehicle1, case.vehicle2)[i - 1]
    length = show(_pick(reference_length(v), index), "length")
    if v.length is not None:
        return length
    return f"{length}, estimated as its radius of gyration / {GYRATION_PER_LENGTH:g}"


def _pick(value, index) -> float:
    """Element ``index`` of ``value`` broadcast to the shape of the flag (a float)."""
    value = np.asarray(value, dtype=float)
    return float(value if value.ndim == 0 else np.broadcast_to(value, index[1])[index[0]])


def _direction(v, index) -> tuple[float, float]:
    """(heading, direction of the velocity) [rad] of vehicle ``v`` at ``index``."""
    velocity = np.asarray(v.velocity, dtype=float)
    heading = _pick(v.heading, index)
    vx, vy = (_pick(velocity[..., k], index) for k in (0, 1))
    turn = 2 * np.pi
    return round(heading % turn, 9) % turn, round(np.arctan2(vy, vx) % turn, 9) % turn


def _message(case, key: str, value: float, limit: float, show: Show, index) -> str:
    """The sentence of a failed geometry check (``index``: the element it is about)."""
    i = int(key[-1]) if key[-1].isdigit() else 0
    name, length = f"vehicle{i}", "length"
    if key.startswith("near"):
        return (f"{name}: C is {show(value, length)} from its CG, less than {NEAR_CG:g} x its "
                f"length ({_length_text(case, i, show, index)}): the crush would reach the "
                f"CG; a CG or C written in mm or cm instead of m? (check {name}.cg and "
                f"impact.point)")
    if key.startswith("unreachable"):
        return (f"{name}: C is {show(value, length)} from its CG, farther than its whole "
                f"length ({_length_text(case, i, show, index)}): no part of the vehicle is "
                f"there, so the vehicles cannot touch at C (check impact.point and {name}.cg)")
    if key.startswith("far"):
        return (f"{name}: C is {show(value, length)} from its CG, more than {FAR_FROM_CG:g} x "
                f"its length ({_length_text(case, i, show, index)}): C must lie on the "
                f"vehicle (check impact.point and {name}.cg)")
    if key.startswith("outside"):
        return (f"{name}: C lies {show(value, length)} outside its outline (more than "
                f"{show(limit, length)}): the vehicles cannot touch there (check impact.point, "
                f"{name}.cg, {name}.heading and its length and width)")
    if key.startswith("deep"):
        return (f"{name}: C lies {show(value, length)} inside its outline, deeper than its "
                f"plausible crush {_crush_text(case, i, show)} (check impact.point and "
                f"{name}.cg)")
    if key == "overlap":
        return (f"the outlines overlap by {show(value, length)} at the impact, more than both "
                f"vehicles' plausible crush together ({show(limit, length)}: vehicle 1 "
                f"{_crush_text(case, 1, show)}, vehicle 2 {_crush_text(case, 2, show)}): "
                f"check the CGs, headings and outlines")
    if key.startswith("spin"):
        return _spin_message(name, value, limit, show)
    v = (case.vehicle1, case.vehicle2)[i - 1]
    if key.startswith("sliding"):
        return _sliding_message(v, name, value, limit, show, index)
    heading, moving = _direction(v, index)
    value = round(value, 9)         # round-off of arctan2 is no angle: 0 deg, not 3.5e-15
    angles = (f"{show(value, 'angle')} from its heading (heading {show(heading, 'angle')}, "
              f"moving toward {show(moving, 'angle')})")
    if key.startswith("forward"):
        return f"{name}: reversing = true, but it moves forwards: its velocity points {angles}"
    return (f"{name} is reversing: its velocity points {angles}, so its PDOF and clock "
            f"position read the impact as if the nose led. If it is reversing, say so with "
            f"reversing = true in [{name}]; else check {name}.heading")


def _spin_message(name: str, value: float, limit: float, show: Show) -> str:
    """The sentence of a yaw rate beyond :data:`PLAUSIBLE_YAW_RATE` (``value`` [rad/s])."""
    return (f"{name} turns at {show(value, 'angular_velocity')} before the impact "
            f"({value:.4g} rad/s), more than {show(limit, 'angular_velocity')} (one turn a "
            f"second), beyond what a car reaches: rad/s written for deg/s? (check "
            f"{name}.yaw_rate: '{value:.4g} deg/s' would be {np.radians(value):.4g} rad/s)")


def _sliding_message(v, name: str, value: float, limit: float, show: Show, index) -> str:
    """The sentence of a velocity more than :data:`SLIDING_ANGLE` (``limit``) off the
    fore-aft axis (``value`` [rad])."""
    heading, moving = _direction(v, index)
    angle = abs(((moving - heading + np.pi) % (2 * np.pi)) - np.pi)
    return (f"{name} slides sideways into the impact: its velocity points "
            f"{show(angle, 'angle')} from its heading (heading {show(heading, 'angle')}, "
            f"moving toward {show(moving, 'angle')}), {show(value, 'angle')} off its "
            f"fore-aft axis, more than {show(limit, 'angle')}. If it slides or yaws "
            f"sideways, say so with sliding = true in [{name}]; else check {name}.heading "
            f"and {name}.velocity")


def geometry_findings(case, show: Show = si_text) -> tuple[list[str], list[str]]:
    """The failed checks of :func:`geometry_checks` in words, each with its numbers (in
    ``show``'s units), as (errors, warnings): C farther from a moving vehicle's CG than its
    length is impossible (an error, :data:`IMPOSSIBLE_CHECKS`), the rest implausible. A
    vehicle with an impossible C gets no further warning about C. For a batch, the first
    failing case's numbers and how many fail."""
    checks = geometry_checks(case)
    errors, warnings = [], []
    for key, (flag, value, limit) in checks.items():
        flag = np.asarray(flag)
        bad = int(np.count_nonzero(flag))
        impossible = key.rstrip("12") in IMPOSSIBLE_CHECKS
        if not bad or (not impossible and key[-1].isdigit() and key.startswith(_ABOUT_C)
                       and np.all(checks[f"unreachable{key[-1]}"][0])):
            continue
        index = (int(np.flatnonzero(flag)[0]) if flag.ndim else 0, flag.shape)
        text = _message(case, key, _pick(value, index), _pick(limit, index), show, index)
        text = text if flag.ndim == 0 else f"{text} ({bad} of {flag.size} cases)"
        (errors if impossible else warnings).append(text)
    return errors, warnings


def geometry_warnings(case, show: Show = si_text) -> list[str]:
    """Every failed geometry check in words, errors first (:func:`geometry_findings`)."""
    errors, warnings = geometry_findings(case, show)
    return errors + warnings




#: How much deeper [m] the outlines must overlap again, after their least overlap since the
#: impact, to count as a secondary contact of two moving outlines (:func:`secondary_contact`).
SECONDARY_DEPTH = 0.05


def secondary_contact(times, poses1, poses2, vehicle1, vehicle2,
                      tolerance: float = SECONDARY_DEPTH) -> tuple[float, np.ndarray] | None:
    """When and where two vehicles' outlines run into each other again after the impact.

    Parameters
    ----------
    times : array_like (n,)
        Time after the impact [s], increasing from 0 (the impact pose).
    poses1, poses2 : array_like (n, 3)
        Each vehicle's CG position and heading (x [m], y [m], heading [rad]) at ``times``.
    vehicle1, vehicle2 : Vehicle
        Their outlines (``length``, ``width``, ``cg_to_front``).
    tolerance : float
        Growth [m] of the overlap depth over its least value since the impact that counts.

    Returns
    -------
    (float, ndarray (2,)) or None
        The first time [s] at which the outlines overlap (depth > 0) by more than
        ``tolerance`` beyond their least overlap since the impact, and the deepest corner of
        either outline inside the other then [m]; None without both outlines or when it never
        happens (the outlines may overlap at the impact, by the crush, and part).

    Notes
    -----
    The overlap depth is :func:`pim.model.geometry.outline_penetration` per frame; the
    running minimum makes an overlap that only shrinks after the impact no contact.
    """
    if _outline(vehicle1) is None or _outline(vehicle2) is None:
        return None
    p1, p2 = np.asarray(poses1, dtype=float), np.asarray(poses2, dtype=float)
    outlines = [(p[:, :2], p[:, 2], v.length, v.width, v.cg_to_front)
                for p, v in ((p1, vehicle1), (p2, vehicle2))]
    depth = outline_penetration(*outlines)
    hit = np.flatnonzero((depth > 0) & (depth > np.minimum.accumulate(depth) + tolerance))
    if not hit.size:
        return None
    i = int(hit[0])
    corners = []
    for (own, other) in ((outlines[0], outlines[1]), (outlines[1], outlines[0])):
        cg, heading, length, width, front = own
        world = outline_world(length, width, cg[i], heading[i], front)
        inside = point_outline_distance(world, other[0][i], other[1][i], *other[2:])
        corners += list(zip(inside, world, strict=True))
    return float(np.asarray(times)[i]), min(corners, key=lambda c: c[0])[1]
