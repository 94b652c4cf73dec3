"""Case files: TOML descriptions of an impact, with units, in global or Brach form.

A case file names each quantity with units (``"31.09 ft/s"``, ``"2255.4 lbf"``, ``"90 deg"``,
``"976 slug*ft**2"``) with nothing after the unit. A bare number is read only for a
dimensionless input (restitution, beta, friction) and for 0 of any kind; any other bare
number (``velocity = [50, 0]``: 50 m/s, km/h or mph?) is refused with the units it could mean
(:func:`pim.io.units.parse`).
Unknown keys are errors, so a typo is never silently ignored; every error is a
:class:`pim.InputError` naming the field. Layout (global form; see ``pim/io/cases/ricsac9.toml``)::

    name = "ricsac9"
    description = "..."
    [vehicle1]                      # and [vehicle2]
    mass = "..."                    # or weight = "... lbf" (divided by standard gravity)
    yaw_inertia = "..."             # or radius_of_gyration = "... ft"; or neither, with
    wheelbase = "2.7 m"             #   wheelbase (and optionally cg_to_front_axle = "1.2 m",
    body = "car"                    #   body = "car" / "suv" / "pickup" / "van"): estimated
                                    #   (without a wheelbase: a car's length gives it,
                                    #   else from the mass alone)
    cg = ["4.774 ft", "0.502 ft"]
    heading = "180 deg"
    velocity = ["-31.09 ft/s", 0]     # 0 needs no unit
    yaw_rate = "0 deg/s"
    length = "4.1 m"                # optional, with width: outline for drawing
    cg_to_front = "1.9 m"           # optional: CG to front bumper (default length / 2)
    reversing = true                # optional: it moves backwards (silences that warning)
    sliding = true                  # optional: it slides sideways (silences that warning)
    [impact]
    point = [0, 0]
    normal_angle = "0 deg"          # Gamma: n points from vehicle 2 toward vehicle 1
    # or contact_plane_angle = "90 deg": PC-Crash's contact plane (its direction psi);
    #    Gamma = psi +- 90 deg, whichever normal points toward vehicle 1's CG
    restitution = 0.355             # optional defaults for solve (k for kudlich-slibar)
    beta = 1
    law = "brach"                   # or "kudlich-slibar", "brach-capped" (docs/impact-laws.md)
    contact_friction = 0.6          # mu_c of "kudlich-slibar" / the cap of "brach-capped"
    [measured]                      # optional
    vehicle1.velocity = ["-5.1 ft/s", "17.6 ft/s"]
    vehicle1.yaw_rate = "-180 deg/s"
    [units]                         # optional: the units results are presented in
    system = "us"                   # "si" or "us" (default: the units the file is written in)
    speed = "mph"                   # "km/h", "mph", "m/s" or "ft/s" (default: km/h for si,
                                    # mph for us)

A vehicle without ``yaw_inertia`` and ``radius_of_gyration`` gets its yaw inertia estimated
from its mass and wheelbase by the yaw dynamic index of its body class (NHTSA's measured
vehicles, :mod:`pim.model.inertia`; docs/inertia-estimate.md): the case records the estimate
(``Case.estimates``), the Monte Carlo draws it with its scatter unless ``[uncertainty]`` gives
``vehicleN.yaw_inertia`` a distribution, and loading the file writes one line on stderr
naming the vehicle, the value and the method. The wheelbase and CG-to-front-axle distance
may come from ``[evidence.vehicleN]`` instead (they must agree where both give them).
Without a wheelbase, a car's overall ``length`` gives one (the wheelbase line of Lock's 1993
cars, :mod:`pim.io.length_data`, its scatter added); else the mass alone estimates it.

``fixed = true`` in ``[vehicle2]`` makes it a barrier or pole (no mass, inertia, velocity;
``cg`` defaults to the impact point and ``heading`` to 0, as neither changes the answer).

Every quantity must lie within :data:`pim.io.units.LIMITS` (e.g. lengths within 1e5 m,
speeds within 1e4 m/s, masses between 1 g and 1e9 kg). The case records the unit system its
file is written in (``Case.units``: "us" when any quantity uses ft, lbf, mph, slug ...), which
the commands print in unless ``[units] system`` or ``--units`` says otherwise, and the speed
unit of ``[units] speed`` (``Case.speed_unit``; ``--speed-unit`` overrides it).
``convention = "brach"`` replaces each vehicle's ``cg`` and ``heading`` by Brach's ``theta``,
``phi`` and ``d`` (see :mod:`pim.io.brach`), with C at ``impact.point`` (default the origin).
"""

