"""Every Sphinx cross-reference in the package's docstrings names something that exists.

The docstrings of every module, class and function (methods included) of src/gd_analyze are
read with ``ast`` (no import needed to find them), with the ``#:`` comments that document
attributes, and every ``:func:``, ``:mod:``,
``:class:``, ``:meth:``, ``:data:``, ``:attr:`` and ``:exc:`` role is resolved the way Sphinx's
Python domain would look it up:

- a leading ``~`` (show the last part only) is dropped;
- ``.name`` (a leading dot) is looked up relative to the module the docstring is in: first
  as a submodule or attribute of that module's package, then within the module itself;
- a dotted name is imported as the longest importable module prefix, the rest by getattr
  (a dataclass field, a ``__slots__`` entry or an attribute the class's code sets on
  ``self`` counts);
- a bare name is looked up in the module's namespace, then in the enclosing class, then as a
  builtin (``ValueError``) or a top-level module (``numpy``).
"""

import ast
import builtins
import importlib
import inspect
import pathlib
import re

import pytest

import gd_analyze

SRC = pathlib.Path(gd_analyze.__file__).parent
ROLES = ("func", "mod", "class", "meth", "data", "attr", "exc")
_ROLE = re.compile(r":(" + "|".join(ROLES) + r"):`([^`]+)`")


def module_name(path):
    """The dotted module name of a source file of the package."""
    parts = ("gd_analyze",) + path.relative_to(SRC).with_suffix("").parts
    return ".".join(p for p in parts if p != "__init__")


