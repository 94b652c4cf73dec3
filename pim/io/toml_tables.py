"""Checks shared by the case file's table parsers: a table is a table, with known keys."""

from __future__ import annotations

from ..model.numbers import InputError

__all__ = ["check_keys"]


def check_keys(table, allowed, where: str) -> dict:
    """``table`` if it is a TOML table whose keys are all in ``allowed``.

    Raises
    ------
    InputError
        Not a table, or an unknown key: the message names ``where``, the first unknown key
        and the allowed ones (sorted).
    """
    if not isinstance(table, dict):
        raise InputError(f"{where} must be a table")
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise InputError(f"{where}: unknown key {unknown[0]!r} "
                         f"(allowed: {', '.join(sorted(allowed))})")
    return table
