"""The compiled CSV body parser against its oracles: Python's ``float()`` for every value (bit
for bit, the sign of zero included) and, for what it accepts, the plain-number grammar on
lines split by the csv module."""

import csv
import io
import random
import re
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import gd_analyze.io.csv_numbers as csv_numbers
from gd_analyze.io.csv_numbers import parse_body

PLAIN = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def _bits(a):
    return np.asarray(a, float).view(np.uint64)


def _parse_lines(cells, fields=None, newline="\n"):
    """parse_body on a header line and the given rows of cells."""
    rows = [",".join(r) for r in cells]
    raw = ("h" + newline + newline.join(rows) + newline).encode("ascii")
    return parse_body(raw, 1 + len(newline), fields or len(cells[0]))


def _oracle(cells):
    return np.array([[float(c) for c in r] for r in cells])


def _halfway(m, e):
    """The exact decimal string of (2 m + 1) 2^(e - 1): halfway between two doubles."""
    if e >= 1:
        return str((2 * m + 1) << (e - 1))
    k = 1 - e                             # (2 m + 1) / 2^k = (2 m + 1) 5^k / 10^k
    text = str((2 * m + 1) * 5 ** k).rjust(k + 1, "0")
    text = text[:-k] + "." + text[-k:]
    assert Fraction(text) == Fraction(2 * m + 1, 2 ** k)
    return text


TRICKY = [
    "0.1", "0.30000000000000004", "9007199254740993", "9007199254740992.5",
    "4503599627370496.5", "4503599627370497.5", "2.2250738585072011e-308",
    "2.2250738585072014e-308", "4.9406564584124654e-324", "2.4703282292062327e-324",
    "2.4703282292062328e-324", "1.7976931348623157e308", "1.7976931348623158e308",
    "1.7976931348623159e308", "1e400", "1e-400", "123456789012345678901234567890",
    "1.00000000000000011102230246251565404236316680908203125",
    "1.00000000000000011102230246251565404236316680908203124",
    "1.00000000000000011102230246251565404236316680908203126",
    "9007199254740993.0000000000000000001", "7.3177701707893310e+15", "-0", "-0.0e5",
    "+0.000", "0e-999999999999", "1e-342", "1e-343", "9999999999999999999e-343", "5e-324",
    "3e-324", "8.98846567431158e307", "1" + "0" * 300, "0." + "0" * 300 + "1",
    "18446744073709551615", "18446744073709551616", "1.8446744073709551616e19",
    "10000000000000000000000000000000000000000001e-40", ".5", "5.", "+.5e-0", "-5.E+3",
    "1e22", "1e23", "9007199254740993e-22", "1.448997445238699", "3.4028236692093846e38",
    "-1.0471975511965976", "4.1617956120834288e-06", "7.2551829465201911e-06",
]


def test_tricky_numbers_are_float_of_the_text():
    cells = [[c] for c in TRICKY]
    assert np.array_equal(_bits(_parse_lines(cells)), _bits(_oracle(cells)))


def test_numbers_exactly_halfway_between_two_doubles_round_to_even_as_float_does():
    rng = random.Random(3)
    cells = []
    for _ in range(400):
        text = _halfway(rng.randint(2 ** 52, 2 ** 53 - 1), rng.randint(-70, 60))
        cells += [[text], [text + "1"], [text + "0000000000000000000000001"]]
    assert np.array_equal(_bits(_parse_lines(cells)), _bits(_oracle(cells)))


def _random_number(rng):
    digits = "".join(rng.choice("0123456789") for _ in range(rng.randint(1, 25)))
    kind = rng.randrange(5)
    if kind == 0:
        text = repr(rng.uniform(-1e3, 1e3) * 10.0 ** rng.randint(-30, 30))
    elif kind == 1:
        text = f"{rng.uniform(-10, 10) * 10.0 ** rng.randint(-300, 300):.17g}"
    elif kind == 2:
        p = rng.randint(0, len(digits))
        text = digits[:p] + "." + digits[p:]
    elif kind == 3:
        text = digits + "e" + str(rng.randint(-350, 330))
    else:
        text = digits[0] + "." + digits[1:] + rng.choice("eE") + rng.choice(["+", "-", ""]) + \
            str(rng.randint(0, 320))
    if text[0] not in "+-" and rng.random() < 0.3:
        text = rng.choice("+-") + text
    return text


