"""Evidence that contradicts itself beyond P_CONTRADICTED (chi-square p < 0.001) ends
``pim fit``, ``pim compare``, ``pim plot`` and ``pim sensitivity`` with exit 1 after their output, the reason first, as it ends
``pim reconstruct`` (issue 33 point 3; tests/pim_cli/test_reconstruct.py has reconstruct's)."""

from __future__ import annotations

import json
from importlib import resources

import pytest

from pim.analysis.residuals import P_CONTRADICTED
from pim_cli.main import main

REASON = "error: the evidence contradicts itself: chi-square = 262.4 with 1 degrees of freedom"


def _edr(tmp_path, pre_crash_speed: str) -> str:
    """synthetic-edr (the truth: vehicle 2 at 28.8 km/h, recorded at 1 km/h) with vehicle
    2's recorded pre-crash speed replaced: at the given speeds the fit of (epsilon, beta)
    cannot move it, so 45 km/h lies 16 sigma off (p = 5e-59) and 31.5 km/h 2.7 sigma
    (p = 0.0069, between the warning's 0.01 and the refusal's 0.001)."""
    text = (resources.files("pim.io") / "cases" / "synthetic-edr.toml").read_text()
    path = tmp_path / f"edr-{pre_crash_speed.split()[0]}.toml"
    path.write_text(text.replace('pre_crash_speed = "28.8 km/h"',
                                 f'pre_crash_speed = "{pre_crash_speed}"'))
    return str(path)


def test_fit_exits_1_after_its_answer_when_the_evidence_contradicts_itself(tmp_path, capsys):
    case = _edr(tmp_path, "45 km/h")
    assert main(["fit", case]) == 1
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert err[0].startswith(REASON), err
    assert f"p = 5e-59 < {P_CONTRADICTED:g} (the refusal threshold)" in err[0]
    assert err[0].endswith("the evidence in conflict: pre_crash_speed2 -16 sigma"), err[0]
    # the recorder's delta-V, met to 3e-11 sigma by the fit, is round-off, not conflict
    assert err[-1] == ("error: the evidence contradicts itself (the reason above); "
                       "--allow-inconsistent accepts it")
    assert "epsilon = 0.2" in captured.out           # the answer is still printed
    for flag in ("--allow-inconsistent", "--allow-inadmissible"):
        assert main(["fit", case, flag]) == 0
        assert "error:" not in capsys.readouterr().err
    assert main(["fit", case, "--json", "--allow-inconsistent"]) == 0
    good = json.loads(capsys.readouterr().out)["goodness_of_fit"]
    assert good["contradicted"] is True and good["p_value"] < P_CONTRADICTED


def test_fit_of_doubtful_or_consistent_evidence_exits_0(tmp_path, capsys):
    """Between the warning (p < 0.01) and the refusal: the verdict's warning, exit 0."""
    assert main(["fit", _edr(tmp_path, "31.5 km/h")]) == 0
    captured = capsys.readouterr()
    assert "error" not in captured.err and "p = 0.0069 < 0.01" in captured.out
    assert main(["fit", "synthetic-edr"]) == 0
    assert "error" not in capsys.readouterr().err


def test_compare_exits_1_after_its_report_when_the_evidence_contradicts_itself(
        tmp_path, capsys, monkeypatch):
    """The report is written whole, the reason leads stderr and the report's results; the
    same report with --allow-inconsistent exits 0 (replayed: one compare run is enough)."""
    import comparisons.report.compare as report

    case, out = _edr(tmp_path, "45 km/h"), tmp_path / "report"
    runs = []
    real = report.compare_case

    def recorded(*args, **kwargs):
        runs.append(real(*args, **kwargs))
        return runs[-1]

    monkeypatch.setattr(report, "compare_case", recorded)
    args = ["compare", case, "--out", str(out), "--no-animation", "--no-speed-error",
            "--no-assumptions", "--no-progress"]
    assert main(args) == 1
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert err[0].startswith(REASON), err
    assert "--allow-inconsistent accepts it" in err[-1]
    assert "delta-V, vehicle 1:" in captured.out and "wrote " in captured.out
    text = (out / "report.md").read_text()
    results = text.split("The evidence contradicts itself (the answer below")[1]
    assert results.index("pre_crash_speed2 -16 sigma") < results.index("delta-V")
    monkeypatch.setattr(report, "compare_case", lambda *a, **k: runs[0])
    for flag in ("--allow-inconsistent", "--allow-inadmissible"):
        assert main([*args, flag]) == 0
        assert "error:" not in capsys.readouterr().err
    assert main([*args, "--json", "--allow-inconsistent"]) == 0
    assert json.loads(capsys.readouterr().out)["goodness_of_fit"]["contradicted"] is True


def test_plot_exits_1_after_writing_its_figures(tmp_path, capsys):
    out = tmp_path / "plots"
    assert main(["plot", _edr(tmp_path, "45 km/h"), "--out", str(out), "--format",
                 "png"]) == 1
    captured = capsys.readouterr()
    assert captured.err.startswith(REASON) and sorted(out.glob("*.png"))
    assert str(out) in captured.out


@pytest.mark.parametrize("command", ["fit", "compare", "plot"])
def test_the_option_is_documented(command, capsys):
    assert main([command, "--help"]) == 0
    assert "--allow-inconsistent" in capsys.readouterr().out


def test_sensitivity_exits_1_after_its_table_when_the_evidence_contradicts_itself(
        tmp_path, capsys):
    """pim sensitivity differentiates the fit's optimum: the fit's evidence is checked as
    pim fit checks it."""
    case = _edr(tmp_path, "45 km/h")
    assert main(["sensitivity", case]) == 1
    captured = capsys.readouterr()
    assert captured.err.startswith(REASON)
    assert captured.out.strip()                      # the table is still printed
    assert main(["sensitivity", case, "--allow-inconsistent"]) == 0
    assert main(["sensitivity", "synthetic-edr"]) == 0
