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
                        "vehicle2": {"velocity": [0, "1 m/s"], "velocity_sigma": "0.5 m/s"}})
    np.testing.assert_allclose(m.velocity1_sigma, [FT, 0.3])
    np.testing.assert_allclose(m.velocity2_sigma, [0.5, 0.5])
    assert m.yaw_rate1_sigma == pytest.approx(np.radians(5))
    assert m.yaw_rate2_sigma is None


@pytest.mark.parametrize("table, words", [
    ({"vehicle1": {"velocity_sigma": "1 m/s"}}, ["velocity1_sigma", "not measured"]),
    ({"vehicle1": {"velocity": ["1 m/s", "2 m/s"], "velocity_sigma": "0 m/s"}},
     ["measured.vehicle1.velocity_sigma", "> 0", "'0 m/s'"]),
    ({"vehicle1": {"yaw_rate": "1 rad/s", "yaw_rate_sigma": "-1 deg/s"}},     # as written, not rad/s
     ["measured.vehicle1.yaw_rate_sigma", "> 0", "'-1 deg/s'"]),
    ({"vehicle1": {"velocity": ["1 m/s", "2 m/s"], "velocity_sigma": ["1 m/s"]}},
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


# --- recorder and energy evidence (issue 19) -------------------------------------------

def test_recorder_and_energy_fields_parse_in_si():
    from pim.io.measured_table import parse_measured

    m = parse_measured({"vehicle1": {"delta_v": ["-36 km/h", "3.6 km/h"],
                                     "delta_v_sigma": "3.6 km/h"},
                        "vehicle2": {"pre_crash_speed": "72 km/h",
                                     "pre_crash_speed_sigma": "1 m/s"},
                        "energy_loss": "95 kJ", "energy_loss_sigma": "10 kJ"})
    assert list(m.delta_v1) == [-10.0, 1.0] and list(m.delta_v1_sigma) == [1.0, 1.0]
    assert (m.pre_crash_speed2, m.energy_loss, m.energy_loss_sigma) == (20.0, 95e3, 10e3)


@pytest.mark.parametrize("table, words", [
    ({"vehicle1": {"delta_v": ["-9 m/s", "1 m/s"], "delta_v_sigma": "0 m/s"}},
     r"measured.vehicle1.delta_v_sigma must be > 0, got '0 m/s'"),
    ({"vehicle1": {"delta_v": ["-9 m/s", "1 m/s"], "delta_v_sigma": "-1 m/s"}},
     r"vehicle1.delta_v_sigma must be > 0, got '-1 m/s'"),
    ({"vehicle1": {"delta_v": ["-9 m/s", "1 m/s"]}}, r"vehicle1.delta_v_sigma is required"),
    ({"energy_loss": "0 kJ", "energy_loss_sigma": "1 kJ"}, r"energy_loss must be > 0"),
    ({"energy_loss": "-5 kJ", "energy_loss_sigma": "1 kJ"}, r"energy_loss must be > 0"),
    ({"energy_loss": "50 kJ", "energy_loss_sigma": "0 kJ"}, r"energy_loss_sigma must be"),
    ({"vehicle2": {"pre_crash_speed": "-3 mph", "pre_crash_speed_sigma": "1 mph"}},
     r"vehicle2.pre_crash_speed must be >= 0 \(a speed\), got '-3 mph'"),
    ({"vehicle1": {"delta_v": "-9 m/s", "delta_v_sigma": "1 m/s"}}, r"vehicle1.delta_v must "
                                                                    r"be a list of two"),
    ({"energy_loss": "50 m/s", "energy_loss_sigma": "1 kJ"}, r"measured.energy_loss")])
def test_bad_recorder_or_energy_evidence_names_the_field(table, words):
    """Each fails on the code before issue 19 too (an unknown key then)."""
    from pim.io.measured_table import parse_measured

    with pytest.raises(ValueError, match=words):
        parse_measured(table)
