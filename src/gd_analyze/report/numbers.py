"""Numbers as the reports print them: significant digits, percentages in one format per
column, counts with a thousands separator, and powers of ten in superscripts.

Private to the reports (:mod:`gd_analyze.report.common` re-exports these names).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import numpy.typing as npt

__all__ = ["fmt", "fmt_column", "fmt_columns", "given", "count", "share", "pct", "pct_column",
           "pct_columns", "power_of_ten", "decade_label"]

#: :func:`fmt_column` writes a column in fixed notation with at most this many decimals and
#: this many digits more than its significant ones in its widest entry (magnitudes over three
#: decades); in exponent form beyond.
_COLUMN_DECIMALS, _COLUMN_SPAN = 6, 3
#: :func:`pct_column` keeps at most this many significant digits of a column's largest
#: percentage.
_PCT_DIGITS = 4


def fmt(value: Any, digits: int = 4, sci_outside: tuple[float, float] | None = None) -> str:
    """A number as short text.

    Parameters
    ----------
    value : float or object
        A number; anything ``float()`` rejects is returned as ``str(value)``.
    digits : int, optional
        Significant digits.
    sci_outside : (float, float), optional
        If given, magnitudes outside ``[lo, hi)`` are written as ``d.dde+XX`` with
        ``digits - 1`` decimals; else ``'g'`` format decides.

    Returns
    -------
    str
        ``"n/a"`` for NaN and infinities, ``"0"`` for zero; a comma between thousands, as
        in every count (:func:`count`).

    Examples
    --------
    >>> fmt(1474.2), fmt(0.8302), fmt(12744.0, 6), fmt(2.5e-5)
    ('1,474', '0.8302', '12,744', '2.5e-05')
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(v):
        return "n/a"
    if v == 0:
        return "0"
    if sci_outside is not None and not sci_outside[0] <= abs(v) < sci_outside[1]:
        return f"{v:.{digits - 1}e}"
    if sci_outside is not None and abs(v) >= 10.0 ** digits:
        return f"{v:,.0f}"          # inside the range: never e-notation (34,780, not 3.478e+04)
    return f"{v:,.{digits}g}"


#: Significant digits that reproduce a parameter as a robot file gives it (its decimals), and
#: hide the rounding of a unit conversion (pi/2 rad printed as 90 deg).
_GIVEN_DIGITS = 12


def given(value: float) -> str:
    """A parameter the robot file gives (a DH length or angle) as given: every decimal it
    has, never rounded to a few digits (d3 = 0.15005 is never printed 0.15).

    Parameters
    ----------
    value : float
        The parameter [m or deg].

    Returns
    -------
    str
        The shortest text of :data:`_GIVEN_DIGITS` significant digits; "0" for zero (no
        "-0"); "n/a" if not finite.

    Examples
    --------
    >>> given(0.15005), given(0.4318), given(90.00000000000001), given(-0.0)
    ('0.15005', '0.4318', '90', '0')
    """
    v = float(value)
    if not math.isfinite(v):
        return "n/a"
    return "0" if v == 0 else f"{v:.{_GIVEN_DIGITS}g}"


def _close(texts, values, digits):
    """Each text, read back, within half a unit of its value's last significant digit."""
    for t, v in zip(texts, values):
        unit = 10.0 ** (math.floor(math.log10(abs(v))) - digits + 1)
        if abs(float(t.replace(",", "")) - v) > 0.5 * unit * (1 + 1e-9):
            return False
    return True


def fmt_column(values: npt.ArrayLike, digits: int = 4,
               off: npt.ArrayLike | None = None) -> list[str]:
    """A column of numbers in one notation (one format per column).

    Parameters
    ----------
    values : array_like, shape (M,)
        The numbers [any one unit].
    digits : int, optional
        Significant digits each entry keeps, at least.
    off : array_like of bool, shape (M,), optional
        Entries that are round-off by the caller's rule: shown as "≡ 0".

    Returns
    -------
    list of str
        ``"0"`` for zero, ``"n/a"`` if not finite. The others all in fixed notation with one
        number of decimals, the fewest that keep ``digits`` significant digits of every entry
        (of the smallest above all), with a comma between thousands (as :func:`fmt`), if that
        takes at most 6 decimals and ``digits + 3`` digits in the widest entry; else all in exponent form
        ``d.dde-05`` with one number of mantissa decimals, the fewest that keep ``digits``
        significant digits of every entry. So no column shows "0.00015" beside "4e-05".

    Examples
    --------
    >>> fmt_column([0.00015, 4e-05, 0.0])
    ['0.00015', '0.00004', '0']
    >>> fmt_column([0.0008908, 7.829e-05, 3.696])
    ['8.908e-04', '7.829e-05', '3.696e+00']
    >>> fmt_column([15.6, 8.1, 0.34])
    ['15.60', '8.10', '0.34']
    >>> fmt_column([1474.2, 0.8302])
    ['1.474e+03', '8.302e-01']
    """
    v = np.asarray(values, dtype=float).ravel()
    hide = (np.zeros(v.shape, bool) if off is None else np.asarray(off, bool).ravel())
    shown = v[~hide & np.isfinite(v) & (v != 0)]
    texts = None
    if shown.size:
        wide = math.floor(math.log10(float(np.abs(shown).max()))) + 1     # digits before "."
        specs = [f",.{d}f" for d in range(_COLUMN_DECIMALS + 1)
                 if wide + d <= digits + _COLUMN_SPAN] + [f".{d}e" for d in range(digits)]
        texts = next((t for spec in specs
                      if _close(t := [format(x, spec) for x in shown], shown, digits)), None)
    it = iter(texts or [])
    return _cells(v, hide, lambda x: next(it))