from __future__ import annotations

import logging
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

from ..model.case import Case, Impact, ImpactSpec, Vehicle
from ..model.distributions import Distribution, UncertaintyTable
from ..model.numbers import InputError, unit_text
from ..model.tyres import STANDARD_GRAVITY
from .brach import cg_from_brach, heading_from_theta
from .evidence_table import AXLE_KEY, OLD_AXLE_KEY, parse_evidence, parse_unknown
from .inertia_data import (
    estimate_notes,
    estimate_yaw_inertia,
    estimate_yaw_inertia_from_length,
    estimate_yaw_inertia_from_mass,
)
from .measured_table import parse_measured
from .toml_tables import check_keys
from .tyre_table import attach_tyres
from .uncertainty_table import parse_uncertainty
from .units import (LIMITS, SPEED_UNITS, UNIT_SYSTEMS, DisplayUnits, messages_in, parse,
                    unit_system_of)

__all__ = ["load_case", "list_cases", "parse_case", "parse_impacts", "MAX_FURTHER"]

_TOP = {"name", "description", "source", "convention", "vehicle1", "vehicle2", "impact",
        "measured", "uncertainty", "evidence", "unknown", "tyres", "driver", "units",
        "impacts"}
_VEHICLE = {"mass", "weight", "yaw_inertia", "radius_of_gyration", "velocity", "yaw_rate",
            "length", "width", "cg_to_front", "fixed", "cg", "heading", "theta", "phi", "d",
            "wheelbase", "cg_to_front_axle", "body", "reversing", "sliding"}
#: Keys of a moving vehicle that a fixed obstacle must not have.
_MOVING = ("mass", "weight", "yaw_inertia", "radius_of_gyration", "velocity", "yaw_rate",
           "wheelbase", "cg_to_front_axle", "body", "reversing", "sliding")
_LOG = logging.getLogger(__name__)

#: Deepest nesting of tables and lists a case file may have: the deepest legitimate value,
#: ``[measured] vehicle1.velocity = [..]``, sits at depth 4.
MAX_DEPTH = 8
#: Longest ``name``, ``description`` or ``source`` [characters].
MAX_TEXT = {"name": 200, "description": 10_000, "source": 10_000}
_IMPACT = {"point", "normal_angle", "contact_plane_angle", "restitution", "beta", "law",
           "contact_friction"}
#: The keys of an ``[[impacts]]`` entry (an event's further impact, :class:`ImpactSpec`).
_FURTHER = {"law", "restitution", "beta", "contact_friction", "point", "normal_angle"}
#: Most ``[[impacts]]`` entries (the event's further impacts, MAX_IMPACTS).
MAX_FURTHER = 12


def _require(table: dict, key: str, where: str, *, file: bool = False):
    """``table[key]``, or an InputError naming what is missing: ``vehicle1.cg is missing``
    inside a table; ``FILE: [impact] is missing`` for a table of the file (``file=True``:
    ``where`` is then the file's name, never glued to the key)."""
    if key not in table:
        raise InputError(f"{where}: table [{key}] is missing" if file
                         else f"{where}.{key} is missing")
    return table[key]


def _pair(value, kind: str, field: str) -> np.ndarray:
    if not isinstance(value, list) or len(value) != 2:
        raise InputError(f"{field} must be a list of two values [x, y], got {value!r}")
    return np.array([parse(value[0], kind, f"{field}[0]"), parse(value[1], kind, f"{field}[1]")])


