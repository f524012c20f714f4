"""The extremes of a quadratic form with zero diagonal over the vertices of a box, compiled.

The velocity part of a regressor column, qd^T C qd, is bounded over the box |qd_j| <= a_j by
:class:`gd_analyze.certify.regressor_bounds._QuadraticBound`: its off-diagonal part
f(v) = sum_{j < l} m_jl a_j a_l v_j v_l is affine in each v_j, so its extremes over the box are
at vertices v in {-1, 1}^s (half of them: v and -v give the same value, so v_0 = 1). Here they
are searched in Gray-code order (Gray 1953; Knuth, TAOCP 4A, Sec. 7.2.1.1): from one vertex to
the next one sign v_j flips, so that f changes by -2 v_j g_j with g = M v, and g by -2 v_j
M[:, j]: s + 1 operations per vertex instead of a sum over all s (s - 1) / 2 pairs. The rows of
a batch share the order of the vertices, so each step runs over the rows, which are the inner,
contiguous loop. Every :data:`BLOCK` vertices f and g are computed afresh from v, so the
round-off of the updates does not accumulate past a block; :func:`vertex_extremes` returns an
explicit bound of the round-off that remains.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from numba import njit

__all__ = ["BLOCK", "vertex_extremes"]

#: Vertices between two evaluations of f and g from scratch.
BLOCK = 64
#: Rows of one pass (its M, g and f stay in the cache).
_ROWS = 256
_U = np.finfo(float).eps / 2


@njit(cache=True, fastmath=False, nogil=True)
def _extremes(mid, j_of, l_of, w_off, s, c_max, c_min):
    R, P = mid.shape
    V = 1 << (s - 1)
    v = np.ones(s)
    for r0 in range(0, R, _ROWS):
        r1 = min(R, r0 + _ROWS)
        m = r1 - r0
        M = np.zeros((s, s, m))
        for p in range(P):
            j, l = j_of[p], l_of[p]
            for r in range(m):
                x = mid[r0 + r, p] * w_off[p]
                M[j, l, r] = x
                M[l, j, r] = x
        g = np.empty((s, m))
        f = np.empty(m)
        hi = np.empty(m)
        lo = np.empty(m)
        for t in range(V):
            if t % BLOCK == 0:                  # f and g afresh at this vertex
                for i in range(s):
                    v[i] = 1.0
                gray = t ^ (t >> 1)
                for i in range(1, s):
                    if (gray >> (i - 1)) & 1:
                        v[i] = -1.0
                for i in range(s):
                    for r in range(m):
                        g[i, r] = 0.0
                    for k in range(s):
                        if k != i:
                            for r in range(m):
                                g[i, r] += M[i, k, r] * v[k]
                for r in range(m):
                    f[r] = 0.0
                for i in range(s):
                    for r in range(m):
                        f[r] += 0.5 * v[i] * g[i, r]
            else:                               # flip the sign of the Gray code's bit
                b = 0
                while not (t >> b) & 1:
                    b += 1
                j = b + 1
                c = -2.0 * v[j]
                for r in range(m):
                    f[r] += c * g[j, r]
                for i in range(s):
                    if i != j:
                        for r in range(m):
                            g[i, r] += c * M[i, j, r]
                v[j] = -v[j]
            if t == 0:
                for r in range(m):
                    hi[r] = f[r]
                    lo[r] = f[r]
            else:
                for r in range(m):
                    hi[r] = max(hi[r], f[r])
                    lo[r] = min(lo[r], f[r])
        for r in range(m):
            c_max[r0 + r] = hi[r]
            c_min[r0 + r] = lo[r]


def vertex_extremes(mid: npt.NDArray[np.float64], j: npt.NDArray[np.int64],
                    l: npt.NDArray[np.int64], w_off: npt.NDArray[np.float64], s: int,
                    widen: bool = True) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Enclosures of the largest and the smallest f(v) over the vertices v in {-1, 1}^s.

    Parameters
    ----------
    mid : ndarray, shape (R, P)
        Per row, the coefficients m_p of the P = s (s - 1) / 2 pairs (j_p, l_p).
    j, l : ndarray of int, shape (P,)
        The pairs, 0 <= j_p < l_p < s, each once.
    w_off : ndarray, shape (P,)
        The weights a_j a_l >= 0 of the pairs.
    s : int
        The number of signs, 1 <= s (2^(s - 1) vertices are searched).
    widen : bool, optional
        Widen the computed extremes by the bound of their round-off (default), so that they
        enclose the exact ones; without, they are the computed values (for sampled peaks,
        which are found, not proved).

    Returns
    -------
    top, bottom : ndarray, shape (R,)
        top >= max_v f(v) and bottom <= min_v f(v), f(v) = sum_p m_p w_p v_j v_l, each the
        computed extreme widened by the bound of its round-off (``widen``).

    Raises
    ------
    ValueError
        If the shapes do not agree or s < 1.

    Notes
    -----
    Let u be the unit round-off and F = sum_p |m_p w_p|, so that |g_i| <= G_i = sum_k |M_ik|
    <= F, sum_i G_i = 2 F and |f| <= F. Every :data:`BLOCK` vertices g and f are summed afresh,
    with errors at most s u G_i and 2 s u F (Higham 2002, Sec. 3.1). Each of the at most
    BLOCK - 1 updates since adds at most 2 u F to every g_i (the product by c = +-2 is exact)
    and, through g_j and its own rounding, at most 2 (2 (s + BLOCK) + 1) u F to f. The
    widening is twice the sum of these, with the rounding of the products m_p w_p (u F) on
    top.
    """
    mid = np.ascontiguousarray(mid, dtype=float)
    j, l = np.asarray(j, np.int64), np.asarray(l, np.int64)
    w_off = np.asarray(w_off, float)
    R, P = mid.shape
    if s < 1 or j.shape != (P,) or l.shape != (P,) or w_off.shape != (P,) \
            or P != s * (s - 1) // 2:
        raise ValueError("vertex_extremes: the pairs do not match the shapes")
    c_max, c_min = np.zeros(R), np.zeros(R)
    if P and R:
        _extremes(mid, j, l, w_off, s, c_max, c_min)
    if not widen:
        return c_max, c_min
    F = (np.abs(mid) * np.abs(w_off)).sum(axis=1)      # row by row, whatever R
    slack = 2 * (1 + 2 * s + (BLOCK - 1) * (2 * (2 * (s + BLOCK) + 1) + 2)) * _U * F
    return c_max + slack, c_min - slack