def _cells(values, hide, cell):
    """"≡ 0" where hidden, "n/a" where not finite, "0" for zero, ``cell(x)`` elsewhere."""
    return ["\u2261 0" if h else "n/a" if not math.isfinite(x) else "0" if x == 0 else cell(x)
            for x, h in zip(values, hide)]


def fmt_columns(columns: Sequence[npt.ArrayLike], digits: int = 4,
                off: Sequence[npt.ArrayLike | None] | None = None) -> list[list[str]]:
    """Several columns of one quantity (the peaks of an element's parts, in one unit) in one
    notation, as if they were one column (:func:`fmt_column`; one format per
    quantity, never "0.7840" beside "4.480e+00").

    Parameters
    ----------
    columns : sequence of array_like, each shape (M,)
        The numbers [one unit for all].
    digits : int, optional
        Significant digits each entry keeps, at least.
    off : sequence of (array_like of bool, shape (M,), or None), optional
        Per column, the entries that are round-off ("≡ 0").

    Returns
    -------
    list of list of str
        One list per column.

    Examples
    --------
    >>> fmt_columns([[2.835, 0.8302], [0.784, 0.0]])
    [['2.8350', '0.8302'], ['0.7840', '0']]
    >>> fmt_columns([[4.48, 3.976e-05], [0.784, 0.0]])
    [['4.480e+00', '3.976e-05'], ['7.840e-01', '0']]
    """
    return _as_one(lambda v, o: fmt_column(v, digits, o), columns, off)


def _as_one(column, columns, off):
    """``column(values, off)`` applied to several columns as one, split back."""
    arrays = [np.asarray(c, dtype=float).ravel() for c in columns]
    offs = [np.zeros(a.shape, bool) if o is None else np.asarray(o, bool).ravel()
            for a, o in zip(arrays, off or [None] * len(arrays))]
    texts = column(np.concatenate(arrays), np.concatenate(offs))
    ends = np.cumsum([a.size for a in arrays])
    return [texts[e - a.size:e] for a, e in zip(arrays, ends)]


def pct_columns(columns: Sequence[npt.ArrayLike],
                off: Sequence[npt.ArrayLike | None] | None = None) -> list[list[str]]:
    """Several columns of one relative quantity as percentages in one format, as if one column
    (:func:`pct_column`; never "0.363 %" beside "0.1827 %").

    Parameters
    ----------
    columns : sequence of array_like, each shape (M,)
        The fractions [1].
    off : sequence of (array_like of bool, shape (M,), or None), optional
        Per column, the entries that are round-off ("≡ 0").

    Returns
    -------
    list of list of str

    Examples
    --------
    >>> pct_columns([[0.00363, 0.00012], [0.001827, 0.000055]])
    [['0.3630 %', '0.0120 %'], ['0.1827 %', '0.0055 %']]
    """
    return _as_one(pct_column, columns, off)


