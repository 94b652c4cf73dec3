"""comparisons/report/event.py on a hand-built event: timeline.csv's columns in the user's
units (independent factors: 1 ft = 0.3048 m, 1 mph = 0.44704 m/s), the impacts table."""

import numpy as np
import pytest

from comparisons.report.event import crosscheck_table, impacts_table, timeline_table
from sim.event_check import event_crosscheck
from tests.comparisons.animation.test_render import slide
from tests.sim.test_event_check import hand_event, hand_record


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


def test_crosscheck_table_has_each_impact_each_vehicle_and_rest_in_mph():
    # impact 1 the same; impact 2 of the simulated event only; vehicle 1 of the simulated
    # event starts 1 ft ahead and runs at 8 m/s against 10 m/s
    first = hand_record(0.0, (0, 0), 0.0, [[10, 0], [0, 0]], [[6, 0], [1, 0]], [np.pi, 0.0])
    late = hand_record(0.9, (2.0, 2.0), 0.0, [[3, 0], [3, 4]], [[2, 0], [3, 4]], [np.pi, 0.0])
    check = event_crosscheck(hand_event("analytic", (first,)),
                             hand_event("simulated", (first, late), v1=(8.0, 0.0),
                                         shift=0.3048))
    table = crosscheck_table(check, "us")
    assert "speed difference before [mph]" in table.columns and "CG apart [ft]" in table.columns
    rows = {r[0]: dict(zip(table.columns, r, strict=True)) for r in table.rows}
    assert list(rows) == ["impact 1, vehicle 1", "impact 1, vehicle 2",
                          "impact 2 (simulated only)", "rest, vehicle 1", "rest, vehicle 2"]
    one = rows["impact 1, vehicle 1"]
    assert one["CG apart [ft]"] == pytest.approx(1.0)            # 1 ft apart at t = 0
    assert one["speed difference before [mph]"] == pytest.approx(0.0)   # the records' own
    assert rows["impact 2 (simulated only)"]["time [s]"] == 0.9
    # at rest (t = 2 s): 20 m against 0.3048 + 16 m
    assert rows["rest, vehicle 1"]["CG apart [ft]"] == pytest.approx((4.0 - 0.3048) / 0.3048)
    assert rows["rest, vehicle 1"]["speed difference after [mph]"] == pytest.approx(
        2.0 / 0.44704)
    assert "the counts differ" in table.note and "impact 2 of the simulated event" in table.note
