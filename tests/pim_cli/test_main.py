"""The pim command line: solve, cases, draw (text, JSON, files) and its exit codes."""

import json
from pathlib import Path
from importlib import resources

import pytest

import pim
from pim_cli.main import main

ROOT = Path(__file__).resolve().parents[2]


def test_solve_prints_the_ricsac9_table_in_us_units(capsys):
    assert main(["solve", "ricsac9", "--units", "us"]) == 0
    out = capsys.readouterr().out
    # the design sheet prints final yaw rates -199.702 and 87.322 deg/s, speeds 9.669 and
    # 18.885 mph (shared spec ricsac9.md; relative 2e-3 for its printed digits); US output
    # gives every speed in mph, as the sheet (and the field) does
    rows = {line[:40].strip(): line[40:].split() for line in out.splitlines()}
    w1, w2, unit = rows["post-impact yaw rate"]
    assert unit == "deg/s"
    assert float(w1) == pytest.approx(-199.702, rel=2e-3)
    assert float(w2) == pytest.approx(87.322, rel=2e-3)
    s1, s2, unit = rows["post-impact speed"]
    assert unit == "mph" and float(s1) == pytest.approx(9.669, rel=2e-3)
    assert float(s2) == pytest.approx(18.885, rel=2e-3)
    assert "ft lbf" in out and "ft/s" not in out and "m/s" not in out


