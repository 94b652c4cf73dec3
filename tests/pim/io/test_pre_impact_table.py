"""The [evidence.vehicleN.pre_impact] sub-table (pim.io.pre_impact_table), its place in the
case file's [evidence] and its [uncertainty] entries."""

import math
import tomllib
from importlib import resources

import pytest

from pim.io.casefile import load_case, parse_case
from pim.io.pre_impact_table import PRE_IMPACT_KEYS, parse_pre_impact
from pim.io.uncertainty_table import parse_uncertainty
from pim.model.numbers import InputError

FT = 0.3048
WHERE = "evidence.vehicle1.pre_impact"


def test_units_words_and_defaults():
    m = parse_pre_impact({"skid_length": "42 ft", "friction": 0.7}, WHERE)
    assert m.skid_length == pytest.approx(42 * FT)
    assert m.friction == 0.7 and m.braking == (1.0,) * 4 and m.grade == 0.0
    assert m.length_sigma == 0.0 and m.where == WHERE
    m = parse_pre_impact({"skid_length": "12 m", "friction": "0.6", "braking": 0.5,
                          "grade": "2 %", "length_sigma": "2 ft"}, WHERE)
    assert m.braking == (0.5,) * 4 and m.grade == pytest.approx(0.02)
    assert m.length_sigma == pytest.approx(2 * FT)


@pytest.mark.parametrize("grade, expected", [
    ("2 %", 0.02), ("-3.5 %", -0.035), ("2 percent", 0.02), (0.02, 0.02),
    ("1.1458 deg", math.tan(math.radians(1.1458)))])
def test_grade_as_percent_number_or_angle(grade, expected):
    m = parse_pre_impact({"skid_length": "42 ft", "friction": 0.7, "grade": grade}, WHERE)
    assert m.grade == pytest.approx(expected, rel=1e-12)


def test_per_wheel_braking_weighs_the_axle_loads():
    m = parse_pre_impact({"skid_length": "42 ft", "friction": 0.7,
                          "braking": ["locked", "locked", "free", 0.5]}, WHERE,
                         front_share=0.6)
    assert m.braking == (1.0, 1.0, 0.0, 0.5)
    assert m.drag == pytest.approx(0.6 * 1.0 + 0.4 * 0.25)


@pytest.mark.parametrize("table, words", [
    ({"skid_length": "-42 ft", "friction": 0.7}, "skid_length must be a length >= 0, got '-42 ft'"),
    ({"skid_length": "42 ft", "friction": 0.0}, "friction must be > 0"),
    ({"skid_length": "42 ft", "friction": -0.5}, "friction must be > 0"),
    ({"skid_length": "42 ft", "friction": 0.7, "braking": 1.5}, "braking must be a braking "
     "fraction in [0, 1]"),
    ({"skid_length": "42 ft", "friction": 0.7, "braking": [1, 1, 1]}, "braking must be one "
     "state or four"),
    ({"skid_length": "42 ft", "friction": 0.7, "braking": ["locked", "stuck", 1, 1]},
     "braking[1]"),
    ({"skid_length": "42 ft", "friction": 0.3, "grade": "-40 %"}, "grade -40 % is steeper "
     "downhill than the friction holds"),
    ({"skid_length": "42 ft", "friction": 0.7, "grade": "150 %"}, "grade must be in [-1, 1]"),
    ({"skid_length": "42 ft", "friction": 0.7, "length_sigma": "-1 ft"}, "length_sigma must "
     "be a length >= 0"),
    ({"skid_length": "42 kg", "friction": 0.7}, "skid_length"),
    ({"skid_length": "42 ft"}, "missing friction"),
    ({"friction": 0.7}, "missing skid_length"),
    ({"skid_length": "42 ft", "friction": 0.7, "mu": 0.7}, "unknown key 'mu'"),
])
def test_every_bad_entry_names_its_field(table, words):
    with pytest.raises(InputError) as exc:
        parse_pre_impact(table, WHERE)
    assert WHERE in str(exc.value) and words in str(exc.value), str(exc.value)


def _case_text(extra: str) -> str:
    return (resources.files("pim.io") / "cases" / "synthetic-runout.toml").read_text() + extra


def test_the_case_file_attaches_the_marks_to_the_vehicles_evidence(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(_case_text('\n[evidence.vehicle2.pre_impact]\nskid_length = "20 ft"\n'
                               'friction = 0.7\nbraking = ["locked", "locked", "free", "free"]'
                               '\n'))
    case = load_case(path)
    assert case.evidence.vehicle1.pre_impact is None
    marks = case.evidence.vehicle2.pre_impact
    assert marks.skid_length == pytest.approx(20 * FT)
    # wheelbase 3.0 m, CG 1.4 m behind the front axle: the front axle carries 1.6 / 3.0
    assert marks.front_share == pytest.approx(1.6 / 3.0) and marks.drag == pytest.approx(
        1.6 / 3.0)
    assert marks.where == "evidence.vehicle2.pre_impact"


def test_a_bad_sub_table_in_a_case_names_it(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(_case_text('\n[evidence.vehicle1.pre_impact]\nskid_length = "20 ft"\n'
                               'friction = 0\n'))
    with pytest.raises(InputError, match=r"evidence\.vehicle1\.pre_impact\.friction must be"):
        load_case(path)


def test_the_bundled_case_has_marks_for_both_vehicles():
    case = load_case("pre-impact-skids")
    assert case.evidence.vehicle1.pre_impact.skid_length == pytest.approx(30 * FT)
    assert case.evidence.vehicle2.pre_impact.grade == pytest.approx(-0.02)
    names = set(case.uncertainty.inputs)
    assert {"evidence.vehicle1.pre_impact.friction", "evidence.vehicle1.pre_impact.skid_length",
            "evidence.vehicle2.pre_impact.friction"} <= names


def test_uncertainty_entries_of_the_marks():
    """Before: uncertainty: unknown input 'evidence.vehicle1.pre_impact'."""
    table = parse_uncertainty({"evidence": {"vehicle1": {
        "friction": {"plusminus": 0.05},
        "pre_impact": {"friction": {"plusminus": 0.1}, "skid_length": {"normal": "2 ft"}}}}})
    d = table.inputs["evidence.vehicle1.pre_impact.skid_length"]
    assert d.kind == "normal" and d.b == pytest.approx(2 * FT)
    assert table.inputs["evidence.vehicle1.pre_impact.friction"].b == pytest.approx(0.1)
    assert "evidence.vehicle1.friction" in table.inputs
    with pytest.raises(InputError, match=r"unknown input 'evidence\.vehicle1\.pre_impact\.grade'"):
        parse_uncertainty({"evidence": {"vehicle1": {"pre_impact": {"grade": {"fixed": 0}}}}})
    with pytest.raises(InputError, match=r"evidence\.vehicle1\.pre_impact"):
        parse_uncertainty({"evidence": {"vehicle1": {"pre_impact": 0.1}}})


def test_the_keys_are_the_documented_ones():
    doc = parse_pre_impact.__module__
    text = (resources.files("pim.io") / "pre_impact_table.py").read_text()
    assert doc == "pim.io.pre_impact_table"
    for key in PRE_IMPACT_KEYS:
        assert f"\n{key} = " in text


def test_parse_case_refuses_marks_without_a_number(tmp_path):
    data = tomllib.loads(_case_text('\n[evidence.vehicle1.pre_impact]\nskid_length = "20 ft"\n'
                                    'friction = "0.7 m"\n'))
    with pytest.raises(InputError, match=r"evidence\.vehicle1\.pre_impact\.friction"):
        parse_case(data)
