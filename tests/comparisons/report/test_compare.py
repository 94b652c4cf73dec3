"""The `pim compare` report as a colleague reads it (issue 12): results first, the case
file's units, coefficients with their source, output folders that never mix runs (issue 22:
interrupts, concurrent runs, a failed encoder, a hostile manifest), the report's data
gathered into one object and rendered (issue 21)."""

import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import replace

import pytest

import pim
from comparisons.report.compare import compare_case
from comparisons.report.compare_document import compare_document
from comparisons.report.data import ReportData
from comparisons.report.render import render_csv, render_markdown
from pim.io.output import MARKER
from pim_cli.main import main


def sections(text):
    return re.findall(r"^## (.+)$", text, flags=re.M)


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "ricsac9"
    rep = compare_case(pim.load_case("ricsac9"), out, animation=False, speed_error=False,
                       progress=False)
    return out, rep


def test_report_opens_with_the_reconstruction_results(quick):
    out, _ = quick
    text = (out / "report.md").read_text()
    heads = sections(text)
    assert heads[0] == "Results"
    assert heads.index("Appendix A: PIM against a pymunk simulation") > heads.index(
        "The design sheet's plots")
    results = text.split("## Results")[1].split("## ")[0]
    for words in (r"\|delta-V\|", "delta-V x", "PDOF (clockwise", "clock position",
                  "post-impact speed", "post-impact yaw rate", "energy lost",
                  "normal crush energy", "tangential crush energy", "fit to the measured",
                  "5-95 %", "uniform on [0.25, 0.45]"):
        assert words in results, words


def test_report_speaks_the_case_files_units(quick):
    out, _ = quick
    text = (out / "report.md").read_text()
    assert "mph" in text and "deg/s" in text and "ft lbf" in text     # speeds in mph
    for unit in ("km/h", "rad/s", "| m/s", "ft/s"):
        assert unit not in text, unit
    assert "nan" not in text.lower().replace("nanosecond", "")


def test_si_units_on_request(tmp_path):
    compare_case(pim.load_case("ricsac9"), tmp_path, animation=False, speed_error=False,
                 progress=False, units="si", eps=0.4, beta=0.8, parallel=False)
    text = (tmp_path / "report.md").read_text()
    assert "km/h" in text and "ft/s" not in text and "m/s" not in text and "mph" not in text


def test_eps_and_beta_skip_the_fit_even_with_measurements(tmp_path, capsys):
    assert main(["compare", "ricsac9", "--out", str(tmp_path), "--eps", "0.4", "--beta",
                 "0.8", "--no-animation", "--no-speed-error", "--no-progress"]) == 0
    text = (tmp_path / "report.md").read_text()
    assert "epsilon = 0.4** (command line)" in text and "beta = 0.8** (command line)" in text
    assert not (tmp_path / "fit.csv").exists()


def listed_files(out):
    """The files report.md's Files section lists."""
    text = (out / "report.md").read_text().split("## Files")[1]
    return set(re.findall(r"^- \[(.+?)\]", text, flags=re.M))


def on_disk(out):
    return {p.relative_to(out).as_posix() for p in out.rglob("*")
            if p.is_file() and p.name != MARKER}


def test_rerun_never_mixes_runs(tmp_path):
    case = pim.load_case("ricsac9")
    out = tmp_path / "r"
    compare_case(case, out, animation=False, speed_error=False, progress=False,
                 assumptions=False, parallel=False)
    assert (out / "fit.csv").exists()
    # (a file pim did not write is the user's and is kept: tests/pim/io/test_output.py)
    compare_case(case, out, eps=0.4, beta=0.8, animation=False, speed_error=False,
                 progress=False, assumptions=False, parallel=False)
    assert not (out / "fit.csv").exists()           # the earlier run's files are gone
    assert on_disk(out) == listed_files(out)
    assert [p.name for p in tmp_path.iterdir()] == ["r"]     # no temporary litter


