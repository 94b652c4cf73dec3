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


@pytest.mark.parametrize("beta", [1e308, 1e200, 1e154, 5.0])
def test_total_loss_stays_finite_for_any_finite_beta(beta):
    """`pim solve ricsac9 --beta 1e308` printed "Brach T_L -inf" with numpy's overflow
    warnings (issue 33 point 11): mu^2 overflowed although q mu stays finite. T_L equals the
    kinetic energy lost (from the velocities, another route) and warns of nothing."""
    import warnings

    import numpy as np

    case = pim.load_case("ricsac9")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = pim.solve(case, 0.355, beta)
        loss = float(r.total_loss_brach)
    assert np.isfinite(loss)
    assert loss == pytest.approx(float(r.energy_loss), rel=1e-9)
    assert not r.admissible or beta <= 1


def test_solve_with_a_huge_beta_prints_no_numpy_warning(capsys):
    from pim_cli.main import main

    assert main(["solve", "ricsac9", "--beta", "1e308"]) == 1       # inadmissible
    captured = capsys.readouterr()
    assert "RuntimeWarning" not in captured.err and "sheet_notation" not in captured.err
    (line,) = [x for x in captured.out.splitlines() if x.startswith("Brach T_L")]
    assert "inf" not in line and "nan" not in line
