"""Compiled interval-box enclosures of the regressor recursion, box by box.

The same recursion as :mod:`.ball_kernels` (forward: the links' velocities and accelerations
per channel; backward: each column of a link through every joint below it), in interval
arithmetic instead of midpoint-radius balls: a vector is three intervals,
stored as six numbers along the last axis (the lower ends, then the upper ends). Interval boxes
keep each component's own width, where a ball gives the three one radius; they wrap under
rotations, where a ball does not. Each is the tighter on some channels
(``regressor_bounds.channel_enclosures`` intersects the two), so this is the second of two
sound enclosures, not a replacement.

Rounding: each operation computes its ends in floating point from the operands' ends, as the
tests' array oracle does (``tests/interval_oracle.py``; a product's ends the least and largest of the four endpoint products,
a point matrix's product the positive and negative parts of the matrix), and then widens each
end outward by 32 units of round-off of the magnitudes it combined plus 2^-996 (an underflowing
product's absolute error is at most 2^-1075), in one step. The operation performs at most six
roundings, each within one unit of round-off of those magnitudes (IEEE 754, round to nearest;
Higham 2002, Sec. 2.2), and the widening's own three roundings are far inside the margin, so
the widened ends enclose the exact operation's range over the operands' intervals (Moore,
Kearfott & Cloud 2009, Ch. 2-4). The cosine of a joint's interval [a, b] is widened by 4e-16
plus 4 ulps of the angle and reaches -1 or 1 where the interval holds an odd or even multiple
of pi; sin x = cos(x - pi/2). The array code of ``regressor_bounds._column_groups`` with the
oracle's box algebra (``Box``, which rounds each operation by one ulp) is the tests' oracle of
these kernels.

Compiling: the small helpers (an operation's rounding, a product, a row) are inlined into their
callers in numba's own code (``inline="always"``); the composite ones (cross products,
rotations, sums of vectors, a link's position, the clip by the balls) and the reads and writes
of a stored vector are compiled once each and called, because inlining them copies their bodies
into every call site of the two kernels, which made compiling the kernels, once after an
install, about twice as long (and the enclosures about a tenth faster). The arithmetic
is the same operations in the same order either way (no ``fastmath``), so the enclosures are
equal bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import ball_kernels as bk
from .intervals import ROUNDING

__all__ = ["box_forward_kernel", "both_backward_kernel"]

_SLACK = 32 * ROUNDING
#: The absolute part of the widening (2^-996): above the underflow of any few products.
_TINY = 2.0 ** -996
_EPS = 2 * ROUNDING
_HALF_PI = np.pi / 2
_TWO_PI = 2 * np.pi


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _down(x, m):
    """x widened down by the slack of magnitudes m."""
    return x - (_SLACK * m + _TINY)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _up(x, m):
    """x widened up by the slack of magnitudes m."""
    return x + (_SLACK * m + _TINY)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _mul(alo, ahi, blo, bhi):
    """The product's ends (least and largest endpoint products, unrounded) and magnitude."""
    p, q, r, s = alo * blo, alo * bhi, ahi * blo, ahi * bhi
    lo = min(min(p, q), min(r, s))
    hi = max(max(p, q), max(r, s))
    return lo, hi, max(abs(lo), abs(hi))


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _msub(alo, ahi, blo, bhi, clo, chi, dlo, dhi):
    """a b - c d for intervals, rounded outward."""
    xl, xh, xm = _mul(alo, ahi, blo, bhi)
    yl, yh, ym = _mul(clo, chi, dlo, dhi)
    m = xm + ym
    return _down(xl - yh, m), _up(xh - yl, m)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _madd(alo, ahi, blo, bhi, clo, chi, dlo, dhi):
    """a b + c d for intervals, rounded outward."""
    xl, xh, xm = _mul(alo, ahi, blo, bhi)
    yl, yh, ym = _mul(clo, chi, dlo, dhi)
    m = xm + ym
    return _down(xl + yl, m), _up(xh + yh, m)


