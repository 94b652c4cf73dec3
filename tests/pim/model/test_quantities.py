"""pim/model/quantities.py: the one list of inputs and outputs covers the model exactly."""

import dataclasses

import numpy as np
import pytest

import pim
from pim.model.quantities import FIELDS, INPUTS, OUTPUTS, VECTOR_FIELDS, field_of
from pim.model.result import output_values


def test_fields_are_the_case_types_fields():
    for group, kind in (("vehicle1", pim.Vehicle), ("vehicle2", pim.Vehicle)):
        # the outline and the reversing and sliding statements are never inputs of the formula
        names = {f.name for f in dataclasses.fields(kind)} - {"length", "width", "cg_to_front",
                                                               "reversing", "sliding"}
        assert {k.split(".")[1] for k in FIELDS if k.startswith(group)} == names
    # the impact law (a choice, not a number) and its contact friction (not an input of
    # Brach's formula, which the kernel, the derivatives and the Monte Carlo evaluate)
    assert {k.split(".")[1] for k in FIELDS if k.startswith("impact")} == {
        f.name for f in dataclasses.fields(pim.Impact)} - {"law", "contact_friction"}
    assert VECTOR_FIELDS <= set(FIELDS)


def test_inputs_split_vectors_and_map_back():
    assert field_of("impact.point_y") == ("impact.point", 1)
    assert field_of("vehicle2.mass") == ("vehicle2.mass", None)
    assert len(INPUTS) == len(FIELDS) + len(VECTOR_FIELDS)
    with pytest.raises(ValueError, match="unknown input 'vehicle3.mass'"):
        field_of("vehicle3.mass")


def test_outputs_are_exactly_what_results_give():
    r = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    values = output_values(r)
    assert set(values) == set(OUTPUTS)
    for name in OUTPUTS:
        base = name[:-2] if name.endswith(("_x", "_y")) else name
        if hasattr(r, base):
            value = np.asarray(getattr(r, base))
            if name != base:
                value = value[..., "xy".index(name[-1])]
            assert np.allclose(values[name], value, equal_nan=True), name
