"""The hard-case table (`pim hard-cases`): numbers asserted at stated tolerances (issue 5).

Independent references: closed forms of the physics (momentum, energy, frictionless and
plastic limits), the pymunk engine for the simulated column, and the lever-arm argument
for a detected contact start (error ~ dt, none against a fixed straight barrier).
"""

from pathlib import Path

import pytest

import pim
from comparisons.studies.hard_cases import hard_case_names, run_hard_cases

TOL = 1e-6          # the simulator's target, relative to the impact's velocity changes
DOCS = Path(__file__).resolve().parents[3] / "docs"


@pytest.fixture(scope="module")
def study():
    return run_hard_cases(progress=False)


def test_every_hard_case_is_in_the_table(study):
    names = [c.name for c in study.cases]
    assert names == hard_case_names()
    assert set(names) == {n for n, _ in pim.list_cases() if n.startswith("hard-")}
    table = study.results_table()
    assert table.column("case") == names


@pytest.mark.parametrize("name", [n for n, _ in pim.list_cases() if n.startswith("hard-")])
def test_default_simulation_reaches_1e6(study, name):
    c = study[name]
    assert c.limitations == []
    assert c.failure is None
    assert c.error <= TOL
    # exact start reaches the target at every dt of the sweep with at most 30 iterations
    assert c._min_iterations() is not None and c._min_iterations() <= 30


def test_frictionless_needs_one_sweep(study):
    # no friction row: one normal solve is exact, whatever the coupling
    for name in ("hard-beta0", "hard-eps1-frictionless"):
        assert study[name]._min_iterations() == 1


def test_physics_columns_against_closed_forms(study):
    r = study["hard-eps1-frictionless"].result
    assert abs(float(r.energy_loss_percent)) < 1e-9       # elastic and frictionless
    assert abs(float(r.impulse_t)) < 1e-9 * abs(float(r.impulse_n))
    assert abs(float(study["hard-beta0"].result.impulse_t)) < 1e-9
    r = study["hard-eps0"].result
    assert abs(float(r.separation_n)) < 1e-9 * abs(float(r.approach_n))   # plastic
    case = pim.load_case("hard-car-truck")
    r = study["hard-car-truck"].result
    ratio = float(r.delta_v2_magnitude / r.delta_v1_magnitude)
    assert ratio == pytest.approx(float(case.vehicle1.mass / case.vehicle2.mass), rel=1e-12)
    assert ratio == pytest.approx(1 / 50, rel=1e-12)
    for name in ("hard-barrier", "hard-pole"):
        assert float(study[name].result.delta_v2_magnitude) == 0.0


def test_detected_start_error_grows_with_dt(study):
    for c in study.cases:
        if c.name == "hard-barrier":
            continue
        pts = {p.dt: p for p in c.study.points if p.start == "detected"
               and p.contact == "point" and p.iterations is None}
        ratio = pts[1e-4].error / pts[1e-5].error
        assert ratio == pytest.approx(10, rel=0.35), c.name
        assert pts[1e-5].error > 1e-7, c.name


def test_barrier_detected_start_has_no_lever_arm_error(study):
    # a fixed straight wall: a late contact hits the same material point of the car
    c = study["hard-barrier"]
    assert c.detected_needs is not None and c.detected_needs.dt >= 1e-3


def test_high_speed_tunnels_at_large_dt(study):
    c = study["hard-high-speed"]
    fails = {p.dt for p in c.study.points if p.failure == "no_contact" and p.start == "detected"}
    u = abs(float(c.result.approach_n))
    for dt in (1e-2, 3e-3, 1e-3):
        assert dt in fails                 # u_n dt >= 2 x contact radius (0.1 m)
        assert u * dt >= 0.1 - 1e-12
    assert 1e-4 not in fails


def test_outline_contact_cannot_reach_1e6_for_t_bones(study):
    for name in ("hard-eps0", "hard-spinning", "hard-gamma37"):
        outline = [p for p in study[name].study.points if p.contact == "outline"]
        assert outline, name                      # the outline contact was run...
        # ...and no run of it reaches 1e-3: it fails, or it errs by more
        assert all(p.failure is not None or p.error > 1e-3 for p in outline), name


def test_committed_doc_has_the_command_and_every_case():
    text = (DOCS / "hard-cases.md").read_text()
    assert "pim hard-cases" in text
    for name in hard_case_names():
        assert name in text
