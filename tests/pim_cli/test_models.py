"""pim validate-models and pim pulses (pim_cli.models)."""

import json

from click.testing import CliRunner

from pim_cli.main import main


def test_pulses_command(tmp_path, capsys):
    code = main(["pulses", "--out", str(tmp_path), "--json"])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert {p.split("/")[-1] for p in data["files"]} == {"pulses.md", "pulses-nhtsa10146.csv",
                                                         "pulses.html", "pulses.png"}
    assert "pim pulses" in (tmp_path / "pulses.md").read_text()


def test_pulses_rejects_a_bad_restitution(tmp_path):
    from pim_cli.models import pulses

    res = CliRunner().invoke(pulses, ["--eps", "1.5", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "--eps" in res.output


def test_validate_models_rejects_too_few_tests(tmp_path):
    from pim_cli.models import validate_models

    res = CliRunner().invoke(validate_models, ["--max-tests", "1", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "--max-tests" in res.output
