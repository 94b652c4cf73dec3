"""Published overall lengths and wheelbases (Cars93), and the line of wheelbase on length.

``pim/io/data/lock1993_cars93_dimensions.csv`` (its ``#`` lines give the source) holds the 93
cars and vans of Lock's "1993 New Car Data" (Journal of Statistics Education, 1993; R's MASS
data set Cars93): overall length, wheelbase and curb weight. :func:`wheelbase_lines` fits
each body class's least-squares line of wheelbase on overall length
(:func:`pim.model.inertia.wheelbase_line`); a class's line is used only when its slope
differs from zero at the 5 % level (:data:`SLOPE_LEVEL`: the cars; the 9 vans' slope does
not), and :func:`pim.io.inertia_data.estimate_yaw_inertia_from_length` then estimates the
yaw inertia of a vehicle whose case gives its mass and overall length but no wheelbase.
``python -m comparisons.docs inertia-estimate`` writes the table of docs/inertia-estimate.md
from them (a test keeps the two equal).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from ..model.inertia import WheelbaseLine, wheelbase_line
from ..model.numbers import InputError
from .datasets import body_class, bundled_rows

__all__ = ["DimensionRecord", "DATA_FILE", "SOURCE", "TYPES", "SLOPE_LEVEL",
           "load_dimension_records", "wheelbase_lines", "usable_lines", "slope_p_value",
           "held_out"]

DATA_FILE = "lock1993_cars93_dimensions.csv"
#: Short citation of the data, for notes and reports.
SOURCE = "Lock 1993 (Cars93)"
#: The data's types in each body class of :data:`pim.model.inertia.BODIES` they cover
#: (no SUVs or pickups).
TYPES = {"car": ("Small", "Compact", "Midsize", "Large", "Sporty"), "van": ("Van",)}
#: A class's line is used when the two-sided p-value of its slope is below this.
SLOPE_LEVEL = 0.05
_COLUMNS = ("row", "manufacturer", "model", "type", "length_in", "wheelbase_in", "weight_lb")
_INCH, _POUND = 0.0254, 0.45359237


@dataclass(frozen=True)
class DimensionRecord:
    """One vehicle of the Cars93 data [SI].

    Attributes
    ----------
    make, model : str
        As published.
    body : str
        Its class, a key of :data:`TYPES` (from the published type).
    length : float
        Overall length l [m].
    wheelbase : float
        Wheelbase L [m].
    mass : float
        Curb weight as a mass [kg].
    """

    make: str
    model: str
    body: str
    length: float
    wheelbase: float
    mass: float


def _record(row: dict, line: int) -> DimensionRecord:
    where = f"{DATA_FILE} line {line}"
    try:
        length, wheelbase, weight = (float(row[k]) for k in ("length_in", "wheelbase_in",
                                                              "weight_lb"))
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}: not a number ({exc})") from None
    if not (0 < wheelbase < length and weight > 0):
        raise InputError(f"{where}: the wheelbase must lie between 0 and the length, the "
                         f"weight be > 0")
    return DimensionRecord(make=row["manufacturer"], model=row["model"],
                           body=body_class(row["type"], TYPES, where), length=length * _INCH,
                           wheelbase=wheelbase * _INCH, mass=weight * _POUND)


@cache
def load_dimension_records() -> tuple[DimensionRecord, ...]:
    """Every vehicle of the bundled file, in its order.

    Raises
    ------
    InputError
        A malformed row (naming the line) or missing columns.
    """
    return tuple(_record(row, line) for line, row in bundled_rows(DATA_FILE, _COLUMNS))


def _rows(body: str) -> list[DimensionRecord]:
    return [r for r in load_dimension_records() if r.body == body]


@cache
def wheelbase_lines() -> dict[str, WheelbaseLine]:
    """Body class (a key of :data:`TYPES`) -> its line of wheelbase on overall length, used
    or not (:func:`usable_lines`)."""
    return {body: wheelbase_line([r.length for r in _rows(body)],
                                 [r.wheelbase for r in _rows(body)], body, SOURCE)
            for body in TYPES}


def slope_p_value(line: WheelbaseLine) -> float:
    """Two-sided p-value of the line's slope against zero (Student's t, n - 2 degrees of
    freedom)."""
    from scipy.stats import t as student

    se = line.sd / np.sqrt(line.length_ss)
    return float(2.0 * student.sf(abs(line.slope) / se, line.count - 2))


@cache
def usable_lines() -> dict[str, WheelbaseLine]:
    """The lines :func:`pim.io.inertia_data.estimate_yaw_inertia_from_length` uses: those
    whose slope's p-value is below :data:`SLOPE_LEVEL`."""
    return {body: line for body, line in wheelbase_lines().items()
            if slope_p_value(line) < SLOPE_LEVEL}


def held_out(body: str) -> tuple[int, int, float]:
    """How the class's line does on its vehicles it did not see: each left out in turn, the
    others' line estimates its wheelbase from its length. Returns (vehicles within 1.96
    predictive sd, vehicles, sd of the standardised errors [-])."""
    rows = _rows(body)
    z = []
    for i, r in enumerate(rows):
        others = rows[:i] + rows[i + 1:]
        line = wheelbase_line([o.length for o in others], [o.wheelbase for o in others],
                              body, SOURCE)
        z.append((r.wheelbase - float(line.wheelbase(r.length)))
                 / float(line.predictive_sd(r.length)))
    z = np.array(z)
    return int(np.sum(np.abs(z) <= 1.96)), len(rows), float(z.std(ddof=1))
