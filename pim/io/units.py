"""Units at the edge: parse quantities with pint, present results in SI or US customary units.

Nothing inside the model knows about units; it works in SI. This module is the only place
that converts, and it delegates every conversion factor to pint's registry. pint is imported
on first use so that ``import pim`` stays fast, and the common units (those case files are
written in and every display unit) are read from :mod:`pim.model.unit_table`, pint's
factors checked against pint by a test, so that ``pim solve`` never imports pint (0.2-0.5 s);
any other unit, and every error message, is pint's.

Results are presented in a :class:`DisplayUnits`: a unit system ("si" or "us": lengths,
masses, forces, energies) and a speed unit for every speed, velocity component and delta-V.
The speed unit is what the field reports, km/h in a metric case and mph in a US one, unless
the case file (``[units] speed``) or the command line (``--speed-unit``) asks for another of
:data:`SPEED_UNITS`.
"""

from __future__ import annotations

import difflib
import re
from contextlib import contextmanager
from functools import lru_cache

import numpy as np

from ..model.case import SPEED_UNITS
from ..model.numbers import MESSAGE_KINDS, InputError, units_in
from ..model.display import (
    DISPLAY_UNITS,
    SI_UNITS,
    SPEED_KINDS,
    UNIT_SYSTEMS,
    DisplayUnits,
    convert,
    display_factor,
    display_units,
    label,
    unit_scale,
)
from ..model.unit_table import unit_factor

__all__ = ["registry", "parse", "convert", "DISPLAY_UNITS", "UNIT_SYSTEMS", "LIMITS",
           "unit_system_of", "DisplayUnits", "display_units", "SPEED_UNITS", "SPEED_KINDS",
           "messages_in", "quantity_text", "unit_scale", "bare_number_error",
           "BARE_NUMBER_UNITS", "quantity_in"]

#: SI unit of each kind of input quantity (its dimension is the expected one).
DIMENSIONS = {
    "length": "m",
    "mass": "kg",
    "force": "N",
    "inertia": "kg*m**2",
    "velocity": "m/s",
    "angle": "rad",
    "angular_velocity": "rad/s",
    "energy": "J",
    "force_per_length": "N/m",
    "force_per_area": "N/m**2",
    "dimensionless": "",
}

#: Largest magnitude [SI unit of the kind] an input may have, and for masses, inertias and
#: forces (weights) also the smallest. These bounds lie far outside any vehicle collision
#: (a 1e5 m scene, 1e4 m/s, a 1 g to 1e9 kg body) and keep every product the solver forms
#: (m v^2, I w^2, m k^2) far from float overflow and underflow. The crush stiffnesses A
#: [N/m] and B [N/m^2] of cars are 1e4-1e6 and 1e5-1e7; their bounds are as wide.
LIMITS = {
    "length": (0.0, 1e5),
    "mass": (1e-3, 1e9),
    "force": (1e-2, 1e10),
    "inertia": (1e-6, 1e12),
    "velocity": (0.0, 1e4),
    "angle": (0.0, 1e4),
    "angular_velocity": (0.0, 1e4),
    "energy": (0.0, 1e12),
    "force_per_length": (1.0, 1e10),
    "force_per_area": (1.0, 1e12),
    "dimensionless": (0.0, 1e6),
}

#: Units that mark a case file as written in US customary units (pint's names).
US_UNIT_NAMES = frozenset({"foot", "inch", "yard", "mile", "mile_per_hour", "force_pound",
                           "pound", "slug", "foot_per_second"})

@lru_cache(maxsize=1)
def registry():
    """The shared pint UnitRegistry (created on first use).

    pint caches its parsed unit definitions in the user's cache folder (``:auto:``), which
    makes the registry 0.02 s to build instead of 0.7 s; without a writable cache it is
    built from the definitions as usual.
    """
    import pint

    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except Exception:       # no writable cache folder (or an unreadable one): build afresh
        return pint.UnitRegistry()


#: Longest quantity string read [characters]: "-1.23456789e+02 slug*ft**2" is 26; the cap
#: bounds the parse time whatever the input.
MAX_QUANTITY_LENGTH = 100

_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
#: Characters a unit may be written with: letters, digits of exponents, * / ^ ( ) and spaces
#: (pint's grammar). Anything else (# ; ! ' , = ...) is trailing text, never read.
_UNIT_TEXT = re.compile(r"[\w\s*/^().+-]*")
_EXPONENT = re.compile(r"(?:\*\*|\^)[\s(]{0,3}[+-]?\d{1,3}\)?")

