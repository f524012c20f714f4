"""Lines of code in ``src/gd_analyze``, per folder, split into the core and the shell.

A line of code is a physical line that holds part of a statement: blank lines, comments and
docstrings (a string literal that is a module's, class's or function's first statement) are
not counted; a statement over several lines counts each of its lines. The core is what issue
43 names: the folders ``model``, ``dynamics``, ``ranking``, ``regressor``, ``symbolic``,
``certify``, ``simplify`` and ``estimation`` (the estimation of identification); the shell is
everything else (``cli``, ``jobs``, ``store``, ``report``, ``trajectory`` and the package's
top-level modules). It prints a Markdown table with each folder's physical lines, code lines,
docstring lines and modules, and the totals of the core and the shell.

Usage::

    python analysis/code_lines.py [--src DIR]
"""

from __future__ import annotations

import argparse
import ast
import io
import tokenize
from collections import defaultdict
from pathlib import Path

CORE = ("model", "dynamics", "ranking", "regressor", "symbolic", "certify", "simplify",
        "estimation")


def docstring_lines(tree):
    """The line numbers (1-based) of every docstring in a parsed module."""
    lines = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if (body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)
                    and isinstance(body[0].value.value, str)):
                lines.update(range(body[0].lineno, body[0].end_lineno + 1))
    return lines


def count(text):
    """(physical lines, code lines, docstring lines) of one module's source."""
    doc = docstring_lines(ast.parse(text))
    code = set()
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT,
                        tokenize.DEDENT, tokenize.ENDMARKER):
            continue
        code.update(range(tok.start[0], tok.end[0] + 1))
    return len(text.splitlines()), len(code - doc), len(doc)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--src", default=str(Path(__file__).resolve().parents[1] / "src"))
    args = parser.parse_args(argv)
    root = Path(args.src) / "gd_analyze"
    per = defaultdict(lambda: [0, 0, 0, 0])
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        folder = rel.parts[0] if len(rel.parts) > 1 else "(top level)"
        row = per[folder]
        for k, v in enumerate(count(path.read_text(encoding="utf-8"))):
            row[k] += v
        row[3] += 1
    print("| folder | part | physical lines | code lines | docstring lines | modules |")
    print("|---|---|---|---|---|---|")
    totals = {"core": [0, 0, 0, 0], "shell": [0, 0, 0, 0]}
    for folder in sorted(per, key=lambda f: (f not in CORE, f)):
        part = "core" if folder in CORE else "shell"
        row = per[folder]
        totals[part] = [a + b for a, b in zip(totals[part], row)]
        print(f"| {folder} | {part} | {row[0]:,} | {row[1]:,} | {row[2]:,} | {row[3]} |")
    for part, row in totals.items():
        print(f"| **{part}** | | {row[0]:,} | **{row[1]:,}** | {row[2]:,} | {row[3]} |")
    all_ = [a + b for a, b in zip(totals["core"], totals["shell"])]
    print(f"| **src** | | {all_[0]:,} | **{all_[1]:,}** | {all_[2]:,} | {all_[3]} |")


if __name__ == "__main__":
    main()
