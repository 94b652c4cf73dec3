"""Results read well in a notebook (issue 33 point 9): a short repr, an HTML table in the
case's units, to_dict() and to_frame() (pandas, optional) -- for pim.Result, FitResult,
UncertaintyResult and the reconstruction's result.

Unit factors here are the definitions (1 mph = 0.44704 m/s, 1 km/h = 1/3.6 m/s), not the
program's."""

from __future__ import annotations

import re
import sys
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

import pim
from pim.analysis.reconstruction import reconstruct
from pim.model.notebook import Table, frame, html_table

ROOT = Path(__file__).resolve().parents[3]
MPH, KMH = 0.44704, 1 / 3.6


class Cells(HTMLParser):
    """The text of each table row of an HTML page, as lists of cells."""

    def __init__(self):
        super().__init__()
        self.rows, self.caption, self._in = [], "", None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th", "caption"):
            self._in = tag
            if tag != "caption":
                self.rows[-1].append("")

    def handle_endtag(self, tag):
        self._in = None

    def handle_data(self, data):
        if self._in == "caption":
            self.caption += data
        elif self._in:
            self.rows[-1][-1] += data


def cells(page: str) -> Cells:
    parser = Cells()
    parser.feed(page)
    return parser


@pytest.fixture(scope="module")
def metric():
    return pim.load_case(str(ROOT / "tests/data/metric-kmh.toml"))


def test_a_results_repr_is_one_short_line_in_the_cases_speed_unit(ricsac9, metric):
    us, si = repr(pim.solve(ricsac9)), repr(pim.solve(metric))
    assert us.startswith("Result('ricsac9', eps=0.355, beta=1: |delta-V| ") and "mph" in us
    assert "km/h" in si and "mph" not in si
    for text in (us, si):
        assert "\n" not in text and len(text) < 120 and "shape=()" not in text
    dv = float(pim.solve(ricsac9).delta_v1_magnitude) / MPH
    assert f"{dv:.4g} mph" in us
    assert "inadmissible" in repr(pim.solve(ricsac9, 0.3, 5.0))


def test_the_html_table_shows_speeds_in_the_cases_unit(ricsac9, metric):
    for case, factor, unit in ((ricsac9, MPH, "mph"), (metric, KMH, "km/h")):
        result = pim.solve(case)
        page = cells(result._repr_html_())
        rows = {r[0]: r[1:] for r in page.rows}
        assert rows["quantity"] == ["vehicle 1", "vehicle 2", "unit"]
        s1, s2, shown = rows["post-impact speed"]
        assert shown == unit
        assert float(s1) == pytest.approx(float(result.speed1) / factor, rel=5e-4)
        assert float(s2) == pytest.approx(float(result.speed2) / factor, rel=5e-4)
        assert rows["post-impact yaw rate"][2] == "deg/s"
        assert rows["post-impact yaw rate"][0] == f"{np.degrees(float(result.yaw_rate1)):.4g}"
        assert "epsilon" in page.caption


def test_to_dict_is_the_table_in_the_cases_units_and_another_on_request(ricsac9):
    result = pim.solve(ricsac9)
    d = result.to_dict()
    assert d["case"] == "ricsac9" and d["units"] == {"system": "us", "speed": "mph"}
    assert d["outputs"]["speed"]["unit"] == "mph"
    assert d["outputs"]["speed"]["vehicle1"] == pytest.approx(float(result.speed1) / MPH)
    assert d["admissible"] is True and d["eps"] == pytest.approx(0.355)
    si = result.to_dict("si")
    assert si["outputs"]["speed"]["unit"] == "km/h"
    assert si["outputs"]["speed"]["vehicle1"] == pytest.approx(float(result.speed1) / KMH)


def test_a_batch_shows_its_spread(ricsac9):
    result = pim.solve(ricsac9, np.array([0.1, 0.5, 0.9]), 0.9)
    assert repr(result) == "Result('ricsac9', 3 impacts, shape=(3,))"
    rows = {r[0]: r[1:] for r in cells(result._repr_html_()).rows}
    low, mid, high, unit = rows["post-impact speed of vehicle 1"]
    speeds = np.asarray(result.speed1) / MPH
    assert unit == "mph" and float(low) == pytest.approx(speeds.min(), rel=5e-4)
    assert float(mid) == pytest.approx(np.median(speeds), rel=5e-4)
    assert float(high) == pytest.approx(speeds.max(), rel=5e-4)
    d = result.to_dict()
    assert d["shape"] == [3] and d["outputs"]["speed1"]["values"] == pytest.approx(speeds)


