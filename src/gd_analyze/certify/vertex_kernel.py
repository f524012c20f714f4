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

__all__ = ["BLOCK", "vertex_extremes", "found_extremes", "INNER"]

#: Vertices between two evaluations of f and g from scratch.
BLOCK = 64
#: Rows of one pass (its M, g and f stay in the cache).
_ROWS = 256
_U = np.finfo(float).eps / 2
#: Signs of the inner half of :func:`found_extremes` (2^(INNER - 1) patterns, a table of their
#: values per row).
INNER = 8


@njit(cache=True, fastmath=False, nogil=True)
def _pair_matrix(mid, j_of, l_of, w_off, s, r0, m):
    """The symmetric matrices M[j, l, r] = m_p w_p of the rows r0 .. r0 + m - 1 (zero diagonal)."""
    M = np.zeros((s, s, m))
    for p in range(mid.shape[1]):
        j, l = j_of[p], l_of[p]
        for r in range(m):
            x = mid[r0 + r, p] * w_off[p]
            M[j, l, r] = x
            M[l, j, r] = x
    return M


@njit(cache=True, fastmath=False, nogil=True)
def _flip(f, g, M, v, j, s, m):
    """Flip the sign v_j of the first s signs: f changes by -2 v_j g_j, g by -2 v_j M[:, j]."""
    c = -2.0 * v[j]
    for r in range(m):
        f[r] += c * g[j, r]
    for i in range(s):
        if i != j:
            for r in range(m):
                g[i, r] += c * M[i, j, r]
    v[j] = -v[j]


@njit(cache=True, fastmath=False, nogil=True)
def _extremes(mid, j_of, l_of, w_off, s, c_max, c_min):
    R = mid.shape[0]
    V = 1 << (s - 1)
    v = np.ones(s)
    for r0 in range(0, R, _ROWS):
        r1 = min(R, r0 + _ROWS)
        m = r1 - r0
        M = _pair_matrix(mid, j_of, l_of, w_off, s, r0, m)
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
                _flip(f, g, M, v, b + 1, s, m)
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


def _checked(mid, j, l, w_off, s, name):
    """The arguments as the kernels take them, their shapes checked."""
    mid = np.ascontiguousarray(mid, dtype=float)
    j, l = np.asarray(j, np.int64), np.asarray(l, np.int64)
    w_off = np.asarray(w_off, float)
    P = mid.shape[1]
    if s < 1 or j.shape != (P,) or l.shape != (P,) or w_off.shape != (P,) \
            or P != s * (s - 1) // 2:
        raise ValueError(f"{name}: the pairs do not match the shapes")
    return mid, j, l, w_off


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
    mid, j, l, w_off = _checked(mid, j, l, w_off, s, "vertex_extremes")
    R, P = mid.shape
    c_max, c_min = np.zeros(R), np.zeros(R)
    if P and R:
        _extremes(mid, j, l, w_off, s, c_max, c_min)
    if not widen:
        return c_max, c_min
    F = (np.abs(mid) * np.abs(w_off)).sum(axis=1)      # row by row, whatever R
    slack = 2 * (1 + 2 * s + (BLOCK - 1) * (2 * (2 * (s + BLOCK) + 1) + 2)) * _U * F
    return c_max + slack, c_min - slack


