"""comparisons/report/law.py and the compare / animate commands under the impact laws other
than Brach's (issue 18, "Done when": a PC-Crash-style case runs through compare and animate)."""

import csv
import json

import imageio.v3 as iio
import numpy as np
import pytest

import pim
from comparisons.report.law import NOT_RUN, compare_law_case
from comparisons.studies.law_runs import law_setup
from pim_cli.main import main


def rows(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.reader(f))


def test_report_gives_the_laws_answer_its_run_and_the_fit_under_the_law(tmp_path):
    case = pim.load_case("ricsac9")
    setup = law_setup(case, "kudlich-slibar", 0.1, None, 0.6)
    rep = compare_law_case(case, tmp_path, setup, animation=False, units="si")
    text = (tmp_path / "report.md").read_text()
    assert "Impact law: **Kudlich-Slibar law (PC-Crash, Virtual CRASH), k = 0.1, mu_c = 0.6**" \
        in text
    # the fit is the law's own (k, mu_c), not Brach's with a mapping
    fit = pim.fit(case, law="kudlich-slibar")
    assert fit.law == "kudlich-slibar"
    assert "The fit is done under the **Kudlich-Slibar law**" in text
    assert "Brach's law" not in text and f"k = {fit.eps:.6g}, mu_c" in text
    fitted = {r[0]: r[1] for r in rows(tmp_path / "fit.csv")}
    assert fitted["impact law"] == "kudlich-slibar" and float(fitted["k"]) == pytest.approx(
        fit.eps)
    assert NOT_RUN in text
    # results.csv holds pim.solve's numbers (SI)
    table = {r[0]: r for r in rows(tmp_path / "results.csv")}
    yaw = table["post-impact yaw rate"]
    assert float(yaw[1]) == pytest.approx(np.degrees(float(setup.result.yaw_rate1)), rel=1e-6)
    assert float(yaw[2]) == pytest.approx(np.degrees(float(setup.result.yaw_rate2)), rel=1e-6)
    law = {r[0]: r[1] for r in rows(tmp_path / "law.csv")}
    assert law["impact law"] == "kudlich-slibar" and float(law["contact friction mu_c"]) == 0.6
    assert rep.error < 1e-12
    assert (tmp_path / "crosscheck.csv").is_file()


def test_compare_command_under_the_law_prints_and_writes_it(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["compare", "ricsac9", "--law", "kudlich-slibar", "--k", "0.3", "--mu-c",
                 "0.2", "--out", str(out), "--no-animation", "--no-progress", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    r = pim.solve(pim.load_case("ricsac9"), law="kudlich-slibar", k=0.3, mu_c=0.2)
    assert data["law"] == "kudlich-slibar"
    assert (data["restitution"], data["contact_friction"]) == (0.3, 0.2)
    assert data["beta"] == pytest.approx(float(r.beta), rel=1e-12)
    assert data["error"] < 1e-12
    assert "k = 0.3, mu_c = 0.2" in (out / "report.md").read_text()


def test_compare_command_under_the_capped_law(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["compare", "ricsac9", "--law", "brach-capped", "--eps", "0.355",
                 "--mu-c", "0.3", "--out", str(out), "--no-animation", "--no-progress"]) == 0
    said = capsys.readouterr().out
    assert "friction-capped Brach (PIM), epsilon = 0.355, effective beta = " in said
    assert "pymunk vs analytic error" in said


def test_animate_command_plays_the_two_phase_run_with_the_analytic_ghost(tmp_path, capsys):
    out = tmp_path / "a.mp4"
    assert main(["animate", "ricsac9", "--law", "kudlich-slibar", "--k", "0.1", "--mu-c",
                 "0.6", "--out", str(out), "--after", "0.3", "--size", "320", "240",
                 "--tyre-friction", "0", "--no-progress", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["law"] == "kudlich-slibar" and data["contact_friction"] == 0.6
    r = pim.solve(pim.load_case("ricsac9"), law="kudlich-slibar", k=0.1, mu_c=0.6)
    assert (data["restitution"], data["beta"]) == (0.1, float(r.beta))
    assert data["max_ghost_offset_px"] < 1e-6       # the run and the law agree
    frames = list(iio.imiter(out))
    assert frames[0].shape == (240, 320, 3)


def test_animate_command_names_the_law(tmp_path, capsys):
    assert main(["animate", "ricsac9", "--law", "brach-capped", "--eps", "0.1", "--mu-c",
                 "0.3", "--out", str(tmp_path / "b.mp4"), "--after", "0.1", "--size", "320",
                 "240", "--no-progress"]) == 0
    assert "friction-capped Brach (PIM), epsilon = 0.1" in capsys.readouterr().out


@pytest.mark.parametrize("command,out", [("compare", "x"), ("animate", "x.mp4")])
def test_law_options_are_checked(tmp_path, capsys, command, out):
    assert main([command, "ricsac9", "--k", "0.5", "--out", str(tmp_path / out)]) == 2
    assert "--k is the restitution of law kudlich-slibar" in capsys.readouterr().err


def test_a_rerun_replaces_the_folder_whole(tmp_path):
    """The law's report is written through pim.io.output.output_folder like Brach's: a
    second run without the animation leaves no MP4 of the first."""
    case = pim.load_case("ricsac9-pccrash")
    setup = law_setup(case)
    first = compare_law_case(case, tmp_path / "r", setup, animation=True)
    assert (tmp_path / "r" / "animation.mp4").is_file()
    assert first.animation.path == tmp_path / "r" / "animation.mp4"
    second = compare_law_case(case, tmp_path / "r", setup, animation=False)
    assert not (tmp_path / "r" / "animation.mp4").exists()
    assert all(p.parent == tmp_path / "r" and p.is_file() for p in second.files)


def test_the_law_report_is_a_page_too_and_leads_with_the_answer(tmp_path, capsys):
    """Issue 27: `pim compare` under another law wrote report.md only ("no report.html yet")
    although the README promises report.html; now the same pipeline writes both, the answer
    first, the animation playing in the page."""
    out = tmp_path / "r"
    assert main(["compare", "ricsac9-pccrash", "--out", str(out), "--no-progress"]) == 0
    said = capsys.readouterr().out.strip().splitlines()
    assert said[-1].startswith(f"wrote {out / 'report.html'} (and report.md")
    page = (out / "report.html").read_text()
    assert page.startswith("<!DOCTYPE html>") and "data:video/mp4;base64," in page
    cards = page.split('<dl class="facts">')[1].split("</dl>")[0]
    assert cards.index("delta-V, vehicle 1") < cards.index("PDOF, vehicle 1")
    assert 'id="table-results"' in page and 'id="table-law"' in page
    assert "[report.html](report.html)" in (out / "report.md").read_text()