#: Common units of each kind, offered as "did you mean" suggestions.
COMMON_UNITS = {
    "length": ("m", "cm", "mm", "km", "ft", "inch", "yd", "mi"),
    "mass": ("kg", "g", "t", "lb", "slug"),
    "force": ("N", "kN", "lbf", "kgf"),
    "inertia": ("kg*m**2", "slug*ft**2", "lb*ft**2"),
    "velocity": ("m/s", "km/h", "kph", "mph", "ft/s", "knot"),
    "angle": ("deg", "rad", "degree", "radian"),
    "angular_velocity": ("deg/s", "rad/s", "rpm"),
    "energy": ("J", "kJ", "ft*lbf", "N*m"),
    "force_per_length": ("N/m", "kN/m", "lbf/in", "lbf/ft"),
    "force_per_area": ("N/m**2", "kN/m**2", "lbf/in**2", "lbf/ft**2"),
    "dimensionless": (),
}


@lru_cache(maxsize=256)
def _unit(text: str):
    """pint Unit of ``text`` and its root units (base units, radian kept as such)."""
    ureg = registry()
    unit = ureg.Unit(text)
    return unit, ureg.get_root_units(unit)[1]


#: Unit symbols outside pint's grammar, and the unit each is: ``"10°"`` (also ``"30°/s"``)
#: and ``"35.5 %"`` (0.355).
SYMBOLS = {"\N{DEGREE SIGN}": "deg", "%": "percent"}


def _symbols(unit: str) -> str:
    """The unit text after the number with a leading symbol of :data:`SYMBOLS` spelled as
    pint's unit (one symbol, first: ``"°/s"`` is ``"deg/s"``); any other text as it is."""
    for symbol, name in SYMBOLS.items():
        rest = unit[len(symbol):]
        if unit.startswith(symbol) and symbol not in rest and rest[:1] in ("", "/", "*", " "):
            return name + rest
    return unit


def _split(value: str, field: str) -> tuple[float, str]:
    """A quantity string as (number, unit text): exactly one number, then a unit or nothing.

    Linear in the string's length (and the length is capped at
    :data:`MAX_QUANTITY_LENGTH`): one anchored number, then one character-class match of the
    unit text; anything after the unit (``"2255.4 lbf # comment"``, ``"10 deg;"``) is an
    error, never ignored.
    """
    if len(value) > MAX_QUANTITY_LENGTH:
        raise InputError(f"{field}: a quantity of {len(value)} characters is too long "
                         f"(at most {MAX_QUANTITY_LENGTH}); write one number and one unit, "
                         f"e.g. '1200 kg'")
    text = value.strip()
    match = _NUMBER.match(text)
    if match is None:
        raise InputError(f"{field}: {value!r} must be one number followed by a unit, "
                         f"e.g. '1200 kg' or '90 deg'")
    number, unit = match.group(0), text[match.end():].strip()
    if unit[:1] in SYMBOLS:
        text, unit = f"{number} {_symbols(unit)}", _symbols(unit)
    if unit and (text[match.end()] not in " \t*/" and not unit[0].isalpha()):
        raise InputError(f"{field}: {value!r} must be one number followed by a unit, "
                         f"e.g. '1200 kg' or '90 deg'")
    if _UNIT_TEXT.fullmatch(unit) is None:
        bad = next(c for c in unit if not (c.isalnum() or c in " \t*/^()._+-"))
        raise InputError(f"{field}: {value!r} has text after its unit (from {bad!r}); write "
                         f"exactly one number and one unit, e.g. '1200 kg', with nothing "
                         f"after it (TOML comments go outside the quotes)")
    if re.search(r"\d", _EXPONENT.sub("", unit)):
        raise InputError(f"{field}: {value!r} holds more than one number; write one number "
                         f"and one unit, e.g. '1200 kg'")
    return float(number), unit


#: The force unit of the weight of one mass unit, for the suggestion to a weight written in
#: a mass unit (``weight = "1500 kg"``: mass = '1500 kg', or '1500 kgf').
FORCE_OF_MASS_UNIT = {"kg": "kgf", "kilogram": "kgf", "g": "gf", "gram": "gf", "lb": "lbf",
                      "lbs": "lbf", "pound": "lbf", "t": "tf", "tonne": "tf"}


