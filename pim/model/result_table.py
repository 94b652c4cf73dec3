"""Tabulate a scalar :class:`pim.Result` in display units, for tables, JSON, reports and
notebooks (:meth:`pim.Result._repr_html_`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from typing import TYPE_CHECKING

from .display import convert
from .numbers import InputError

if TYPE_CHECKING:
    from .result import Result

__all__ = ["Row", "summarize", "format_table", "rows_to_json", "table_title"]


@dataclass(frozen=True)
class Row:
    """One line of a result table: a quantity per vehicle (or one shared value) and its unit.

    Attributes
    ----------
    key : str
        Machine name of the quantity (the key in JSON output, e.g. "delta_v").
    label : str
        Plain-language label (e.g. "|delta-V|").
    vehicle1 : float or None
        Vehicle 1's value, or the shared value of a ``single`` row, in ``unit``.
    vehicle2 : float or None
        Vehicle 2's value in ``unit`` (None for a ``single`` row, or a quantity a fixed
        barrier does not have).
    unit : str
        Unit symbol of the values in the table's unit system ("" when dimensionless).
    single : bool
        One shared value (in ``vehicle1``), not one per vehicle.
    """

    key: str
    label: str
    vehicle1: float | None
    vehicle2: float | None
    unit: str
    single: bool = False    #: one shared value (in ``vehicle1``), not one per vehicle


def _f(x) -> float:
    return float(np.asarray(x).reshape(()))


def summarize(result: Result, units: str = "si") -> list[Row]:
    """Rows describing one impact (a Result of size 1) in the ``units`` system ("si"/"us")."""
    if np.size(result.impulse_n) != 1:
        raise InputError("summarize needs a single case; index the Result first")
    rows: list[Row] = []
    barrier = bool(np.asarray(result.case.vehicle2.fixed).reshape(()))

    def pair(key, label, a, b, kind, movable_only=False):
        (ca, cb), unit = convert(np.array([_f(a), _f(b)]), kind, units)
        hide = movable_only and barrier
        rows.append(Row(key, label, float(ca), None if hide else float(cb), unit))

    def one(key, label, a, kind=None, unit=""):
        value = _f(a)
        if kind is not None:
            value, unit = convert(value, kind, units)
        rows.append(Row(key, label, float(value), None, unit, single=True))

    pair("velocity_x", "post-impact velocity x", result.velocity1[..., 0],
         result.velocity2[..., 0], "velocity")
    pair("velocity_y", "post-impact velocity y", result.velocity1[..., 1],
         result.velocity2[..., 1], "velocity")
    pair("speed", "post-impact speed", result.speed1, result.speed2, "speed")
    pair("yaw_rate", "post-impact yaw rate", result.yaw_rate1, result.yaw_rate2,
         "angular_velocity")
    pair("delta_v_x", "delta-V x", result.delta_v1[..., 0], result.delta_v2[..., 0], "velocity")
    pair("delta_v_y", "delta-V y", result.delta_v1[..., 1], result.delta_v2[..., 1], "velocity")
    pair("delta_v", "|delta-V|", result.delta_v1_magnitude, result.delta_v2_magnitude, "speed")
    # A fixed obstacle has no PDOF: it has no heading that a principal direction of force
    # could be measured from (its outline, if any, only places the drawing).
    pair("pdof", "PDOF (clockwise from heading)", result.pdof1, result.pdof2, "angle",
         movable_only=True)
    rows.append(Row("clock", "PDOF clock position", float(_f(result.clock1)),
                    None if barrier else float(_f(result.clock2)), "o'clock"))
    pair("impulse_x", "impulse on the vehicle, x", result.impulse[..., 0], -result.impulse[..., 0],
         "impulse")
    pair("impulse_y", "impulse on the vehicle, y", result.impulse[..., 1], -result.impulse[..., 1],
         "impulse")
    one("impulse_n", "normal impulse Pn", result.impulse_n, "impulse")
    one("impulse_t", "tangential impulse Pt", result.impulse_t, "impulse")
    one("impulse_angle", "impulse direction on vehicle 1 (from +x)", result.impulse_angle,
        "angle")
    one("eps", "restitution epsilon", result.eps)
    one("beta", "beta = mu / mu0", result.beta)
    one("mu0", "critical impulse ratio mu0", result.mu0)
    one("mu", "impulse ratio mu", result.mu)
    for key in ("A", "B", "C", "q", "r"):
        one(key, f"Brach {key}", getattr(result, key))
    one("restitution_check", "restitution check -V_crn/v_crn", result.restitution_check)
    one("ke_before", "kinetic energy before", result.kinetic_energy_before, "energy")
    one("ke_after", "kinetic energy after", result.kinetic_energy_after, "energy")
    one("energy_loss", "energy lost", result.energy_loss, "energy")
    one("energy_loss_percent", "energy lost", result.energy_loss_percent, unit="%")
    one("total_loss_brach", "Brach T_L", result.total_loss_brach, "energy")
    one("crush_normal", "normal crush energy", result.crush_energy_normal, "energy")
    one("crush_tangential", "tangential crush energy", result.crush_energy_tangential, "energy")
    one("tangential_share", "tangential share of the loss", 100 * result.tangential_share,
        unit="%")
    return rows


def format_table(rows: list[Row], title: str = "") -> str:
    """Plain-text table of rows: label, vehicle 1, vehicle 2, unit."""
    def num(x, single=False):
        return ("" if single else "-") if x is None else f"{x:.6g}"

    header = ("quantity", "vehicle 1", "vehicle 2", "unit")
    body = [(r.label, num(r.vehicle1), num(r.vehicle2, r.single), r.unit) for r in rows]
    widths = [max(len(line[i]) for line in [header, *body]) for i in range(4)]
    lines = [title] if title else []
    fmt = "{{:<{}}}  {{:>{}}}  {{:>{}}}  {{:<{}}}".format(*widths)
    lines.append(fmt.format(*header).rstrip())
    lines.append("  ".join("-" * w for w in widths))
    lines += [fmt.format(*line).rstrip() for line in body]
    return "\n".join(lines)


def rows_to_json(rows: list[Row]) -> dict:
    """Rows as a JSON-ready dict: key -> {vehicle1, vehicle2 or value, unit}."""
    out = {}
    for r in rows:
        if r.single:
            out[r.key] = {"value": r.vehicle1, "unit": r.unit}
        else:
            out[r.key] = {"vehicle1": r.vehicle1, "vehicle2": r.vehicle2, "unit": r.unit}
    return out


def table_title(name: str, result: Result, law: str = "brach") -> str:
    """The title of one impact's table: the case, the law and the parameters it used.

    Parameters
    ----------
    name : str
        The case's name.
    result : Result
        One impact under ``law``.
    law : {"brach", "brach-capped", "kudlich-slibar"}
        The law it was solved under: Kudlich-Slibar's k and mu_c with Brach's equivalent
        beta; Brach's epsilon and beta (the effective beta under the friction cap).

    Returns
    -------
    str
    """
    if law == "kudlich-slibar":
        return (f"{name}: Kudlich-Slibar law, k = {float(result.eps):g}, mu_c = "
                f"{float(result.contact_friction):g} (equivalent PIM beta = "
                f"{float(result.beta):g})")
    title = f"{name}: epsilon = {float(result.eps):g}, beta = {float(result.beta):g}"
    if law == "brach-capped":
        title += " (friction-capped Brach, effective beta)"
    return title
