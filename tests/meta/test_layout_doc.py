"""The Layout section of docs/architecture.md names every module, under its own package, and
no module that does not exist (issue 21 point 4: the layout cannot drift from the tree)."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "architecture.md"
PACKAGES = ("pim/model", "pim/io", "pim/analysis", "pim/plotting", "sim", "comparisons/report",
            "comparisons/studies", "comparisons/regression", "comparisons/animation",
            "comparisons/docs",
            "pim_cli")


def layout_section(doc: str) -> str:
    start = doc.index("## Layout")
    end = doc.find("\n## ", start + 1)
    end = len(doc) if end < 0 else end
    return doc[start:end]


def bullets(section: str) -> dict:
    """Package folder -> the text of its bullet (``- `pim/model/`: ...``)."""
    out = {}
    for item in re.split(r"\n- ", section)[1:]:
        head = re.match(r"`([\w/]+?)/?`", item)
        if head:
            out[head.group(1)] = item
    return out


def layout_drift(doc: str, root: Path = ROOT) -> list[str]:
    found = bullets(layout_section(doc))
    problems = []
    for package in PACKAGES:
        text = found.get(package)
        if text is None:
            problems.append(f"no bullet for {package}/")
            continue
        named = set(re.findall(r"`(\w+)\.py`", text))
        modules = {p.stem for p in (root / package).glob("*.py")
                   if p.name not in ("__init__.py", "__main__.py")}
        problems += [f"{package}/{m}.py not in the layout" for m in sorted(modules - named)]
        problems += [f"{package}/{m}.py named but absent" for m in sorted(named - modules)]
    return problems


def test_the_layout_names_every_module():
    assert layout_drift(DOC.read_text()) == []


def test_a_missing_or_stale_module_fails():
    doc = DOC.read_text()
    assert layout_drift(doc.replace("`kernel.py`", "`kernal.py`")) == [
        "pim/model/kernel.py not in the layout", "pim/model/kernal.py named but absent"]
