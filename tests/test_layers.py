"""The package's folders follow the data flow, and imports run down it only.

    model -> dynamics -> ranking -> symbolic -> certify -> simplify -> estimation -> trajectory
    -> store -> jobs -> report -> cli

A package imports only those before it (and the leaf modules errors, files, cache, _version
and config, importable from anywhere; ``__main__``, ``python -m gd_analyze``, runs cli). Every
import statement of every module is read with ``ast``, including imports inside functions, so a
lazy import cannot hide an upward arrow.
"""

import ast
import pathlib
import sys

import gd_analyze

SRC = pathlib.Path(gd_analyze.__file__).parent
#: The packages in the order the data flows.
LAYERS = ["model", "dynamics", "ranking", "symbolic", "certify", "simplify", "estimation",
          "trajectory", "store", "jobs", "report", "cli"]
#: The domain: the computations (pure, batched, no files), the rest being the shell.
DOMAIN = LAYERS[:7]
LEAVES = {"errors", "files", "_version", "config", "cache"}
# the shared report modules, and the main report's own parts (figures and sentences) and the
# PDF typesetter and tick labels of all three
SHARED_REPORTS = {"report.common", "report.typeset", "report.drawing",
                  "report.main_figures", "report.main_text",
                  "report.simplified_section", "report.main_context", "report.main_figures",
                  "report.numbers"}
# the domain modules a report may read: names and labels of the ranking's classes and elements
REPORT_CORE = {"ranking.ranking", "ranking.labels"}

# the one section list of the three reports and what it is built with
SHARED_REPORTS |= {"report.markup", "report.sections", "report.figure_style"}


def _module_name(path):
    parts = path.relative_to(SRC).with_suffix("").parts
    return ".".join(p for p in parts if p != "__init__")


def _imports(path):
    """Yield the gd_analyze-relative dotted names a module imports (absolute or relative)."""
    name = _module_name(path)
    package = name.split(".")[:-1] if path.name != "__init__.py" else name.split(".") if name else []
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "gd_analyze" or alias.name.startswith("gd_analyze."):
                    yield alias.name[len("gd_analyze."):] if "." in alias.name else ""
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
                target = ".".join(base + ([node.module] if node.module else []))
            elif node.module and (node.module == "gd_analyze" or node.module.startswith("gd_analyze.")):
                target = node.module[len("gd_analyze."):] if "." in node.module else ""
            else:
                continue
            if target == "" or target in LAYERS:
                # "from . import x" / "from ..model import x": the names are modules or re-exports
                for alias in node.names:
                    yield f"{target}.{alias.name}".lstrip(".")
            else:
                yield target


def _layer(dotted):
    head = dotted.split(".")[0]
    if head in LEAVES:
        return -1
    if head in LAYERS:
        return LAYERS.index(head)
    return None     # the package's own __init__ re-exports (gd_analyze.X)


def check(path):
    """The upward or sideways imports of one module, as 'module -> target' strings."""
    me = _module_name(path)
    bad = []
    mine = _layer(me)
    if me == "" or mine is None:
        return bad      # gd_analyze/__init__.py: the public facade re-exports the domain
    for target in _imports(path):
        theirs = _layer(target)
        if theirs is None:
            if target.split(".")[0] not in ("__version__",):
                bad.append(f"{me} -> gd_analyze.{target} (import the defining module)")
            continue
        if mine == -1 and theirs != -1:
            bad.append(f"{me} -> {target} (a leaf imports nothing of the package)")
        elif theirs > mine:
            bad.append(f"{me} -> {target} (upward)")
        elif me.startswith("report.") and (target.startswith(("dynamics", "jobs"))
                                           or (target.startswith("report.")
                                               and target not in SHARED_REPORTS)):
            bad.append(f"{me} -> {target} (a report reads the store and the shared report "
                       "modules)")
        elif me.startswith("report.") and target.split(".")[0] in DOMAIN \
                and target not in REPORT_CORE:
            bad.append(f"{me} -> {target} (a report computes no dynamics)")
    return bad


MODULES = sorted(p for p in SRC.rglob("*.py"))


def test_imports_run_down_the_layers():
    """Every module at once, every wrong import listed."""
    bad = [b for path in MODULES for b in check(path)]
    assert bad == [], "\n".join(bad)


def test_the_check_can_fail(tmp_path, monkeypatch):
    fake = tmp_path / "gd_analyze"
    (fake / "model").mkdir(parents=True)
    (fake / "report").mkdir()
    (fake / "model" / "bad.py").write_text("from ..jobs.analyze import x\n"
                                           "def f():\n    from ..report import main\n")
    (fake / "report" / "bad.py").write_text("from ..dynamics.pinocchio import y\n"
                                            "from .sweep import z\nfrom ..certify.region import w\n"
                                            "from .common import ok\nfrom ..store.datasets import ok2\n")
    monkeypatch.setattr(sys.modules[__name__], "SRC", fake)
    assert len(check(fake / "model" / "bad.py")) == 2
    assert len(check(fake / "report" / "bad.py")) == 3


#: The domain modules that touch files: the robot files' loaders and writers, and the operation
#: counts (kept in the derivation cache).
FILE_MODULES = {"model.robots", "model.urdf", "model.urdf_xml", "model.urdf_writer",
                "model.robot_file"}
