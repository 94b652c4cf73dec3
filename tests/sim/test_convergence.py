"""Chipmunk's sweep contraction (sim.convergence) against the Gauss-Seidel iteration matrix.

Independent reference: for the sticking contact the sweeps are Gauss-Seidel on K P = b, whose
iteration matrix -(D + L)^-1 U has spectral radius K_nt^2 / (K_nn K_tt) (Golub & Van Loan,
Matrix Computations, 4th ed., sec. 11.2: for a 2x2 system the nonzero eigenvalue is
a12 a21 / (a11 a22)); it is computed here by numpy's eigvals.
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim.convergence import (
    MAX_ITERATIONS,
    MIN_ITERATIONS,
    TARGET_ERROR,
    auto_iterations,
    contraction_rate,
)

positive = st.floats(1e-4, 1e2)


@given(a=positive, b=positive, c=st.floats(0.0, 0.99))
def test_sticking_rate_is_the_gauss_seidel_spectral_radius(a, b, c):
    k_nt = c * math.sqrt(a * b)          # |K_nt| < sqrt(K_nn K_tt): K positive definite
    k = np.array([[a, k_nt], [k_nt, b]])
    lower, upper = np.tril(k), np.triu(k, 1)
    radius = max(abs(np.linalg.eigvals(-np.linalg.solve(lower, upper))))
    assert contraction_rate(a, k_nt, b, 0.3, sticking=True) == pytest.approx(radius,
                                                                            abs=1e-12)


def test_sliding_rate_and_the_iteration_count():
    assert contraction_rate(2.0, -0.5, 3.0, 0.8, sticking=False) == pytest.approx(0.2)
    rho = 0.5
    n = auto_iterations(rho)
    assert rho ** (n / 2) <= TARGET_ERROR < rho ** ((n - 1) / 2)
    assert auto_iterations(1.5) == auto_iterations(0.0) == MIN_ITERATIONS
    assert auto_iterations(1 - 1e-12) == MAX_ITERATIONS
