"""RICSAC collision 9: every value the design sheet prints, reproduced.

Source of the printed values: the PIM worksheet of RICSAC 9 (Brach & Brach 2011, Fig. 7.14),
transcribed in the project's spec (``ricsac9.md``, "Values the sheet prints"). The values are
copied here so the suite runs without the spec. Tolerance: relative 2e-3 for values printed
with 3-4 significant digits, as the spec recommends; tighter where the sheet prints more.
"""

import numpy as np
import pytest

import pim
from pim.io.brach import brach_arms
from pim.io.units import DisplayUnits, convert

#: The design sheet's units: US customary, velocities in ft/s.
SHEET = DisplayUnits("us", "ft/s")

# (quantity, printed value, relative tolerance) -- ricsac9.md, validation table.
EPS, BETA = 0.355, 1.0
CASE = pim.load_case("ricsac9")


def us(value, kind):
    if kind == "mph":
        from pim.io.units import registry

        return float(registry().Quantity(float(value), "m/s").to("mph").magnitude)
    return float(convert(value, kind, SHEET)[0])


@pytest.fixture(scope="module")
def result():
    return pim.solve(CASE, EPS, BETA)


def test_case_defaults_are_the_sheet_constraints():
    assert CASE.impact.restitution == EPS and CASE.impact.beta == BETA


@pytest.mark.parametrize("key, printed", [("d_a", 4.864), ("d_b", 2.775), ("d_c", 0.502),
                                          ("d_d", 4.774)])
def test_moment_arms(key, printed):
    # Sheet p. 3: d_a = 4.864, d_b = 2.775, d_c = 0.502, d_d = 4.774 ft.
    assert us(brach_arms(CASE)[key], "length") == pytest.approx(printed, abs=6e-4)


@pytest.mark.parametrize("name, printed, rel", [("A", 1.3, 2e-3), ("B", 0.282, 2e-3),
                                                ("C", 1.214, 2e-3), ("r", 1.0, 1e-12),
                                                ("mu0", 0.512, 2e-3), ("mu", 0.512, 2e-3),
                                                ("restitution_check", 0.355, 1e-12)])
def test_brach_coefficients(result, name, printed, rel):
    assert float(getattr(result, name)) == pytest.approx(printed, rel=rel)


@pytest.mark.parametrize("attr, kind, printed", [
    ("yaw_rate1", "angular_velocity", -199.702),
    ("yaw_rate2", "angular_velocity", 87.322),
    ("speed1", "mph", 9.669),      # the sheet prints speeds in mph
    ("speed2", "mph", 18.885),
    ("impulse_angle", "angle", 27.127),
])
def test_printed_scalars(result, attr, kind, printed):
    assert us(getattr(result, attr), kind) == pytest.approx(printed, rel=2e-3)


@pytest.mark.parametrize("attr, index, printed", [
    ("velocity1", 0, -6.126), ("velocity1", 1, 12.79),
    ("velocity2", 0, -11.498), ("velocity2", 1, 25.199),
])
def test_post_impact_velocities(result, attr, index, printed):
    assert us(getattr(result, attr)[index], "velocity") == pytest.approx(printed, rel=2e-3)


@pytest.mark.parametrize("index, printed", [(0, 1749.993), (1, 896.544)])
def test_impulse_on_vehicle_1(result, index, printed):
    assert us(result.impulse[index], "impulse") == pytest.approx(printed, rel=2e-3)


def test_initial_kinetic_energy(result):
    assert us(result.kinetic_energy_before, "energy") == pytest.approx(1.074e5, rel=2e-3)


def test_energy_at_plastic_sticking():
    # Sheet: at (0, 1) Delta KE = T_L = E_normal + E_tangential = 3.38e4 ft lb, 31.457 %.
    r = pim.solve(CASE, 0.0, 1.0)
    assert us(r.energy_loss, "energy") == pytest.approx(3.38e4, rel=2e-3)
    assert float(r.energy_loss_percent) == pytest.approx(31.457, rel=2e-3)
    assert us(r.total_loss_brach, "energy") == pytest.approx(3.38e4, rel=2e-3)
    crush = r.crush_energy_normal + r.crush_energy_tangential
    assert us(crush, "energy") == pytest.approx(3.38e4, rel=2e-3)
    # The closed form and the kinetic-energy difference are the same quantity.
    np.testing.assert_allclose(r.total_loss_brach, r.energy_loss, rtol=1e-12)
    np.testing.assert_allclose(crush, r.energy_loss, rtol=1e-12)


def test_normal_crush_at_half_half():
    # Sheet: E_NormalCrush(0.5, 0.5) = 1.412e4 ft lb.
    r = pim.solve(CASE, 0.5, 0.5)
    assert us(r.crush_energy_normal, "energy") == pytest.approx(1.412e4, rel=2e-3)


def test_pdof_definition_on_ricsac9(result):
    # The impulse on vehicle 1 points at 27.1 deg; vehicle 1 heads at 180 deg, so the force
    # comes from 207.1 deg: 27.1 deg to the left of straight ahead, 11 o'clock. Vehicle 2
    # (heading 90 deg) is pushed from 27.1 deg, 62.9 deg right of its nose: 2 o'clock.
    assert np.degrees(result.pdof1) == pytest.approx(-27.127, rel=2e-3)
    assert np.degrees(result.pdof2) == pytest.approx(62.873, rel=2e-3)
    assert int(result.clock1) == 11 and int(result.clock2) == 2


def test_brach_form_equals_global_form():
    brach = pim.load_case("ricsac9-brach")
    for a, b in ((CASE.vehicle1, brach.vehicle1), (CASE.vehicle2, brach.vehicle2)):
        np.testing.assert_allclose(a.cg, b.cg, atol=1e-8)
        np.testing.assert_allclose(np.cos(a.heading), np.cos(b.heading), atol=1e-12)
        np.testing.assert_allclose(np.sin(a.heading), np.sin(b.heading), atol=1e-12)
        for field in ("mass", "yaw_inertia", "velocity", "yaw_rate"):
            np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
    # The global file gives the CGs to 8 significant digits, hence 1e-7.
    ra, rb = pim.solve(CASE), pim.solve(brach)
    np.testing.assert_allclose(ra.velocity1, rb.velocity1, rtol=1e-7)
    np.testing.assert_allclose(ra.yaw_rate2, rb.yaw_rate2, rtol=1e-7)


def test_brach_adapter_places_the_cgs_of_the_spec():
    # ricsac9.md: with C at the origin, CG1 = (+4.774, +0.502) ft, CG2 = (-2.775, -4.864) ft.
    brach = pim.load_case("ricsac9-brach")
    np.testing.assert_allclose(convert(brach.vehicle1.cg, "length", "us")[0], [4.774, 0.502],
                               atol=6e-4)
    np.testing.assert_allclose(convert(brach.vehicle2.cg, "length", "us")[0], [-2.775, -4.864],
                               atol=6e-4)


def test_measured_values_are_loaded():
    m = CASE.measured
    np.testing.assert_allclose(convert(m.velocity1, "velocity", SHEET)[0], [-5.1, 17.6])
    np.testing.assert_allclose(convert(m.velocity2, "velocity", SHEET)[0], [-7.3, 20.2])
    assert us(m.yaw_rate1, "angular_velocity") == pytest.approx(-180)
    assert us(m.yaw_rate2, "angular_velocity") == pytest.approx(45)