@njit(cache=True, fastmath=False, nogil=True)
def _add(a, b):
    """a + b (:func:`.intervals.add`)."""
    l0, l1, l2 = a[0] + b[0], a[1] + b[1], a[2] + b[2]
    h0, h1, h2 = a[3] + b[3], a[4] + b[4], a[5] + b[5]
    return (_down(l0, abs(l0)), _down(l1, abs(l1)), _down(l2, abs(l2)),
            _up(h0, abs(h0)), _up(h1, abs(h1)), _up(h2, abs(h2)))


@njit(cache=True, fastmath=False, nogil=True)
def _scale(a, s):
    """s a for a point number s (:func:`.intervals.scale`)."""
    x0, x1, x2 = a[0] * s, a[1] * s, a[2] * s
    y0, y1, y2 = a[3] * s, a[4] * s, a[5] * s
    l0, l1, l2 = min(x0, y0), min(x1, y1), min(x2, y2)
    h0, h1, h2 = max(x0, y0), max(x1, y1), max(x2, y2)
    return (_down(l0, abs(l0)), _down(l1, abs(l1)), _down(l2, abs(l2)),
            _up(h0, abs(h0)), _up(h1, abs(h1)), _up(h2, abs(h2)))


@njit(cache=True, fastmath=False, nogil=True)
def _cross(a, b):
    """a x b (the oracle's ``cross``)."""
    l0, h0 = _msub(a[1], a[4], b[2], b[5], a[2], a[5], b[1], b[4])
    l1, h1 = _msub(a[2], a[5], b[0], b[3], a[0], a[3], b[2], b[5])
    l2, h2 = _msub(a[0], a[3], b[1], b[4], a[1], a[4], b[0], b[3])
    return (l0, l1, l2, h0, h1, h2)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _psub(alo, ahi, b, clo, chi, d):
    """a b - c d for intervals a, c and point numbers b, d, rounded outward."""
    x, y = alo * b, ahi * b
    u, v = clo * d, chi * d
    xl, xh, ul, uh = min(x, y), max(x, y), min(u, v), max(u, v)
    m = max(abs(xl), abs(xh)) + max(abs(ul), abs(uh))
    return _down(xl - uh, m), _up(xh - ul, m)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _cross_point(a, p):
    """a x p for a point vector p (``p`` a box whose ends are equal)."""
    l0, h0 = _psub(a[1], a[4], p[2], a[2], a[5], p[1])
    l1, h1 = _psub(a[2], a[5], p[0], a[0], a[3], p[2])
    l2, h2 = _psub(a[0], a[3], p[1], a[1], a[4], p[0])
    return (l0, l1, l2, h0, h1, h2)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _cross_unit(a, m):
    """a x e_m for the unit vector e_m, exactly: each component is one of a's, negated, or
    0 (a x e_x = (0, a_z, -a_y), a x e_y = (-a_z, 0, a_x), a x e_z = (a_y, -a_x, 0))."""
    if m == 0:
        return (0.0, a[2], -a[4], 0.0, a[5], -a[1])
    if m == 1:
        return (-a[5], 0.0, a[0], -a[2], 0.0, a[3])
    return (a[1], -a[3], 0.0, a[4], -a[0], 0.0)


