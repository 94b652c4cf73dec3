"""Speed against error of the finite-duration contact (coarse grid)."""

import pytest

import pim
from comparisons import speed_error_compliant as S


@pytest.fixture(scope="module")
def study():
    return S.compliant_sweep(pim.load_case("ricsac9"), 0.355, steps=(10, 40, 160),
                             rtols=(1e-3, 1e-7), methods=("DOP853",),
                             scenes={"frictionless": 0.0}, repeats=1, progress=False)


def test_errors_fall_as_the_step_shrinks_and_the_reference_is_consistent(study):
    pymunk = [p for p in study.points if p.integrator == "pymunk"]
    errors = [p.error for p in sorted(pymunk, key=lambda p: -p.setting)]
    assert errors[0] > errors[1] > errors[2]
    assert study.reference_spread < 1e-9          # DOP853 1e-13 against Radau 1e-12
    tight = [p for p in study.points if p.integrator == "DOP853" and p.setting == 1e-7][0]
    assert tight.error < 1e-5


def test_pareto_front_and_recommendation(study, tmp_path):
    front = study.pareto("frictionless")
    assert all(a.wall_time <= b.wall_time and a.error > b.error
               for a, b in zip(front, front[1:], strict=False))
    rec = study.recommended("frictionless")
    assert rec is not None and rec.error <= S.TARGET and rec in front
    files = S.write_compliant_study(study, tmp_path, "ricsac9")
    assert all(f.exists() for f in files)
    assert "recommended" in files[0].read_text()
