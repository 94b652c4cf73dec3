"""`pim reconstruct` (pim.cli.reconstruct): refusal of a case without evidence, and the
synthetic case's report files and JSON (slow: two run-out fits)."""

import json

import pytest

from pim.cli.main import main

KNOWN = 31.09 * 0.3048


def test_case_without_evidence_is_one_line_and_exit_code_2(capsys):
    assert main(["reconstruct", "ricsac9"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "[evidence]" in err[0]


@pytest.mark.slow
def test_synthetic_case_report_and_json(tmp_path, capsys):
    assert main(["reconstruct", "synthetic-runout", "--out", str(tmp_path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("vehicle1.speed", "vehicle2.speed"):
        row = data["unknowns"][key]
        assert row["value"] == pytest.approx(KNOWN, abs=1e-5)
        assert row["p5"] < KNOWN < row["p95"]
    assert {p.name for p in tmp_path.iterdir()} == {"report.md", "reconstruction.csv",
                                                    "scene.png"}
    assert "vehicle1.speed" in (tmp_path / "report.md").read_text()
