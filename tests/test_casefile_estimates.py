"""A case file without a yaw inertia (issue 28, point 5): the estimate from mass and
wheelbase on load, its note on stderr, its scatter in the Monte Carlo, and its tag in the
reports."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pim
from pim.analysis.inverse_pim import inverse_pim
from pim.analysis.montecarlo import uncertainty
from pim.analysis.reconstruction_mc import solve_samples
from pim.io.casefile import parse_case
from pim.model.distributions import nominal_values, sample_inputs
from pim.model.numbers import InputError

ROOT = Path(__file__).resolve().parents[1]
# The cars' yaw dynamic index as K. Tse (2020) published it from NHTSA's database
# (Heydinger et al., SAE 1999-01-1336): mean 1.091, printed to 3 decimals.
PUBLISHED_CAR_INDEX = 1.091


def _data(**vehicle1):
    v1 = {"mass": "1500 kg", "wheelbase": "2.7 m", "cg": ["-2 m", "0 m"], "heading": "0 deg",
          "velocity": ["15 m/s", "0 m/s"], **vehicle1}
    return {"name": "no-inertia",
            "vehicle1": {k: v for k, v in v1.items() if v is not None},
            "vehicle2": {"mass": "1700 kg", "yaw_inertia": "2900 kg*m**2",
                         "cg": ["1 m", "-2 m"], "heading": "90 deg",
                         "velocity": ["0 m/s", "5 m/s"]},
            "impact": {"point": [0, 0], "normal_angle": "180 deg", "restitution": 0.2,
                       "beta": 1}}


def test_case_without_inertia_loads_with_the_estimate_and_solves():
    case = parse_case(_data())
    (estimate,) = case.estimates
    assert estimate.name == "vehicle1.yaw_inertia"
    # D m a b with a = b = L/2: the published index, to its printed digits
    assert float(case.vehicle1.yaw_inertia) == pytest.approx(
        PUBLISHED_CAR_INDEX * 1500 * 2.7**2 / 4, rel=5e-4)
    assert float(case.vehicle1.yaw_inertia) == estimate.value
    assert 0.06 < estimate.relative_sd < 0.08 and estimate.assumptions == ("a = L/2",)
    result = pim.solve(case)
    assert result.problems() == []
    # momentum is exchanged whatever the inertia: the two delta-Vs balance
    assert 1500 * np.asarray(result.delta_v1) == pytest.approx(
        -1700 * np.asarray(result.delta_v2))


def test_axle_position_and_body_class_change_the_estimate():
    base = parse_case(_data()).vehicle1.yaw_inertia
    forward = parse_case(_data(cg_to_front_axle="1.08 m")).vehicle1.yaw_inertia
    assert forward / base == pytest.approx(4 * 0.4 * 0.6)         # a b = 0.24 L^2
    pickup = parse_case(_data(body="pickup"))
    assert pickup.vehicle1.yaw_inertia < base
    assert "pickup" in pickup.estimates[0].method
    with pytest.raises(InputError, match=r"vehicle1\.body must be one of"):
        parse_case(_data(body="bus"))


def test_without_wheelbase_the_error_names_what_is_missing():
    with pytest.raises(InputError) as info:
        parse_case(_data(wheelbase=None))
    text = str(info.value)
    assert "vehicle1" in text and "yaw_inertia" in text and "wheelbase" in text
    with pytest.raises(InputError, match="exactly one of 'yaw_inertia' or 'radius_of"):
        parse_case(_data(yaw_inertia="2500 kg*m**2", radius_of_gyration="1.3 m"))


def test_given_inertia_is_not_estimated():
    case = parse_case(_data(yaw_inertia="2500 kg*m**2"))
    assert case.estimates == () and float(case.vehicle1.yaw_inertia) == 2500.0
    assert case.uncertainty is None


def test_dimensions_from_the_evidence_table_and_their_conflict():
    data = _data(wheelbase=None)
    data["evidence"] = {"vehicle1": {"rest_position": ["20 m", "5 m"], "rest_heading": "30 deg",
                                     "wheelbase": "2.7 m", "track": "1.5 m",
                                     "cg_to_front_axle": "1.08 m", "friction": 0.7}}
    case = parse_case(data)
    assert float(case.vehicle1.yaw_inertia) == pytest.approx(
        float(parse_case(_data(cg_to_front_axle="1.08 m")).vehicle1.yaw_inertia))
    data["vehicle1"]["wheelbase"] = "2.8 m"
    with pytest.raises(InputError, match=r"vehicle1\.wheelbase .* differs from "
                                         r"evidence\.vehicle1\.wheelbase"):
        parse_case(data)


def test_fixed_obstacle_takes_no_wheelbase():
    data = _data()
    data["vehicle2"] = {"fixed": True, "wheelbase": "2 m"}
    with pytest.raises(InputError, match="fixed obstacle has no wheelbase"):
        parse_case(data)


def test_uncertainty_table_gets_the_estimates_scatter_unless_it_gives_one():
    case = parse_case(_data())
    dist = case.uncertainty.inputs["vehicle1.yaw_inertia"]
    assert (dist.kind, dist.a, dist.b) == ("normal", None, case.estimates[0].sd)
    data = _data()
    data["uncertainty"] = {"vehicle1": {"yaw_inertia": {"plusminus": "100 kg*m**2"}},
                           "vehicle2": {"mass": {"normal": "20 kg"}}}
    own = parse_case(data).uncertainty.inputs
    assert own["vehicle1.yaw_inertia"].kind == "plusminus" and "vehicle2.mass" in own


def test_monte_carlo_draws_the_estimate_with_its_scatter():
    case = parse_case(_data())
    estimate = case.estimates[0]
    values, _ = sample_inputs(case.uncertainty, nominal_values(case), 20_000,
                              np.random.default_rng(1))
    drawn = values["vehicle1.yaw_inertia"]
    assert drawn.mean() == pytest.approx(estimate.value, rel=3 * 0.07 / np.sqrt(20_000))
    assert drawn.std() == pytest.approx(estimate.sd, rel=0.03)
    result = uncertainty(case, n=4000, seed=0)
    assert result.varying == ("vehicle1.yaw_inertia",)
    stats = result.stats["yaw_rate1"]
    assert stats.p95 - stats.p5 > 0.05 * abs(stats.nominal)       # the yaw rate spreads
    assert result.sensitivity["yaw_rate1"][0][0] == "vehicle1.yaw_inertia"


def test_reconstruction_monte_carlo_draws_the_estimate():
    data = _data()
    data["measured"] = {"vehicle1": {"velocity": ["9.8 m/s", "2.3 m/s"],
                                     "yaw_rate": "135 deg/s"},
                        "vehicle2": {"velocity": ["4.6 m/s", "2.9 m/s"],
                                     "yaw_rate": "-237 deg/s"}}
    data["unknown"] = {"vehicle1": {"speed": {"bounds": ["0 m/s", "40 m/s"]}}}
    case = parse_case(data)
    fit = inverse_pim(case, case.unknown)
    block = solve_samples(case, fit, case.unknown, 50, np.random.default_rng(0))
    assert "vehicle1.yaw_inertia" in block.uniforms


def _write(tmp_path, text_units="si"):
    path = tmp_path / f"case-{text_units}.toml"
    mass, wheelbase = ("1500 kg", "2.7 m") if text_units == "si" else ("3307 lb", "106.3 inch")
    path.write_text(f"""
