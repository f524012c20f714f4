"""Numbers and dataset attributes as the reports print them: significant digits, e-notation
only outside a range, percentages with one format per column (re-exported by
:mod:`gd_analyze.reports.common`)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["fmt", "pct", "pct_column", "attr"]

def fmt(value, digits=4, sci_outside=None):
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
        ``"n/a"`` for NaN and infinities, ``"0"`` for zero.
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
        return f"{v:.0f}"           # inside the range: never e-notation (34780, not 3.478e+04)
    return f"{v:.{digits}g}"


def pct(value):
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


def pct_column(values, off=None):
    """A column of fractions as percentages in one format (issue 18: one format per column).

    Parameters
    ----------
    values : array_like, shape (M,)
        The fractions [1].
    off : array_like of bool, shape (M,), optional
        Entries that are round-off or exactly zero by the caller's rule
        (:func:`gd_analyze.core.selection.ranking.is_round_off`): shown as "\u2261 0"; an exact
        0 is always shown so.

    Returns
    -------
    list of str
        Two decimals ("1.23 %") when every shown value is at least 0.01 %, else one
        significant decimal in exponent form for all ("1.2e-02 %"); "n/a" where not finite.

    Examples
    --------
    >>> pct_column([0.0123, 0.5])
    ['1.23 %', '50.00 %']
    >>> pct_column([2e-4, 6.4e-5, 0.0], off=[False, False, True])
    ['2.0e-02 %', '6.4e-03 %', '\u2261 0']
    """
    v = 100.0 * np.asarray(values, dtype=float).ravel()
    hide = (v == 0) | (np.zeros(v.shape, bool) if off is None
                       else np.asarray(off, bool).ravel())
    shown = v[~hide & np.isfinite(v)]
    fixed = bool(np.all(np.abs(shown) >= 0.01))
    return ["\u2261 0" if h else "n/a" if not math.isfinite(x) else
            f"{x:.2f} %" if fixed else f"{x:.1e} %" for x, h in zip(v, hide)]


def attr(ds, key, default="\u2014", *, parens=True, bools=False, sci_outside=None):
    """A global attribute of a dataset as text.

    Parameters
    ----------
    ds : xarray.Dataset
        The dataset.
    key : str
        The attribute's name.
    default : str, optional
        Returned if the attribute is missing or empty.
    parens : bool, optional
        Put an array's values, joined by ", ", in parentheses.
    bools : bool, optional
        Format booleans as numbers (``1``) rather than as ``True``.
    sci_outside : (float, float), optional
        Passed to :func:`fmt` (numbers are written with 6 digits).

    Returns
    -------
    str
    """
    value = ds.attrs.get(key, None)
    if value is None:
        return default
    if isinstance(value, bytes):
        value = value.decode()
    if isinstance(value, np.ndarray):
        text = ", ".join(fmt(v, 6, sci_outside) for v in value.ravel())
        return f"({text})" if parens else text
    if isinstance(value, (np.generic, float, int)) and (
            bools or not isinstance(value, (bool, np.bool_))):
        return fmt(value, 6, sci_outside)
    from .markup import clean

    text = clean(str(value))            # no sub/superscript marks from a file's text
    return text if text else default
