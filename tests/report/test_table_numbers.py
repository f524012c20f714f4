"""One number format per table column (as for the percentages): Table 1.3 printed
Izz "0.00015" beside "4e-05", Table 4.1 "0.0008908" beside "7.829e-05". Checked on the report
context of the PUMA 560 and the Stanford arm (joint 3 prismatic): no column of any table mixes
exponent form with fixed notation, and each printed value reads back within its four
significant digits of the value stored in results.h5 (the oracle)."""

import numpy as np
import pytest
from table_checks import number, reads_back, tables

from gd_analyze.report.main_context import report_context
from gd_analyze.report.markup import plain


@pytest.fixture(scope="module", params=("puma560", "stanford"))
def context(request, shipped_dataset):
    name = request.param
    ds = shipped_dataset(name)
    return name, ds, report_context(ds)


def test_no_column_mixes_exponent_and_fixed(context):
    name, _, ctx = context
    found = list(tables(ctx))
    assert len(found) >= 5
    for where, table in found:
        for c, head in enumerate(table["header"]):
            cells = [plain(str(row[c])) for row in table["rows"] if c < len(row)]
            nums = [t for t in cells if number(t) is not None and number(t) != 0]
            sci = {("e" in t) for t in nums}
            assert len(sci) <= 1, (name, where, head, nums)


def test_printed_values_read_back_within_their_digits(context):
    """Table 1.3 (link inertial parameters) and Table 4.1 (peaks), against results.h5."""
    name, ds, ctx = context
    link = ctx["link"]
    inertia = ds["link_inertia"].values
    stored = np.column_stack([ds["link_mass"].values, ds["link_com"].values,
                              inertia[:, 0, 0], inertia[:, 1, 1], inertia[:, 2, 2]])
    for row, values in zip(link["rows"], stored):
        for text, value in zip(row[1:], values):
            reads_back(text, value)
    ranking = ctx["ranking"]
    peaks = [ds[v].values for v in ("peak_tran", "peak_rot", "peak_total")]
    checked = 0
    for k, row in enumerate(ranking["rows"]):
        for text, v in zip(row[3:6], peaks):
            if "\u2261" not in text:
                reads_back(text, v[k])
                checked += 1
    assert checked > 20


def test_share_columns_have_one_number_of_decimals(context):
    """Table 4.1 printed the PUMA's shares as "0.27" beside "0.746" and "0.9996": a column
    of shares writes every share that is not exactly 0 or 1 with the same decimals, and each
    reads back within half a unit of its last decimal of the stored share_tran."""
    name, ds, ctx = context
    found = 0
    for where, table in tables(ctx):
        for c, head in enumerate(table["header"]):
            if "share" not in plain(str(head)):
                continue
            cells = [plain(str(row[c])) for row in table["rows"] if c < len(row)]
            decimals = {len(t.split(".")[1]) for t in cells
                        if number(t) is not None and "." in t}
            assert len(decimals) <= 1, (name, where, head, cells)
            found += 1
    assert found >= 1
    share = ds["share_tran"].values
    table = next(t for _, t in tables(ctx) if any("share" in plain(str(h))
                                                     for h in t["header"]))
    col = next(c for c, h in enumerate(table["header"]) if "share" in plain(str(h)))
    for k, row in enumerate(table["rows"]):
        shown = number(plain(str(row[col])))
        if shown is not None and shown not in (0.0, 1.0):
            assert abs(shown - share[k]) <= 0.5e-4 * (1 + 1e-9), (row, share[k])
