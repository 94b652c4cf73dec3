"""`pim sim` and the simulator's batch APIs (issue 12, defects 8 and 9, units)."""

from dataclasses import replace
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

import pim
import sim
import sim.sweep
from pim_cli.main import main
from sim.error_measure import impact_error


def head_on_16():
    """hard-eps0 with u_n = -16 m/s exactly (binary-exact, so dt x |u_n| can equal 0.1 m)."""
    case = pim.load_case("hard-eps0")
    return replace(case, vehicle1=replace(case.vehicle1, velocity=np.array([16.0, 0.0])),
                   vehicle2=replace(case.vehicle2, velocity=np.array([0.0, 0.0])))


def test_defect8_a_step_equal_to_the_diameter_tunnels():
    settings = sim.Settings(start="detected", dt=2 * 0.05 / 16)   # 16 m/s x dt = 0.1 m
    with pytest.raises(sim.SimulationError) as info:
        sim.simulate(head_on_16(), 0.3, 1.0, settings)
    assert info.value.kind == "no_contact" and "tunnelled" in str(info.value)


def test_defect8_no_impulse_is_no_contact(monkeypatch):
    # A touch that transfers no impulse (the engine's callback sees zero total impulse) is
    # not an impact: the run must fail as no_contact, never report success.
    import sim.run as run

    original = run._post_solve

    def zero_impulse(arbiter, space, mon):
        original(arbiter, space, mon)
        mon.impulse = [0.0, 0.0]

    monkeypatch.setattr(run, "_post_solve", zero_impulse)
    with pytest.raises(sim.SimulationError) as info:
        sim.simulate(pim.load_case("ricsac9"), 0.355, 1.0)
    assert info.value.kind == "no_contact" and "no impulse" in str(info.value)



def test_defect8_cli_exit_code(tmp_path):
    text = (resources.files("pim.io") / "cases" / "hard-eps0.toml").read_text()
    path = tmp_path / "c.toml"
    path.write_text(text.replace('velocity = ["15 m/s", "0 m/s"]',
                                 'velocity = ["16 m/s", "0 m/s"]')
                    .replace('velocity = ["0 m/s", "10 m/s"]', 'velocity = ["0 m/s", "0 m/s"]'))
    assert main(["sim", str(path), "--start", "detected", "--dt", "0.00625"]) == 1


@pytest.mark.parametrize("call", [
    lambda c: sim.simulate_many([c, c], eps=np.array([0.3, np.nan])),
    lambda c: sim.simulate_many([c], beta=np.nan),
    lambda c: sim.simulate_many([c], eps=np.nan, executor="process"),
    lambda c: sim.simulate_many([c], beta=float("nan"), executor="serial"),
])
def test_defect9_nan_coefficients_are_rejected(call):
    with pytest.raises(ValueError, match="NaN"):
        call(pim.load_case("ricsac9"))


def test_sim_speaks_the_case_files_units(capsys):
    assert main(["sim", "ricsac9"]) == 0
    out = capsys.readouterr().out
    assert "mph" in out and "deg/s" in out and "rad/s" not in out and "m/s" not in out
    assert "ft/s" not in out                       # speeds as the field reports them
    assert main(["sim", "ricsac9", "--units", "si"]) == 0
    out = capsys.readouterr().out
    assert " km/h" in out and "ft/s" not in out and "m/s" not in out


def test_defect11_detected_start_spread_is_documented_and_holds():
    # The docs state the spread of error / dt over random scenes (0.8-11 per second of dt,
    # 5-95 %, median 3), not RICSAC 9's 1.2 alone; check the claim on 40 fresh scenes.
    root = Path(__file__).resolve().parents[2]
    for doc in ("docs/guide.md", "docs/comparisons.md"):
        text = " ".join((root / doc).read_text().split())
        assert "random" in text and "0.8-11" in text, doc
    rng = np.random.default_rng(12)
    ratios = []
    while len(ratios) < 40:
        def vehicle():
            m = rng.uniform(100, 40000)
            return pim.Vehicle(m, m * rng.uniform(0.3, 3) ** 2, rng.uniform(-4, 4, 2),
                               rng.uniform(-40, 40, 2), rng.uniform(-6, 6),
                               rng.uniform(-np.pi, np.pi))

        case = pim.Case(vehicle(), vehicle(), pim.Impact(rng.uniform(-3, 3, 2),
                                                         rng.uniform(-np.pi, np.pi)))
        result = pim.solve(case, 0.3, 1.0)
        if not (bool(result.approaching) and bool(result.admissible)):
            continue
        try:
            s = sim.simulate(case, 0.3, 1.0, sim.Settings(start="detected", dt=1e-4))
        except sim.SimulationError:
            continue
        ratios.append(float(impact_error(case, result, s.velocity1, s.velocity2,
                                         s.yaw_rate1, s.yaw_rate2)) / 1e-4)
    assert 1.0 < np.median(ratios) < 6.0
    assert max(ratios) > 3 * 1.2      # one factor of 1.2 does not describe random scenes
