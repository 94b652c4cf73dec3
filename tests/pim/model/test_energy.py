"""pim/model/energy.py: kinetic energies, the loss and its crush split, against closed forms.

A central (collinear, frictionless) impact of two point masses is the textbook 1D collision:
loss = (1 - eps^2) m_c u^2 / 2, all of it normal crush.
"""

import numpy as np
import pytest

import pim


def _central(eps, m1=1200.0, m2=1800.0, u=14.0):
    big = 1e12   # point masses: no rotation
    v1 = pim.Vehicle(m1, m1 * big, (-2.0, 0.0), (u, 0.0), 0.0)
    v2 = pim.Vehicle(m2, m2 * big, (2.0, 0.0), (0.0, 0.0), 0.0)
    return pim.Case(v1, v2, pim.Impact((0.0, 0.0), np.pi)), m1 * m2 / (m1 + m2), u


@pytest.mark.parametrize("eps", [0.0, 0.3, 1.0])
def test_one_dimensional_collision(eps):
    case, mc, u = _central(eps)
    r = pim.solve(case, eps, 1.0)
    expected = 0.5 * (1 - eps ** 2) * mc * u ** 2
    assert float(r.energy_loss) == pytest.approx(expected, rel=1e-9, abs=1e-6)
    assert float(r.crush_energy_normal) == pytest.approx(expected, rel=1e-9, abs=1e-6)
    assert float(r.crush_energy_tangential) == pytest.approx(0.0, abs=1e-6)
    assert float(r.kinetic_energy_before) == pytest.approx(0.5 * 1200.0 * u ** 2)
    if expected:   # (eps = 1 loses nothing: its share of a zero loss is round-off)
        assert float(r.energy_loss_percent) == pytest.approx(
            100 * expected / float(r.kinetic_energy_before))
        assert float(r.tangential_share) == pytest.approx(0.0, abs=1e-12)


def test_sheet_energy_values():
    """RICSAC 9 design sheet (ricsac9.md): KE before 1.074e5 ft lb, at (0, 1) a loss of
    3.38e4 ft lb = 31.457 %, normal crush at (0.5, 0.5) 1.412e4 ft lb."""
    ftlb = 0.3048 * 0.45359237 * 9.80665
    case = pim.load_case("ricsac9")
    r = pim.solve(case, 0.0, 1.0)
    assert float(r.kinetic_energy_before) / ftlb == pytest.approx(1.074e5, rel=2e-3)
    assert float(r.energy_loss) / ftlb == pytest.approx(3.38e4, rel=2e-3)
    assert float(r.energy_loss_percent) == pytest.approx(31.457, rel=2e-3)
    half = pim.solve(case, 0.5, 0.5)
    assert float(half.crush_energy_normal) / ftlb == pytest.approx(1.412e4, rel=2e-3)


def test_kinetic_energies_from_the_definition():
    """EnergyOutputs (pim.model.energy) against 1/2 m v^2 + 1/2 I w^2 written out here."""
    from pim.model.energy import EnergyOutputs

    case = pim.load_case("ricsac9")
    r = pim.solve(case, 0.355, 1.0)
    assert isinstance(r, EnergyOutputs)

    def kinetic(m, i, v, w):
        return 0.5 * float(m) * float(np.dot(v, v)) + 0.5 * float(i) * float(w) ** 2

    a, b = case.vehicle1, case.vehicle2
    before = kinetic(a.mass, a.yaw_inertia, a.velocity, a.yaw_rate) + kinetic(
        b.mass, b.yaw_inertia, b.velocity, b.yaw_rate)
    after = kinetic(a.mass, a.yaw_inertia, r.velocity1, r.yaw_rate1) + kinetic(
        b.mass, b.yaw_inertia, r.velocity2, r.yaw_rate2)
    assert float(r.kinetic_energy_before) == pytest.approx(before, rel=1e-12)
    assert float(r.energy_loss) == pytest.approx(before - after, rel=1e-9)
