"""pytest plugin (entry point ``pytest11``): regression fixtures for any test suite.

Installed with the project, it gives every test suite two fixtures::

    def test_my_case(pim_check):
        pim_check("cases/my-case.toml", "baselines/my-cases.json")

    def test_simulation_agrees(assert_agrees):
        import pim, sim
        case = pim.load_case("ricsac9")
        assert_agrees(pim.solve(case), sim.simulate(case), 1e-9)

``pim_check(case, baseline)`` reruns that case of a baseline (``pim baseline``) and fails
with the table of what moved beyond tolerance (``pim check``'s); ``assert_agrees(a, b, tol)``
fails when two answers to a case differ by more than ``tol`` in the project's one error
measure (:func:`comparisons.regression.baseline.agreement`). See docs/regression.md.

Loading the plugin imports only pytest: the baseline machinery (numpy, pim, sim, pymunk) is
imported when a fixture is first called, so installing the project adds nothing heavy to an
unrelated test suite's start (tests/comparisons/regression/test_plugin.py checks it).
"""

from __future__ import annotations

from pathlib import Path

import pytest

__all__ = ["pim_check", "assert_agrees", "check_case"]


def check_case(case: str, baseline) -> None:
    """Fail (AssertionError with the drift table) when ``case`` of ``baseline`` moved.

    ``case`` is a bundled name, the case's name, or the case file's path as the user types
    it (from the current folder, e.g. ``cases/my-case.toml``; any trailing part of the path
    is enough when the tests run from another folder) or as the baseline stores it
    (relative to the baseline's folder); ``baseline`` is the baseline file.
    """
    from comparisons.regression.baseline import check_baseline, format_report

    report = check_baseline(Path(baseline), [str(case)])
    if not report.ok:
        raise AssertionError("\n" + format_report(report))


@pytest.fixture
def pim_check():
    """``pim_check(case, baseline)``: assert that a case still matches its baseline."""
    return check_case


@pytest.fixture
def assert_agrees():
    """``assert_agrees(result_a, result_b, tol)``: assert that two answers to a case agree
    within ``tol`` by the project's one error measure; returns the error."""
    from comparisons.regression.baseline import assert_agrees as agrees

    return agrees
