"""pim validate-models and pim pulses (pim_cli.models)."""

import json

from click.testing import CliRunner

from pim_cli.main import cli as main_group
from pim_cli.main import main


def test_pulses_command(tmp_path, capsys):
    code = main(["pulses", "--out", str(tmp_path), "--json"])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    # issue 27: the one pipeline writes pulses.html too, leading with the answer
    assert {p.split("/")[-1] for p in data["files"]} == {"pulses.md", "pulses.html",
                                                         "pulses-nhtsa10146.csv", "pulses.png"}
    assert "pim pulses" in (tmp_path / "pulses.md").read_text()
    page = (tmp_path / "pulses.html").read_text()
    peak = next(r for r in data["rows"] if r["quantity"] == "peak force")
    cards = page.split('<dl class="facts">')[1].split("</dl>")[0]
    assert "error in peak force" in cards and f"{peak['error [%]']:+.0f} %" in cards
    assert page.index('<dl class="facts">') < page.index('id="table-pulses-nhtsa10146"')


def test_pulses_speaks_the_chosen_speed_unit(tmp_path, capsys):
    assert main(["pulses", "--out", str(tmp_path), "--units", "us"]) == 0
    page = (tmp_path / "pulses.html").read_text()
    assert "mph" in page.split('<dl class="facts">')[1].split("</dl>")[0]
    md = (tmp_path / "pulses.md").read_text()
    assert "| rebound speed | fitted: eps from this test's rebound | mph |" in md
    assert "| km/h |" not in md


def test_pulses_rejects_a_bad_restitution(tmp_path):
    from pim_cli.models import pulses

    res = CliRunner().invoke(pulses, ["--eps", "1.5", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "--eps" in res.output


def test_validate_models_rejects_too_few_tests(tmp_path):
    from pim_cli.models import validate_models

    res = CliRunner().invoke(validate_models, ["--max-tests", "1", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "--max-tests" in res.output


def test_validate_models_json_reports_verdicts_p_values_and_medians(tmp_path, capsys):
    """Two small classes (the full run is tests/comparisons/docs): per class and input
    variant a verdict and p-value, per model the leave-one-out medians [m/s, deg/s] and
    the multi-start agreement counts; the files written whole."""
    out = tmp_path / "vm"
    code = main(["validate-models", "--class", "ricsac", "--class", "car-to-car", "--out",
                 str(out), "--json", "--no-progress"])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert list(data["classes"]) == ["ricsac", "car-to-car"] and data["wall_time"] > 0
    for key, cls in data["classes"].items():
        assert key in cls["name"].lower()
        for variant in cls["variants"].values():
            assert variant["verdict"] == "too few tests to decide"      # 3 and 4 tests
            assert "p_value" in variant
            for model in ("pim", "scene", "scene-mu0"):
                m = variant["models"][model]
                assert m["loo_velocity_median"] > 0 and m["loo_yaw_median"] > 0
                assert 1 <= m["class_fit"]["agreeing"] <= m["class_fit"]["starts"]
                assert len(m["loo_starts"]["agreeing"]) == len(cls["tests"])
        phys, prof = cls["physical"], cls["profile"]                   # issue 34
        assert phys["verdict"] == "too few tests to decide" and len(phys["interval"]) == 2
        assert phys["class_fit"]["x"]["T [s]"] >= 0.05
        assert prof["T"][0] == 0.02 and prof["T"][-1] == 0.25         # seconds
        assert len(prof["score"]) == len(prof["parameters"]) == len(prof["T"])
        assert prof["threshold"] > prof["best_score"] > 0
        assert cls["conclusion"].startswith(f"**{cls['name']}**")
    assert data["classes"]["car-to-car"]["outcome_origin"] == "PIM analysis output"
    assert {p.split("/")[-1] for p in data["files"]} >= {"tuned-scene.md", "tuned-scene.html"}
    assert "--class ricsac" in (out / "tuned-scene.md").read_text()
    page = (out / "tuned-scene.html").read_text()                 # issue 27: the pipeline's
    first = page.index('<section id="verdicts"')                    # after the conclusion
    assert page.index('<section id="conclusion"') < first
    assert first < page.index("too few tests to decide", first) < page.index('<section id="method"')


def test_validate_models_prints_the_wall_time(tmp_path):
    res = CliRunner().invoke(main_group, ["validate-models", "--class", "ricsac9", "--out",
                                          str(tmp_path / "one")])
    assert res.exit_code == 0, res.output
    assert "too few tests to decide" in res.output and "wall time" in res.output
    assert res.output.startswith("RICSAC 9, design sheet (1 test, published inputs). A class "
                                 "of one")                    # the conclusion first
