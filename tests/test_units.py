"""pim/io/units.py: quantities parsed to SI and results presented in SI or US units.

Expected factors are exact definitions (1 ft = 0.3048 m, 1 lb = 0.45359237 kg,
standard gravity 9.80665 m/s^2, 1 mph = 0.44704 m/s), not pint's output.
"""

import math

import numpy as np
import pytest

from pim.io.units import convert, parse


@pytest.mark.parametrize("text, kind, si", [
    ("31.09 ft/s", "velocity", 31.09 * 0.3048),
    ("21.2 mph", "velocity", 21.2 * 0.44704),
    ("2255.4 lbf", "force", 2255.4 * 0.45359237 * 9.80665),
    ("90 deg", "angle", math.pi / 2),
    ("976 slug*ft**2", "inertia", 976 * 0.45359237 * 9.80665 / 0.3048 * 0.3048 ** 2),
    (12.5, "length", 12.5),
])
def test_parse_to_si(text, kind, si):
    assert parse(text, kind, "x") == pytest.approx(si, rel=1e-12)


def test_wrong_dimension_names_the_field():
    with pytest.raises(ValueError, match="vehicle1.mass"):
        parse("3 m/s", "mass", "vehicle1.mass")


def test_convert_to_us_and_si():
    value, unit = convert(np.array([1.0]), "speed", "us")
    assert unit == "ft/s" and value[0] == pytest.approx(1 / 0.3048)   # one speed unit
    value, unit = convert(1.0, "angular_velocity", "us")
    assert unit == "deg/s" and float(value) == pytest.approx(180 / math.pi)
    value, unit = convert(1000.0, "energy", "us")
    assert unit.replace(" ", "") in ("ft*lbf", "ftlbf", "ft·lbf") or "ft" in unit
    assert float(value) == pytest.approx(1000.0 / (0.3048 * 0.45359237 * 9.80665))
