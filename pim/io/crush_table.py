"""The ``[evidence.vehicleN.crush]`` table of a case file: a crush profile and its stiffness.

```toml
[evidence.vehicle1.crush]
side = "front"                  # front, rear, left or right
width = "60 in"                 # damage width L
depths = ["10 in", "12 in", "14 in", "12 in", "9 in", "5 in"]   # C1..Cn, n >= 2, equally spaced
stiffness_a = "300 lbf/in"      # A per unit width ...
stiffness_b = "100 lbf/in^2"    # ... and B; or instead: class = "midsize car"
stiffness_g = "450 lbf"         # optional (default A^2 / 2B)
offset = "0 in"                 # damage centre along the side (y for front/rear, x for sides)
depth_sigma = "1 in"            # optional: sigma of each depth
width_sigma = "2 in"            # optional
stiffness_a_sigma = "30 lbf/in" # optional
stiffness_b_sigma = "10 lbf/in^2"   # optional
energy_sigma = 0.1              # optional: a further relative sigma of the energy
```

:func:`parse_crush` returns a :class:`pim.model.crush.CrushProfile` (SI). A ``class``
picks A and B (and their scatter) for the side from the bundled
``pim/io/data/crush_stiffness_classes.csv`` (:func:`load_stiffness_classes`; its source
lines open the file).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from functools import lru_cache

from ..model.crush import SIDES, CrushProfile
from ..model.numbers import InputError, unit_text
from .datasets import data_path, source_lines
from .toml_tables import check_keys
from .units import parse, quantity_in

__all__ = ["parse_crush", "CRUSH_KEYS", "StiffnessClass", "load_stiffness_classes",
           "STIFFNESS_CLASS_FILE"]

#: Keys a crush table may hold.
CRUSH_KEYS = frozenset({"side", "width", "depths", "stiffness_a", "stiffness_b",
                        "stiffness_g", "class", "offset", "depth_sigma", "width_sigma",
                        "stiffness_a_sigma", "stiffness_b_sigma", "energy_sigma"})

STIFFNESS_CLASS_FILE = "crush_stiffness_classes.csv"


@dataclass(frozen=True)
class StiffnessClass:
    """Default stiffness of one vehicle class and side (SI), from the bundled table.

    Attributes
    ----------
    name : str
        The class, lower case (``"midsize car"``).
    side : str
        The damaged side it applies to.
    stiffness_a, stiffness_b : float
        A [N/m] and B [N/m^2] per unit width.
    stiffness_g : float or None
        G [N] where the source lists it (else A^2 / 2B).
    stiffness_a_sigma, stiffness_b_sigma : float
        Their scatter within the class [N/m, N/m^2] (0 where the source gives none).
    source : str
        Where the numbers come from.
    """

    name: str
    side: str
    stiffness_a: float
    stiffness_b: float
    stiffness_g: float | None
    stiffness_a_sigma: float
    stiffness_b_sigma: float
    source: str


_CLASS_COLUMNS = ["class", "side", "A_lbf_per_in", "B_lbf_per_in2", "G_lbf",
                  "A_sd_lbf_per_in", "B_sd_lbf_per_in2", "source"]
#: The SI unit of each number column (the file's units are US, as published).
_CLASS_UNITS = {"A_lbf_per_in": ("lbf/inch", "N/m"), "B_lbf_per_in2": ("lbf/inch**2", "N/m**2"),
                "G_lbf": ("lbf", "N"), "A_sd_lbf_per_in": ("lbf/inch", "N/m"),
                "B_sd_lbf_per_in2": ("lbf/inch**2", "N/m**2")}


def _class_row(name: str, line: int, fields: list[str]) -> StiffnessClass:
    where = f"{name} line {line}"
    if len(fields) != len(_CLASS_COLUMNS):
        raise InputError(f"{where}: {len(fields)} fields, expected {len(_CLASS_COLUMNS)}")
    row = dict(zip(_CLASS_COLUMNS, (f.strip() for f in fields), strict=True))
    if row["side"] not in SIDES:
        raise InputError(f"{where}: side {row['side']!r} is not one of {', '.join(SIDES)}")
    numbers = {}
    for column, (unit, si) in _CLASS_UNITS.items():
        optional = column != "A_lbf_per_in" and column != "B_lbf_per_in2"
        text = row[column] or ("0" if optional else "")
        try:
            value = float(text)
        except ValueError:
            raise InputError(f"{where} column {column!r}: {row[column]!r} is not a number") \
                from None
        if not math.isfinite(value) or value < 0 or (value == 0 and not optional):
            raise InputError(f"{where} column {column!r}: {row[column]!r} must be a finite "
                             f"number {'>= 0' if optional else '> 0'}")
        numbers[column] = quantity_in(f"{value!r} {unit}", si)
    return StiffnessClass(row["class"].lower(), row["side"], numbers["A_lbf_per_in"],
                          numbers["B_lbf_per_in2"],
                          numbers["G_lbf"] if row["G_lbf"] else None,
                          numbers["A_sd_lbf_per_in"], numbers["B_sd_lbf_per_in2"],
                          row["source"])


@lru_cache(maxsize=4)
def load_stiffness_classes(path=None) -> dict:
    """The vehicle-class default stiffnesses: ``{(class, side): StiffnessClass}`` (SI).

    The CSV (default: the bundled :data:`STIFFNESS_CLASS_FILE`) opens with ``#`` source
    lines, then the header ``class,side,A_lbf_per_in,B_lbf_per_in2,G_lbf,A_sd_lbf_per_in,
    B_sd_lbf_per_in2,source`` (US units as published; G and the standard deviations may be
    empty).
    """
    path = path or data_path(STIFFNESS_CLASS_FILE)
    try:
        with open(path, encoding="utf-8") as f:
            lines = [line for line in f.read().splitlines() if not line.startswith("#")]
    except OSError as exc:
        raise InputError(f"{path}: cannot read the stiffness classes ({exc.strerror})") \
            from None
    name = str(path).rsplit("/", 1)[-1]
    rows = list(csv.reader(lines))
    if not rows or rows[0] != _CLASS_COLUMNS:
        raise InputError(f"{name}: header must be {','.join(_CLASS_COLUMNS)}")
    table = {}
    first = len(source_lines(path)) + 2
    for offset, fields in enumerate(rows[1:]):
        if fields:
            entry = _class_row(name, first + offset, fields)
            table[entry.name, entry.side] = entry
    return table


def _known_classes(side: str) -> str:
    names = sorted({name for name, s in load_stiffness_classes() if s == side})
    return ", ".join(names) or "none"


def _depths(value, where: str) -> tuple:
    if not isinstance(value, list):
        raise InputError(f"{where}.depths must be a list of crush depths, e.g. "
                         f"['10 in', '12 in', '9 in']")
    if len(value) < 2:
        raise InputError(f"{where}.depths: {len(value)} depth given; at least 2 are needed "
                         f"(C1..Cn equally spaced over the damage width)")
    depths = []
    for i, c in enumerate(value):
        depth = parse(c, "length", f"{where}.depths[{i}]")
        if depth < 0:
            raise InputError(f"{where}.depths[{i}] = {c!r}: a crush depth must be >= 0 "
                             f"(residual crush is measured inward)")
        depths.append(depth)
    return tuple(depths)


def _stiffness(table, where: str, side: str) -> dict:
    """A, B (G) and their sigmas from the table's numbers or its ``class``."""
    given = [k for k in ("stiffness_a", "stiffness_b") if k in table]
    if "class" in table:
        if given:
            raise InputError(f"{where}: give either class or stiffness_a and stiffness_b, "
                             f"not both")
        name = table["class"]
        entry = load_stiffness_classes().get((str(name).lower(), side))
        if entry is None:
            raise InputError(f"{where}.class = {name!r} has no {side} stiffness (known "
                             f"classes: {_known_classes(side)})")
        out = {"stiffness_a": entry.stiffness_a, "stiffness_b": entry.stiffness_b,
               "stiffness_a_sigma": entry.stiffness_a_sigma,
               "stiffness_b_sigma": entry.stiffness_b_sigma}
        if entry.stiffness_g is not None:
            out["stiffness_g"] = entry.stiffness_g
    elif len(given) == 2:
        out = {"stiffness_a": parse(table["stiffness_a"], "force_per_length",
                                    f"{where}.stiffness_a"),
               "stiffness_b": parse(table["stiffness_b"], "force_per_area",
                                    f"{where}.stiffness_b")}
    else:
        raise InputError(f"{where}: give stiffness_a and stiffness_b (per unit width, e.g. "
                         f"'300 lbf/in' and '100 lbf/in^2') or a class (known: "
                         f"{_known_classes(side)})")
    for key, kind in (("stiffness_a_sigma", "force_per_length"),
                      ("stiffness_b_sigma", "force_per_area")):
        if key in table:
            out[key] = parse(table[key], kind, f"{where}.{key}")
    if "stiffness_g" in table:
        out["stiffness_g"] = parse(table["stiffness_g"], "force", f"{where}.stiffness_g")
    for key in ("stiffness_a", "stiffness_b"):
        if out[key] <= 0:
            raise InputError(f"{where}.{key} must be > 0 (Campbell's A and B per unit "
                             f"width are positive)")
    return out


