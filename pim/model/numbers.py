"""Input checks shared by the model's types and functions: real numbers, never strings,
booleans, complex numbers or None read as numbers; and the one way a message prints a
speed, a length or a yaw rate in the user's units (:func:`unit_text`, :func:`speed_text`)."""

from __future__ import annotations

import difflib
import math
from contextlib import contextmanager
from contextvars import ContextVar

import numpy as np

__all__ = ["InputError", "ArgumentTypeError", "check_type", "did_you_mean", "real_array",
           "checked_number", "checked_count", "check_counts", "check_numbers", "speed_text",
           "speeds_in", "unit_text", "units_in", "message_units", "MESSAGE_KINDS"]


class InputError(ValueError):
    """Bad user input: a case file, an option or an argument outside what the model accepts.

    The message names the field (``vehicle1.mass``, ``--friction-limit``, ``samples``) and
    the allowed range. The command line turns this error, and only this one, into one line
    and exit code 2; any other exception is a bug and surfaces with its traceback. It is a
    ``ValueError``, so code that catches ``ValueError`` keeps working.
    """


class ArgumentTypeError(InputError, TypeError):
    """An argument of the wrong type (a string where a :class:`pim.Case` is expected): a
    ``TypeError``, as Python's own, and an :class:`InputError` (one line on the command
    line). The message names the argument and what it takes."""


def did_you_mean(word, choices) -> str:
    """``"; did you mean 'yaw_rate'?"`` for the choice closest to a mistyped ``word``
    (:func:`difflib.get_close_matches`, the units' suggestion), "" when none is close."""
    close = difflib.get_close_matches(str(word), list(choices), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def check_type(value, name: str, types, what: str, *, none: bool = False):
    """``value`` if it is an instance of ``types`` (or None with ``none``), else an
    :class:`ArgumentTypeError` naming ``name``, ``what`` it takes (e.g. "a pim.Case, e.g.
    pim.load_case('ricsac9')") and the type given (a string is quoted)."""
    if (value is None and none) or isinstance(value, types):
        return value
    got = repr(value) if isinstance(value, str) else f"a {type(value).__name__}"
    raise ArgumentTypeError(f"{name} must be {what}{' or None' if none else ''}, got {got}")


def real_array(value, name: str, unit: str = "-") -> np.ndarray:
    """``value`` as a float array, or an :class:`InputError` naming the field.

    Parameters
    ----------
    value : array_like
        A number or an array of numbers (int or float).
    name : str
        The field, for the message (e.g. ``"vehicle1.mass"``, ``"eps"``).
    unit : str
        Its unit, for the message (e.g. ``"kg"``).

    Raises
    ------
    InputError
        A string, bytes, boolean, None, complex or object value (``"1000"``, ``True``) or
        a ragged sequence.
    """
    if isinstance(value, str | bytes | bool | np.bool_) or value is None:
        raise InputError(f"{name} must be a number in [{unit}], got {value!r}")
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numbers in [{unit}] ({exc})") from None
    if arr.dtype.kind not in "fiu":
        raise InputError(f"{name} must be real numbers in [{unit}], got {arr.dtype} values")
    return arr.astype(float, copy=False)


def checked_number(value, name: str, *, low: float | None = None, high: float | None = None,
                   low_open: bool = False, unit: str = "-"):
    """``value`` as a finite float within [low, high] (or (low, high] with ``low_open``).

    The one check of a scalar numeric argument of the public API (``approach_tol``,
    ``friction_limit`` ...): an :class:`InputError` naming ``name``, its unit and range for
    a string, boolean, None, complex, NaN, inf or out-of-range value.
    """
    if type(value) is not float:        # the common case goes straight to the range check
        if isinstance(value, str | bytes | bool | np.bool_) or value is None or not isinstance(
                value, int | float | np.integer | np.floating):
            raise InputError(f"{name} must be a number [{unit}]{_range(low, high, low_open)}, "
                             f"got {value!r}")
        value = float(value)
    if not (math.isfinite(value) and (low is None or value > low or (value == low and not low_open))
            and (high is None or value <= high)):
        raise InputError(f"{name} must be a finite number [{unit}]"
                         f"{_range(low, high, low_open)}, got {value!r}")
    return value


def checked_count(value, name: str, *, low: int = 1, none: bool = False):
    """``value`` as an int >= ``low`` (None passes when ``none``): the one check of a
    count argument (``samples``, ``max_starts``, ``max_workers``, ``chunksize``, ``blocks``).

    Integral floats (``1e6``) are taken; strings, booleans, fractions and NaN are an
    :class:`InputError` naming ``name``.
    """
    if value is None and none:
        return None
    if isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_):
        number = int(value)
    elif isinstance(value, float | np.floating) and math.isfinite(value) and value == int(value):
        number = int(value)
    else:
        raise InputError(f"{name} must be an integer >= {low}"
                         f"{' or None' if none else ''}, got {value!r}")
    if number < low:
        raise InputError(f"{name} must be an integer >= {low}{' or None' if none else ''}, "
                         f"got {number}")
    return number


