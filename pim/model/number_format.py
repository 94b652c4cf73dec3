"""The one number format of every report: significant digits, digits matched to an
interval, round-off shown as 0.

Pure functions of numbers (no units: the caller converts first). A number is written in
fixed point between 1e-3 and 1e6 and in scientific notation outside, never as ``0.0000``;
a value with a 5-95 % interval gets the decimals that show two significant digits of the
interval's half-width, and its interval the same decimals, so that ``28.0467 ft/s`` with an
interval from 24.81 to 31.27 reads ``28.0 (24.8 to 31.3)``. A number smaller than a
round-off fraction of the scale of its quantity (a tangential crush energy of 4.96e-16 kJ
beside a kinetic energy of 100 kJ) is 0.
"""

from __future__ import annotations

import math
from decimal import ROUND_HALF_EVEN, Decimal

__all__ = ["format_number", "interval_decimals", "format_interval", "round_off",
           "duration_text", "SIGNIFICANT", "ROUND_OFF"]

#: Significant digits of a number that carries no interval.
SIGNIFICANT = 4
#: A value below this fraction of its quantity's scale is round-off, shown as 0.
ROUND_OFF = 1e-10
#: Fixed-point notation for magnitudes in [FIXED_LOW, FIXED_HIGH); scientific outside.
FIXED_LOW, FIXED_HIGH = 1e-3, 1e6


def _exponent(x: float) -> int:
    """The power of ten of the leading digit of ``x`` (x != 0)."""
    return math.floor(math.log10(abs(x)))


def _blank(x) -> bool:
    return x is None or (isinstance(x, float) and math.isnan(x))


def _fixed(x: float, decimals: int) -> str:
    """``x`` rounded to ``decimals`` decimal places (negative: to tens, hundreds ...),
    half to even, in fixed point; never "-0"."""
    quantum = Decimal(1).scaleb(-decimals)
    text = f"{Decimal(repr(float(x))).quantize(quantum, rounding=ROUND_HALF_EVEN):f}"
    if decimals < 0:
        text = str(int(Decimal(text)))
    return "0" if float(text) == 0 else text


def _scientific(x: float, digits: int) -> str:
    """``x`` with ``digits`` significant digits in scientific notation (1.2e-07)."""
    return f"{x:.{max(digits - 1, 0)}e}"


def format_number(x, sig: int = SIGNIFICANT, decimals: int | None = None) -> str:
    """A number as every report writes it.

    Parameters
    ----------
    x : float, int, bool, str or None
        The value; text is returned as it is, None and NaN as "", a bool as yes/no, an int
        in full.
    sig : int
        Significant digits when ``decimals`` is None; trailing zeros are dropped (they are
        not known to be significant).
    decimals : int, optional
        Decimal places (negative rounds to tens, hundreds ...), e.g. from
        :func:`interval_decimals`; trailing zeros are kept (they are significant).

    Returns
    -------
    str
        Fixed point for magnitudes in [1e-3, 1e6), scientific notation outside (with as
        many significant digits); 0 as "0".

    Examples
    --------
    >>> format_number(31485.5), format_number(31485.5, decimals=-2)
    ('31490', '31500')
    >>> format_number(6.09e-05), format_number(1.0), format_number(28.0467, decimals=1)
    ('6.09e-05', '1', '28.0')
    """
    if _blank(x):
        return ""
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, str):
        return x
    x = float(x)
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    if x == 0:
        return "0"
    e = _exponent(x)
    if decimals is None:
        decimals = sig - 1 - e
        if not FIXED_LOW <= abs(x) < FIXED_HIGH:
            mantissa, exponent = _scientific(x, sig).split("e")
            return (mantissa.rstrip("0").rstrip(".") if "." in mantissa else mantissa) \
                + "e" + exponent
        text = _fixed(x, decimals)
        return text.rstrip("0").rstrip(".") if "." in text else text
    if not FIXED_LOW <= abs(x) < FIXED_HIGH:
        return _scientific(x, e + decimals + 1)
    return _fixed(x, decimals)


def interval_decimals(low: float, high: float, sig: int = 2) -> int | None:
    """The decimal places that show ``sig`` significant digits of the half-width of the
    interval [low, high]; None when the interval is empty, zero-width or not finite.

    Examples
    --------
    >>> interval_decimals(24.81, 31.27), interval_decimals(27450.0, 35810.0)
    (1, -2)
    """
    if _blank(low) or _blank(high):
        return None
    half = (float(high) - float(low)) / 2
    if not math.isfinite(half) or half <= 0:
        return None
    return sig - 1 - _exponent(half)


def format_interval(value: float, low: float, high: float,
                    sig: int = 2) -> tuple[str, str, str]:
    """``value`` and its interval [low, high] with the same decimals: those that show
    ``sig`` significant digits of the half-width (:func:`interval_decimals`); without a
    usable interval the value with :data:`SIGNIFICANT` digits and two empty strings.

    Examples
    --------
    >>> format_interval(28.0467, 24.81, 31.27)
    ('28.0', '24.8', '31.3')
    >>> format_interval(31485.5, 27450.0, 35810.0)
    ('31500', '27400', '35800')
    """
    decimals = interval_decimals(low, high, sig)
    if decimals is None:
        return format_number(value), "", ""
    return (format_number(value, decimals=decimals), format_number(low, decimals=decimals),
            format_number(high, decimals=decimals))


def round_off(x: float, scale: float, rtol: float = ROUND_OFF) -> float:
    """``x``, or 0.0 when ``|x|`` is below ``rtol`` times ``scale`` (the size of the
    quantity it belongs to: the kinetic energy for an energy, the closing speed for a
    velocity): what floating-point round-off leaves where the exact answer is 0.

    Examples
    --------
    >>> round_off(4.96e-16, 92.3), round_off(13.9, 92.3)
    (0.0, 13.9)
    """
    if _blank(x) or _blank(scale) or not math.isfinite(scale):
        return x
    return 0.0 if abs(x) < rtol * abs(scale) else x


def duration_text(seconds: float) -> str:
    """A duration in the unit a reader takes in at once: seconds below 2 min, minutes below
    2 h, else hours.

    Examples
    --------
    >>> duration_text(95), duration_text(600), duration_text(9000)
    ('95 s', '10 min', '2.5 h')
    """
    return f"{seconds:.0f} s" if seconds < 120 else (
        f"{seconds / 60:.0f} min" if seconds < 7200 else f"{seconds / 3600:.1f} h")
