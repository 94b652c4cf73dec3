"""No mutable module state (issue 27 point 7).

A module of pim/, sim/, comparisons/ or pim_cli/ may build its tables at import (a dict of
units, a tuple of names) but never changes a module-level object afterwards: no ``global``
statement, and no function that mutates a module-level list, dict, set (or
``collections`` container) bound at module level, by a mutating method (``append``,
``update``, ``clear`` ...), an item assignment or deletion, or an augmented assignment to
an item, or an assignment to an attribute of a module-level object (``_STATE.x = 1``,
``setattr(_STATE, "x", 1)``). What a run must remember lives in an object its caller holds,
and what is computed once per process in
``functools.cache`` (or ``functools.lru_cache``: the compiled scene keeps its last four
case set-ups so, keyed by the case's identity).

PENDING lists the breaches left to the helpers who own their files; each must still breach
(a fixed one must leave the list).

Read from the source (ast), so nothing is imported; planted breaches show the check fails.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("pim", "sim", "comparisons", "pim_cli")
MUTATORS = {"append", "extend", "insert", "remove", "pop", "popitem", "clear", "update",
            "add", "discard", "setdefault", "sort", "reverse", "appendleft", "extendleft",
            "popleft", "rotate", "difference_update", "intersection_update",
            "symmetric_difference_update", "__setitem__", "__delitem__"}
#: (file, module-level name) left to the helper who owns the file (cli2: the command line and
#: the process module pim/io/output.py).
PENDING: set[tuple[str, str]] = set()
CONTAINERS = {"list", "dict", "set", "defaultdict", "OrderedDict", "Counter", "deque",
              "bytearray"}


def _mutable(value) -> bool:
    """Whether a module-level value is a mutable container (a display, a comprehension or
    a constructor call)."""
    if isinstance(value, ast.List | ast.Dict | ast.Set | ast.ListComp | ast.DictComp
                  | ast.SetComp):
        return True
    if isinstance(value, ast.Call):
        func = value.func
        name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
        return name in CONTAINERS
    return False


def _module_containers(tree: ast.Module) -> set[str]:
    names = set()
    for node in tree.body:
        targets, value = [], None
        if isinstance(node, ast.Assign):
            targets, value = node.targets, node.value
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            targets, value = [node.target], node.value
        if value is not None and _mutable(value):
            names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


def _module_names(tree: ast.Module) -> set[str]:
    """Names bound by an assignment at module level (not imports, functions or classes)."""
    names = set()
    for node in tree.body:
        targets = (node.targets if isinstance(node, ast.Assign)
                   else [node.target] if isinstance(node, ast.AnnAssign | ast.AugAssign)
                   else [])
        for target in targets:
            names.update(n.id for n in ast.walk(target) if isinstance(n, ast.Name))
    return names


def _locals(function) -> set[str]:
    """Names a function binds itself (its parameters and assignments): they shadow the
    module's."""
    args = function.args
    names = {a.arg for a in args.posonlyargs + args.args + args.kwonlyargs}
    names |= {a.arg for a in (args.vararg, args.kwarg) if a is not None}
    for node in ast.walk(function):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
    return names


def state_breaches(source: str, filename: str) -> list[str]:
    """Every ``global`` statement, every mutation of a module-level container and every
    attribute assignment to a module-level object inside a function of ``source`` (module
    notes)."""
    tree = ast.parse(source)
    containers, objects = _module_containers(tree), _module_names(tree)
    found = []
    functions = [n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef
                                                         | ast.AsyncFunctionDef | ast.Lambda)]
    for function in functions:
        shadowed = _locals(function) if not isinstance(function, ast.Lambda) else set()
        for node in ast.walk(function):
            where = f"{filename}:{getattr(node, 'lineno', function.lineno)}"
            found += [f"{where}: {hit}" for hit in
                      _node_breaches(node, containers - shadowed, objects - shadowed)]
    return sorted(set(found))


