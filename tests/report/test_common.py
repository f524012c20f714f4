"""The helpers the three reports share (gd_analyze.report.common), in each report's variant."""

import numpy as np
import pytest
import xarray as xr

from gd_analyze.report import common as rp
from gd_analyze.report import figure_style
from gd_analyze.report.control import fmt_number as control_fmt
from gd_analyze.report.control import stored_text as control_text


def test_fmt_plain_and_scientific():
    assert rp.fmt(1234.5678) == "1,235"            # thousands separated, as every count
    assert rp.fmt(1.5e-7) == "1.5e-07"
    assert rp.fmt(0.0) == "0" and rp.fmt(np.nan) == "n/a" and rp.fmt("abc") == "abc"
    # the control report: 3 digits, e-notation outside [1e-3, 1e5)
    assert control_fmt(1234.5678) == "1,235"         # inside the range: no e-notation
    assert control_fmt(12.3456) == "12.3"
    assert control_fmt(1.5e-7) == "1.50e-07"
    assert control_fmt(123456.0) == "1.23e+05"
    assert control_fmt(12.3456, digits=4) == "12.35"


def test_pct():
    assert rp.pct(0.0123) == "1.23 %"
    assert rp.pct(1e-6) == "1.0e-04 %"
    assert rp.pct(0) == "0.00 %" and rp.pct(np.inf) == "n/a"


@pytest.mark.parametrize("values", [[7.84e-4, 1.29e-4, 2.65e-4], [4.33e-4, 6.38e-5, 1.55e-4],
                                    [2.39e-3, 2.36e-3, 1.7e-3, 4.45e-3, 3.01e-4],
                                    [1.31e-3, 5.79e-5, 1.48e-3, 1.58e-3]])
def test_pct_column_fixed_notation_two_significant_digits(values):
    """Table 5.1 printed RMS errors as "4.3e-02 %" beside "0.08 %", and 0.0129 % as "0.01 %"
    (one significant digit): a column is in fixed notation, one number of decimals, and every
    entry reads back its value to at least two significant digits."""
    cells = rp.pct_column(values)
    decimals = {len(c.split()[0].split(".")[1]) for c in cells}
    assert len(decimals) == 1 and not any("e" in c for c in cells), cells
    for cell, v in zip(cells, values):
        shown = float(cell.split()[0])
        assert abs(shown - 100 * v) <= 0.051 * abs(100 * v), (cell, v)   # two digits


def _significant(cell):
    """Significant digits of a fixed-notation cell ("31.88 %": 4, "0.0064 %": 2)."""
    return len(cell.split()[0].replace(".", "").lstrip("0"))


@pytest.mark.parametrize("values", [[0.3188459, 1.2e-6, 0.0123], [2.0273, 0.0051, 0.31],
                                    [0.3188459, 4.2e-9], [12.5, 0.5, 3e-3]])
def test_pct_column_keeps_four_digits_of_its_largest(values):
    """A long sweep printed "31.88459 %" beside "0.00012 %": the decimals of a column are
    capped so that its largest entry keeps at most four significant digits; still one number
    of decimals and no exponent form in the column; an entry too small for those decimals is
    a true bound ("< 0.01 %"), every other entry reads back within half a unit of its last
    decimal."""
    cells = rp.pct_column(values)
    numbers = [c for c in cells if not c.startswith("<")]
    figures = [c.lstrip("< ").split()[0] for c in cells]
    decimals = {len(f.split(".")[1]) if "." in f else 0 for f in figures}
    assert len(decimals) == 1 and not any("e" in c for c in cells), cells
    d = decimals.pop()
    big = int(np.argmax(values))
    assert _significant(cells[big]) <= 4, cells
    for cell, v in zip(cells, values):
        if cell.startswith("<"):
            assert 100 * v < float(cell.split()[1]) == 10.0 ** -d, (cell, v)
        else:
            assert abs(float(cell.split()[0]) - 100 * v) <= 0.5 * 10.0 ** -d * (1 + 1e-9)
    assert numbers


