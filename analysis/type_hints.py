"""Count the public functions of src/gd_analyze with and without type hints, per folder.

Public: a name not starting with ``_``, defined at module level or as a method of a public
class (module level) in a module whose own name does not start with ``_``. Annotated: every
parameter but ``self``/``cls`` and the return carry an annotation (``__init__`` may omit the
return). Read with :mod:`ast`; nothing is imported.

    python analysis/type_hints.py            # the table
    python analysis/type_hints.py --list DIR # also the unannotated functions under DIR
"""

import argparse
import ast
from collections import Counter
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "gd_analyze"


def _annotated(node):
    args = node.args
    params = [*args.posonlyargs, *args.args, *args.kwonlyargs]
    if params and params[0].arg in ("self", "cls"):
        params = params[1:]
    params += [a for a in (args.vararg, args.kwarg) if a is not None]
    return all(p.annotation is not None for p in params) and (
        node.returns is not None or node.name == "__init__")


def public_functions(path):
    """(name, line, annotated) of the public functions and methods of one module."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    functions = (ast.FunctionDef, ast.AsyncFunctionDef)
    for node in tree.body:
        if isinstance(node, functions) and not node.name.startswith("_"):
            found.append((node.name, node.lineno, _annotated(node)))
        elif isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
            for item in node.body:
                if isinstance(item, functions) and (not item.name.startswith("_")
                                                    or item.name == "__init__"):
                    found.append((f"{node.name}.{item.name}", item.lineno, _annotated(item)))
    return found


def counts(src=SRC):
    """Per folder (relative to src/gd_analyze), Counter of 'annotated' and 'missing'."""
    table = {}
    for path in sorted(src.rglob("*.py")):
        if path.name.startswith("_") and path.name != "__init__.py":
            continue
        folder = str(path.parent.relative_to(src)) if path.parent != src else "."
        counter = table.setdefault(folder, Counter())
        for _, _, ok in public_functions(path):
            counter["annotated" if ok else "missing"] += 1
    return table


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--list", metavar="DIR", help="list the unannotated functions under "
                        "DIR (relative to src/gd_analyze)")
    args = parser.parse_args()
    table = counts()
    print(f"{'folder':<22} {'annotated':>9} {'missing':>8} {'public':>7}")
    total = Counter()
    for folder, c in table.items():
        total.update(c)
        print(f"{folder:<22} {c['annotated']:>9} {c['missing']:>8} "
              f"{c['annotated'] + c['missing']:>7}")
    print(f"{'all':<22} {total['annotated']:>9} {total['missing']:>8} "
          f"{total['annotated'] + total['missing']:>7}")
    if args.list:
        for path in sorted((SRC / args.list).rglob("*.py")):
            for name, line, ok in public_functions(path):
                if not ok:
                    print(f"{path.relative_to(SRC)}:{line}: {name}")


if __name__ == "__main__":
    main()
