"""Interval arithmetic on numpy arrays, rounded outward: the enclosures behind a proved bound.

An interval array is a pair ``(lo, hi)`` of float arrays of one shape; vectors carry their three
components on the last axis. Every operation returns an enclosure of all values the exact
operation takes over its operands' intervals, widened outward for floating-point rounding: a
sum or a product by one ulp (``numpy.nextafter``; IEEE 754 rounds each to within half an ulp),
a product by a point matrix by 16 units of round-off of the terms' magnitudes, a cosine or sine
by 4e-16 plus 4 ulps of the angle (libm's cos and sin are within one ulp; sin x is taken as
cos(x - pi/2), whose argument rounds). So the computed enclosure contains the exact
real range (Moore, Kearfott & Cloud, *Introduction to Interval Analysis*, SIAM 2009, Ch. 2-4).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: A batch of intervals: (lower, upper) bounds, elementwise.
_Interval = tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]

__all__ = ["point", "add", "sub", "mul", "scale", "magnitude", "cos_sin", "cross",
           "matvec", "ROUNDING"]

#: Unit round-off of a float [1].
ROUNDING = np.finfo(float).eps / 2


def _out(lo, hi):
    return np.nextafter(lo, -np.inf), np.nextafter(hi, np.inf)


def point(x: npt.ArrayLike) -> _Interval:
    """The degenerate interval [x, x].

    Parameters
    ----------
    x : array_like
        Any shape.

    Returns
    -------
    (ndarray, ndarray)
        ``(x, x)`` as float arrays.
    """
    x = np.asarray(x, float)
    return x, x


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
    >>> lo, hi = add(point(0.1), point(0.2))
    >>> bool(lo <= 0.3 <= hi)
    True
    """
    return _out(a[0] + b[0], a[1] + b[1])


def sub(a: _Interval, b: _Interval) -> _Interval:
    """a - b, rounded outward.

    Parameters
    ----------
    a, b : (ndarray, ndarray)
        Intervals of broadcastable shapes.

    Returns
    -------
    (ndarray, ndarray)
    """
    return _out(a[0] - b[1], a[1] - b[0])


def mul(a: _Interval, b: _Interval) -> _Interval:
    """a b, rounded outward (the four endpoint products).

    Parameters
    ----------
    a, b : (ndarray, ndarray)
        Intervals of broadcastable shapes.

    Returns
    -------
    (ndarray, ndarray)

    Examples
    --------
    >>> bool(mul((np.array(-1.0), np.array(2.0)), (np.array(3.0), np.array(4.0)))[1] >= 8.0)
    True
    """
    p = (a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1])
    return _out(np.minimum(np.minimum(p[0], p[1]), np.minimum(p[2], p[3])),
                np.maximum(np.maximum(p[0], p[1]), np.maximum(p[2], p[3])))


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


def cos_sin(lo: npt.NDArray[np.float64],
            hi: npt.NDArray[np.float64]) -> tuple[_Interval, _Interval]:
    """Enclosures of cos and sin over [lo, hi].

    Parameters
    ----------
    lo, hi : ndarray
        Angles [rad], lo <= hi, of one shape.

    Returns
    -------
    cos, sin : (ndarray, ndarray)
        Intervals containing cos x and sin x for every x in [lo, hi], within [-1, 1].

    Notes
    -----
    An extremum of cos lies inside the interval when it contains a multiple of pi; sin x =
    cos(x - pi/2).

    Examples
    --------
    >>> c, s = cos_sin(np.array([-0.1]), np.array([0.1]))
    >>> float(c[1][0]) == 1.0 and bool(c[0][0] < np.cos(0.1))
    True
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)

    def enclose(a, b):
        ca, cb = np.cos(a), np.cos(b)
        top = np.maximum(ca, cb)
        bot = np.minimum(ca, cb)
        # a multiple of 2 pi inside: cos reaches 1; an odd multiple of pi: -1
        k_hi = np.ceil(a / (2 * np.pi) - 1e-12)
        has_max = k_hi * 2 * np.pi <= b + 1e-12
        k_lo = np.ceil((a - np.pi) / (2 * np.pi) - 1e-12)
        has_min = k_lo * 2 * np.pi + np.pi <= b + 1e-12
        wide = (b - a) >= 2 * np.pi
        top = np.where(has_max | wide, 1.0, top)
        bot = np.where(has_min | wide, -1.0, bot)
        slack = 4e-16 + 4 * np.finfo(float).eps * np.maximum(np.abs(a), np.abs(b))
        return np.maximum(bot - slack, -1.0), np.minimum(top + slack, 1.0)
    return enclose(lo, hi), enclose(lo - np.pi / 2, hi - np.pi / 2)


def cross(a: _Interval, b: _Interval) -> _Interval:
    """The cross product a x b of interval vectors.

    Parameters
    ----------
    a, b : (ndarray, ndarray)
        Interval vectors of broadcastable shapes (..., 3).

    Returns
    -------
    (ndarray, ndarray)
        Shape (..., 3).
    """
    def comp(x):
        return a[0][..., x], a[1][..., x]

    def compb(x):
        return b[0][..., x], b[1][..., x]
    parts = [sub(mul(comp(i), compb(j)), mul(comp(j), compb(i)))
             for i, j in ((1, 2), (2, 0), (0, 1))]
    return np.stack([p[0] for p in parts], -1), np.stack([p[1] for p in parts], -1)


def matvec(M: npt.NDArray[np.float64], v: _Interval) -> _Interval:
    """M v for a point matrix M and an interval vector v, rounded outward.

    Parameters
    ----------
    M : ndarray, shape (3, 3)
        A point matrix.
    v : (ndarray, ndarray)
        Interval vectors, shape (..., 3).

    Returns
    -------
    (ndarray, ndarray)
        Shape (..., 3).
    """
    M = np.asarray(M, float)
    Mp, Mn = np.maximum(M, 0.0), np.minimum(M, 0.0)
    lo = v[0] @ Mp.T + v[1] @ Mn.T
    hi = v[1] @ Mp.T + v[0] @ Mn.T
    slack = 16 * ROUNDING * (magnitude(v) @ np.abs(M).T)
    return lo - slack, hi + slack