@njit(cache=True, fastmath=False, nogil=True)
def _cross_p(a, p, point):
    """a x p, p a point vector where ``point`` (its ends equal: a revolute joint's p_k)."""
    if point:
        return _cross_point(a, p)
    return _cross(a, p)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _neg(a):
    """-a, exactly."""
    return (-a[3], -a[4], -a[5], -a[0], -a[1], -a[2])


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _row(M, r, a):
    """Row r of M a for a point matrix M: its ends and the terms' magnitude."""
    lo = 0.0
    hi = 0.0
    m = 0.0
    for c in range(3):
        e = M[r, c]
        if e >= 0.0:
            lo += e * a[c]
            hi += e * a[3 + c]
        else:
            lo += e * a[3 + c]
            hi += e * a[c]
        m += abs(e) * max(abs(a[c]), abs(a[3 + c]))
    return _down(lo, m), _up(hi, m)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _matvec(M, a):
    """M a for a point matrix M (3, 3) (the oracle's ``matvec``)."""
    l0, h0 = _row(M, 0, a)
    l1, h1 = _row(M, 1, a)
    l2, h2 = _row(M, 2, a)
    return (l0, l1, l2, h0, h1, h2)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _cos_range(a, b):
    """An enclosure of cos over [a, b] (the oracle's ``cos_sin``)."""
    ca, cb = math.cos(a), math.cos(b)
    top, bot = max(ca, cb), min(ca, cb)
    k_hi = math.ceil(a / _TWO_PI - 1e-12)
    k_lo = math.ceil((a - np.pi) / _TWO_PI - 1e-12)
    wide = (b - a) >= _TWO_PI
    if wide or k_hi * _TWO_PI <= b + 1e-12:
        top = 1.0
    if wide or k_lo * _TWO_PI + np.pi <= b + 1e-12:
        bot = -1.0
    slack = 4e-16 + 4 * _EPS * max(abs(a), abs(b))
    return max(bot - slack, -1.0), min(top + slack, 1.0)


@njit(cache=True, fastmath=False, nogil=True)
def _trig(q_lo, q_hi):
    """Per joint of a box, enclosures of cos q and sin q: (cos lo, cos hi, sin lo, sin hi),
    shape (n, 4) (the oracle's ``cos_sin``: sin x = cos(x - pi/2))."""
    out = np.empty((q_lo.shape[0], 4))
    for j in range(q_lo.shape[0]):
        out[j, 0], out[j, 1] = _cos_range(q_lo[j], q_hi[j])
        out[j, 2], out[j, 3] = _cos_range(q_lo[j] - _HALF_PI, q_hi[j] - _HALF_PI)
    return out


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _rot_z(a, trig, transpose):
    """Rz(q) a, or Rz(q)^T a, for every q of the joint's interval (the oracle's ``rotz``;
    ``trig`` the joint's row of :func:`_trig`)."""
    cl, ch, sl, sh = trig[0], trig[1], trig[2], trig[3]
    if transpose:
        xl, xh = _madd(cl, ch, a[0], a[3], sl, sh, a[1], a[4])
        yl, yh = _msub(cl, ch, a[1], a[4], sl, sh, a[0], a[3])
    else:
        xl, xh = _msub(cl, ch, a[0], a[3], sl, sh, a[1], a[4])
        yl, yh = _madd(sl, sh, a[0], a[3], cl, ch, a[1], a[4])
    return (xl, yl, a[2], xh, yh, a[5])


@njit(cache=True, fastmath=False, nogil=True)
def _get(A, index):
    return (A[index, 0], A[index, 1], A[index, 2], A[index, 3], A[index, 4], A[index, 5])


@njit(cache=True, fastmath=False, nogil=True)
def _set(A, index, a):
    for c in range(6):
        A[index, c] = a[c]


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _slide(t, x, y):
    """t + [min(x, y), max(x, y)], rounded outward (one component of the oracle's ``Box.slide``)."""
    m = abs(t) + max(abs(x), abs(y))
    return _down(t + min(x, y), m), _up(t + max(x, y), m)