def count(value: Any) -> str:
    """A count (operations, set points, elements) as the reports print every integer: with a
    comma between thousands.

    Parameters
    ----------
    value : int or float or object
        A whole number; one that is not whole, or not a number, is written by :func:`fmt`.

    Returns
    -------
    str
        ``"1,212"``, ``"22,911"``, ``"608"``; ``"n/a"`` if not finite.

    Examples
    --------
    >>> count(22911), count(1178.0), count(608), count(-12345)
    ('22,911', '1,178', '608', '-12,345')
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(v) or v != round(v):
        return fmt(value)
    return f"{int(round(v)):,}"


def share(value: float) -> str:
    """A fraction in [0, 1] (a translational share) that prints as 1 or 0 only when it is, in
    one format for every share of a table (one format per column).

    Parameters
    ----------
    value : float
        The fraction [1].

    Returns
    -------
    str
        ``"1"`` and ``"0"`` for exactly 1 and 0; ``"> 0.9999"`` within 1e-4 below 1,
        ``"< 0.0001"`` below 1e-4 above 0; else four decimals (so a column of shares never
        shows "0.27" beside "0.746"); ``"n/a"`` if not finite.

    Examples
    --------
    >>> share(0.99993), share(0.9996), share(0.27), share(1.0), share(3e-5)
    ('> 0.9999', '0.9996', '0.2700', '1', '< 0.0001')
    """
    v = float(value)
    if not math.isfinite(v):
        return "n/a"
    if v in (0.0, 1.0):
        return f"{v:g}"
    if 0 < 1 - v < 1e-4:
        return "> 0.9999"
    if 0 < v < 1e-4:
        return "< 0.0001"
    return f"{v:.4f}"


def pct(value: float) -> str:
    """A fraction as a percentage, e.g. ``0.0123`` as ``"1.23 %"``.

    Parameters
    ----------
    value : float
        The fraction [1].

    Returns
    -------
    str
        Two decimals, or ``1.2e-03 %`` style below 0.01 %; ``"n/a"`` if not finite.
    """
    v = 100.0 * float(value)
    if not math.isfinite(v):
        return "n/a"
    if v == 0 or abs(v) >= 0.01:
        return f"{v:.2f} %"
    return f"{v:.1e} %"


def pct_column(values: npt.ArrayLike, off: npt.ArrayLike | None = None) -> list[str]:
    """A column of fractions as percentages in one format (one format per column).

    Parameters
    ----------
    values : array_like, shape (M,)
        The fractions [1].
    off : array_like of bool, shape (M,), optional
        Entries that are round-off or exactly zero by the caller's rule
        (:func:`gd_analyze.ranking.ranking.is_round_off`): shown as "\u2261 0"; an exact
        0 is always shown so.

    Returns
    -------
    list of str
        Fixed notation with one number of decimals for the whole column: enough for two
        significant digits of its smallest shown value ("0.078 %", "0.013 %"), at least two,
        but no more than leave its largest value :data:`_PCT_DIGITS` significant digits
        ("31.88 %", not "31.88459 %"; "202.7 %"). An entry that rounds to 0 with those
        decimals is shown as a bound ("< 0.01 %"). Exponent form for all ("1.2e-05 %") only
        when the smallest value is below 1e-4 % and the largest is small enough to keep its
        four digits in it. "n/a" where not finite.

    Examples
    --------
    >>> pct_column([0.0123, 0.5])
    ['1.23 %', '50.00 %']
    >>> pct_column([2e-4, 6.4e-5, 0.0], off=[False, False, True])
    ['0.0200 %', '0.0064 %', '\u2261 0']
    >>> pct_column([0.3188459, 0.0123, 4.2e-6])
    ['31.88 %', '1.23 %', '< 0.01 %']
    >>> pct_column([2.0273, 0.0051])
    ['202.7 %', '0.5 %']
    """
    v = 100.0 * np.asarray(values, dtype=float).ravel()
    hide = (v == 0) | (np.zeros(v.shape, bool) if off is None
                       else np.asarray(off, bool).ravel())
    shown = np.abs(v[~hide & np.isfinite(v)])
    least = float(shown.min()) if shown.size else 1.0
    most = float(shown.max()) if shown.size else 1.0
    need = max(2, 1 - math.floor(math.log10(least)))            # two digits of the smallest
    cap = max(0, _PCT_DIGITS - 1 - math.floor(math.log10(most)))  # four of the largest
    if least < 1e-4 and need <= cap:
        return _cells(v, hide, lambda x: f"{x:.1e} %")
    d = min(need, cap)                                          # rounds to 0: a bound
    return _cells(v, hide, lambda x: f"< {10.0 ** -d:.{d}f} %" if abs(x) < 0.5 * 10.0 ** -d
                  else f"{x:.{d}f} %")


#: Superscript digits and minus, for a power of ten written without mathtext.
_SUPERSCRIPT = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076"
                                             "\u2077\u2078\u2079")


def power_of_ten(k: int) -> str:
    """10^k in Unicode superscripts, as the reports write a power of ten without mathtext.

    Parameters
    ----------
    k : int
        The exponent.

    Returns
    -------
    str

    Examples
    --------
    >>> power_of_ten(-5), power_of_ten(12)
    ('10⁻⁵', '10¹²')
    """
    return "10" + str(int(k)).translate(_SUPERSCRIPT)


def decade_label(x: float) -> str:
    """A decade of a logarithmic axis as a power of ten, in Unicode superscripts.

    Parameters
    ----------
    x : float
        The tick [data units].

    Returns
    -------
    str
        ``"10⁶"`` for 1e6 (never the code-like ``"1e6"``); ``""`` for a tick that is no power
        of ten.

    Examples
    --------
    >>> decade_label(1e6), decade_label(0.01), decade_label(300.0)
    ('10⁶', '10⁻²', '')
    """
    if not x > 0:
        return ""
    k = round(math.log10(x))
    if abs(x / 10.0 ** k - 1.0) > 1e-9:
        return ""
    return power_of_ten(k)
