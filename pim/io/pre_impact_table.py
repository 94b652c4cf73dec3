"""The ``[evidence.vehicleN.pre_impact]`` sub-table of a case file: tyre marks before the
impact (SI after parsing; the model is :mod:`pim.model.pre_impact`).

```toml
[evidence.vehicle1.pre_impact]
skid_length = "42 ft"     # marks up to the impact (the end of the marks at the impact)
friction = 0.7            # tyre-road friction along the marks
braking = 1.0             # drag fraction: one fraction in [0, 1], or per wheel as
                          # [evidence] wheels: ["locked", "locked", "free", 0.5]
grade = "2 %"             # optional, + uphill in the direction of travel ("2 %", 0.02,
                          # "2 percent" or an angle "1.15 deg")
length_sigma = "2 ft"     # optional, standard deviation of the measured length
```

The Monte Carlo of ``pim reconstruct`` varies the friction and the length from the
``[uncertainty]`` table: ``evidence.vehicle1.pre_impact.friction = {plusminus = 0.1}``,
``evidence.vehicle1.pre_impact.skid_length = {normal = "2 ft"}``.
"""

from __future__ import annotations

import math

from ..model.numbers import InputError
from ..model.pre_impact import PreImpactMarks
from .toml_tables import check_keys
from .units import parse
from .wheels import wheel_fractions

__all__ = ["parse_pre_impact", "PRE_IMPACT_KEYS"]

#: Keys of a ``pre_impact`` sub-table.
PRE_IMPACT_KEYS = ("skid_length", "friction", "braking", "grade", "length_sigma")


def _grade(value, where) -> float:
    """Rise over run [-] from a number, a percentage ("2 %", "2 percent") or an angle."""
    if isinstance(value, str):
        text = value.strip()
        if text.endswith("%"):
            text = text[:-1].rstrip() + " percent"
        if any(unit in text for unit in ("deg", "rad")):
            return math.tan(parse(text, "angle", where))
        return parse(text, "dimensionless", where)
    return parse(value, "dimensionless", where)


def parse_pre_impact(table, where: str, front_share: float = 0.5) -> PreImpactMarks:
    """Parse a ``pre_impact`` sub-table (already read by tomllib) at ``where`` (e.g.
    ``evidence.vehicle1.pre_impact``).

    Parameters
    ----------
    table : dict
    where : str, the table's dotted name for error messages.
    front_share : float, the front axle's static share of the weight (weighs per-wheel
        braking; from the vehicle's wheelbase and CG position).

    Raises
    ------
    InputError
        Unknown or missing key, bad unit, negative length, friction <= 0, braking outside
        [0, 1], a grade steeper than 100 % or one down which friction cannot hold the car;
        naming the field.
    """
    check_keys(table, PRE_IMPACT_KEYS, where)
    for key in ("skid_length", "friction"):
        if key not in table:
            raise InputError(f"{where}: missing {key}")
    kwargs = {}
    for key in ("skid_length", "length_sigma"):      # the message quotes the user's value
        if key in table and parse(table[key], "length", f"{where}.{key}") < 0:
            raise InputError(f"{where}.{key} must be a length >= 0, got {table[key]!r}")
    if "length_sigma" in table:
        kwargs["length_sigma"] = parse(table["length_sigma"], "length", f"{where}.length_sigma")
    if "grade" in table:
        kwargs["grade"] = _grade(table["grade"], f"{where}.grade")
    return PreImpactMarks(
        skid_length=parse(table["skid_length"], "length", f"{where}.skid_length"),
        friction=parse(table["friction"], "dimensionless", f"{where}.friction"),
        braking=wheel_fractions(table.get("braking", 1.0), f"{where}.braking"),
        front_share=front_share, where=where, **kwargs)