def docstrings(tree):
    """(enclosing class name or None, docstring) of the module, its classes and functions."""
    doc = ast.get_docstring(tree, clean=False)
    if doc:
        yield None, doc
    stack = [(node, None) for node in tree.body]
    while stack:
        node, owner = stack.pop()
        if isinstance(node, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = ast.get_docstring(node, clean=False)
            here = node.name if isinstance(node, ast.ClassDef) else owner
            if doc:
                yield here, doc
            stack += [(child, here) for child in node.body]


def attribute_comments(source):
    """The ``#:`` comments (Sphinx's documentation of module and class attributes), each run
    of consecutive lines joined (a role may wrap onto the next line)."""
    runs, current = [], []
    for line in source.splitlines():
        stripped = line.strip()
        if stripped.startswith("#:"):
            current.append(stripped[2:].strip())
        elif current:
            runs.append(" ".join(current))
            current = []
    if current:
        runs.append(" ".join(current))
    return runs


def references(text):
    """The (role, target) pairs of one docstring; the target without ``~`` or a title."""
    for role, target in _ROLE.findall(text):
        target = target.strip()
        if "<" in target and target.endswith(">"):       # :func:`title <target>`
            target = target[target.index("<") + 1:-1]
        yield role, target.lstrip("~!").rstrip("()")


def _import(name):
    try:
        return importlib.import_module(name), True
    except ImportError:
        return None, False


def _has(obj, attr):
    if hasattr(obj, attr):
        return True
    # a dataclass field without a default, or a __slots__ entry, is an attribute of instances
    fields = getattr(obj, "__dataclass_fields__", None) or {}
    slots = getattr(obj, "__slots__", ()) or ()
    if attr in fields or attr in slots:
        return True
    # an attribute the class's own code sets on its instances (self.peaks = ...)
    if inspect.isclass(obj):
        try:
            source = inspect.getsource(obj)
        except (OSError, TypeError):
            return False
        return re.search(rf"\bself\.{re.escape(attr)}\s*=", source) is not None
    return False


def resolve_dotted(dotted):
    """Whether an absolute dotted name is an importable module or an attribute of one."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        module, ok = _import(".".join(parts[:cut]))
        if not ok:
            continue
        obj = module
        for k, attr in enumerate(parts[cut:]):
            if not _has(obj, attr):
                return False
            if k < len(parts[cut:]) - 1:
                obj = getattr(obj, attr)
        return True
    return False


def resolve(target, module, owner=None):
    """Whether a cross-reference ``target`` written in ``module`` (dotted name) resolves.

    Parameters
    ----------
    target : str
        As written in the role, without ``~``.
    module : str
        The module the docstring belongs to.
    owner : str, optional
        The enclosing class of the docstring.
    """
    if target.startswith("."):
        dots = len(target) - len(target.lstrip("."))
        rest = target[dots:]
        package = module.rsplit(".", dots)[0] if module.count(".") >= dots else module
        return any(resolve_dotted(f"{base}.{rest}") for base in (package, module))
    head = target.split(".")[0]
    mod = importlib.import_module(module)
    if hasattr(mod, head):
        obj = getattr(mod, head)
        for attr in target.split(".")[1:]:
            if not _has(obj, attr):
                return False
            obj = getattr(obj, attr, None)
        return True
    if owner is not None and hasattr(mod, owner) and "." not in target \
            and _has(getattr(mod, owner), target):
        return True
    if "." not in target and hasattr(builtins, target):
        return True
    return resolve_dotted(target)


def _sources():
    return sorted(SRC.rglob("*.py"))


def _all_references():
    for path in _sources():
        source = path.read_text(encoding="utf-8")
        name = module_name(path)
        docs = list(docstrings(ast.parse(source)))
        docs += [(None, comment) for comment in attribute_comments(source)]
        for owner, doc in docs:
            for role, target in references(doc):
                yield name, owner, role, target


def test_every_cross_reference_resolves():
    found = list(_all_references())
    assert len(found) > 100          # the scan sees the package's references
    bad = sorted({f"{name}: :{role}:`{target}`" for name, owner, role, target in found
                  if not resolve(target, name, owner)})
    assert not bad, "stale cross-references:\n" + "\n".join(bad)


@pytest.mark.parametrize("target, ok", [
    ("gd_analyze.symbolic.explicit.prune", True),            # absolute function
    ("gd_analyze.symbolic", True),                           # package
    ("gd_analyze.ranking.ranking.Ranking.choices", True),  # method
    ("gd_analyze.dynamics.dalembert.GDTerms.D_tran", True),  # dataclass field
    ("PartPeaks.peaks", True),                                    # set in __init__
    ("PartPeaks.no_such_peaks", False),
    ("gd_analyze.robot", False),                                  # a module that is gone
    ("gd_analyze.opcount.count_operations", False),
    ("gd_analyze.symbolic.explicit.no_such_function", False),
    ("gd_analyze.ranking.ranking.Ranking.no_such_method", False),
    (".torque_error.torque_error", True),                        # relative, sibling module
    (".recursive.PARTS", False),                                  # not beside budget
    (".no_such_module.PARTS", False),
    ("budget_drop", True),                                        # imported into the module
    ("select_terms", True),                                       # defined in the module
    ("load_robot", False),                                        # not in this namespace
    ("ValueError", True),                                         # builtin
    ("numpy.linalg.solve", True),
    ("numpy.linalg.no_such_solver", False),
])
def test_resolver_on_planted_references(target, ok):
    """The resolver as written in simplify/budget.py (relative names from there)."""
    assert resolve(target, "gd_analyze.simplify.budget") is ok


def test_relative_references_resolve_against_their_own_module():
    # ".recursive.PARTS" exists beside recursive_model (symbolic/), not beside budget
    assert resolve(".recursive.PARTS", "gd_analyze.symbolic.recursive_model")
    assert not resolve(".recursive.PARTS", "gd_analyze.model.robot")
    # a bare name of the enclosing class: Selection's field from inside Selection
    assert resolve("bound", "gd_analyze.simplify.budget", owner="Selection")
    assert not resolve("bound", "gd_analyze.simplify.budget")


def test_scan_finds_a_planted_stale_reference(tmp_path):
    """A docstring with a stale target in a class method is found and fails to resolve."""
    text = ('"""Module. See :mod:`gd_analyze.simplify.budget`."""\n'
            'class A:\n'
            '    def f(self):\n'
            '        """Uses :func:`~gd_analyze.robot.load_robot` and '
            ':meth:`title <gd_analyze.ranking.ranking.Ranking.choices>`."""\n')
    found = [ref for _, doc in docstrings(ast.parse(text)) for ref in references(doc)]
    assert [ref for c in attribute_comments("#: The limit (see\n#: :data:`~a.b.C`).\nX = 1\n")
            for ref in references(c)] == [("data", "a.b.C")]
    assert sorted(found) == [("func", "gd_analyze.robot.load_robot"),
                             ("meth", "gd_analyze.ranking.ranking.Ranking.choices"),
                             ("mod", "gd_analyze.simplify.budget")]
    verdicts = {t: resolve(t, "gd_analyze.simplify.budget") for _, t in found}
    assert verdicts == {"gd_analyze.robot.load_robot": False,
                        "gd_analyze.ranking.ranking.Ranking.choices": True,
                        "gd_analyze.simplify.budget": True}
