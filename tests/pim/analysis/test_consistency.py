"""Momentum consistency of measured data (pim.analysis.consistency)."""

import pytest

from pim.analysis.consistency import CrashTestVehicle, check_ricsac, momentum_check
from pim.io.datasets import load_ricsac


def test_ricsac_inconsistent_tests_flagged():
    """The five tests the issue names (1, 4, 7, 8, 12) have m1 dV1 / (m2 dV2) off by 15.7 to
    38.6 % with the Brach & Smith (2002) corrected delta-Vs; test 5 sits at 15.4 %, just over
    the 15 % default (0.2 % from the table's rounding)."""
    checks = {c.test: c for c in check_ricsac(load_ricsac())}
    ratio = {int(t.split()[1]): c.impulse_ratio for t, c in checks.items()}
    assert {n for n, r in ratio.items() if abs(r) > 0.155} == {1, 4, 7, 8, 12}
    assert ratio[8] == pytest.approx(2031 * 6.97 / (2136 * 4.78) - 1)
    assert 0.15 < ratio[5] < 0.155
    for n in (1, 4, 7, 8, 12):
        assert checks[f"RICSAC {n}"].flagged
    for n in (3, 6, 11):
        assert not checks[f"RICSAC {n}"].flagged, checks[f"RICSAC {n}"].reasons
    assert "RICSAC 2" not in checks     # no data


def test_balanced_data_pass_and_imbalance_is_measured():
    # equal and opposite impulses: balanced
    c = momentum_check(
        "x", CrashTestVehicle(1000.0, delta_v=8.06, velocity_pre=(10, 0), velocity_post=(2, 1),
                              yaw_inertia=2000.0, yaw_rate_change=1.0),
        CrashTestVehicle(2000.0, delta_v=4.03, velocity_pre=(0, 0), velocity_post=(4, -0.5)))
    assert c.linear_imbalance == pytest.approx(0.0, abs=1e-12)
    assert c.impulse_ratio == pytest.approx(0.0, abs=1e-3)
    assert c.arm1 == pytest.approx(2000.0 / (1000 * 8.0622577), rel=1e-6)
    assert not c.flagged
    # 20 % more impulse on vehicle 2
    c = momentum_check("y", CrashTestVehicle(1000.0, velocity_pre=(10, 0), velocity_post=(0, 0)),
                       CrashTestVehicle(2000.0, velocity_pre=(0, 0), velocity_post=(6, 0)))
    assert c.linear_imbalance == pytest.approx(2000.0 / 12000.0)
    assert c.flagged and "linear momentum" in c.reasons[0]
    # an arm longer than a car
    c = momentum_check("z", CrashTestVehicle(1000.0, velocity_pre=(1, 0), velocity_post=(0, 0)),
                       CrashTestVehicle(1000.0, velocity_pre=(0, 0), velocity_post=(1, 0),
                                        yaw_inertia=2500.0, yaw_rate_change=2.0))
    assert c.arm2 == pytest.approx(5.0) and c.flagged


def test_bad_mass():
    with pytest.raises(ValueError, match="masses must be > 0"):
        momentum_check("x", CrashTestVehicle(0.0), CrashTestVehicle(1.0))
