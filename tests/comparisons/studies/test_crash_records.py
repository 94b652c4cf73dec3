"""The crash classes, the origins of their inputs and the leave-one-out input variants
(comparisons.studies.crash_records): no fold's inputs hold its held-out test's outcome."""

import dataclasses

import numpy as np
import pytest

from comparisons.studies import crash_records as R
from pim.io.datasets import FITTED_BY_PIM, MEASURED, PIM_OUTPUT


def test_classes_cover_the_datasets_both_models_run(classes):
    assert {k: len(v) for k, v in classes.items()} == {
        R.NON_SIDESWIPE: 16, R.SIDESWIPE: 24, R.RICSAC: 3, R.RICSAC9: 1, R.CAR_TO_CAR: 4}
    assert list(classes) == list(R.CLASS_NAMES)
    assert "iihs-car-to-car" in R.UNRUNNABLE
    assert all(r.outcome_origin == MEASURED for k in (R.NON_SIDESWIPE, R.RICSAC)
               for r in classes[k])
    assert classes[R.CAR_TO_CAR][0].outcome_origin == PIM_OUTPUT
    assert classes[R.NON_SIDESWIPE][0].origins["phi"] == FITTED_BY_PIM


def test_observables(classes):
    barrier, car = classes[R.SIDESWIPE][0], classes[R.CAR_TO_CAR][0]
    assert barrier.moving == (1,) and barrier.observed.shape == (3,)
    assert classes[R.RICSAC][0].observed.shape == (6,)
    assert car.observable == R.MAGNITUDES and car.observed.shape == (4,)
    c = car.case
    moved = car.observe(c, np.asarray(c.vehicle1.velocity) + [3.0, 4.0], 0.5,
                        c.vehicle2.velocity, -0.2)
    np.testing.assert_allclose(moved, [5.0, 0.5, 0.0, 0.2])
    m = barrier.case.measured
    np.testing.assert_allclose(barrier.observe(barrier.case, m.velocity1, m.yaw_rate1, None,
                                               None), barrier.observed)


def test_leak_free_folds_hold_nothing_of_the_held_out_test(classes, radii):
    """Fold f: phi the median of the other tests' published phi, k the median of the other
    tests' fitted radii of gyration; fold n: the class's own medians."""
    records = classes[R.NON_SIDESWIPE]
    leak_free, published = R.input_variants(records, radii)
    assert (leak_free.name, published.name) == (R.LEAK_FREE, R.PUBLISHED_PHI)
    phis = np.array([r.source.phi for r in records])
    n = len(records)
    for f in range(n):
        assert np.all(leak_free.phi[:, f] == np.median(np.delete(phis, f)))
    assert np.all(leak_free.phi[:, n] == np.median(phis))
    np.testing.assert_array_equal(published.phi, np.repeat(phis[:, None], n + 1, axis=1))
    barrier, k = radii
    held = records[0].source
    others = [k[t.test_id] for t in barrier
              if t.vehicle_type == held.vehicle_type and t.test_id != held.test_id]
    assert leak_free.radius_of_gyration[0, 0] == pytest.approx(np.median(others))
    assert leak_free.origins["phi"].startswith("median of the other tests")
    assert published.origins["phi"] == FITTED_BY_PIM


def _edited(records, radii, shift):
    """Records and radii with test 0's published phi and fitted k moved by ``shift``."""
    moved = dataclasses.replace(records[0].source, phi=records[0].source.phi + shift)
    barrier, k = radii
    k = dict(k, **{moved.test_id: k[moved.test_id] + shift})
    return R.input_variants([dataclasses.replace(records[0], source=moved), *records[1:]],
                            (barrier, k))[0]


def test_a_fold_does_not_change_with_its_held_out_tests_phi_or_radius(classes, radii):
    """Move test 0's published phi and fitted k (both outcome-derived) down and up: fold 0's
    inputs of every test stay; fold 1's (which trains on test 0) move."""
    records = classes[R.NON_SIDESWIPE][:5]
    before = R.input_variants(records, radii)[0]
    moved = [_edited(records, radii, shift) for shift in (-0.5, 0.5)]
    for after in moved:
        np.testing.assert_array_equal(after.phi[:, 0], before.phi[:, 0])
        np.testing.assert_array_equal(after.radius_of_gyration[:, 0],
                                      before.radius_of_gyration[:, 0])
    assert any(not np.array_equal(a.phi[:, 1], before.phi[:, 1]) for a in moved)
    assert any(not np.array_equal(a.radius_of_gyration[:, 1], before.radius_of_gyration[:, 1])
               for a in moved)


def test_variant_cases_follow_the_fold(classes, radii):
    records = classes[R.NON_SIDESWIPE][:4]
    v = R.input_variants(records, radii)[0]
    batch = v.case(1, records[1], np.arange(5)[:, None])
    assert batch.shape == (5, 1)
    assert R.input_variants(classes[R.RICSAC], radii)[0].name == R.PUBLISHED_INPUTS
    ricsac = R.input_variants(classes[R.RICSAC], radii)[0]
    assert ricsac.case(0, classes[R.RICSAC][0], 2) is classes[R.RICSAC][0].case