def test_attr_variants():
    ds = xr.Dataset(attrs={"arr": np.array([1.0, 2.5]), "flag": np.bool_(True), "empty": "",
                           "tiny": 1.5e-7, "name": b"puma"})
    assert rp.attr_text(ds.attrs.get("arr")) == "(1, 2.5)"
    assert control_text(ds.attrs["arr"]) == "1, 2.5"
    assert rp.attr_text(ds.attrs.get("flag")) == "True"
    assert control_text(ds.attrs["flag"]) == "1"
    assert rp.attr_text(ds.attrs.get("tiny")) == "1.5e-07"
    assert control_text(ds.attrs["tiny"]) == "1.50000e-07"
    assert rp.attr_text(ds.attrs["empty"]) == rp.attr_text(ds.attrs.get("missing")) == "\u2014"
    assert rp.attr_text(None, "x") == "x" and rp.attr_text(ds.attrs["name"]) == "puma"


def test_table_alignment():
    t = rp.table(["a", "b", "c"], [[1, 2.5, "x"]])
    assert t["rows"] == [["1", "2.5", "x"]]
    assert t["align"] == ["left"] * 3 and t["widths"] == [1, 1, 1] and t["colour_cols"] == []
    assert rp.table(["a", "b", "c"], [], align="right")["align"] == ["left", "right", "right"]
    assert rp.table(["a", "b"], [], align=["right", "left"])["align"] == ["right", "left"]


def test_check_formats():
    assert rp.check_formats(("HTML", "pdf", "html"), ("html", "pdf")) == ["html", "pdf"]
    assert rp.check_formats("pdf", ("html", "pdf")) == ["pdf"]
    for bad in ([], ["xml"]):
        with pytest.raises(ValueError, match="report formats must be among"):
            rp.check_formats(bad, ("html", "pdf"))


def test_grid_shape():
    assert figure_style.grid_shape(1, 2) == (1, 1)
    assert figure_style.grid_shape(6, 2) == (3, 2)
    assert figure_style.grid_shape(5, 3) == (2, 3)


def test_svg_ids_prefixed_and_still_resolved():
    """Every id of a figure's SVG gets the prefix, and every reference still names an id of
    the figure (the clip paths of the axes)."""
    import re

    from matplotlib.figure import Figure

    from gd_analyze.report.drawing import figure_svg, prefix_ids

    fig = Figure(figsize=(2, 1))
    fig.add_subplot().plot([0, 1], [0, 1])
    plain = figure_svg(fig, figure_style.BASE_RC)
    prefixed = prefix_ids(plain, "fig-a")
    assert plain.startswith("<svg") and prefixed.startswith("<svg")
    ids = re.findall(r'\bid="([^"]+)"', prefixed)
    assert ids and all(i.startswith("fig-a-") for i in ids)
    assert not re.findall(r'\bid="fig-a-', plain)
    refs = re.findall(r'url\(#([^)]+)\)', prefixed) + re.findall(r'href="#([^"]+)"', prefixed)
    assert refs and set(refs) <= set(ids)


def test_fmt_inside_the_range_is_never_e_notation():
    # a gain of 34,780 N m/rad printed as 3.478e+04 beside 6071 in one column,
    # although sci_outside promises e-notation only outside [1e-3, 1e5)
    from gd_analyze.report.common import fmt

    for v in (34780.2, 99999.0, 1234.5, 0.00123, 12.5):
        text = fmt(v, digits=4, sci_outside=(1e-3, 1e5))
        assert "e" not in text, (v, text)
        assert abs(float(text.replace(",", "")) - v) <= 0.5 + 1e-3 * abs(v)
    assert "e" in fmt(2e5, digits=4, sci_outside=(1e-3, 1e5))
    assert "e" in fmt(4e-4, digits=4, sci_outside=(1e-3, 1e5))


def test_or_default_keeps_every_stored_value_but_none():
    assert rp.or_default(None, "x") == "x"
    for stored in (0, 0.0, "", False, "chapter", np.float64(np.nan)):
        assert rp.or_default(stored, "x") is stored


def test_joints_text_agrees_with_the_count():
    assert rp.joints_text([3]) == "joint 3"
    assert rp.joints_text(["1", "2", "4"]) == "joints 1, 2, 4"
    assert rp.joints_text((5, 6)) == "joints 5, 6"