def _one_of(table: dict, a: str, b: str, where: str) -> str:
    present = [k for k in (a, b) if k in table]
    if len(present) != 1:
        raise InputError(f"{where}: give exactly one of {a!r} or {b!r}")
    return present[0]


def _optional(table: dict, key: str, kind: str, where: str):
    return parse(table[key], kind, f"{where}.{key}") if key in table else None


def _length(table: dict, key: str, where: str, what: str, strict: bool = True):
    """A length of a vehicle table [m] (None when absent), checked to be > 0 (``strict``) or
    >= 0 here, where the value as written (its unit the case's) can be quoted."""
    if key not in table:
        return None
    value = parse(table[key], "length", f"{where}.{key}")
    if value < 0 or (strict and value == 0):
        raise InputError(f"{where}.{key} = {table[key]!r} must be {'>' if strict else '>='} 0 "
                         f"({what})")
    return value


def _cg_to_front(table: dict, length, where: str):
    """``cg_to_front`` [m] (None when absent), inside the outline: in [0, length]."""
    if "cg_to_front" not in table:
        return None
    value = parse(table["cg_to_front"], "length", f"{where}.cg_to_front")
    if length is None:
        raise InputError(f"{where}.cg_to_front needs {where}.length (the outline it places "
                         f"the CG in)")
    if not 0 <= value <= length:
        raise InputError(f"{where}.cg_to_front = {table['cg_to_front']!r} must lie in the "
                         f"outline: between 0 and {where}.length = {table['length']!r}")
    return value


def _vehicle(table, where: str, convention: str, point: np.ndarray, number: int,
             evidence=None) -> tuple[Vehicle, object]:
    """The vehicle of ``[vehicleN]`` and the estimate of its yaw inertia (None when given);
    ``evidence`` is its raw ``[evidence.vehicleN]`` table, if any (wheelbase, axle)."""
    table = check_keys(table, _VEHICLE, where)
    placement = {"global": ("cg", "heading"), "brach": ("theta", "phi", "d")}[convention]
    stray = sorted(set(table) & ({"cg", "heading", "theta", "phi", "d"} - set(placement)))
    if stray:
        raise InputError(f"{where}: key {stray[0]!r} does not belong to the {convention!r} "
                         f"convention (use {', '.join(placement)})")
    flags = {key: table.get(key, False) for key in ("fixed", "reversing", "sliding")}
    for key, value in flags.items():
        if not isinstance(value, bool):
            raise InputError(f"{where}.{key} must be true or false, got {value!r}")
    fixed = flags.pop("fixed")
    if convention == "global" and fixed:
        cg = _pair(table["cg"], "length", f"{where}.cg") if "cg" in table else point
        heading = parse(table.get("heading", 0.0), "angle", f"{where}.heading")
    elif convention == "global":
        cg = _pair(_require(table, "cg", where), "length", f"{where}.cg")
        heading = parse(_require(table, "heading", where), "angle", f"{where}.heading")
    else:
        theta = parse(_require(table, "theta", where), "angle", f"{where}.theta")
        phi = parse(_require(table, "phi", where), "angle", f"{where}.phi")
        _require(table, "d", where)
        d = _length(table, "d", where, "the distance from the CG to C", strict=False)
        cg = cg_from_brach(theta, phi, d, number, point)
        heading = float(heading_from_theta(theta, number))
    length = _length(table, "length", where, "the outline's length")
    width = _length(table, "width", where, "the outline's width")
    cg_to_front = _cg_to_front(table, length, where)

    outline = {"length": length, "width": width, "cg_to_front": cg_to_front}
    if fixed:
        if number == 1:
            raise InputError(f"{where}.fixed: only vehicle2 may be a fixed obstacle")
        extra = sorted(set(table) & set(_MOVING))
        if extra:
            raise InputError(f"{where}.{extra[0]}: a fixed obstacle has no {extra[0]}")
        return _wrap(where, Vehicle.obstacle, cg=cg, heading=heading, **outline), None
    mass = _mass(table, where)
    inertia, estimate = _inertia(table, mass, where, evidence)
    velocity = _pair(_require(table, "velocity", where), "velocity", f"{where}.velocity")
    yaw_rate = parse(table.get("yaw_rate", 0.0), "angular_velocity", f"{where}.yaw_rate")
    return _wrap(where, Vehicle, mass=mass, yaw_inertia=inertia, cg=cg, velocity=velocity,
                 yaw_rate=yaw_rate, heading=heading, **flags, **outline), estimate


