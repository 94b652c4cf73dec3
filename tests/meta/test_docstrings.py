"""Docstrings that cannot drift from the code (issue 21 point 3).

- The numpydoc ``Attributes`` section of every public dataclass in pim/, sim/ and
  comparisons/ names exactly its fields (and may add its properties): a field renamed,
  added or removed without its documentation fails here.
- Every public dataclass documents its fields in an ``Attributes`` section (or
  ``Parameters``, or ``#:`` comments above the fields), with no exception: the former debt
  list of dataclasses documented only in prose (NO_SECTION) is cleared and gone, so a new
  dataclass without a section fails.

Parsed from the source (ast), so nothing is imported; a planted drift in a temporary module
shows the check fails.
"""

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("pim", "sim", "comparisons", "pim_cli")
SECTION = re.compile(r"^(\s*)(Attributes|Parameters)\n\1-{3,}\n", re.M)
HEADER = re.compile(r"^\s*[A-Z][A-Za-z ]+\n\s*-{3,}\s*$", re.M)
ENTRY = re.compile(r"^([A-Za-z_][\w]*(?:\s*,\s*[A-Za-z_][\w]*)*)\s*(?::.*)?$")


def _is_dataclass(node: ast.ClassDef) -> bool:
    for d in node.decorator_list:
        target = d.func if isinstance(d, ast.Call) else d
        name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
        if name == "dataclass":
            return True
    return False


def _fields(node: ast.ClassDef, lines: list | None = None) -> list[str]:
    """Field names; with the source ``lines``, only those without a ``#:`` comment above
    them (Sphinx's attribute documentation, which counts as documented)."""
    out = []
    for item in node.body:
        if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
            if "ClassVar" in ast.unparse(item.annotation):
                continue
            if lines is not None and lines[item.lineno - 2].strip().startswith("#:"):
                continue
            out.append(item.target.id)
    return out


def _members(node: ast.ClassDef) -> set[str]:
    names = set()
    for item in node.body:
        if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef):
            names.add(item.name)
        elif isinstance(item, ast.Assign):
            names.update(t.id for t in item.targets if isinstance(t, ast.Name))
    return names


def documented(doc: str, section: str = "Attributes") -> list[str] | None:
    """Names in a numpydoc section of ``doc`` (None if it has none)."""
    match = next((m for m in SECTION.finditer(doc) if m.group(2) == section), None)
    if match is None:
        return None
    body = doc[match.end():]
    end = HEADER.search(body)
    body = body[:end.start()] if end else body
    indent = len(match.group(1))
    names = []
    for line in body.splitlines():
        if not line.strip() or len(line) - len(line.lstrip()) != indent:
            continue
        for part in line.strip().split("; "):    # "a : float [m]; b : float [s]"
            entry = ENTRY.match(part.strip())
            if entry:
                names += [n.strip() for n in entry.group(1).split(",")]
    return names


def dataclasses_in(path: Path):
    """(class name, fields needing an entry, other members, docstring) of each public
    dataclass in a file."""
    source = path.read_text()
    tree, lines = ast.parse(source), source.splitlines()
    classes = {n.name: n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)}
    for node in classes.values():
        if not _is_dataclass(node) or node.name.startswith("_"):
            continue
        fields, members = _fields(node, lines), _members(node) | set(_fields(node))
        for base in node.bases:     # dataclass bases in the same file
            if isinstance(base, ast.Name) and base.id in classes:
                fields = _fields(classes[base.id], lines) + fields
                members |= set(_fields(classes[base.id]))
                members |= _members(classes[base.id])
        yield node.name, fields, members, ast.get_docstring(node) or ""


def drift(fields: list, members: set, doc: str) -> list[str]:
    """What the Attributes section (or Parameters, when it has none) gets wrong."""
    names = documented(doc, "Attributes")
    if names is None:
        names = documented(doc, "Parameters")
    if names is None:
        return ["no Attributes section"]
    public = [f for f in fields if not f.startswith("_")]
    problems = [f"field {f!r} not documented" for f in public if f not in names]
    problems += [f"documents {n!r}, which is not a field or member" for n in names
                 if n not in fields and n not in members]
    return problems


CLASSES = [(f"{path.relative_to(ROOT)}:{name}", fields, members, doc)
           for package in PACKAGES for path in sorted((ROOT / package).rglob("*.py"))
           for name, fields, members, doc in dataclasses_in(path)]


@pytest.mark.parametrize("where, fields, members, doc", CLASSES, ids=[c[0] for c in CLASSES])
def test_documented_attributes_match_the_fields(where, fields, members, doc):
    assert drift(fields, members, doc) == [], where


def test_the_check_finds_dataclasses():
    assert len(CLASSES) > 20
    assert any(where.endswith("montecarlo.py:UncertaintyResult") for where, *_ in CLASSES)


PLANTED = '''
from dataclasses import dataclass


@dataclass(frozen=True)
class Summary:
    """A planted drift.

    Attributes
    ----------
    mean : float
        Mean [m/s].
    sd, spread : float
        Standard deviation [m/s].
    """

    mean: float
    sd: float
    count: int
'''


def test_a_planted_drift_fails(tmp_path):
    path = tmp_path / "planted.py"
    path.write_text(PLANTED)
    [(name, fields, members, doc)] = dataclasses_in(path)
    assert drift(fields, members, doc) == ["field 'count' not documented",
                                           "documents 'spread', which is not a field or member"]
    fixed = PLANTED.replace("sd, spread : float", "sd : float\n        SD.\n    count : int")
    path.write_text(fixed)
    [(name, fields, members, doc)] = dataclasses_in(path)
    assert drift(fields, members, doc) == []


def test_a_dataclass_documented_in_prose_fails(tmp_path):
    path = tmp_path / "prose.py"
    path.write_text(PLANTED.split("    Attributes")[0].rstrip() + '\n    """\n\n'
                    "    mean: float\n    sd: float\n    count: int\n")
    [(name, fields, members, doc)] = dataclasses_in(path)
    assert drift(fields, members, doc) == ["no Attributes section"]
