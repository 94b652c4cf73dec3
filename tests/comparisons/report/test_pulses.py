"""``pim pulses`` in a table, Markdown and HTML through the one pipeline: every row named
fitted or predicted, the report leading with the predictions' errors."""

import pytest

from comparisons.report import pulses as R
from comparisons.studies.pulses import compare_pulses


@pytest.fixture(scope="module")
def comparison():
    return compare_pulses()


def test_the_table_names_each_row_fitted_or_predicted(comparison):
    table = R.pulse_table(comparison)
    assert table.columns[1] == "fitted or predicted"
    role = {r[0]: r[1] for r in table.rows}
    assert role["maximum crush"] == role["time of maximum crush"] == \
        "fitted: k from this test's loading"
    assert role["rebound speed"] == role["delta-V"] == "fitted: eps from this test's rebound"
    for name in ("peak force", "time of peak force", "crush at peak force",
                 "contact duration (force > 5 % of peak)"):
        assert role[name] == "predicted"


def test_errors_are_stated_against_the_csv_numbers(comparison):
    rows = {r[0]: r for r in R.pulse_table(comparison).rows}
    peak = rows["peak force"]
    assert peak[3] == pytest.approx(719.0, abs=1.0)          # kN, the file's largest sample
    assert peak[5] == pytest.approx(peak[4] - peak[3])
    assert abs(rows["maximum crush"][6]) < 5.0                # fitted: agrees
    assert rows["peak force"][6] < -10.0                      # predicted: misses the spikes
    us = {r[0]: r for r in R.pulse_table(comparison, "us").rows}
    assert us["maximum crush"][2] == "ft"


def test_the_markdown_says_which_rows_check_nothing(comparison, tmp_path):
    files = R.write_pulses(comparison, tmp_path, command="pim pulses --out docs")
    text = (tmp_path / "pulses.md").read_text()
    assert {f.name for f in files} == {"pulses.md", "pulses.html", "pulses-nhtsa10146.csv",
                                       "pulses.png"}
    assert files[0].name == "pulses.md"
    assert "agree by construction" in text and "check nothing" in text
    peak = {r[0]: r for r in R.pulse_table(comparison).rows}["peak force"][6]
    assert f"peak force {peak:+.0f} %" in text
    assert "fitted or predicted" in (tmp_path / "pulses-nhtsa10146.csv").read_text()


def test_the_page_leads_with_the_predictions_errors(comparison, tmp_path):
    """Issue 27: pim pulses wrote Markdown by hand and no pulses.html; now the pipeline
    writes both, the page opening with the predicted figures' errors (in the table's
    numbers), then the table, the plot inline, the source last."""
    R.write_pulses(comparison, tmp_path, command="pim pulses")
    page = (tmp_path / "pulses.html").read_text()
    assert page.startswith("<!DOCTYPE html>")
    assert '<meta name="generator" content="pim pulses">' in page
    cards = page.split('<dl class="facts">')[1].split("</dl>")[0]
    rows = {r[0]: r for r in R.pulse_table(comparison).rows}
    assert cards.index("error in peak force") < cards.index("RMS difference in force")
    assert f"{rows['peak force'][6]:+.0f} %" in cards
    assert "maximum crush" not in cards                     # fitted: checks nothing
    assert page.index('<dl class="facts">') < page.index('id="table-pulses-nhtsa10146"') \
        < page.index("data:image/png;base64,") < page.index("Source: ")
    md = (tmp_path / "pulses.md").read_text()
    assert md.index("error in peak force") < md.index("| quantity |") < md.index("Source: ")
    us = R.pulses_document(comparison, "us")
    assert "mph" in next(iter(us.blocks())).cards[-1].value