def _check_extent(profile: CrushProfile, where: str, vehicle_length, vehicle_width) -> None:
    """The damage fits on the vehicle: width within the damaged side, depth within the
    vehicle (when its length and width are known)."""
    along_x = profile.side in ("left", "right")
    side_length = vehicle_length if along_x else vehicle_width
    depth_limit = vehicle_width if along_x else vehicle_length
    dimension = "length" if along_x else "width"
    if side_length is not None:
        if profile.width > side_length:
            raise InputError(f"{where}.width = {_length(profile.width)} is longer than the "
                             f"damaged {profile.side} side (the vehicle's {dimension}, "
                             f"{_length(side_length)}); allowed: (0, {_length(side_length)}]")
        reach = abs(profile.offset) + profile.width / 2
        if reach > side_length / 2 * (1 + 1e-9):
            raise InputError(f"{where}.offset = {_length(profile.offset)} puts the damage "
                             f"({_length(profile.width)} wide) beyond the end of the "
                             f"{profile.side} side; allowed: |offset| + width/2 <= "
                             f"{_length(side_length / 2)}")
    if depth_limit is not None:
        deepest = max(profile.depths)
        other = "width" if along_x else "length"
        if deepest > depth_limit:
            raise InputError(f"{where}.depths: a crush of {_length(deepest)} is deeper than "
                             f"the vehicle ({other} {_length(depth_limit)}); allowed: [0, "
                             f"{_length(depth_limit)}]")


