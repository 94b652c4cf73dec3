"""The common units, read without pint: a case file's units and every display unit.

Importing pint costs about 0.2-0.5 s (its registry and what it imports), more than all of
``pim solve``'s own work. The units case files are written in and results are shown in are
few; this table holds them, each with its factor to SI and its dimension, so that reading a
case and showing a result need no pint. Any other unit text (parentheses, ``"N s"`` with a
space, ``"furlong"``) is left to pint (:func:`pim.io.units.parse`), which also writes every
error message. The table is checked against pint, name by name and for the display units'
products, to round-off (tests/pim/model/test_unit_table.py): pint stays the authority.

A unit text is products and quotients of the names of :data:`UNITS`, each with an optional
integer power (``**2``, ``^2``), read left to right as pint reads them: ``"slug*ft**2"``,
``"lbf/inch**2"``, ``"km/h"``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from .tyres import STANDARD_GRAVITY

__all__ = ["UNITS", "UnitFactor", "unit_factor", "DIMENSIONS"]

# pint's factors to SI as floats (its chains of definitions round the exact 0.3048 m and
# 0.45359237 kg in the last bit; the table keeps pint's, so a case reads to the same bits)
_FT, _IN, _YD, _MI = 0.30479999999999996, 0.0254, 0.9144, 1609.344
_LB, _SLUG, _LBF = 0.4535923700000001, 14.59390293720637, 4.4482216152605005

#: Exponents of (m, kg, s, rad) of each dimension a quantity may have.
DIMENSIONS = {"length": (1, 0, 0, 0), "mass": (0, 1, 0, 0), "time": (0, 0, 1, 0),
              "angle": (0, 0, 0, 1), "force": (1, 1, -2, 0), "energy": (2, 1, -2, 0),
              "velocity": (1, 0, -1, 0), "angular_velocity": (0, 0, -1, 1),
              "acceleration": (1, 0, -2, 0), "none": (0, 0, 0, 0)}


def _entries(dimension: str, us: bool, **factors: float) -> dict:
    return {name: (factor, DIMENSIONS[dimension], us) for name, factor in factors.items()}


#: Unit name -> (factor to SI, dimension exponents of (m, kg, s, rad), whether it is a US
#: customary unit). Names as pint spells them (its symbols and a few of its long names).
UNITS = {
    **_entries("length", False, m=1.0, meter=1.0, metre=1.0, cm=0.01, mm=0.001, km=1000.0),
    **_entries("length", True, ft=_FT, foot=_FT, feet=_FT, inch=_IN, yd=_YD, yard=_YD,
               mi=_MI, mile=_MI),
    **{"in": (_IN, DIMENSIONS["length"], True)},
    **_entries("mass", False, kg=1.0, g=0.001, gram=0.001, t=1000.0, tonne=1000.0),
    **_entries("mass", True, lb=_LB, pound=_LB, slug=_SLUG),
    **_entries("force", False, N=1.0, newton=1.0, kN=1000.0, kgf=STANDARD_GRAVITY),
    **_entries("force", True, lbf=_LBF),
    **_entries("time", False, s=1.0, second=1.0, sec=1.0, ms=0.001, min=60.0, minute=60.0,
               h=3600.0, hr=3600.0, hour=3600.0),
    **_entries("angle", False, rad=1.0, radian=1.0, deg=math.pi / 180, degree=math.pi / 180),
    **_entries("energy", False, J=1.0, joule=1.0, kJ=1000.0),
    **_entries("velocity", False, kph=1 / 3.6, knot=1852 / 3600),
    **_entries("velocity", True, mph=0.44704),
    **_entries("angular_velocity", False, rpm=2 * math.pi / 60),
    **_entries("acceleration", False, standard_gravity=STANDARD_GRAVITY),
    **_entries("none", False, percent=0.01, dimensionless=1.0),
}

_FACTOR = re.compile(r"\s*([A-Za-z_]+)\s*(?:(?:\*\*|\^)\s*([+-]?\d{1,2}))?\s*")


@dataclass(frozen=True)
class UnitFactor:
    """A unit text read from :data:`UNITS`.

    Attributes
    ----------
    factor : float
        Its value in SI units (``"mph"``: 0.44704 m/s).
    inverse : float
        The SI unit's value in it (1 / factor, formed as its own product, as pint forms a
        conversion into the unit: ``"km/h"`` 3.6 exactly, not 1 / 0.2777...).
    dimension : tuple of int
        Its exponents of (m, kg, s, rad).
    us : bool
        Whether it uses a US customary unit (ft, lbf, mph, slug ...).
    """

    factor: float
    dimension: tuple
    us: bool
    inverse: float


def unit_factor(text: str) -> UnitFactor | None:
    """The :class:`UnitFactor` of ``text`` (``"ft/s"``, ``"slug*ft**2"``), or None when a
    name is not in :data:`UNITS` or the text is not a plain product and quotient of names
    (pint reads those)."""
    parts = re.split(r"([*/])(?!\*)", text.replace("**", "^"))
    factor, inverse, dimension, us, sign = 1.0, 1.0, (0, 0, 0, 0), False, 1
    for i, part in enumerate(parts):
        if i % 2:
            sign = 1 if part == "*" else -1
            continue
        match = _FACTOR.fullmatch(part)
        if match is None or match.group(1) not in UNITS:
            return None
        each, dims, is_us = UNITS[match.group(1)]
        power = sign * int(match.group(2) or 1)
        factor *= each ** power
        inverse *= each ** -power
        dimension = tuple(a + power * b for a, b in zip(dimension, dims, strict=True))
        us = us or is_us
    return UnitFactor(factor, dimension, us, inverse)
