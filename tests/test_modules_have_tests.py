"""Every module of pim/, sim/ and comparisons/ has its own test file that imports it
(pvlib's layout): tests/test_<module>.py, or the file named in EXCEPTIONS.

"Imports it" is read from the test file's source (ast): ``import pkg.mod``, ``from pkg.mod
import ...``, ``from pkg import mod``, or (for a module whose public names a package
re-exports, e.g. ``sim.simulate`` from sim/run.py) a use ``pkg.name`` / ``from pkg import
name`` of a name in the module's ``__all__``. A command-line module counts as imported when
its test file imports the package's command group (``pim.cli`` / ``sim.cli`` / ...), through
which its commands run.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("pim", "sim", "comparisons")
#: module -> its test file, where the stem alone does not name it (shared stems, commands
#: exercised through their command, modules tested with the study that uses them).
EXCEPTIONS = {
    "pim/cli/main.py": "test_cli.py",
    "pim/cli/fit.py": "test_fitting.py",            # pim fit / sensitivity / plot commands
    "pim/cli/uncertainty.py": "test_montecarlo.py",  # pim uncertainty
    "pim/cli/reconstruct.py": "test_reconstruct.py",
    "pim/cli/validate.py": "test_validate.py",
    "sim/cli.py": "test_cli.py",
    "comparisons/cli.py": "test_cli.py",
    "sim/run.py": "test_sim.py",
    "sim/batch.py": "test_sim.py",
    "sim/settings.py": "test_sim.py",
    "sim/failures.py": "test_sim_defects.py",
    "sim/limits.py": "test_sim.py",
    "sim/compliant_setup.py": "test_compliant.py",
    "comparisons/motion.py": "test_animation.py",
    "comparisons/tables.py": "test_comparison_tables.py",   # test_tables: pim.plotting.tables
    "comparisons/hard_cases.py": "test_hard_case_table.py",  # test_hard_cases: pim on them
    "sim/result.py": "test_sim_result.py",                  # test_result: pim.model.result
    "sim/compliant_batch.py": "sim/test_compliant_batch.py",
    "sim/compliant_kernel.py": "sim/test_compliant_batch.py",   # the engine behind it
    "sim/compliant_formula.py": "sim/test_compliant_formula.py",
}
COMMAND_GROUPS = {"pim": "pim.cli", "sim": "sim.cli", "comparisons": "comparisons.cli"}


def _name(path: Path) -> str:
    return ".".join(path.relative_to(ROOT).with_suffix("").parts)


def _public(path: Path) -> set[str]:
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__"
                                                for t in node.targets):
            return {ast.literal_eval(e) for e in node.value.elts}
    return set()


def imports_module(test_source: str, module: str, public: set[str]) -> bool:
    """Whether a test file's source imports ``module`` (module notes)."""
    package, _, stem = module.rpartition(".")
    tree = ast.parse(test_source)
    top = module.split(".")[0]
    if stem == "cli" or module.startswith("pim.cli."):
        # commands run through pim's command group, which loads sim's and comparisons'
        wanted = {module, COMMAND_GROUPS[top], "pim.cli", "pim.cli.main"}
    else:
        wanted = {module}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import) and any(a.name in wanted for a in node.names):
            return True
        if isinstance(node, ast.ImportFrom) and node.module:
            if node.module in wanted:
                return True
            names = {a.name for a in node.names}
            if node.module == package and (stem in names or names & public):
                return True
            if f"{node.module}.{next(iter(names))}" in wanted:
                return True
            if node.module == top and names & public:
                return True
        if (isinstance(node, ast.Attribute) and node.attr in public
                and ast.unparse(node.value) in (package, top)):
            return True
    return False


MODULES = sorted(p for package in PACKAGES for p in (ROOT / package).rglob("*.py")
                 if p.name != "__init__.py")


@pytest.mark.parametrize("path", MODULES, ids=[str(p.relative_to(ROOT)) for p in MODULES])
def test_module_has_its_own_test_file_that_imports_it(path):
    rel = str(path.relative_to(ROOT))
    test = ROOT / "tests" / EXCEPTIONS.get(rel, f"test_{path.stem}.py")
    assert test.exists(), f"{rel}: no tests/{test.name}"
    assert imports_module(test.read_text(), _name(path), _public(path)), (
        f"{rel}: tests/{test.name} does not import it")


def test_an_unrelated_test_file_is_not_enough():
    assert not imports_module("import numpy\nimport pim\n", "pim.model.energy",
                              {"energy_loss"})
    assert imports_module("from pim.model.energy import energy_loss\n", "pim.model.energy",
                          set())
    assert imports_module("import sim\nsim.simulate(case)\n", "sim.run", {"simulate"})
    assert not imports_module("import sim\nsim.simulate(case)\n", "sim.batch",
                              {"simulate_many"})


def test_exceptions_are_current():
    assert all((ROOT / module).exists() for module in EXCEPTIONS)
