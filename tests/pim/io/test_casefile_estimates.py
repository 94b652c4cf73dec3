"""A case file without a yaw inertia (issue 28, point 5): the estimate from mass and
wheelbase on load, the error naming what is missing, and the estimate's scatter in the
Monte Carlo of ``pim uncertainty`` and of the reconstruction. The note on stderr and the JSON
are tested in tests/pim_cli/test_estimates.py, the reports' tags in
tests/comparisons/report/test_estimates.py."""

import tomllib
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
from tests.published_cg import car_estimate, car_fraction

CASE = Path(__file__).resolve().parents[2] / "data" / "no-yaw-inertia.toml"


def _data(**vehicle1):
    """The case file of CASE, its vehicle 1 keys replaced (None: removed)."""
    data = tomllib.loads(CASE.read_text())
    data["vehicle1"] = {k: v for k, v in {**data["vehicle1"], **vehicle1}.items()
                        if v is not None}
    return data


def test_case_without_inertia_loads_with_the_estimate_and_solves():
    case = pim.load_case(CASE)
    (estimate,) = case.estimates
    assert estimate.name == "vehicle1.yaw_inertia"
    # D m L^2 E[f (1 - f)]: the published index (to its printed digits) and the cars' CG
    # position from the NCAP table's own front-weight column (tests/published_cg.py)
    assert float(case.vehicle1.yaw_inertia) == pytest.approx(car_estimate(), rel=5e-4)
    assert float(case.vehicle1.yaw_inertia) == estimate.value
    assert 0.07 < estimate.relative_sd < 0.08
    (assumed,) = estimate.assumptions
    assert assumed.startswith("a = 0.397 L") and "NCAP 2004" in assumed
    result = pim.solve(case)
    assert result.problems() == []
    # momentum is exchanged whatever the inertia: the two delta-Vs balance
    assert 1500 * np.asarray(result.delta_v1) == pytest.approx(
        -1700 * np.asarray(result.delta_v2))


def test_axle_position_and_body_class_change_the_estimate():
    base = parse_case(_data()).vehicle1.yaw_inertia
    middle = parse_case(_data(cg_to_front_axle="1.35 m")).vehicle1.yaw_inertia
    forward = parse_case(_data(cg_to_front_axle="1.08 m")).vehicle1.yaw_inertia
    assert forward / middle == pytest.approx(4 * 0.4 * 0.6)       # a b = 0.24 L^2
    # without the axle: E[f (1 - f)] of the cars' measured CG position, below the half's 1/4
    mu, s = car_fraction()
    assert base / middle == pytest.approx(4 * (mu * (1 - mu) - s * s), rel=1e-9)
    pickup = parse_case(_data(body="pickup"))
    assert pickup.vehicle1.yaw_inertia < base
    assert "pickup" in pickup.estimates[0].method
    with pytest.raises(InputError, match=r"vehicle1\.body must be one of"):
        parse_case(_data(body="bus"))


def test_without_wheelbase_the_mass_alone_estimates_it():
    """No wheelbase (refused before issue 33 point 4): the mass-only line of the body's
    group, as an estimate with its wider scatter, drawn in the Monte Carlo; a mass outside
    the line's vehicles is refused naming what to give."""
    from pim.io.inertia_data import mass_regressions

    case = parse_case(_data(wheelbase=None))
    (estimate,) = case.estimates
    line = mass_regressions()["car"]
    assert float(case.vehicle1.yaw_inertia) == pytest.approx(line.slope * 1500
                                                             + line.intercept)
    assert estimate.value == float(case.vehicle1.yaw_inertia)
    assert 0.10 < estimate.relative_sd < 0.13 and "without a wheelbase" in estimate.method
    dist = case.uncertainty.inputs["vehicle1.yaw_inertia"]
    assert (dist.kind, dist.b) == ("normal", estimate.sd)
    values, _ = sample_inputs(case.uncertainty, nominal_values(case), 20_000,
                              np.random.default_rng(2))
    assert values["vehicle1.yaw_inertia"].std() == pytest.approx(estimate.sd, rel=0.03)
    with pytest.raises(InputError) as info:
        parse_case(_data(wheelbase=None, mass="3000 kg"))
    text = str(info.value)
    assert "vehicle1" in text and "yaw_inertia" in text and "wheelbase" in text
    with pytest.raises(InputError, match="exactly one of 'yaw_inertia' or 'radius_of"):
        parse_case(_data(yaw_inertia="2500 kg*m**2", radius_of_gyration="1.3 m"))