def _mass(table, where: str) -> float:
    """``mass``, or ``weight`` divided by standard gravity [kg]."""
    if _one_of(table, "mass", "weight", where) == "mass":
        return parse(table["mass"], "mass", f"{where}.mass")
    weight = parse(table["weight"], "force", f"{where}.weight")
    if weight <= 0:
        raise InputError(f"{where}.weight must be > 0, got {table['weight']!r}")
    return weight / STANDARD_GRAVITY


def _inertia(table, mass: float, where: str, evidence) -> tuple[float, object]:
    """The yaw inertia [kg m^2] (given, from the radius of gyration, or estimated from the
    mass and wheelbase) and its :class:`pim.model.inertia.InputEstimate` (None unless
    estimated)."""
    given = [k for k in ("yaw_inertia", "radius_of_gyration") if k in table]
    if len(given) > 1:
        raise InputError(f"{where}: give exactly one of 'yaw_inertia' or 'radius_of_gyration'")
    if not given:
        return _estimated_inertia(table, mass, where, evidence)
    if given[0] == "yaw_inertia":
        return parse(table["yaw_inertia"], "inertia", f"{where}.yaw_inertia"), None
    k = parse(table["radius_of_gyration"], "length", f"{where}.radius_of_gyration")
    if k <= 0:
        raise InputError(f"{where}.radius_of_gyration must be > 0, "
                         f"got {table['radius_of_gyration']!r}")
    inertia = mass * k * k
    low, high = LIMITS["inertia"]
    if mass > 0 and not low <= inertia <= high:
        raise InputError(f"{where}.radius_of_gyration = {table['radius_of_gyration']!r} "
                         f"gives a yaw inertia m k^2 = {unit_text(inertia, 'inertia', '.3g')} "
                         f"outside [{unit_text(low, 'inertia', '.3g')}, "
                         f"{unit_text(high, 'inertia', '.3g')}]")
    return inertia, None


def _estimated_inertia(table, mass: float, where: str, evidence) -> tuple[float, object]:
    """The yaw dynamic index's estimate (:func:`pim.io.inertia_data.estimate_yaw_inertia`)
    from the wheelbase and CG-to-front-axle distance of ``[vehicleN]`` or
    ``[evidence.vehicleN]``; without a wheelbase, from the mass and the outline's overall
    ``length`` (:func:`pim.io.inertia_data.estimate_yaw_inertia_from_length`: the wheelbase
    from the length), else the mass-only line of NHTSA's measured vehicles
    (:func:`pim.io.inertia_data.estimate_yaw_inertia_from_mass`; an error naming what to give
    when the mass lies outside its vehicles')."""
    wheelbase = _dimension(table, evidence, ("wheelbase",), where)
    body = table.get("body", "car")
    if wheelbase is None:
        estimate = (estimate_yaw_inertia_from_mass(mass, body, where) if "length" not in table
                    else estimate_yaw_inertia_from_length(
                        mass, parse(table["length"], "length", f"{where}.length"), body, where))
        return estimate.value, estimate
    axle = _dimension(table, evidence, (AXLE_KEY, OLD_AXLE_KEY), where)
    estimate = estimate_yaw_inertia(mass, wheelbase, axle, body, where)
    return estimate.value, estimate


