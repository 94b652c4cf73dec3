"""The units results are shown in: a unit system and a speed unit, and the factors into them.

A :class:`DisplayUnits` is what every table, report, plot label and JSON converts through
(:func:`convert`): lengths, masses, forces, impulses and energies in the SI or US customary
system, speeds and delta-V as the field reports them (km/h, mph) unless asked otherwise. The
factors are :mod:`pim.model.unit_table`'s (pint's, checked against pint), so that showing a
result, in a table or a notebook, needs no pint. :mod:`pim.io.units` re-exports these names
with the parsing of case files' quantities.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .case import SPEED_UNITS
from .numbers import InputError
from .unit_table import unit_factor

__all__ = ["DISPLAY_UNITS", "UNIT_SYSTEMS", "SPEED_KINDS", "SI_UNITS", "DisplayUnits",
           "display_units", "label", "display_factor", "convert", "unit_scale"]

#: Display units of each output kind, per unit system, by default: speeds, velocity
#: components and delta-V (:data:`SPEED_KINDS`) as the field reports them, km/h and mph
#: (a :class:`DisplayUnits` may choose another speed unit).
DISPLAY_UNITS = {
    "si": {"velocity": "km/h", "speed": "km/h", "angular_velocity": "deg/s", "impulse": "N*s",
           "energy": "kJ", "length": "m", "mass": "kg", "inertia": "kg*m**2", "angle": "deg",
           "force": "N", "impact_speed": "km/h", "force_per_length": "kN/m",
           "force_per_area": "kN/m**2", "dimensionless": "dimensionless",
           "percent": "percent"},
    "us": {"velocity": "mph", "speed": "mph", "angular_velocity": "deg/s", "impulse": "lbf*s",
           "energy": "ft*lbf", "length": "ft", "mass": "slug", "inertia": "slug*ft**2",
           "angle": "deg", "force": "lbf", "impact_speed": "mph",
           "force_per_length": "lbf/inch", "force_per_area": "lbf/inch**2",
           "dimensionless": "dimensionless", "percent": "percent"},
}
UNIT_SYSTEMS = tuple(DISPLAY_UNITS)

#: Output kinds shown in the speed unit of a :class:`DisplayUnits`.
SPEED_KINDS = frozenset({"velocity", "speed", "impact_speed"})

#: SI unit of each output kind.
SI_UNITS = {"velocity": "m/s", "speed": "m/s", "angular_velocity": "rad/s", "impulse": "N*s",
            "energy": "J", "length": "m", "mass": "kg", "inertia": "kg*m**2", "angle": "rad",
            "force": "N", "impact_speed": "m/s", "force_per_length": "N/m",
            "force_per_area": "N/m**2", "dimensionless": "dimensionless", "percent": "percent"}


@dataclass(frozen=True)
class DisplayUnits:
    """The units results are presented in: a unit system and a speed unit.

    Parameters
    ----------
    system : {"si", "us"}
        Units of lengths, masses, forces, impulses, energies (:data:`DISPLAY_UNITS`);
        angles are in deg and yaw rates in deg/s in both.
    speed : {"km/h", "mph", "m/s", "ft/s"}, optional
        Unit of every speed, velocity component, delta-V and impact speed
        (:data:`SPEED_KINDS`); default the system's field unit, km/h for "si" and mph for
        "us".
    """

    system: str = "si"
    speed: str | None = None

    def __post_init__(self) -> None:
        if self.system not in DISPLAY_UNITS:
            raise InputError(f"units must be one of {', '.join(UNIT_SYSTEMS)}, "
                             f"got {self.system!r}")
        if self.speed is None:
            object.__setattr__(self, "speed", DISPLAY_UNITS[self.system]["speed"])
        elif self.speed not in SPEED_UNITS:
            raise InputError(f"speed unit must be one of {', '.join(SPEED_UNITS)}, "
                             f"got {self.speed!r}")

    def unit(self, kind: str) -> str:
        """The pint unit of an output ``kind`` (a key of :data:`SI_UNITS`)."""
        return self.speed if kind in SPEED_KINDS else DISPLAY_UNITS[self.system][kind]

    def label(self, kind: str) -> str:
        """The unit symbol printed beside a value of ``kind`` ("-" when dimensionless)."""
        return label(self.unit(kind))

    def to_json(self) -> dict:
        """The ``units`` entry of ``--json``: the system, the speed unit and the unit of
        each output kind (the units every number of the output is in)."""
        return {"system": self.system, "speed": self.speed,
                **{kind: self.label(kind) for kind in SI_UNITS}}

    def __str__(self) -> str:
        return f"{self.system.upper()} units, speeds in {self.speed}"


def display_units(units=None, speed: str | None = None, case=None) -> DisplayUnits:
    """The :class:`DisplayUnits` of an output.

    Parameters
    ----------
    units : {"si", "us"} or DisplayUnits, optional
        The unit system asked for (``--units``), or the display units themselves; default
        the case's own system (``case.units``), else "si".
    speed : {"km/h", "mph", "m/s", "ft/s"}, optional
        The speed unit asked for (``--speed-unit``). Default: that of ``units`` when it is
        a DisplayUnits, else the case file's choice (``case.speed_unit``, its
        ``[units] speed``), else the system's field unit (km/h for "si", mph for "us").
    case : pim.Case, optional
        The case presented.
    """
    if isinstance(units, DisplayUnits):
        return units if speed is None else DisplayUnits(units.system, speed)
    system = units or getattr(case, "units", None) or "si"
    return DisplayUnits(system, speed or getattr(case, "speed_unit", None))


def label(unit: str) -> str:
    """The symbol printed for a display ``unit`` ("km/h", "kg m^2"; "-" when dimensionless)."""
    return {"dimensionless": "-", "percent": "%"}.get(
        unit, unit.replace("**", "^").replace("*", " "))


@lru_cache(maxsize=64)
def display_factor(kind: str, unit: str) -> float:
    """The factor that takes SI values of an output ``kind`` into ``unit`` (a display unit:
    every one is in :mod:`pim.model.unit_table`, whose factors are pint's)."""
    source, target = unit_factor(SI_UNITS[kind]), unit_factor(unit)
    if source is None or target is None or source.dimension != target.dimension:
        raise InputError(f"{unit!r} is no display unit of {kind}")
    return source.factor * target.inverse


def convert(value, kind: str, units):
    """Convert SI values of an output ``kind`` to their display unit.

    Parameters
    ----------
    value : float or array_like
        Values in the SI unit of ``kind`` (:data:`SI_UNITS`).
    kind : str
        A key of :data:`SI_UNITS`.
    units : {"si", "us"} or DisplayUnits
        The display units; a bare system presents speeds in its field unit (km/h, mph).

    Returns
    -------
    tuple
        The converted values (same shape, an array) and the unit label.
    """
    shown = units if isinstance(units, DisplayUnits) else DisplayUnits(units)
    target = shown.unit(kind)
    return np.asarray(value) * display_factor(kind, target), label(target)


def unit_scale(kind: str, units) -> tuple[float, str]:
    """The factor that takes SI values of ``kind`` into ``units`` and the unit's label
    (:func:`convert` of 1), for a number a message or a table scales itself.

    Examples
    --------
    >>> unit_scale("velocity", "si")
    (3.6, 'km/h')
    """
    factor, label = convert(1.0, kind, units)
    return float(factor), label