def _suggestion(magnitude: float, text: str, kind: str, dimension: str) -> str:
    """" (did you mean ...?)" for a unit of the wrong kind or an unknown one, else ""."""
    if kind == "force" and dimension == "[mass]":
        twin = FORCE_OF_MASS_UNIT.get(text.strip(), "N")
        return (f"; {text!r} is a mass: give mass = '{magnitude:g} {text.strip()}', or a "
                f"weight in a force unit, e.g. '{magnitude:g} {twin}'")
    if kind == "mass" and dimension == "[mass] * [length] / [time] ** 2":
        return (f"; {text!r} is a force: give weight = '{magnitude:g} {text}' or a mass unit "
                f"such as '{magnitude:g} lb'")
    close = difflib.get_close_matches(text.replace(" ", ""), COMMON_UNITS[kind], n=1,
                                      cutoff=0.5)
    return f"; did you mean '{magnitude:g} {close[0]}'?" if close else ""


def unit_system_of(value) -> str | None:
    """"us" when a quantity string uses a US customary unit (ft, lbf, mph, slug ...), "si"
    when it uses another unit, None for bare numbers and unreadable strings."""
    if not isinstance(value, str):
        return None
    try:
        _, unit = _split(value, "")
        if not unit:
            return None
        known = unit_factor(unit)
        if known is not None:
            return "us" if known.us else "si"
        parsed, _ = _unit(unit)
    except Exception:
        return None
    names = dict(registry().Quantity(1.0, parsed).unit_items())
    return "us" if set(names) & US_UNIT_NAMES else "si"


#: Units a bare number of each dimensional kind could mean, named when it is refused
#: (:func:`bare_number_error`).
BARE_NUMBER_UNITS = {
    "length": ("m", "ft", "cm", "inch"),
    "mass": ("kg", "lb", "slug"),
    "force": ("N", "lbf", "kgf"),
    "inertia": ("kg*m**2", "slug*ft**2", "lb*ft**2"),
    "velocity": ("m/s", "km/h", "mph", "ft/s"),
    "angle": ("deg", "rad"),
    "angular_velocity": ("deg/s", "rad/s", "rpm"),
    "energy": ("J", "kJ", "ft*lbf"),
    "force_per_length": ("N/m", "kN/m", "lbf/inch"),
    "force_per_area": ("N/m**2", "kN/m**2", "lbf/inch**2"),
}


def bare_number_error(field: str, value, kind: str) -> InputError:
    """The error for a non-zero number without a unit given for a dimensional ``kind``: it
    names the field, the number and the units it could mean (a km/h user's ``50`` is not
    the 50 m/s it would be read as)."""
    number = f"{float(value):g}" if isinstance(value, int | float) else str(value).strip()
    meanings = [f"'{number} {u}'" for u in BARE_NUMBER_UNITS[kind]]
    what = kind.replace("_", " ")
    return InputError(f"{field} = {value!r} has no unit: write the {what} with its unit, "
                      f"e.g. {', '.join(meanings[:-1])} or {meanings[-1]} (a bare number "
                      f"is read only for 0 and for dimensionless inputs)")


def _parse_number(value, kind: str, field: str) -> float:
    """A bare number for :func:`parse`: a dimensionless input, or 0 of any kind (0 is 0 in
    every unit); any other bare number of a dimensional kind is refused."""
    try:
        number = float(value)
    except OverflowError:
        raise InputError(f"{field}: {str(value)[:20]}... is too large a number") from None
    if kind != "dimensionless" and number != 0 and np.isfinite(number):
        raise bare_number_error(field, value, kind)
    return number


def _dimension(parsed, root) -> str:
    """The dimension of a parsed unit in words: pint's (``[length] / [time]``), with the
    angles (whose radian pint counts as dimensionless) called what they are."""
    if parsed is None:
        return ""
    text = str(parsed.dimensionality)
    radians = dict(registry().Quantity(1.0, root).unit_items()).get("radian")
    if radians:
        text = "angle" + ("" if text == "dimensionless" else f" times {text}")
        text += "" if radians == 1 else f" to the power {radians:g}"
    return text