def test_a_hostile_manifest_deletes_nothing_outside_the_folder(tmp_path):
    """Issue 22: a rerun deleted every path listed in .pim-compare-files, absolute ones too."""
    out = tmp_path / "r"
    out.mkdir()
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    sibling = tmp_path / "sibling.txt"
    sibling.write_text("precious")
    (out / ".pim-compare-files").write_text(f"{victim}\n../sibling.txt\n{sibling}\n")
    compare_case(pim.load_case("ricsac9"), out, eps=0.4, beta=0.8, animation=False,
                 speed_error=False, progress=False, assumptions=False, parallel=False)
    assert victim.read_text() == "precious" and sibling.read_text() == "precious"
    assert (out / "report.md").exists()


def test_out_below_a_regular_file_is_one_line(tmp_path, capsys):
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    assert main(["compare", "ricsac9", "--out", str(blocker / "report"), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --out") and "is a file" in err and len(err.splitlines()) == 1


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_out_in_a_read_only_folder_is_one_line(tmp_path, capsys):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        assert main(["compare", "ricsac9", "--out", str(ro / "r"), "--no-progress"]) == 2
    finally:
        ro.chmod(0o755)
    assert capsys.readouterr().err.startswith("error: --out")


def test_no_impact_is_one_line_and_exit_1(tmp_path, capsys):
    from importlib import resources
    text = (resources.files("pim.io") / "cases" / "hard-eps0.toml").read_text()
    path = tmp_path / "apart.toml"
    path.write_text(text.replace('velocity = ["15 m/s", "0 m/s"]',
                                 'velocity = ["-15 m/s", "0 m/s"]'))
    assert main(["compare", str(path), "--out", str(tmp_path / "r"), "--no-progress"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("no impact: the vehicles separate at C") and "\n" not in err
    assert not (tmp_path / "r" / "report.md").exists()


def pim_command():
    """What the `pim` console script runs (pyproject.toml: pim = "pim_cli:run")."""
    return [sys.executable, "-m", "pim_cli"]


def snapshot(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def old_run(tmp_path_factory):
    """A complete earlier run (eps and beta given: no fit.csv) to copy into a folder."""
    out = tmp_path_factory.mktemp("old") / "r"
    compare_case(pim.load_case("ricsac9"), out, eps=0.4, beta=0.8, animation=False,
                 speed_error=False, progress=False, assumptions=False, parallel=False)
    return out


def copy_run(old_run, parent):
    out = parent / "r"
    shutil.copytree(old_run, out)
    return out, snapshot(out)


def new_files(parent, since):
    """Files written since ``since`` under their final names (not atomic_path's temporary
    .NAME-XXXX.tmp files), in the folder or in a temporary folder beside it."""
    return [p for p in parent.rglob("*") if p.is_file() and not p.name.startswith(".")
            and p.stat().st_mtime > since]


def interrupt_at(parent, signum, seconds):
    """Start `pim compare` (with animation and the assumptions step: well over 5 s) into
    parent/r, signal it after ``seconds`` (or "writing": as soon as it has written a file,
    into the folder or beside it) while it still runs; return code and stderr."""
    start = time.time()
    proc = subprocess.Popen(pim_command() + ["compare", "ricsac9", "--out", str(parent / "r"),
                                             "--no-progress", "--no-speed-error"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    if seconds == "writing":
        while not new_files(parent, start) and proc.poll() is None \
                and time.time() < start + 120:
            time.sleep(0.02)
    else:
        time.sleep(seconds)
    running = proc.poll() is None
    os.killpg(proc.pid, signum)             # the whole group, as a terminal's Ctrl-C does
    _, err = proc.communicate(timeout=120)
    assert running, f"the run ended before the signal at {seconds} s: the test proves nothing"
    return proc.returncode, err


# The early ones raced with process start-up (an interrupt taken while a forkserver worker
# started lost the pool: the worker, still unpickling its start-up data when the parent's
# semaphores were removed, printed a FileNotFoundError traceback), with ffmpeg (given part of
# a frame, it printed its own error) and with numba compiling (llvmlite's callback printed the
# Terminated it dropped): about 1 run in 10 on 2 cores; pim.io.process.starting_processes,
# the animation writer's whole frames and in_callback close them.
@pytest.mark.parametrize("signum, seconds", [
    (signal.SIGINT, 0.5), (signal.SIGTERM, "writing"),
    pytest.param(signal.SIGINT, "writing", marks=pytest.mark.slow),
    pytest.param(signal.SIGTERM, 2.0, marks=pytest.mark.slow),
    pytest.param(signal.SIGINT, 2.0, marks=pytest.mark.slow),
    pytest.param(signal.SIGTERM, 0.5, marks=pytest.mark.slow),
    pytest.param(signal.SIGINT, 4.0, marks=pytest.mark.slow),
    pytest.param(signal.SIGTERM, 4.0, marks=pytest.mark.slow)])
def test_a_killed_run_keeps_the_old_run_whole(old_run, tmp_path, signum, seconds):
    """Issue 22: an interrupt left the new MP4 and plots beside the old report, or printed
    the worker's traceback; now: the old run untouched, exit 130/143, one line, no litter."""
    out, before = copy_run(old_run, tmp_path)
    code, err = interrupt_at(tmp_path, signum, seconds)
    assert code == (130 if signum == signal.SIGINT else 143), err
    assert "Traceback" not in err and "Error" not in err, err
    assert err.strip() in ("aborted", "terminated"), err
    assert snapshot(out) == before
    assert [p.name for p in tmp_path.iterdir()] == ["r"]     # no temporary litter


def test_two_runs_into_one_folder_leave_one_run_whole(old_run, tmp_path):
    """Issue 22: two runs started together ended with files of both; now the second fails
    at once (exit 2, one line) and the folder holds one run."""
    out, _ = copy_run(old_run, tmp_path)
    args = ["compare", "ricsac9", "--out", str(out), "--no-progress", "--no-speed-error",
            "--no-animation", "--no-assumptions"]
    procs = [subprocess.Popen(pim_command() + args + extra, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True)
             for extra in ([], ["--eps", "0.4", "--beta", "0.8"])]
    results = [(p.wait(timeout=300), p.stderr.read()) for p in procs]
    codes = sorted(code for code, _ in results)
    assert codes == [0, 2], results
    err = next(e for code, e in results if code == 2).strip()
    assert "another pim run is writing" in err and len(err.splitlines()) == 1
    assert on_disk(out) == listed_files(out)
    fitted = (out / "fit.csv").exists()
    assert ("(fit to the measured motion)" in (out / "report.md").read_text()) == fitted
    assert [p.name for p in tmp_path.iterdir()] == ["r"]


def test_a_truncated_video_is_an_error_and_keeps_the_old_run(old_run, tmp_path,
                                                             monkeypatch, capsys):
    """Issue 22: a full disk (ffmpeg's "Error writing trailer") left a truncated
    animation.mp4 under its final name; now exit 2, one line, the old run whole."""
    import imageio.v2

    real = imageio.v2.get_writer

    class Truncating:
        def __init__(self, path, *args, **kwargs):
            self.path, self.writer = path, real(path, *args, **kwargs)

        def append_data(self, frame):
            self.writer.append_data(frame)

        def close(self):
            self.writer.close()
            size = os.path.getsize(self.path)
            os.truncate(self.path, size // 2)        # the trailer never reached the disk

    monkeypatch.setattr(imageio.v2, "get_writer", Truncating)
    out, before = copy_run(old_run, tmp_path)
    assert main(["compare", "ricsac9", "--out", str(out), "--no-progress",
                 "--no-speed-error", "--no-assumptions"]) == 2
    err = capsys.readouterr().err.strip()
    assert "incomplete" in err and len(err.splitlines()) == 1, err
    assert snapshot(out) == before
    assert [p.name for p in tmp_path.iterdir()] == ["r"]


def test_report_data_is_gathered_once_and_rendered(quick):
    out, rep = quick
    data = rep.data
    assert isinstance(data, ReportData)
    shown = {k: v for k, v in data.seconds.items() if k != "report"}    # timed after it
    doc = compare_document(replace(data, seconds=shown))
    assert (out / "report.md").read_text() == render_markdown(doc)
    for name, text in render_csv(doc).items():
        assert (out / name).read_text() == text
    assert {"results", "misfit", "inputs", "fit", "crosscheck", "assumptions"} <= \
        set(data.tables)


def test_suggested_commands_name_the_case_as_given_and_run_in_a_shell(quick):
    _, rep = quick
    text = render_markdown(compare_document(replace(rep.data, case_path="cases/my case.toml")))
    assert "`pim assumptions 'cases/my case.toml'`" in text
    assert "pim assumptions ricsac9" not in text


@pytest.mark.slow
def test_suggested_commands_use_the_case_path_the_user_gave(tmp_path):
    """Issue 22: the report said `pim assumptions pickup-sedan` (the case's name), which
    fails when the case came from a file; now it prints the path given."""
    from importlib import resources
    src = resources.files("pim.io") / "cases" / "ricsac9.toml"
    path = tmp_path / "my case.toml"
    path.write_text(src.read_text())
    out = tmp_path / "r"
    assert main(["compare", str(path), "--out", str(out), "--no-progress", "--no-animation",
                 "--no-speed-error"]) == 0
    text = (out / "report.md").read_text()
    assert f"`pim assumptions '{path}'`" in text


def test_fit_table_with_sigmas_is_a_unit_free_chi_square():
    """issue 22: fit.csv named the chi-square a (ft/s)^2 sum and changed with the units."""
    from dataclasses import replace

    from comparisons.report.compare_tables import fit_table

    case = pim.load_case("ricsac9")
    m = replace(case.measured, velocity1_sigma=[0.3, 0.3], velocity2_sigma=[0.3, 0.3])
    f = pim.fit(replace(case, measured=m))
    tables = {u: {r[0]: r[1:] for r in fit_table(f, u).rows} for u in ("si", "us")}
    for rows in tables.values():
        assert rows["chi-square"] == (f.cost, "-")
        assert rows["degrees of freedom"] == (2, "-")
        assert not any("^2" in str(v) for row in rows.values() for v in row)
    assert "cost (sum of squared velocity errors)" in {
        r[0] for r in fit_table(pim.fit(case), "us").rows}


def test_pre_impact_table_from_the_case_velocities():
    """pre-impact-skids: vehicle 1 slid 30 ft locked (friction 0.7) into the impact at
    31.09 ft/s: sqrt(31.09^2 + 2 x 32.174 x 0.7 x 30) = 48.14 ft/s = 32.83 mph."""
    from comparisons.report.compare_tables import pre_impact_table

    table = pre_impact_table(pim.load_case("pre-impact-skids"), "us")
    assert table.name == "pre_impact" and table.columns[1] == "value [mph]"
    rows = {r[0]: r[1:] for r in table.rows}
    assert rows["vehicle1.speed_at_marks_start"][0] == pytest.approx(48.14 / 1.46667, rel=1e-3)
    assert "30 ft of marks" in rows["vehicle1.speed_at_marks_start"][2]
    assert pre_impact_table(pim.load_case("ricsac9")) is None


def test_compare_report_shows_the_speeds_before_the_impact(tmp_path):
    out = tmp_path / "report"
    assert main(["compare", "pre-impact-skids", "--out", str(out), "--no-animation",
                 "--no-speed-error", "--no-assumptions", "--no-progress"]) == 0
    assert "**Speeds before the impact** ([pre_impact.csv]" in (out / "report.md").read_text()
    assert 'id="table-pre_impact"' in (out / "report.html").read_text()
    assert (out / "pre_impact.csv").read_text().startswith("speed,value [mph],")


def test_compare_case_takes_its_options_as_one_object_or_by_name(tmp_path):
    """Issue 27 point 7: compare_case takes a CompareOptions (or its fields by name, as
    before); a misspelt option is refused naming the allowed ones, before anything is
    written."""
    from comparisons.report.compare import CompareOptions

    with pytest.raises(ValueError, match=r"unknown option\(s\) animations; allowed: "
                                         r"options, eps, beta, gif, animation"):
        compare_case(pim.load_case("ricsac9"), tmp_path / "r", animations=False)
    assert not (tmp_path / "r").exists()
    options = CompareOptions(eps=0.4, beta=0.8, animation=False, speed_error=False,
                             assumptions=False, progress=False, parallel=False)
    rep = compare_case(pim.load_case("ricsac9"), tmp_path / "r", options, eps=0.5)
    assert rep.eps == pytest.approx(0.5) and rep.beta == pytest.approx(0.8)
