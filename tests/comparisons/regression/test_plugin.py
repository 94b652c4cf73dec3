"""comparisons.regression.plugin: the fixtures are registered through the pytest11 entry point,
pim_check fails with the drift table, assert_agrees with the error measure."""

import json
from pathlib import Path

import pytest

import pim
from comparisons.regression.baseline import make_baseline
from comparisons.regression.plugin import check_case


def test_the_plugin_is_loaded_by_its_entry_point(pytestconfig):
    assert pytestconfig.pluginmanager.has_plugin("pim_regression")


def test_pim_check_fails_with_the_drift_table(tmp_path):
    doc = make_baseline(["hard-pole"], sections=["solve"])
    doc["cases"][0]["quantities"]["solve.speed1"]["value"] *= 1.01
    (tmp_path / "b.json").write_text(json.dumps(doc))
    with pytest.raises(AssertionError, match="solve.speed1") as err:
        check_case("hard-pole", tmp_path / "b.json")
    assert "1 of" in str(err.value) and "tolerance" in str(err.value)
    doc["cases"][0]["quantities"]["solve.speed1"]["value"] /= 1.01
    (tmp_path / "b.json").write_text(json.dumps(doc))
    check_case("hard-pole", tmp_path / "b.json")


def test_fixtures_work_in_a_users_test_suite(tmp_path, monkeypatch):
    """A test file outside the project uses the fixtures with no import or conftest."""
    doc = make_baseline(["hard-barrier"], sections=["solve"])
    (tmp_path / "b.json").write_text(json.dumps(doc))
    (tmp_path / "test_user.py").write_text(
        "import pim\n\n"
        "def test_ok(pim_check):\n"
        "    pim_check('hard-barrier', 'b.json')\n\n"
        "def test_differs(assert_agrees):\n"
        "    case = pim.load_case('hard-barrier')\n"
        "    assert_agrees(pim.solve(case, 0.1, 1.0), pim.solve(case, 0.5, 1.0), 1e-6)\n")
    outcomes = {}

    class Collect:
        def pytest_runtest_logreport(self, report):
            if report.when == "call":
                outcomes[report.nodeid.split("::")[-1]] = (report.outcome, report.longreprtext)

    monkeypatch.chdir(tmp_path)
    # a fresh pytest session on the user's folder: the plugin comes from its entry point
    code = pytest.main(["-q", "-p", "no:cacheprovider", "--rootdir", str(tmp_path),
                        str(tmp_path / "test_user.py")], plugins=[Collect()])
    assert code == pytest.ExitCode.TESTS_FAILED
    assert outcomes["test_ok"][0] == "passed"
    assert outcomes["test_differs"][0] == "failed"
    assert "largest error in the velocity changes" in outcomes["test_differs"][1]


def test_the_example_test_file_exists_and_uses_both_fixtures():
    text = (Path(__file__).resolve().parent / "test_plugin_example.py").read_text()
    assert "pim_check" in text and "assert_agrees" in text
    assert pim.list_cases()


def test_loading_the_plugin_imports_nothing_heavy():
    """Issue 27: the plugin loads in every pytest run where the project is installed; it
    imported pim, sim, pymunk and numpy (0.6-0.8 s) through the baseline module and
    comparisons/__init__. Loaded in a fresh interpreter, it now imports none of them."""
    import subprocess
    import sys

    heavy = ("numpy", "scipy", "pymunk", "matplotlib", "numba", "pint", "imageio", "pim", "sim",
             "comparisons.regression.baseline")
    code = ("import sys, comparisons.regression.plugin; "
            f"print(','.join(m for m in {heavy!r} if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == ""
