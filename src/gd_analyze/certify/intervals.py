"""Interval arithmetic on numpy arrays, rounded outward: the enclosures behind a proved bound.

An interval array is a pair ``(lo, hi)`` of float arrays of one shape. Every operation returns
an enclosure of all values the exact operation takes over its operands' intervals, widened
outward for floating-point rounding: a sum or a product by a point number by one ulp
(``numpy.nextafter``; IEEE 754 rounds each to within half an ulp). So the computed enclosure
contains the exact real range (Moore, Kearfott & Cloud, *Introduction to Interval Analysis*,
SIAM 2009, Ch. 2-4). The recursion's own interval arithmetic (products, cross products,
rotations, the cosine and sine of an interval) is compiled in :mod:`.box_kernels`; its array
form is the tests' oracle of those kernels.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: A batch of intervals: (lower, upper) bounds, elementwise.
_Interval = tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]

__all__ = ["add", "scale", "magnitude", "ROUNDING"]

#: Unit round-off of a float [1].
ROUNDING = np.finfo(float).eps / 2


def _out(lo, hi):
    return np.nextafter(lo, -np.inf), np.nextafter(hi, np.inf)


def add(a: _Interval, b: _Interval) -> _Interval:
    """a + b, rounded outward.

    Parameters
    ----------
    a, b : (ndarray, ndarray)
        Intervals of broadcastable shapes.

    Returns
    -------
    (ndarray, ndarray)

    Examples
    --------
    >>> lo, hi = add((np.array(0.1),) * 2, (np.array(0.2),) * 2)
    >>> bool(lo <= 0.3 <= hi)
    True
    """
    return _out(a[0] + b[0], a[1] + b[1])


def scale(a: _Interval, c: float) -> _Interval:
    """c a for a point number c, rounded outward.

    Parameters
    ----------
    a : (ndarray, ndarray)
        Interval.
    c : float

    Returns
    -------
    (ndarray, ndarray)
    """
    lo, hi = a[0] * c, a[1] * c
    return _out(np.minimum(lo, hi), np.maximum(lo, hi))


def magnitude(a: _Interval) -> npt.NDArray[np.float64]:
    """max |x| over the interval.

    Parameters
    ----------
    a : (ndarray, ndarray)

    Returns
    -------
    ndarray
        max(|lo|, |hi|), of the intervals' shape.
    """
    return np.maximum(np.abs(a[0]), np.abs(a[1]))