def _dimension(table, evidence, keys: tuple, where: str) -> float | None:
    """A length [m] given in ``[vehicleN]`` (``keys[0]``) and/or ``[evidence.vehicleN]``
    (any of ``keys``, the axle's old name included); an error when the two disagree."""
    mine = _optional(table, keys[0], "length", where)
    theirs, key = None, keys[0]
    if isinstance(evidence, dict):
        for key in (k for k in keys if k in evidence):
            theirs = parse(evidence[key], "length", f"evidence.{where}.{key}")
            break
    if mine is not None and theirs is not None and not np.isclose(mine, theirs, rtol=1e-9):
        raise InputError(f"{where}.{keys[0]} = {table[keys[0]]!r} differs from "
                         f"evidence.{where}.{key} = {evidence[key]!r}: give it once, or the "
                         f"same length in both")
    return mine if mine is not None else theirs


def _wrap(where: str, factory, **kwargs):
    """Call ``factory`` and prefix any validation error with the table's name."""
    try:
        return factory(**kwargs)
    except ValueError as exc:
        raise InputError(f"{where}.{exc}") from None


def _uncertainty(table):
    """The ``[uncertainty]`` table (see :mod:`pim.model.distributions`), when present."""
    return None if table is None else parse_uncertainty(table)


def parse_case(data: dict, source: str = "<case>") -> Case:
    """Build a :class:`pim.Case` from a parsed TOML document (a dict).

    Raises
    ------
    ValueError
        Missing or unknown key, bad unit or dimension, or a value out of range; the message
        names the field.
    """
    _check_depth(data, source)
    data = check_keys(data, _TOP, source)
    presentation = _presentation(data)
    with messages_in(DisplayUnits(presentation["units"], presentation["speed_unit"])):
        return _parsed_case(data, source, presentation)


def _parsed_case(data: dict, source: str, presentation: dict) -> Case:
    """:func:`parse_case` of a checked document, its messages in the case's units
    (``presentation``: :func:`_presentation`'s)."""
    convention = data.get("convention", "global")
    if convention not in ("global", "brach"):
        raise InputError(f"convention must be 'global' or 'brach', got {convention!r}")
    impact_table = check_keys(_require(data, "impact", source, file=True), _IMPACT, "impact")
    if convention == "global" or "point" in impact_table:
        point = _pair(_require(impact_table, "point", "impact"), "length", "impact.point")
    else:
        point = np.zeros(2)
    normal_angle = None
    if "contact_plane_angle" not in impact_table:
        normal_angle = parse(_require(impact_table, "normal_angle", "impact"), "angle",
                             "impact.normal_angle")
    elif "normal_angle" in impact_table:
        raise InputError("impact: give normal_angle or contact_plane_angle, not both")
    eps = _optional(impact_table, "restitution", "dimensionless", "impact")
    beta = _optional(impact_table, "beta", "dimensionless", "impact")
    # the impact law and its contact friction (docs/impact-laws.md)
    law = impact_table.get("law")
    contact_friction = _optional(impact_table, "contact_friction", "dimensionless", "impact")
    evidence = data.get("evidence") if isinstance(data.get("evidence"), dict) else {}
    vehicles, estimates = zip(*(
        _vehicle(_require(data, f"vehicle{i}", source, file=True), f"vehicle{i}", convention,
                 point, i, evidence.get(f"vehicle{i}")) for i in (1, 2)), strict=True)
    estimates = tuple(e for e in estimates if e is not None)
    if normal_angle is None:
        normal_angle = _plane_normal(impact_table["contact_plane_angle"], point,
                                     vehicles[0].cg)
    impact = _wrap("impact", Impact, point=point, normal_angle=normal_angle,
                   restitution=eps, beta=beta, law=law, contact_friction=contact_friction)
    name = data.get("name", Path(source).stem)
    description = data.get("description", "")
    for key, value in (("name", name), ("description", description),
                       ("source", data.get("source", ""))):
        if not isinstance(value, str):
            raise InputError(f"{key} must be a string, got {value!r}")
        if len(value) > MAX_TEXT[key]:
            raise InputError(f"{key} has {len(value)} characters; at most {MAX_TEXT[key]}")
    case = Case(vehicle1=vehicles[0], vehicle2=vehicles[1], impact=impact,
                measured=parse_measured(data.get("measured")), name=name, description=description,
                uncertainty=_with_estimates(_uncertainty(data.get("uncertainty")), estimates),
                **presentation,
                evidence=attach_tyres(parse_evidence(data.get("evidence"), {
                    i + 1: (v.length, v.width) for i, v in enumerate(vehicles)},
                    _front_shares(data)), data.get("tyres"), data.get("driver")),
                unknown=parse_unknown(data.get("unknown")), estimates=estimates,
                impacts=parse_impacts(data.get("impacts")))
    for line in estimate_notes(case, case.units):
        _LOG.warning(f"note: {source}: {line}")
    return case


