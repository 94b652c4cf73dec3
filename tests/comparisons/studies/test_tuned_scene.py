"""The finite-duration scene tuned to crash tests; leave-one-out against PIM
(comparisons.studies.tuned_scene)."""

import dataclasses

import numpy as np
import pytest

import pim
import sim
from comparisons.studies import tuned_scene as T
from sim.contact_law import stiffness_for_duration


def _with_measured(test: T.TestCase, v1, w1, v2=None, w2=None) -> T.TestCase:
    m = pim.Measured(velocity1=v1, yaw_rate1=w1, velocity2=v2, yaw_rate2=w2)
    return T.TestCase(test.crash_class, test.name, dataclasses.replace(test.case, measured=m))


def test_the_fit_recovers_known_parameters_of_a_synthetic_crash():
    """Truth from the independent solve_ivp integration (sim.reference_compliant) of RICSAC 9
    at known (eps, mu_c, T) with tyres; the fit runs the pymunk scene."""
    case = pim.load_case("ricsac9")
    probe = T.TestCase("synthetic", "ricsac9", case)
    eps, mu, duration, tyre = 0.3, 0.6, 0.12, 0.7
    k = float(stiffness_for_duration(duration, probe.k_nn, eps))
    r = sim.reference_compliant(case, eps, k, friction=mu, tyre_friction=tyre,
                                settings=sim.CompliantSettings(record=False, rtol=1e-8))
    test = _with_measured(probe, r.velocity1, r.yaw_rate1, r.velocity2, r.yaw_rate2)
    fit = T.fit_parameters(T.SCENE_MODEL, [test], fixed={3: tyre}, steps=40)
    assert fit.x[0] == pytest.approx(eps, abs=0.01)
    assert fit.x[1] == pytest.approx(mu, abs=0.02)
    assert fit.x[2] == pytest.approx(duration, rel=0.05)
    assert fit.x[3] == tyre
    assert fit.rms < 0.1                        # scaled by 1 mph and 10 deg/s


@pytest.fixture(scope="module")
def sideswipe():
    return T.crash_classes(max_tests=3)["IIHS barrier, sideswipe"]


@pytest.mark.parametrize("model, nfev", [(T.PIM_MODEL, None), (T.SCENE_MODEL, 2)])
def test_leave_one_out_leaves_the_held_out_test_out(sideswipe, model, nfev):
    """Changing the held-out test's measurements changes neither its refit class parameters
    nor its prediction; the other tests, whose training set holds it, do change (so this
    test sees a leak)."""
    fixed = {3: T.TYRE_DEFAULT} if model is T.SCENE_MODEL else None
    per_test = {t.name: T.fit_parameters(model, [t], fixed=fixed, max_nfev=nfev).x
                for t in sideswipe}
    before = T.leave_one_out(model, sideswipe, per_test, max_nfev=nfev)
    held = sideswipe[0]
    m = held.case.measured
    moved = _with_measured(held, m.velocity1 + np.array([3.0, -2.0]), m.yaw_rate1 + 1.0)
    tests = [moved, *sideswipe[1:]]
    per_test[held.name] = T.fit_parameters(model, [moved], fixed=fixed, max_nfev=nfev).x
    after = T.leave_one_out(model, tests, per_test, max_nfev=nfev)
    assert after[0].x == before[0].x
    assert after[0].velocity_error != before[0].velocity_error     # measured differently
    assert after[1].x != before[1].x and after[2].x != before[2].x


def test_study_of_three_tests_of_one_class():
    tests = T.crash_classes(max_tests=3)["IIHS barrier, non-sideswipe"]
    st = T.study_class("IIHS barrier, non-sideswipe", tests, loo_nfev=2)
    for model in ("PIM", "scene"):
        for kind in ("per-test fit", "class fit", "leave-one-out"):
            rows = st.rows(model, kind)
            assert [r.test for r in rows] == [t.name for t in tests]
    scene_own = np.median([r.velocity_error for r in st.rows("scene", "per-test fit")])
    scene_class = np.median([r.velocity_error for r in st.rows("scene", "class fit")])
    assert scene_own <= scene_class + 1e-9
    assert all(r.x[3] == T.TYRE_DEFAULT for r in st.rows("scene", "per-test fit"))
    assert all(r.wall_time > 0 for r in st.predictions)
    dv, dw = T.coarse_check(tests[0], st.class_fits["scene"].x)
    # coarse scene against 10x finer: within half the fit scales (1 mph, 10 deg/s)
    assert dv < 0.2 and dw < 0.09


def test_classes_cover_the_datasets_with_motion():
    classes = T.crash_classes()
    sizes = {k: len(v) for k, v in classes.items()}
    assert sizes == {"IIHS barrier, non-sideswipe": 16, "IIHS barrier, sideswipe": 24,
                     "RICSAC, momentum-consistent": 3, "RICSAC 9, design sheet": 1}
    assert "iihs-car-to-car" in T.UNRUNNABLE
    assert T.predict(T.SCENE_MODEL, classes["RICSAC 9, design sheet"][0],
                     (0.3, 0.5, 0.1, 0.0)).shape == (6,)


@pytest.mark.slow
def test_full_study_every_class():
    for name, tests in T.crash_classes().items():
        st = T.study_class(name, tests)
        loo = st.rows("scene", "leave-one-out")
        assert len(loo) == (len(tests) if len(tests) > 2 else 0)
        assert all(np.isfinite(r.velocity_error) for r in st.rows("PIM", "per-test fit"))
