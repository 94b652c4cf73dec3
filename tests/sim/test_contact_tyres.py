"""Tyre forces during the contact: static load, free-rolling and locked wheels."""

import numpy as np
import pytest

from sim import contact_tyres as tyres

WHEELS = tyres.wheels_from_outline(4.5, 1.8)


def test_wheel_positions():
    assert WHEELS[0] == pytest.approx([0.5 * 0.6 * 4.5, 0.5 * 0.86 * 1.8])
    assert tyres.wheels_from_outline(None, None, 1.2)[0, 0] == pytest.approx(0.3 * 1.2 / 0.3)


def test_locked_wheels_sliding_straight_give_mu_m_g_backwards():
    load, mu = 1500 * 9.80665 / 4, 0.7
    f, m = tyres.tyre_force((20.0, 0.0), 0.0, 0.0, WHEELS, load, mu, "locked")
    assert f == pytest.approx([-mu * 4 * load * 20 / np.hypot(20, 0.05), 0.0], rel=1e-12)
    assert m == pytest.approx(0.0, abs=1e-9)


def test_free_rolling_wheels_resist_only_sideways_motion():
    load = 1000.0
    f, m = tyres.tyre_force((20.0, 0.0), 0.0, 0.0, WHEELS, load, 0.8, "rolling")
    assert np.abs(f).max() < 1e-9 and abs(m) < 1e-9          # rolling straight: nothing
    f, m = tyres.tyre_force((0.0, 5.0), 0.0, 0.0, WHEELS, load, 0.8, "rolling")
    assert f[1] == pytest.approx(-0.8 * 4 * load * 5 / np.hypot(5, 0.05))
    assert f[0] == pytest.approx(0.0, abs=1e-9)


def test_spinning_on_the_spot_is_resisted():
    f, m = tyres.tyre_force((0.0, 0.0), 2.0, 0.3, WHEELS, 1000.0, 0.7, "locked")
    assert np.abs(f).max() < 1e-6 and m < 0


def test_bad_mode():
    with pytest.raises(ValueError, match="mode"):
        tyres.tyre_force((1.0, 0.0), 0.0, 0.0, WHEELS, 1.0, 0.5, "drifting")


def test_wheels_are_centred_on_the_outline_not_the_cg():
    # 4.5 m car, CG 1.9 m behind the bumper: the 2.7 m wheelbase sits mid-outline, so both
    # overhangs are (4.5 - 2.7) / 2 = 0.9 m and the front axle is 1.9 - 0.9 = 1.0 m ahead
    wheels = tyres.wheels_from_outline(4.5, 1.8, cg_to_front=1.9)
    np.testing.assert_allclose(wheels[:, 0], [1.0, 1.0, -1.7, -1.7], atol=1e-12)
    loads = tyres.wheel_loads(1500.0, wheels, 9.81)
    # static axle loads: front carries m g b / L (b = 1.7 m CG to rear axle)
    np.testing.assert_allclose(loads, [1500 * 9.81 * 1.7 / 2.7 / 2] * 2
                               + [1500 * 9.81 * 1.0 / 2.7 / 2] * 2, rtol=1e-12)
    np.testing.assert_allclose(tyres.wheel_loads(1500.0, WHEELS, 9.81), 1500 * 9.81 / 4)


def test_cg_outside_the_axles_is_refused():
    with pytest.raises(ValueError, match="cg_to_front"):
        tyres.wheels_from_outline(4.5, 1.8, cg_to_front=0.5)


def test_locked_car_with_cg_forward_brakes_at_mu_m_g():
    wheels = tyres.wheels_from_outline(4.5, 1.8, cg_to_front=1.9)
    f, m = tyres.tyre_force((20.0, 0.0), 0.0, 0.0, wheels,
                            tyres.wheel_loads(1500.0, wheels, 9.81), 0.7, "locked")
    assert f[0] == pytest.approx(-0.7 * 1500 * 9.81 * 20 / np.hypot(20, 0.05), rel=1e-12)
    assert m == pytest.approx(0.0, abs=1e-9)
