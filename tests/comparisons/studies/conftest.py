"""Fixtures of the crash-test studies: the barrier tests' fitted radii of gyration and the
crash classes (each computed once per module)."""

import dataclasses

import numpy as np
import pytest

import pim
import sim
from comparisons.studies import crash_records as R
from sim.contact_law import stiffness_for_duration


@pytest.fixture(scope="module")
def radii():
    return R.fitted_radii()


@pytest.fixture(scope="module")
def classes(radii):
    return R.crash_classes(radii=radii)


@pytest.fixture(scope="module")
def synthetic(classes):
    """``synthetic(eps, mu, duration, tyre)``: RICSAC 9 integrated by
    sim.reference_compliant (solve_ivp, independent of the compiled stepper) at those
    parameters, as a record whose observed outcome is that motion."""

    def make(eps, mu, duration, tyre):
        record = classes[R.RICSAC9][0]
        case = record.case
        k = float(stiffness_for_duration(duration, float(pim.solve(case, eps).k_nn), eps))
        r = sim.reference_compliant(case, eps, k, friction=mu, tyre_friction=tyre,
                                    settings=sim.CompliantSettings(record=False, rtol=1e-9))
        return dataclasses.replace(record, observed=np.r_[r.velocity1, r.yaw_rate1,
                                                          r.velocity2, r.yaw_rate2])

    return make
