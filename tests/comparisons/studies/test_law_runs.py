"""comparisons/studies/law_runs.py: each impact law's analytic answer and the pymunk run that
cross-checks it (issue 18: compare and animate under the law)."""

import math

import numpy as np
import pytest

import pim
import sim
from comparisons.studies.law_runs import law_setup, simulate_law
from pim.model.impact_laws import brach_as_kudlich_slibar, solve_kudlich_slibar
from sim.kudlich_slibar import KudlichSlibarRun


def test_kudlich_slibar_setup_is_solve_laws_answer_and_names_its_parameters():
    case = pim.load_case("ricsac9")
    setup = law_setup(case, "kudlich-slibar", 0.1, None, 0.6)
    r = solve_kudlich_slibar(case, 0.1, 0.6)
    np.testing.assert_array_equal(setup.result.velocity1, r.velocity1)
    assert (setup.restitution, setup.contact_friction) == (0.1, 0.6)
    assert setup.describe() == ("Kudlich-Slibar law (PC-Crash, Virtual CRASH), k = 0.1, "
                                "mu_c = 0.6")


def test_capped_setup_carries_the_effective_beta_and_the_cap():
    case = pim.load_case("ricsac9")
    setup = law_setup(case, "brach-capped", 0.355, 1.0, 0.3)
    mu0 = float(pim.solve(case, 0.355, 1.0).mu0)
    assert setup.beta == pytest.approx(0.3 / mu0, rel=1e-12)      # capped: |mu| = mu_c
    assert "cap mu_c = 0.3" in setup.describe()


@pytest.mark.parametrize("law,args", [("kudlich-slibar", (0.1, None, 0.6)),
                                      ("kudlich-slibar", (0.3, None, 0.2)),
                                      ("brach-capped", (0.355, 1.0, 0.3)),
                                      ("brach", (0.355, 0.8, None))])
@pytest.mark.parametrize("name", ["ricsac9", "hard-gamma37", "hard-barrier"])
def test_the_laws_run_reproduces_its_analytic_answer(name, law, args):
    case = pim.load_case(name)
    setup = law_setup(case, law, *args)
    run = simulate_law(case, setup)
    assert isinstance(run, KudlichSlibarRun) == (law == "kudlich-slibar")
    scale = float(np.abs(setup.result.delta_v1).max())
    assert np.abs(run.velocity1 - setup.result.velocity1).max() < 1e-8 * scale
    assert np.abs(run.velocity2 - setup.result.velocity2).max() < 1e-8 * scale


def test_an_always_sticking_contact_runs_with_a_large_coulomb_coefficient():
    case = pim.load_case("ricsac9")
    setup = law_setup(case, "kudlich-slibar", 0.2, None, math.inf)
    run = simulate_law(case, setup, sim.Settings(record=True, duration=0.1))
    np.testing.assert_allclose(run.velocity1, setup.result.velocity1, atol=1e-9)
    assert run.trajectory.time[-1] == pytest.approx(0.1)


def test_brachs_sheet_answer_maps_to_the_bundled_pccrash_parameters():
    case = pim.load_case("ricsac9")
    k, mu_c = brach_as_kudlich_slibar(case, 0.355, 1.0)
    assert float(k) == 0.355
    assert float(mu_c) == pytest.approx(0.512, abs=5e-4)  # mu0(0.355), the sheet's printed value
