"""The reports' fixed wording and the code that says it agree, checked without a report.

The package's code (every ``.py`` file, read with ``ast``) says a passage by
``gd_analyze.report.common.say(name, ...)``; the passages are the macros of
``report/templates/wording.j2`` (read with Jinja2's parser). Every call names its macro by a
string literal, so the names said are known without running anything; each of them is a macro
of the file; and each macro is said by the code or called by a macro that is. A misspelt name
fails here, not only on the run whose report reaches the sentence, and no wording is left that
nothing says.
"""

import ast
import pathlib
from importlib import resources

import jinja2
from jinja2 import nodes

import gd_analyze

SRC = pathlib.Path(gd_analyze.__file__).resolve().parent
WORDING = resources.files("gd_analyze.report").joinpath("templates/wording.j2") \
    .read_text(encoding="utf-8")


def _is_say(node):
    """Whether an expression is the function ``say`` (by its name or as ``module.say``)."""
    return (isinstance(node, ast.Name) and node.id == "say") or \
        (isinstance(node, ast.Attribute) and node.attr == "say")


def _said():
    """The passages the package says.

    Returns
    -------
    said : dict of str to list of str
        Each macro name given to ``say`` as a string literal, with where ("report/x.py:12").
    unread : list of str
        Where ``say`` is used so that the name cannot be read: a first argument that is not
        a string literal, ``say`` as a value (passed on, assigned) or imported under another
        name.
    """
    said, unread = {}, []
    for path in sorted(SRC.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        where = path.relative_to(SRC).as_posix()
        called = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and _is_say(node.func):
                called.add(id(node.func))
                first = node.args[0] if node.args else None
                if isinstance(first, ast.Constant) and isinstance(first.value, str):
                    said.setdefault(first.value, []).append(f"{where}:{node.lineno}")
                else:
                    unread.append(f"{where}:{node.lineno}: {ast.unparse(node)[:60]}")
        for node in ast.walk(tree):
            if _is_say(node) and id(node) not in called:
                unread.append(f"{where}:{node.lineno}: say as a value")
            elif isinstance(node, ast.alias) and node.name == "say" and node.asname:
                unread.append(f"{where}:{node.lineno}: say imported as {node.asname}")
    return said, unread


def _macros():
    """The macros of wording.j2, each with the other macros it calls.

    Returns
    -------
    dict of str to set of str
        A name used in a macro counts as a call of the macro of that name unless the macro
        binds it itself (a parameter, a ``set``, a loop variable).
    """
    body = jinja2.Environment().parse(WORDING).body
    defined = [node for node in body if isinstance(node, nodes.Macro)]
    names = {macro.name for macro in defined}
    calls = {}
    for macro in defined:
        used = list(macro.find_all(nodes.Name))
        own = {n.name for n in used if n.ctx in ("param", "store")}
        calls[macro.name] = {n.name for n in used if n.ctx == "load" and n.name in names
                             and n.name not in own and n.name != macro.name}
    return calls


def test_every_passage_is_said_by_a_literal_name():
    said, unread = _said()
    assert said, "no say(...) found: the scan reads nothing"
    assert not unread, "say(...) whose macro name cannot be read as a literal:\n" + "\n".join(unread)


def test_every_name_said_is_a_macro_of_the_wording():
    said, _ = _said()
    macros = _macros()
    missing = {name: where for name, where in said.items() if name not in macros}
    assert not missing, f"said but not a macro of wording.j2: {missing}"


def test_every_macro_of_the_wording_is_said():
    """Said by the code, or called by a macro that is (so a helper of a dead macro is dead)."""
    said, _ = _said()
    macros = _macros()
    reached, todo = set(), [name for name in said if name in macros]
    while todo:
        name = todo.pop()
        if name not in reached:
            reached.add(name)
            todo.extend(macros[name])
    dead = sorted(set(macros) - reached)
    assert not dead, f"macros of wording.j2 that nothing says: {dead}"


def test_each_passage_is_compiled_as_the_whole_file_reads_it():
    """``say`` compiles each macro on its own, not the whole file: each macro cut out is the
    same macro (its parsed tree) as in the whole file read as Jinja reads it, and is handed
    every macro it calls (found by Jinja's parser, not by words), compiled on its own too."""
    import re

    from gd_analyze.report.common import _passage, _passages

    text = re.sub(r"(?<=%}|#})\n|[ \t]*\n(?={[%#])", "", WORDING)
    text = re.sub(r"[ \t]*\n", " ", text).replace("~", "\u00a0")
    whole = {node.name: node for node in jinja2.Environment().parse(text).body
             if isinstance(node, nodes.Macro)}
    passages = _passages()
    assert list(passages) == list(whole)
    calls = _macros()
    for name, source in passages.items():
        alone = [node for node in jinja2.Environment().parse(source).body
                 if isinstance(node, nodes.Macro)]
        assert alone == [whole[name]], name
        handed = _passage(name)._environment.globals
        assert all(handed[m] is _passage(m) for m in calls[name]), name
