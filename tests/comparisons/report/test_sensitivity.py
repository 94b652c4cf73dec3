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


def _per_sigma(lines):
    """The per-sigma column of every table row."""
    return [float(line.split()[-1]) for line in lines
            if line.startswith("  ") and line.split()[-1][-1].isdigit()
            and not line.strip().startswith(("input", "-"))]


@pytest.mark.parametrize("name", ["hard-beta0", "hard-eps0"])
def test_round_off_is_shown_as_zero(name):
    """issue 33, point 6: at beta = 0 the velocities along y and C's x do not move delta-V
    (its derivative is 0), and the central differences printed 6.4e-11 km/h per sigma; at
    epsilon = 0, Gamma's 3.2e-11. What lies below the differences' resolution is 0."""
    sens = sensitivity(pim.load_case(name))
    lines = sensitivity_lines(name, sens, "si")
    values = _per_sigma(lines)
    assert values and 0.0 in values, lines
    assert all(v == 0 or v > 1e-4 for v in values), lines
    data = sensitivity_json(sens, "si")
    rows = [r for e in data["outputs"].values() for r in e["inputs"]]
    assert all(r["per_sigma"] == 0 or r["per_sigma"] > 1e-4 for r in rows)
    assert all(r["per_unit"] == 0 for r in rows if r["per_sigma"] == 0)


def test_a_real_small_effect_is_kept(sens):
    """The resolution is relative to the answer's scale: effects of 1 and 1e-5 m/s on a
    value of 10 m/s stay, 1e-9 m/s (below 1e-7 of it) is 0, whatever the sign."""
    from dataclasses import replace

    import numpy as np

    from comparisons.report.sensitivity import resolved_derivative

    effect = np.zeros_like(sens.derivative)
    effect[:, :3] = [1.0, -1e-5, 1e-9]
    values = np.full(len(sens.outputs), 10.0)
    moved = replace(sens, derivative=effect / sens.sigma, values=values)
    np.testing.assert_array_equal(resolved_derivative(moved)[:, :3] * sens.sigma[:3],
                                  np.tile([1.0, -1e-5, 0.0], (len(sens.outputs), 1)))


def test_a_fixed_barrier_has_no_table_of_zeros():
    """issue 33, point 6: a barrier's delta-V (0 whatever the inputs) was a table of zeros."""
    sens = sensitivity(pim.load_case("hard-barrier"))
    lines = sensitivity_lines("hard-barrier", sens, "si")
    at = next(i for i, line in enumerate(lines) if line.startswith("|delta-V| of vehicle 2"))
    assert lines[at + 1:] == ["  vehicle 2 is a fixed barrier: its delta-V is 0 whatever the "
                              "inputs"]
    entry = sensitivity_json(sens, "si")["outputs"]["delta_v2_magnitude"]
    assert entry["inputs"] == [] and "fixed barrier" in entry["note"] and entry["value"] == 0
    assert all(v > 0 for v in _per_sigma(lines))        # vehicle 1's table: effects only
