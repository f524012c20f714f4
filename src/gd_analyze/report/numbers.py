"""Numbers as the reports print them: significant digits, percentages in one format per
column, counts with a thousands separator, powers of ten in superscripts, and the ticks of the
report figures.

Private to the reports (:mod:`gd_analyze.report.common` re-exports the text formats). The
ticks are matplotlib's locators and formatters, set once per figure: :func:`set_ticks` places
a few round ticks (:class:`matplotlib.ticker.MaxNLocator`) within given limits;
:func:`label_axes` writes the ticks of a figure's axes in one form with
:class:`matplotlib.ticker.ScalarFormatter`, each axis in units of a power of ten stated once,
in its axis label (no offset text: "[10⁻³ kg m²]"); :func:`decade_formatter` writes the
decades of a logarithmic axis as 10⁶; :func:`joint_ticks` labels a panel's joints across
"joint i", or "i" under an axis label "joint" where those would touch.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import numpy.typing as npt
    from matplotlib.axis import Axis
    from matplotlib.ticker import Formatter, ScalarFormatter

__all__ = ["fmt", "fmt_column", "fmt_columns", "given", "count", "share", "pct", "pct_column",
           "pct_columns", "power_of_ten", "decade_label", "nice_ticks", "set_ticks",
           "label_axes", "tick_label_width", "with_power", "scaled_formatter",
           "decade_formatter", "joint_ticks", "time_origin"]

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


# --------------------------------------------------------------------------------------------
# Ticks of the report figures
# --------------------------------------------------------------------------------------------
#: :func:`label_axes` writes ticks as they are while the largest |tick| is in this range,
#: in units of a power of ten outside (no 0.0015, no 20000 on a small panel).
_PLAIN = (1e-2, 1e4)


def nice_ticks(lo: float, hi: float, nbins: int = 3) -> npt.NDArray[np.float64]:
    """At most ``nbins + 1`` ticks at round values (1, 2, 2.5, 5 times a power of 10) in [lo, hi].

    Parameters
    ----------
    lo, hi : float
        The limits the ticks must lie within (any order).
    nbins : int, optional
        The most intervals between ticks.

    Returns
    -------
    ndarray, shape (K,)
        Tick positions within the limits, at least one (the midpoint of a degenerate range):
        the most that :class:`matplotlib.ticker.MaxNLocator` places within them.

    Examples
    --------
    >>> nice_ticks(0.0, 1.0, 4).tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    from matplotlib.ticker import MaxNLocator

    lo, hi = float(min(lo, hi)), float(max(lo, hi))
    span = hi - lo
    if not (np.isfinite(span) and span > 0):
        return np.array([lo])
    nbins, tol = max(1, int(nbins)), 1e-9 * span
    best = np.array([0.5 * (lo + hi)])
    # the locator covers [lo, hi]: more bins until the ticks within would be too many
    for k in range(nbins, 4 * nbins + 4):
        ticks = np.asarray(MaxNLocator(nbins=k, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi))
        ticks = ticks[(ticks >= lo - tol) & (ticks <= hi + tol)]
        if len(ticks) > nbins + 1:
            break
        if len(ticks) >= len(best):
            best = ticks
    best[np.abs(best) < 1e-12 * (float(np.ptp(best)) / max(len(best) - 1, 1) or span)] = 0.0
    return best


def scaled_formatter(k: int | None = 0) -> ScalarFormatter:
    """Tick labels in units of 10^k: 0.0025 reads ``2.5`` for k = -3.

    Parameters
    ----------
    k : int or None, optional
        The power of ten, stated elsewhere (the axis label, :func:`with_power`): no offset
        text; 0 writes the ticks as they are. None: matplotlib's, for ticks outside
        [0.01, 10⁴) in magnitude, stated at the axis' end ("1e−5", offset text).

    Returns
    -------
    matplotlib.ticker.ScalarFormatter
        No offset; fixed notation with the fewest common decimals that give back round
        ticks, a minus sign U+2212 (``axes.unicode_minus``).
    """
    from matplotlib.ticker import ScalarFormatter

    fmt = ScalarFormatter(useOffset=False, useMathText=False)      # no mathtext to parse
    if k is None:
        fmt.set_powerlimits((-3, 4))        # scaled outside [0.01, 10⁴), as _PLAIN
    elif k:
        fmt.set_powerlimits((k, k))         # equal limits: this power whatever the ticks
    else:
        fmt.set_scientific(False)
    return fmt