@njit(cache=True, fastmath=False, nogil=True)
def _position(k, q_lo, q_hi, t, P, pris):
    """p_k as a box: t_k, plus q_k P_k z for a prismatic joint (the oracle's ``Box.slide``)."""
    if not pris[k]:
        return (t[k, 0], t[k, 1], t[k, 2], t[k, 0], t[k, 1], t[k, 2])
    l0, h0 = _slide(t[k, 0], q_lo[k] * P[k, 0, 2], q_hi[k] * P[k, 0, 2])
    l1, h1 = _slide(t[k, 1], q_lo[k] * P[k, 1, 2], q_hi[k] * P[k, 1, 2])
    l2, h2 = _slide(t[k, 2], q_lo[k] * P[k, 2, 2], q_hi[k] * P[k, 2, 2])
    return (l0, l1, l2, h0, h1, h2)


@njit(cache=True, fastmath=False, nogil=True)
def _rot(k, a, trig, P, pris):
    """R_k a = P_k Rz(q_k) a (revolute) or P_k a (prismatic)."""
    if not pris[k]:
        a = _rot_z(a, trig[k], False)
    return _matvec(P[k], a)


@njit(cache=True, fastmath=False, nogil=True)
def _rot_t(k, a, trig, P, pris):
    """R_k^T a = Rz(q_k)^T P_k^T a (revolute) or P_k^T a (prismatic)."""
    u = _matvec(P[k].T, a)
    if pris[k]:
        return u
    return _rot_z(u, trig[k], True)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _sym(a, i, j):
    """E a for the symmetric unit matrix E of the index pair (i, j) (the oracle's ``Box.sym``)."""
    return (a[j] if i == 0 else (a[i] if j == 0 else 0.0),
            a[j] if i == 1 else (a[i] if j == 1 else 0.0),
            a[j] if i == 2 else (a[i] if j == 2 else 0.0),
            a[3 + j] if i == 0 else (a[3 + i] if j == 0 else 0.0),
            a[3 + j] if i == 1 else (a[3 + i] if j == 1 else 0.0),
            a[3 + j] if i == 2 else (a[3 + i] if j == 2 else 0.0))


@njit(cache=True, fastmath=False, nogil=True)
def _clip(A, balls):
    """Each box A[m] (m, 6) intersected with the bounding box of the ball balls[m] (m, 4)
    (centre c, radius r: c_i - r <= x_i <= c_i + r, rounded outward)."""
    for m in range(A.shape[0]):
        r = balls[m, 3]
        for c in range(3):
            x = balls[m, c]
            A[m, c] = max(A[m, c], _down(x - r, abs(x) + r))
            A[m, 3 + c] = min(A[m, 3 + c], _up(x + r, abs(x) + r))


