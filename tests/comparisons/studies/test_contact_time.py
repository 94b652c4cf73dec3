"""The contact time of the tuned scene (comparisons.studies.contact_time) and the scene held
to the physical ranges (comparisons.studies.tuned_scene): the profile finds a synthetic
crash's contact time, its threshold is the chi-square rule, the physical scene keeps its
outputs in their ranges, the mechanisms switch off one thing each."""

import math

import numpy as np
import pytest

import pim
from comparisons.studies import contact_time as C
from comparisons.studies import crash_records as R
from comparisons.studies import tuned_scene as T


def test_the_threshold_is_the_likelihood_ratio_rule():
    """chi2_1(0.95) = 3.841 (any chi-square table); n_r ln(S/S_min) = 3.841 at the
    threshold."""
    assert C.lr_threshold(2.0, 48) == pytest.approx(2.0 * math.exp(3.8415 / 96), rel=1e-4)
    t = C.lr_threshold(1.3, 18)
    assert 18 * math.log((t / 1.3) ** 2) == pytest.approx(3.8415, abs=1e-3)


def test_the_profile_finds_a_synthetic_crashs_contact_time(synthetic):
    """Truth: RICSAC 9 integrated by sim.reference_compliant (solve_ivp, independent of the
    compiled stepper) at T = 0.1 s; the profile refits the rest at each held T: its least
    rms sits at 0.1 s, near zero, and rises away from it."""
    mu = 0.6
    truth = synthetic(0.3, mu, 0.1, 0.7)
    variant = R.input_variants([truth])[0]
    p = C.profile_contact_time([truth], variant, times=(0.03, 0.1, 0.25), steps=100)
    assert p.times[int(np.argmin(p.rms))] == 0.1 and p.rms[1] < 0.05
    assert p.rms[0] > 0.2 and p.rms[2] > 0.2 and not {0.03, 0.25} & set(p.kept)
    assert p.fits[1].x[2] == 0.1 and abs(p.fits[1].x[1] - mu) < 0.05
    assert p.free.x[2] == pytest.approx(0.1, abs=0.01) and p.n_residuals == 6


def test_the_physical_scene_is_boxed_and_keeps_its_outputs_in_range():
    m = T.SCENE_PHYSICAL_MODEL
    for name, i in (("contact time", 2), ("friction", 1), ("tyre friction", 3)):
        assert (m.lower[i], m.upper[i]) == T.PHYSICAL_RANGES[name][:2]
    nan = np.full(3, np.nan)
    motion = T.Motion(nan, nan, nan, nan, np.array([True, True, False]),
                      np.array([0.1, 0.262, 0.5]), np.array([0.03, 0.5, 3.0]), nan)
    pen = T.output_penalty(m, motion)
    np.testing.assert_allclose(pen, [[0, 20], [12, 0], [0, 0]], atol=1e-9)   # ms, mm
    assert T.output_penalty(T.SCENE_MODEL, motion).shape == (3, 0)


def test_the_physical_fit_holds_the_contact_inside_its_ranges(classes, radii):
    """The RICSAC class fitted in the physical box: parameters and every fitted test's
    contact time and crush inside the ranges (the free scene's leaves them)."""
    records = classes[R.RICSAC]
    variant = R.input_variants(records, radii)[0]
    fit = T.fit_class(T.SCENE_PHYSICAL_MODEL, records, variant, loo=False)[len(records)]
    m = T.SCENE_PHYSICAL_MODEL
    assert all(lo <= x <= hi for x, lo, hi in zip(fit.x, m.lower, m.upper, strict=True))
    for t, rec in enumerate(records):
        p = T.predict(m, rec, variant.case(t, rec, len(records)), fit.x, ("class fit", "x"))
        assert 0.05 - 2e-3 <= p.contact_time <= 0.25 + 2e-3
        assert 0.05 - 2e-3 <= p.peak_crush <= 1.2 + 2e-3


def test_each_mechanism_switches_off_one_thing():
    full, frozen, tyres, plastic = C.MECHANISMS
    assert full.model() is T.SCENE_MODEL and not full.held
    assert dict(frozen.model().options) == {"geometry_change": False} and not frozen.held
    assert tyres.model() is T.SCENE_MODEL and dict(tyres.held) == {C.TYRE_INDEX: 0.0}
    assert dict(plastic.model().options) == {"tangential_recovery": 0.0}
    case = pim.load_case("ricsac9")
    x = np.array([[0.2, 0.8, t, 0.0] for t in (0.02, 0.25)])
    m = T.run_model(frozen.model(), case, x)
    np.testing.assert_allclose(m.velocity1[0], m.velocity1[1], atol=1e-9)


def test_study_classes_adds_the_profile_and_the_mechanisms_where_asked():
    (st,) = C.study_classes(classes=["ricsac9"])
    assert st.profile is not None and st.mechanisms == ()
    assert st.profile.times == C.PROFILE_TIMES
    assert st.profile.best_rms <= st.variants[0].class_fits["scene"].rms + 1e-9
    assert "scene-physical" in st.variants[0].comparisons


@pytest.mark.slow
def test_the_mechanisms_on_the_non_sideswipe_class():
    """The study's own class: frozen geometry flattens the profile, no tyres steepens it."""
    (st,) = C.study_classes(classes=["non-sideswipe"])
    full, frozen, tyres, _ = st.mechanisms
    assert frozen.rise < full.rise < tyres.rise
    assert len(frozen.profile.kept) == len(C.MECHANISM_TIMES)
