"""The compiled event kernel (pim.model.event_kernel): contacts found without tunnelling, stopped
at for the caller or solved in place, rest, records."""

import numpy as np
import pytest

from pim.model.event_formula import CONTACT_TOLERANCE, MAX_IMPACTS
from pim.model.event_kernel import RECORD_COLUMNS, EventScene, run_event
from pim.model.runout import RhsData, RunoutVehicle

CAR = RunoutVehicle(1500.0, 2500.0, 2.7, 1.5, 1.35, 0.7)


def scene(n=1, friction=0.7):
    data = RhsData.of(CAR, n)
    if friction == 0.0:
        from dataclasses import replace
        data = replace(data, friction=np.zeros(n))
    outlines = np.array([[[2.25, 4.5, 1.8], [2.25, 4.5, 1.8]]])
    inverse = np.array([[1 / 1500, 1 / 2500, 1 / 1500, 1 / 2500]])
    # brach-capped (law 1), eps 0.1, beta 1, cap 0.5, C and Gamma from the outlines
    coefficients = np.tile([0.1, 1.0, 0.5, 1.0, np.nan, np.nan, np.nan], (1, MAX_IMPACTS, 1))
    return EventScene(data, data, outlines, inverse, coefficients)


def side_on(speed, gap=6.0):
    """Vehicle 1 heading +x at ``speed`` [m/s] toward vehicle 2 standing across its path
    (heading +y) ``gap`` [m] ahead (CG to CG)."""
    return np.array([[[0.0, 0.0, 0.0, speed, 0.0, 0.0],
                      [gap, 0.0, np.pi / 2, 0.0, 0.0, 0.0]]])


def test_no_tunnelling_at_a_coarse_step():
    """At 80 m/s and a 50 ms step the front would jump 4 m, through the other car's 1.8 m
    width; the step shrinks while the bounding circles overlap and the contact is found
    as the overlap passes the tolerance: vehicle 1's front (x = 2.25) a depth beyond vehicle
    2's side (x = 6 - 0.9)."""
    run = run_event(scene(friction=0.0), side_on(80.0), solve=False, step=0.05, max_time=1.0)
    assert run.status[0] == "contact"
    depth, cx, cy, nx, ny = run.contact[0]
    assert 0 < depth <= CONTACT_TOLERANCE + 1e-3
    assert depth == pytest.approx(CONTACT_TOLERANCE, abs=1e-4)     # 1 us at 80 m/s
    assert run.time[0] == pytest.approx((6.0 - 0.9 - 2.25 + depth) / 80.0, abs=1e-9)
    assert (nx, ny) == pytest.approx((-1.0, 0.0))
    assert cx == pytest.approx(6.0 - 0.9 + depth, abs=1e-6)


def test_solved_in_place_and_at_rest():
    run = run_event(scene(3), np.repeat(side_on(10.0), 3, 0), solve=True, record=0)
    assert (run.status == "rest").all() and (run.count >= 1).all()
    assert not run.moving.any()
    px, py = run.impacts[0, 0, 5:7]
    assert px < 0 and abs(py) < abs(px)        # vehicle 1 pushed back along -x
    assert run.impacts[0, 0, 14] > 0            # energy lost


def test_the_record_starts_at_the_start_state():
    start = side_on(10.0)
    run = run_event(scene(), start, solve=True, record=5000)
    assert run.record.shape[1] == len(RECORD_COLUMNS)
    assert run.record[0, 1:7] == pytest.approx(start[0, 0])
    assert run.record[-1, 0] == pytest.approx(run.time[0])
    # time increases but at each impact: a row just before it and one just after it
    step = np.diff(run.record[:, 0])
    same = np.flatnonzero(step == 0)
    assert np.all(step >= 0) and len(same) == run.count[0] >= 1
    assert run.record[same, 0] == pytest.approx(run.impacts[0, :run.count[0], 0])
    before, after = run.record[same], run.record[same + 1]
    assert before[:, 1:4] == pytest.approx(after[:, 1:4])         # the same place
    assert before[:, 4:6] == pytest.approx(run.impacts[0, :run.count[0], 15:17])
    assert after[:, 4:6] == pytest.approx(run.impacts[0, :run.count[0], 8:10])


def test_far_apart_vehicles_run_to_rest_without_contact():
    run = run_event(scene(), side_on(5.0, gap=100.0), solve=True)
    assert run.status[0] == "rest" and run.count[0] == 0
    # four locked wheels: 25 / (2 0.7 g) = 1.82 m
    assert run.final[0, 0, 0] == pytest.approx(25 / (2 * 0.7 * 9.80665), abs=5e-3)


def test_a_full_record_stops_the_run():
    """A record too short for the run stops it (status "record") with the rows it holds;
    pim.event then runs again with a longer one."""
    run = run_event(scene(), side_on(10.0), solve=True, record=10)
    assert run.status[0] == "record" and run.record.shape == (10, len(RECORD_COLUMNS))
    assert np.all(np.diff(run.record[:, 0]) > 0)


def test_reference_free_views_take_only_c_contiguous_arrays():
    """The event's step reads the vehicles' arrays through views over their data
    (_borrowed, numba.carray): the same numbers for a C-contiguous array; a strided one
    (whose data a C-ordered view would misread) does not compile."""
    from numba import njit
    from numba.core.errors import TypingError

    from pim.model import event_kernel

    borrowed = event_kernel._borrowed

    @njit
    def row_sum(a, i):
        return borrowed(a[i]).sum()

    @njit
    def column_sum(a, j):
        return borrowed(a[:, j]).sum()

    x = np.arange(12.0).reshape(4, 3)
    assert row_sum(x, 2) == x[2].sum()
    with pytest.raises(TypingError):
        column_sum(x, 1)