def test_without_wheelbase_a_cars_length_estimates_it_through_the_wheelbase():
    """Mass and overall length, no wheelbase (issue 33 point 4: the length was ignored and
    the mass-only line used): the index's estimate with the wheelbase from Lock's 1993 cars'
    line, narrower than the mass-only line's, its scatter in the Monte Carlo. Expected value
    from the published index and the NCAP table's own column (tests/published_cg.py) and
    an independent least-squares fit of the bundled Cars93 rows."""
    from scipy.stats import linregress

    from pim.io.inertia_data import mass_regressions
    from tests.pim.io.test_length_data import _raw

    cars = [r for r in _raw() if r["type"] != "Van"]
    fit = linregress([float(r["length_in"]) * 0.0254 for r in cars],
                     [float(r["wheelbase_in"]) * 0.0254 for r in cars])
    wheelbase = fit.slope * 4.6 + fit.intercept
    case = parse_case(_data(wheelbase=None, length="4.6 m", width="1.8 m"))
    (estimate,) = case.estimates
    # E[L^2] = mu^2 + s^2 (s ~ 7 cm: 0.07 % of the estimate); the rest as with a wheelbase
    assert float(case.vehicle1.yaw_inertia) == pytest.approx(
        car_estimate(wheelbase=wheelbase), rel=2e-3)
    assert "L from the overall length l" in estimate.method
    assert any("line of the wheelbase L on the length l" in a for a in estimate.assumptions)
    mass_only = mass_regressions()["car"].predictive_sd(1500.0)
    assert 0.075 < estimate.relative_sd < mass_only
    dist = case.uncertainty.inputs["vehicle1.yaw_inertia"]
    assert (dist.kind, dist.b) == ("normal", estimate.sd)


@pytest.mark.parametrize("change, why", [
    ({"body": "suv"}, "no line of the wheelbase on the overall length for a suv"),
    ({"length": "6.5 m"}, "the overall length lies outside the lengths of the 84 cars"),
])
def test_a_length_the_wheelbase_line_cannot_use_falls_back_to_the_mass_line(change, why):
    from pim.io.inertia_data import mass_regressions, regression_group

    case = parse_case(_data(**{"wheelbase": None, "length": "4.6 m", "width": "1.8 m",
                               **change}))
    (estimate,) = case.estimates
    line = mass_regressions()[regression_group(change.get("body", "car"))]
    assert estimate.value == pytest.approx(line.slope * 1500 + line.intercept)
    assert "without a wheelbase" in estimate.method and why in estimate.method


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


def test_swapped_case_renames_the_estimate():
    case = pim.load_case(CASE).swapped()
    assert [e.name for e in case.estimates] == ["vehicle2.yaw_inertia"]
    assert float(case.vehicle2.yaw_inertia) == case.estimates[0].value


def test_uncertainty_table_gets_the_estimates_scatter_unless_it_gives_one():
    case = pim.load_case(CASE)
    dist = case.uncertainty.inputs["vehicle1.yaw_inertia"]
    assert (dist.kind, dist.a, dist.b) == ("normal", None, case.estimates[0].sd)
    data = _data()
    data["uncertainty"] = {"vehicle1": {"yaw_inertia": {"plusminus": "100 kg*m**2"}},
                           "vehicle2": {"mass": {"normal": "20 kg"}}}
    own = parse_case(data).uncertainty.inputs
    assert own["vehicle1.yaw_inertia"].kind == "plusminus" and "vehicle2.mass" in own


def test_monte_carlo_draws_the_estimate_with_its_scatter():
    case = pim.load_case(CASE)
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
    block = solve_samples(case, inverse_pim(case, case.unknown), case.unknown, 50,
                          np.random.default_rng(0))
    assert "vehicle1.yaw_inertia" in block.uniforms


def test_docs_example_note_is_what_the_code_prints():
    from pim.io.inertia_data import estimate_notes

    (line,) = estimate_notes(pim.load_case(CASE), "si")
    docs = Path(__file__).resolve().parents[3] / "docs" / "inertia-estimate.md"
    assert f"\n{line}\n" in docs.read_text()


def test_docs_example_note_without_a_wheelbase_is_what_the_code_prints():
    from pim.io.inertia_data import estimate_notes

    (line,) = estimate_notes(parse_case(_data(wheelbase=None)), "si")
    docs = Path(__file__).resolve().parents[3] / "docs" / "inertia-estimate.md"
    assert f"\n{line}\n" in docs.read_text()


def test_docs_example_note_with_the_length_is_what_the_code_prints():
    from pim.io.inertia_data import estimate_notes

    (line,) = estimate_notes(parse_case(_data(wheelbase=None, length="4.6 m")), "si")
    docs = Path(__file__).resolve().parents[3] / "docs" / "inertia-estimate.md"
    assert f"\n{line}\n" in docs.read_text()
