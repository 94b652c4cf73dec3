"""pim/model/case.py: case types validate their fields and transform the scene rigidly."""

import numpy as np
import pytest

import pim


def test_vehicle_rejects_bad_fields_by_name():
    for kwargs, words in (({"mass": 0.0}, "mass must be > 0"),
                          ({"yaw_inertia": -1.0}, "yaw_inertia must be > 0"),
                          ({"mass": np.inf}, "both be inf"),
                          ({"mass": "1000"}, "mass must be a number"),
                          ({"cg": (1.0,)}, "cg must be an \\[x, y\\] pair"),
                          ({"velocity": (np.nan, 0.0)}, "velocity must be finite"),
                          ({"yaw_rate": True}, "yaw_rate must be a number")):
        base = dict(mass=1000.0, yaw_inertia=1500.0, cg=(0.0, 0.0))
        with pytest.raises(ValueError, match=words):
            pim.Vehicle(**{**base, **kwargs})


def test_obstacle_and_case_shape():
    wall = pim.Vehicle.obstacle(cg=(1.0, 0.0))
    assert bool(wall.fixed) and wall.inverse_mass == 0.0
    car = pim.Vehicle(1000.0, 1500.0, (0.0, 0.0), (10.0, 0.0))
    case = pim.Case(car, wall, pim.Impact((0.5, 0.0), np.pi))
    assert case.is_scalar and case.shape == ()
    batch = pim.Case(pim.Vehicle(np.array([1e3, 2e3, 3e3]), 1500.0, (0.0, 0.0)), wall,
                     pim.Impact((0.5, 0.0), np.pi))
    assert not batch.is_scalar and batch.shape == (3,)
    with pytest.raises(ValueError, match="vehicle1"):
        pim.Case(wall, car, pim.Impact((0.5, 0.0), 0.0))
    with pytest.raises(ValueError, match="impact must be a pim.Impact"):
        pim.Case(car, wall, None)


def test_rotating_the_scene_rotates_the_answer():
    case = pim.load_case("ricsac9")
    turned = case.transformed(rotation=0.7, translation=(3.0, -2.0))
    a, b = pim.solve(case, 0.355, 1.0), pim.solve(turned, 0.355, 1.0)
    c, s = np.cos(0.7), np.sin(0.7)
    rot = np.array([[c, -s], [s, c]])
    np.testing.assert_allclose(b.velocity1, rot @ a.velocity1, atol=1e-12)
    assert float(b.yaw_rate2) == pytest.approx(float(a.yaw_rate2), abs=1e-12)
    swapped = pim.solve(case.swapped(), 0.355, 1.0)
    np.testing.assert_allclose(swapped.velocity1, a.velocity2, atol=1e-12)


def test_a_string_for_a_table_of_the_case_is_refused_naming_it():
    """Issue 28: pim.fit(Case(..., measured='x')) failed deep inside with an AttributeError."""
    from dataclasses import replace

    case = pim.load_case("ricsac9")
    with pytest.raises(TypeError, match=r"^measured must be a pim.Measured or None, got 'x'$"):
        pim.Case(case.vehicle1, case.vehicle2, case.impact, measured="x")
    for name, what in (("uncertainty", "a pim.model.distributions.UncertaintyTable"),
                       ("evidence", "a pim.model.evidence.Evidence"),
                       ("unknown", "a dict of dotted key -> (low, high) bounds")):
        with pytest.raises(pim.InputError) as info:
            replace(case, **{name: "x"})
        assert str(info.value) == f"{name} must be {what} or None, got 'x'"
