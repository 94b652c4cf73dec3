"""The [tyres] and [driver] tables of a case file (pim.io.tyre_table): units, defaults,
errors naming the field, and attachment to the evidence."""

import numpy as np
import pytest

from pim.io.tyre_table import attach_tyres, parse_driver, parse_tyres
from pim.model.evidence import Evidence, VehicleEvidence
from pim.model.tyres import SEDAN_TYRE


def _evidence():
    return Evidence(vehicle1=VehicleEvidence(np.zeros(2), 0.0, 2.7, 1.5, 1.2, 0.8))


def test_tyres_parse_units_and_defaults():
    tyres = parse_tyres({"vehicle1": {"cornering_stiffness": "1400 N/deg",
                                      "longitudinal_stiffness": ["150 kN"] * 2 + ["120 kN"] * 2,
                                      "buildup_time": "200 ms", "cg_height": "22 in"}})
    t = tyres["vehicle1"]
    assert t.cornering_stiffness == pytest.approx(1400 * 180 / np.pi)
    assert t.longitudinal_stiffness == (150e3, 150e3, 120e3, 120e3)
    assert t.buildup_time == pytest.approx(0.2) and t.cg_height == pytest.approx(0.5588)
    assert t.rolling_resistance == SEDAN_TYRE["rolling_resistance"]
    assert parse_tyres(None) == {}


@pytest.mark.parametrize("table, field", [
    ({"cornering_stiffness": "80 kN"}, "tyres.vehicle1.cornering_stiffness"),
    ({"cornering_stiffness": -5.0}, "tyres.vehicle1.cornering_stiffness"),
    ({"buildup_time": "0.2 m"}, "tyres.vehicle1.buildup_time"),
    ({"longitudinal_stiffness": [1, 2]}, "tyres.vehicle1.longitudinal_stiffness"),
    ({"stiffness": 1.0}, "stiffness"),
])
def test_bad_tyre_data_names_the_field(table, field):
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        parse_tyres({"vehicle1": table})


def test_driver_table_and_attachment():
    driver = parse_driver({"vehicle1": {"time": ["-0.5 s", "0 s", "1 s"],
                                        "steer": ["0 deg", "0 deg", "5 deg"],
                                        "brake": [0, 1, [1, 1, 0.5, 0.5]]}})["vehicle1"]
    assert driver.time.tolist() == [-0.5, 0.0, 1.0]
    assert driver.steer[-1] == pytest.approx(np.radians(5))
    assert driver.brake.tolist() == [[0] * 4, [1] * 4, [1, 1, 0.5, 0.5]]
    ev = attach_tyres(_evidence(), {"vehicle1": {}}, {"vehicle1": {"time": [0], "brake": [1]}})
    vehicle = ev.vehicle1.runout_vehicle(1500.0, 2500.0)
    assert vehicle.tyre_model == "brush" and vehicle.driver.brake.tolist() == [[1] * 4]
    assert attach_tyres(_evidence(), None, None).vehicle1.runout_vehicle(1, 1).tyre_model == (
        "coulomb")
    with pytest.raises(ValueError, match=r"tyres\.vehicle2 needs \[evidence\.vehicle2\]"):
        attach_tyres(_evidence(), {"vehicle2": {}}, None)
    with pytest.raises(ValueError, match=r"driver\.vehicle1: steer and brake"):
        parse_driver({"vehicle1": {"time": [0, 1], "steer": ["1 deg"]}})
    with pytest.raises(ValueError, match=r"driver\.vehicle1\.time"):
        parse_driver({"vehicle1": {"time": ["1 s", "0 s"]}})
