"""pim/model/result.py and its mixins: read-only results, lazy fields, energy at any mass ratio."""

import pickle

import numpy as np
import pytest

import pim


@pytest.fixture()
def ricsac9():
    return pim.load_case("ricsac9")


def test_result_is_read_only(ricsac9):
    r = pim.solve(ricsac9, 0.355, 1.0)
    with pytest.raises(AttributeError, match="read-only"):
        r.velocity1 = np.zeros(2)
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        _ = r.nonsense


def test_scalar_fields_become_arrays_when_read(ricsac9):
    r = pim.solve(ricsac9, 0.355, 1.0)
    assert r.backend == "python" and "velocity1" not in r.__dict__
    assert isinstance(r.velocity1, np.ndarray) and r.velocity1.shape == (2,)
    assert r.approaching.dtype == bool and r.yaw_rate1.shape == ()


def test_results_pickle_with_every_field(ricsac9):
    for backend in ("auto", "numpy"):
        r = pim.solve(ricsac9, 0.355, 0.7, backend=backend)
        back = pickle.loads(pickle.dumps(r))
        assert type(back) is pim.Result
        for name in ("velocity1", "k_nt", "approaching", "energy_loss", "pdof2"):
            np.testing.assert_array_equal(getattr(back, name), getattr(r, name))


@pytest.mark.parametrize("ratio", [1e-12, 1e12])
def test_energy_loss_holds_at_extreme_mass_ratios(ratio):
    """A point mass on a body 1e12 times heavier (or lighter): the loss must equal the closed
    form for a 1D impact, (1 - eps^2) m_c u^2 / 2, with m_c the reduced mass. The difference
    of the kinetic energies loses it to round-off; the impulse form does not."""
    m1, m2, u, eps = 1000.0, 1000.0 * ratio, 10.0, 0.3
    big = 1e30   # inertia: a point mass (no rotation)
    v1 = pim.Vehicle(m1, m1 * big, (-1.0, 0.0), (u, 0.0), 0.0)
    v2 = pim.Vehicle(m2, m2 * big, (1.0, 0.0), (0.0, 0.0), 0.0)
    case = pim.Case(v1, v2, pim.Impact((0.0, 0.0), np.pi))   # n from 2 toward 1: -x
    r = pim.solve(case, eps, 0.0)
    mc = m1 * m2 / (m1 + m2)
    expected = 0.5 * (1 - eps ** 2) * mc * u ** 2
    assert float(r.energy_loss) == pytest.approx(expected, rel=1e-9)
    assert float(r.total_loss_brach) == pytest.approx(expected, rel=1e-9)


def test_sheet_notation_mixin_against_the_sheet(ricsac9):
    """RICSAC 9 design sheet (shared spec ricsac9.md): mu0(0.355) = 0.512."""
    r = pim.solve(ricsac9, 0.355, 1.0)
    assert float(r.mu0) == pytest.approx(0.512, abs=5e-4)
    assert float(r.q) == pytest.approx(1.0 / (float(r.A) - float(r.mu) * float(r.B)))
