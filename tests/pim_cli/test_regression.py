"""pim baseline and pim check on the command line: exit codes 0 / 1 / 2, the drift table,
--json, one line for a bad baseline."""

import json
import shutil
from importlib import resources

import pytest

from pim_cli import regression as regression_cli
from pim_cli.main import main

RICSAC9 = resources.files("pim.io") / "cases" / "ricsac9.toml"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """A copied case and its baseline, written by pim baseline."""
    folder = tmp_path_factory.mktemp("cli")
    shutil.copy(RICSAC9, folder / "mine.toml")
    assert main(["baseline", str(folder / "mine.toml"), "--without", "uncertainty",
                 "--out", str(folder / "b.json")]) == 0
    return folder


def test_baseline_then_check_is_exit_0(folder, capsys):
    doc = json.loads((folder / "b.json").read_text())
    assert doc["sections"] == ["solve", "fit", "crosscheck", "reconstruct"]
    assert main(["check", str(folder / "b.json")]) == 0
    assert "within tolerance" in capsys.readouterr().out


def test_the_commands_run_from_their_module(folder, tmp_path, capsys):
    """regression_cli's click commands on their own (outside pim's group): check returns 0
    on the unchanged baseline and DRIFT_EXIT_CODE after the case file changed."""
    assert regression_cli.check.main([str(folder / "b.json"), "--json"],
                                      standalone_mode=False) == 0
    assert json.loads(capsys.readouterr().out)["ok"] is True
    shutil.copy(folder / "b.json", tmp_path / "b.json")
    text = (folder / "mine.toml").read_text().replace("4896.2 lbf", "5200 lbf")
    (tmp_path / "mine.toml").write_text(text)
    assert regression_cli.check.main([str(tmp_path / "b.json")], standalone_mode=False) \
        == regression_cli.DRIFT_EXIT_CODE == 1


def test_a_changed_mass_is_exit_1_with_a_readable_table(folder, tmp_path, capsys,
                                                         monkeypatch):
    monkeypatch.chdir(tmp_path)      # the case is shown by its path from the current folder
    shutil.copy(folder / "b.json", tmp_path / "b.json")
    text = (folder / "mine.toml").read_text().replace("4896.2 lbf", "5200 lbf")
    (tmp_path / "mine.toml").write_text(text)
    assert main(["check", str(tmp_path / "b.json")]) == 1
    out = capsys.readouterr().out
    assert "input changed: mine.toml" in out
    header = next(line for line in out.splitlines() if line.startswith("case"))
    assert header.split()[:6] == ["case", "quantity", "baseline", "now", "difference",
                                  "tolerance"]
    row = next(line for line in out.splitlines() if "solve.velocity2_y" in line)
    assert row.split()[-2:] == ["mph", "baseline"]        # the case's units (US: mph)
    assert main(["check", str(tmp_path / "b.json"), "--units", "si", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["ok"] is False and data["input_changes"]
    assert {"solve.velocity2_y", "fit.eps"} <= {d["quantity"] for d in data["drifts"]}
    drift = next(d for d in data["drifts"] if d["quantity"] == "solve.velocity2_y")
    assert drift["unit"] == "km/h" and drift["si_unit"] == "m/s"          # --units si


@pytest.mark.parametrize("text", ["{", '{"format": "pim-baseline/1", "cases": "x"}', ""])
def test_a_corrupted_baseline_is_exit_2_and_one_line(tmp_path, capsys, text):
    (tmp_path / "b.json").write_text(text)
    assert main(["check", str(tmp_path / "b.json")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and "\n" not in err and "b.json" in err


def test_a_missing_baseline_is_exit_2(tmp_path, capsys):
    assert main(["check", str(tmp_path / "none.json")]) == 2
    assert "no such baseline file" in capsys.readouterr().err


def test_baseline_of_an_unknown_case_is_exit_2(tmp_path, capsys):
    assert main(["baseline", "no-such-case", "--out", str(tmp_path / "b.json")]) == 2
    assert "no-such-case" in capsys.readouterr().err
    assert not (tmp_path / "b.json").exists()


def test_assumptions_are_opt_in_and_check_clean(tmp_path, capsys):
    out = tmp_path / "b.json"
    assert main(["baseline", "hard-pole", "--with", "assumptions", "--without", "crosscheck",
                 "--out", str(out)]) == 0
    entry = json.loads(out.read_text())["cases"][0]
    assert entry["sections"] == ["solve", "assumptions"]
    q = entry["quantities"]["assumptions.instantaneous.delta_v1"]
    assert q["tolerance"]["absolute"] == 1e-3 and "contact-model.md" in q["tolerance_basis"]
    assert "assumptions" in entry["seconds"]
    assert main(["check", str(out)]) == 0


def test_check_names_dependency_versions_that_differ(folder, tmp_path, capsys):
    doc = json.loads((folder / "b.json").read_text())
    doc["versions"]["pymunk"] = "6.0.0"
    (tmp_path / "b.json").write_text(json.dumps(doc))
    shutil.copy(folder / "mine.toml", tmp_path / "mine.toml")
    assert main(["check", str(tmp_path / "b.json")]) == 0
    assert "version differs: pymunk 6.0.0 ->" in capsys.readouterr().out
    assert main(["check", str(tmp_path / "b.json"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["version_changes"]["pymunk"][0] == "6.0.0"
