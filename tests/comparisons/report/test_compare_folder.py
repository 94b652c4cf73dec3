"""`pim compare ricsac9`: the report folder, its CSVs, PNGs and MP4 (issue 5).

Independent references: the RICSAC 9 optimum printed in Brach's sheet (epsilon = 0.355 on
the bound beta = 1, spec ricsac9.md) and the pymunk engine for the cross-check column.
"""

import csv
import re

import imageio.v3 as iio
import numpy as np
import pytest
from PIL import Image

import pim
from comparisons.report import compare as report_module
from pim_cli.main import main


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("compare") / "ricsac9"
    assert main(["compare", "ricsac9", "--out", str(out), "--no-progress"]) == 0
    return out


def read_csv(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_report_links_every_file_and_files_exist(folder):
    text = (folder / "report.md").read_text()
    links = re.findall(r"\]\(([^)]+)\)", text)
    assert links, "the report links nothing"
    for link in links:
        assert (folder / link).is_file(), link
    for name in ("inputs.csv", "fit.csv", "crosscheck.csv", "speed_error.csv",
                 "speed_error_pareto.csv", "animation.mp4", "speed_error.png"):
        assert name in links
    assert sum(link.startswith("plots/") and link.endswith(".png") for link in links) >= 5
    # nothing half-written left behind
    assert not [p for p in folder.rglob("*") if ".tmp" in p.name]


def test_fit_matches_the_sheet_optimum(folder):
    # Brach's sheet: optimum epsilon = 0.355 with beta on its bound 1 (3 printed digits)
    rows = {r["quantity"]: r for r in read_csv(folder / "fit.csv")}
    assert float(rows["epsilon"]["value"]) == pytest.approx(0.355, abs=0.0006)
    assert float(rows["beta"]["value"]) == pytest.approx(1.0, abs=1e-9)
    assert "beta upper" in rows["on a bound"]["value"]
    printed = re.search(r"epsilon = ([0-9.]+)", (folder / "report.md").read_text())
    assert float(printed.group(1)) == pytest.approx(0.355, abs=0.0006)


def test_crosscheck_table_every_quantity_and_agreement(folder):
    rows = read_csv(folder / "crosscheck.csv")
    keys = {r["quantity"] for r in rows}
    for label in ("vehicle 1 velocity x", "vehicle 2 velocity y", "vehicle 1 yaw rate",
                  "vehicle 2 yaw rate", "normal impulse Pn", "tangential impulse Pt",
                  "kinetic energy lost", "vehicle 1 |delta-V|"):
        assert label in keys
    for r in rows:
        a, s = float(r["PIM"]), float(r["pymunk"])
        assert abs(float(r["absolute error"]) - abs(s - a)) <= 1e-12 * max(abs(a), 1)
        # pymunk reproduces the closed form to round-off at the default settings
        assert abs(s - a) <= 1e-9 * max(abs(a), 1.0), r["quantity"]
    # the analytic column at the fitted eps is close to the sheet's values at eps = 0.355
    by = {r["quantity"]: float(r["PIM"]) for r in rows}
    # the report speaks the case file's units (ricsac9 is written in ft: speeds in mph); the
    # sheet prints ft/s: 1 ft/s = 0.3048 / 0.44704 mph exactly
    ft = 0.3048 / 0.44704
    assert {r["unit"] for r in rows} >= {"mph", "deg/s", "lbf s", "ft lbf"}
    assert by["vehicle 1 velocity x"] / ft == pytest.approx(-6.126, abs=0.02)
    assert by["vehicle 1 velocity y"] / ft == pytest.approx(12.79, abs=0.02)
    assert by["vehicle 2 velocity y"] / ft == pytest.approx(25.199, abs=0.02)


def test_pngs_are_images(folder):
    pngs = list(folder.rglob("*.png"))
    assert len(pngs) >= 6
    for path in pngs:
        with Image.open(path) as img:
            img.verify()
        with Image.open(path) as img:
            assert img.width > 300 and img.height > 200
            # not blank: more than a handful of distinct colours
            assert len(img.convert("RGB").getcolors(1 << 20) or []) > 20


def test_mp4_reads_back_with_expected_frames_that_change(folder):
    """The whole event from the 1 s approach to rest: its frames start 30 frames before the
    impact, the vehicles move in every third of a second until they stop, and the last
    frames, at rest, differ only in the clock above the scene."""
    frames = np.stack(list(iio.imiter(folder / "animation.mp4")))
    assert frames.shape[0] >= 30 + 15 and frames.shape[2] <= 960 and frames.shape[1] <= 720
    diffs = [np.abs(frames[i].astype(int) - frames[i + 10].astype(int)).mean()
             for i in range(0, 40, 10)]
    assert min(diffs) > 0.05          # the vehicles move in every third of a second
    still = np.abs(frames[-1].astype(int) - frames[-2].astype(int)).sum(-1)
    rows = np.nonzero(still > 60)[0]  # beyond the encoder's noise
    # below the caption panel at most a few isolated pixels (the encoder's blocks around
    # a tyre mark's end); a vehicle still moving changes hundreds
    assert (rows >= 0.2 * frames.shape[1]).sum() <= 4, rows


def test_interrupted_run_leaves_no_report_and_no_temp_files(tmp_path, monkeypatch):
    import comparisons.animation.render as anim

    def boom(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(anim.Renderer, "frame", boom)
    with pytest.raises(KeyboardInterrupt):
        report_module.compare_case(pim.load_case("hard-pole"), tmp_path / "r",
                                   speed_error=False, progress=False)
    assert list(tmp_path.iterdir()) == []     # no folder, no temporary folder or lock


def test_bad_input_is_a_one_line_error(tmp_path, capsys):
    assert main(["compare", "ricsac9", "--out", str(tmp_path), "--eps", "1.5",
                 "--beta", "1", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and "eps" in err


def test_the_event_crosscheck_has_each_impact_in_the_case_units(folder):
    # issue 32 item 3: the analytic event against the pymunk event at each impact and at
    # rest (RICSAC 9 is written in ft: lengths in ft, speeds in mph)
    rows = read_csv(folder / "event_crosscheck.csv")
    at = [r["at"] for r in rows]
    assert at[:2] == ["impact 1, vehicle 1", "impact 1, vehicle 2"]
    assert at[-2:] == ["rest, vehicle 1", "rest, vehicle 2"]
    assert "delta-V difference [mph]" in rows[0] and "CG apart [ft]" in rows[0]
    assert float(rows[0]["time difference [s]"]) == pytest.approx(0.0, abs=1e-9)
    assert "at each impact and at rest" in (folder / "report.md").read_text()