@njit(cache=True, fastmath=False, nogil=True)
def box_forward_kernel(q_lo, q_hi, P, t, pris, gravity, top, balls):
    """The forward recursion of the regressor's channels, every box, as interval boxes.

    Parameters
    ----------
    q_lo, q_hi : ndarray, shape (B, n)
        The boxes [rad or m], checked (q_lo <= q_hi).
    P : ndarray, shape (n, 3, 3)
        The joints' fixed placements.
    t : ndarray, shape (n, 3)
        The placements' translations [m].
    pris : ndarray of bool, shape (n,)
    gravity : ndarray, shape (3,)
        [m/s^2].
    top : int
        The links to run, the first ``top``.
    balls : tuple of three ndarrays, or None
        :func:`.ball_kernels.forward_kernel`'s (W, WD, VD) on the same boxes, whose balls
        enclose the same vectors: each link's boxes are intersected with the balls' bounding
        boxes before the next link is run (so they do not wrap beyond the balls); None: the
        boxes alone.

    Returns
    -------
    W : ndarray, shape (top, B, top, 6)
        Per link k and box, the angular velocity of link k per unit qd_j, j < top (the lower
        ends, then the upper ends, along the last axis).
    WD, VD : ndarray, shape (top, B, C, 6)
        Per link k and box, its angular and linear accelerations per channel (C = 1 + top +
        top^2: gravity, qdd_j, the velocity pairs qd_j qd_l), in the layout of
        ``regressor_bounds._forward``, whose array code with the box algebra (the tests'
        oracle) performs the same operations over all boxes at once.

    Raises
    ------
    None: the caller (``regressor_bounds._boxes_and_balls``) passes checked arrays.

    Notes
    -----
    Source: the forward recursion of the Newton-Euler equations (Fu, Gonzalez & Lee 1987,
    Table 3.3) per channel, as the regressor of Khalil & Kleinfinger (1987), in interval
    arithmetic rounded outward (the module's rounding).
    """
    B = q_lo.shape[0]
    n = top
    W, WD, VD, w, wp, wd, vd, a = bk._forward_arrays(B, n, 6)
    active, count = bk._active(n)
    for b in range(B):
        trig = _trig(q_lo[b], q_hi[b])
        bk._zero(w)
        bk._zero(wp)
        bk._zero(wd)
        bk._zero(vd)
        for c in range(3):
            vd[0, c] = vd[0, 3 + c] = -gravity[c]
        for k in range(n):
            p = _position(k, q_lo[b], q_hi[b], t, P, pris)
            point = not pris[k]
            # only the channels of joints 0..k: the others are exactly zero up to link k
            for x in range(count[k]):
                c = active[k, x]
                _set(a, c, _add(_get(vd, c), _cross_p(_get(wd, c), p, point)))
            for j in range(k + 1):
                for l in range(k + 1):
                    c = 1 + n + j * n + l
                    _set(a, c, _add(_get(a, c), _cross(_get(w, j),
                                                       _cross_p(_get(w, l), p, point))))
            for x in range(count[k]):
                c = active[k, x]
                _set(vd, c, _rot_t(k, _get(a, c), trig, P, pris))
            for j in range(k + 1):
                _set(wp, j, _rot_t(k, _get(w, j), trig, P, pris))
            for x in range(count[k]):
                c = active[k, x]
                _set(wd, c, _rot_t(k, _get(wd, c), trig, P, pris))
            if pris[k]:
                vd[1 + k, 2] += 1.0          # exact: the channel is zero before link k
                vd[1 + k, 5] += 1.0
                for j in range(k + 1):
                    c = 1 + n + j * n + k
                    zk = _cross_unit(_get(wp, j), 2)
                    _set(vd, c, _add(_get(vd, c), _scale(zk, 2.0)))
            else:
                wd[1 + k, 2] += 1.0
                wd[1 + k, 5] += 1.0
                for j in range(k + 1):
                    c = 1 + n + j * n + k
                    zk = _cross_unit(_get(wp, j), 2)
                    _set(wd, c, _add(_get(wd, c), zk))
                wp[k, 2] += 1.0
                wp[k, 5] += 1.0
            bk._copy(w, wp)
            if balls is not None:
                _clip(w, balls[0][k, b])
                _clip(wd, balls[1][k, b])
                _clip(vd, balls[2][k, b])
            bk._copy(W[k, b], w)
            bk._copy(WD[k, b], wd)
            bk._copy(VD[k, b], vd)
    return W, WD, VD


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _clip_one(a, ball, alone):
    """The box a intersected with the bounding box of ``ball`` (centre, radius), rounded
    outward; a itself where ``alone``."""
    if alone:
        return a
    r = ball[3]
    m0, m1, m2 = abs(ball[0]) + r, abs(ball[1]) + r, abs(ball[2]) + r
    return (max(a[0], _down(ball[0] - r, m0)), max(a[1], _down(ball[1] - r, m1)),
            max(a[2], _down(ball[2] - r, m2)), min(a[3], _up(ball[0] + r, m0)),
            min(a[4], _up(ball[1] + r, m1)), min(a[5], _up(ball[2] + r, m2)))


