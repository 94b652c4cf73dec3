"""NHTSA's measured CG positions (NCAP 2004), and the CG's axle position per body class.

``pim/io/data/nhtsa_ncap2004_cg_position.csv`` (its ``#`` lines give the source) holds the 52
vehicles of NHTSA's NCAP 2004 rollover resistance measurements: wheelbase, test weight and
the CG's distance behind the front axle. :func:`axle_fractions` gives each body class of
:data:`pim.model.inertia.BODIES` its :class:`pim.model.inertia.AxleFraction` (a / L, its
mean and scatter), which :func:`pim.io.inertia_data.estimate_yaw_inertia` uses when a case
gives no ``cg_to_front_axle``. A class with fewer than :data:`MIN_COUNT` measured vehicles
(the vans: 3) takes the pooled fraction of all 52. :func:`pim.io.inertia_data.axle_table`
writes the CG table of docs/inertia-estimate.md from them (``python -m pim.io.inertia_data``
prints it; a test keeps the two equal).

The data give no overall length or front overhang, so the CG's distance from the front of
the outline (``[vehicleN] cg_to_front``) is not estimated from them (docs/inertia-estimate.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from ..model.inertia import BODIES, AxleFraction, axle_fraction
from ..model.numbers import InputError
from .datasets import body_class, bundled_rows

__all__ = ["CgRecord", "DATA_FILE", "SOURCE", "MIN_COUNT", "TYPES", "load_cg_records",
           "axle_fractions", "held_out"]

DATA_FILE = "nhtsa_ncap2004_cg_position.csv"
#: Short citation of the data, for notes and reports.
SOURCE = "NHTSA's NCAP 2004 measurements"
#: Fewest measured vehicles a class needs for its own CG position; fewer: the pooled one.
MIN_COUNT = 5
#: The table's body styles in each class of :data:`pim.model.inertia.BODIES`.
TYPES = {"car": ("Sedan", "Wagon", "Hatchback", "Convertible"), "suv": ("SUV",),
         "pickup": ("Pickup",), "van": ("Van",)}
_COLUMNS = ("ncap_year", "model_year", "make", "model", "drive", "type", "wheelbase_in",
            "test_weight_lb", "cg_long_in", "wd_front")
_INCH, _POUND = 0.0254, 0.45359237


@dataclass(frozen=True)
class CgRecord:
    """One measured vehicle of NHTSA's NCAP 2004 rollover measurements [SI].

    Attributes
    ----------
    model_year : int
        Model year.
    make, model, drive : str
        As tabulated.
    body : str
        Its class, a key of :data:`pim.model.inertia.BODIES` (from the table's body style).
    wheelbase : float
        Wheelbase L [m].
    mass : float
        Test weight as a mass [kg].
    cg_to_front_axle : float
        The CG's distance behind the front axle, a [m].
    front_share : float
        The table's share of the weight on the front axle, b / L [-].
    """

    model_year: int
    make: str
    model: str
    drive: str
    body: str
    wheelbase: float
    mass: float
    cg_to_front_axle: float
    front_share: float

    @property
    def fraction(self) -> float:
        """a / L [-]: the CG's fraction of the wheelbase behind the front axle."""
        return self.cg_to_front_axle / self.wheelbase


def _record(row: dict, line: int) -> CgRecord:
    where = f"{DATA_FILE} line {line}"
    try:
        year, wheelbase = int(row["model_year"]), float(row["wheelbase_in"])
        weight, a, share = (float(row[k]) for k in ("test_weight_lb", "cg_long_in", "wd_front"))
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}: not a number ({exc})") from None
    if not (wheelbase > 0 and weight > 0 and 0 < a < wheelbase and 0 < share < 1):
        raise InputError(f"{where}: wheelbase and weight must be > 0, the CG between the axles")
    return CgRecord(model_year=year, make=row["make"], model=row["model"], drive=row["drive"],
                    body=body_class(row["type"], TYPES, where), wheelbase=wheelbase * _INCH,
                    mass=weight * _POUND, cg_to_front_axle=a * _INCH, front_share=share)


@cache
def load_cg_records() -> tuple[CgRecord, ...]:
    """Every vehicle of the bundled file, in its order.

    Raises
    ------
    InputError
        A malformed row (naming the line) or missing columns.
    """
    return tuple(_record(row, line) for line, row in bundled_rows(DATA_FILE, _COLUMNS))


def _own(body: str) -> list[CgRecord]:
    return [r for r in load_cg_records() if r.body == body]


@cache
def axle_fractions() -> dict[str, AxleFraction]:
    """Body class (a key of :data:`pim.model.inertia.BODIES`) -> its CG position a / L: the
    class's own when it has at least :data:`MIN_COUNT` measured vehicles, else the pooled
    one of all vehicles (its ``body`` then "all")."""
    pooled = axle_fraction([r.fraction for r in load_cg_records()], "all", SOURCE)
    out = {}
    for body in BODIES:
        rows = _own(body)
        out[body] = (axle_fraction([r.fraction for r in rows], body, SOURCE)
                     if len(rows) >= MIN_COUNT else pooled)
    return out


def held_out(body: str) -> tuple[int, int, float]:
    """How the class's CG position does on its measured vehicles it did not see: each left
    out in turn, the others' fraction (or, for a class below :data:`MIN_COUNT`, all other
    vehicles') estimates its a / L. Returns (vehicles within 1.96 predictive sd, vehicles,
    sd of the standardised errors [-])."""
    rows = _own(body)
    pool = load_cg_records() if len(rows) < MIN_COUNT else tuple(rows)
    z = []
    for r in rows:
        others = axle_fraction([o.fraction for o in pool if o is not r], body, SOURCE)
        z.append((r.fraction - others.mean) / others.predictive_sd)
    z = np.array(z)
    return int(np.sum(np.abs(z) <= 1.96)), len(rows), float(z.std(ddof=1))