@njit(cache=True, fastmath=False, nogil=True)
def _row_matrix(V, chans, cols, factor, j_of, l_of, w_off, s, r0, m):
    """:func:`_pair_matrix` of the rows r0 .. r0 + m - 1 of V (B, C, N, b) read in place: row
    (b, g, i) has m_p = factor V[b, chans[p], i, cols[g]]."""
    G, N = cols.size, V.shape[2]
    pos = np.empty(m, np.int64)
    col = np.empty(m, np.int64)
    row = np.empty(m, np.int64)
    for r in range(m):
        x = r0 + r
        pos[r] = x // (G * N)
        col[r] = cols[(x // N) % G]
        row[r] = x % N
    M = np.zeros((s, s, m))
    for p in range(chans.size):
        j, l, c = j_of[p], l_of[p], chans[p]
        for r in range(m):
            x = (factor * V[pos[r], c, row[r], col[r]]) * w_off[p]
            M[j, l, r] = x
            M[l, j, r] = x
    return M


@njit(cache=True, fastmath=False, nogil=True)
def _listed(T, u, step, coef, keep, cross, H, L, fB, hi, lo, started, a, m):
    """One outer pattern of :func:`_split` over the inner patterns t with keep[t] only: the
    extremes of T[t] + v_A(t) . u + f_B folded into hi and lo; returns whether any was."""
    NA = T.shape[0]
    cur = -1
    for r in range(m):
        x = 0.0
        for i in range(a):
            x += u[i, r]
        cross[r] = x
    for t in range(NA):
        if t > 0:
            i = step[t]
            c = coef[t]
            for r in range(m):
                cross[r] += c * u[i, r]
        if not keep[t]:
            continue
        if cur < 0:
            for r in range(m):
                y = T[t, r] + cross[r]
                H[0, r] = y
                L[0, r] = y
            cur = 0
            continue
        new = 1 - cur
        for r in range(m):
            y = T[t, r] + cross[r]
            h = H[cur, r]
            H[new, r] = y if y > h else h
            lw = L[cur, r]
            L[new, r] = y if y < lw else lw
        cur = new
    if cur < 0:
        return started
    for r in range(m):
        if started:
            hi[r] = max(hi[r], H[cur, r] + fB[r])
            lo[r] = min(lo[r], L[cur, r] + fB[r])
        else:
            hi[r] = H[cur, r] + fB[r]
            lo[r] = L[cur, r] + fB[r]
    return True


@njit(cache=True, fastmath=False, nogil=True)
def _split(V, chans, cols, factor, j_of, l_of, w_off, s, a, step, coef, mask, masked,
           c_max, c_min):
    G, N = cols.size, V.shape[2]
    R = V.shape[0] * G * N
    b = s - a
    NA = 1 << (a - 1)
    NB = 1 << b
    vA = np.ones(a)
    vB = np.ones(max(b, 1))
    for r0 in range(0, R, _ROWS):
        r1 = min(R, r0 + _ROWS)
        m = r1 - r0
        M = _row_matrix(V, chans, cols, factor, j_of, l_of, w_off, s, r0, m)
        # the inner signs' own part f_A at each of their patterns, in Gray-code order
        T = np.empty((NA, m))
        g = np.zeros((a, m))
        f = np.zeros(m)
        for i in range(a):
            for k in range(a):
                if k != i:
                    for r in range(m):
                        g[i, r] += M[i, k, r]
            for k in range(i + 1, a):
                for r in range(m):
                    f[r] += M[i, k, r]
        for r in range(m):
            T[0, r] = f[r]
        for i in range(a):
            vA[i] = 1.0
        for t in range(1, NA):
            _flip(f, g, M, vA, step[t], a, m)
            for r in range(m):
                T[t, r] = f[r]
        hi = np.empty(m)
        lo = np.empty(m)
        H = np.empty((2, m))                    # the inner extremes, written alternately
        L = np.empty((2, m))                    # (a select, not a masked store: vectorized)
        u = np.empty((a, m))
        fB = np.empty(m)
        cross = np.empty(m)
        last = (NA - 1) & 1
        started = r0 < 0                        # False, typed bool: a literal False
                                                # would compile _listed a second time
        for k in range(b):                      # the outer signs from +1 (the mask's start)
            vB[k] = 1.0
        for tb in range(NB):
            if tb > 0:                          # the outer signs in Gray-code order
                k = 0
                while not (tb >> k) & 1:
                    k += 1
                vB[k] = -vB[k]
            # the outer part f_B and the coupling u = M_AB v_B, afresh
            for r in range(m):
                fB[r] = 0.0
            for k in range(b):
                for k2 in range(k + 1, b):
                    x = vB[k] * vB[k2]
                    for r in range(m):
                        fB[r] += M[a + k, a + k2, r] * x
            for i in range(a):
                for r in range(m):
                    u[i, r] = 0.0
                for k in range(b):
                    x = vB[k]
                    for r in range(m):
                        u[i, r] += M[i, a + k, r] * x
            if masked:                          # the listed vertices only
                started = _listed(T, u, step, coef, mask[tb], cross, H, L, fB, hi, lo,
                                  started, a, m)
                continue
            for r in range(m):
                x = 0.0
                for i in range(a):
                    x += u[i, r]
                cross[r] = x
                y = T[0, r] + x
                H[0, r] = y
                L[0, r] = y
            for t in range(1, NA):              # one inner sign flipped: f_A from the table
                i = step[t]
                c = coef[t]
                new = t & 1
                old = 1 - new
                for r in range(m):
                    x = cross[r] + c * u[i, r]
                    cross[r] = x
                    y = T[t, r] + x
                    h = H[old, r]
                    H[new, r] = y if y > h else h
                    lw = L[old, r]
                    L[new, r] = y if y < lw else lw
            if tb == 0:
                for r in range(m):
                    hi[r] = H[last, r] + fB[r]
                    lo[r] = L[last, r] + fB[r]
            else:
                for r in range(m):
                    hi[r] = max(hi[r], H[last, r] + fB[r])
                    lo[r] = min(lo[r], L[last, r] + fB[r])
        for r in range(m):
            c_max[r0 + r] = hi[r]
            c_min[r0 + r] = lo[r]


def found_extremes(mid: npt.NDArray[np.float64], j: npt.NDArray[np.int64],
                   l: npt.NDArray[np.int64], w_off: npt.NDArray[np.float64], s: int,
                   channels: npt.NDArray[np.int64] | None = None,
                   columns: npt.NDArray[np.int64] | None = None,
                   factor: float = 1.0, vertices: npt.NDArray[np.float64] | None = None
                   ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The largest and the smallest f(v) over the vertices v in {-1, 1}^s, as computed.

    Parameters
    ----------
    mid, j, l, w_off, s
        As :func:`vertex_extremes` takes them: per row the coefficients m_p of the pairs
        (j_p, l_p), shape (R, P), P = s (s - 1) / 2, their weights w_p >= 0 and the number of
        signs s >= 1. With ``channels``, mid is instead an array (B, C, N, b) read in place.
    channels : ndarray of int, shape (P,), optional
        The pairs' channels: row (b, g, i) (R = B g N rows in that order) has m_p =
        factor mid[b, channels[p], i, columns[g]].
    columns : ndarray of int, shape (g,), optional
        With ``channels``: the columns read (default all b).
    factor : float, optional
        With ``channels``: the factor of the coefficients (default 1).
    vertices : ndarray, shape (K, s), optional
        Signs +-1: the extremes over these vertices only (v and -v alike), not all.

    Returns
    -------
    top, bottom : ndarray, shape (R,)
        max_v f(v) and min_v f(v), f(v) = sum_p m_p w_p v_j v_l over the 2^(s - 1) vertices
        with v_0 = 1 (v and -v give the same value), up to round-off (not bounded: for sampled
        peaks, which are found, not proved).

    Raises
    ------
    ValueError
        If the shapes do not agree or s < 1.

    Notes
    -----
    Meet in the middle: with the inner signs A = v_0 .. v_{a-1} (a = min(s, :data:`INNER`))
    and the outer ones B, f(v) = f_A(v_A) + f_B(v_B) + v_A . u, u = M_AB v_B. The values
    f_A of the 2^(a - 1) inner patterns are tabulated once per row (Gray-code order, as in
    :func:`vertex_extremes`), and for each of the 2^(s - a) outer patterns f_B and u are
    computed afresh, then the inner patterns are visited in the table's order, each changing
    v_A . u by one term: about 4 operations per vertex and row, where :func:`vertex_extremes`
    takes s + 3. The round-off of v_A . u accumulates over at most 2^(a - 1) updates.
    """
    V: np.ndarray
    chans: np.ndarray
    cols: np.ndarray
    if channels is None:
        mid, j, l, w_off = _checked(mid, j, l, w_off, s, "found_extremes")
        V = mid.reshape(mid.shape[0], mid.shape[1], 1, 1)
        chans, cols = np.arange(mid.shape[1]), np.zeros(1, np.int64)
    else:
        V = np.ascontiguousarray(mid, dtype=float)
        chans = np.asarray(channels, np.int64)
        cols = np.arange(V.shape[3]) if columns is None else np.asarray(columns, np.int64)
        _, j, l, w_off = _checked(np.empty((0, chans.size)), j, l, w_off, s, "found_extremes")
    R, P = V.shape[0] * cols.size * V.shape[2], chans.size
    c_max, c_min = np.zeros(R), np.zeros(R)
    if P and R:
        a = min(s, INNER)
        t = range(1, 1 << (a - 1))
        step = np.zeros(1 << (a - 1), np.int64)     # the sign flipped at step t: 1 + its lowest bit
        step[1:] = [(x & -x).bit_length() for x in t]
        coef = np.zeros(1 << (a - 1))
        v = np.ones(a)
        for x in t:                                 # -2 v_i, v_i before the flip
            coef[x] = -2.0 * v[step[x]]
            v[step[x]] = -v[step[x]]
        b = s - a
        mask = np.ones((1 << b, 1 << (a - 1)), np.uint8)
        if vertices is not None:        # each listed vertex, v_0 = +1, as (outer, inner) steps
            listed = np.asarray(vertices, float).reshape(-1, s)
            listed = listed * np.where(listed[:, :1] < 0, -1.0, 1.0)
            mask[:] = 0
            mask[_gray_step(listed[:, a:] < 0), _gray_step(listed[:, 1:a] < 0)] = 1
        _split(V, chans, cols, float(factor), j, l, w_off, s, a, step, coef, mask,
               vertices is not None, c_max, c_min)
    return c_max, c_min


def _gray_step(bits):
    """The step t of the reflected Gray code whose pattern has these bits set (K, k) (bit i:
    the part's sign i flipped), the inverse of g = t ^ (t >> 1)."""
    g = (bits.astype(np.int64) << np.arange(bits.shape[1], dtype=np.int64)).sum(axis=1)
    t = g.copy()
    for shift in range(1, max(bits.shape[1], 1)):
        t ^= g >> shift
    return t
