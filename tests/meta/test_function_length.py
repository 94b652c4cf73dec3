"""No function or method over 80 lines outside the compiled kernel (issue 21, "Done when").

A function's length is ``end_lineno - lineno + 1`` as ast reports it: from its ``def`` line to
its last line, docstring and nested functions included (decorators excluded). The compiled
kernel's functions (numba, where a call costs more than an inlined line) are exempt by name in
ALLOWED; every other function of pim/, sim/, comparisons/ and pim_cli/ must be readable at
once.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("pim", "sim", "comparisons", "pim_cli")
LIMIT = 80
#: (file, function) exempt from the limit: the compiled kernel's functions only.
ALLOWED = {
    ("pim/model/kernel.py", name) for name in (
        "_sincos", "_impact", "_case", "_solve_kernel_fast", "_solve_block",
        "_solve_kernel_simd", "_solve_kernel_libm", "_copy_kernel")
} | {
    ("pim/model/runout_kernel.py", name) for name in ("_segment_distance", "_integrate")
}


def long_functions(source: str, filename: str) -> list[tuple[str, str, int]]:
    """(file, qualified name, lines) of every function in ``source`` over LIMIT lines,
    except those in ALLOWED."""
    found = []

    def visit(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                length = child.end_lineno - child.lineno + 1
                if length > LIMIT and (filename, child.name) not in ALLOWED:
                    found.append((filename, prefix + child.name, length))
                visit(child, f"{prefix}{child.name}.")
            elif isinstance(child, ast.ClassDef):
                visit(child, f"{prefix}{child.name}.")
            else:
                visit(child, prefix)

    visit(ast.parse(source), "")
    return found


def _sources():
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            yield path.relative_to(ROOT).as_posix(), path.read_text()


def test_no_function_over_the_limit():
    offenders = [hit for name, source in _sources() for hit in long_functions(source, name)]
    assert not offenders, "\n".join(f"{f}: {n} has {k} lines (limit {LIMIT})"
                                    for f, n, k in offenders)


def test_every_package_is_walked():
    names = {name for name, _ in _sources()}
    for package in PACKAGES:
        assert any(n.startswith(package + "/") for n in names), package


def test_allow_list_names_existing_kernel_functions():
    """A renamed kernel function must not leave a stale exemption behind."""
    for filename, function in ALLOWED:
        tree = ast.parse((ROOT / filename).read_text())
        names = {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
        assert function in names, (filename, function)


def _function(name: str, lines: int, indent: str = "") -> str:
    """Source of a function spanning exactly ``lines`` lines (def line included)."""
    body = [f"{indent}    x{i} = {i}" for i in range(lines - 2)]
    return "\n".join([f"{indent}def {name}():", *body, f"{indent}    return 0"]) + "\n"


@pytest.mark.parametrize("lines, expected", [(LIMIT, 0), (LIMIT + 1, 1)])
def test_planted_function_is_caught(lines, expected):
    source = _function("planted", lines)
    assert len(long_functions(source, "pim/planted.py")) == expected


def test_planted_method_and_nested_function_are_caught():
    method = "class A:\n" + _function("method", LIMIT + 1, indent="    ")
    assert long_functions(method, "sim/planted.py") == [("sim/planted.py", "A.method",
                                                         LIMIT + 1)]
    nested = "def outer():\n" + _function("inner", LIMIT + 1, indent="    ")
    assert [n for _, n, _ in long_functions(nested, "x.py")] == ["outer", "outer.inner"]


def test_exemption_is_by_file_and_name():
    source = _function("_solve_block", LIMIT + 1)
    assert long_functions(source, "pim/model/kernel.py") == []
    assert len(long_functions(source, "pim/model/solver.py")) == 1