@njit(cache=True, fastmath=False, nogil=True)
def both_backward_kernel(k, types, ms, ch, balls, boxes, mid, half, norms, q_lo, q_hi, P, t,
                         pris, top, alone, lo, hi):
    """The backward recursion of link k's columns in both arithmetics at once, every box:
    their torques' enclosures intersected, written into the caller's arrays.

    Parameters
    ----------
    k : int
        The link.
    types : ndarray of int, shape (g,)
        Its columns' standard parameters (0-5 the inertia XX..ZZ, 6-8 the first moments, 9
        the mass).
    ms : ndarray of int, shape (g,)
        Their positions in the output's last axis.
    ch : ndarray of int, shape (Ck,)
        The link's channels' positions in the output's channel axis (Ck = 1 + (k + 1) +
        (k + 1)^2: gravity, the accelerations of joints 0..k, the velocity pairs).
    balls : tuple of three ndarrays
        :func:`.ball_kernels.forward_kernel`'s (W, WD, VD) at link k, shapes (B, top, 4),
        (B, C, 4), (B, C, 4).
    boxes : tuple of three ndarrays
        :func:`box_forward_kernel`'s at link k, shapes (B, top, 6), (B, C, 6), (B, C, 6).
    mid, half : ndarray, shape (B, n)
        The boxes' mid points and half-widths as the balls take them
        (``regressor_bounds._Ball``'s, widened) [rad or m].
    norms : ndarray, shape (n,)
        Upper bounds of the spectral norms of P_k.
    q_lo, q_hi : ndarray, shape (B, n)
        The boxes [rad or m].
    P : ndarray, shape (n, 3, 3)
        The joints' fixed placements.
    t : ndarray, shape (n, 3)
        The placements' translations [m].
    pris : ndarray of bool, shape (n,)
    top : int
        The links the forward recursions ran.
    alone : bool
        True: the boxes' enclosures alone, neither intersected nor clipped with the balls
        (the boxes' arithmetic on its own, as ``regressor_bounds._column_groups`` runs it in
        the box algebra of the tests' oracle).
    lo, hi : ndarray, shape (B, C_all, n, m)
        Written at [b, ch[x], i, ms[q]] for every joint i <= k: lo <= torque <= hi [N m or N
        per unit parameter] (``regressor_bounds.channel_enclosures``' layout).

    Raises
    ------
    None: the caller (``regressor_bounds.channel_enclosures``) passes checked boxes.

    Notes
    -----
    Source: the backward recursion of the Newton-Euler equations (Fu, Gonzalez & Lee 1987,
    Table 3.3) per standard parameter (Khalil & Kleinfinger 1987): f_{i-1} = R_i f_i,
    n_{i-1} = R_i n_i + p_i x f_i, and tau_i the z component of n_i (of f_i for a prismatic
    joint). Each box runs :func:`.ball_kernels.backward_kernel`'s recursion (the same
    operations) and the same recursion in interval boxes side by side (an inertia column's
    force is exactly zero, so its moment's box is only rotated; a product by a unit vector
    is exact); after each joint the boxes are intersected with the balls' bounding boxes
    (both enclose the same wrench), so that they do not wrap beyond them, and the torque is
    the intersection of the two enclosures of its component (Moore, Kearfott & Cloud 2009,
    Ch. 6: an intersection of enclosures encloses).
    """
    W, WD, VD = balls
    X, XD, XV = boxes
    B = mid.shape[0]
    kk = k + 1
    Ck = 1 + kk + kk * kk
    g = types.shape[0]
    own = bk._own(k, top)
    pairs = np.array([[0, 0], [0, 1], [0, 2], [1, 1], [1, 2], [2, 2]])
    zero4 = (0.0, 0.0, 0.0, 0.0)
    zero6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    f = np.zeros((g, Ck, 4))
    mom = np.zeros((g, Ck, 4))
    fx = np.zeros((g, Ck, 6))
    mx = np.zeros((g, Ck, 6))
    for b in range(B):
        m, h = mid[b], half[b]
        trig = bk._trig(m, h)
        trig_x = _trig(q_lo[b], q_hi[b])
        for q in range(g):
            c = types[q]
            for x in range(Ck):
                wd, vd = bk._get(WD[b], own[x]), bk._get(VD[b], own[x])
                wdx, vdx = _get(XD[b], own[x]), _get(XV[b], own[x])
                vel = x >= 1 + kk
                if vel:
                    ja, jb = (x - 1 - kk) // kk, (x - 1 - kk) % kk
                    wa, wb = bk._get(W[b], ja), bk._get(W[b], jb)
                    wax, wbx = _get(X[b], ja), _get(X[b], jb)
                else:
                    wa, wb, wax, wbx = zero4, zero4, zero6, zero6
                if c < 6:
                    i, j = pairs[c, 0], pairs[c, 1]
                    bk._set(f[q], x, zero4)
                    bk._set(mom[q], x, bk._add(bk._sym(wd, i, j), bk._cross(wa, bk._sym(wb, i, j))))
                    _set(fx[q], x, zero6)
                    if vel:
                        _set(mx[q], x, _add(_sym(wdx, i, j), _cross(wax, _sym(wbx, i, j))))
                    else:
                        _set(mx[q], x, _sym(wdx, i, j))
                elif c < 9:
                    e = (1.0 if c == 6 else 0.0, 1.0 if c == 7 else 0.0,
                         1.0 if c == 8 else 0.0, 0.0)
                    bk._set(f[q], x, bk._add(bk._cross(wd, e), bk._cross(wa, bk._cross(wb, e))))
                    bk._set(mom[q], x, bk._cross(e, vd))
                    if vel:
                        _set(fx[q], x, _add(_cross_unit(wdx, c - 6),
                                            _cross(wax, _cross_unit(wbx, c - 6))))
                    else:
                        _set(fx[q], x, _cross_unit(wdx, c - 6))
                    _set(mx[q], x, _neg(_cross_unit(vdx, c - 6)))
                else:
                    bk._set(f[q], x, vd)
                    bk._set(mom[q], x, zero4)
                    _set(fx[q], x, vdx)
                    _set(mx[q], x, zero6)
        for i in range(k, -1, -1):
            src, srx = (f, fx) if pris[i] else (mom, mx)
            for q in range(g):
                for x in range(Ck):
                    if alone:
                        lo[b, ch[x], i, ms[q]] = srx[q, x, 2]
                        hi[b, ch[x], i, ms[q]] = srx[q, x, 5]
                    else:
                        lo[b, ch[x], i, ms[q]] = max(src[q, x, 2] - src[q, x, 3], srx[q, x, 2])
                        hi[b, ch[x], i, ms[q]] = min(src[q, x, 2] + src[q, x, 3], srx[q, x, 5])
            if i == 0:
                break
            p = bk._position(i, m, h, t, P, pris)
            px = _position(i, q_lo[b], q_hi[b], t, P, pris)
            point = not pris[i]
            for q in range(g):
                inertial = types[q] < 6
                for x in range(Ck):
                    moved = bk._rot(i, bk._get(mom[q], x), trig, P, norms, pris)
                    movedx = _rot(i, _get(mx[q], x), trig_x, P, pris)
                    if inertial:
                        bk._set(mom[q], x, bk._add(moved, zero4))
                        _set(mx[q], x, _clip_one(movedx, bk._get(mom[q], x), alone))
                    else:
                        fi = bk._rot(i, bk._get(f[q], x), trig, P, norms, pris)
                        bk._set(f[q], x, fi)
                        bk._set(mom[q], x, bk._add(moved, bk._cross(p, fi)))
                        fix = _clip_one(_rot(i, _get(fx[q], x), trig_x, P, pris), fi, alone)
                        _set(fx[q], x, fix)
                        _set(mx[q], x, _clip_one(_add(movedx, _neg(_cross_p(fix, px, point))),
                                                 bk._get(mom[q], x), alone))
