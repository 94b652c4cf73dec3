"""The whole event's speed against error (comparisons.studies.event_speed_error) on a small
sweep of a side slap: errors against the reference fall with the step, a run at the
reference's own setting has no error, a different impact count is an infinite error."""

import math

import numpy as np
import pytest

import pim
import sim
from comparisons.studies.event_speed_error import (
    EventPoint,
    event_error,
    event_pareto_table,
    event_study_table,
    event_sweep,
    plot_event_speed_error,
)
from sim.event_check import side_slap_case

REF = {"dt": 5e-4, "iterations": 30}


@pytest.fixture(scope="module")
def study():
    return event_sweep(side_slap_case(1.6, eps=0.3, beta=0.5), dts=(4e-3, 1e-3, 5e-4),
                       iterations=(30,), analytic_steps=(0.004,), progress=False,
                       reference=REF)


def test_pymunk_converges_to_the_reference(study):
    errors = [p.error for p in study.points if p.engine == "pymunk"]
    assert errors[-1] == 0.0                        # the reference's own setting
    assert errors[0] > errors[1] > 0                # coarser steps err more
    assert all(p.impacts == len(study.reference.impacts) for p in study.points)


def test_the_analytic_event_is_measured_against_the_same_reference(study):
    (analytic,) = [p for p in study.points if p.engine == "analytic"]
    assert analytic.ok and 0 < analytic.error < 0.05 and analytic.wall_time > 0
    assert study.recommended("analytic") is analytic
    assert analytic in study.pareto()


def test_a_different_impact_count_is_an_infinite_error():
    case = side_slap_case(1.6)
    with_slaps = sim.simulate_event(case)
    without = pim.event(case, single_impact=True)
    error, rest = event_error(without, with_slaps)
    assert math.isinf(error) and rest > 0


def test_tables_and_figure(study):
    table = event_study_table(study)
    assert len(table.rows) == len(study.points) and "error [-]" in table.columns
    assert event_pareto_table(study).rows[0][0].startswith("reference")
    fig = plot_event_speed_error(study)
    assert fig.axes[0].get_xscale() == "log"
    failed = EventPoint("pymunk", 1e-2, 3, 0, np.nan, np.nan, np.nan, failure="not_converged")
    assert not failed.ok and failed.label == "pymunk dt=0.01 it=3"
