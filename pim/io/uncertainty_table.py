"""The ``[uncertainty]`` table of a case file, parsed into :class:`UncertaintyTable` (SI).

See :mod:`pim.model.distributions` for the inputs, the distribution kinds and sampling.
"""

from __future__ import annotations

from ..model.distributions import KINDS, Distribution, UncertaintyTable
from ..model.numbers import InputError, did_you_mean
from ..model.quantities import UNCERTAIN
from .priors import prior_distribution
from .toml_tables import unknown_key
from .units import parse

__all__ = ["parse_uncertainty"]


def _parse_one(name: str, spec) -> Distribution:
    where = f"uncertainty.{name}"
    kind_of = UNCERTAIN[name].kind
    if not isinstance(spec, dict):
        raise InputError(f"{where} must be a table such as {{normal = ...}}, "
                         f"{{uniform = [low, high]}}, {{plusminus = ...}}, {{fixed = ...}} "
                         "or {{prior = \"name\"}}")
    kinds = [k for k in spec if k in KINDS]
    unknown = sorted(set(spec) - set(KINDS) - {"mean"})
    if unknown:
        raise unknown_key(unknown[0], (*KINDS, "mean"), where)
    if len(kinds) != 1:
        raise InputError(f"{where}: give exactly one of {', '.join(KINDS)}")
    kind = kinds[0]
    if kind == "prior":
        if len(spec) != 1:
            raise InputError(f"{where}: a prior takes no other key")
        return prior_distribution(spec["prior"], name)
    if "mean" in spec and kind != "normal":
        raise InputError(f"{where}.mean: only a normal distribution takes a mean")
    value = spec[kind]
    if kind == "uniform":
        if not isinstance(value, list) or len(value) != 2:
            raise InputError(f"{where}.uniform must be [low, high], got {value!r}")
        low = parse(value[0], kind_of, f"{where}.uniform[0]")
        high = parse(value[1], kind_of, f"{where}.uniform[1]")
        if not low <= high:
            raise InputError(f"{where}.uniform: low {low:g} must be <= high {high:g}")
        return Distribution("uniform", low, high)
    number = parse(value, kind_of, f"{where}.{kind}")
    if kind == "fixed":
        return Distribution("fixed", number)
    if number < 0:
        raise InputError(f"{where}.{kind} must be >= 0 (a spread), got {number:g}")
    if kind == "plusminus":
        return Distribution("plusminus", None, number)
    mean = parse(spec["mean"], kind_of, f"{where}.mean") if "mean" in spec else None
    return Distribution("normal", mean, number)


def parse_uncertainty(table) -> UncertaintyTable | None:
    """Parse the ``[uncertainty]`` table of a case file (already read by tomllib).

    Raises
    ------
    ValueError
        Unknown input or key, bad unit or dimension, or bounds in the wrong order.
    """
    if table is None:
        return None
    if not isinstance(table, dict):
        raise InputError("uncertainty must be a table")
    flat = {}
    groups = [(g, e) for g, e in table.items() if g not in ("evidence", "measured")]
    for top, example in (("evidence", "evidence.vehicle1.friction = {plusminus = 0.1}"),
                         ("measured", "measured.vehicle1.delta_v_scale = "
                                      "{uniform = [0.88, 1.0]}")):
        nested = table.get(top)
        if nested is None:
            continue
        if not isinstance(nested, dict) or not all(isinstance(e, dict)
                                                    for e in nested.values()):
            raise InputError(f"uncertainty.{top} must hold vehicle1 / vehicle2 tables, e.g. "
                             f"{example}")
        for g, e in nested.items():       # and the evidence's marks before the impact
            e = dict(e)
            marks = e.pop("pre_impact", None) if top == "evidence" else None
            groups += [(f"{top}.{g}", e)] + ([] if marks is None else
                                              [(f"{top}.{g}.pre_impact", marks)])
    for group, entries in groups:
        if group.split(".")[0] not in ("vehicle1", "vehicle2", "impact", "evidence",
                                       "measured") or \
                not isinstance(entries, dict):
            raise InputError(f"uncertainty: unknown input {group!r} (use vehicle1.<input>, "
                             f"vehicle2.<input>, impact.<input>, evidence.vehicleN.friction or "
                             f"evidence.vehicleN.pre_impact.friction / .skid_length; "
                             f"allowed: {', '.join(UNCERTAIN)})")
        if group.startswith("evidence.") and isinstance(entries.get("crush"), dict):
            entries = {**{k: v for k, v in entries.items() if k != "crush"},
                       **{f"crush.{k}": v for k, v in entries["crush"].items()}}
        for key, spec in entries.items():
            name = f"{group}.{key}"
            if name not in UNCERTAIN:
                raise InputError(f"uncertainty: unknown input {name!r}"
                                 f"{did_you_mean(name, UNCERTAIN)} (allowed: "
                                 f"{', '.join(UNCERTAIN)})")
            flat[name] = _parse_one(name, spec)
    return UncertaintyTable(flat)
