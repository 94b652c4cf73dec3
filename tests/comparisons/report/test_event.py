"""comparisons/report/event.py on a hand-built event: timeline.csv's columns in the user's
units (independent factors: 1 ft = 0.3048 m, 1 mph = 0.44704 m/s), the impacts table."""

import numpy as np
import pytest

from comparisons.report.event import impacts_table, timeline_table
from tests.comparisons.animation.test_render import slide


def test_timeline_columns_carry_their_units_and_convert():
    ev = slide()
    table = timeline_table(ev, "us")
    assert table.columns[:4] == ("time [s]", "phase", "x1 [ft]", "y1 [ft]")
    assert "vx1 [mph]" in table.columns and "heading2 [deg]" in table.columns
    k = 7
    row = dict(zip(table.columns, table.rows[k], strict=True))
    assert row["x1 [ft]"] == pytest.approx(ev.vehicle1.position[k, 0] / 0.3048)
    assert row["vx1 [mph]"] == pytest.approx(ev.vehicle1.velocity[k, 0] / 0.44704)
    assert row["heading2 [deg]"] == pytest.approx(90.0)
    si = dict(zip(timeline_table(ev, "si").columns, timeline_table(ev, "si").rows[k],
                  strict=True))
    assert si["vx1 [km/h]"] == pytest.approx(3.6 * ev.vehicle1.velocity[k, 0])
    assert table.show is False and table.name == "timeline"


def test_impacts_table_in_time_order_with_units():
    ev = slide()
    table = impacts_table(ev, "si")
    assert table.columns[1] == "time [s]" and "delta-V 1 [km/h]" in table.columns
    row = dict(zip(table.columns, table.rows[0], strict=True))
    assert row["time [s]"] == 0.5 and row["C x [m]"] == 5.0
    assert row["Gamma [deg]"] == pytest.approx(np.degrees(0.3))
    assert row["energy lost [kJ]"] == pytest.approx(0.01)