def test_a_fit_reprs_its_coefficients_not_its_case(ricsac9):
    fitted = pim.fit(ricsac9)
    text = repr(fitted)
    assert text.startswith("FitResult('ricsac9', brach: eps=") and "Vehicle(" not in text
    assert "\n" not in text and len(text) < 200 and "mph" in text
    rows = {r[0]: r[1:] for r in cells(fitted._repr_html_()).rows}
    measured, fit, error, _, unit = rows["post-impact velocity of vehicle 1, x"]
    assert unit == "mph"
    vx = float(ricsac9.measured.velocity1[0]) / MPH
    assert float(measured) == pytest.approx(vx, rel=5e-4)
    assert float(fit) == pytest.approx(float(fitted.result.velocity1[0]) / MPH, rel=5e-4)
    assert float(rows["restitution epsilon"][1]) == pytest.approx(fitted.eps, rel=5e-4)


def test_an_uncertainty_result_shows_its_percentiles_in_the_cases_units(ricsac9):
    spread = pim.uncertainty(ricsac9, n=2000, seed=3)
    text = repr(spread)
    assert text.startswith("UncertaintyResult('ricsac9', 2000 samples, ") and "mph" in text
    assert "samples={" not in text and "\n" not in text
    stats = spread.stats["speed2"]
    rows = {r[0]: r[1:] for r in cells(spread._repr_html_()).rows}
    nominal, p5, p50, p95, unit = rows["post-impact speed of vehicle 2"]
    assert unit == "mph"
    for shown, si in ((nominal, stats.nominal), (p5, stats.p5), (p95, stats.p95)):
        assert float(shown) == pytest.approx(si / MPH, rel=5e-4)
    d = spread.to_dict("si")
    assert d["outputs"]["speed2"]["unit"] == "km/h"
    assert d["outputs"]["speed2"]["p50"] == pytest.approx(stats.p50 / KMH)
    assert d["n_admissible"] == spread.n_admissible


def test_a_reconstruction_shows_its_unknowns_in_words_and_units():
    rec = reconstruct(pim.load_case("ricsac9-reconstruct"))
    text = repr(rec)
    assert text.startswith("Reconstruction('ricsac9-reconstruct': ") and "mph" in text
    rows = {r[0]: r[1:] for r in cells(rec._repr_html_()).rows}
    value, *_, unit = rows["pre-impact speed of vehicle 1"]
    assert unit == "mph"
    assert float(value) == pytest.approx(rec.values["vehicle1.speed"] / MPH, rel=5e-4)
    d = rec.to_dict()
    assert d["unknowns"]["vehicle1.speed"]["value"] == pytest.approx(
        rec.values["vehicle1.speed"] / MPH)
    assert d["determined"] is True


def test_html_escapes_text_and_leaves_blanks_blank():
    page = html_table(Table("a <b>", ("x", "y"), (("<i>", None), ("n", float("nan")))))
    assert "<i>" not in page.replace("<div>", "") and "&lt;i&gt;" in page
    assert re.search(r"<td>n</td><td></td>", page)


def test_to_frame_holds_the_tables_numbers(ricsac9):
    pd = pytest.importorskip("pandas")
    result = pim.solve(ricsac9)
    df = result.to_frame()
    assert isinstance(df, pd.DataFrame) and df.index.name == "quantity"
    assert df.loc["post-impact speed", "vehicle 1"] == pytest.approx(
        float(result.speed1) / MPH)
    assert df.loc["post-impact speed", "unit"] == "mph"


def test_to_frame_without_pandas_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        frame(Table("t", ("a", "b"), (("x", 1.0),)))


def test_the_readme_quotes_the_repr_the_code_gives(ricsac9):
    readme = (ROOT / "README.md").read_text()
    shown = re.search(r"`(Result\('ricsac9'.*?\))`", readme.replace("\n", " "), re.S)
    assert shown is not None
    assert shown.group(1) == repr(pim.solve(ricsac9, eps=0.355, beta=1.0))
