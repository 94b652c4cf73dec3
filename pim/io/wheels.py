"""Wheel states of a case file: a braking fraction per wheel, in words or numbers.

Both ``[evidence.vehicleN] wheels`` (the run-out) and ``[evidence.vehicleN.pre_impact]
braking`` (the marks before the impact) take one state for all four wheels or four states
(front-left, front-right, rear-left, rear-right), each ``"locked"`` (1), ``"free"`` or
``"free-rolling"`` (0) or a braking fraction in [0, 1] (:mod:`pim.model.tyres`).
"""

from __future__ import annotations

from ..model.numbers import InputError
from .units import parse

__all__ = ["WHEEL_WORDS", "braking_fraction", "wheel_fractions"]

#: The words a wheel state may be given as, and their braking fractions.
WHEEL_WORDS = {"locked": 1.0, "free": 0.0, "free-rolling": 0.0}


def braking_fraction(value, where: str) -> float:
    """One wheel's braking fraction [-] from a word of :data:`WHEEL_WORDS` or a number in
    [0, 1].

    Raises
    ------
    InputError
        Another word, a malformed number or a fraction outside [0, 1], naming ``where``.
    """
    if isinstance(value, str) and value.strip() in WHEEL_WORDS:
        return WHEEL_WORDS[value.strip()]
    if isinstance(value, str) and not any(c.isdigit() for c in value):
        raise InputError(f"{where} must be 'locked', 'free' or a braking fraction in [0, 1], "
                         f"got {value!r}")
    fraction = parse(value, "dimensionless", where)
    if not 0 <= fraction <= 1:
        raise InputError(f"{where} must be a braking fraction in [0, 1] (1 locked, 0 "
                         f"free-rolling), got {value!r}")
    return fraction


def wheel_fractions(value, where: str) -> tuple:
    """Four braking fractions (front-left, front-right, rear-left, rear-right) from one state
    for all wheels or a list of four (:func:`braking_fraction` each)."""
    if not isinstance(value, list):
        return (braking_fraction(value, where),) * 4
    if len(value) != 4:
        raise InputError(f"{where} must be one state or four (front-left, front-right, "
                         f"rear-left, rear-right), got {value!r}")
    return tuple(braking_fraction(v, f"{where}[{i}]") for i, v in enumerate(value))