def set_ticks(axis: Axis, lo: float, hi: float, nbins: int = 3,
              labels: bool = True) -> npt.NDArray[np.float64]:
    """Fixed round ticks on one axis of a plot.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        ``ax.xaxis`` or ``ax.yaxis``.
    lo, hi : float
        The limits the ticks must lie within.
    nbins : int, optional
        The most intervals between ticks (:func:`nice_ticks`).
    labels : bool, optional
        Write the ticks (:func:`scaled_formatter` with matplotlib's power of ten); else no
        labels, until :func:`label_axes` writes them.

    Returns
    -------
    ndarray
        The tick positions.
    """
    from matplotlib.ticker import FixedLocator, NullFormatter

    ticks = nice_ticks(lo, hi, nbins)
    axis.set_major_locator(FixedLocator(ticks.tolist()))
    axis.set_major_formatter(scaled_formatter(None) if labels else NullFormatter())
    return ticks


def label_axes(axes: Iterable[Axis]) -> None:
    """Write the tick labels of several axes of one figure in one form.

    Parameters
    ----------
    axes : iterable of matplotlib.axis.Axis
        Axes whose ticks are placed (:func:`set_ticks`) and whose axis label, if any, is
        written; each gets a :func:`scaled_formatter` and, if scaled, its power in its label.

    Notes
    -----
    The rule, one form for the whole figure:

    - *plain*, if every axis' largest |tick| is in [0.01, 10⁴): every axis reads, e.g.,
      0.00, 0.25, 0.50 or 0, 20, 40.
    - *in units of a power of ten* otherwise: every axis whose largest |tick| is below 1 or at
      least 10⁴ is written in units of its own 10^k, 1 <= max|tick| / 10^k < 10 (its ticks
      read 0.0, 1.5, 3.0 and its axis label says the power); an axis whose largest |tick| is
      in [1, 10⁴) keeps its ticks as they are. So no figure shows "0.01" on one panel beside
      "5 [×10⁻³]" on the next.
    """
    placed = []
    for a in axes:
        ticks = np.abs(np.asarray(a.get_ticklocs(), float))
        ticks = ticks[np.isfinite(ticks)]
        placed.append((a, float(ticks.max()) if ticks.size else 0.0))
    odd = [big > 0 and not _PLAIN[0] <= big < _PLAIN[1] for _, big in placed]
    for (a, big), scale in zip(placed, odd):
        k = math.floor(math.log10(big)) if scale or (any(odd) and 0 < big < 1) else 0
        a.set_major_formatter(scaled_formatter(k))
        a.get_offset_text().set_visible(False)          # the label states the power
        if k:
            a.set_label_text(with_power(a.label.get_text(), k))


def with_power(label: str, k: int) -> str:
    """An axis label in units of 10^k: ``"[kg m²]"`` reads ``"[10⁻⁵ kg m²]"``.

    Parameters
    ----------
    label : str
        The axis label: with its units in brackets, or without units, or empty.
    k : int
        The power of ten the ticks are written in.

    Returns
    -------
    str
        The power written into the last brackets, or appended as ``"[×10ᵏ]"`` (``"×10ᵏ"``
        alone for an empty label).

    Examples
    --------
    >>> with_power("[kg m\u00b2]", -5), with_power("", 3), with_power("t [s]", 0)
    ('[10⁻⁵ kg m²]', '×10³', 't [s]')
    """
    if not k:
        return label
    power = power_of_ten(k)
    at = label.rfind("[")
    if at >= 0 and label.endswith("]"):
        return f"{label[:at + 1]}{power} {label[at + 1:]}"
    return f"{label} [\u00d7{power}]" if label else f"\u00d7{power}"


