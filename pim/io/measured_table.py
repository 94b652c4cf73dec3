"""The case file's ``[measured]`` table: measured post-impact motion and its standard deviations.

    [measured]
    vehicle1.velocity = ["-5.1 ft/s", "17.6 ft/s"]
    vehicle1.velocity_sigma = ["0.3 m/s", "0.3 m/s"]   # or one value for both components
    vehicle1.yaw_rate = "-180 deg/s"
    vehicle1.yaw_rate_sigma = "5 deg/s"

A ``*_sigma`` is the standard deviation of the measured quantity of the same name (> 0, any
unit of its kind); :func:`pim.fit` then divides that residual by it (a chi-square cost).
"""

from __future__ import annotations

import numpy as np

from ..model.case import Measured
from ..model.numbers import InputError
from .toml_tables import check_keys
from .units import parse

__all__ = ["parse_measured", "MEASURED_KEYS"]

#: Keys allowed in ``[measured.vehicleN]``.
MEASURED_KEYS = ("velocity", "velocity_sigma", "yaw_rate", "yaw_rate_sigma")


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
    check_keys(table, ("vehicle1", "vehicle2"), "measured")
    values = {}
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
    try:
        return Measured(**values)
    except ValueError as exc:
        raise InputError(f"measured: {exc}") from None
