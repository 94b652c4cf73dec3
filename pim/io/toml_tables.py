"""Checks shared by the case file's table parsers: a table is a table, with known keys."""

from __future__ import annotations

from ..model.numbers import InputError, did_you_mean

__all__ = ["check_keys", "unknown_key"]


def unknown_key(key: str, allowed, where: str) -> InputError:
    """The error of an unknown ``key`` in table ``where``: it names the key, the closest
    allowed one when one is close ("did you mean 'yaw_rate'?", :mod:`difflib`, as the units
    do) and the allowed ones (sorted)."""
    allowed = sorted(allowed)
    return InputError(f"{where}: unknown key {key!r}{did_you_mean(key, allowed)} (allowed: "
                      f"{', '.join(allowed)})")


def check_keys(table, allowed, where: str) -> dict:
    """``table`` if it is a TOML table whose keys are all in ``allowed``.

    Raises
    ------
    InputError
        Not a table, or an unknown key: the message names ``where``, the first unknown key,
        the closest allowed key when one is close, and the allowed ones (sorted).
    """
    if not isinstance(table, dict):
        raise InputError(f"{where} must be a table")
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise unknown_key(unknown[0], allowed, where)
    return table
