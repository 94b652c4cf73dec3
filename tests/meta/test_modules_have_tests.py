"""Every module of pim/, sim/, comparisons/ and pim_cli/ has its own test file that imports
it, in the folder of tests/ that mirrors its package (pvlib's layout): the module
``pkg/sub/mod.py`` is tested by ``tests/pkg/sub/test_mod.py``, or by the file named in
EXCEPTIONS.

"Imports it" is read from the test file's source (ast): ``import pkg.mod``, ``from pkg.mod
import ...``, ``from pkg import mod``, or (for a module whose public names a package
re-exports, e.g. ``sim.simulate`` from sim/run.py) a use ``pkg.name`` / ``from pkg import
name`` of a name in the module's ``__all__``. A command-line module counts as imported when
its test file imports the command group (``pim_cli.main``), through which its commands run.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("pim", "sim", "comparisons", "pim_cli")
#: module -> its test file (relative to tests/), where the mirrored name does not name it
#: (commands exercised through their command, modules tested with the study that uses them).
EXCEPTIONS = {
    "pim_cli/fit.py": "pim/analysis/test_fitting.py",        # pim fit / sensitivity / plot
    "pim_cli/uncertainty.py": "pim/analysis/test_montecarlo.py",  # pim uncertainty
    "pim_cli/sim.py": "pim_cli/test_main.py",
    "pim_cli/solve.py": "pim_cli/test_main.py",                # pim solve / draw / cases
    "pim_cli/compare.py": "pim_cli/test_main.py",
    "sim/run.py": "sim/test_sim.py",
    "sim/batch.py": "sim/test_sim.py",
    "sim/settings.py": "sim/test_sim.py",
    "sim/limits.py": "sim/test_sim.py",
    "sim/compliant_setup.py": "sim/test_compliant.py",
    "comparisons/animation/motion.py": "comparisons/animation/test_collision.py",
    "pim_cli/event.py": "pim_cli/test_event.py",
    "pim/plotting/validation.py": "pim/analysis/test_validation.py",
    "sim/compliant_kernel.py": "sim/test_compliant_batch.py",   # the engine behind it
}
COMMAND_GROUP = "pim_cli.main"


def mirrored_test(path: Path) -> Path:
    """The test file of the module at ``path`` (module notes)."""
    rel = path.relative_to(ROOT)
    default = rel.parent / f"test_{path.stem}.py"
    return ROOT / "tests" / EXCEPTIONS.get(str(rel), str(default))


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
    # commands run through pim's command group, which loads every command module
    wanted = {module, COMMAND_GROUP} if top == "pim_cli" else {module}
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
                 if p.name not in ("__init__.py", "__main__.py"))


@pytest.mark.parametrize("path", MODULES, ids=[str(p.relative_to(ROOT)) for p in MODULES])
def test_module_has_its_own_test_file_that_imports_it(path):
    rel = str(path.relative_to(ROOT))
    test = mirrored_test(path)
    shown = test.relative_to(ROOT)
    assert test.exists(), f"{rel}: no {shown}"
    assert imports_module(test.read_text(), _name(path), _public(path)), (
        f"{rel}: {shown} does not import it")


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
