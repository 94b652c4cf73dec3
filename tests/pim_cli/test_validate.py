"""``pim validate`` and a named prior through ``pim uncertainty`` (command line)."""

import csv
import json
import re
from importlib import resources

import pytest

from pim.io.casefile import load_case
from pim.io.files import write_text
from pim.io.units import convert
from pim_cli.main import main


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("validate")
    assert main(["validate", "--out", str(out), "--units", "us", "--json"]) == 0
    return out


def test_the_html_report_holds_the_same_tables_and_figures_inline(report):
    page = (report / "report.html").read_text()
    for key in ("consistency", "coefficients"):
        assert f'id="table-{key}"' in page, key
    barrier = re.findall(r'id="table-barrier-\d".*?</thead>', page, re.S)
    assert len(barrier) == 3                                    # split to fit a screen
    headers = [len(re.findall(r"<th[ >]", b)) for b in barrier]
    assert max(headers) <= 10 and sum(h - 1 for h in headers) == 22   # all but 'test' once
    assert "Other columns" not in page
    assert page.count("data:image/png;base64,") == 2            # both figures, inline
    assert "dVx meas [mph]" in page and "[m/s]" not in page and "[ft/s]" not in page
    assert '<section id="summary"' in page and "SAE 2014-01-0469" in page
    assert "https://" not in page and "<script" not in page


def test_report_files_and_summary(report, capsys):
    for name in ("report.md", "barrier.csv", "consistency.csv", "coefficients.csv",
                 "predicted_vs_measured.png", "coefficients.png"):
        assert (report / name).stat().st_size > 0, name
    text = (report / "report.md").read_text()
    assert "delta-V error median" in text and "within 1 mph" in text
    assert "SAE 2014-01-0469" in text
    rows = list(csv.DictReader((report / "barrier.csv").read_text().splitlines()))
    assert len(rows) == 41
    cen1201 = next(r for r in rows if r["test"] == "CEN1201")
    # the measured values in the user's units: 35.44 ft/s and 48.78 deg/s (paper, App. 2)
    factor, unit = convert(1.0, "speed", "us")
    assert float(cen1201[f"dVx meas [{unit}]"]) == pytest.approx(35.44 * 0.3048 * factor,
                                                               abs=0.006)
    assert float(cen1201["Omega meas [deg/s]"]) == pytest.approx(48.78, abs=0.06)
    flagged = {r["test"] for r in csv.DictReader(
        (report / "consistency.csv").read_text().splitlines())
               if r["flagged"] == "yes"}
    assert {"RICSAC 1", "RICSAC 4", "RICSAC 7", "RICSAC 8", "RICSAC 12"} <= flagged


def test_one_dataset_and_text_output(tmp_path, capsys):
    assert main(["validate", "ricsac", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "ricsac: 11 tests checked, momentum-inconsistent: 1, 4" in out
    assert not (tmp_path / "barrier.csv").exists()


def test_unknown_dataset_is_a_usage_error(tmp_path):
    assert main(["validate", "nope", "--out", str(tmp_path)]) == 2


def test_named_prior_in_a_case_file_runs_uncertainty(tmp_path, capsys):
    base = load_case("ricsac9-brach")
    assert base.impact.restitution is not None
    text = (resources.files("pim.io") / "cases" / "ricsac9-brach.toml").read_text()
    text = text.split("[uncertainty]")[0] + (
        '\n[uncertainty]\nimpact.restitution = {prior = "iihs-small-overlap-car-to-car"}\n'
        'impact.beta = {prior = "iihs-small-overlap-car-to-car"}\n')
    path = write_text(tmp_path / "prior.toml", text)
    assert main(["uncertainty", str(path), "--samples", "2000", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["samples"] == 2000
    bad = write_text(tmp_path / "bad.toml", text.replace("car-to-car\"}\nimpact.beta",
                                                          "car-to-carx\"}\nimpact.beta"))
    assert main(["uncertainty", str(bad), "--samples", "100"]) == 2
    assert ("uncertainty.impact.restitution.prior = 'iihs-small-overlap-car-to-carx' is not a "
            "known prior; did you mean 'iihs-small-overlap-car-to-car'?") in capsys.readouterr().err
