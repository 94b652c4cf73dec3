"""`pim reconstruct` (pim_cli.reconstruct): refusal of a case without evidence, and the
synthetic case's report files and JSON (slow: two run-out fits)."""

import json
from dataclasses import replace
from importlib import resources
from types import SimpleNamespace

import pytest

import pim
from comparisons.report.html import render_html
from comparisons.report.reconstruct import (
    ReconstructionRows,
    reconstruction_document,
    tyre_models_line,
)
from comparisons.report.render import render_markdown
from pim.analysis.reconstruction import reconstruct
from pim.io.casefile import load_case
from pim.io.output import MARKER
from pim_cli.main import main

KNOWN = 31.09 * 0.3048


def test_case_without_unknowns_is_one_line_and_exit_code_2(capsys):
    assert main(["reconstruct", "ricsac9"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "[unknown]" in err[0]


def test_ricsac9_turned_around_covers_the_staged_speeds(tmp_path, capsys):
    """RICSAC 9's measured post-impact motion -> its impact speeds: the staged 21.2 mph of
    each car (Brach & Brach 2011) lies inside the stated 5-95 % interval."""
    assert main(["reconstruct", "ricsac9-reconstruct", "--out", str(tmp_path), "--json",
                 "--samples", "4000"]) == 0
    data = json.loads(capsys.readouterr().out)
    staged = 21.2                               # mph: --json speaks the case's units
    assert data["units"]["system"] == "us" and data["units"]["speed"] == "mph"
    for key in ("vehicle1.speed", "vehicle2.speed"):
        row = data["unknowns"][key]
        assert row["unit"] == "mph"
        assert row["p5"] < staged < row["p95"], (key, row)
        assert row["p5"] < row["p50"] < row["p95"]
    assert {"impact.restitution", "impact.beta"} <= set(data["unknowns"])
    assert {p.name for p in tmp_path.iterdir()} == {"report.md", "report.html",
                                                    "reconstruction.csv", MARKER}
    csv = (tmp_path / "reconstruction.csv").read_text()
    assert "vehicle1.speed,mph," in csv          # US case: mph in, mph out
    page = (tmp_path / "report.html").read_text()
    table = page.split('id="table-reconstruction"')[1].split("</table>")[0]
    assert "<td>vehicle1.speed</td>" in table and "<td>mph</td>" in table
    assert "momentum check" in table and "nan" not in table     # no percentiles: empty
    assert "<video" not in page and "https://" not in page


def test_under_determined_is_said_not_a_number(tmp_path, capsys):
    """Both speeds, eps and beta from one vehicle's post-impact motion (3 numbers): exit 2
    and one line naming what is missing."""
    text = (resources.files("pim.io") / "cases" / "ricsac9-reconstruct.toml").read_text()
    kept = [line for line in text.splitlines() if not line.startswith("vehicle2.velocity =")
            and not line.startswith("vehicle2.yaw_rate =")]
    path = tmp_path / "one-vehicle.toml"
    path.write_text("\n".join(kept) + "\n")
    assert main(["reconstruct", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "under-determined" in err[0] and "vehicle2" in err[0]
    case = load_case("ricsac9-reconstruct")
    one = replace(case, measured=pim.Measured(velocity1=case.measured.velocity1,
                                              yaw_rate1=case.measured.yaw_rate1))
    rec = reconstruct(one, samples=100)
    assert not rec.determined and rec.values == {} and rec.samples is None
    msg = " ".join(rec.messages)
    assert "under-determined" in msg and "vehicle2's post-impact velocity" in msg


@pytest.mark.slow
def test_synthetic_case_report_and_json(tmp_path, capsys):
    assert main(["reconstruct", "synthetic-runout", "--out", str(tmp_path), "--json",
                 "--samples", "2000"]) == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("vehicle1.speed", "vehicle2.speed"):
        row = data["unknowns"][key]
        assert row["unit"] == "mph" and data["units"]["system"] == "us"
        row = {k: v * 0.44704 for k, v in row.items() if k != "unit"}     # mph -> m/s
        assert row["value"] == pytest.approx(KNOWN, abs=1e-5)
        assert row["p5"] < KNOWN < row["p95"]
    assert {p.name for p in tmp_path.iterdir()} == {"report.md", "reconstruction.csv",
                                                    "scene.png", "reconstruction.mp4",
                                                    "report.html", MARKER}
    page = (tmp_path / "report.html").read_text()
    assert page.count("data:image/png;base64,") >= 2 and "data:video/mp4;base64," in page
    assert "vehicle1.speed" in (tmp_path / "report.md").read_text()


def test_no_monte_carlo_prints_no_nan_and_json_speaks_the_case_units(capsys):
    """Issue 22: before, --samples 0 printed [nan, nan, nan] on every row (the momentum
    check's too), and --json answered in SI for a US case."""
    assert main(["reconstruct", "ricsac9-reconstruct", "--samples", "0"]) == 0
    out = capsys.readouterr().out
    assert "5/50/95 %: not computed, --samples 0" in out and "1 sd = " in out
    assert "nan" not in out.lower()
    assert main(["reconstruct", "ricsac9-reconstruct", "--samples", "0", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["units"]["system"] == "us" and data["unknowns"]["vehicle1.speed"]["unit"] == "mph"
    assert 10 < data["unknowns"]["vehicle1.speed"]["value"] < 30          # mph, not m/s
    check = data["momentum_check"]["vehicle1.speed"]
    assert check["unit"] == "mph" and check["sd"] > 0
def test_the_tyre_model_line_names_each_vehicles_run_out_law():
    rec = SimpleNamespace(post=SimpleNamespace(runouts={2: SimpleNamespace(tyre_model="coulomb"),
                                                        1: SimpleNamespace(tyre_model="brush")}))
    assert tyre_models_line(rec) == ("Run-out tyre model: vehicle 1 brush, "
                                     "vehicle 2 coulomb.")


def test_report_md_and_html_name_the_tyre_model(tmp_path):
    # report.html did not say which tyre law the run-outs used (only the CLI, --json and
    # report.md did)
    rec = SimpleNamespace(post=SimpleNamespace(runouts={1: SimpleNamespace(tyre_model="brush"),
                                                        2: SimpleNamespace(tyre_model="coulomb")}),
                          samples=None, messages=[], goodness=None, fit=None, crush=None,
                          case=SimpleNamespace(name="field",
                                               impact=SimpleNamespace(law=None)))
    line = "Run-out tyre model: vehicle 1 brush, vehicle 2 coulomb."
    doc = reconstruction_document(rec, ReconstructionRows((), ()), "si")
    assert line in render_html(doc, tmp_path)
    assert line in render_markdown(doc)


@pytest.mark.slow   # two field-tyre run-out fits (compiled right-hand side: seconds)
def test_reconstruct_on_the_field_tyre_gives_back_the_speeds_and_says_so(tmp_path, capsys):
    """The bundled field-tyre case (rest evidence generated by the numpy brush run-out from
    21.2 mph each): the nominal speeds come back, and the CLI, --json, report.md and
    report.html say each vehicle's run-out used the brush tyre."""
    assert main(["reconstruct", "synthetic-runout-field", "--samples", "0", "--no-video",
                 "--json", "--out", str(tmp_path)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["tyre_models"] == {"vehicle1": "brush", "vehicle2": "brush"}
    for key in ("vehicle1.speed", "vehicle2.speed"):
        assert data["unknowns"][key]["value"] * 0.44704 == pytest.approx(KNOWN, abs=1e-5)
    line = "Run-out tyre model: vehicle 1 brush, vehicle 2 brush."
    assert line in (tmp_path / "report.md").read_text()
    assert line in (tmp_path / "report.html").read_text()
    case = tmp_path / "case.toml"
    case.write_text((resources.files("pim.io") / "cases" / "synthetic-runout.toml").read_text()
                    + '\n[tyres.vehicle1]\ncg_height = "0.5 m"\n')
    assert main(["reconstruct", str(case), "--samples", "0", "--no-video", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["tyre_models"] == {"vehicle1": "brush", "vehicle2": "coulomb"}
    assert main(["reconstruct", str(case), "--samples", "0", "--no-video"]) == 0
    assert "Run-out tyre model: vehicle 1 brush, vehicle 2 coulomb." in capsys.readouterr().out


def test_recorder_evidence_says_which_evidence_drove_each_speed(capsys):
    """synthetic-edr (vehicle 1's recorded delta-V, vehicle 2's recorded pre-crash speed):
    the text names the driving evidence per speed in the case's units, the JSON too."""
    assert main(["reconstruct", "synthetic-edr", "--samples", "0", "--units", "si"]) == 0
    out = capsys.readouterr().out
    assert "evidence: vehicle1.speed (1 sd = " in out and "km/h): vehicle1 recorded delta-V" in out
    assert main(["reconstruct", "synthetic-edr", "--samples", "0", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["unknowns"]["vehicle1.speed"]["value"] == pytest.approx(9.5 / 0.44704, abs=0.01)
    drivers = data["evidence_drivers"]["vehicle2.speed"]
    assert drivers["unit"] == "mph" and max(drivers["shares"], key=drivers["shares"].get) == \
        "vehicle2 recorded pre-crash speed"


def test_crush_outputs_in_the_report(tmp_path, capsys):
    assert main(["reconstruct", "synthetic-crush", "--samples", "0", "--units", "si",
                 "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "crush: vehicle1: crush energy 16.96" in out and "EES" in out
    report = (tmp_path / "out" / "report.md").read_text()
    assert "## Crush energy" in report and "delta-V from crush" in report
    assert "## Which evidence drove each unknown" in report


def test_a_delta_v_beyond_the_speed_bounds_is_one_line_and_exit_2(tmp_path, capsys):
    text = (resources.files("pim.io") / "cases" / "synthetic-edr.toml").read_text()
    path = tmp_path / "bad.toml"
    path.write_text(text.replace('"-23.65 km/h", "-9.36 km/h"', '"-200 km/h", "0 km/h"'))
    assert main(["reconstruct", str(path), "--samples", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "measured.vehicle1.delta_v" in err[0]


def test_a_kudlich_slibar_case_is_reconstructed_under_its_law(tmp_path, capsys):
    """RICSAC 9 written the PC-Crash way (law kudlich-slibar, POI, contact plane) with the
    speeds, k and mu_c unknown: `pim reconstruct` solves it under that law (it refused the
    law before, exit 2) and the staged 21.2 mph of each car (Brach & Brach 2011) lies inside
    the 5-95 % interval."""
    assert main(["reconstruct", "ricsac9-pccrash-reconstruct", "--out", str(tmp_path),
                 "--json", "--samples", "400"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["law"] == "kudlich-slibar" and data["units"]["system"] == "us"
    for key in ("vehicle1.speed", "vehicle2.speed"):
        row = data["unknowns"][key]
        assert row["unit"] == "mph" and row["p5"] < 21.2 < row["p95"], (key, row)
    assert {"impact.k", "impact.mu_c"} <= set(data["unknowns"])
    assert data["unknowns"]["impact.k"]["unit"] == "-"
    # the fitted contact sticks: mu_c is a lower bound, and the output says so
    assert data["unknowns"]["impact.mu_c"]["lower_bound"] is True
    assert any("mu_c only has a lower bound" in m for m in data["messages"])
    report = (tmp_path / "report.md").read_text()
    assert "Impact law: Kudlich-Slibar" in report and "| impact.mu_c | - | >= " in report
    assert main(["reconstruct", "ricsac9-pccrash-reconstruct", "--samples", "0",
                 "--units", "si"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("Impact law: Kudlich-Slibar") and "km/h" in out and "mph" not in out
    assert ">= " in next(line for line in out.splitlines() if line.startswith("impact.mu_c"))


def test_help_of_out_promises_what_a_case_without_evidence_writes(tmp_path, capsys):
    """Issue 28: --help promised scene.png, which a case without [evidence] never writes."""
    import re

    assert main(["reconstruct", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    out_help = text[text.index("--out DIRECTORY"):text.index("--samples")]
    always = out_help.split("with run-out evidence")[0]
    promised = set(re.findall(r"[\w-]+\.(?:md|html|csv|png|mp4)", always))
    assert main(["reconstruct", "ricsac9-reconstruct", "--out", str(tmp_path / "o"),
                 "--samples", "0"]) == 0
    written = {p.name for p in (tmp_path / "o").iterdir()} - {MARKER}
    assert promised == written == {"report.md", "report.html", "reconstruction.csv"}


def test_a_rerun_keeps_the_users_notes_in_the_output_folder(tmp_path, capsys):
    """Issue 28 (fault harness): a rerun deleted the notes.txt a user had added."""
    out = tmp_path / "out"
    args = ["reconstruct", "ricsac9-reconstruct", "--out", str(out), "--samples", "0"]
    assert main(args) == 0
    (out / "notes.txt").write_text("called the witness")
    capsys.readouterr()
    assert main(args) == 0
    assert (out / "notes.txt").read_text() == "called the witness"
    assert f"note: --out {out}: kept notes.txt (pim did not write it)" in capsys.readouterr().err


def test_the_monte_carlo_budget_says_and_refuses_before_the_work(capsys):
    """Issue 28: a reconstruction from run-outs ran minutes (every sample refits them) with
    nothing said; the pilot's estimate now is said over 10 s and refused over --max-minutes."""
    from pim_cli.reconstruct import budget

    check = budget(10_000, 1, 1.0)
    check(5.0)
    assert capsys.readouterr().err == ""
    check(30.0)
    assert capsys.readouterr().err == ("note: Monte Carlo: 10000 samples, each refitting the "
                                       "run-outs: about 30 s\n")
    with pytest.raises(pim.InputError) as err:
        check(600.0)
    assert str(err.value) == ("--max-minutes 1: the Monte Carlo of 10000 samples refits the "
                              "run-outs of each sample, about 10 min here; give --samples 1000 "
                              "or fewer, or raise --max-minutes")
    budget(10_000, 4, 3.0)(600.0)           # four workers: 150 s, within 3 min


@pytest.mark.slow
def test_a_quoted_wheel_fraction_reconstructs_within_the_stated_budget(tmp_path, capsys):
    """The fault harness's case: synthetic-runout with `wheels = '0.3'`: exit 2 and one line
    before the Monte Carlo when its estimate exceeds --max-minutes."""
    text = (resources.files("pim.io") / "cases" / "synthetic-runout.toml").read_text()
    path = tmp_path / "w.toml"
    path.write_text(text.replace('wheels = ["locked", "locked", 0.3, 0.3]', "wheels = '0.3'"))
    assert main(["solve", str(path)]) == 0
    capsys.readouterr()
    assert main(["reconstruct", str(path), "--max-minutes", "0.01"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --max-minutes 0.01: the Monte Carlo of 10000 samples refits "
                          "the run-outs of each sample, about ") and "\n" not in err, err


def _edr_conflict(tmp_path, pre_crash_speed: str):
    """synthetic-edr with vehicle 2's recorded pre-crash speed replaced (the truth: 28.8
    km/h at 1 km/h): 45 km/h is the conflict of docs/reconstruction.md (p = 2.4e-4)."""
    text = (resources.files("pim.io") / "cases" / "synthetic-edr.toml").read_text()
    path = tmp_path / "conflict.toml"
    path.write_text(text.replace('pre_crash_speed = "28.8 km/h"',
                                 f'pre_crash_speed = "{pre_crash_speed}"'))
    return str(path)


def test_contradictory_evidence_exits_1_after_the_output_with_the_reason_first(
        tmp_path, capsys):
    """Evidence whose chi-square p lies below P_CONTRADICTED (0.001) is refused: the reason
    on stderr before the table, the table, then exit 1 (issue 33 point 3); the report is
    still written; --allow-inconsistent and --allow-inadmissible accept it (exit 0)."""
    from pim.analysis.residuals import P_CONTRADICTED

    case = _edr_conflict(tmp_path, "45 km/h")
    out_dir = tmp_path / "out"
    assert main(["reconstruct", case, "--samples", "0", "--out", str(out_dir)]) == 1
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert err[0].startswith("error: the evidence contradicts itself: chi-square = 13.5")
    assert f"< {P_CONTRADICTED:g} (the refusal threshold)" in err[0]
    assert "pre_crash_speed2" in err[0] or "delta_v1" in err[0]
    assert "--allow-inconsistent" in err[-1]
    assert "vehicle1.speed" in captured.out                 # the answer is still printed
    assert (out_dir / "report.md").is_file()
    for flag in ("--allow-inconsistent", "--allow-inadmissible"):
        assert main(["reconstruct", case, "--samples", "0", flag]) == 0
        assert "error:" not in capsys.readouterr().err
    assert main(["reconstruct", case, "--samples", "0", "--json",
                 "--allow-inconsistent"]) == 0
    good = json.loads(capsys.readouterr().out)["goodness_of_fit"]
    assert good["contradicted"] is True and good["refusal_p"] == P_CONTRADICTED
    assert good["p_value"] < P_CONTRADICTED


def test_doubtful_evidence_warns_and_exits_0(tmp_path, capsys):
    """Between the warning (p < 0.01) and the refusal (p < 0.001): a warning, exit 0; the
    consistent case: neither."""
    assert main(["reconstruct", _edr_conflict(tmp_path, "40.5 km/h"), "--samples", "0",
                 "--json"]) == 0
    good = json.loads(capsys.readouterr().out)["goodness_of_fit"]
    assert 1e-3 < good["p_value"] < 1e-2 and good["contradicted"] is False
    assert main(["reconstruct", "synthetic-edr", "--samples", "0"]) == 0
    assert "error" not in capsys.readouterr().err


SKIDS = '''
[evidence.vehicle1.pre_impact]
skid_length = "30 ft"
friction = 0.7
braking = 1.0

[evidence.vehicle2.pre_impact]
skid_length = "20 ft"
friction = 0.7
braking = ["locked", "locked", "free", "free"]
'''


def test_a_pre_impact_skid_combines_with_measured_post_impact_motion(tmp_path, capsys):
    """Marks before the impact with measured post-impact motion and no run-out were refused
    ("needs the vehicle's run-out evidence", issue 33 point 4): the skid formula needs none
    of it. The speed at the start of the marks against the formula by hand, from the
    reconstructed impact speed: v0 = sqrt(v^2 + 2 g L f mu), f = 1 (all four locked) and
    0.5 (the fronts locked, the default even axle loads)."""
    text = (resources.files("pim.io") / "cases" / "ricsac9-reconstruct.toml").read_text()
    path = tmp_path / "skids.toml"
    path.write_text(text.replace("\n[uncertainty]\n", SKIDS + "\n[uncertainty]\n", 1))
    assert main(["reconstruct", str(path), "--samples", "0", "--json", "--units", "si",
                 "--speed-unit", "m/s"]) == 0
    data = json.loads(capsys.readouterr().out)
    g, ft = 9.80665, 0.3048
    for i, length, drag in ((1, 30 * ft, 1.0), (2, 20 * ft, 0.5)):
        v = data["unknowns"][f"vehicle{i}.speed"]["value"]
        row = data["pre_impact"][f"vehicle{i}.speed_at_marks_start"]
        assert row["unit"] == "m/s" and row["impact"] == pytest.approx(v, rel=1e-9)
        assert row["value"] == pytest.approx((v * v + 2 * g * length * drag * 0.7) ** 0.5,
                                             rel=1e-9)
