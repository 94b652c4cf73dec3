"""What a test run adds to the checkout (issue 33 point 10: no test writes outside its
temporary folder).

:func:`listing` walks the checkout itself, so it needs no git (a clean clone, an unpacked
source archive): every file and folder except the caches that Python and the test tools keep
(:data:`CACHES`). The commands' default output folder ``out/`` counts: git ignores it for
the user's runs, but a test that writes there writes into the checkout.
"""

from __future__ import annotations

import fnmatch
import os
from pathlib import Path

#: Names of the folders and files that tools write during a run, never counted:
#: bytecode and numba caches, pytest's, hypothesis's, coverage's, git's own.
CACHES = ("__pycache__", "*.pyc", ".pytest_cache", ".hypothesis", ".ruff_cache",
          ".mypy_cache", "*.egg-info", ".git", ".coverage", ".coverage.*")


def cached(name: str) -> bool:
    """Whether a file or folder called ``name`` is a tool's cache (:data:`CACHES`)."""
    return any(fnmatch.fnmatchcase(name, pattern) for pattern in CACHES)


def listing(root) -> frozenset[str]:
    """Every file and folder under ``root`` (paths relative to it, "/"-separated), caches
    left out; folders end in "/" so that an empty one a test leaves is seen too."""
    root = Path(root)
    found = set()
    for folder, subfolders, files in os.walk(root):
        subfolders[:] = [d for d in subfolders if not cached(d)]
        here = Path(folder).relative_to(root).as_posix()
        prefix = "" if here == "." else here + "/"
        found.update(prefix + d + "/" for d in subfolders)
        found.update(prefix + f for f in files if not cached(f))
    return frozenset(found)


def gained(before: frozenset[str], after: frozenset[str]) -> list[str]:
    """The paths in ``after`` that ``before`` lacks, sorted (a new folder's own entry only,
    not every file in it)."""
    new = after - before
    return sorted(p for p in new
                  if not any(p.startswith(q) and p != q for q in new if q.endswith("/")))
