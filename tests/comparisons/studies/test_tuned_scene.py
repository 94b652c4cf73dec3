"""The tuned scene against PIM (comparisons.studies.tuned_scene): multi-start fits on the
compiled scene recover a synthetic crash of the independent solve_ivp reference, escape the
local minimum one start falls into, converge in leave-one-out without an evaluation cap, and
the held-out test lends nothing to its own prediction."""

import dataclasses

import numpy as np
import pytest

import pim
from comparisons.studies import crash_records as R
from comparisons.studies import tuned_scene as T


@pytest.mark.parametrize("model", [T.SCENE_MODEL, T.SCENE_MU0_MODEL])
def test_the_multistart_fit_recovers_a_synthetic_crash(classes, synthetic, model):
    """Truth: RICSAC 9 integrated by sim.reference_compliant (solve_ivp, independent of the
    compiled stepper) at known (eps, friction, T, mu_tyre); the fit sees only its
    post-impact motion, from a Sobol screen of the whole box."""
    case = classes[R.RICSAC9][0].case
    eps, duration, tyre = 0.3, 0.12, 0.7
    law = 0.6 if model is T.SCENE_MODEL else 0.8       # mu_c, or b with mu_c = b |mu0|
    mu = law if model is T.SCENE_MODEL else law * abs(float(pim.solve(case, eps).mu0))
    truth = synthetic(eps, mu, duration, tyre)
    variant = R.input_variants([truth])[0]
    fit = T.fit_class(model, [truth], variant, loo=False, steps=200)[1]
    np.testing.assert_allclose(fit.x, [eps, law, duration, tyre], rtol=0.03, atol=0.01)
    assert fit.rms < 0.02 and fit.agreeing >= 2 and fit.converged == fit.starts


def test_the_class_fit_escapes_the_local_minimum_of_one_start(classes, radii):
    """The barrier non-sideswipe class at the published phi: one start from the old default
    (0.2, 0.8, 0.1 s, 0.7) stops at rms 2.1 (issue 26); the screened multi-start search
    reaches about 1.53, at the shortest contact time allowed (flagged: outside the
    physical range)."""
    records = classes[R.NON_SIDESWIPE]
    published = R.input_variants(records, radii)[1]
    fit = T.fit_class(T.SCENE_MODEL, records, published, loo=False)[len(records)]
    assert fit.rms < 1.6 and fit.starts == T.CLASS_STARTS["scene"]
    case = published.case(0, records[0], len(records))
    p = T.predict(T.SCENE_MODEL, records[0], case, fit.x, ("class fit", published.name))
    assert (fit.x[2] > 0.05) or "contact time" in p.flags


@pytest.fixture(scope="module")
def four(classes):
    return classes[R.NON_SIDESWIPE][:4]


def _loo(records, radii, model):
    variants = R.input_variants(records, radii)
    return variants, {v.name: T.fit_class(model, records, v) for v in variants}


def _moved(records, radii):
    """Test 0 with its measured motion, its published phi and its fitted radius of gyration
    (the two inputs derived from its outcome) all changed."""
    held = records[0]
    source = dataclasses.replace(held.source, phi=held.source.phi + 0.4)
    moved = dataclasses.replace(held, source=source,
                                observed=held.observed + np.array([1.0, -1.0, 0.5]))
    barrier, k = radii
    return [moved, *records[1:]], (barrier, dict(k, **{held.name: k[held.name] + 0.3}))


@pytest.mark.parametrize("model", [T.PIM_MODEL, T.SCENE_MODEL])
def test_the_held_out_test_lends_nothing_to_its_own_prediction(four, radii, model):
    """Leak-free variant: test 0's refit and predicted motion stay when its measurements and
    its outcome-derived inputs change; the fit of fold 1, which trains on test 0, moves,
    and so does test 0's prediction under the published PIM-fitted phi (a leak this test
    sees). Every refit converged (no evaluation cap)."""
    variants, before = _loo(four, radii, model)
    records, moved_radii = _moved(four, radii)
    variants_after, after = _loo(records, moved_radii, model)
    free, leaky = R.LEAK_FREE, R.PUBLISHED_PHI
    assert (after[free][0].x, after[free][0].rms) == (before[free][0].x, before[free][0].rms)
    assert after[free][1].rms != before[free][1].rms

    def motion(vs, fits, name, recs):
        v = next(x for x in vs if x.name == name)
        m = T.run_model(model, v.case(0, recs[0], 0), fits[name][0].x)
        return np.r_[m.velocity1, m.yaw_rate1]

    np.testing.assert_array_equal(motion(variants, before, free, four),
                                  motion(variants_after, after, free, records))
    assert not np.allclose(motion(variants, before, leaky, four),
                           motion(variants_after, after, leaky, records))
    for fits in before.values():
        assert all(f.converged == f.starts for f in fits.values())


def test_starts_are_one_sobol_sample_for_every_fold():
    a, b = T.sobol_starts(T.SCENE_MODEL, 8), T.sobol_starts(T.SCENE_MODEL, 8)
    np.testing.assert_array_equal(a, b)
    assert np.all((a >= T.SCENE_MODEL.lower) & (a <= T.SCENE_MODEL.upper))
    assert not hasattr(T, "LOO_NFEV") and not hasattr(T, "TYRE_DEFAULT")


def test_a_study_of_a_small_class(classes, radii):
    """Three tests (four parameters): predictions of every kind, no verdict."""
    records = classes[R.SIDESWIPE][:3]
    st = T.study_class(R.SIDESWIPE, records, radii=radii)
    assert [v.variant.name for v in st.variants] == [R.LEAK_FREE, R.PUBLISHED_PHI]
    for v in st.variants:
        for m in T.MODELS:
            for kind in ("class fit", "leave-one-out"):
                assert [r.test for r in v.rows(m.name, kind)] == [r.name for r in records]
        assert v.verdict.verdict == "too few tests to decide" and v.verdict.p_value is None
        assert set(v.comparisons) == {"scene", "scene-mu0", "scene-physical"}
    scene = st.variants[0].rows("scene", "class fit")[0]
    assert scene.contact_time > 0 and scene.peak_crush > 0
    assert all(f in T.PHYSICAL_RANGES for r in st.variants[0].predictions for f in r.flags)
    dv, dw = st.coarse_check          # coarse against 10x finer: within a fifth of the scales
    assert dv < 0.2 * 0.44704 * 2 and dw < np.radians(2.0)


def test_run_model_broadcasts_and_marks_failures(classes):
    record = classes[R.RICSAC][0]
    x = np.array([[0.3, 0.5, 0.1, 0.7], [0.2, 0.4, 0.08, 0.0]])
    m = T.run_model(T.SCENE_MODEL, record.case, x)
    assert m.velocity1.shape == (2, 2) and m.ok.all()
    p = T.run_model(T.PIM_MODEL, record.case, x[:, :2])
    assert p.velocity2.shape == (2, 2) and np.isnan(p.contact_time).all()
    mu0 = T.run_model(T.SCENE_MU0_MODEL, record.case, x)
    assert np.all(mu0.friction == x[:, 1] * abs(pim.solve(record.case, x[:, 0]).mu0))
