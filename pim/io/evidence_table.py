"""The ``[evidence]`` and ``[unknown]`` tables of a case file (SI after parsing).

```toml
[evidence.vehicle1]
rest_position = ["30 ft", "12 ft"]
rest_heading = "95 deg"
wheelbase = "108 in"
track = "58 in"
cg_to_front_axle = "45 in"   # optional: CG to the FRONT AXLE, default half the wheelbase
                             # (not [vehicleN] cg_to_front, the CG to the outline's front)
friction = 0.75
wheels = ["locked", "locked", "free", 0.3]   # or one word for all four
steer = "0 deg"              # optional: one angle (front wheels) or four
position_sigma = "0.3 ft"    # optional
heading_sigma = "2 deg"      # optional
path_points = [["10 ft", "3 ft"]]   # optional
# the run-out keys above may all be left out when the vehicle has only sub-tables
# (:data:`SUBTABLES`: crush, pre_impact): then it has no run-out, and its speed at the
# impact comes from the other evidence ([measured] motion, the other vehicle's run-out, ...)

[evidence.vehicle1.pre_impact]   # optional: marks before the impact (pim.io.pre_impact_table)
skid_length = "42 ft"
friction = 0.7

[evidence.vehicle2.crush]    # a crush profile (pim.io.crush_table); vehicle2 has no run-out
side = "left"
width = "60 in"
depths = ["2 in", "8 in", "9 in", "3 in"]
class = "midsize car"
partition = "total"          # optional: "total" (CRASH3, default) or "normal" (Brach & Welsh)

[unknown]
vehicle1.speed = {bounds = ["0 mph", "80 mph"]}
impact.restitution = {bounds = [0, 1]}
```
"""

from __future__ import annotations

import functools
import logging

import numpy as np

from ..model.evidence import UNKNOWN_KINDS, Evidence, VehicleEvidence
from ..model.numbers import InputError, did_you_mean
from .crush_table import parse_crush
from .pre_impact_table import parse_pre_impact
from .toml_tables import check_keys
from .units import parse
from .wheels import wheel_fractions

__all__ = ["parse_evidence", "parse_unknown", "SUBTABLES", "OLD_AXLE_KEY", "AXLE_KEY"]

#: CG to the front axle [m] in ``[evidence.vehicleN]``; its old name, still read (the same
#: length) with a deprecation message, because ``[vehicleN] cg_to_front`` is another
#: length (the CG to the front of the outline).
AXLE_KEY, OLD_AXLE_KEY = "cg_to_front_axle", "cg_to_front"
_EVIDENCE = {"rest_position", "rest_heading", "wheelbase", "track", AXLE_KEY, OLD_AXLE_KEY,
             "friction", "wheels", "steer", "position_sigma", "heading_sigma", "path_points"}
_LOG = logging.getLogger(__name__)
#: Sub-tables of ``[evidence.vehicleN]`` beside the run-out keys (each optional; a vehicle
#: may have only these): the crush profile, the marks before the impact.
SUBTABLES = {"crush": "crush-profile evidence", "pre_impact": "pre-impact (skid-mark) evidence"}
#: The sub-tables this version reads.
_PARSED = ("crush", "pre_impact")


def _point(value, where):
    if not isinstance(value, list) or len(value) != 2:
        raise InputError(f"{where} must be [x, y], got {value!r}")
    return np.array([parse(v, "length", f"{where}[{i}]") for i, v in enumerate(value)])


def _cg_to_front_axle(table, wheelbase, where) -> float:
    """CG to the front axle [m] of ``[evidence.vehicleN]`` (default half the wheelbase).

    The old key ``cg_to_front`` (always the axle distance in this table) is read as the same
    length, with a message on stderr (once) naming the new key: old case files keep their
    results, and a reader who meant the bumper distance of ``[vehicleN] cg_to_front`` is told
    which length this is. Both keys at once are an error."""
    if OLD_AXLE_KEY in table:
        if AXLE_KEY in table:
            raise InputError(f"{where}: give {AXLE_KEY} (CG to the front axle) only, not "
                             f"also its old name {OLD_AXLE_KEY}")
        _say_old_axle_key()
        return parse(table[OLD_AXLE_KEY], "length", f"{where}.{OLD_AXLE_KEY}")
    if AXLE_KEY in table:
        return parse(table[AXLE_KEY], "length", f"{where}.{AXLE_KEY}")
    return wheelbase / 2