#: Calls that read or write files; none belongs in the domain.
FILE_CALLS = {"open", "read_text", "read_bytes", "write_text", "write_bytes", "mkdir",
              "unlink", "atomic_path"}


def _file_io(path):
    """The file-system calls and imports of a module, as 'line: name' strings."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) \
                else None
            recv = f.value.id if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) \
                else None
            if name in FILE_CALLS and recv not in ("str", "text", "s", "name"):
                out.append(f"{node.lineno}: {name}")
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            mods = [a.name for a in node.names] if isinstance(node, ast.Import) \
                else [node.module or ""]
            out += [f"{node.lineno}: import {m}" for m in mods
                    if m.split(".")[0] in ("tomllib", "tomli", "shutil", "tempfile", "pathlib", "os")
                    or m.endswith("files")]
    return out


CORE_MODULES = sorted(p for pkg in DOMAIN for p in (SRC / pkg).rglob("*.py")
                      if p.name != "__init__.py")


def test_every_module_is_in_a_layer_and_the_domain_reads_no_files():
    """Every module at once, every misplaced module and file call listed."""
    bad = []
    for path in MODULES:
        parts = path.relative_to(SRC).parts
        if len(parts) == 1 and path.stem in LEAVES | {"__init__", "__main__"}:   # __main__: cli
            continue
        if not (len(parts) == 2 and parts[0] in LAYERS):
            bad.append(f"{_module_name(path)}: a module lives in <{'|'.join(LAYERS)}>/")
    for path in CORE_MODULES:
        if _module_name(path) not in FILE_MODULES:
            bad += [f"{_module_name(path)}: {call}" for call in _file_io(path)]
    assert bad == [], "\n".join(bad)


def test_the_file_io_check_can_fail(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("import tomllib\nfrom pathlib import Path\n"
                   "def f(p):\n    return open(p).read() + Path(p).read_text()\n")
    assert len(_file_io(bad)) == 4


def _runtime_edges(path):
    """The package modules a module imports when it runs: every import statement, inside
    functions too, but not those under ``if TYPE_CHECKING:`` (never executed), as
    gd_analyze-relative dotted names of modules."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    typing_only = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            typing_only |= {id(n) for s in node.body for n in ast.walk(s)}
    name = _module_name(path)
    package = name.split(".")[:-1] if path.name != "__init__.py" else name.split(".")
    modules = {_module_name(p) for p in MODULES}
    out = set()
    for node in ast.walk(tree):
        if id(node) in typing_only or not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
            target = ".".join(base + ([node.module] if node.module else []))
        elif (node.module or "").startswith("gd_analyze"):
            target = node.module[len("gd_analyze."):] if "." in node.module else ""
        else:
            continue
        for alias in node.names:
            sub = f"{target}.{alias.name}".strip(".")
            out.add(sub if sub in modules else target)
    return out & modules


def circles(graph):
    """The strongly connected components of more than one module (Tarjan), sorted."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def test_no_import_circle_even_through_function_local_imports():
    """A function-local import is no way around a circle: the graph holds every import that
    runs (module level and inside functions)."""
    graph = {_module_name(p): _runtime_edges(p) - {_module_name(p)} for p in MODULES}
    assert len(graph) > 100 and sum(map(len, graph.values())) > 300   # the scan sees them
    assert circles(graph) == []


def test_the_circle_check_can_fail():
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []


def upward(path):
    """The imports of a module that run against the flow, at any depth (functions and type
    hints included), as 'module -> target' strings."""
    me = _module_name(path)
    mine = _layer(me)
    if mine is None or mine < 0:
        return []
    return sorted(f"{me} -> {t}" for t in _runtime_edges(path) | set(_imports(path))
                  if _layer(t) is not None and _layer(t) > mine)


def test_the_packages_import_down_the_flow():
    bad = [b for path in MODULES for b in upward(path)]
    assert bad == [], "\n".join(bad)


#: Function-local imports of the package's own modules allowed: the compiled (numba) kernels,
#: imported by their first call (a command that computes nothing never imports numba), and
#: the CLI's sweep, which imports dask.
MAX_LOCAL_IMPORTS = 20


def local_imports(path):
    """The package imports a module makes inside its functions, as 'module:line' strings."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    me = _module_name(path)
    out = []
    for f in ast.walk(tree):
        if not isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for node in ast.walk(f):
            if isinstance(node, ast.ImportFrom) and (
                    node.level or (node.module or "").startswith("gd_analyze")):
                out.append(f"{me}:{node.lineno}")
            elif isinstance(node, ast.Import) and any(a.name.startswith("gd_analyze")
                                                      for a in node.names):
                out.append(f"{me}:{node.lineno}")
    return sorted(set(out))


def test_few_function_local_imports_of_the_package():
    found = [x for path in MODULES for x in local_imports(path)]
    assert 0 < len(found) <= MAX_LOCAL_IMPORTS, "\n".join(found)


def test_the_local_import_count_can_fail(tmp_path):
    bad = tmp_path / "gd_analyze" / "model" / "bad.py"
    bad.parent.mkdir(parents=True)
    bad.write_text("from .ok import x\n\ndef f():\n    from .a import b\n    if b:\n"
                   "        import gd_analyze.c\n    import numpy\n")
    global SRC
    saved, SRC = SRC, tmp_path / "gd_analyze"
    try:
        assert [x.split(":")[1] for x in local_imports(bad)] == ["4", "6"]
    finally:
        SRC = saved