def test_solve_json_matches_the_library(capsys):
    assert main(["solve", "ricsac9", "--eps", "0.5", "--beta", "0.5", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    r = pim.solve(pim.load_case("ricsac9"), 0.5, 0.5)
    assert data["admissible"] is True and data["problems"] == []
    assert data["results"]["velocity_x"]["vehicle1"] == pytest.approx(
        float(r.velocity1[0]) / 0.44704)                      # 1 mph = 0.44704 m/s exactly
    assert data["results"]["velocity_x"]["unit"] == "mph"     # ricsac9 is written in ft
    assert data["results"]["energy_loss"]["value"] == pytest.approx(
        float(r.energy_loss) / 1.3558179483314004)


def test_separating_case_says_no_impact_once(tmp_path, capsys):
    text = (resources.files("pim.io") / "cases" / "hard-eps0.toml").read_text()
    path = tmp_path / "apart.toml"
    path.write_text(text.replace('velocity = ["15 m/s", "0 m/s"]',
                                 'velocity = ["-15 m/s", "0 m/s"]'))
    assert main(["solve", str(path)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.strip().startswith("no impact: the vehicles separate at C")
    assert len(captured.err.strip().splitlines()) == 1 and "-0" not in captured.err


def test_singular_q_is_an_error(capsys):
    from tests.pim.test_hard_cases import singular_beta

    beta = singular_beta(pim.load_case("hard-eps0"), 0.0)
    assert main(["solve", "hard-eps0", "--eps", "0", "--beta", repr(beta)]) == 2
    assert "q is singular" in capsys.readouterr().err


def test_cases_lists_the_bundled_cases(capsys):
    assert main(["cases"]) == 0
    out = capsys.readouterr().out
    for name in ("ricsac9", "ricsac9-brach", "hard-grazing", "hard-pole"):
        assert name in out


def test_draw_writes_an_image(tmp_path):
    out = tmp_path / "fig" / "conventions.png"
    assert main(["draw", "ricsac9", "--out", str(out)]) == 0
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000
    assert not [p for p in out.parent.iterdir() if p.name.startswith(".")]


def test_import_is_light():
    import subprocess
    import sys

    code = ("import sys, pim; heavy = {'matplotlib', 'pint', 'numba', 'scipy', 'pymunk'}; "
            "print(sorted(heavy & set(sys.modules)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


@pytest.mark.parametrize("case", ["ricsac9", "tests/data/metric-kmh.toml"])
def test_solve_reads_a_case_and_shows_its_answer_without_pint_or_the_heavy_libraries(case):
    """``pim solve`` (a US case and a km/h one) loads no pint, scipy, numba, matplotlib or
    dask: reading the case's units and showing the answer in them is
    :mod:`pim.model.unit_table`'s (issue 33 point 9: pint alone took 0.55 s of 1.6 s)."""
    import subprocess
    import sys

    code = ("import sys; from pim_cli.main import main; code = main(['solve', sys.argv[1]]); "
            "import pim; r = pim.solve(pim.load_case(sys.argv[1])); r._repr_html_(); "
            "heavy = {'matplotlib', 'pint', 'numba', 'scipy', 'pymunk', 'dask'}; "
            "print(code, sorted(heavy & set(sys.modules)), file=sys.stderr)")
    out = subprocess.run([sys.executable, "-c", code, case], capture_output=True, text=True,
                         check=True, cwd=ROOT)
    assert out.stderr.strip().splitlines()[-1] == "0 []", out.stderr


def test_public_functions_are_not_shadowed_by_their_modules():
    import importlib
    import pkgutil

    modules = [m.name for m in pkgutil.walk_packages(pim.__path__, "pim.")]
    for name in modules:
        importlib.import_module(name)
    # after importing every submodule, pim.fit & co. are still the functions...
    for name in ("fit", "sensitivity", "uncertainty", "solve", "load_case"):
        assert callable(getattr(pim, name)) and getattr(pim, name).__name__ == name
    # ...and no public name of pim is also the name of one of its submodules
    tops = {m.split(".")[1] for m in modules}
    assert not tops & set(pim.__all__)


def test_help_says_what_compare_does_with_eps(capsys):
    # issue 12 item 6: compare's --eps default is the fit, not "the case's"
    assert main(["compare", "--help"]) == 0
    out = capsys.readouterr().out
    assert "fitted to the case's" in " ".join(out.split())
    assert "reconstruction report" in out


def test_fit_prints_no_search_range_for_a_fixed_parameter(capsys):
    assert main(["fit", "ricsac9", "--beta", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    beta = next(line for line in lines if line.strip().startswith("beta"))
    eps = next(line for line in lines if line.strip().startswith("epsilon"))
    assert "search range" not in beta and "(fixed)" in beta
    assert "search range [0, 1]" in eps


# --- Issue 21 point 7 and issue 22: input errors exit 2, bugs keep their traceback ----


def test_input_error_is_one_line_and_exit_2(capsys):
    assert main(["solve", "no-such-case"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and len(err.strip().splitlines()) == 1


def test_an_internal_bug_is_not_disguised_as_bad_input(monkeypatch):
    """Before: any ValueError, internal bugs included, became "error: ..." and exit 2."""
    import pim.model.law

    def broken(*args, **kwargs):
        raise ValueError("an internal bug")

    monkeypatch.setattr(pim.model.law, "solve_brach", broken)    # what pim solve calls
    with pytest.raises(ValueError, match="an internal bug"):
        main(["solve", "ricsac9"])


@pytest.mark.parametrize("args, words", [
    (["solve", "ricsac9", "--friction-limit", "nan"], ["--friction-limit", "finite"]),
    (["solve", "ricsac9", "--friction-limit", "-1"], ["--friction-limit", ">= 0"]),
    (["solve", "ricsac9", "--eps", "inf"], ["--eps", "[0, 1]"]),
    (["solve", "ricsac9", "--beta", "nan"], ["--beta", "finite"]),
    (["uncertainty", "ricsac9", "--eps", "nan"], ["--eps", "finite"]),
])
def test_non_finite_options_are_usage_errors(capsys, args, words):
    """Before: --friction-limit nan was accepted."""
    assert main(args) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err


@pytest.mark.parametrize("command", [["fit"], ["sensitivity"], ["solve"],
                                     ["uncertainty", "--samples", "200"], ["sim"]])
def test_every_json_names_its_units_and_speaks_them(capsys, command):
    """Before: fit, sensitivity and reconstruct --json answered in SI for a US case."""
    args = [command[0], "ricsac9", *command[1:], "--json"]
    try:
        code = main(args)
    except SystemExit as exc:           # pim sim exits through sys.exit
        code = exc.code
    assert code == 0
    us = json.loads(capsys.readouterr().out)
    assert us["units"]["system"] == "us" and us["units"]["speed"] == "mph"
    try:
        main([*args, "--units", "si"])
    except SystemExit:
        pass
    si = json.loads(capsys.readouterr().out)
    assert si["units"]["system"] == "si" and si["units"]["speed"] == "km/h"
    assert json.dumps(us) != json.dumps(si)
    mph_per_kmh = 1 / (3.6 * 0.44704)         # 1 km/h = 1/3.6 m/s, 1 mph = 0.44704 m/s
    if command[0] == "fit":
        assert us["rms_unit"] == "mph" and si["rms_unit"] == "km/h"
        assert us["rms"] == pytest.approx(si["rms"] * mph_per_kmh)
    if command[0] == "sensitivity":
        v_us, v_si = us["outputs"]["delta_v1_magnitude"], si["outputs"]["delta_v1_magnitude"]
        assert v_us["value"] == pytest.approx(v_si["value"] * mph_per_kmh)


@pytest.mark.parametrize("args", [
    ["uncertainty", "ricsac9", "--seed", "-1"],
    ["reconstruct", "ricsac9-reconstruct", "--seed", "-5"],
    ["baseline", "hard-pole", "--seed", "-5", "--out", "never-written.json"],
])
def test_a_negative_seed_is_one_line_naming_the_option(capsys, tmp_path, monkeypatch, args):
    """Issue 28: numpy's ValueError and its traceback before."""
    monkeypatch.chdir(tmp_path)
    assert main(args) == 2
    assert not (tmp_path / "never-written.json").exists()
    err = capsys.readouterr().err
    seed = args[args.index("--seed") + 1]
    assert err.count("\n") == 1 and "'--seed'" in err, err
    assert f"{seed} is not in the range x>=0" in err, err


def test_a_negative_seed_names_the_argument_in_the_library():
    from pim.analysis.reconstruction import reconstruct

    with pytest.raises(pim.InputError, match="seed must be an integer >= 0 or None, got -1"):
        pim.uncertainty(pim.load_case("ricsac9"), seed=-1)
    with pytest.raises(pim.InputError, match="seed must be an integer >= 0, got -5"):
        reconstruct(pim.load_case("ricsac9-reconstruct"), seed=-5)


def test_pim_sim_names_its_options_not_the_library_settings(capsys):
    """Issue 28: `pim sim` told a command-line user to "raise settings.iterations"."""
    assert main(["sim", "hard-grazing", "--iterations", "2"]) == 1
    err = capsys.readouterr().err
    assert "raise the solver iterations per step (--iterations)" in err, err
    assert "settings." not in err, err
    assert main(["sim", "ricsac9", "--dt", "0"]) == 2
    err = capsys.readouterr().err
    assert err == "error: --dt must be in (0, 1], got 0.0\n", err


def test_animate_after_beyond_its_bound_names_the_option_and_its_unit(capsys, tmp_path):
    """Issue 28: "settings.duration must be in [0, 1e+06]" for --after 1e7, in no unit."""
    assert main(["animate", "ricsac9", "--after", "1e7", "--out", str(tmp_path / "a.mp4")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: Invalid value for '--after': '1e7' is not a finite number "
                          "in [0, 600] s"), err
    assert err.count("\n") == 1 and not (tmp_path / "a.mp4").exists()


# --- Issue 27 point 3: a run's signals through pim.io.process.Interrupts --------------


def _swallowing_load(monkeypatch, signum, then=None):
    """Make `pim solve`'s load_case receive ``signum``, swallow it (as an extension's
    callback may), then raise ``then`` or load the case."""
    import os

    import pim.io.casefile

    real = pim.io.casefile.load_case

    def load(name):
        try:
            os.kill(os.getpid(), signum)
        except KeyboardInterrupt:
            pass
        if then is not None:
            raise then
        return real(name)

    monkeypatch.setattr(pim.io.casefile, "load_case", load)


def test_a_run_that_swallowed_its_interrupt_still_ends_interrupted(monkeypatch, capsys):
    import signal

    _swallowing_load(monkeypatch, signal.SIGINT)
    assert main(["solve", "ricsac9"]) == 130
    assert capsys.readouterr().err.strip() == "aborted"


def test_an_error_after_sigterm_is_reported_as_the_interrupt(monkeypatch, capsys):
    """ffmpeg or a worker may fail first, with a broken pipe: the run was terminated."""
    import signal

    _swallowing_load(monkeypatch, signal.SIGTERM, then=BrokenPipeError(32, "Broken pipe"))
    assert main(["solve", "ricsac9"]) == 143
    assert capsys.readouterr().err.strip() == "terminated"


def test_the_runs_handlers_are_gone_after_it():
    import signal

    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    assert main(["cases"]) == 0
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before
