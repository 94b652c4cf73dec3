"""What `pim sensitivity` shows (comparisons.report.sensitivity): units of derivatives, the
JSON in the user's units (1 mph = 0.44704 m/s, 1 ft = 0.3048 m exactly), the ranked tables."""

import pytest

import pim
from comparisons.report.sensitivity import ratio_unit, sensitivity_json, sensitivity_lines
from pim.analysis.sensitivity import sensitivity

MPH, FT = 0.44704, 0.3048


@pytest.fixture(scope="module")
def sens():
    return sensitivity(pim.load_case("ricsac9"))


@pytest.mark.parametrize("out, inp, unit", [
    ("mph", "mph", "-"), ("-", "ft", "1/ft"), ("mph", "deg", "mph/deg"),
    ("km/h", "deg", "(km/h)/deg"), ("ft lbf", "ft", "(ft lbf)/ft")])
def test_ratio_unit(out, inp, unit):
    assert ratio_unit(out, inp) == unit


def test_json_in_the_users_units(sens):
    data = sensitivity_json(sens, "us")
    si = sens.to_dict()
    name = next(n for n in data["outputs"] if n.startswith("delta"))
    assert data["outputs"][name]["unit"] == "mph"
    assert data["outputs"][name]["value"] == pytest.approx(si["outputs"][name]["value"] / MPH)
    row = next(r for r in data["outputs"][name]["inputs"] if r["sigma_unit"] == "ft")
    raw = next(r for r in si["outputs"][name]["inputs"] if r["input"] == row["input"])
    assert row["sigma"] == pytest.approx(raw["sigma"] / FT)
    assert row["per_unit"] == pytest.approx(raw["per_unit"] * FT / MPH)
    assert row["per_unit_unit"] == "mph/ft"
    assert data["units"]["velocity"] == "mph"


def test_lines_rank_and_cut_at_top(sens):
    lines = sensitivity_lines("ricsac9", sens, "us", top=2)
    assert lines[0].startswith("ricsac9: sensitivity at epsilon = ")
    heads = [i for i, line in enumerate(lines) if line.split()[:1] == ["input"]]
    assert heads, lines
    for i in heads:                 # header, rule, at most two rows
        block = lines[i + 2:]
        rows = block[:next((j for j, x in enumerate(block) if x == ""), len(block))]
        assert 1 <= len(rows) <= 2
        effects = [float(r.split()[-1]) for r in rows]
        assert effects == sorted(effects, reverse=True)
