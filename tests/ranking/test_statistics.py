"""The layout of the ranking's statistics array: every series has the statistics the module
says, the named rows are the rows of their names, the sums come first, and the layout is read
without loading numba."""

import subprocess
import sys

import pytest

from gd_analyze.ranking import statistics as st


def test_the_three_series_have_every_statistic_and_rot_its_peak():
    expected = {(s, t) for s in ("tran", "rot_arm", "total") for t in st.STATISTICS}
    expected.add(("rot", "peak_abs"))
    assert set(st.ROWS) == expected and len(st.ROWS) == len(expected) == st.N_ROWS


def test_the_sums_come_first():
    kinds = [t for _, t in st.ROWS]
    assert st.SUMS == 6
    assert all(t != "peak_abs" for t in kinds[:st.SUMS])
    assert all(t == "peak_abs" for t in kinds[st.SUMS:])


@pytest.mark.parametrize("series", st.SERIES)
@pytest.mark.parametrize("statistic", st.STATISTICS)
def test_each_named_row_is_the_row_of_its_name(series, statistic):
    if (series, statistic) not in st.ROWS:
        with pytest.raises(ValueError, match="accumulates no"):
            st.row(series, statistic)
        return
    constant = getattr(st, f"{series}_{statistic}".upper())
    assert st.row(series, statistic) == constant
    assert st.ROWS[constant] == (series, statistic)


def test_the_layout_is_read_without_numba():
    code = ("import sys\nfrom gd_analyze.ranking import statistics, ranking\n"
            "print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                         text=True).stdout
    assert out.strip() == "False"
