"""The case file's ``[measured]`` table: measured post-impact motion and its standard deviations.

    [measured]
    vehicle1.velocity = ["-5.1 ft/s", "17.6 ft/s"]
    vehicle1.velocity_sigma = ["0.3 m/s", "0.3 m/s"]   # or one value for both components
    vehicle1.yaw_rate = "-180 deg/s"
    vehicle1.yaw_rate_sigma = "5 deg/s"

A ``*_sigma`` is the standard deviation of the measured quantity of the same name (> 0, any
unit of its kind); :func:`pim.fit` then divides that residual by it (a chi-square cost).

Evidence other than the post-impact motion (:mod:`pim.model.evidence_terms`), each with
its sigma (required):

    [measured]
    vehicle1.delta_v = ["-25 km/h", "3 km/h"]    # recorder: [longitudinal, lateral],
    vehicle1.delta_v_sigma = "1 km/h"            # vehicle frame (x forward, y left)
    vehicle2.pre_crash_speed = "40 km/h"         # recorder: |V| before the impact
    vehicle2.pre_crash_speed_sigma = "1 km/h"
    energy_loss = "95 kJ"                         # kinetic energy lost (e.g. crush)
    energy_loss_sigma = "15 kJ"
"""

from __future__ import annotations

import re

import numpy as np

from ..model.case import Measured
from ..model.numbers import InputError
from .toml_tables import check_keys
from .units import parse

__all__ = ["parse_measured", "MEASURED_KEYS"]

#: Keys allowed in ``[measured.vehicleN]``.
MEASURED_KEYS = ("velocity", "velocity_sigma", "yaw_rate", "yaw_rate_sigma", "delta_v",
                 "delta_v_sigma", "pre_crash_speed", "pre_crash_speed_sigma")
#: Keys allowed at the top of ``[measured]`` beside the vehicles.
PAIR_KEYS = ("energy_loss", "energy_loss_sigma")


def _pair(value, field: str, allow_one: bool) -> np.ndarray:
    if allow_one and not isinstance(value, list):
        v = parse(value, "velocity", field)
        return np.array([v, v])
    if not isinstance(value, list) or len(value) != 2:
        raise InputError(f"{field} must be a list of two values [x, y]"
                         f"{' or one value' if allow_one else ''}, got {value!r}")
    return np.array([parse(value[0], "velocity", f"{field}[0]"),
                     parse(value[1], "velocity", f"{field}[1]")])


def parse_measured(table) -> Measured | None:
    """The :class:`pim.Measured` of a ``[measured]`` table (None when the table is absent).

    Raises
    ------
    ValueError
        Unknown key, malformed value, a sigma <= 0 or a sigma without its measured value,
        naming the field.
    """
    if table is None:
        return None
    check_keys(table, ("vehicle1", "vehicle2") + PAIR_KEYS, "measured")
    values = {key: parse(table[key], "energy", f"measured.{key}") for key in PAIR_KEYS
              if key in table}
    for i in (1, 2):
        where = f"measured.vehicle{i}"
        sub = table.get(f"vehicle{i}", {})
        check_keys(sub, MEASURED_KEYS, where)
        if "velocity" in sub:
            values[f"velocity{i}"] = _pair(sub["velocity"], f"{where}.velocity", False)
        if "velocity_sigma" in sub:
            values[f"velocity{i}_sigma"] = _pair(sub["velocity_sigma"],
                                                 f"{where}.velocity_sigma", True)
        for key in ("yaw_rate", "yaw_rate_sigma"):
            if key in sub:
                values[key.replace("yaw_rate", f"yaw_rate{i}")] = parse(
                    sub[key], "angular_velocity", f"{where}.{key}")
        values.update(_recorder(sub, i, where))
        _check_signs(sub, values, i, where)
    _check_signs(table, values, None, "measured")
    try:
        return Measured(**values)
    except ValueError as exc:
        raise InputError(f"measured: {_field_names(str(exc))}") from None


def _recorder(sub: dict, i: int, where: str) -> dict:
    """The event data recorder's fields of ``[measured.vehicleN]`` as :class:`Measured`
    keyword arguments [SI]."""
    out = {}
    if "delta_v" in sub:
        out[f"delta_v{i}"] = _pair(sub["delta_v"], f"{where}.delta_v", False)
    if "delta_v_sigma" in sub:
        out[f"delta_v{i}_sigma"] = _pair(sub["delta_v_sigma"], f"{where}.delta_v_sigma", True)
    for key in ("pre_crash_speed", "pre_crash_speed_sigma"):
        if key in sub:
            out[key.replace("speed", f"speed{i}")] = parse(sub[key], "velocity",
                                                           f"{where}.{key}")
    return out


def _check_signs(table: dict, values: dict, i: int | None, where: str) -> None:
    """InputError naming the field, with the value as written (the case's units), for a
    sigma <= 0, an energy loss <= 0 or a pre-crash speed < 0 (:class:`Measured` checks the
    same in SI)."""
    for key, text in table.items():
        name = key if i is None else (key.replace("_sigma", f"{i}_sigma") if key.endswith(
            "_sigma") else f"{key}{i}")
        if name not in values or isinstance(text, dict):
            continue
        value = np.asarray(values[name], dtype=float)
        if key.endswith("_sigma") or key == "energy_loss":
            if np.any(value <= 0):
                raise InputError(f"{where}.{key} must be > 0, got {text!r}")
        elif key == "pre_crash_speed" and np.any(value < 0):
            raise InputError(f"{where}.{key} must be >= 0 (a speed), got {text!r}")


def _field_names(message: str) -> str:
    """A :class:`Measured` message with its field names as the case file spells them
    (``delta_v1_sigma`` -> ``vehicle1.delta_v_sigma``)."""
    return re.sub(r"\b(delta_v|pre_crash_speed)([12])(_sigma)?\b",
                  lambda m: f"vehicle{m[2]}.{m[1]}{m[3] or ''}", message)
