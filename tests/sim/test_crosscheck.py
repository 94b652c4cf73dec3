"""PIM against the pymunk simulation of one case (sim.crosscheck)."""

import dataclasses

import pytest

import pim
from sim.crosscheck import CrossCheck, crosscheck, crosscheck_law
from sim.kudlich_slibar import KudlichSlibarCheck, crosscheck_kudlich_slibar


def under(law: str, **impact):
    """RICSAC 9 under ``law`` (restitution 0.355, and the other impact fields given)."""
    case = pim.load_case("ricsac9")
    fields = dict(law=law, restitution=0.355, **impact)
    return dataclasses.replace(case, impact=dataclasses.replace(case.impact, **fields))


def test_ricsac9_crosscheck_agrees_and_tabulates():
    check = crosscheck(pim.load_case("ricsac9"), eps=0.355, beta=1.0)
    assert isinstance(check, CrossCheck) and check.limitations == []
    assert (check.eps, check.beta) == (0.355, 1.0)
    # sticking contact (beta = 1) on the fixed-step engine: agreement to 1e-6 of the change
    # (docs/sim.md), the one error measure of sim.error_measure
    assert check.error < 1e-6
    assert "velocity" in check.format_table()


def test_bad_input_is_a_value_error():
    with pytest.raises(ValueError):
        crosscheck(pim.load_case("ricsac9"), eps=2.0, beta=1.0)


def test_crosscheck_law_runs_brachs_law_as_crosscheck_does():
    case = under("brach", beta=1.0)
    check = crosscheck_law(case)
    assert isinstance(check, CrossCheck) and (check.eps, check.beta) == (0.355, 1.0)
    assert check.error == crosscheck(case, 0.355, 1.0).error


def test_crosscheck_law_runs_the_capped_law_at_its_effective_beta():
    """Brach's beta capped by mu_c: the rigid scene at the smaller, effective beta."""
    case = under("brach-capped", beta=1.0, contact_friction=0.1)
    check = crosscheck_law(case)
    effective = float(pim.solve(case).beta)
    assert 0 < effective < 1.0                           # the cap bites on this case
    assert check.beta == effective and check.eps == 0.355
    assert check.error == crosscheck(case, 0.355, effective).error


def test_crosscheck_law_runs_kudlich_slibar_in_two_phases_and_takes_no_eps():
    case = under("kudlich-slibar", beta=None, contact_friction=0.4)
    check = crosscheck_law(case)
    assert isinstance(check, KudlichSlibarCheck) and (check.k, check.mu_c) == (0.355, 0.4)
    assert check.error == crosscheck_kudlich_slibar(case).error
    with pytest.raises(pim.InputError, match="^eps and beta do not apply"):
        crosscheck_law(case, eps=0.3)
    with pytest.raises(pim.InputError, match="^--eps and --beta do not apply"):
        crosscheck_law(case, beta=0.3, names={"eps": "--eps", "beta": "--beta"})