def _length(value: float) -> str:
    """A length [m] as a message prints it (in the case's units while one loads)."""
    return unit_text(value, "length", ".3g")


def parse_crush(table, where: str, vehicle_length=None, vehicle_width=None,
                extra_keys=()) -> CrushProfile:
    """Parse one ``[evidence.vehicleN.crush]`` table into a CrushProfile (SI).

    Parameters
    ----------
    table : dict
        The TOML table (see the module notes).
    where : str
        Its name for messages, e.g. ``"evidence.vehicle1.crush"``.
    vehicle_length, vehicle_width : float, optional
        The vehicle's overall length and width [m], when known: the damage width must fit on
        the damaged side (the length for left/right, the width for front/rear) and no crush
        may be deeper than the vehicle.
    extra_keys : iterable of str
        Further keys the caller reads itself (allowed here and ignored).

    Raises
    ------
    InputError
        A missing or unknown key, a bad quantity, an unknown side or class (the known ones
        listed), fewer than 2 depths, a negative crush, A or B <= 0, or damage that does
        not fit on the vehicle; the message names the field and the allowed range.
    """
    check_keys(table, CRUSH_KEYS | set(extra_keys), where)
    for key in ("side", "width", "depths"):
        if key not in table:
            raise InputError(f"{where}: missing {key}")
    side = table["side"]
    if side not in SIDES:
        raise InputError(f"{where}.side = {side!r} is not a side (allowed: "
                         f"{', '.join(SIDES)})")
    kwargs = _stiffness(table, where, side)
    kwargs["depths"] = _depths(table["depths"], where)
    kwargs["width"] = parse(table["width"], "length", f"{where}.width")
    if kwargs["width"] <= 0:
        raise InputError(f"{where}.width must be > 0 (the damage width)")
    for key in ("offset", "depth_sigma", "width_sigma"):
        if key in table:
            kwargs[key] = parse(table[key], "length", f"{where}.{key}")
    if "energy_sigma" in table:
        kwargs["energy_sigma_relative"] = parse(table["energy_sigma"], "dimensionless",
                                                f"{where}.energy_sigma")
    profile = CrushProfile(side=side, where=where, **kwargs)
    _check_extent(profile, where, vehicle_length, vehicle_width)
    return profile
