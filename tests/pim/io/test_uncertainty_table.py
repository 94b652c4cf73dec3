"""pim/io/uncertainty_table.py: the case file's [uncertainty] table, parsed to SI, and its
errors (unknown input or key, wrong dimension, bounds in the wrong order)."""

import numpy as np
import pytest

import pim
from pim.io.uncertainty_table import parse_uncertainty
from pim.model.distributions import Distribution, UncertaintyTable
from tests.pim.analysis.test_montecarlo import collinear


def test_parsing_units_and_errors():
    unc = parse_uncertainty({"vehicle1": {"mass": {"normal": "44.0925 lb"}},
                             "impact": {"normal_angle": {"plusminus": "5 deg"},
                                        "beta": {"fixed": 0.8}}})
    assert unc.inputs["vehicle1.mass"].b == pytest.approx(20.0, rel=1e-5)
    assert unc.inputs["impact.normal_angle"].b == pytest.approx(np.radians(5))
    with pytest.raises(ValueError, match="unknown input 'vehicle1.massx'"):
        parse_uncertainty({"vehicle1": {"massx": {"normal": 1}}})
    with pytest.raises(ValueError, match="unknown key 'sd'"):
        parse_uncertainty({"vehicle1": {"mass": {"normal": 1, "sd": 2}}})
    with pytest.raises(ValueError, match="exactly one"):
        parse_uncertainty({"vehicle1": {"mass": {"normal": 1, "fixed": 2}}})
    with pytest.raises(ValueError, match="dimension"):
        parse_uncertainty({"vehicle1": {"mass": {"normal": "3 m"}}})
    with pytest.raises(ValueError, match="low"):
        parse_uncertainty({"impact": {"restitution": {"uniform": [0.5, 0.2]}}})
    case = collinear({"impact": {"restitution": {"uniform": [0.5, 1.2]}}})
    with pytest.raises(ValueError, match="admissible range"):
        pim.uncertainty(case, n=100)
    with pytest.raises(ValueError, match="no \\[uncertainty\\]"):
        pim.uncertainty(collinear(), n=100)
    with pytest.raises(ValueError, match="unknown input"):
        UncertaintyTable({"impact.gamma": Distribution("fixed", 1.0)})


def test_evidence_friction_is_an_uncertain_input():
    unc = parse_uncertainty({"evidence": {"vehicle1": {"friction": {"plusminus": 0.1}}},
                             "impact": {"normal_angle": {"plusminus": "5 deg"}}})
    assert unc.inputs["evidence.vehicle1.friction"] == Distribution("plusminus", None, 0.1)
    with pytest.raises(ValueError, match="unknown input 'evidence.vehicle1.grip'"):
        parse_uncertainty({"evidence": {"vehicle1": {"grip": {"plusminus": 0.1}}}})
    with pytest.raises(ValueError, match="vehicle1 / vehicle2 tables"):
        parse_uncertainty({"evidence": {"vehicle1": 0.1}})
    # a friction spread reaching zero is outside the admissible range (0, inf)
    from pim.model.distributions import sample_inputs

    table = parse_uncertainty({"evidence": {"vehicle1": {"friction": {"uniform": [0.0, 0.8]}}}})
    with pytest.raises(ValueError, match="admissible range"):
        sample_inputs(table, {"evidence.vehicle1.friction": 0.7}, 10,
                      np.random.default_rng(0))
    with pytest.raises(ValueError, match=r"\[evidence\]"):
        sample_inputs(table, {}, 10, np.random.default_rng(0))


def test_recorder_scale_and_crush_inputs_are_uncertain_inputs():
    from pim.io.uncertainty_table import parse_uncertainty

    t = parse_uncertainty({"measured": {"vehicle1": {"delta_v_scale": {"uniform": [0.9, 1.0]}}},
                           "evidence": {"vehicle2": {"crush": {
                               "stiffness_a": {"normal": "5 kN/m"},
                               "depth_scale": {"plusminus": 0.05}}}}})
    assert t.inputs["measured.vehicle1.delta_v_scale"].a == 0.9
    assert t.inputs["evidence.vehicle2.crush.stiffness_a"].b == pytest.approx(5000.0)
    assert "evidence.vehicle2.crush.depth_scale" in t.inputs
    with pytest.raises(ValueError, match="unknown input 'measured.vehicle1.delta_v'"):
        parse_uncertainty({"measured": {"vehicle1": {"delta_v": {"normal": 1}}}})
