"""pim/model/display.py: the display units and their factors, pint's without pint."""

import pytest

from pim.io.units import registry
from pim.model.display import (
    DISPLAY_UNITS,
    SI_UNITS,
    DisplayUnits,
    convert,
    display_factor,
    display_units,
)
from pim.model.numbers import InputError

PAIRS = sorted({(kind, unit) for units in DISPLAY_UNITS.values() for kind, unit in units.items()}
               | {("speed", s) for s in ("km/h", "mph", "m/s", "ft/s")})


@pytest.mark.parametrize("kind, unit", PAIRS)
def test_every_display_factor_is_pints(kind, unit):
    expected = registry().Quantity(1.0, SI_UNITS[kind]).to(unit).magnitude
    assert display_factor(kind, unit) == pytest.approx(expected, rel=4e-16)


def test_speeds_follow_the_system_or_the_chosen_unit():
    assert convert(10.0, "speed", "si")[1] == "km/h"
    value, unit = convert(0.44704, "speed", DisplayUnits("si", "mph"))
    assert unit == "mph" and value == pytest.approx(1.0, rel=1e-15)
    assert convert(1.0, "velocity", "si")[0] == 3.6            # as pint gives it, exactly
    assert display_units("us").speed == "mph"


def test_a_unit_of_another_dimension_is_refused():
    with pytest.raises(InputError, match="no display unit of speed"):
        display_factor("speed", "kg")
