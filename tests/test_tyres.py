"""Tyre forces during the contact: static load, free-rolling and locked wheels."""

import numpy as np
import pytest

from sim import tyres

WHEELS = tyres.wheel_positions(4.5, 1.8)


def test_wheel_positions():
    assert WHEELS[0] == pytest.approx([0.5 * 0.6 * 4.5, 0.5 * 0.86 * 1.8])
    assert tyres.wheel_positions(None, None, 1.2)[0, 0] == pytest.approx(0.3 * 1.2 / 0.3)


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
