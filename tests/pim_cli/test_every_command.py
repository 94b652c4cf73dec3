"""Every command's output on every bundled case (issue 12, defect 15).

What a new user would see: no "nan", no traceback, an exit code of 0 (or 1 with one line
saying why), the case file's units, and no PDOF or clock position for a fixed obstacle.
Fast commands run on every case here; the report, the animation and the sweeps on every
case are behind ``-m slow``.
"""

import re

import pytest

import pim
from pim.io.casefile import list_cases
from pim_cli.main import main

ALL_CASES = [name for name, _ in list_cases()]
#: Cases a forward command can run: those with a restitution (a reconstruction case such as
#: ricsac9-reconstruct has its speeds and coefficients as unknowns; see test_reconstruct).
CASES = [name for name in ALL_CASES if pim.load_case(name).impact.restitution is not None]
#: Cases under Brach's law: the commands that apply only Brach's (eps, beta) (fit,
#: sensitivity, uncertainty) refuse the others with what to do (see
#: test_brach_only_commands_on_another_law_say_what_to_do).
BRACH_CASES = [name for name in CASES if (pim.load_case(name).impact.law or "brach") == "brach"]
NAN = re.compile(r"\bnan\b", re.IGNORECASE)


def run(args, capsys):
    try:
        code = main(args)
    except SystemExit as exc:          # pim sim exits through sys.exit(1)
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def check(name, code, out, err, *, allow_failure=True):
    text = out + err
    assert "Traceback" not in text
    assert not NAN.search(text), f"{name}: 'nan' in the output:\n{text}"
    assert code in ((0, 1) if allow_failure else (0,)), (code, err)
    if code == 1:
        assert err.strip(), "exit 1 needs a reason on stderr"
    case = pim.load_case(name)
    # speeds as the field reports them: mph in US units, km/h in SI (never ft/s or m/s)
    other = {"us": ["m/s", "km/h", "rad/s", "ft/s"], "si": ["ft/s", "mph", "lbf", "m/s"]}[
        case.units]
    for unit in other:
        assert not re.search(rf"(?<![\w/]){re.escape(unit)}\b", out), (name, unit)


def barrier_rows(out):
    return [line for line in out.splitlines() if line.startswith(("PDOF", "|delta-V|"))]


@pytest.mark.parametrize("name", CASES)
def test_solve(name, capsys):
    code, out, err = run(["solve", name], capsys)
    check(name, code, out, err, allow_failure=False)
    if bool(pim.load_case(name).vehicle2.fixed):
        pdof = [line for line in out.splitlines() if line.startswith("PDOF")]
        assert pdof and all(line.split()[-2] == "-" for line in pdof), pdof
        assert "-103" not in out


@pytest.mark.parametrize("name", CASES)
def test_solve_json(name, capsys):
    code, out, err = run(["solve", name, "--json"], capsys)
    check(name, code, out, err, allow_failure=False)


@pytest.mark.parametrize("name", CASES)
def test_sim(name, capsys):
    code, out, err = run(["sim", name], capsys)
    check(name, code, out, err)


@pytest.mark.parametrize("name", BRACH_CASES)
def test_sensitivity(name, capsys):
    code, out, err = run(["sensitivity", name, "--top", "3"], capsys)
    check(name, code, out, err, allow_failure=False)


@pytest.mark.parametrize("name", [n for n in BRACH_CASES
                                  if pim.load_case(n).measured is not None])
def test_fit(name, capsys):
    code, out, err = run(["fit", name], capsys)
    check(name, code, out, err, allow_failure=False)


@pytest.mark.parametrize("name", [n for n in BRACH_CASES
                                  if pim.load_case(n).uncertainty is not None])
def test_uncertainty(name, capsys):
    code, out, err = run(["uncertainty", name, "-n", "2000"], capsys)
    check(name, code, out, err, allow_failure=False)


@pytest.mark.parametrize("name", ["ricsac9", "hard-barrier", "hard-grazing"])
def test_compare_quick(name, tmp_path, capsys):
    code, out, err = run(["compare", name, "--out", str(tmp_path), "--no-animation",
                          "--no-speed-error", "--no-progress"], capsys)
    check(name, code, out, err, allow_failure=False)
    report = (tmp_path / "report.md").read_text()
    assert not NAN.search(report), report
    if bool(pim.load_case(name).vehicle2.fixed):
        results = report.split("## Coefficients")[0]
        pdof = [line for line in results.splitlines() if line.startswith("| PDOF")]
        assert pdof and all(line.split("|")[3].strip() == "-" for line in pdof), pdof


@pytest.mark.slow
@pytest.mark.parametrize("name", CASES)
def test_compare_full(name, tmp_path, capsys):
    code, out, err = run(["compare", name, "--out", str(tmp_path), "--no-progress"], capsys)
    check(name, code, out, err, allow_failure=False)
    assert not NAN.search((tmp_path / "report.md").read_text())


@pytest.mark.slow
@pytest.mark.parametrize("name", CASES)
def test_animate_and_draw(name, tmp_path, capsys):
    code, out, err = run(["animate", name, "--out", str(tmp_path / "a.mp4"),
                          "--no-progress"], capsys)
    check(name, code, out, err)
    code, out, err = run(["draw", name, "--out", str(tmp_path / "d.png")], capsys)
    check(name, code, out, err, allow_failure=False)


@pytest.mark.parametrize("name", sorted(set(ALL_CASES) - set(CASES)))
def test_forward_command_on_a_reconstruction_case_says_what_to_run(name, capsys):
    code, out, err = run(["solve", name], capsys)
    assert code == 2 and "pim reconstruct" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("name", sorted(set(CASES) - set(BRACH_CASES)))
@pytest.mark.parametrize("command", ["sensitivity", "uncertainty"])
def test_brach_only_commands_on_another_law_say_what_to_do(name, command, capsys):
    code, out, err = run([command, name], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "cannot use impact law" in err and 'set impact.law = "brach"' in err
