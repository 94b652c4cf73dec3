"""``pim pulses`` in a table and Markdown: every row named fitted or predicted."""

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
    assert {f.name for f in files} == {"pulses.md", "pulses-nhtsa10146.csv", "pulses.png"}
    assert "agree by construction" in text and "check nothing" in text
    peak = {r[0]: r for r in R.pulse_table(comparison).rows}["peak force"][6]
    assert f"peak force {peak:+.0f} %" in text
    assert "fitted or predicted" in (tmp_path / "pulses-nhtsa10146.csv").read_text()
