"""Units at the edge: parse quantities with pint, present results in SI or US customary units.

Nothing inside the model knows about units; it works in SI. This module is the only place
that converts, and it delegates every conversion factor to pint's registry. pint is imported
on first use so that ``import pim`` stays fast.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["registry", "parse", "convert", "DISPLAY_UNITS", "UNIT_SYSTEMS"]

#: SI unit of each kind of input quantity (its dimension is the expected one).
DIMENSIONS = {
    "length": "m",
    "mass": "kg",
    "force": "N",
    "inertia": "kg*m**2",
    "velocity": "m/s",
    "angle": "rad",
    "angular_velocity": "rad/s",
    "dimensionless": "",
}

#: Display units of each output kind, per unit system.
DISPLAY_UNITS = {
    "si": {"velocity": "m/s", "speed": "km/h", "angular_velocity": "deg/s", "impulse": "N*s",
           "energy": "kJ", "length": "m", "mass": "kg", "inertia": "kg*m**2", "angle": "deg",
           "force": "N"},
    "us": {"velocity": "ft/s", "speed": "mph", "angular_velocity": "deg/s", "impulse": "lbf*s",
           "energy": "ft*lbf", "length": "ft", "mass": "slug", "inertia": "slug*ft**2",
           "angle": "deg", "force": "lbf"},
}
UNIT_SYSTEMS = tuple(DISPLAY_UNITS)

#: SI unit of each output kind.
SI_UNITS = {"velocity": "m/s", "speed": "m/s", "angular_velocity": "rad/s", "impulse": "N*s",
            "energy": "J", "length": "m", "mass": "kg", "inertia": "kg*m**2", "angle": "rad",
            "force": "N"}


@lru_cache(maxsize=1)
def registry():
    """The shared pint UnitRegistry (created on first use)."""
    import pint

    return pint.UnitRegistry()


def parse(value, kind: str, field: str) -> float:
    """Convert one input value to SI.

    Parameters
    ----------
    value : str or float
        A quantity with units (``"31.09 ft/s"``, ``"90 deg"``) or a bare number, taken as SI.
    kind : str
        Key of :data:`DIMENSIONS` naming the expected physical dimension.
    field : str
        Dotted name of the input, used in error messages.

    Returns
    -------
    float
        The magnitude in the SI unit of ``kind`` (radians for angles).

    Raises
    ------
    ValueError
        Unknown unit, wrong dimension, not a number, or NaN/inf; the message names ``field``.
    """
    unit = DIMENSIONS[kind]
    if isinstance(value, bool):
        raise ValueError(f"{field} must be a number or a quantity string, got {value!r}")
    if isinstance(value, int | float):
        number = float(value)
    elif isinstance(value, str):
        import pint

        ureg = registry()
        try:
            quantity = ureg.Quantity(value)
        except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError) as exc:
            raise ValueError(f"{field}: unknown unit in {value!r} ({exc})") from None
        except Exception:
            raise ValueError(f"{field}: cannot read {value!r} as a quantity") from None
        if not isinstance(quantity, ureg.Quantity):
            quantity = ureg.Quantity(float(quantity), "")
        wanted = ureg.Quantity(1, unit).dimensionality
        if quantity.dimensionality != wanted:
            expected = str(wanted) if wanted else "dimensionless"
            raise ValueError(f"{field}: {value!r} has dimension {quantity.dimensionality}, "
                             f"expected {expected} (e.g. {unit or 'a bare number'})")
        number = float(quantity.to(unit).magnitude)
    else:
        raise ValueError(f"{field} must be a number or a quantity string, got {value!r}")
    if not np.isfinite(number):
        raise ValueError(f"{field} must be a finite number, got {value!r}")
    return number


def convert(value, kind: str, system: str):
    """Convert SI values of an output ``kind`` to the display unit of ``system``.

    Returns the converted values (same shape) and the unit label.
    """
    if system not in DISPLAY_UNITS:
        raise ValueError(f"units must be one of {', '.join(UNIT_SYSTEMS)}, got {system!r}")
    target = DISPLAY_UNITS[system][kind]
    factor = registry().Quantity(1.0, SI_UNITS[kind]).to(target).magnitude
    return np.asarray(value) * factor, target.replace("**", "^").replace("*", " ")
