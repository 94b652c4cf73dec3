"""The layout's rules, checked on the source (docs/architecture.md).

- Layers: pim.model <- pim.io <- pim.analysis <- pim.plotting <- pim (the top-level API,
  pim/__init__.py) <- sim <- comparisons <- pim_cli (the command line); a module never imports
  a layer above its own, so only sim, comparisons and pim_cli may ``import pim`` itself. pim
  never imports sim, comparisons or pim_cli; sim never imports comparisons; no package imports
  the command line.
- No private name (``_x``) is imported from another module.
- No function-level import of a project module, except the lazy loads of heavy optional
  parts listed in LAZY (numba's kernels, and the CLI's commands, which import on use so that
  ``pim --help`` stays fast).
- Every package directory has an ``__init__.py`` (so a regular install ships it).
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("pim", "sim", "comparisons", "pim_cli")
RANK = {"pim.model": 0, "pim.io": 1, "pim.analysis": 2, "pim.plotting": 3, "pim": 4,
        "sim": 5, "comparisons": 6, "pim_cli": 7}
#: Function-level imports allowed: (module, imported module) -- lazy loads, not cycle dodges.
LAZY = {("pim.model.solver", "pim.model.kernel"),
        ("pim.analysis.reconstruction", "pim.analysis.runout_fit_batch"),
        ("pim.analysis.runout_fit", "pim.model.runout_kernel"),
        ("pim.analysis.event", "pim.model.event_kernel"),
        ("sim.compliant_batch", "sim.compliant_kernel"),
        # the pytest plugin loads in every pytest run where the project is installed
        ("comparisons.regression.plugin", "comparisons.regression.baseline")}


def _modules():
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            rel = path.relative_to(ROOT).with_suffix("")
            parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
            yield ".".join(parts), path, rel.name == "__init__"


def _layer(module: str) -> str:
    parts = module.split(".")
    if parts[0] == "pim" and len(parts) > 1 and f"pim.{parts[1]}" in RANK:
        return f"pim.{parts[1]}"
    return parts[0]


def _imports(module: str, path: Path, is_package: bool):
    """(imported module, names, line, function-level) of each project import."""
    tree = ast.parse(path.read_text())
    package = module if is_package else module.rpartition(".")[0]
    functions = [n for n in ast.walk(tree)
                 if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef)]
    inner = {id(n) for f in functions for n in ast.walk(f)}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[:len(package.split(".")) - (node.level - 1)]
                base = ".".join(up + ([base] if base else []))
            if base.split(".")[0] in PACKAGES:
                yield base, [a.name for a in node.names], node.lineno, id(node) in inner
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] in PACKAGES:
                    yield alias.name, [], node.lineno, id(node) in inner


MODULES = list(_modules())


def violations(module: str, path: Path, is_package: bool) -> list[str]:
    """Every breach of the rules above in one module's source."""
    rank, found = RANK[_layer(module)], []
    for target, names, line, function_level in _imports(module, path, is_package):
        where = f"{path.name}:{line}"
        target_layer = _layer(target)
        if RANK[target_layer] > rank:
            found.append(f"{where}: {module} ({_layer(module)}) imports {target} ({target_layer})")
        if module.split(".")[0] == "pim" and target.split(".")[0] in ("sim", "comparisons",
                                                                        "pim_cli"):
            found.append(f"{where}: pim imports {target}")
        if module.split(".")[0] == "sim" and target.split(".")[0] in ("comparisons", "pim_cli"):
            found.append(f"{where}: sim imports {target}")
        private = [n for n in names if n.startswith("_") and not n.startswith("__")]
        if private:
            found.append(f"{where}: private names {private} imported from {target}")
        if (function_level and not module.startswith("pim_cli")
                and (module, target) not in LAZY):
            found.append(f"{where}: function-level import of {target}")
    return found


@pytest.mark.parametrize("module, path, is_package", MODULES, ids=[m[0] for m in MODULES])
def test_layers_private_names_and_function_level_imports(module, path, is_package):
    assert violations(module, path, is_package) == []


@pytest.mark.parametrize("planted, expected", [
    ("import pim", "pim.model.energy (pim.model) imports pim (pim)"),
    ("from pim import solve", "imports pim (pim)"),
    ("from .. import analysis", "pim.model.energy (pim.model) imports pim (pim)"),
    ("from ...sim import run", "pim imports sim"),
    ("from .geometry import _private", "private names ['_private']"),
])
def test_a_planted_breach_is_caught(tmp_path, planted, expected):
    """The rules fail on a breach planted in a copy of pim/model/energy.py (the hole through
    which any layer could ``import pim`` is closed)."""
    source = (ROOT / "pim" / "model" / "energy.py").read_text()
    assert violations("pim.model.energy", ROOT / "pim" / "model" / "energy.py", False) == []
    copy = tmp_path / "energy.py"
    copy.write_text(f"{planted}\n{source}")
    found = violations("pim.model.energy", copy, False)
    assert any(expected in text for text in found), found


def test_only_the_command_line_and_outside_packages_import_pim_itself():
    importers = {module for module, path, is_package in MODULES
                 for target, *_ in _imports(module, path, is_package) if target == "pim"}
    assert importers and all(_layer(m) in ("pim_cli", "sim", "comparisons") for m in importers)


def test_every_package_directory_has_an_init():
    for package in PACKAGES:
        for folder in (ROOT / package).rglob("*"):
            if folder.is_dir() and any(folder.glob("*.py")):
                assert (folder / "__init__.py").exists(), folder