def _front_shares(data: dict) -> dict:
    """Vehicle number -> the front axle's static weight share 1 - a / L [-] from
    ``[vehicleN]`` wheelbase and cg_to_front_axle (where both are given), for the per-wheel
    braking of marks before the impact without run-out evidence."""
    shares = {}
    for i in (1, 2):
        table = data.get(f"vehicle{i}")
        if isinstance(table, dict) and "wheelbase" in table and AXLE_KEY in table:
            length = parse(table["wheelbase"], "length", f"vehicle{i}.wheelbase")
            a = parse(table[AXLE_KEY], "length", f"vehicle{i}.{AXLE_KEY}")
            if 0 <= a <= length and length > 0:
                shares[i] = 1.0 - a / length
    return shares
def parse_impacts(entries) -> tuple:
    """The ``[[impacts]]`` list: the law and coefficients of the event's further impacts in
    order (entry k is the event's impact k + 2; the last also any later one), each an
    :class:`ImpactSpec` (``law``, ``restitution``, ``beta``, ``contact_friction``, and
    optionally ``point`` and ``normal_angle`` instead of the outlines' contact geometry);
    () when absent."""
    if entries is None:
        return ()
    if not isinstance(entries, list) or not entries:
        raise InputError("impacts must be a list of tables ([[impacts]] entries)")
    if len(entries) > MAX_FURTHER:
        raise InputError(f"impacts has {len(entries)} entries; an event takes at most "
                         f"{MAX_FURTHER} further impacts")
    specs = []
    for k, entry in enumerate(entries):
        where = f"impacts[{k}]"
        table = check_keys(entry, _FURTHER, where)
        law = table.get("law", "brach-capped")
        if not isinstance(law, str):
            raise InputError(f"{where}.law must be a string, got {law!r}")
        point = _pair(table["point"], "length", f"{where}.point") if "point" in table else None
        specs.append(ImpactSpec(
            law=law, restitution=_optional(table, "restitution", "dimensionless", where),
            beta=_optional(table, "beta", "dimensionless", where),
            contact_friction=_optional(table, "contact_friction", "dimensionless", where),
            point=point, normal_angle=_optional(table, "normal_angle", "angle", where),
            where=where))
    return tuple(specs)


def _with_estimates(table, estimates) -> UncertaintyTable | None:
    """The ``[uncertainty]`` table with a normal distribution (sd: the estimate's) for each
    estimated input it does not give one, so that the Monte Carlo draws the estimate's
    scatter (None when there is neither)."""
    extra = {e.name: Distribution("normal", None, e.sd) for e in estimates
             if table is None or e.name not in table.inputs}
    if not extra:
        return table
    return UncertaintyTable({**({} if table is None else table.inputs), **extra})


def _plane_normal(value, point, cg1) -> float:
    """Gamma [rad] from PC-Crash's contact plane angle psi: psi + 90 deg or psi - 90 deg,
    whichever normal n points from the plane toward vehicle 1's CG (docs/impact-laws.md)."""
    psi = parse(value, "angle", "impact.contact_plane_angle")
    gamma = psi + np.pi / 2
    side = float(np.dot([np.cos(gamma), np.sin(gamma)],
                        np.asarray(cg1, float).reshape(2) - np.asarray(point, float).reshape(2)))
    if not abs(side) > 1e-9 * (1.0 + float(np.hypot(*np.asarray(cg1, float).reshape(2)))):
        raise InputError("impact.contact_plane_angle: the contact plane passes through vehicle "
                         "1's CG, so the side of vehicle 1 (the normal's sign) is undefined; "
                         "give impact.normal_angle")
    return gamma if side > 0 else psi - np.pi / 2


