"""Compiled chunk updates of the ranking's statistics and of the parts' peak contributions.

:class:`gd_analyze.ranking.ranking.RankingAccumulator` and
:class:`gd_analyze.simplify.budget.PartPeaks` take the G-D terms of a trajectory chunk by
chunk. Written with numpy, each chunk went through a dozen temporaries of shape (N, M): the
gathered elements, their absolute values, the sums of parts. These kernels make one pass over
the chunk's rows instead, with the same arithmetic in the same order, so the results are the
numpy formulation's bit for bit (the tests keep it as their oracle):

- a column sum over the chunk is the rows' values added in row order to 0 (as numpy reduces
  axis 0 of a C-ordered (N, M) array, M >= 2), then added to the running sum;
- a peak is a maximum, exact whatever the order; a NaN propagates as in ``np.maximum``, except
  in :func:`part_peaks_kernel`, whose running peaks ignore a chunk whose peak is NaN, as the
  built-in ``max(peak, chunk_peak)`` of the numpy formulation did;
- ``np.clip(x, 0, None)`` is ``np.maximum(x, 0.0)``: x where ``x >= 0`` or x is NaN, else 0.

This module imports numba; its users import it by their first call only.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .statistics import (
    N_ROWS,
    ROT_ARM_PEAK_ABS,
    ROT_ARM_SUM_ABS,
    ROT_ARM_SUM_SQ,
    ROT_PEAK_ABS,
    SUMS,
    TOTAL_PEAK_ABS,
    TOTAL_SUM_ABS,
    TOTAL_SUM_SQ,
    TRAN_PEAK_ABS,
    TRAN_SUM_ABS,
    TRAN_SUM_SQ,
)

__all__ = ["ranking_kernel", "part_peaks_kernel", "inertia_block_kernel",
           "inertia_screen_kernel"]


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _peak(m, v):  # pragma: no cover - compiled
    """``np.maximum(m, v)`` for a running peak: NaN propagates."""
    return v if (v > m or v != v) else m


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _element(c, e, t, r, a):  # pragma: no cover - compiled
    """One set point of element e (tran t, rot r, armature a) into the chunk's statistics c,
    of shape (M, N_ROWS): its sums and peaks from 0."""
    ra = r + a
    v = (t + r) + a
    at = abs(t)
    ara = abs(ra)
    av = abs(v)
    c[e, TRAN_SUM_ABS] += at
    c[e, TRAN_SUM_SQ] += t * t
    c[e, ROT_ARM_SUM_ABS] += ara
    c[e, ROT_ARM_SUM_SQ] += ra * ra
    c[e, TOTAL_SUM_ABS] += av
    c[e, TOTAL_SUM_SQ] += v * v
    c[e, TRAN_PEAK_ABS] = _peak(c[e, TRAN_PEAK_ABS], at)
    c[e, ROT_ARM_PEAK_ABS] = _peak(c[e, ROT_ARM_PEAK_ABS], ara)
    c[e, TOTAL_PEAK_ABS] = _peak(c[e, TOTAL_PEAK_ABS], av)
    c[e, ROT_PEAK_ABS] = _peak(c[e, ROT_PEAK_ABS], abs(r))


@njit(cache=True, fastmath=False, nogil=True)
def ranking_kernel(D_tran, D_rot, h_tran, h_rot, tau, arm, arm_d, bounds, stats, scale_D,
                   peak_tau):  # pragma: no cover - compiled
    """Add a chunk of set points to the ranking's running statistics, in place, each of its
    segments (consecutive set points of one trajectory) to its own trajectory's.

    Parameters
    ----------
    D_tran, D_rot : ndarray, shape (N, n, n)
        The chunk's inertia matrix parts [kg m^2].
    h_tran, h_rot : ndarray, shape (N, n)
        The chunk's Coriolis and centrifugal parts [N m].
    tau : ndarray, shape (N, n)
        The chunk's joint torques [N m].
    arm : ndarray, shape (M,)
        The armature on each element (Ia_i on D_ii, 0 elsewhere) [kg m^2].
    arm_d : ndarray, shape (n,)
        The armature Ia [kg m^2] (zeros without drives).
    bounds : ndarray of int, shape (S + 1,)
        The segments' bounds in the chunk: segment s is rows bounds[s] .. bounds[s + 1] - 1
        (bounds[0] = 0, bounds[S] = N; one segment for a chunk of one trajectory).
    stats : ndarray, shape (S, len(ROWS), M)
        The running statistics of each segment's trajectory, per element and series, row r
        being entry r of :data:`gd_analyze.ranking.statistics.ROWS`: sums of |x| and peaks of
        |x| in the element's units ([kg m^2] for D, [N m] for h), sums of x^2 in their
        squares; updated.
    scale_D : ndarray, shape (S, n (n + 1) / 2)
        The running peak sqrt(D_ii D_jj) (D_ii with the armature, clipped at 0) [kg m^2],
        updated.
    peak_tau : ndarray, shape (S, n)
        The running peak |tau_i| [N m], updated.

    Notes
    -----
    The M = n (n + 1) / 2 + n elements are the upper triangle of D row by row, then h
    (:func:`gd_analyze.ranking.ranking.element_labels`); the series and statistics are those
    of :mod:`gd_analyze.ranking.statistics`. A segment's statistics are formed apart, element
    by element in one block (faster than updating the running peaks in place): a sum is the
    segment's values added in row order to 0, then added to the running sum (module
    docstring); a peak is the segment's from 0 (|x| >= 0), then the larger of it and the
    running one, NaN propagating as it would row by row. A segment's statistics are thus
    those of a chunk holding it alone.
    """
    n = h_tran.shape[1]
    T = n * (n + 1) // 2
    M = T + n
    c = np.empty((M, N_ROWS))           # a segment's statistics, element by element
    diag = np.empty(n)
    for s in range(bounds.shape[0] - 1):
        c[:, :] = 0.0
        scale = scale_D[s]              # the segment's trajectory's running peaks
        peak = peak_tau[s]
        for k in range(bounds[s], bounds[s + 1]):
            for i in range(n):
                v = (D_tran[k, i, i] + D_rot[k, i, i]) + arm_d[i]
                diag[i] = v if (v >= 0.0 or v != v) else 0.0
            e = 0
            for i in range(n):
                for j in range(i, n):
                    _element(c, e, D_tran[k, i, j], D_rot[k, i, j], arm[e])
                    scale[e] = _peak(scale[e], np.sqrt(diag[i] * diag[j]))
                    e += 1
            for i in range(n):
                _element(c, e, h_tran[k, i], h_rot[k, i], arm[e])
                peak[i] = _peak(peak[i], abs(tau[k, i]))
                e += 1
        for e in range(M):
            for r in range(SUMS):
                stats[s, r, e] += c[e, r]
            for r in range(SUMS, N_ROWS):
                stats[s, r, e] = _peak(stats[s, r, e], c[e, r])


@njit(cache=True, fastmath=False, nogil=True)
def part_peaks_kernel(D_tran, D_rot, h_tran, h_rot, qdd, tau, rot, elem_i, elem_j, peaks,
                      tau_peak):  # pragma: no cover - compiled
    """Add a chunk of set points to the parts' running peak contributions, in place.

    Parameters
    ----------
    D_tran, D_rot, h_tran, h_rot, qdd, tau : ndarray
        The chunk, as :meth:`gd_analyze.simplify.budget.PartPeaks.update` takes it.
    rot : ndarray of bool, shape (P,)
        Whether part r is the rotational one (else translational).
    elem_i, elem_j : ndarray of int, shape (P,)
        Part r's element: D_ij (i <= j), or h_i where ``elem_j[r] < 0``.
    peaks : ndarray, shape (P, n)
        Running peak |contribution| of part r to each joint torque, replaced where the
        chunk's peak exceeds it: D_ij qdd_j to tau_i and, for i != j, D_ij qdd_i to tau_j;
        h_i to tau_i.
    tau_peak : ndarray, shape (n,)
        Running peak |tau_i|, updated (NaN propagates).
    """
    N, n = h_tran.shape
    P = rot.shape[0]
    mi = np.zeros(P)                # the chunk's peak of each part on tau_i
    mj = np.zeros(P)                # ... and on tau_j (D_ij, i != j)
    for k in range(N):
        for r in range(P):
            i = elem_i[r]
            j = elem_j[r]
            if j < 0:
                v = h_rot[k, i] if rot[r] else h_tran[k, i]
                mi[r] = _peak(mi[r], abs(v))
            else:
                d = D_rot[k, i, j] if rot[r] else D_tran[k, i, j]
                mi[r] = _peak(mi[r], abs(d * qdd[k, j]))
                if i != j:
                    mj[r] = _peak(mj[r], abs(d * qdd[k, i]))
        for i in range(n):
            tau_peak[i] = _peak(tau_peak[i], abs(tau[k, i]))
    if N == 0:
        return
    for r in range(P):
        i = elem_i[r]
        j = elem_j[r]
        if mi[r] > peaks[r, i]:
            peaks[r, i] = mi[r]
        if j >= 0 and i != j and mj[r] > peaks[r, j]:
            peaks[r, j] = mj[r]


@njit(cache=True, fastmath=False, nogil=True)
def inertia_block_kernel(D, S, pos, proved, norm):  # pragma: no cover - compiled
    """The D_s check's pass over a block of matrices
    (:func:`gd_analyze.certify.positive_definite.check_inertia`), in place.

    Parameters
    ----------
    D : ndarray, shape (M, n, n)
        D_s at M positions [kg m^2; kg].
    S : ndarray, shape (M, n, n)
        Receives 0.5 (D + D^T), as numpy forms it.
    pos, proved : ndarray of bool, shape (M,)
        Receive whether every diagonal entry is positive, and whether the Gershgorin discs of
        S scaled to a unit diagonal all lie right of 0 (the numpy formulation's sums, in row
        order).
    norm : ndarray, shape (M,)
        Receives ||S||_F.
    """
    M, n = D.shape[0], D.shape[1]
    s = np.empty(n)
    for p in range(M):
        total = 0.0
        for i in range(n):
            for j in range(n):
                v = 0.5 * (D[p, i, j] + D[p, j, i])
                S[p, i, j] = v
                total += v * v
        norm[p] = np.sqrt(total)
        ok = True
        for i in range(n):
            d = S[p, i, i]
            ok = ok and d > 0
            s[i] = 1.0 / np.sqrt(d if d > 0 else 1.0)
        pos[p] = ok
        disc = ok
        for i in range(n):
            row = 0.0
            for j in range(n):
                row += abs(S[p, i, j] * s[i] * s[j])
            disc = disc and (row - abs(S[p, i, i] * s[i] * s[i])) < 1.0
        proved[p] = disc


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _definite_shifted(S, p, shift, A):  # pragma: no cover - compiled
    """Whether S[p] - shift I is positive definite: every pivot of its L D L^T positive."""
    n = S.shape[1]
    for i in range(n):
        for j in range(n):
            A[i, j] = S[p, i, j] - (shift if i == j else 0.0)
    for k in range(n):
        d = A[k, k]
        if not d > 0:
            return False
        for i in range(k + 1, n):
            c = A[i, k] / d
            for j in range(k + 1, n):
                A[i, j] -= c * A[k, j]
    return True


@njit(cache=True, fastmath=False, nogil=True)
def inertia_screen_kernel(S, norm, hi_a, step, best_lo, best_ratio, round_off,
                          maybe):  # pragma: no cover - compiled
    """Which positions of a block may hold the D_s check's minima, in place
    (:func:`gd_analyze.certify.positive_definite.check_inertia`'s shifted definiteness
    test, as its array formulation makes it).

    Parameters
    ----------
    S : ndarray, shape (M, n, n)
        Symmetric matrices [kg m^2; kg].
    norm : ndarray, shape (M,)
        ||S||_F.
    hi_a : ndarray, shape (ceil(M / step),)
        max |lambda| of each anchor (every step-th matrix).
    step : int
    best_lo, best_ratio, round_off : float
        The smallest lambda_min and lambda_min / max |lambda| found, the relative margin.
    maybe : ndarray of bool, shape (M,)
        Receives True where the eigenvalues must be computed (never at an anchor).
    """
    M, n = S.shape[0], S.shape[1]
    A = np.empty((n, n))
    r = best_ratio + round_off
    for p in range(M):
        a = (p // step) * step
        if p == a:
            maybe[p] = False
            continue
        delta = 0.0
        for i in range(n):
            for j in range(n):
                e = S[p, i, j] - S[a, i, j]
                delta += e * e
        margin = round_off * norm[p]
        if r > 0:
            bound = min(norm[p], hi_a[p // step] + np.sqrt(delta))
        else:
            bound = 0.0
            for i in range(n):
                bound = max(bound, abs(S[p, i, i]))
        maybe[p] = not (_definite_shifted(S, p, best_lo + margin, A)
                        and _definite_shifted(S, p, r * bound + margin, A))
