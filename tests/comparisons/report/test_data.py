"""ReportData, the one typed object ``pim compare`` gathers and its renderers consume: the
tables keep their insertion order under their own names, and the defaults say "nothing
gathered" (no fit, no simulation, no animation, NaN error). The full gather-and-render
round trip is in tests/comparisons/report/test_compare.py."""

import math

import pytest

import pim
from comparisons.report.data import ReportData
from comparisons.report.tables import Table


@pytest.fixture
def data():
    case = pim.load_case("ricsac9")
    return ReportData(case, "ricsac9", "si", 0.2, 0.9, {"eps": "case", "beta": "case"},
                      pim.solve(case, 0.2, 0.9))


def test_tables_are_kept_by_name_in_insertion_order(data):
    for name in ("results", "inputs", "fit"):
        data.add_table(Table(name, name.title(), ("a [m]",), ((1.0,),)))
    assert list(data.tables) == ["results", "inputs", "fit"]
    assert data.tables["inputs"].title == "Inputs"
    data.add_table(Table("inputs", "Replaced", ("a [m]",), ((2.0,),)))
    assert list(data.tables) == ["results", "inputs", "fit"]
    assert data.tables["inputs"].rows == ((2.0,),)


def test_defaults_say_nothing_was_gathered(data):
    assert data.fit is None and data.simulated is None and data.sim_error is None
    assert data.animation is None and data.animation_requested is True
    assert data.study is None and data.assumptions is None
    assert math.isnan(data.error)
    assert data.warnings == [] and data.limits == [] and data.files == []


def test_instances_do_not_share_their_containers(data):
    other = ReportData(data.case, "x", "us", 0.1, 0.5, {}, data.result)
    data.add_table(Table("results", "Results", ("a [m]",), ((1.0,),)))
    data.files.append("x.csv")
    assert other.tables == {} and other.files == []