def check_counts(**counts) -> None:
    """:func:`checked_count` of each keyword (>= 1, None allowed: "the default"), for a
    one-line check at the top of a public function."""
    for name, value in counts.items():
        checked_count(value, name, none=True)


def _range(low, high, low_open: bool) -> str:
    if low is not None and high is not None:
        return f" in {'(' if low_open else '['}{low:g}, {high:g}]"
    if low is not None:
        return f" {'>' if low_open else '>='} {low:g}"
    return f" <= {high:g}" if high is not None else ""


def check_numbers(**values) -> None:
    """Each keyword None (the default) or finite real numbers (:func:`real_array`): a
    one-line check of optional numeric arguments such as ``eps`` and ``beta``."""
    for name, value in values.items():
        if value is not None and not np.isfinite(real_array(value, name)).all():
            raise InputError(f"{name} must be finite, got {value!r}")


#: Kinds of quantity a message prints in the user's units, with their SI (factor 1, label)
#: outside a :func:`units_in` block: speeds, lengths, yaw rates, yaw inertias.
MESSAGE_KINDS = {"speed": (1.0, "m/s"), "length": (1.0, "m"), "angular_velocity": (1.0, "rad/s"),
                 "inertia": (1.0, "kg m^2")}

_MESSAGE_UNITS: ContextVar[dict] = ContextVar("message_units", default=MESSAGE_KINDS)


def unit_text(value, kind: str, spec: str = ".4g") -> str:
    """A quantity [SI] of ``kind`` (a key of :data:`MESSAGE_KINDS`) as a message prints it:
    in the user's unit of that kind with its symbol.

    The model works in SI and does not convert; the command line chooses the units for the
    run with :func:`pim.io.units.messages_in` (the factors come from pint there). Outside
    such a block the quantity is printed in its SI unit.
    """
    factor, unit = _MESSAGE_UNITS.get()[kind]
    return f"{float(value) * factor:{spec}} {unit}"


def message_units() -> dict:
    """The units messages print now ({kind: (factor per SI unit, label)}, every kind of
    :data:`MESSAGE_KINDS`): what a worker process is handed to enter :func:`units_in` with,
    since a process does not inherit the block it was started from."""
    return dict(_MESSAGE_UNITS.get())


def speed_text(value, spec: str = ".4g") -> str:
    """A speed [m/s] as a message prints it (:func:`unit_text` of kind "speed")."""
    return unit_text(value, "speed", spec)


@contextmanager
def units_in(table: dict):
    """Within the block, :func:`unit_text` prints each kind of ``table`` ({kind: (factor per
    SI unit, label)}) as ``value * factor`` followed by the label; other kinds as before."""
    token = _MESSAGE_UNITS.set({**_MESSAGE_UNITS.get(), **table})
    try:
        yield
    finally:
        _MESSAGE_UNITS.reset(token)


def speeds_in(factor: float, unit: str):
    """Within the block, :func:`speed_text` prints ``value * factor`` followed by ``unit``."""
    return units_in({"speed": (float(factor), unit)})
