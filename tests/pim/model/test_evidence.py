"""Evidence types (pim.model.evidence): validation naming the field, conversion to the
run-out vehicle."""

import numpy as np
import pytest

from pim.model.evidence import UNKNOWN_KINDS, VehicleEvidence
from pim.model.tyres import STANDARD_GRAVITY


def test_runout_vehicle_carries_the_evidence():
    ev = VehicleEvidence(np.array([1.0, 2.0]), 0.3, 2.6, 1.5, 1.0, 0.7,
                         braking=(1, 1, 0, 0), where="evidence.vehicle2")
    rv = ev.runout_vehicle(1200.0, 2000.0)
    assert rv.friction == 0.7 and rv.braking == (1, 1, 0, 0)
    # CG 1.0 m behind the front axle of 2.6: 1.6/2.6 of the weight on the front axle
    np.testing.assert_allclose(rv.loads[:2].sum(), 1200 * STANDARD_GRAVITY * 1.6 / 2.6)


@pytest.mark.parametrize("kwargs, match", [
    (dict(friction=0.0), "evidence.vehicle2.friction"),
    (dict(friction=float("nan")), "evidence.vehicle2.friction"),
    (dict(cg_to_front_axle=3.0), "evidence.vehicle2.cg_to_front_axle"),
    (dict(rest_position=np.array([np.nan, 0.0])), "evidence.vehicle2.rest_position"),
    (dict(braking=(1, 1, 2, 0)), "evidence.vehicle2.braking"),
])
def test_bad_evidence_names_the_field(kwargs, match):
    args = dict(rest_position=np.zeros(2), rest_heading=0.0, wheelbase=2.6, track=1.5,
                cg_to_front_axle=1.0, friction=0.7, where="evidence.vehicle2")
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        VehicleEvidence(**args)


def test_unknown_keys_follow_the_fit_api():
    assert {"vehicle1.speed", "vehicle2.speed", "impact.restitution",
            "impact.beta"} <= set(UNKNOWN_KINDS)