@functools.cache
def _say_old_axle_key() -> None:
    """The deprecation message of ``cg_to_front`` in ``[evidence.vehicleN]``, logged once
    per process (functools.cache: later calls return at once)."""
    _LOG.warning(f"evidence.vehicleN.{OLD_AXLE_KEY} is deprecated: it is read as the CG to "
                 f"the FRONT AXLE; rename it {AXLE_KEY} ([vehicleN] {OLD_AXLE_KEY} is the CG "
                 f"to the outline's front)")


def _marks_alone(table, where, front_share: float):
    """The ``pre_impact`` marks of an ``[evidence.vehicleN]`` table without run-out keys
    (None without marks); per-wheel braking weighs by ``front_share``."""
    if "pre_impact" not in table:
        return None
    return parse_pre_impact(table["pre_impact"], f"{where}.pre_impact",
                            front_share=front_share)


def _vehicle(table, where) -> VehicleEvidence | None:
    """The run-out evidence of ``[evidence.vehicleN]``, or None when the table holds only
    sub-tables of other evidence (:data:`SUBTABLES`: crush, marks before the impact)."""
    check_keys(table, _EVIDENCE | set(SUBTABLES), where)
    if not table:
        raise InputError(f"[{where}] is empty: give the run-out's rest_position, "
                         f"rest_heading, wheelbase, track and friction, or a "
                         f"[{where}.crush] or [{where}.pre_impact] sub-table, or leave the "
                         f"table out")
    for key in set(SUBTABLES) - set(_PARSED):
        if key in table:
            raise InputError(f"{where}.{key}: {SUBTABLES[key]} is not supported by this "
                             f"version")
    if not set(table) - set(SUBTABLES):
        return None
    for key in ("rest_position", "rest_heading", "wheelbase", "track", "friction"):
        if key not in table:
            raise InputError(f"{where}: missing {key}")
    wheelbase = parse(table["wheelbase"], "length", f"{where}.wheelbase")
    steer = table.get("steer", 0.0)
    if isinstance(steer, list):
        if len(steer) != 4:
            raise InputError(f"{where}.steer must be one angle (front wheels) or four")
        steer = tuple(parse(s, "angle", f"{where}.steer[{i}]") for i, s in enumerate(steer))
    else:
        front = parse(steer, "angle", f"{where}.steer")
        steer = (front, front, 0.0, 0.0)
    points = table.get("path_points", [])
    if not isinstance(points, list):
        raise InputError(f"{where}.path_points must be a list of [x, y]")
    path = np.array([_point(p, f"{where}.path_points[{i}]") for i, p in enumerate(points)])
    kwargs = {}
    if "position_sigma" in table:
        kwargs["position_sigma"] = parse(table["position_sigma"], "length",
                                         f"{where}.position_sigma")
    if "heading_sigma" in table:
        kwargs["heading_sigma"] = parse(table["heading_sigma"], "angle",
                                        f"{where}.heading_sigma")
    a = _cg_to_front_axle(table, wheelbase, where)
    if "pre_impact" in table:      # per-wheel braking weighs by the static axle loads
        share = 1 - a / wheelbase if wheelbase > 0 else 0.5
        kwargs["pre_impact"] = parse_pre_impact(table["pre_impact"], f"{where}.pre_impact",
                                                front_share=min(max(share, 0.0), 1.0))
    return VehicleEvidence(
        rest_position=_point(table["rest_position"], f"{where}.rest_position"),
        rest_heading=parse(table["rest_heading"], "angle", f"{where}.rest_heading"),
        wheelbase=wheelbase, track=parse(table["track"], "length", f"{where}.track"),
        cg_to_front_axle=a,
        friction=parse(table["friction"], "dimensionless", f"{where}.friction"),
        braking=wheel_fractions(table.get("wheels", "locked"), f"{where}.wheels"), steer=steer,
        path_points=path.reshape(-1, 2), where=where, **kwargs)


