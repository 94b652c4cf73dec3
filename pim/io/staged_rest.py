"""Published rest positions of staged two-car collisions (Day, SAE 2004-01-1207).

``pim/io/data/day2004_staged_rest.csv`` (its ``#`` lines give the source) holds the five
vehicle-to-vehicle crash tests of Day's SIMON validation as transcribed in J. Cormier's
pycrash: the vehicles, their impact speeds, and each vehicle's displacement from impact to
rest and heading at rest. Four are RICSAC collisions (2, 3, 6, 10; the ``ricsac`` column,
identified here). The transcript states no axes for the displacements, so only their
length (the path range, as Day's statistics use it: :attr:`StagedRest.rest_range`) is
frame-free. docs/event.md ("Staged tests with secondary impacts") runs RICSAC 10 through
the event against it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from ..model.numbers import InputError
from .datasets import bundled_rows

__all__ = ["StagedRest", "DATA_FILE", "SOURCE", "load_staged_rest", "staged_rest"]

DATA_FILE = "day2004_staged_rest.csv"
#: Short citation of the data, for notes and tables.
SOURCE = "Day, SAE 2004-01-1207 (as transcribed in pycrash)"
_COLUMNS = ("test", "type", "vehicle1", "vehicle2", "speed1_mph", "speed2_mph",
            "relative_angle_deg", "dx1_ft", "dy1_ft", "heading1_deg", "dx2_ft", "dy2_ft",
            "heading2_deg", "dv1_mph", "dv2_mph", "ricsac")
_FT, _MPH, _DEG = 0.3048, 0.44704, math.pi / 180


@dataclass(frozen=True)
class StagedRest:
    """One staged collision's published rest positions [SI].

    Attributes
    ----------
    test : str
        The transcript's name (``VC1`` ... ``VC11``).
    kind : str
        ``oblique`` or ``collinear``.
    vehicles : tuple of str
        Vehicle 1 and vehicle 2 as named.
    speed : ndarray (2,)
        Impact speeds [m/s].
    relative_angle : float
        Relative heading of the two vehicles [rad].
    displacement : ndarray (2, 2)
        Each vehicle's displacement from impact to rest [m] (row: vehicle; axes unstated).
    heading : ndarray (2,)
        Each vehicle's heading at rest as tabulated [rad] (its reference unstated).
    delta_v : ndarray (2,)
        Each vehicle's delta-V [m/s].
    ricsac : int or None
        The RICSAC collision this test is (identified here), None for a non-RICSAC test.
    line : int
        Line of the row in the file.
    """

    test: str
    kind: str
    vehicles: tuple
    speed: np.ndarray
    relative_angle: float
    displacement: np.ndarray
    heading: np.ndarray
    delta_v: np.ndarray
    ricsac: int | None
    line: int

    @property
    def rest_range(self) -> np.ndarray:
        """Each vehicle's straight-line distance from impact to rest [m] (2,)."""
        return np.hypot(self.displacement[:, 0], self.displacement[:, 1])


def _numbers(row: dict, where: str) -> dict:
    out = {}
    for key in _COLUMNS[4:15]:
        try:
            value = float(row[key])
        except (TypeError, ValueError):
            raise InputError(f"{where} column {key!r}: {row[key]!r} is not a number") from None
        if not math.isfinite(value):
            raise InputError(f"{where} column {key!r}: {row[key]!r} is not a finite number")
        out[key] = value
    for key in ("speed1_mph", "speed2_mph", "dv1_mph", "dv2_mph"):
        if not 0 <= out[key] <= 200:
            raise InputError(f"{where} column {key!r}: {out[key]:g} outside [0, 200] mph")
    return out


def _record(row: dict, line: int) -> StagedRest:
    where = f"{DATA_FILE} line {line}"
    n = _numbers(row, where)
    ricsac = row["ricsac"].strip()
    if ricsac and not (ricsac.isdigit() and 1 <= int(ricsac) <= 12):
        raise InputError(f"{where} column 'ricsac': {ricsac!r} is not a RICSAC number 1-12")
    return StagedRest(
        test=row["test"], kind=row["type"], vehicles=(row["vehicle1"], row["vehicle2"]),
        speed=np.array([n["speed1_mph"], n["speed2_mph"]]) * _MPH,
        relative_angle=n["relative_angle_deg"] * _DEG,
        displacement=np.array([[n["dx1_ft"], n["dy1_ft"]], [n["dx2_ft"], n["dy2_ft"]]]) * _FT,
        heading=np.array([n["heading1_deg"], n["heading2_deg"]]) * _DEG,
        delta_v=np.array([n["dv1_mph"], n["dv2_mph"]]) * _MPH,
        ricsac=int(ricsac) if ricsac else None, line=line)


@cache
def load_staged_rest() -> tuple[StagedRest, ...]:
    """Every test of the bundled file, in its order.

    Raises
    ------
    InputError
        A malformed row (naming the line and column) or missing columns.
    """
    return tuple(_record(row, line) for line, row in bundled_rows(DATA_FILE, _COLUMNS))


def staged_rest(ricsac: int) -> StagedRest:
    """The test of the file that is RICSAC collision ``ricsac``.

    Raises
    ------
    InputError
        No row is that collision.
    """
    for record in load_staged_rest():
        if record.ricsac == ricsac:
            return record
    have = sorted(r.ricsac for r in load_staged_rest() if r.ricsac is not None)
    raise InputError(f"ricsac: no published rest positions of RICSAC {ricsac} "
                     f"(the file has {', '.join(map(str, have))})")
