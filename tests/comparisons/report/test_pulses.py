"""The report of `pim pulses` (comparisons.report.pulses): NHTSA 10146 against the contact
law, in the user's units, through the pipeline."""

from comparisons.report.pulses import pulses_document, write_pulses
from comparisons.report.render import render_markdown
from comparisons.studies.pulses import compare_pulses
from pim.io.units import convert


def test_the_report_speaks_the_users_units_and_writes_its_files(tmp_path):
    c = compare_pulses()
    us = render_markdown(pulses_document(c, "us", "pim pulses --units us"))
    line = next(x for x in us.splitlines() if x.startswith("Contact law at the test's speed"))
    speed, mass = convert(1.0, "speed", "us")[1], convert(1.0, "mass", "us")[1]
    assert f" {speed}, " in line and f" {mass})" in line and "m/s" not in line
    assert "Regenerate with `pim pulses --units us`" in us
    files = write_pulses(c, tmp_path, "si")
    assert [f.name for f in files] == ["pulses.md", "pulses-nhtsa10146.csv", "pulses.html",
                                       "pulses.png"]
    assert "data:image/png;base64," in (tmp_path / "pulses.html").read_text()