def time_origin(t: npt.ArrayLike, name: str = "t") -> tuple[float, str]:
    """The time a figure's time axis counts from, and that axis' label.

    A time axis whose first stamp lies farther from 0 than 10⁴ times its span (Unix time
    stamps, as a ROS log writes them: 1.7e9 s for a few seconds of motion) would need ticks
    of ten digits, which run into each other: it counts from its first stamp instead, and
    its label says from which.

    Parameters
    ----------
    t : array_like, shape (N,)
        The time stamps [s], in order (the first and the last are read).
    name : str, optional
        The axis label's name of time.

    Returns
    -------
    origin : float
        0, or the first stamp [s], or the whole second before it where that is as near:
        subtract it from the times drawn.
    label : str
        ``"t [s]"``, or ``"t − 1700000000 [s]"`` (the origin written exactly).

    Examples
    --------
    >>> time_origin([0.0, 4.2])
    (0.0, 't [s]')
    >>> time_origin([1.7e9 + 0.77, 1.7e9 + 4.2])
    (1700000000.0, 't − 1700000000 [s]')
    """
    t = np.asarray(t, dtype=float).reshape(-1)
    if t.size == 0 or not np.isfinite(t[[0, -1]]).all():
        return 0.0, f"{name} [s]"
    t0, span = float(t[0]), abs(float(t[-1]) - float(t[0]))
    if span == 0.0 or abs(t0) <= 1e4 * span:
        return 0.0, f"{name} [s]"
    if t0 - math.floor(t0) <= 1e4 * span:      # from a whole second where that is near
        t0 = float(math.floor(t0))
    text = np.format_float_positional(abs(t0), trim="-")
    sign = "\u2212" if t0 > 0 else "+"
    return t0, f"{name} {sign} {text} [s]"


def decade_formatter() -> Formatter:
    """Decades of a logarithmic axis as 10⁶ in the tick labels' own type
    (:func:`gd_analyze.report.numbers.decade_label`; mathtext's exponents print at 70 %)."""
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(lambda x, pos=None: decade_label(x))


def joint_ticks(axis: Axis, n: int, slot: float, least: float, short: bool = False) -> bool:
    """Label positions 1 to n of an axis as the arm's joints: "joint i" where the widest such
    label, at the size it prints at, fits its slot with a gap, else "i" with the axis label
    "joint" (a panel of 12 or 15 joints across a page: "joint 9joint 10oint 11").

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        The axis across which the joints sit, at 1, ..., n.
    n : int
    slot : float
        The room of one joint along the axis [in].
    least : float
        The least size [pt] a text of the figure is drawn at, so that it prints at the
        reports' minimum (tick labels smaller than it are raised to it when drawn).
    short : bool, optional
        "i" whatever the room (a column-wide figure).

    Returns
    -------
    bool
        The short labels were set (the callers set their other per-joint texts the same way).
    """
    from matplotlib.textpath import TextPath

    labels = [f"joint {i}" for i in range(1, n + 1)]
    axis.set_ticks(range(1, n + 1), labels)
    if not short and n:
        size = max(float(axis.get_major_ticks()[0].label1.get_fontsize()), least)    # [pt]
        widest = max(TextPath((0, 0), t, size=size).get_extents().width for t in labels) / 72
        short = widest > 0.85 * slot
    if short:
        axis.set_ticks(range(1, n + 1), [str(i) for i in range(1, n + 1)])
        axis.set_label_text("joint")
        axis.labelpad = 1.0
    return short


def tick_label_width(axis: Axis) -> float:
    """The width of the widest tick label an axis will print.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        An axis whose ticks and formatter are set (:func:`set_ticks`, :func:`label_axes`).

    Returns
    -------
    float
        [in], each label measured on its glyphs' outlines
        (:class:`matplotlib.textpath.TextPath`) at the axis' own tick-label size, so that a
        fixed layout can leave room for the labels without drawing the figure.
    """
    from matplotlib.textpath import TextPath

    lo, hi = sorted(axis.get_view_interval())
    locs = [x for x in axis.get_ticklocs() if lo <= x <= hi]
    if not locs:
        return 0.0
    size = float(axis.get_major_ticks()[0].label1.get_fontsize())         # [pt]
    texts = axis.get_major_formatter().format_ticks(locs)
    return max((TextPath((0, 0), t, size=size).get_extents().width / 72.0
                for t in texts if t), default=0.0)
