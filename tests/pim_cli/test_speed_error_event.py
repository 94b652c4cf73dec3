"""`pim speed-error CASE --event`: the whole event's study from the command line (slow: the
tight pymunk reference and the rigid sweep take about 15 s)."""

import json

import pytest
from click.testing import CliRunner

from pim_cli.main import cli


@pytest.mark.slow
def test_speed_error_event_writes_its_report_and_json(tmp_path):
    out = tmp_path / "se"
    result = CliRunner().invoke(cli, ["speed-error", "ricsac9", "--coarse", "--no-compliant",
                                      "--event", "--repeats", "1", "--out", str(out),
                                      "--json", "--no-progress"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)[0]
    assert data["event"]["reference_impacts"] == 1
    assert data["event"]["recommended"]["analytic"] is not None
    assert (out / "speed-error-event-ricsac9.md").exists()
    assert (out / "speed-error-event-ricsac9.png").exists()
