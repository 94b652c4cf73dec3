"""No function takes more than 8 positional parameters or 12 in all (issue 27 point 7).

Counted on the source (ast) of pim/, sim/, comparisons/ and pim_cli/: a parameter that can
be given by position (positional-only or ordinary) is positional, one after ``*`` is
keyword-only; ``self`` and ``cls`` of a method are not counted, nor ``*args`` and
``**kwargs`` (they name no parameter). Where the arguments travel together they are one
dataclass; where they are options, keyword-only.

Exempt: compiled kernels, whose arguments are the numbers numba compiles a loop over:
functions with a numba decorator (``njit``, ``jit``, ``vectorize``, ``guvectorize``,
``cfunc``, ``stencil``, bare or ``numba.``-qualified, called or not), functions compiled by
wrapping (``njit(...)(tyres.wheel_force)``, found anywhere in the project and resolved
through the module's imports) and every function of a module compiled whole
(``compile_module(compliant_formula, ...)``: the compliant scene's formula, which the
pymunk scene runs on floats and numba compiles into the batch integrator); click commands
(decorated by a ``command`` or ``group`` decorator), whose parameters are their options.

The same limit holds where a function or class is called: no call passes more than 8
positional arguments to a project function or class (a dataclass built from 9 positional
values is as hard to read as a function that takes them), except to the exempt ones. The
callee is resolved through the module's imports (``formula.point_contact`` is the compiled
formula's, ``point_contact`` imported from ``sim.compliant_setup`` is not); a method call
(``self.f(...)``, ``obj.f(...)``) is checked when some project definition of that name is
not exempt.

PENDING lists the functions left to the helpers who own their files; each must still
breach (a fixed one must leave the list).
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("pim", "sim", "comparisons", "pim_cli")
MAX_POSITIONAL, MAX_ALL = 8, 12
NUMBA = {"njit", "jit", "vectorize", "guvectorize", "cfunc", "stencil"}
#: A project function that compiles every function of the module it is given.
MODULE_COMPILERS = {"compile_module"}
#: (file, function) left to the helpers who own the files.
PENDING: set[tuple[str, str]] = set()
#: Calls (file, callee) left to the helpers who own the calling file, for the same reason.
PENDING_CALLS: set[tuple[str, str]] = set()


def _name(node) -> str:
    """The last name of a decorator or callee: ``numba.njit(...)`` -> "njit"."""
    node = node.func if isinstance(node, ast.Call) else node
    if isinstance(node, ast.Attribute):
        return node.attr
    return node.id if isinstance(node, ast.Name) else ""


def _is_numba(decorator) -> bool:
    return _name(decorator) in NUMBA


def _is_click_command(decorator) -> bool:
    return _name(decorator) in ("command", "group")


def _positional(call: ast.Call) -> int:
    return len([a for a in call.args if not isinstance(a, ast.Starred)])


def _sources():
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            yield path.relative_to(ROOT).as_posix(), path.read_text()


def _module_path(dotted: str, files) -> str | None:
    """The file of the module ``dotted`` ("sim/compliant_setup" or "pim"), if a project one."""
    for candidate in (f"{dotted}.py", f"{dotted}/__init__.py"):
        if candidate in files:
            return candidate
    return None


def imports(filename: str, tree: ast.Module, files) -> dict[str, tuple[str, str | None]]:
    """Local name -> (file, None) for each project module ``filename`` imports as a module
    (``from . import tyres``, ``from pim.model import formula``, ``import pim.model.x as
    x``, ``import pim``), (file, name) for each name it imports from one."""
    package = Path(filename).parent
    out = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package
                for _ in range(node.level - 1):
                    base = base.parent
                base = base / (node.module or "").replace(".", "/")
            else:
                base = Path((node.module or "").replace(".", "/"))
            for alias in node.names:
                module = _module_path((base / alias.name).as_posix(), files)
                owner = _module_path(base.as_posix(), files)
                if module is not None:
                    out[alias.asname or alias.name] = (module, None)
                elif owner is not None:
                    out[alias.asname or alias.name] = (owner, alias.name)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                module = _module_path(alias.name.replace(".", "/"), files)
                if module is not None and (alias.asname or "." not in alias.name):
                    out[alias.asname or alias.name] = (module, None)
    return out


class Index:
    """Every project function and class by (file, name), which of them are exempt, and
    each module's imports (module notes)."""

    def __init__(self, sources):
        self.trees = {filename: ast.parse(source) for filename, source in sources}
        files = set(self.trees)
        self.imports = {f: imports(f, tree, files) for f, tree in self.trees.items()}
        self.kernels, self.compiled_modules = self._compiled()
        self.defined, self.exempt, self.top = set(), set(), {}
        for filename, tree in self.trees.items():
            self._index(filename, tree)

    def _target(self, filename: str, node) -> tuple[str, str | None] | None:
        """(file, name) of ``module.f`` or of an imported ``f``; (file, None) of a module."""
        modules = self.imports[filename]
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            module = modules.get(node.value.id)
            if module is not None and module[1] is None:
                return module[0], node.attr
        elif isinstance(node, ast.Name) and node.id in modules:
            return modules[node.id]
        return None

    def _compiled(self) -> tuple[set, set]:
        """(file, function) of every function compiled by wrapping, ``njit(...)(module.f)``
        or ``njit(module.f)``; the files of the modules compiled whole (MODULE_COMPILERS)."""
        kernels, modules = set(), set()
        for filename, tree in self.trees.items():
            for node in ast.walk(tree):
                if not isinstance(node, ast.Call):
                    continue
                if isinstance(node.func, ast.Call) and _is_numba(node.func):
                    targets = node.args
                elif _is_numba(node) and node.args:
                    targets = node.args[:1]
                elif _name(node) in MODULE_COMPILERS and node.args:
                    target = self._target(filename, node.args[0])
                    if target is not None and target[1] is None:
                        modules.add(target[0])
                    continue
                else:
                    continue
                for target in (self._target(filename, t) for t in targets):
                    if target is not None and target[1] is not None:
                        kernels.add(target)
        return kernels, modules

    def _index(self, filename: str, tree: ast.Module) -> None:
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                key = (filename, node.name)
                self.defined.add(key)
                if (filename in self.compiled_modules or key in self.kernels
                        or any(_is_numba(d) or _is_click_command(d)
                               for d in node.decorator_list)
                        or getattr(getattr(node, "args", None), "vararg", None)):
                    self.exempt.add(key)
            elif (isinstance(node, ast.Assign) and isinstance(node.value, ast.Call)
                  and (_is_numba(node.value) or _is_numba(node.value.func))):
                self.exempt.update((filename, t.id) for t in node.targets
                                   if isinstance(t, ast.Name))
        self.top[filename] = {n.name for n in tree.body if isinstance(
            n, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef)}

    def resolve(self, filename: str, name: str, depth: int = 0) -> tuple[str, str] | None:
        """The (file, name) that defines ``name`` as seen from ``filename`` (through
        imports and re-exports), or None (not a project function or class)."""
        if name in self.top.get(filename, ()):
            return filename, name
        target = self.imports.get(filename, {}).get(name)
        if target is None or target[1] is None or depth > 5:
            return None
        return self.resolve(target[0], target[1], depth + 1)

    def callee(self, filename: str, call: ast.Call) -> tuple[str, list] | None:
        """(name, the definitions it may be) of the project function or class ``call``
        calls, or None."""
        func = call.func
        if isinstance(func, ast.Name):
            found = self.resolve(filename, func.id)
            return (func.id, [found]) if found in self.defined else None
        if not isinstance(func, ast.Attribute):
            return None
        target = self._target(filename, func)
        if target is not None:
            found = self.resolve(target[0], target[1])
            return (func.attr, [found]) if found in self.defined else None
        if isinstance(func.value, ast.Name) and func.value.id in self.imports[filename]:
            return None                             # a name imported, not a module
        if isinstance(func.value, ast.Name) and _external(self.trees[filename], func.value.id):
            return None                             # np.f(...), math.f(...)
        same = [d for d in self.defined if d[1] == func.attr]
        return (func.attr, same) if same else None