def _node_breaches(node, containers: set[str], objects: set[str]) -> list[str]:
    """What ``node`` changes of the module's ``containers`` and ``objects`` (names)."""
    if isinstance(node, ast.Global):
        return [f"global {', '.join(node.names)}"]
    if isinstance(node, ast.Call):
        func = node.func
        if (isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name)
                and func.value.id in containers and func.attr in MUTATORS):
            return [f"{func.value.id}.{func.attr}(...) changes module state"]
        if (isinstance(func, ast.Name) and func.id in ("setattr", "delattr") and node.args
                and isinstance(node.args[0], ast.Name) and node.args[0].id in objects):
            return [f"{func.id}({node.args[0].id}, ...) changes module state"]
        return []
    if not isinstance(node, ast.Assign | ast.AugAssign | ast.AnnAssign | ast.Delete):
        return []
    targets = node.targets if isinstance(node, ast.Assign | ast.Delete) else [node.target]
    hits = []
    for target in targets:
        if not isinstance(target, ast.Subscript | ast.Attribute) or not isinstance(
                target.value, ast.Name):
            continue
        name = target.value.id
        if isinstance(target, ast.Subscript) and name in containers:
            hits.append(f"{name}[...] changes module state")
        elif isinstance(target, ast.Attribute) and name in objects:
            hits.append(f"{name}.{target.attr} = ... changes module state")
    return hits


def _sources():
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            yield path.relative_to(ROOT).as_posix(), path.read_text()


def _pending(hit: str) -> bool:
    filename = hit.split(":", 1)[0]
    return any(filename == f and f" {name}" in hit for f, name in PENDING)


def test_no_module_keeps_mutable_state():
    found = [hit for filename, source in _sources() for hit in state_breaches(source, filename)
             if not _pending(hit)]
    assert not found, "\n".join(found)


def test_every_pending_entry_still_breaches():
    """A breach fixed by its owner leaves PENDING."""
    sources = dict(_sources())
    for filename, name in PENDING:
        assert any(f" {name}" in hit for hit in state_breaches(sources[filename], filename)), \
            (filename, name)


@pytest.mark.parametrize("planted, expected", [
    ("_shown = []\ndef f():\n    if not _shown:\n        _shown.append(True)\n",
     "_shown.append"),
    ("_SIGNALS: list[int] = []\ndef note(s):\n    _SIGNALS.clear()\n", "_SIGNALS.clear"),
    ("_cache = {}\ndef f(k):\n    _cache[k] = 1\n", "_cache[...]"),
    ("_seen = set()\ndef f(k):\n    _seen.add(k)\n", "_seen.add"),
    ("from collections import defaultdict\n_c = defaultdict(int)\ndef f(k):\n"
     "    _c[k] += 1\n", "_c[...]"),
    ("_count = 0\ndef f():\n    global _count\n    _count += 1\n", "global _count"),
    ("class A:\n    def m(self):\n        _R.append(self)\n_R = []\n", "_R.append"),
    ("import types\n_STATE = types.SimpleNamespace(n=0)\ndef f():\n    _STATE.n += 1\n",
     "_STATE.n = "),
    ("_STATE = object()\ndef f(v):\n    setattr(_STATE, 'v', v)\n", "setattr(_STATE"),
    ("from collections import OrderedDict\n_CACHE: OrderedDict = OrderedDict()\n"
     "def f(k):\n    _CACHE.popitem(last=False)\n", "_CACHE.popitem")])
def test_a_planted_breach_is_caught(planted, expected):
    found = state_breaches(planted, "pim/planted.py")
    assert any(expected in hit for hit in found), found


@pytest.mark.parametrize("fine", [
    "UNITS = {'m': 1.0}\nUNITS['km'] = 1e3\n",               # built at import
    "NAMES = ('a', 'b')\ndef f():\n    return NAMES\n",
    "_cache = {}\ndef f(_cache):\n    _cache['x'] = 1\n",    # a parameter shadows it
    "ROWS = []\ndef f():\n    ROWS = []\n    ROWS.append(1)\n    return ROWS\n",
    "import functools\n@functools.cache\ndef once():\n    return 1\n",
    "import numpy as np\ndef f(a):\n    np.x = 1\n",               # not the module's name
    "_DEFAULT = object()\ndef f(_DEFAULT):\n    _DEFAULT.x = 1\n",   # a parameter
    "def f(box):\n    box.x = 1\n    box['k'] = 2\n"])
def test_module_tables_and_local_state_are_fine(fine):
    assert state_breaches(fine, "pim/planted.py") == []