def _check_depth(data, source: str) -> None:
    """InputError when tables and lists nest deeper than :data:`MAX_DEPTH` (walked without
    recursion, so any depth is answered in linear time)."""
    stack = [(data, 0)]
    while stack:
        value, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise InputError(f"{source}: tables and lists nest {depth} deep; a case file "
                             f"nests at most {MAX_DEPTH} deep")
        if isinstance(value, dict):
            stack.extend((v, depth + 1) for v in value.values())
        elif isinstance(value, list):
            stack.extend((v, depth + 1) for v in value)


#: Keys of the ``[units]`` table: the units results are presented in.
_UNITS = {"system": UNIT_SYSTEMS, "speed": SPEED_UNITS}


def _presentation(data) -> dict:
    """``units`` and ``speed_unit`` of the Case: the ``[units]`` table's choices, else the
    system the file is written in and the system's field speed unit (None)."""
    table = check_keys(data.get("units", {}), _UNITS, "units")
    for key, allowed in _UNITS.items():
        if key in table and table[key] not in allowed:
            raise InputError(f"units.{key} must be one of "
                             f"{', '.join(repr(a) for a in allowed)}, got {table[key]!r}")
    return {"units": table.get("system") or _unit_system(data),
            "speed_unit": table.get("speed")}


def _unit_system(data) -> str:
    """"us" when any quantity string of the file uses a US customary unit, else "si"."""
    data = {k: v for k, v in data.items() if k != "units"}
    stack, systems = [data], set()
    while stack:
        x = stack.pop()
        if isinstance(x, dict):
            stack.extend(x.values())
        elif isinstance(x, list):
            stack.extend(x)
        elif isinstance(x, str):
            systems.add(unit_system_of(x))
    return "us" if "us" in systems else "si"


def _bundled() -> dict[str, object]:
    folder = resources.files("pim.io") / "cases"
    return {p.name[: -len(".toml")]: p for p in folder.iterdir() if p.name.endswith(".toml")}


def list_cases() -> list[tuple[str, str]]:
    """Names and one-line descriptions of the bundled cases, sorted by name."""
    out = []
    for name, path in sorted(_bundled().items()):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        out.append((name, data.get("description", "")))
    return out


def _is_file(key: str) -> bool:
    """Whether ``key`` names a readable regular file; False for a name the file system
    refuses to look up (too long, a NUL byte, a denied folder on the way)."""
    try:
        return Path(key).is_file()
    except (OSError, ValueError):
        return False


def _shown(key: str, limit: int = 80) -> str:
    """``key`` quoted for a message, cut to about ``limit`` characters (with its length):
    its start and its end, where a path names the file."""
    if len(key) <= limit:
        return repr(key)
    head = limit // 3
    return f"{key[:head]!r}...{key[head - limit:]!r} ({len(key)} characters)"


def load_case(name_or_path) -> Case:
    """Load a case by bundled name (``"ricsac9"``) or from a TOML file path.

    Raises
    ------
    ValueError
        Unknown case name, unreadable or malformed file, or invalid content.
    """
    bundled = _bundled()
    key = str(name_or_path)
    if key in bundled and not _is_file(key):
        text, source = bundled[key].read_text(encoding="utf-8"), f"{key}.toml"
    else:
        path = Path(key)
        if not _is_file(key):
            names = ", ".join(sorted(bundled))
            raise InputError(f"case {_shown(key)} is neither a file nor a bundled case "
                             f"({names})")
        try:
            text, source = path.read_text(encoding="utf-8"), str(path)
        except (OSError, UnicodeDecodeError) as exc:
            raise InputError(f"{path}: cannot read ({exc})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source}: malformed TOML ({exc})") from None
    except RecursionError:      # tomllib recurses into nested inline tables and arrays
        raise InputError(f"{source}: tables and lists nest too deep; a case file nests at "
                         f"most {MAX_DEPTH} deep") from None
    return parse_case(data, source)