def _external(tree: ast.Module, name: str) -> bool:
    """Whether ``name`` is a module ``tree`` imports from outside the project."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            if any((a.asname or a.name.split(".")[0]) == name for a in node.names):
                return True
        elif isinstance(node, ast.ImportFrom) and not node.level:
            if any((a.asname or a.name) == name for a in node.names):
                return True
    return False


def _counts(function, method: bool) -> tuple[int, int]:
    args = function.args
    positional = [a.arg for a in args.posonlyargs + args.args]
    if method and positional[:1] in (["self"], ["cls"]):
        positional = positional[1:]
    return len(positional), len(positional) + len(args.kwonlyargs)


def signature_breaches(source: str, filename: str, exempt=frozenset()) -> list[str]:
    """Every function of ``source`` over the limits (module notes), except those ``exempt``
    ((file, name)) or compiled by decorator or a click command."""
    found = []

    def visit(node, prefix, in_class):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                positional, total = _counts(child, in_class)
                skip = ((filename, child.name) in exempt
                        or any(_is_numba(d) or _is_click_command(d)
                               for d in child.decorator_list))
                if not skip and (positional > MAX_POSITIONAL or total > MAX_ALL):
                    found.append(f"{filename}:{child.lineno} {prefix}{child.name} takes "
                                 f"{positional} positional, {total} in all")
                visit(child, f"{prefix}{child.name}.", False)
            elif isinstance(child, ast.ClassDef):
                visit(child, f"{prefix}{child.name}.", True)
            else:
                visit(child, prefix, in_class)

    visit(ast.parse(source), "", False)
    return found


def call_breaches(filename: str, index: Index, pending=frozenset()) -> list[str]:
    """Every call in ``filename`` passing more than MAX_POSITIONAL positional arguments to a
    project function or class that is not exempt (module notes), except ``pending``
    ((file, callee))."""
    found = []
    for node in ast.walk(index.trees[filename]):
        if not isinstance(node, ast.Call) or _positional(node) <= MAX_POSITIONAL:
            continue
        callee = index.callee(filename, node)
        if (callee is not None and (filename, callee[0]) not in pending
                and any(d not in index.exempt for d in callee[1])):
            found.append(f"{filename}:{node.lineno} calls {callee[0]} with "
                         f"{_positional(node)} positional arguments")
    return sorted(found)


SOURCES = list(_sources())
INDEX = Index(SOURCES)


def _exempt_definitions(index: Index) -> set:
    return index.exempt | {(f, n) for f in index.compiled_modules for n in index.top[f]}


def test_no_function_takes_too_many_parameters():
    exempt = _exempt_definitions(INDEX) | PENDING
    found = [hit for filename, source in SOURCES
             for hit in signature_breaches(source, filename, exempt)]
    assert not found, "\n".join(found)


def test_no_call_passes_too_many_positional_arguments():
    found = [hit for filename, _ in SOURCES for hit in call_breaches(filename, INDEX,
                                                                        PENDING_CALLS)]
    assert not found, "\n".join(found)


def test_the_compiled_kernels_are_found():
    """The wrapped PIM formula and tyre laws and the compliant scene's formula are
    recognised (a renamed wrapper would make the kernels' long signatures breaches,
    loudly)."""
    assert {("pim/model/formula.py", "contact"), ("pim/model/formula.py", "post_impact"),
            ("pim/model/tyres.py", "wheel_force"),
            ("pim/model/tyres.py", "field_wheel_force")} <= INDEX.kernels
    assert INDEX.compiled_modules == {"sim/compliant_formula.py", "pim/model/runout_formula.py",
                                      "pim/model/formula.py", "pim/model/event_formula.py"}
    # the formula's point_contact is compiled; sim.compliant_setup's of the same name is not
    assert ("sim/compliant_formula.py", "point_contact") in INDEX.exempt
    assert ("sim/compliant_setup.py", "point_contact") not in INDEX.exempt


def test_every_pending_entry_still_breaches():
    """A function fixed by its owner leaves PENDING (and its calls PENDING_CALLS)."""
    sources = dict(SOURCES)
    for filename, function in PENDING:
        hits = signature_breaches(sources[filename], filename, _exempt_definitions(INDEX))
        assert any(f" {function} takes" in h or f".{function} takes" in h for h in hits), \
            (filename, function)
    for filename, callee in PENDING_CALLS:
        assert any(f" calls {callee} with" in h for h in call_breaches(filename, INDEX)), \
            (filename, callee)


PLANTED = '''
import click
import numpy as np
from numba import njit
from . import kernel_source
from .kernel_source import wrapped, plain
from . import formula as f


def nine(a, b, c, d, e, f, g, h, i):
    return a


def eight_and_five(a, b, c, d, e, f, g, h, *, i, j, k, l, m):
    return a


def fine(a, b, c, d, e, f, g, h, *args, i=0, j=0, k=0, l=0, **kwargs):
    return a


class Box:
    def method(self, a, b, c, d, e, f, g, h, i):
        return a

    def ok(self, a, b, c, d, e, f, g, h):
        return a


@njit(cache=True)
def kernel(a, b, c, d, e, f, g, h, i, j, k, l, m):
    return a


@click.command()
def command(a, b, c, d, e, f, g, h, i, j, k, l, m):
    return a


def spread(*args):
    return args


_compiled = njit(inline="always")(kernel_source.wrapped)
_whole = compile_module(f)


def calls(box):
    CALL
'''
KERNEL_SOURCE = '''
def wrapped(a, b, c, d, e, f, g, h, i):
    return a


def plain(a, b, c, d, e, f, g, h, i):
    return a
'''
FORMULA = '''
def point(a, b, c, d, e, f, g, h, i):
    return a
'''


def _planted(call: str = "pass") -> Index:
    return Index([("pim/model/planted.py", PLANTED.replace("CALL", call)),
                  ("pim/model/kernel_source.py", KERNEL_SOURCE),
                  ("pim/model/formula.py", FORMULA)])


def test_planted_breaches_are_caught_and_exemptions_hold():
    found = signature_breaches(PLANTED, "pim/planted.py")
    names = [hit.split()[1] for hit in found]
    assert names == ["nine", "eight_and_five", "Box.method"], found
    index = _planted()
    assert index.kernels == {("pim/model/kernel_source.py", "wrapped")}
    assert index.compiled_modules == {"pim/model/formula.py"}
    exempt = _exempt_definitions(index)
    assert signature_breaches(KERNEL_SOURCE, "pim/model/kernel_source.py", exempt) == [
        "pim/model/kernel_source.py:6 plain takes 9 positional, 9 in all"]
    assert signature_breaches(FORMULA, "pim/model/formula.py", exempt) == []
    assert signature_breaches(FORMULA, "pim/model/formula.py") != []


@pytest.mark.parametrize("call, expected", [
    ("Box(1, 2, 3, 4, 5, 6, 7, 8, 9)", 1),
    ("nine(1, 2, 3, 4, 5, 6, 7, 8, 9)", 1),
    ("box.method(1, 2, 3, 4, 5, 6, 7, 8, 9)", 1),                 # a method by its name
    ("plain(1, 2, 3, 4, 5, 6, 7, 8, 9)", 1),                      # imported, not compiled
    ("kernel_source.plain(1, 2, 3, 4, 5, 6, 7, 8, 9)", 1),
    ("Box(1, 2, 3, 4, 5, 6, 7, 8, i=9)", 0),
    ("Box(*values)", 0),
    ("np.broadcast_shapes(1, 2, 3, 4, 5, 6, 7, 8, 9)", 0),        # not a project name
    ("np.nine(1, 2, 3, 4, 5, 6, 7, 8, 9)", 0),                    # numpy's, not ours
    ("kernel(1, 2, 3, 4, 5, 6, 7, 8, 9)", 0),                      # compiled
    ("_compiled(1, 2, 3, 4, 5, 6, 7, 8, 9)", 0),                   # compiled by wrapping
    ("wrapped(1, 2, 3, 4, 5, 6, 7, 8, 9)", 0),
    ("f.point(1, 2, 3, 4, 5, 6, 7, 8, 9)", 0),                     # a module compiled whole
    ("spread(1, 2, 3, 4, 5, 6, 7, 8, 9)", 0)])                     # takes *args
def test_a_planted_call_is_caught(call, expected):
    found = call_breaches("pim/model/planted.py", _planted(call))
    assert len(found) == expected, found
