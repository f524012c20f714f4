"""Input text made safe for comments of emitted C and Python (symbolic/safe_text.py).

Oracles: Python's own parser (the text inside a ``#`` comment and inside string literals of
either quote leaves the syntax tree unchanged), the C comment grammar (nothing in the text ends
a block comment or splices a line), hashlib for the digest, and hypothesis for the inputs."""

import ast
import hashlib
import string

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from gd_analyze.symbolic.safe_text import MAX_LENGTH, SAFE_CHARACTERS, comment_safe, header_lines

HOSTILE = ['a */ int x; /* b', 'x"""; import os; """', "x'''; import os; '''", "a\\\nb",
           "??/", "#include <stdio.h>", "line\rbreak", "u\u2028v\u2029w", "tab\there", "\x00",
           "`rm -rf`", "\ud800", "*" * 500]


def _python_is_harmless(s):
    """The text in a # comment and in a string of either quote: the tree has exactly the
    three assignments, and each string holds the text itself."""
    src = f"# {s}\na = '{s}'\nb = \"{s}\"\nc = \"\"\"{s}\"\"\"\n"
    tree = ast.parse(src)
    assert [type(node) for node in tree.body] == [ast.Assign] * 3
    assert [node.value.value for node in tree.body] == [s, s, s]


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=300))
@example("two-link")
def test_safe_text_cannot_leave_a_comment_or_a_string(text):
    s = comment_safe(text)
    assert set(s) <= SAFE_CHARACTERS and len(s) <= MAX_LENGTH
    for bad in ("*/", "/*", '"""', "'''", "\\", "??/", "#"):
        assert bad not in s
    assert len(s.splitlines()) <= 1
    _python_is_harmless(s)
    # in a C block comment: the only end of the comment is the one we write
    assert f"/* {s} */".count("*/") == 1
    assert comment_safe(s) == s                                  # idempotent


def test_the_safe_characters_exclude_every_comment_and_string_delimiter():
    for ch in "*\\?\"'`#\n\r\t\f\v\u2028\u2029":
        assert ch not in SAFE_CHARACTERS
    assert set(string.ascii_letters + string.digits + " -_.") <= SAFE_CHARACTERS


def test_plain_names_pass_unchanged_and_hostile_ones_are_replaced_character_by_character():
    for name in ("puma560", "two-link", "UR5 (e-series), v1.2", "a/b:c"):
        assert comment_safe(name) == name
    for text in HOSTILE[:-1]:
        s = comment_safe(text)
        assert len(s) == len(text)
        assert all(a == b if a in SAFE_CHARACTERS else b == "_" for a, b in zip(text, s))


def test_long_text_is_cut_and_the_digest_names_the_whole_raw_text():
    text = "x" * 1000
    s = comment_safe(text)
    assert len(s) == MAX_LENGTH and s.endswith("...")
    for raw in ("two-link", text, "a */ b", "\ud800 lone surrogate"):
        got = comment_safe(raw, digest=True)
        want = hashlib.sha256(raw.encode("utf-8", "backslashreplace")).hexdigest()
        assert got == f"{comment_safe(raw)} (sha256 {want})"
        _python_is_harmless(got)
    # texts differing only in replaced characters keep different digests
    assert comment_safe("a*b", digest=True) != comment_safe("a#b", digest=True)


def test_header_lines_make_keys_and_values_safe():
    header = {"robot": HOSTILE[0], 'key"""': HOSTILE[1], "tolerance": 0.01}
    lines = header_lines(header)
    assert len(lines) == 3
    assert lines[2] == "tolerance: 0.01"
    for line, (key, value) in zip(lines, header.items()):
        assert line == f"{comment_safe(key)}: {comment_safe(value)}"
        _python_is_harmless(line)


@pytest.mark.parametrize("length", [1, 120, 150, 199, 200, 201, 500])
def test_a_header_entry_keeps_the_whole_digest_of_a_long_name(length):
    """The digest names the raw text: the header's own pass never cuts it off (a 150-character
    name's digested comment is longer than MAX_LENGTH)."""
    import hashlib

    from gd_analyze.symbolic.safe_text import MAX_LENGTH, comment_safe, header_lines

    name = ("a*/" * length)[:length]
    entry = comment_safe(name, digest=True)
    (line,) = header_lines({"robot": entry})
    assert line == f"robot: {entry}"
    assert hashlib.sha256(name.encode()).hexdigest() in line
    assert len(entry.split(" (sha256 ")[0]) <= MAX_LENGTH
