"""The table of common units (pim.model.unit_table) is pint's, name by name and in the
products the display units form; anything else is left to pint."""

import math

import pytest

from pim.io.units import DISPLAY_UNITS, DIMENSIONS, SI_UNITS, US_UNIT_NAMES, registry
from pim.model.unit_table import UNITS, unit_factor


def pint_factor(text: str) -> tuple[float, tuple]:
    """pint's factor of ``text`` to SI and its exponents of (m, kg, s, rad)."""
    ureg = registry()
    root = ureg.Quantity(1.0, text).to_root_units()
    items = dict(root.unit_items())
    base = {"meter": 0, "gram": 1, "second": 2, "radian": 3}
    exponents = [0, 0, 0, 0]
    for name, power in items.items():
        exponents[base[name]] += power
    factor = root.magnitude * 1e-3 ** exponents[1]       # pint's root mass unit is the gram
    return factor, tuple(exponents)


SI = {(1, 0, 0, 0): "m", (0, 1, 0, 0): "kg", (0, 0, 1, 0): "s", (0, 0, 0, 1): "rad",
      (1, 1, -2, 0): "N", (2, 1, -2, 0): "J", (1, 0, -1, 0): "m/s", (0, 0, -1, 1): "rad/s",
      (1, 0, -2, 0): "m/s**2", (0, 0, 0, 0): ""}


@pytest.mark.parametrize("name", sorted(UNITS))
def test_each_name_is_pints_unit_to_the_last_bit(name):
    factor, dims = pint_factor(name)
    ours = UNITS[name]
    assert ours[1] == dims
    assert ours[0] == registry().Quantity(1.0, name).to(SI[dims]).magnitude   # pint's float
    names = set(dict(registry().Quantity(1.0, name).unit_items()))
    assert ours[2] == bool(names & US_UNIT_NAMES)


TEXTS = sorted({u for system in DISPLAY_UNITS.values() for u in system.values()}
               | set(SI_UNITS.values()) | {u for u in DIMENSIONS.values() if u}
               | {"ft/s", "kg*m^2", "lb*ft**2", "lbf/ft", "N / m ** 2", "deg/s", "rad/s"})


@pytest.mark.parametrize("text", TEXTS)
def test_every_display_and_input_unit_is_read_as_pint_reads_it(text):
    known = unit_factor(text)
    assert known is not None, text
    factor, dims = pint_factor(text)
    assert known.factor == pytest.approx(factor, rel=1e-15) and known.dimension == dims


@pytest.mark.parametrize("text", ["N s", "(m/s)", "furlong", "1/s", "m**x", "kg*", "", "Hz"])
def test_anything_else_is_left_to_pint(text):
    assert unit_factor(text) is None


def test_powers_and_quotients_read_left_to_right():
    assert unit_factor("lbf/inch**2").factor == pytest.approx(6894.757293168361, rel=1e-15)
    assert unit_factor("km/h").factor == pytest.approx(1 / 3.6, rel=1e-15)
    assert unit_factor("deg/s").dimension == (0, 0, -1, 1)
    assert math.isclose(unit_factor("m/s/s").factor, 1.0)
    assert unit_factor("m/s/s").dimension == (1, 0, -2, 0)
