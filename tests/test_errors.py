"""One-line errors (gd_analyze.errors)."""

import os
import pathlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gd_analyze.errors import InputError, check_flags, expect, path_text, regular_file


def test_the_parts_and_their_order():
    assert str(InputError("x", "f.csv", row=3, column="q1")) == "f.csv: row 3, column q1: x"
    assert str(InputError("x", "m.json", column="robot.name")) == "m.json: key robot.name: x"
    assert str(InputError("x", column="--payload")) == "--payload: x"
    # a URDF's element or attribute names itself (no TOML "key"); a CSV header cell stays a column
    assert str(InputError("x", "a.urdf", column="<robot name>")) == "a.urdf: <robot name>: x"
    assert str(InputError("x", "f.csv", row=1, column="<q1>")) == "f.csv: row 1, column <q1>: x"


def test_a_key_or_file_name_with_a_line_break_stays_on_one_line():
    # found by the model-JSON fuzz test: a key ending in a newline broke the message
    err = InputError("bad\nvalue", "/tmp/a\nb.json", column="choices.\U0004d6bd\u00f4\n")
    assert str(err) == "/tmp/a\\nb.json: key choices.\\U0004d6bd\u00f4\\n: bad value"


@settings(max_examples=200, deadline=None)
@given(st.text(), st.text(), st.text())
def test_always_one_line(message, path, column):
    text = str(InputError(message, path, column=column))
    assert len(text.splitlines()) <= 1


def test_a_file_argument_is_a_str_or_a_path_like():
    assert path_text(pathlib.Path("a/b.csv"), "CSV file") == str(pathlib.Path("a/b.csv"))
    assert path_text("b.csv", "CSV file") == "b.csv"
    for bad in (None, 1.5, b"b.csv", ["b.csv"]):
        with pytest.raises(InputError) as e:
            path_text(bad, "CSV file")
        assert str(e.value) == f"path: a CSV file (str or os.PathLike), not a {type(bad).__name__}"


def test_an_argument_of_another_type_is_one_line_naming_it():
    assert expect(3, (int, str), "n", "a number or a name") == 3
    with pytest.raises(InputError) as e:
        expect(None, (int, str), "n", "a number or a name")
    assert str(e.value) == "n: a number or a name, not a NoneType"
    check_flags(a=True, b=False, c=np.True_, d=np.bool_(False))
    for bad in ("no", 1, 0.0, None, np.array([True])):
        with pytest.raises(InputError) as e:
            check_flags(a=True, flag=bad)
        assert str(e.value) == f"flag: True or False, not a {type(bad).__name__}"


def test_an_empty_file_name_is_written_as_two_quotes():
    """An empty file name began the line with ": no such file", as if the path were left
    out."""
    assert str(InputError("no such file", "")) == "'': no such file"
    assert str(InputError("x", pathlib.Path("a.csv"))) == "a.csv: x"


def test_a_file_to_read_is_a_regular_file_or_one_line_says_what_it_is(tmp_path):
    """Oracle: the file system (a file written, a folder, os.devnull, a missing name)."""
    (tmp_path / "a.csv").write_text("t\n")
    regular_file(tmp_path / "a.csv", "a CSV file")
    for path, said in [(tmp_path, "is a folder, not a CSV file"),
                       (os.devnull, "not a regular file (a device, FIFO or socket?): give a "
                                    "CSV file"),
                       (tmp_path / "missing.csv", "no such file"), ("", "no such file")]:
        with pytest.raises(InputError) as e:
            regular_file(path, "a CSV file")
        assert str(e.value) == (f"{path}: {said}" if path else f"'': {said}")
