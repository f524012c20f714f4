"""Frozen values stay frozen and the code path is one (issue 19, items 4 and 5).

Every module of the package is read with ``ast``: no ``object.__setattr__`` (a frozen
dataclass mutated behind its back), no assignment into an instance's ``__dict__`` (the same by
another door), and none of the speed machinery that changed the code path from run to run: an
early ``os._exit``, a paused garbage collector, a second figure interpreter, writes into
matplotlib's private state.
"""

import ast
import pathlib

import pytest

import gd_analyze

SRC = pathlib.Path(gd_analyze.__file__).parent
MODULES = sorted(SRC.rglob("*.py"))


def _offences(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            if (isinstance(f, ast.Attribute) and f.attr == "__setattr__"
                    and isinstance(f.value, ast.Name) and f.value.id == "object"):
                yield node.lineno, "object.__setattr__"
            if isinstance(f, ast.Attribute) and f.attr in ("_exit", "disable") and \
                    isinstance(f.value, ast.Name) and f.value.id in ("os", "gc"):
                yield node.lineno, f"{f.value.id}.{f.attr}"
        elif isinstance(node, (ast.Assign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for t in targets:
                if (isinstance(t, ast.Subscript) and isinstance(t.value, ast.Attribute)
                        and t.value.attr == "__dict__"):
                    yield node.lineno, "assignment into __dict__"
                if isinstance(t, ast.Attribute) and t.attr == "_character_tracker":
                    yield node.lineno, "matplotlib's private _character_tracker"
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names = [a.name for a in node.names] + [getattr(node, "module", None) or ""]
            if any("main_worker" in n for n in names):
                yield node.lineno, "the figure worker"


#: The one allowed ``os._exit``: a signal after the command has returned and flushed its output
#: ends the process with 128 + its number (issue 32: no KeyboardInterrupt traceback after
#: "wrote"); it skips no work, so the code path stays one.
ALLOWED = {("io/signals.py", "os._exit")}


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(SRC)))
def test_no_mutation_of_frozen_values_and_no_second_code_path(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    where = str(path.relative_to(SRC))
    assert [o for o in _offences(tree) if (where, o[1]) not in ALLOWED] == []


def test_the_check_finds_what_it_looks_for():
    code = ("object.__setattr__(self, 'x', 1)\nout.__dict__['_p'] = p\nos._exit(0)\n"
            "gc.disable()\nf._character_tracker = t\nfrom .main_worker import draw\n")
    found = [what for _, what in sorted(_offences(ast.parse(code)))]
    assert found == ["object.__setattr__", "assignment into __dict__", "os._exit",
                     "gc.disable", "matplotlib's private _character_tracker", "the figure worker"]
