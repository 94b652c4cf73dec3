"""The Examples of the docstrings and the Python blocks of the README and docs/ run.

Every module of pim/, sim/ and comparisons/ whose source holds a ``>>>`` example is run by
doctest (found by reading the files, so a new example joins by itself); every fenced
```python block of README.md and docs/*.md is executed in a fresh namespace in a temporary
folder. An example that raises or prints something else than it shows fails here.
"""

import doctest
import importlib
import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("pim", "sim", "comparisons", "pim_cli")
FENCE = re.compile(r"^```python\n(.*?)^```", re.M | re.S)


def _module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


WITH_EXAMPLES = sorted(_module_name(p) for package in PACKAGES
                       for p in (ROOT / package).rglob("*.py") if ">>>" in p.read_text())
BLOCKS = [(f"{path.relative_to(ROOT)}#{k}", code)
          for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
          for k, code in enumerate(FENCE.findall(path.read_text()), start=1)]


def run_doctests(module) -> doctest.TestResults:
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in finder.find(module, module.__name__):
        runner.run(test)
    return runner.summarize(verbose=False)


@pytest.mark.parametrize("name", WITH_EXAMPLES)
def test_docstring_examples_run(name):
    results = run_doctests(importlib.import_module(name))
    assert results.attempted > 0 and results.failed == 0, name


@pytest.mark.parametrize("where, code", BLOCKS, ids=[b[0] for b in BLOCKS])
def test_markdown_python_blocks_run(where, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, where, "exec"), {"__name__": "__example__"})


def test_a_wrong_example_fails(tmp_path, monkeypatch):
    """The runner is able to fail: a planted example with a wrong answer."""
    (tmp_path / "planted_example.py").write_text(
        '"""\n>>> 1 + 1\n3\n"""\n')
    monkeypatch.syspath_prepend(str(tmp_path))
    results = run_doctests(importlib.import_module("planted_example"))
    assert results.attempted == 1 and results.failed == 1


def test_examples_are_found():
    assert "pim.model.solver" in WITH_EXAMPLES and any(w.startswith("README") for w, _ in BLOCKS)
    assert os.sep not in "".join(WITH_EXAMPLES)
