"""Input checks shared by the model's types and functions: real numbers, never strings,
booleans, complex numbers or None read as numbers."""

from __future__ import annotations

import numpy as np

__all__ = ["InputError", "real_array"]


class InputError(ValueError):
    """Bad user input: a case file, an option or an argument outside what the model accepts.

    The message names the field (``vehicle1.mass``, ``--friction-limit``, ``samples``) and
    the allowed range. The command line turns this error, and only this one, into one line
    and exit code 2; any other exception is a bug and surfaces with its traceback. It is a
    ``ValueError``, so code that catches ``ValueError`` keeps working.
    """


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
