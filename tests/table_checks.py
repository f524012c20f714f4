"""Reading the reports' tables back: every table of a report context, and a printed number
against the stored value it came from (one format per column). Used by
tests/report/test_table_numbers.py and tests/report/test_sweep_control_tables.py."""

import csv
import io
import math
import re

from html_checks import html_tables

from gd_analyze.report.markup import plain

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


def csv_matches_html(folder, prefix, html):
    """Every ``<prefix><s>_<k>.csv`` in ``folder`` against the HTML report's tables, in order:
    one file per table, the same rows and cells, every number equal. Returns how many numbers
    were compared."""
    tables = html_tables(html)
    files = sorted(folder.glob(prefix + "*.csv"),
                   key=lambda p: tuple(int(k) for k in p.stem[len(prefix):].split("_")))
    assert files and len(files) == len(tables), (len(files), len(tables))
    numeric = re.compile(r"^-?\d+(\.\d*)?(e[+-]?\d+)?$")
    compared = 0
    for path, table in zip(files, tables, strict=True):
        rows = list(csv.reader(io.StringIO(path.read_text(encoding="utf-8"))))
        assert len(rows) == len(table), path.name
        for row, cells in zip(rows, table, strict=True):
            assert len(row) == len(cells), (path.name, row, cells)
            for c, h in zip(row, cells, strict=True):
                h = h.replace("\u2212", "-").replace("\u00a0", " ")
                if numeric.match(c):
                    assert float(c) == float(h), (path.name, c, h)
                    compared += 1
    return compared
