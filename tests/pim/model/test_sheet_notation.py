"""pim/model/sheet_notation.py: Brach's A, B, C, r, mu0, q and T_L against the design sheet
(shared spec ricsac9.md: A, B, C = 1.3, 0.282, 1.214; r = 1; mu0(0.355) = 0.512; relative
2e-3 for the printed digits) and against their definitions."""

import pytest

import pim


@pytest.fixture(scope="module")
def result():
    return pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)


def test_printed_sheet_values(result):
    assert float(result.A) == pytest.approx(1.3, rel=2e-3)
    assert float(result.B) == pytest.approx(0.282, rel=2e-3)
    assert float(result.C) == pytest.approx(1.214, rel=2e-3)
    assert float(result.r) == pytest.approx(1.0, rel=2e-3)
    assert float(result.mu0) == pytest.approx(0.512, rel=2e-3)


def test_definitions(result):
    assert float(result.q) == pytest.approx(1 / (float(result.A) - float(result.mu)
                                                 * float(result.B)), rel=1e-12)
    assert float(result.mu) == pytest.approx(float(result.beta) * float(result.mu0))
    assert float(result.total_loss_brach) == pytest.approx(float(result.energy_loss), rel=1e-9)


def test_mu0_is_the_critical_impulse_ratio():
    """SheetNotation (pim.model.sheet_notation): mu0 = Pt0 / Pn0 (Brach eq. 6.60)."""
    from pim.model.sheet_notation import SheetNotation

    r = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    assert isinstance(r, SheetNotation)
    assert float(r.mu0) == pytest.approx(float(r.critical_impulse_t / r.critical_impulse_n),
                                         rel=1e-15)
