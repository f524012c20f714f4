"""The running statistics the ranking accumulates per element, and their rows in one array.

Per element of D and h (:func:`gd_analyze.ranking.ranking.element_labels`) and set point k,
with arm_k the armature on the element (Ia_i on D_ii, 0 elsewhere), the series are

- ``"tran"``: tran_k;
- ``"rot_arm"``: rot_k + arm_k, the rotational side with the armature, as the shares count it;
- ``"total"``: (tran_k + rot_k) + arm_k;
- ``"rot"``: rot_k alone (the links' rotational part; its peak only).

and the statistics of a series x along the trajectory are ``"sum_abs"`` (sum_k |x_k|),
``"sum_sq"`` (sum_k x_k^2) and ``"peak_abs"`` (max_k |x_k|). The three series tran, rot_arm and
total have all three; a column that is a function of these (and of the number of set points)
needs no change to the compiled pass (:func:`gd_analyze.ranking.kernels.ranking_kernel`), only
to :class:`gd_analyze.ranking.ranking.Ranking` and its result.

This module imports nothing compiled: the ranking reads the layout without loading numba.
"""

from __future__ import annotations

from typing import Final

__all__ = ["SERIES", "STATISTICS", "ROWS", "N_ROWS", "SUMS", "row", "TRAN_SUM_ABS", "TRAN_SUM_SQ",
           "ROT_ARM_SUM_ABS", "ROT_ARM_SUM_SQ", "TOTAL_SUM_ABS", "TOTAL_SUM_SQ",
           "TRAN_PEAK_ABS", "ROT_ARM_PEAK_ABS", "TOTAL_PEAK_ABS", "ROT_PEAK_ABS"]

#: The series whose statistics are accumulated (module docstring).
SERIES: Final = ("tran", "rot_arm", "total", "rot")
#: The statistics of a series (module docstring).
STATISTICS: Final = ("sum_abs", "sum_sq", "peak_abs")
#: The rows of the statistics array, as (series, statistic): the sums first (a chunk's sums
#: are formed apart and then added to the running ones), then the peaks.
ROWS: Final = (("tran", "sum_abs"), ("tran", "sum_sq"),
               ("rot_arm", "sum_abs"), ("rot_arm", "sum_sq"),
               ("total", "sum_abs"), ("total", "sum_sq"),
               ("tran", "peak_abs"), ("rot_arm", "peak_abs"), ("total", "peak_abs"),
               ("rot", "peak_abs"))
#: The number of rows.
N_ROWS: Final = len(ROWS)
#: The number of sums: rows 0 .. SUMS - 1 (the peaks are rows SUMS .. N_ROWS - 1).
SUMS: Final = sum(1 for _, statistic in ROWS if statistic != "peak_abs")

# the rows by name, for the compiled pass (numba reads module-level ints as constants)
TRAN_SUM_ABS: Final = ROWS.index(("tran", "sum_abs"))
TRAN_SUM_SQ: Final = ROWS.index(("tran", "sum_sq"))
ROT_ARM_SUM_ABS: Final = ROWS.index(("rot_arm", "sum_abs"))
ROT_ARM_SUM_SQ: Final = ROWS.index(("rot_arm", "sum_sq"))
TOTAL_SUM_ABS: Final = ROWS.index(("total", "sum_abs"))
TOTAL_SUM_SQ: Final = ROWS.index(("total", "sum_sq"))
TRAN_PEAK_ABS: Final = ROWS.index(("tran", "peak_abs"))
ROT_ARM_PEAK_ABS: Final = ROWS.index(("rot_arm", "peak_abs"))
TOTAL_PEAK_ABS: Final = ROWS.index(("total", "peak_abs"))
ROT_PEAK_ABS: Final = ROWS.index(("rot", "peak_abs"))


def row(series: str, statistic: str) -> int:
    """The row of a statistic of a series in the statistics array.

    Parameters
    ----------
    series : str
        One of :data:`SERIES`.
    statistic : str
        One of :data:`STATISTICS`.

    Returns
    -------
    int
        Its row, in 0 .. len(ROWS) - 1.

    Raises
    ------
    ValueError
        If that statistic of that series is not accumulated.

    Examples
    --------
    >>> row("tran", "sum_abs"), row("total", "sum_sq"), row("rot", "peak_abs")
    (0, 5, 9)
    """
    try:
        return ROWS.index((series, statistic))
    except ValueError:
        raise ValueError(f"the ranking accumulates no {statistic!r} of {series!r}; it has "
                         + ", ".join(f"{s}.{t}" for s, t in ROWS)) from None