def _parse_string(value: str, kind: str, field: str, unit: str) -> float:
    """A quantity string for :func:`parse`: its magnitude in ``unit``, the kind's SI unit
    (a unit of :mod:`pim.model.unit_table` of the kind's dimension without pint)."""
    magnitude, text = _split(value, field)
    if not text:
        if kind != "dimensionless" and magnitude != 0 and np.isfinite(magnitude):
            raise bare_number_error(field, value, kind)
        return magnitude
    known, wanted = unit_factor(text), unit_factor(unit or "dimensionless")
    if known is not None and wanted is not None and known.dimension == wanted.dimension:
        return magnitude * known.factor * wanted.inverse
    try:
        parsed, root = _unit(text) if text else (None, None)
    except Exception as exc:
        hint = _suggestion(magnitude, text, kind, "")
        raise InputError(f"{field}: unknown unit in {value!r} ({exc}){hint}") from None
    _, wanted = _unit(unit) if unit else (None, None)
    none = registry().Unit("")
    if (none if root is None else root) != (none if wanted is None else wanted):
        what = "dimensionless number" if kind == "dimensionless" else kind.replace("_", " ")
        dim, expected = _dimension(parsed, root), _dimension(*(_unit(unit) if unit else
                                                              (None, None)))
        raise InputError(f"{field}: {value!r} is not a{'n' if what[0] in 'aeiou' else ''} "
                         f"{what} (its unit has dimension {dim or 'dimensionless'}, "
                         f"expected {expected or 'dimensionless'}: a unit like "
                         f"{unit or 'none, a bare number'})"
                         f"{_suggestion(magnitude, text, kind, str(dim))}")
    if parsed is None:
        return magnitude
    return float(registry().Quantity(magnitude, parsed).to(unit).magnitude)


def parse(value, kind: str, field: str) -> float:
    """Convert one input value to SI.

    Parameters
    ----------
    value : str or float
        A quantity with units (``"31.09 ft/s"``, ``"90 deg"``): exactly one number and one
        unit. A number without a unit (``50`` or ``"50"``) is read only where it cannot be
        misread: for a dimensionless kind, and 0 of any kind (0 is 0 in every unit); any
        other is refused with the units it could mean (50 m/s, km/h, mph or ft/s?).
    kind : str
        Key of :data:`DIMENSIONS` naming the expected physical dimension. The unit must
        reduce to the kind's base units exactly, so ``"1 Hz"`` is no yaw rate and ``"1 sr"``
        or ``"1 m/m"`` no angle.
    field : str
        Dotted name of the input, used in error messages.

    Returns
    -------
    float
        The magnitude in the SI unit of ``kind`` (radians for angles), within
        :data:`LIMITS`.

    Raises
    ------
    ValueError
        Unknown unit, wrong dimension, more or fewer than one number, a value outside
        :data:`LIMITS`, or NaN/inf; the message names ``field``.
    """
    unit = DIMENSIONS[kind]
    if isinstance(value, bool):
        raise InputError(f"{field} must be a number or a quantity string, got {value!r}")
    if isinstance(value, int | float):
        number = _parse_number(value, kind, field)
    elif isinstance(value, str):
        number = _parse_string(value, kind, field, unit)
    else:
        raise InputError(f"{field} must be a number or a quantity string, got {value!r}")
    if not np.isfinite(number):
        raise InputError(f"{field} must be a finite number, got {value!r}")
    low, high = LIMITS[kind]
    if abs(number) > high or (number != 0 and abs(number) < low):
        raise InputError(f"{field} = {value!r} is outside the physically meaningful range: "
                         f"|value| must be {f'between {low:g} and ' if low else 'at most '}"
                         f"{high:g} {unit or '(dimensionless)'}")
    return number


def quantity_in(value, unit: str) -> float:
    """A quantity string (``"80 kN/deg"``) or a pint quantity in ``unit`` (pint's
    conversion; a unit of :mod:`pim.model.unit_table` without pint); pint's error when it
    is not one of ``unit``'s dimension."""
    if isinstance(value, str):
        try:
            magnitude, text = _split(value, "")
        except InputError:
            text = None
        known, target = (unit_factor(text) if text else None), unit_factor(unit)
        if known is not None and target is not None and known.dimension == target.dimension:
            return magnitude * known.factor * target.inverse
    return float(registry().Quantity(value).to(unit).magnitude)


@contextmanager
def messages_in(units):
    """Within the block, speeds, lengths and yaw rates in the model's messages
    (:func:`pim.model.numbers.unit_text`, :func:`~pim.model.numbers.speed_text`) are
    printed in ``units`` (a :class:`DisplayUnits` or a system; yaw rates in deg/s)."""
    shown = units if isinstance(units, DisplayUnits) else display_units(units)
    table = {kind: (float(display_factor(kind, shown.unit(kind))), label(shown.unit(kind)))
             for kind in MESSAGE_KINDS}
    with units_in(table):
        yield shown


def quantity_text(units):
    """A ``show(value [SI], kind) -> "149.7 ft"`` for messages in the display units ``units``
    (a system or a :class:`DisplayUnits`; angles in deg): what :mod:`pim.model.plausibility`
    takes to print its numbers in the case's units."""
    shown_units = units if isinstance(units, DisplayUnits) else DisplayUnits(units)

    def show(value: float, kind: str) -> str:
        shown, label = convert(value, kind, shown_units)
        return f"{float(shown):.4g} {label}"
    return show
