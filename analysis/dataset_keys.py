"""Count where reports/ and cli/ still read a dataset by name rather than through a typed view.

A site is one expression of the code (read with :mod:`ast`, nothing imported) of one of these
forms, each counted once (a name constant inside a counted site is not counted again):

* ``x.attrs[k]``, ``x.attrs.get(k)``, ``k in x.attrs`` (also ``.variables``, ``.coords``,
  ``.data_vars``, ``.sizes``, ``.dims``): a global attribute or a variable by name;
* ``x[k].values`` (also ``.data``, ``.item()``, ``.sel``, ``.isel``, ``.sizes``, ``.dims``,
  ``.attrs``, ``.shape``): an xarray variable read by name, ``k`` any expression;
* ``ds[k]`` or ``k in ds`` for ``ds`` a name ending in ``ds`` or ``dataset`` (``x.dataset``):
  the same, without ``.values``;
* ``f(ds, "k")``: a string passed with a dataset to a helper that reads it by that name;
* any other use of a name constant of :mod:`gd_analyze.store.names` (``Var.X``, ``Attr.X``,
  e.g. passed to a helper that reads the dataset).

    python analysis/dataset_keys.py                 # per module, and the total
    python analysis/dataset_keys.py --list reports  # also each site under a folder
    python analysis/dataset_keys.py --src OTHER/src/gd_analyze   # another checkout
"""

import argparse
import ast
from collections import Counter
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "gd_analyze"
FOLDERS = ("reports", "cli")
_MAPPINGS = {"attrs", "variables", "coords", "data_vars", "sizes", "dims"}
_READS = {"values", "data", "item", "sel", "isel", "sizes", "dims", "attrs", "shape"}
_NAMES = {"Var", "Attr"}


def _is_dataset(node):
    """A name or attribute that, by the code's naming, holds a dataset."""
    name = (node.id if isinstance(node, ast.Name) else
            node.attr if isinstance(node, ast.Attribute) else "")
    return name == "ds" or name.endswith("_ds") or name.endswith("dataset")


def _is_mapping(node):
    return isinstance(node, ast.Attribute) and node.attr in _MAPPINGS


def _is_constant(node):
    return (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
            and node.value.id in _NAMES)


def _site(node, parent):
    """The kind of dataset access ``node`` is, or None."""
    if isinstance(node, ast.Subscript) and _is_mapping(node.value):
        return "mapping[k]"
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and node.func.attr == "get" and _is_mapping(node.func.value)):
        return "mapping.get(k)"
    if isinstance(node, ast.Compare) and any(isinstance(o, (ast.In, ast.NotIn))
                                             for o in node.ops):
        if any(_is_mapping(c) or _is_dataset(c) for c in node.comparators):
            return "k in mapping"
    if isinstance(node, ast.Subscript) and not isinstance(node.slice, ast.Slice):
        if isinstance(parent, ast.Attribute) and parent.attr in _READS:
            if not isinstance(node.slice, (ast.Constant, ast.Tuple)) or isinstance(
                    getattr(node.slice, "value", None), str):
                return "x[k].values"
        if _is_dataset(node.value):
            return "ds[k]"
    if isinstance(node, ast.Call) and any(_is_dataset(a) for a in node.args) and any(
            isinstance(a, ast.Constant) and isinstance(a.value, str) for a in node.args):
        return "f(ds, 'k')"
    if _is_constant(node):
        return "name constant"
    return None


def sites(path):
    """(line, kind, source text) of each dataset access of one module."""
    text = path.read_text(encoding="utf-8")
    tree = ast.parse(text)
    found = []

    def visit(node, parent):
        kind = _site(node, parent)
        if kind is not None:
            found.append((node.lineno, kind, ast.get_source_segment(text, node)))
            return                                  # the site's parts are not counted again
        for child in ast.iter_child_nodes(node):
            visit(child, node)

    visit(tree, None)
    return found


def counts(src=SRC, folders=FOLDERS):
    """{module path relative to src: Counter of kinds} over the folders."""
    table = {}
    for folder in folders:
        for path in sorted((src / folder).rglob("*.py")):
            found = sites(path)
            if found:
                table[str(path.relative_to(src))] = Counter(kind for _, kind, _ in found)
    return table


def _table(table):
    """The table as printed: sites per module, then the total by kind."""
    total = Counter()
    for c in table.values():
        total.update(c)
    rows = [f"{module:<36} {sum(c.values()):>6}" for module, c in table.items()]
    kinds = ", ".join(f"{k} {v}" for k, v in sorted(total.items()))
    return [f"{'module':<36} {'sites':>6}", *rows, f"{'all':<36} {sum(total.values()):>6}   {kinds}"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--list", metavar="DIR", help="list each site under DIR (relative to "
                        "src/gd_analyze)")
    parser.add_argument("--src", type=Path, default=SRC, help="the package's folder "
                        "(default: this checkout's src/gd_analyze)")
    args = parser.parse_args()
    print("\n".join(_table(counts(args.src))))
    if args.list:
        print("\n".join(f"{path.relative_to(args.src)}:{line}: {kind}: {source}"
                        for path in sorted((args.src / args.list).rglob("*.py"))
                        for line, kind, source in sites(path)))

if __name__ == "__main__":
    main()
