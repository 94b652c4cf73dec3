"""``python -m comparisons.docs NAME [--docs DIR]``: regenerate one part of docs/ from the
output of the command it documents (one entry line per part in :data:`PARTS`)."""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

#: Part -> module whose ``regenerate(docs_dir)`` writes it.
PARTS = {
    "validate-models": "comparisons.docs.validate_models",
    "inertia-estimate": "comparisons.docs.inertia_estimate",
    "event": "comparisons.docs.event",
    "readme-animation": "comparisons.docs.readme_animation",
}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comparisons.docs", description=__doc__)
    parser.add_argument("part", choices=sorted(PARTS))
    parser.add_argument("--docs", type=Path, default=Path(__file__).resolve().parents[2]
                        / "docs", help="the docs folder (default: the repository's docs/)")
    args = parser.parse_args(argv)
    for path in importlib.import_module(PARTS[args.part]).regenerate(args.docs):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
