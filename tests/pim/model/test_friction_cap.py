"""pim/model/friction_cap.py: the friction-capped impulse ratio (issue 12, item 3).

mu = sign(mu0) min(beta |mu0|, limit): the friction-capped Brach law ("brach-capped"), not
PC-Crash's law (that is Kudlich-Slibar: tests/pim/model/test_impact_laws.py)."""

import numpy as np
import pytest

import pim
from pim.model.friction_cap import capped_beta, solve_capped
from pim_cli.main import main


def test_friction_cap_formula():
    # mu = sign(mu0) min(beta |mu0|, limit), checked element by element.
    mu0 = np.array([3.0, -3.0, 0.2, 0.0])
    beta = np.array([1.0, 0.5, 1.0, 1.0])
    limit = 0.6
    b = capped_beta(mu0, beta, limit)
    expected = np.sign(mu0) * np.minimum(beta * np.abs(mu0), limit)
    np.testing.assert_allclose(b * mu0, expected)


def test_friction_capped_solve_caps_the_impulse_ratio():
    case = pim.load_case("hard-grazing")
    plain = pim.solve(case)
    assert abs(float(plain.mu)) > 1
    capped = solve_capped(case, limit=0.6)
    assert abs(float(capped.mu)) == pytest.approx(0.6)
    assert float(capped.impulse_t / capped.impulse_n) == pytest.approx(
        np.sign(float(plain.mu0)) * 0.6)
    # No cap below the limit: identical to plain PIM.
    ricsac = pim.load_case("ricsac9")
    assert float(solve_capped(ricsac, limit=10).mu) == pytest.approx(
        float(pim.solve(ricsac).mu))


def test_friction_limit_warns_and_grazing_is_flagged(capsys):
    assert main(["solve", "hard-grazing", "--friction-limit", "0.6"]) == 0
    err = capsys.readouterr().err
    assert "exceeds the friction limit 0.6" in err
    assert "implausible friction" in err
    assert main(["solve", "hard-grazing", "--friction-limit", "0.6", "--cap-friction"]) == 0
    captured = capsys.readouterr()
    assert "friction-capped" in captured.out and "exceeds" not in captured.err
    assert main(["solve", "ricsac9", "--cap-friction"]) == 2


def test_capped_beta_on_dual_numbers_is_one_sided_at_the_cap():
    """The same function serves the dual-number fit: below the cap d beta_eff = d beta,
    above it d(limit / |mu0|)."""
    from pim.model.dual import Dual

    mu0 = Dual(np.array([0.5, 0.5]), np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]))
    beta = Dual(np.array([0.4, 0.9]), np.array([[0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]))
    limit = Dual(np.array([0.3, 0.3]), np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]))
    out = capped_beta(mu0, beta, limit)
    np.testing.assert_allclose(out.value, capped_beta([0.5, 0.5], [0.4, 0.9], 0.3))
    np.testing.assert_allclose(out.grad[0], [0.0, 1.0, 0.0])                 # not capped
    np.testing.assert_allclose(out.grad[1], [-0.3 / 0.25, 0.0, 1 / 0.5])     # capped
