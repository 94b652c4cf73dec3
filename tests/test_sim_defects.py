"""`pim sim` and the simulator's batch APIs (issue 12, defects 8 and 9, units)."""

from dataclasses import replace

import numpy as np
import pytest

import pim
import sim
import sim.sweep
from pim.cli import main


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
    text = (pim.io.casefile.resources.files("pim.io") / "cases" / "hard-eps0.toml").read_text()
    path = tmp_path / "c.toml"
    path.write_text(text.replace('velocity = ["15 m/s", "0 m/s"]',
                                 'velocity = ["16 m/s", "0 m/s"]')
                    .replace('velocity = ["0 m/s", "10 m/s"]', 'velocity = ["0 m/s", "0 m/s"]'))
    with pytest.raises(SystemExit) as info:
        main(["sim", str(path), "--start", "detected", "--dt", "0.00625"])
    assert info.value.code == 1


@pytest.mark.parametrize("call", [
    lambda c: sim.simulate_many([c, c], eps=np.array([0.3, np.nan])),
    lambda c: sim.simulate_many([c], beta=np.nan),
    lambda c: sim.sweep.simulate_sweep([c], eps=np.nan, executor="serial"),
    lambda c: sim.sweep.simulate_sweep([c], beta=float("nan"), executor="serial"),
])
def test_defect9_nan_coefficients_are_rejected(call):
    with pytest.raises(ValueError, match="NaN"):
        call(pim.load_case("ricsac9"))


def test_sim_speaks_the_case_files_units(capsys):
    assert main(["sim", "ricsac9"]) == 0
    out = capsys.readouterr().out
    assert "ft/s" in out and "deg/s" in out and "rad/s" not in out and "| m/s" not in out
    assert main(["sim", "ricsac9", "--units", "si"]) == 0
    out = capsys.readouterr().out
    assert " m/s" in out and "ft/s" not in out
