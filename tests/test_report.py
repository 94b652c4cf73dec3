"""The `pim compare` report as a colleague reads it (issue 12): results first, the case
file's units, coefficients with their source, output folders that never mix runs."""

import os
import re
import signal
import subprocess
import sys
import time

import pytest

import pim
from comparisons.report import MANIFEST, compare_case
from pim.cli import main


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
    assert "ft/s" in text and "deg/s" in text and "ft lbf" in text
    for unit in ("km/h", "rad/s", "| m/s", "mph"):
        assert unit not in text, unit
    assert "nan" not in text.lower().replace("nanosecond", "")


def test_si_units_on_request(tmp_path):
    compare_case(pim.load_case("ricsac9"), tmp_path, animation=False, speed_error=False,
                 progress=False, units="si", eps=0.4, beta=0.8, parallel=False)
    text = (tmp_path / "report.md").read_text()
    assert "m/s" in text and "ft/s" not in text and "km/h" not in text


def test_eps_and_beta_skip_the_fit_even_with_measurements(tmp_path, capsys):
    assert main(["compare", "ricsac9", "--out", str(tmp_path), "--eps", "0.4", "--beta",
                 "0.8", "--no-animation", "--no-speed-error", "--no-progress"]) == 0
    text = (tmp_path / "report.md").read_text()
    assert "epsilon = 0.4** (command line)" in text and "beta = 0.8** (command line)" in text
    assert not (tmp_path / "fit.csv").exists()


def test_rerun_never_mixes_runs(tmp_path):
    case = pim.load_case("ricsac9")
    compare_case(case, tmp_path, animation=False, speed_error=False, progress=False)
    assert (tmp_path / "fit.csv").exists()
    stale = tmp_path / "plots" / ".pdof-abc123.tmp.png"      # left by a killed run
    stale.write_bytes(b"half")
    compare_case(case, tmp_path, eps=0.4, beta=0.8, animation=False, speed_error=False,
                 progress=False)
    assert not (tmp_path / "fit.csv").exists()           # the earlier run's file is gone
    assert not stale.exists()
    listed = set((tmp_path / MANIFEST).read_text().split())
    on_disk = {p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*")
               if p.is_file() and p.name != MANIFEST}
    assert on_disk == listed


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


def test_sigterm_removes_temporary_files(tmp_path):
    out = tmp_path / "r"
    proc = subprocess.Popen([sys.executable, "-m", "pim.cli.main", "compare", "ricsac9",
                             "--out", str(out), "--no-progress", "--no-speed-error"],
                            stderr=subprocess.PIPE, text=True)
    # Wait until the run is writing (a file or a temporary file appears), then terminate.
    deadline = time.time() + 60
    while time.time() < deadline and not any(out.rglob("*.tmp*")) and proc.poll() is None:
        time.sleep(0.01)
    proc.send_signal(signal.SIGTERM)
    proc.wait(timeout=60)
    assert not [p for p in out.rglob("*") if ".tmp" in p.name]
    if proc.returncode != 0:          # it may have finished before the signal arrived
        assert proc.returncode == 143 and "terminated" in proc.stderr.read()


def test_fit_table_with_sigmas_is_a_unit_free_chi_square():
    """issue 22: fit.csv named the chi-square a (ft/s)^2 sum and changed with the units."""
    from dataclasses import replace

    from comparisons.report import fit_table

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
