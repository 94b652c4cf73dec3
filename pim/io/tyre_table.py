"""The ``[tyres]`` and ``[driver]`` tables of a case file (SI after parsing).

```toml
[tyres.vehicle1]                      # the field tyre (pim.model.tyres.field_wheel_force)
cornering_stiffness = "80 kN/rad"     # per tyre: one value or four (FL, FR, RL, RR)
longitudinal_stiffness = "150 kN"     # per tyre and unit slip: one value or four
cg_height = "0.55 m"
rolling_resistance = 0.013
buildup_time = "0.2 s"                # brake build-up
# every key optional: the defaults are a mid-size sedan's (pim.model.tyres.SEDAN_TYRE)

[driver.vehicle1]                     # inputs over time, from the impact (negative: before)
time = ["0 s", "0.5 s", "2 s"]
steer = ["0 deg", "5 deg", "5 deg"]   # road-wheel angle of the front wheels
brake = [[0, 0, 0, 0], [1, 1, 0.5, 0.5], [1, 1, 0.5, 0.5]]   # per time: FL, FR, RL, RR
```

A vehicle with a ``[tyres.vehicleN]`` table runs out on the field tyre, one without on the
Coulomb tyre; a ``[driver.vehicleN]`` table replaces the evidence's constant ``wheels`` and
``steer``. Both attach to the vehicle's ``[evidence]`` (:func:`attach_tyres`).
"""

from __future__ import annotations

import re
from dataclasses import replace

from ..model.driver import DriverInputs
from ..model.evidence import Evidence
from ..model.numbers import InputError
from ..model.tyres import SEDAN_TYRE, TyreData
from .toml_tables import check_keys
from .units import parse, quantity_in

__all__ = ["parse_tyres", "parse_driver", "attach_tyres"]

_VEHICLES = {"vehicle1", "vehicle2"}


def _quantity(value, unit: str, field: str) -> float:
    """A number (SI) or a quantity string converted to ``unit`` (pint), else a ValueError."""
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise InputError(f"{field} must be a number or a quantity string, got {value!r}")
    if not isinstance(value, str):
        return float(value)
    try:
        return quantity_in(value, unit)
    except Exception:
        raise InputError(f"{field}: {value!r} is not a quantity in {unit} "
                         f"(e.g. '1 {unit}')") from None


def _stiffness(value, unit: str, field: str) -> float:
    """A stiffness; per angle (``unit`` "N/rad") the string must name its angle unit, since
    pint takes radians as dimensionless ("80 kN" is no cornering stiffness)."""
    if unit == "N/rad" and isinstance(value, str) and not re.search(
            r"/\s*(rad|radian|deg|degree)s?\s*$", value):
        raise InputError(f"{field}: {value!r} is not a force per angle (e.g. '80 kN/rad', "
                         f"'1400 N/deg')")
    return _quantity(value, unit, field)


def _one_or_four(value, unit: str, field: str):
    if isinstance(value, list):
        if len(value) != 4:
            raise InputError(f"{field} must be one value or four (FL, FR, RL, RR)")
        return tuple(_stiffness(v, unit, f"{field}[{i}]") for i, v in enumerate(value))
    return _stiffness(value, unit, field)


def _tyre(table, where) -> TyreData:
    check_keys(table, set(SEDAN_TYRE), where)
    kwargs = {}
    for key, unit in (("cornering_stiffness", "N/rad"), ("longitudinal_stiffness", "N")):
        if key in table:
            kwargs[key] = _one_or_four(table[key], unit, f"{where}.{key}")
    if "cg_height" in table:
        kwargs["cg_height"] = parse(table["cg_height"], "length", f"{where}.cg_height")
    if "rolling_resistance" in table:
        kwargs["rolling_resistance"] = parse(table["rolling_resistance"], "dimensionless",
                                             f"{where}.rolling_resistance")
    if "buildup_time" in table:
        kwargs["buildup_time"] = _quantity(table["buildup_time"], "s", f"{where}.buildup_time")
    try:
        return TyreData(**kwargs)
    except ValueError as exc:
        raise InputError(str(exc).replace("tyres.", f"{where}.", 1)) from None


def _driver(table, where) -> DriverInputs:
    check_keys(table, {"time", "steer", "brake"}, where)
    if "time" not in table:
        raise InputError(f"{where}: missing time")
    times = table["time"]
    if not isinstance(times, list) or not times:
        raise InputError(f"{where}.time must be a list of times")
    k = len(times)
    steer = table.get("steer", [0.0] * k)
    brake = table.get("brake", [[0.0] * 4] * k)
    if not isinstance(steer, list) or not isinstance(brake, list) or len(steer) != k or len(
            brake) != k:
        raise InputError(f"{where}: steer and brake must hold one entry per time ({k})")
    rows = []
    for i, row in enumerate(brake):
        row = row if isinstance(row, list) else [row] * 4
        if len(row) != 4:
            raise InputError(f"{where}.brake[{i}] must be one fraction or four (FL, FR, RL, RR)")
        rows.append([parse(v, "dimensionless", f"{where}.brake[{i}][{j}]")
                     for j, v in enumerate(row)])
    try:
        return DriverInputs([_quantity(t, "s", f"{where}.time[{i}]") for i, t in enumerate(times)],
                            [parse(s, "angle", f"{where}.steer[{i}]") for i, s in enumerate(steer)],
                            rows)
    except ValueError as exc:
        raise InputError(str(exc).replace("driver.", f"{where}.", 1)) from None


def _per_vehicle(table, name, parse_one) -> dict:
    if table is None:
        return {}
    if not isinstance(table, dict) or not set(table) <= _VEHICLES:
        raise InputError(f"{name} must hold [{name}.vehicle1] and/or [{name}.vehicle2]")
    return {k: parse_one(v, f"{name}.{k}") for k, v in table.items()}


def parse_tyres(table) -> dict:
    """Parse ``[tyres]``: ``{"vehicle1": TyreData, ...}`` (empty when absent)."""
    return _per_vehicle(table, "tyres", _tyre)


def parse_driver(table) -> dict:
    """Parse ``[driver]``: ``{"vehicle1": DriverInputs, ...}`` (empty when absent)."""
    return _per_vehicle(table, "driver", _driver)


def attach_tyres(evidence: Evidence | None, tyres, driver) -> Evidence | None:
    """The evidence with each vehicle's tyre data and driver inputs attached (the raw
    ``[tyres]`` and ``[driver]`` tables); a table for a vehicle without evidence is an
    error."""
    tyre_data, inputs = parse_tyres(tyres), parse_driver(driver)
    for name, table in (("tyres", tyre_data), ("driver", inputs)):
        for key in table:
            if evidence is None or getattr(evidence, key) is None:
                raise InputError(f"{name}.{key} needs [evidence.{key}] (the run-out it drives)")
    if evidence is None:
        return None
    changes = {key: replace(getattr(evidence, key), tyre=tyre_data.get(key),
                            driver=inputs.get(key))
               for key in _VEHICLES if getattr(evidence, key) is not None}
    return replace(evidence, **changes)
