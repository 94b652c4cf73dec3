"""Sensitivities: closed-form d/d(eps, beta) and the effect of uncertain inputs."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

import pim
from pim import fit
from pim.analysis.sensitivity import INPUTS, TypicalUncertainty, sensitivity
from pim_cli.main import main

#: 1 slug [kg] by exact definitions (1 lb = 0.45359237 kg, g0 = 9.80665 m/s^2, 1 ft = 0.3048 m).
SLUG = 0.45359237 * 9.80665 / 0.3048


@pytest.fixture(scope="module")
def noisy(ricsac9):
    """Measured values near (0.4, 0.6) plus noise: an interior optimum with residuals."""
    r = pim.solve(ricsac9, 0.4, 0.6)
    rng = np.random.default_rng(7)
    return replace(ricsac9, measured=pim.Measured(
        r.velocity1 + rng.normal(0, 0.3, 2), r.velocity2 + rng.normal(0, 0.3, 2),
        float(r.yaw_rate1) + 0.1, float(r.yaw_rate2) - 0.1))










def _moved(case, key, step):
    """The case with one input moved by ``step`` (written out here, independent of the module)."""
    v1, v2, imp, m = case.vehicle1, case.vehicle2, case.impact, case.measured
    if key.startswith("measured."):
        name = key[len("measured."):]
        if name.startswith("velocity"):
            i, axis = int(name[8]), "xy".index(name[-1])
            v = np.array(getattr(m, f"velocity{i}"), dtype=float)
            v[axis] += step
            return replace(case, measured=replace(m, **{f"velocity{i}": v}))
        i = int(name[-1])
        return replace(case, measured=replace(m, **{name: getattr(m, name) + step}))
    if key.startswith("impact.point"):
        p = np.array(imp.point, dtype=float)
        p["xy".index(key[-1])] += step
        return replace(case, impact=replace(imp, point=p))
    if key == "impact.normal_angle":
        return replace(case, impact=replace(imp, normal_angle=imp.normal_angle + step))
    group, field = key.split(".")
    v = v1 if group == "vehicle1" else v2
    if field.startswith("velocity"):
        vel = np.array(v.velocity, dtype=float)
        vel["xy".index(field[-1])] += step
        v = replace(v, velocity=vel)
    else:
        v = replace(v, **{field: getattr(v, field) + step})
    return replace(case, **{group: v})


@pytest.mark.parametrize("which, include_yaw", [("ricsac9", False), ("noisy", True)])
def test_fitted_parameters_match_brute_force_refits(request, which, include_yaw):
    case = request.getfixturevalue(which)
    sens = sensitivity(case, include_yaw=include_yaw)
    keys = ["impact.point_x", "impact.point_y", "impact.normal_angle", "vehicle1.mass",
            "vehicle2.yaw_inertia", "vehicle2.velocity_x", "vehicle1.yaw_rate",
            "measured.velocity1_x", "measured.velocity2_y"]
    if include_yaw:
        keys.append("measured.yaw_rate1")
    for key in keys:
        k = sens.inputs.index(key)
        h = 1e-2 * sens.sigma[k]
        plus = fit(_moved(case, key, h), include_yaw=include_yaw)
        minus = fit(_moved(case, key, -h), include_yaw=include_yaw)
        # compared per typical uncertainty (derivative x sigma): the refits converge to
        # ~1e-10, which limits the finite difference to ~1e-7 absolute
        sigma = sens.sigma[k]
        for row, (a, b) in enumerate([(plus.eps, minus.eps), (plus.beta, minus.beta)]):
            fd = (a - b) / (2 * h)
            expected = pytest.approx(fd * sigma, rel=2e-4, abs=1e-6)
            assert sens.derivative[row, k] * sigma == expected, (key, row)
        dv = float(plus.result.delta_v1_magnitude - minus.result.delta_v1_magnitude) / (2 * h)
        assert sens.derivative[2, k] * sigma == pytest.approx(dv * sigma, rel=2e-4, abs=1e-6), key


def test_active_bound_holds_beta(ricsac9):
    sens = sensitivity(ricsac9)
    assert sens.active_bounds == ("beta",)
    assert np.all(sens.derivative[sens.outputs.index("beta")] == 0)
    assert sens.values[0] == pytest.approx(0.355, abs=0.002)


def test_partial_delta_v_matches_finite_differences(spinning):
    sens = sensitivity(spinning, eps=0.4, beta=0.7)
    assert sens.fit is None and sens.outputs == ("delta_v1_magnitude", "delta_v2_magnitude")
    for k, key in enumerate(sens.inputs):
        h = 1e-4 * sens.sigma[k]
        plus = pim.solve(_moved(spinning, key, h), 0.4, 0.7)
        minus = pim.solve(_moved(spinning, key, -h), 0.4, 0.7)
        for i in (1, 2):
            name = f"delta_v{i}_magnitude"
            fd = (getattr(plus, name) - getattr(minus, name)) / (2 * h)
            assert sens.derivative[i - 1, k] == pytest.approx(float(fd), rel=1e-5, abs=1e-9), key


def test_inputs_sigmas_and_ranking(ricsac9):
    unc = TypicalUncertainty(point=0.3, mass_fraction=0.05)
    sens = sensitivity(replace(ricsac9, uncertainty=None), uncertainty=unc)  # typical only
    assert set(sens.inputs) <= set(INPUTS)
    k = sens.inputs.index("vehicle1.mass")
    assert sens.sigma[k] == pytest.approx(0.05 * float(ricsac9.vehicle1.mass))
    assert sens.sigma[sens.inputs.index("impact.point_y")] == 0.3
    assert sens.sigma[sens.inputs.index("impact.normal_angle")] == pytest.approx(np.radians(5))
    order = sens.ranked("delta_v1_magnitude")
    effects = sens.effect[sens.outputs.index("delta_v1_magnitude")][order]
    assert np.all(np.diff(effects) <= 0)
    assert "measured.yaw_rate1" not in sens.inputs  # yaw not fitted (no sigma)
    assert "measured.yaw_rate1" in sensitivity(ricsac9, include_yaw=True).inputs
    # issue 33: the case's own [uncertainty] wins over the typical values, unless preferred
    own = sensitivity(ricsac9, uncertainty=unc)
    assert own.sigma[k] == pytest.approx(1.4 * SLUG) and own.sources[k] == "case"
    assert sensitivity(ricsac9, uncertainty=unc, prefer=("mass_fraction",)).sigma[k] == \
        pytest.approx(0.05 * float(ricsac9.vehicle1.mass))


def test_bad_uncertainty_and_missing_eps(ricsac9):
    with pytest.raises(ValueError, match="point"):
        TypicalUncertainty(point=-0.1)
    bare = replace(ricsac9, measured=None, impact=replace(ricsac9.impact, restitution=None))
    with pytest.raises(ValueError, match="eps"):
        sensitivity(bare)
    assert sensitivity(bare, eps=0.3).fit is None


def test_cli_sensitivity(capsys):
    assert main(["sensitivity", "ricsac9", "--top", "5"]) == 0
    out = capsys.readouterr().out
    assert "fitted epsilon" in out and "|delta-V| of vehicle 1" in out
    assert "held on an active bound" in out
    assert main(["sensitivity", "ricsac9", "--sigma", "point=0.2 m", "--units", "us"]) == 0
    assert "0.6562 ft" in capsys.readouterr().out
    assert main(["sensitivity", "ricsac9", "--sigma", "nonsense=1"]) == 2
    assert "--sigma must be KEY=VALUE" in capsys.readouterr().err


def _with_sigmas(case, s1=0.3):
    m = case.measured
    return replace(case, measured=replace(m, velocity1_sigma=[s1, s1],
                                          velocity2_sigma=[0.3, 0.3]))


def test_stated_sigmas_weight_the_fit_and_size_the_inputs(noisy):
    """issue 22: `sensitivity` used the typical sigma for the measured values and the
    unweighted cost even when [measured] states sigmas. Now the stated sigma is the
    input's sigma, and d(eps, beta)/d(measured) is that of the weighted refit: checked by
    brute-force refits of the weighted fit, and doubling vehicle 1's sigma halves its
    weight (its values pull the refit less, vehicle 2's more)."""
    for s1 in (0.3, 0.6):
        case = _with_sigmas(noisy, s1)
        sens = sensitivity(case)
        k = sens.inputs.index("measured.velocity1_x")
        assert sens.sigma[k] == s1
        assert sens.sigma[sens.inputs.index("measured.velocity2_y")] == 0.3
        for key in ("measured.velocity1_x", "measured.velocity2_y", "impact.point_x"):
            k = sens.inputs.index(key)
            h = 1e-2 * sens.sigma[k]
            plus, minus = fit(_moved(case, key, h)), fit(_moved(case, key, -h))
            for row, (a, b) in enumerate([(plus.eps, minus.eps), (plus.beta, minus.beta)]):
                fd = (a - b) / (2 * h)
                assert sens.derivative[row, k] == pytest.approx(fd, rel=1e-3, abs=1e-7), \
                    (s1, key, row)
    d = {s1: sensitivity(_with_sigmas(noisy, s1)) for s1 in (0.3, 0.6)}
    k1 = d[0.3].inputs.index("measured.velocity1_x")
    k2 = d[0.3].inputs.index("measured.velocity2_x")
    assert abs(d[0.6].derivative[0, k1]) < abs(d[0.3].derivative[0, k1])
    assert abs(d[0.6].derivative[0, k2]) > abs(d[0.3].derivative[0, k2])


def test_sensitivity_of_a_fit_to_recorded_evidence():
    """A fit to a recorded delta-V and pre-crash speed (synthetic-edr): the recorded values
    are inputs of the sensitivity like measured motion, each with its stated sigma."""
    from pim.analysis.sensitivity import sensitivity

    case = pim.load_case("synthetic-edr")
    s = sensitivity(case)
    i = s.inputs.index("measured.delta_v1_long")
    assert s.sigma[i] == pytest.approx(1 / 3.6)
    assert np.all(np.isfinite(s.derivative[:, i])) and np.any(s.derivative[:, i] != 0)


def test_sensitivity_names_the_argument_given_a_string():
    """Issue 28: pim.sensitivity(case, uncertainty='x') failed with an AttributeError."""
    with pytest.raises(TypeError, match=r"^uncertainty must be a "
                                        r"pim.analysis.sensitivity.TypicalUncertainty or None, "
                                        r"got 'x'$"):
        sensitivity(pim.load_case("ricsac9"), uncertainty="x")


def test_typical_kinds_cover_every_typical_uncertainty():
    import dataclasses

    from pim.analysis.sensitivity import TYPICAL_KINDS, TypicalUncertainty

    assert set(TYPICAL_KINDS) == {f.name for f in dataclasses.fields(TypicalUncertainty)}
    assert TYPICAL_KINDS["point"] == "length" and TYPICAL_KINDS["yaw_rate"] == "angular_velocity"


# --- Issue 33: the case's own uncertainties -------------------------------------------------

FT = 0.3048


def test_the_case_s_uncertainty_table_sets_the_sigmas_and_says_so(ricsac9):
    """Issue 33: pim sensitivity used its typical sigmas where [uncertainty] stated others.
    ricsac9.toml: vehicle2.mass normal 3 slug, vehicle1.velocity_x normal 1 ft/s,
    impact.point_x +- 0.5 ft (uniform: sd 0.5 ft / sqrt(3)), impact.normal_angle +- 5 deg;
    the rest typical."""
    sens = sensitivity(ricsac9)
    sigma = dict(zip(sens.inputs, sens.sigma, strict=True))
    source = dict(zip(sens.inputs, sens.sources, strict=True))
    assert sigma["vehicle2.mass"] == pytest.approx(3 * SLUG, rel=1e-12)
    assert sigma["vehicle1.velocity_x"] == pytest.approx(FT, rel=1e-12)
    assert sigma["impact.point_x"] == pytest.approx(0.5 * FT / np.sqrt(3), rel=1e-12)
    assert sigma["impact.normal_angle"] == pytest.approx(np.radians(5) / np.sqrt(3), rel=1e-12)
    assert {k for k, v in source.items() if v == "case"} == {
        "vehicle1.mass", "vehicle2.mass", "vehicle1.velocity_x", "vehicle2.velocity_y",
        "impact.point_x", "impact.point_y", "impact.normal_angle"}
    typical = TypicalUncertainty()
    assert source["vehicle2.yaw_inertia"] == "typical"
    assert sigma["vehicle2.yaw_inertia"] == pytest.approx(
        typical.inertia_fraction * float(ricsac9.vehicle2.yaw_inertia))
    row = sens.to_dict()["outputs"]["eps"]["inputs"]
    assert {r["input"]: r["source"] for r in row} == source


def test_an_estimate_s_scatter_and_a_fixed_input(tmp_path):
    """An estimated yaw inertia takes its estimate's sd ("estimate"); an input the table
    fixes has sigma 0 and no effect, its derivative still finite."""
    from pathlib import Path

    text = (Path(__file__).parents[2] / "data" / "no-yaw-inertia.toml").read_text()
    path = tmp_path / "case.toml"
    path.write_text(text + '\n[uncertainty]\nvehicle2.mass = {fixed = "1700 kg"}\n')
    case = pim.load_case(path)
    sens = sensitivity(case, eps=0.2, beta=1.0)
    k = sens.inputs.index("vehicle1.yaw_inertia")
    assert sens.sources[k] == "estimate" and sens.sigma[k] == pytest.approx(case.estimates[0].sd)
    m = sens.inputs.index("vehicle2.mass")
    assert sens.sources[m] == "case" and sens.sigma[m] == 0.0
    assert np.all(sens.effect[:, m] == 0) and np.all(np.isfinite(sens.derivative[:, m]))
    assert np.any(sens.derivative[:, m] != 0)


def test_the_command_line_shows_the_source_and_sigma_wins_over_the_case(capsys):
    assert main(["sensitivity", "ricsac9"]) == 0
    out = capsys.readouterr().out
    assert "sigma source: case = the case file's [uncertainty] or [measured] sigma" in out
    row = next(x for x in out.splitlines() if x.strip().startswith("mass of vehicle 2"))
    assert row.split()[4:7] == ["3", "slug", "case"], row
    assert main(["sensitivity", "ricsac9", "--sigma", "mass_fraction=0.05", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    rows = {r["input"]: r for r in data["outputs"]["eps"]["inputs"]}
    assert rows["vehicle2.mass"]["source"] == "option"
    assert rows["impact.point_x"]["source"] == "case"