def parse_evidence(table, dimensions=None, front_shares=None) -> Evidence | None:
    """Parse the ``[evidence]`` table (already read by tomllib), or None when absent.

    Parameters
    ----------
    table : dict or None
    dimensions : dict, optional
        Vehicle number -> (length, width) [m] (None where unknown): a crush profile must fit
        on its vehicle (:func:`pim.io.crush_table.parse_crush`).
    front_shares : dict, optional
        Vehicle number -> the front axle's static share of the weight [-], for the per-wheel
        braking of marks before the impact of a vehicle without run-out evidence (from
        ``[vehicleN]`` wheelbase and cg_to_front_axle; default 0.5, as the run-out's
        default axle position gives).

    Raises
    ------
    ValueError
        Unknown key, missing field, bad unit, NaN, friction <= 0, bad crush, ...; naming
        the field.
    """
    if table is None:
        return None
    if not isinstance(table, dict) or not set(table) <= {"vehicle1", "vehicle2"}:
        raise InputError("evidence must hold [evidence.vehicle1] and/or [evidence.vehicle2]")
    for k, v in table.items():
        check_keys(v, _EVIDENCE | set(SUBTABLES), f"evidence.{k}")
    crush, partitions = {}, {}
    for k, v in table.items():
        if "crush" in v:
            i = int(k[-1])
            where = f"evidence.{k}.crush"
            length, width = (dimensions or {}).get(i, (None, None))
            crush[f"crush{i}"] = parse_crush(v["crush"], where, length, width,
                                             extra_keys=("partition",))
            partitions[where] = v["crush"].get("partition", "total")
    if len(set(partitions.values())) > 1:
        raise InputError(f"evidence: the crush tables ask for different partitions "
                         f"({', '.join(f'{w}.partition = {p!r}' for w, p in partitions.items())}"
                         f"); the comparison is of both vehicles' energies together")
    partition = next(iter(partitions.values()), "total")
    runouts = {k: _vehicle(v, f"evidence.{k}") for k, v in table.items()}
    marks = {f"marks{k[-1]}": _marks_alone(v, f"evidence.{k}",
                                           (front_shares or {}).get(int(k[-1]), 0.5))
             for k, v in table.items() if runouts[k] is None}
    return Evidence(**runouts, **crush, crush_partition=partition, **marks)


def parse_unknown(table) -> dict[str, tuple[float, float]] | None:
    """Parse the ``[unknown]`` table: dotted key -> (low, high) bounds in SI.

    Raises
    ------
    ValueError
        Unknown key, bounds not [low, high], low > high, a negative speed bound, or a
        restitution/beta bound outside [0, 1]; naming the key.
    """
    if table is None:
        return None
    if not isinstance(table, dict):
        raise InputError("unknown must be a table")
    flat = {}
    for group, entries in table.items():
        if not isinstance(entries, dict):
            raise InputError(f"unknown.{group} must be a table of keys")
        for key, spec in entries.items():
            name = f"{group}.{key}"
            if name not in UNKNOWN_KINDS:
                raise InputError(f"unknown: {name!r} cannot be solved for"
                                 f"{did_you_mean(name, UNKNOWN_KINDS)} (allowed: "
                                 f"{', '.join(UNKNOWN_KINDS)})")
            if not isinstance(spec, dict) or set(spec) != {"bounds"} or not isinstance(
                    spec["bounds"], list) or len(spec["bounds"]) != 2:
                raise InputError(f"unknown.{name} must be {{bounds = [low, high]}}")
            low, high = (parse(v, UNKNOWN_KINDS[name], f"unknown.{name}.bounds[{i}]")
                         for i, v in enumerate(spec["bounds"]))
            written = [str(v) for v in spec["bounds"]]
            if low > high:
                raise InputError(f"unknown.{name}.bounds: low {written[0]} must be <= high "
                                 f"{written[1]}")
            if key == "speed" and low < 0:
                raise InputError(f"unknown.{name}.bounds must be >= 0 (a speed along the "
                                 f"case's direction), got low = {written[0]}")
            if key in ("restitution", "beta") and not 0 <= low <= high <= 1:
                raise InputError(f"unknown.{name}.bounds must lie in [0, 1]")
            flat[name] = (low, high)
    return flat
