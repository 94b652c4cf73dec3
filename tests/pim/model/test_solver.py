"""pim/model/solver.py: the three paths of pim.solve, tolerances as arguments, bad input.

The scalar path (plain floats) and the numpy path evaluate the same formula, so they must
agree bitwise on every core field; the kernel is tested in tests/pim/model/test_kernel.py.
"""

import numpy as np
import pytest

import pim
from pim.model.result import CORE_FIELDS
from tests.scenes import random_cases


def _element(case, i):
    v = []
    for veh in (case.vehicle1, case.vehicle2):
        v.append(pim.Vehicle(float(veh.mass[i]), float(veh.yaw_inertia[i]),
                             tuple(veh.cg[i].tolist()), tuple(veh.velocity[i].tolist()),
                             float(veh.yaw_rate[i]), float(veh.heading[i])))
    imp = pim.Impact(tuple(case.impact.point[i].tolist()), float(case.impact.normal_angle[i]))
    return pim.Case(v[0], v[1], imp)


@pytest.mark.parametrize("fixed", [False, True])
def test_scalar_path_equals_numpy_path_bitwise(fixed):
    batch = random_cases(300, seed=31, fixed=fixed)
    eps = np.random.default_rng(31).uniform(0, 1, 300)
    ref = pim.solve(batch, eps, 0.6, backend="numpy")
    for i in range(300):
        one = pim.solve(_element(batch, i), float(eps[i]), 0.6)
        assert one.backend == "python"
        for name in CORE_FIELDS:
            assert np.array_equal(getattr(one, name), getattr(ref, name)[i], equal_nan=True), name
        assert np.array_equal(one.energy_loss, ref.energy_loss[i], equal_nan=True)


def test_tolerances_are_arguments():
    """A grazing approach u_n = -1e-10 |u|: an impact at the default tolerance, none at 1e-9."""
    v1 = pim.Vehicle(1000.0, 1500.0, (-1.0, 0.0), (-1e-10, 1.0), 0.0)
    v2 = pim.Vehicle(1000.0, 1500.0, (1.0, 0.0), (0.0, 0.0), 0.0)
    case = pim.Case(v1, v2, pim.Impact((0.0, 0.0), 0.0))
    assert bool(pim.solve(case, 0.3, 1.0).approaching)
    assert not bool(pim.solve(case, 0.3, 1.0, approach_tol=1e-9).approaching)
    for backend in ("numpy", "numba"):
        assert not bool(pim.solve(case, 0.3, 1.0, backend=backend,
                                  approach_tol=1e-9).approaching)
        assert bool(pim.solve(case, 0.3, 1.0, backend=backend).approaching)


@pytest.mark.parametrize("bad", ["0.3", True, 0.3 + 0j, None, [0.3, "x"], np.array([1j])])
def test_eps_must_be_real_numbers(bad):
    case = pim.load_case("ricsac9")
    if bad is None:   # None means "the case's default", which ricsac9 has
        case = pim.Case(case.vehicle1, case.vehicle2, pim.Impact(case.impact.point, 0.0))
    with pytest.raises(ValueError, match="eps"):
        pim.solve(case, bad, 1.0)


@pytest.mark.parametrize("bad", ["1", False, 1j])
def test_beta_must_be_a_real_number(bad):
    with pytest.raises(ValueError, match="beta"):
        pim.solve(pim.load_case("ricsac9"), 0.3, bad)


def test_solve_needs_a_case():
    with pytest.raises(ValueError, match="case must be a pim.Case"):
        pim.solve(None, 0.3, 1.0)


def test_shape_mismatch_names_the_arguments():
    case = pim.load_case("ricsac9")
    with pytest.raises(ValueError, match=r"eps \(3,\), beta \(4,\)"):
        pim.solve(case, np.zeros(3), np.zeros(4))
