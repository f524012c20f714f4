"""Print the Layout block of docs/layout.md: one line per module of src/gd_analyze with its docstring's first line.

    python analysis/layout.py

Read with :mod:`ast` (nothing is imported). tests/test_docs.py checks
that docs/layout.md lists exactly these modules, so a module added, removed or renamed fails
the test until the page is regenerated.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "gd_analyze"


def modules():
    """(path relative to src/, first docstring line) of every module, in path order.

    Returns
    -------
    list of (str, str)
    """
    rows = []
    for path in sorted(PACKAGE.rglob("*.py")):
        doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
        first = doc.strip().splitlines()[0].strip() if doc.strip() else ""
        rows.append((path.relative_to(PACKAGE.parent).as_posix(), first))
    return rows


def lines():
    """The Layout block's lines, indented by four spaces (a Markdown code block).

    Returns
    -------
    list of str
    """
    rows = modules()
    width = max(len(p) for p, _ in rows)
    return [f"    {p:<{width}}  {d}".rstrip() for p, d in rows]


def main():
    """Print the block."""
    print("\n".join(lines()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
