"""pim/model/admissibility.py: every inadmissible result is flagged with a reason."""

import numpy as np

import pim


def test_admissible_ricsac9_has_no_problems():
    r = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    assert bool(r.admissible) and r.problems() == []


def test_each_flag_gives_its_reason():
    case = pim.load_case("ricsac9")
    assert any("|mu| > |mu0|" in p for p in pim.solve(case, 0.355, 1.4).problems())
    away = case.transformed(rotation=0.0)
    v1 = away.vehicle1
    separating = pim.Case(pim.Vehicle(v1.mass, v1.yaw_inertia, v1.cg, -v1.velocity),
                          away.vehicle2, away.impact)
    r = pim.solve(separating, 0.355, 1.0)
    assert not bool(r.approaching) and not bool(r.admissible)
    assert any("do not approach" in p for p in r.problems())
    batch = pim.solve(case, np.array([0.355, 0.355]), np.array([1.0, 1.4]))
    assert batch.admissible.tolist() == [True, False]
    assert any("(1 of 2 cases)" in p for p in batch.problems())


def test_problem_counts_add_up_over_chunks():
    """problem_counts (pim.model.admissibility) gives the counts that problems() words, so a
    chunked Monte Carlo can add them."""
    from pim.model.admissibility import Admissibility

    case = pim.load_case("ricsac9")
    r = pim.solve(case, 0.355, np.array([0.5, 1.0, 1.2, 1.3]))
    assert isinstance(r, Admissibility)
    counts = r.problem_counts()
    reverses = [(text, bad, n) for text, bad, n in counts if "beta > 1" in text]
    assert [(bad, n) for _, bad, n in reverses] == [(2, 4)]      # beta 1.2 and 1.3 of 4
    assert "tangential slip at C reverses" in reverses[0][0]
    assert r.problems() == [f"{text} ({bad} of {n} cases)" for text, bad, n in counts]


def test_unsolvable_says_why_only_where_q_is_singular():
    from tests.pim.test_hard_cases import singular_beta

    case = pim.load_case("hard-eps0")
    assert pim.solve(case, 0.0, 1.0).unsolvable() is None
    singular = pim.solve(case, 0.0, singular_beta(case, 0.0))
    assert bool(np.any(singular.q_singular))
    assert "q is singular" in singular.unsolvable()
