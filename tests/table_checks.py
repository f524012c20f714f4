"""Reading the reports' tables back: every table of a report context, and a printed number
against the stored value it came from (one format per column). Used by
tests/reports/test_table_numbers.py and tests/reports/test_sweep_control_tables.py."""

import math
import re

from gd_analyze.reports.markup import plain

NUMBER = re.compile(r"^[\u2212-]?[\d,]*\.?\d+(e[+-]\d+)?$")


def tables(obj, where=""):
    """Every table (a dict with header and rows) anywhere in the context."""
    if isinstance(obj, dict):
        if "header" in obj and "rows" in obj:
            yield where, obj
        for k, v in obj.items():
            yield from tables(v, f"{where}.{k}")
    elif isinstance(obj, (list, tuple)):
        for k, v in enumerate(obj):
            yield from tables(v, f"{where}[{k}]")


def number(cell):
    """The number a table cell prints, or None if it is not a number alone."""
    text = plain(str(cell)).replace("\u2212", "-").replace(",", "")
    return float(text) if NUMBER.match(text.strip()) else None


def reads_back(text, value, digits=4):
    """Assert that a printed number is within half a unit of its last significant digit
    (``digits`` of them) of the stored value."""
    shown = number(text)
    assert shown is not None, text
    if value == 0:
        assert shown == 0
        return
    unit = 10.0 ** (math.floor(math.log10(abs(value))) - digits + 1)
    assert abs(shown - value) <= 0.5 * unit * (1 + 1e-9), (text, value)
