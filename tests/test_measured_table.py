"""The [measured] table of a case file: values and standard deviations (pim/io/measured_table)."""

from importlib import resources

import numpy as np
import pytest

import pim
from pim.io.measured_table import parse_measured

FT = 0.3048


def test_sigmas_in_units():
    m = parse_measured({"vehicle1": {"velocity": ["1 m/s", "2 m/s"],
                                     "velocity_sigma": ["1 ft/s", "0.3 m/s"],
                                     "yaw_rate": "10 deg/s", "yaw_rate_sigma": "5 deg/s"},
                        "vehicle2": {"velocity": [0, 1], "velocity_sigma": "0.5 m/s"}})
    np.testing.assert_allclose(m.velocity1_sigma, [FT, 0.3])
    np.testing.assert_allclose(m.velocity2_sigma, [0.5, 0.5])
    assert m.yaw_rate1_sigma == pytest.approx(np.radians(5))
    assert m.yaw_rate2_sigma is None


@pytest.mark.parametrize("table, words", [
    ({"vehicle1": {"velocity_sigma": "1 m/s"}}, ["velocity1_sigma", "not measured"]),
    ({"vehicle1": {"velocity": [1, 2], "velocity_sigma": "0 m/s"}}, ["velocity1_sigma", "> 0"]),
    ({"vehicle1": {"yaw_rate": 1, "yaw_rate_sigma": "-1 deg/s"}}, ["yaw_rate1_sigma", "> 0"]),
    ({"vehicle1": {"velocity": [1, 2], "velocity_sigma": ["1 m/s"]}},
     ["measured.vehicle1.velocity_sigma", "two values"]),
    ({"vehicle1": {"speed_sigma": 1}}, ["measured.vehicle1", "speed_sigma", "allowed"]),
])
def test_bad_sigmas_name_the_field(table, words):
    with pytest.raises(ValueError) as info:
        parse_measured(table)
    for w in words:
        assert w in str(info.value)


def test_case_file_with_sigmas_loads(tmp_path):
    text = (resources.files("pim.io") / "cases" / "ricsac9.toml").read_text()
    text = text.replace('vehicle1.yaw_rate = "-180 deg/s"',
                        'vehicle1.yaw_rate = "-180 deg/s"\nvehicle1.yaw_rate_sigma = "5 deg/s"')
    path = tmp_path / "c.toml"
    path.write_text(text)
    case = pim.load_case(path)
    assert case.measured.yaw_rate1_sigma == pytest.approx(np.radians(5))
