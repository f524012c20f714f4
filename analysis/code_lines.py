"""Lines of code in ``src/gd_analyze``, per folder, split into the core and the shell.

A line of code is a physical line that holds part of a statement: blank lines, comments and
docstrings (a string literal that is a module's, class's or function's first statement) are
not counted; a statement over several lines counts each of its lines. The core is what issue
43 names: the folders ``model``, ``dynamics``, ``ranking``, ``regressor``, ``symbolic``,
``certify``, ``simplify`` and ``estimation`` (the estimation of identification); the shell is
everything else (``cli``, ``jobs``, ``store``, ``report``, ``trajectory`` and the package's
top-level modules). It prints a Markdown table with each folder's physical lines, code lines,
docstring lines and modules, and the totals of the core and the shell.

``--kinds`` prints instead the shell's code lines by the kind of statement that holds them
(imports, ``__all__``, the ``def``/``class`` lines with their signatures, the datasets'
variable declarations, ...), each line counted once, for its outermost statement of a kind
listed; ``--clones W`` lists the runs of W statements that stand in more than one place of the
shell once names and constants are blanked (code written twice, in shape).

Usage::

    python analysis/code_lines.py [--src DIR] [--kinds] [--clones W]
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


def code_lines(text, tree):
    """The numbers of the code lines of a module (as :func:`count` counts them)."""
    code = set()
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type not in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT,
                            tokenize.DEDENT, tokenize.ENDMARKER):
            code.update(range(tok.start[0], tok.end[0] + 1))
    return code - docstring_lines(tree)


#: Calls whose lines ``--kinds`` counts apart: (kind, called names).
CALL_KINDS = (("argparse add_argument", {"add_argument"}),
              ("dataset declarations (var, flag, stored, ...)",
               {"var", "flag", "text_coordinate", "stored", "derived", "units_attribute"}),
              ("wording calls (say)", {"say"}))


def kind_of(node):
    """The kind ``--kinds`` counts a statement or call under, or None."""
    if isinstance(node, (ast.Import, ast.ImportFrom)):
        return "imports"
    if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__"
                                            for t in node.targets):
        return "__all__"
    if (isinstance(node, ast.AnnAssign) and isinstance(node.value, ast.Constant)
            and isinstance(node.value.value, str)):
        return "name constants (X: Final = \"x\")"
    if isinstance(node, ast.Raise):
        return "raise (error messages)"
    if isinstance(node, ast.Call):
        name = getattr(node.func, "attr", getattr(node.func, "id", ""))
        return next((kind for kind, names in CALL_KINDS if name in names), None)
    return None


def shell_modules(root):
    """(relative path, text, tree) of every shell module."""
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        if not (len(rel.parts) > 1 and rel.parts[0] in CORE):
            text = path.read_text(encoding="utf-8")
            yield rel, text, ast.parse(text)


def kinds(root):
    """The shell's code lines by kind of statement, most first."""
    total = defaultdict(int)
    for _, text, tree in shell_modules(root):
        code, owner = code_lines(text, tree), {}
        for node in ast.walk(tree):             # outer statements first: a line's outermost
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                first = node.decorator_list[0].lineno if node.decorator_list else node.lineno
                lines, kind = range(first, node.body[0].lineno), "def/class lines"
            else:
                kind = kind_of(node)
                lines = range(getattr(node, "lineno", 0), getattr(node, "end_lineno", -1) + 1)
            for line in lines if kind else ():
                owner.setdefault(line, kind)
        for line in code:
            total[owner.get(line, "other (logic, literals, calls)")] += 1
    print("| kind | code lines |\n|---|---|")
    for kind, n in sorted(total.items(), key=lambda kv: -kv[1]):
        print(f"| {kind} | {n:,} |")
    print(f"| **shell** | **{sum(total.values()):,}** |")


class _Blank(ast.NodeTransformer):
    """Names, arguments and constants blanked: statements alike but for them compare equal."""

    def visit_Name(self, node):
        return ast.Name(id="_", ctx=node.ctx)

    def visit_Constant(self, node):
        return ast.Constant(value=0)

    def visit_arg(self, node):
        return ast.arg(arg="_")


#: Statements whose runs :func:`clones` passes over.
_DECLARATIONS = (ast.Assign, ast.AnnAssign, ast.Import, ast.ImportFrom)


def clones(root, width):
    """Runs of ``width`` statements of one block that stand in two places or more."""
    seen = defaultdict(list)
    for rel, _, tree in shell_modules(root):
        for node in ast.walk(tree):
            for name in ("body", "orelse", "finalbody"):
                if not isinstance(getattr(node, name, None), list):
                    continue
                block = getattr(node, name, None)
                body = [s for s in block if isinstance(s, ast.stmt)
                        and not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
                for k in range(len(body) - width + 1):
                    run = body[k:k + width]
                    if all(isinstance(s, _DECLARATIONS) for s in run):
                        continue                # constants and imports: alike in shape only
                    key = "\n".join(ast.dump(_Blank().visit(ast.parse(ast.unparse(s))))
                                    for s in run)
                    seen[key].append((run[-1].end_lineno - run[0].lineno + 1,
                                      f"{rel}:{run[0].lineno}"))
    rows = sorted(((max(n for n, _ in v), sorted({w for _, w in v}))
                   for v in seen.values() if len({w for _, w in v}) > 1), reverse=True)
    for lines, where in rows:
        print(f"{lines} lines: {', '.join(where)}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--src", default=str(Path(__file__).resolve().parents[1] / "src"))
    parser.add_argument("--kinds", action="store_true")
    parser.add_argument("--clones", type=int, metavar="W")
    args = parser.parse_args(argv)
    root = Path(args.src) / "gd_analyze"
    if args.kinds or args.clones:
        return kinds(root) if args.kinds else clones(root, args.clones)
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
