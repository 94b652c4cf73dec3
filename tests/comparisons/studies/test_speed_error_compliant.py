"""Speed against error of the finite-duration contact (coarse grid)."""

import math
from pathlib import Path

import pytest

import pim
import sim
from comparisons.report.speed_error import write_compliant
from comparisons.studies import speed_error_compliant as S
from pim.io.casefile import load_case


@pytest.fixture(scope="module")
def study():
    return S.compliant_sweep(pim.load_case("ricsac9"), 0.355, grid=S.Grid(
        steps=(10, 40, 160), rtols=(1e-3, 1e-7), methods=("DOP853",), repeats=1),
        scenes={"frictionless": 0.0}, progress=False)


def test_errors_fall_as_the_step_shrinks_and_the_reference_is_consistent(study):
    fixed = [p for p in study.points if p.integrator == "compiled"]
    errors = [p.error for p in sorted(fixed, key=lambda p: -p.setting)]
    assert errors[0] > errors[1] > errors[2]
    assert study.reference_spread < 1e-7          # the reference against the rung before
    assert study.reference_rtol <= 1e-9
    tight = [p for p in study.points if p.integrator == "DOP853" and p.setting == 1e-7][0]
    assert tight.error < 1e-5


def test_pareto_front_and_recommendation(study, tmp_path):
    front = study.pareto("frictionless")
    assert all(a.wall_time <= b.wall_time and a.error > b.error
               for a, b in zip(front, front[1:], strict=False))
    rec = study.recommended("frictionless")
    assert rec is not None and rec.error <= S.TARGET and rec in front
    files = write_compliant(study, tmp_path, "ricsac9")
    assert all(f.exists() for f in files)
    assert "recommended" in files[0].read_text()
    page = (tmp_path / "speed-error-compliant-ricsac9.html").read_text()
    assert '<meta name="generator" content="pim speed-error">' in page
    # the page leads with the recommendation, before the method and the table
    assert page.index(f"recommended {rec.label}") < page.index("Point contact, epsilon") \
        < page.index('id="table-speed-error-compliant-ricsac9"')


PICKUP = Path(__file__).resolve().parents[2] / "data" / "pickup-into-sedan-side.toml"


def test_reference_stops_at_the_budget_and_reports_the_tolerance_reached():
    """The pickup-into-sedan case took 262 s (63 359 steps) at rtol 1e-12; the ladder keeps
    a reference scene within its budget and says which rtol it reached."""
    case = load_case(str(PICKUP))
    assert case.units == "us"
    ref = S.reference_within_budget(case, 0.2, 7.5e5, 0.0)
    assert ref.result.steps <= S.REFERENCE_STEPS
    assert ref.rtol == 1e-10 and ref.spread < 1e-6
    first = S.reference_within_budget(case, 0.2, 7.5e5, 0.0, budget=4)
    assert first.rtol == S.REFERENCE_RTOLS[0]        # the first rung took over budget / 4
    loose = S.reference_within_budget(case, 0.2, 7.5e5, 0.0, rtols=(1e-6,))
    assert loose.rtol == 1e-6 and math.isnan(loose.spread)


def test_a_slow_run_skips_the_finer_settings_as_over_budget():
    study = S.compliant_sweep(pim.load_case("ricsac9"), 0.355, grid=S.Grid(
        steps=(10, 40, 160), rtols=(1e-3,), methods=("DOP853",), repeats=1, run_budget=1e-9),
        scenes={"f": 0.0}, progress=False)
    fixed = [p for p in study.points if p.integrator == "compiled"]
    assert [p.failure for p in fixed] == [None, "over_budget", "over_budget"]
    assert study.wall_time > 0


def test_the_compiled_and_the_pymunk_scene_agree_on_every_step(study):
    """The pymunk path stays the cross-check: over the same dt both step the same functions
    and reach the same error against the same reference (to round-off), the compiled one
    in a fraction of the time."""
    check = S.compliant_sweep(pim.load_case("ricsac9"), 0.355, grid=S.Grid(
        steps=(10, 40, 160), rtols=(1e-3,), methods=(), repeats=1),
        scenes={"frictionless": 0.0}, progress=False, engine="pymunk")
    compiled = sorted((p for p in study.points if p.integrator == "compiled"),
                      key=lambda p: p.setting)
    pymunk = sorted((p for p in check.points if p.integrator == "pymunk"),
                    key=lambda p: p.setting)
    assert [p.setting for p in compiled] == [p.setting for p in pymunk]
    for a, b in zip(compiled, pymunk, strict=True):
        assert a.steps == b.steps
        assert a.error == pytest.approx(b.error, rel=1e-9, abs=1e-13)
    assert sum(p.wall_time for p in compiled) < sum(p.wall_time for p in pymunk)
    assert check.engine == "pymunk" and study.engine == "numba"


def test_the_stiffness_is_that_of_the_typical_contact_time_not_a_frontal_default(study):
    # RICSAC 9 is a vehicle-to-vehicle contact: no measured stiffness applies to it; the
    # scenes take the stiffness of a 100 ms contact at C instead of the 7.5e5 N/m measured
    # on a full-width frontal barrier test
    case = pim.load_case("ricsac9")
    assert study.stiffness == pytest.approx(S.scene_stiffness(case, 0.355, 0.1))
    assert study.stiffness != pytest.approx(7.5e5, rel=0.05) and study.contact_time == 0.1
    k_nn = sim.compliant_setup.build_problem(case, 0.355, study.stiffness).k_nn
    assert float(sim.contact_law.contact_duration_estimate(study.stiffness, k_nn, 0.355)) == \
        pytest.approx(0.1, rel=1e-9)


def test_two_scenes_on_a_process_pool_give_the_serial_errors(study):
    from pim.io.process import worker_pool
    with worker_pool(2) as pool:
        both = S.compliant_sweep(pim.load_case("ricsac9"), 0.355, grid=S.Grid(
            steps=(10, 40, 160), rtols=(1e-3, 1e-7), methods=("DOP853",), repeats=1),
            scenes={"frictionless": 0.0, "friction 0.5": 0.5}, progress=False,
            executor=pool)
    serial = {(p.integrator, p.setting): p.error for p in study.points}
    pooled = {(p.integrator, p.setting): p.error for p in both.points
              if p.scene == "frictionless"}
    assert pooled == serial
    assert {p.scene for p in both.points} == {"frictionless", "friction 0.5"}


def test_a_reference_rung_over_the_budget_is_abandoned_at_it():
    """hard-near-singular-q's frictionless reference (eps 0.1) takes about 120 steps at rtol
    1e-9 (122 on one processor, 120 on another: the adaptive steps follow round-off) and
    1 089 at 1e-10: with a budget of 600 the second rung starts (122 < 600 / 4) and
    is stopped at 600 steps (settings.max_steps) instead of running on; the first is the
    reference. Before the cap the 1e-10 rung ran to the end and was taken."""
    case = pim.load_case("hard-near-singular-q")
    ref = S.reference_within_budget(case, 0.1, 7.5e5, 0.0, rtols=(1e-9, 1e-10), budget=600)
    assert ref.rtol == 1e-9 and 100 <= ref.result.steps < 600 / 4
    assert math.isnan(ref.spread)