[vehicle1]
mass = "{mass}"
wheelbase = "{wheelbase}"
cg = ["-2 m", "0 m"]
heading = "0 deg"
velocity = ["15 m/s", "0 m/s"]
[vehicle2]
mass = "1700 kg"
yaw_inertia = "2900 kg*m**2"
cg = ["1 m", "-2 m"]
heading = "90 deg"
velocity = ["0 m/s", "5 m/s"]
[impact]
point = [0, 0]
normal_angle = "180 deg"
restitution = 0.2
beta = 1
""")
    return path


def _pim(*args):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "pim_entry", *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=300, cwd=ROOT)


@pytest.mark.parametrize("units, value, unit", [("si", "2981 kg m^2", "2.7 m"),
                                               ("us", "slug ft^2", "8.858 ft")])
def test_command_line_notes_the_estimate_once_in_the_case_units(tmp_path, units, value, unit):
    run = _pim("solve", _write(tmp_path, units))
    assert run.returncode == 0, run.stderr
    notes = [line for line in run.stderr.splitlines() if line.startswith("note:")]
    assert len(notes) == 1, run.stderr
    (note,) = notes
    assert "vehicle1.yaw_inertia not given: estimated" in note and value in note
    assert f"wheelbase L {unit}" in note and "±7.0 % (1 sd)" in note
    assert "Heydinger et al. 1999" in note and "a = L/2 assumed" in note


def test_uncertainty_json_carries_the_estimate(tmp_path):
    run = _pim("uncertainty", _write(tmp_path), "--samples", "2000", "--json")
    assert run.returncode == 0, run.stderr
    (estimate,) = json.loads(run.stdout)["estimates"]
    assert estimate["input"] == "vehicle1.yaw_inertia" and estimate["unit"] == "kg m^2"
    assert estimate["value"] == pytest.approx(PUBLISHED_CAR_INDEX * 1500 * 2.7**2 / 4,
                                              rel=5e-4)
    assert estimate["sd"] / estimate["value"] == pytest.approx(0.07, abs=0.005)


def test_compare_report_tags_the_estimate():
    from comparisons.report import inputs_table
    from comparisons.report_data import monte_carlo_note

    case = parse_case(_data())
    rows = {(r[0], r[1]): r[2] for r in inputs_table(case, "si").rows}
    tag = ("yaw inertia (estimated, ±7.0 % (1 sd), NHTSA's measured vehicles, "
           "Heydinger et al. 1999)")
    assert rows[("vehicle 1", tag)] == pytest.approx(case.estimates[0].value)
    assert ("vehicle 2", "yaw inertia") in rows                  # given: no tag
    note = monte_carlo_note(case)
    assert "`vehicle1.yaw_inertia`" in note and "±7.0 %" in note
    assert "[uncertainty]` table" not in note          # the file has none: only the estimate


def test_reconstruct_json_and_report_list_the_estimate(tmp_path, capsys):
    from pim.cli.reconstruct import reconstruct

    path = tmp_path / "rec.toml"
    text = _write(tmp_path).read_text().replace('velocity = ["15 m/s", "0 m/s"]',
                                                'velocity = ["0 m/s", "0 m/s"]')
    path.write_text(text + """
[measured]
vehicle1.velocity = ["9.8 m/s", "2.3 m/s"]
vehicle1.yaw_rate = "135 deg/s"
vehicle2.velocity = ["4.6 m/s", "2.9 m/s"]
vehicle2.yaw_rate = "-237 deg/s"
[unknown]
vehicle1.speed = {bounds = ["0 m/s", "40 m/s"]}
""")
    reconstruct.main([str(path), "--samples", "20", "--json"], standalone_mode=False)
    (estimate,) = json.loads(capsys.readouterr().out)["estimates"]
    assert estimate["input"] == "vehicle1.yaw_inertia" and estimate["assumed"] == ["a = L/2"]
    out = tmp_path / "out"
    reconstruct.main([str(path), "--samples", "20", "--out", str(out), "--no-video"],
                     standalone_mode=False)
    for name in ("report.md", "report.html"):
        assert "vehicle1.yaw_inertia not given: estimated 2981 kg m^2" in (out / name).read_text()
