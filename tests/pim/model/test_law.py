"""pim.solve follows the case's impact law; the law resolved once (pim.model.law)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pim
from pim.model import solver
from pim.model.friction_cap import solve_capped
from pim.model.impact_laws import LAW_INPUTS, motion_of_law, solve_kudlich_slibar
from pim.model.law import API_NAMES, LawChoice, resolve_law
from pim_cli.main import OPTION_NAMES, main
from tests.scenes import random_cases

KS = "kudlich-slibar"
ROOT = Path(__file__).resolve().parents[3]
FIELDS = ("velocity1", "velocity2", "yaw_rate1", "yaw_rate2", "impulse", "mu0", "eps", "beta")


def capped_case(tmp_path) -> Path:
    """ricsac9 under friction-capped Brach, cap 0.3 (the file's own text)."""
    text = (ROOT / "pim/io/cases/ricsac9.toml").read_text()
    text = text.replace("[impact]\n", '[impact]\nlaw = "brach-capped"\ncontact_friction = 0.3\n')
    path = tmp_path / "ricsac9-capped.toml"
    path.write_text(text)
    assert pim.load_case(path).impact.law == "brach-capped"
    return path


def same(a, b, fields=FIELDS):
    for name in fields:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def test_solve_on_a_kudlich_slibar_case_file_is_the_laws_answer():
    case = pim.load_case("ricsac9-pccrash")     # law = "kudlich-slibar", k 0.355, mu_c 0.512
    result = pim.solve(case)
    assert result.law == KS
    same(result, solve_kudlich_slibar(case, 0.355, 0.512))
    # an independent path: the law on dual numbers (impulse ratio through the PIM formula)
    row = np.array([_input(case, name) for name in LAW_INPUTS])
    row[0], row[-1] = 0.355, 0.512
    values, _ = motion_of_law(row, KS, jacobian=False)
    expected = [result.impulse_n, result.impulse_t, *result.impulse, *result.velocity1,
                *result.velocity2, result.yaw_rate1, result.yaw_rate2]
    np.testing.assert_allclose(values, np.array(expected, float), rtol=1e-9, atol=1e-9)


def _input(case, name):
    from pim.model.dual import motion_inputs

    inputs = dict(zip(LAW_INPUTS[:-1], motion_inputs(case, 0.0, 0.0), strict=True))
    return inputs.get(name, 0.0)


def test_solve_on_a_capped_case_file_is_the_capped_law(tmp_path):
    case = pim.load_case(capped_case(tmp_path))
    same(pim.solve(case), solve_capped(case, 0.355, 1.0, 0.3))
    with np.errstate(all="ignore"):
        plain = solver.solve(case, 0.355, 1.0)
    assert abs(float(plain.mu)) > 0.3 >= abs(float(pim.solve(case).mu)) - 1e-12   # capped


@pytest.mark.parametrize("backend", ["auto", "numpy", "numba"])
def test_solve_on_brach_cases_is_bitwise_the_brach_solver(backend):
    case = random_cases(300, seed=7)
    rng = np.random.default_rng(3)
    eps, beta = rng.uniform(0, 1, 300), rng.uniform(-0.2, 1.2, 300)
    with np.errstate(all="ignore"):
        same(pim.solve(case, eps, beta, backend), solver.solve(case, eps, beta, backend))
        same(pim.solve(case, eps, beta, backend=backend, fast_trig=False),
             solver.solve(case, eps, beta, backend=backend, fast_trig=False))
    one = pim.load_case("ricsac9")
    same(pim.solve(one, 0.355, 0.8, backend), solver.solve(one, 0.355, 0.8, backend))
    same(pim.solve(one), solver.solve(one))


def test_resolution_defaults_to_the_case_and_brach():
    assert resolve_law(pim.load_case("ricsac9")) == LawChoice("brach", None, None, None)
    ks = resolve_law(pim.load_case("ricsac9-pccrash"), k=0.2)
    assert (ks.law, float(ks.restitution), float(ks.contact_friction)) == (KS, 0.2, 0.512)
    assert ks.name == pim.LAW_NAMES[KS]
    capped = resolve_law(pim.load_case("ricsac9"), 0.3, cap_friction=True, friction_limit=0.4)
    assert (capped.law, capped.restitution, float(capped.contact_friction)) == (
        "brach-capped", 0.3, 0.4)


@pytest.mark.parametrize("case,options,message", [
    ("ricsac9", dict(k=0.5), "k is the restitution of law kudlich-slibar"),
    ("ricsac9", dict(law=KS, k=0.5, eps=0.3, mu_c=0.2), "give k or eps, not both"),
    ("ricsac9", dict(mu_c=0.5), "mu_c needs law = kudlich-slibar or brach-capped"),
    ("ricsac9", dict(law=KS, k=0.5, mu_c=0.5, beta=1.0), "beta does not apply"),
    ("ricsac9", dict(law=KS, k=0.5), r"mu_c \(the contact friction\) is required"),
    ("ricsac9", dict(law="brach-capped"), r"mu_c \(the cap\) is required"),
    ("ricsac9", dict(law=KS, k=1.5, mu_c=0.5), r"k \(restitution\) must be in \[0, 1\]"),
    ("ricsac9", dict(law=KS, k=0.5, mu_c=-1), r"mu_c \(contact friction\) must be >= 0"),
    ("ricsac9", dict(law=KS, cap_friction=True, friction_limit=0.5), "contradicts law = "),
    ("ricsac9", dict(cap_friction=True), "cap_friction needs friction_limit"),
    ("ricsac9", dict(law="pc-crash"), "law must be one of"),
    ("ricsac9-pccrash", dict(beta=0.5), "beta does not apply to law 'kudlich-slibar'"),
    ("ricsac9-pccrash", dict(law="brach", k=0.3), "k is the restitution of law"),
])
def test_resolution_conflicts_name_the_options(case, options, message):
    with pytest.raises(ValueError, match=message):
        resolve_law(pim.load_case(case), **options)


def test_the_command_line_gets_the_same_conflicts_in_its_option_names(capsys):
    assert set(OPTION_NAMES) == set(API_NAMES)
    assert main(["solve", "ricsac9", "--law", KS, "--k", "0.5", "--eps", "0.3",
                 "--mu-c", "0.2"]) == 2
    assert "give --k or --eps, not both" in capsys.readouterr().err


def test_solve_command_names_the_law_it_applied(capsys):
    # the old command said "brach" in JSON and no cap in the title under --law brach-capped
    assert main(["solve", "ricsac9", "--law", "brach-capped", "--mu-c", "0.3", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["law"] == "brach-capped"
    assert main(["solve", "ricsac9", "--law", "brach-capped", "--mu-c", "0.3"]) == 0
    assert "(friction-capped Brach, effective beta)" in capsys.readouterr().out


def test_law_names_are_defined_once():
    defined = [p for p in ROOT.glob("*/**/*.py") if "LAW_NAMES = " in p.read_text()
               and "tests" not in p.parts]
    assert [p.relative_to(ROOT).as_posix() for p in defined] == ["pim/model/law.py"]


def test_solve_law_is_gone():
    assert not hasattr(pim, "solve_law")


def test_fit_restitution_holds_the_laws_own_parameter():
    from pim.model.law import fit_restitution

    brach, ks = pim.load_case("ricsac9"), pim.load_case("ricsac9-pccrash")
    assert fit_restitution(brach) is None
    assert fit_restitution(brach, eps=0.3) == 0.3
    assert fit_restitution(ks, k=0.2) == 0.2
    names = {**API_NAMES, "eps": "--eps", "k": "--k"}
    with pytest.raises(pim.InputError, match=r"^--k is the restitution of law kudlich-slibar "
                                             r"\(use --eps\)$"):
        fit_restitution(brach, k=0.2, names=names)
    with pytest.raises(pim.InputError, match="^--eps: the case's law is kudlich-slibar; hold "
                                             "k with --k$"):
        fit_restitution(ks, eps=0.2, names=names)
