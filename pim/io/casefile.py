"""Case files: TOML descriptions of an impact, with units, in global or Brach form.

A case file names each quantity with units (``"31.09 ft/s"``, ``"2255.4 lbf"``, ``"90 deg"``,
``"976 slug*ft**2"``) or as a bare SI number. Unknown keys are errors, so a typo is never
silently ignored. Layout (global form; see ``pim/io/cases/ricsac9.toml``)::

    name = "ricsac9"
    description = "..."
    [vehicle1]                      # and [vehicle2]
    mass = "..."                    # or weight = "... lbf" (divided by standard gravity)
    yaw_inertia = "..."             # or radius_of_gyration = "... ft"
    cg = ["4.774 ft", "0.502 ft"]
    heading = "180 deg"
    velocity = ["-31.09 ft/s", 0]
    yaw_rate = "0 deg/s"
    length = "4.1 m"                # optional, with width: outline for drawing
    [impact]
    point = [0, 0]
    normal_angle = "0 deg"          # Gamma: n points from vehicle 2 toward vehicle 1
    restitution = 0.355             # optional defaults for solve
    beta = 1
    [measured]                      # optional
    vehicle1.velocity = ["-5.1 ft/s", "17.6 ft/s"]
    vehicle1.yaw_rate = "-180 deg/s"

``fixed = true`` in ``[vehicle2]`` makes it a barrier or pole (no mass, inertia, velocity;
``cg`` defaults to the impact point and ``heading`` to 0, as neither changes the answer).

Every quantity must lie within :data:`pim.io.units.LIMITS` (e.g. lengths within 1e5 m,
speeds within 1e4 m/s, masses between 1 g and 1e9 kg). The case records the unit system its
file is written in (``Case.units``: "us" when any quantity uses ft, lbf, mph, slug ...), which
the commands print in unless ``--units`` says otherwise.
``convention = "brach"`` replaces each vehicle's ``cg`` and ``heading`` by Brach's ``theta``,
``phi`` and ``d`` (see :mod:`pim.io.brach`), with C at ``impact.point`` (default the origin).
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

from ..model.case import Case, Impact, Vehicle
from ..model.plausibility import bare_angle_warning
from .brach import cg_from_brach, heading_from_theta
from .evidence_table import parse_evidence, parse_unknown
from .measured_table import parse_measured
from .toml_tables import check_keys
from .tyre_table import attach_tyres
from .uncertainty_table import parse_uncertainty
from .units import parse, registry, unit_system_of

__all__ = ["load_case", "list_cases", "parse_case"]

_TOP = {"name", "description", "source", "convention", "vehicle1", "vehicle2", "impact",
        "measured", "uncertainty", "evidence", "unknown", "tyres", "driver"}
_VEHICLE = {"mass", "weight", "yaw_inertia", "radius_of_gyration", "velocity", "yaw_rate",
            "length", "width", "fixed", "cg", "heading", "theta", "phi", "d"}
_IMPACT = {"point", "normal_angle", "restitution", "beta"}


def _require(table: dict, key: str, where: str):
    if key not in table:
        raise ValueError(f"{where}.{key} is missing")
    return table[key]


def _pair(value, kind: str, field: str) -> np.ndarray:
    if not isinstance(value, list) or len(value) != 2:
        raise ValueError(f"{field} must be a list of two values [x, y], got {value!r}")
    return np.array([parse(value[0], kind, f"{field}[0]"), parse(value[1], kind, f"{field}[1]")])


def _one_of(table: dict, a: str, b: str, where: str) -> str:
    present = [k for k in (a, b) if k in table]
    if len(present) != 1:
        raise ValueError(f"{where}: give exactly one of {a!r} or {b!r}")
    return present[0]


def _optional(table: dict, key: str, kind: str, where: str):
    return parse(table[key], kind, f"{where}.{key}") if key in table else None


def _vehicle(table, where: str, convention: str, point: np.ndarray, number: int) -> Vehicle:
    table = check_keys(table, _VEHICLE, where)
    placement = {"global": ("cg", "heading"), "brach": ("theta", "phi", "d")}[convention]
    stray = sorted(set(table) & ({"cg", "heading", "theta", "phi", "d"} - set(placement)))
    if stray:
        raise ValueError(f"{where}: key {stray[0]!r} does not belong to the {convention!r} "
                         f"convention (use {', '.join(placement)})")
    fixed = table.get("fixed", False)
    if not isinstance(fixed, bool):
        raise ValueError(f"{where}.fixed must be true or false")
    if convention == "global" and fixed:
        cg = _pair(table["cg"], "length", f"{where}.cg") if "cg" in table else point
        heading = parse(table.get("heading", 0.0), "angle", f"{where}.heading")
    elif convention == "global":
        cg = _pair(_require(table, "cg", where), "length", f"{where}.cg")
        heading = parse(_require(table, "heading", where), "angle", f"{where}.heading")
    else:
        theta = parse(_require(table, "theta", where), "angle", f"{where}.theta")
        phi = parse(_require(table, "phi", where), "angle", f"{where}.phi")
        d = parse(_require(table, "d", where), "length", f"{where}.d")
        cg = cg_from_brach(theta, phi, d, number, point)
        heading = float(heading_from_theta(theta, number))
    length = _optional(table, "length", "length", where)
    width = _optional(table, "width", "length", where)

    if fixed:
        if number == 1:
            raise ValueError(f"{where}.fixed: only vehicle2 may be a fixed obstacle")
        extra = sorted(set(table) & {"mass", "weight", "yaw_inertia", "radius_of_gyration",
                                     "velocity", "yaw_rate"})
        if extra:
            raise ValueError(f"{where}.{extra[0]}: a fixed obstacle has no {extra[0]}")
        return _wrap(where, Vehicle.obstacle, cg=cg, heading=heading, length=length, width=width)

    if _one_of(table, "mass", "weight", where) == "mass":
        mass = parse(table["mass"], "mass", f"{where}.mass")
    else:
        weight = parse(table["weight"], "force", f"{where}.weight")
        if weight <= 0:
            raise ValueError(f"{where}.weight must be > 0, got {table['weight']!r}")
        mass = weight / registry().Quantity(1, "standard_gravity").to("m/s**2").magnitude
    if _one_of(table, "yaw_inertia", "radius_of_gyration", where) == "yaw_inertia":
        inertia = parse(table["yaw_inertia"], "inertia", f"{where}.yaw_inertia")
    else:
        k = parse(table["radius_of_gyration"], "length", f"{where}.radius_of_gyration")
        if k <= 0:
            raise ValueError(f"{where}.radius_of_gyration must be > 0, "
                             f"got {table['radius_of_gyration']!r}")
        inertia = mass * k * k
    velocity = _pair(_require(table, "velocity", where), "velocity", f"{where}.velocity")
    yaw_rate = parse(table.get("yaw_rate", 0.0), "angular_velocity", f"{where}.yaw_rate")
    return _wrap(where, Vehicle, mass=mass, yaw_inertia=inertia, cg=cg, velocity=velocity,
                 yaw_rate=yaw_rate, heading=heading, length=length, width=width)


def _wrap(where: str, factory, **kwargs):
    """Call ``factory`` and prefix any validation error with the table's name."""
    try:
        return factory(**kwargs)
    except ValueError as exc:
        raise ValueError(f"{where}.{exc}") from None


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
    data = check_keys(data, _TOP, source)
    convention = data.get("convention", "global")
    if convention not in ("global", "brach"):
        raise ValueError(f"convention must be 'global' or 'brach', got {convention!r}")
    impact_table = check_keys(_require(data, "impact", source), _IMPACT, "impact")
    if convention == "global" or "point" in impact_table:
        point = _pair(_require(impact_table, "point", "impact"), "length", "impact.point")
    else:
        point = np.zeros(2)
    normal_angle = parse(_require(impact_table, "normal_angle", "impact"), "angle",
                         "impact.normal_angle")
    eps = _optional(impact_table, "restitution", "dimensionless", "impact")
    beta = _optional(impact_table, "beta", "dimensionless", "impact")
    impact = _wrap("impact", Impact, point=point, normal_angle=normal_angle,
                   restitution=eps, beta=beta)
    vehicles = [
        _vehicle(_require(data, f"vehicle{i}", source), f"vehicle{i}", convention, point, i)
        for i in (1, 2)
    ]
    name = data.get("name", Path(source).stem)
    description = data.get("description", "")
    for key, value in (("name", name), ("description", description),
                       ("source", data.get("source", ""))):
        if not isinstance(value, str):
            raise ValueError(f"{key} must be a string, got {value!r}")
    return Case(vehicle1=vehicles[0], vehicle2=vehicles[1], impact=impact,
                measured=parse_measured(data.get("measured")), name=name, description=description,
                uncertainty=_uncertainty(data.get("uncertainty")), units=_unit_system(data),
                notes=_angle_notes(data),
                evidence=attach_tyres(parse_evidence(data.get("evidence")), data.get("tyres"),
                                      data.get("driver")),
                unknown=parse_unknown(data.get("unknown")))