@pytest.mark.parametrize("seed", range(4))
def test_random_numbers_are_float_of_the_text(seed):
    rng = random.Random(seed)
    cells = [[_random_number(rng) for _ in range(7)] for _ in range(3000)]
    got = _parse_lines(cells)
    assert got.shape == (3000, 7) and got.flags.f_contiguous
    assert np.array_equal(_bits(got), _bits(_oracle(cells)))


def test_fields_left_to_float_are_taken_in_rounds(monkeypatch):
    """Fields the kernel cannot round for certain go back to float(), a few per call."""
    monkeypatch.setattr(csv_numbers, "HARD_CELLS", 4)
    cells = [["1e-320", "2.5", "1e400"], ["4e-320", "1e-310", "3"]] * 50
    got = _parse_lines(cells)
    assert np.array_equal(_bits(got), _bits(_oracle(cells)))


def test_crlf_spaces_tabs_and_a_last_line_without_newline():
    raw = b"t,q1\r\n 1.5 ,\t-2\r\n3,4e1  \n5, 6"
    got = parse_body(raw, raw.find(b"\n") + 1, 2)
    np.testing.assert_array_equal(got, [[1.5, -2.0], [3.0, 40.0], [5.0, 6.0]])


@pytest.mark.parametrize("body", [
    b"1,2\n\n3,4\n", b"1,2\r3,4\n", b"1,2\n3\n", b"1,2,3\n", b'1,"2"\n', b"1,2\n3,4,\n",
    b"1,,\n", b"1,2e\n", b"1,.\n", b"1,e5\n", b"1,2x\n", b"1,1_0\n", b"1,inf\n", b"1,nan\n",
    b"1,0x10\n", b"1,2 3\n", b"1,--2\n", b"1,+\n", b"1,\xef\xbc\x91\n", b"1,2\x00\n",
    b"1,2\n\n", b"", b"1;2\n", b"1,2\v\n", b"1," + b"1" * 1001 + b"\n",
    b"1," + b" " * 1000 + b"1\n"])
def test_anything_but_plain_numbers_is_left_to_the_cell_by_cell_parser(body):
    assert parse_body(b"t,q1\n" + body, 5, 2) is None


_CELL = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False).map(repr),
    st.from_regex(r"[ \t]?[+-]?[0-9]{0,22}(\.[0-9]{0,22})?([eE][+-]?[0-9]{0,4})?[ \t]?",
                  fullmatch=True),
    st.text(alphabet="0123456789+-.eE ,\t\r\"x_", max_size=8))


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(rows=st.lists(st.lists(_CELL, min_size=2, max_size=2), min_size=1, max_size=6),
       crlf=st.booleans(), last_newline=st.booleans())
def test_fuzz_accepts_only_plain_numbers_and_gives_float_of_each(rows, crlf, last_newline):
    """Accepted exactly when every csv row has the header's two fields, each a plain number
    after stripping spaces and tabs (the fields here are short); then every value is float()
    of the cell."""
    newline = "\r\n" if crlf else "\n"
    text = newline.join(",".join(r) for r in rows) + (newline if last_newline else "")
    raw = ("t,q1" + newline + text).encode("ascii")
    got = parse_body(raw, 4 + len(newline), 2)
    split = list(csv.reader(io.StringIO(text, newline="")))
    plain = (len(split) == len(rows) and not any("\r" in c or '"' in c for r in rows for c in r)
             and all(len(r) == 2 and all(PLAIN.fullmatch(c.strip(" \t")) for c in r)
                     for r in split))
    assert (got is not None) == plain, raw
    if plain:
        expected = np.array([[float(c.strip(" \t")) for c in r] for r in split])
        assert np.array_equal(_bits(got), _bits(expected))
