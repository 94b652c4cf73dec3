"""The reconstruction's notes and messages speak the case's units (issue 33: "output speaks
the user's units everywhere"): lengths, speeds and yaw rates of the run-out fits' warnings,
the reachability refusal and the Monte Carlo's notes, also from worker processes, which do
not inherit the command's units."""

from __future__ import annotations

import contextvars
import re
from importlib import resources

import pytest

import pim
from pim.io.units import DisplayUnits, messages_in
from pim.model.numbers import message_units, speed_text, unit_text, units_in
from pim_cli.main import main

REST = 'rest_position = ["0.44940861599726445 m", "2.804097342912324 m"]'


def _runout(tmp_path, x_ft: int) -> str:
    """synthetic-runout (US units) with vehicle 1's rest position moved to (x_ft, 0) ft."""
    text = (resources.files("pim.io") / "cases" / "synthetic-runout.toml").read_text()
    assert REST in text
    path = tmp_path / f"rest-{x_ft}.toml"
    path.write_text(text.replace(REST, f'rest_position = ["{x_ft} ft", "0 ft"]'))
    return str(path)


def test_message_units_default_to_si_and_follow_the_edge():
    assert (speed_text(10.0), unit_text(3.0, "length"), unit_text(1.0, "angular_velocity")) \
        == ("10 m/s", "3 m", "1 rad/s")
    with messages_in(DisplayUnits("us")):
        assert unit_text(3.048, "length") == "10 ft"
        assert unit_text(1.0, "angular_velocity", ".4g") == "57.3 deg/s"   # 180/pi
        shown = message_units()
    assert unit_text(3.0, "length") == "3 m"
    with units_in(shown):                   # what a worker process is handed
        assert speed_text(0.44704) == "1 mph"


@pytest.mark.parametrize("units, rest, speeds, miss", [
    ("us", "(262.47 ft, 0 ft, heading 0.00 deg)", "from 0 mph to 22.37 mph",
     "yaw rate from -859.4 deg/s to 859.4 deg/s"),
    ("si", "(80 m, 0 m, heading 0.00 deg)", "from 0 km/h to 36 km/h",
     "yaw rate from -859.4 deg/s to 859.4 deg/s")])
def test_an_unreached_rest_state_is_said_in_the_runs_units(units, rest, speeds, miss):
    """The run-out fit's warning (a line of pim reconstruct's output) gave the rest in m and
    the yaw-rate bounds in rad/s whatever the case's units; 80 m = 262.47 ft, 10 m/s =
    22.37 mph = 36 km/h, 15 rad/s = 859.4 deg/s."""
    from pim.analysis.runout_fit import fit_runout
    from pim.model.runout import RunoutVehicle

    car = RunoutVehicle(1400.0, 2300.0, 2.6, 1.5, 1.1, 0.75)
    with messages_in(units):
        fit = fit_runout(car, [0.0, 0.0], 0.0, [80.0, 0.0], 0.0, speed_bounds=(0.0, 10.0),
                         max_evaluations=6, rtol=1e-7, atol=1e-9)
    line = fit.message
    assert f"the rest state {rest} is not reached" in line, line
    assert f"speed {speeds} and {miss}" in line, line
    assert "rad/s" not in line and ("ft" not in line if units == "si" else " m," not in line)


def test_an_unreachable_rest_position_is_refused_in_the_cases_units(tmp_path, capsys):
    """Refused before any fit (exit 2), the distance and the bounds in ft, mph and deg/s."""
    assert main(["reconstruct", _runout(tmp_path, 20000), "--samples", "0"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: evidence.vehicle1.rest_position is 2e+04 ft from the CG at "
                          "impact, beyond any run-out within the speed bound 134.2 mph and "
                          "yaw-rate bound 859.4 deg/s (at most "), err
    assert " m " not in err and "rad/s" not in err


class _FreshProcesses:
    """An executor whose jobs run as in a new process: in a fresh context, without the
    caller's units (a spawned or forkserver worker, a Dask worker)."""

    def map(self, fn, jobs):
        return [contextvars.Context().run(fn, job) for job in jobs]


def test_the_monte_carlos_notes_from_workers_speak_the_users_units():
    """No stated sigmas: the note on the residual standard error standing for them was
    written in the worker, in m/s, whatever the run's units."""
    from pim.analysis.reconstruction import reconstruct

    case = pim.load_case("ricsac9-reconstruct")
    with messages_in("si"):
        rec = reconstruct(case, samples=8, executor=_FreshProcesses(), blocks=2)
    note = next(m for m in rec.messages if "residual standard error" in m)
    assert note.endswith("km/h) stands for them") and "m/s" not in note, note


@pytest.mark.parametrize("bounds, said", [
    (["-5 mph", "80 mph"], "must be >= 0 (a speed along the case's direction), got low = "
                           "-5 mph"),
    (["90 mph", "80 mph"], "low 90 mph must be <= high 80 mph")])
def test_unknown_speed_bounds_are_quoted_as_written(bounds, said):
    from pim.io.evidence_table import parse_unknown

    with pytest.raises(pim.InputError) as err:
        parse_unknown({"vehicle1": {"speed": {"bounds": bounds}}})
    assert said in str(err.value)


def _bundled_with(tmp_path, name: str, old: str, new: str) -> str:
    """A bundled case (written in ft and lbf: US units) with ``old`` replaced by ``new``."""
    text = (resources.files("pim.io") / "cases" / f"{name}.toml").read_text()
    assert old in text
    path = tmp_path / f"{name}-changed.toml"
    path.write_text(text.replace(old, new, 1))
    return str(path)


@pytest.mark.parametrize("name, old, new, said", [
    ("synthetic-crush", 'width = "1.2 m"', 'width = "20 ft"',
     "evidence.vehicle1.crush.width = 20 ft is longer than the damaged front side (the "
     "vehicle's width, 5.3 ft); allowed: (0, 5.3 ft]"),
    ("synthetic-crush", 'depths = ["0.25 m", "0.25 m", "0.25 m"]',
     'depths = ["1 ft", "15 ft", "1 ft"]',
     "evidence.vehicle1.crush.depths: a crush of 15 ft is deeper than the vehicle (length "
     "13 ft); allowed: [0, 13 ft]"),
    ("ricsac9", 'radius_of_gyration = "3.7313536 ft"', 'radius_of_gyration = "0.0004 ft"',
     "the radius of gyration sqrt(I/m) = 0.0004 ft is too small for the arm |C - CG| = "
     "4.8 ft"),
    ("ricsac9", 'radius_of_gyration = "3.7313536 ft"', 'radius_of_gyration = "0.00001 ft"',
     "gives a yaw inertia m k^2 = 7.01e-09 slug ft^2 outside [7.38e-07 slug ft^2, "
     "7.38e+11 slug ft^2]"),
])
def test_a_case_files_input_errors_speak_its_units(tmp_path, capsys, name, old, new, said):
    """Errors found while a case file loads printed their lengths in m and inertias in
    kg m^2 whatever the file's units (e.g. "width = 6.1 m is longer than ... 1.62 m");
    a file written in ft and lbf now hears ft and slug ft^2 (20 ft, 5.3 ft = the case's
    width; 0.00001 ft on a 2255.4 lbf car: m k^2 = 70.1 slug * 1e-10 ft^2)."""
    path = _bundled_with(tmp_path, name, old, new)
    assert main(["solve", path]) == 2
    err = capsys.readouterr().err
    assert said in err, err
    assert not re.search(r"\d m\b|kg m\^2", err), err
