"""What `pim uncertainty` shows (comparisons.report.uncertainty): typed rows in the user's
units (1 mph = 0.44704 m/s exactly), a fixed obstacle without its own outputs, the JSON and
the table, and the words about inadmissible samples."""

import dataclasses
import re

import pytest

import pim
from comparisons.report.uncertainty import (
    BARRIER_OUTPUTS,
    UncertaintyRow,
    inadmissible_note,
    no_admissible_error,
    uncertainty_json,
    uncertainty_lines,
    uncertainty_rows,
)
from pim.analysis.montecarlo import uncertainty
from pim.io.units import display_units

MPH = 0.44704


@pytest.fixture(scope="module")
def case():
    return pim.load_case("ricsac9")


@pytest.fixture(scope="module")
def result(case):
    return uncertainty(case, n=500, seed=1)


def test_rows_are_typed_and_in_the_users_units(case, result):
    rows = uncertainty_rows(case, result, "us")
    assert all(isinstance(r, UncertaintyRow) for r in rows)
    speed = next(r for r in rows if r.output == "speed1")
    stats = result.stats["speed1"]
    assert speed.unit == "mph"
    assert (speed.p5, speed.p95) == (pytest.approx(stats.p5 / MPH),
                                     pytest.approx(stats.p95 / MPH))
    assert speed.sensitivity[0][1] >= speed.sensitivity[-1][1]


def test_a_fixed_obstacle_has_no_outputs_of_its_own(case, result):
    barrier = pim.load_case("hard-barrier")         # vehicle 2: a rigid wall
    assert barrier.vehicle2.fixed
    names = {r.output for r in uncertainty_rows(barrier, result, "si")}
    assert names and not names & set(BARRIER_OUTPUTS)
    assert set(BARRIER_OUTPUTS) <= {r.output for r in uncertainty_rows(case, result, "si")}


def test_json_and_lines(case, result):
    units = display_units("us")
    rows = uncertainty_rows(case, result, units)
    data = uncertainty_json(case, result, rows, units, seed=1, findings={"admissible": True})
    keys = list(data)
    assert keys.index("estimates") < keys.index("admissible") < keys.index("outputs")
    assert data["samples"] == 500 and data["seed"] == 1
    first = data["outputs"][0]
    assert first["output"] == rows[0].output
    assert all(round(s["first_order"], 4) == s["first_order"] for s in first["sensitivity"])
    lines = uncertainty_lines(case.name, result, rows, seed=1, top=1)
    assert lines[0] == f"ricsac9: 500 samples (seed 1), {result.n_admissible} admissible"
    assert len(lines) == 2 + len(rows)
    assert all(line.count("; ") == 0 for line in lines[2:])      # one contribution each
    # issue 33, point 6: the inputs by their labels, not their keys
    assert not any(re.search(r"\b(vehicle\d|impact|measured)\.\w", x) for x in lines), lines
    lines = uncertainty_lines(case.name, result, rows, seed=1, top=3)
    assert all(line.count("; ") == 2 for line in lines[2:])


def test_inadmissible_samples_are_said_with_their_share(case, result):
    assert inadmissible_note(result) == [] and no_admissible_error(result) is None
    none = dataclasses.replace(result, n_admissible=0, problems=["kinetic energy is gained"])
    note = inadmissible_note(none)
    assert note[0].startswith("note: 500 of 500 samples (100 %) are inadmissible impacts")
    assert note[1:] == ["warning: samples: kinetic energy is gained"]
    assert no_admissible_error(none) == ("no sample of 500 is an admissible impact: no "
                                         "statistics")