def _angle_notes(data) -> tuple[str, ...]:
    """Warnings for bare numbers above 2 pi given for angles (degrees without a unit?)."""
    notes = []
    for table in ("vehicle1", "vehicle2", "impact"):
        for key in ("heading", "theta", "phi", "normal_angle"):
            value = data.get(table, {}).get(key)
            note = bare_angle_warning(f"{table}.{key}", value)
            if note:
                notes.append(note)
    return tuple(notes)


def _unit_system(data) -> str:
    """"us" when any quantity string of the file uses a US customary unit, else "si"."""
    def strings(x):
        if isinstance(x, dict):
            for v in x.values():
                yield from strings(v)
        elif isinstance(x, list):
            for v in x:
                yield from strings(v)
        elif isinstance(x, str):
            yield x

    systems = {unit_system_of(s) for s in strings(data)}
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


def load_case(name_or_path) -> Case:
    """Load a case by bundled name (``"ricsac9"``) or from a TOML file path.

    Raises
    ------
    ValueError
        Unknown case name, unreadable or malformed file, or invalid content.
    """
    bundled = _bundled()
    key = str(name_or_path)
    if key in bundled and not Path(key).is_file():
        text, source = bundled[key].read_text(encoding="utf-8"), f"{key}.toml"
    else:
        path = Path(key)
        if not path.is_file():
            names = ", ".join(sorted(bundled))
            raise ValueError(f"case {key!r} is neither a file nor a bundled case ({names})")
        try:
            text, source = path.read_text(encoding="utf-8"), str(path)
        except (OSError, UnicodeDecodeError) as exc:
            raise ValueError(f"{path}: cannot read ({exc})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{source}: malformed TOML ({exc})") from None
    return parse_case(data, source)
