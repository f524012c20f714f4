"""Compiled chunk updates of the ranking's sums and peaks and of the parts' peak contributions.

:class:`gd_analyze.core.selection.ranking.RankingAccumulator` and
:class:`gd_analyze.core.selection.budget.PartPeaks` take the G-D terms of a trajectory chunk by
chunk. Written with numpy, each chunk went through a dozen temporaries of shape (N, M): the
gathered elements, their absolute values, the sums of parts. These kernels make one pass over
the chunk's rows instead, with the same arithmetic in the same order, so the results are the
numpy formulation's bit for bit:

- a column sum over the chunk is the rows' values added in row order to 0 (as numpy reduces
  axis 0 of a C-ordered (N, M) array, M >= 2), then added to the running sum;
- a peak is a maximum, exact whatever the order; a NaN propagates as in ``np.maximum``, except
  in :func:`part_peaks_kernel`, whose running peaks ignore a chunk whose peak is NaN, as the
  built-in ``max(peak, chunk_peak)`` of the numpy formulation did;
- ``np.clip(x, 0, None)`` is ``np.maximum(x, 0.0)``: x where ``x >= 0`` or x is NaN, else 0.

Chunks shorter than :data:`gd_analyze.core.dynamics.dalembert.COMPILED_MIN_SETPOINTS` run the
numpy formulation instead (``engine="auto"`` of the two ``update`` methods), so that a short
trajectory never imports numba; this module is imported only by the compiled engine.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["ranking_kernel", "part_peaks_kernel"]


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _peak(m, v):  # pragma: no cover - compiled
    """``np.maximum(m, v)`` for a running peak: NaN propagates."""
    return v if (v > m or v != v) else m


@njit(cache=True, fastmath=False, nogil=True)
def ranking_kernel(D_tran, D_rot, h_tran, h_rot, tau, arm, arm_d, sum_tran, sum_rot,
                   peak_tran, peak_rot, peak_total, scale_D, peak_tau):  # pragma: no cover
    """Add a chunk of set points to the ranking's running sums and peaks, in place.

    Parameters
    ----------
    D_tran, D_rot, h_tran, h_rot, tau : ndarray
        The chunk's terms and torques, as
        :meth:`gd_analyze.core.selection.ranking.RankingAccumulator.update` takes them.
    arm : ndarray, shape (M,)
        The armature on each element (Ia_i on D_ii, 0 elsewhere) [kg m^2].
    arm_d : ndarray, shape (n,)
        The armature Ia [kg m^2] (zeros without drives).
    sum_tran, sum_rot, peak_tran, peak_rot, peak_total, scale_D, peak_tau : ndarray
        The accumulator's running sums of |tran| and |rot + arm| and peaks of |tran|, |rot|,
        |tran + rot + arm|, sqrt(D_ii D_jj) (D_ii with the armature, clipped at 0) and
        |tau_i|, updated.

    Notes
    -----
    The M = n (n + 1) / 2 + n elements are the upper triangle of D row by row, then h
    (:func:`gd_analyze.core.selection.ranking.element_series`).
    """
    N, n = h_tran.shape
    T = n * (n + 1) // 2
    M = T + n
    s_tran = np.zeros(M)
    s_rot = np.zeros(M)
    diag = np.empty(n)
    for k in range(N):
        for i in range(n):
            v = (D_tran[k, i, i] + D_rot[k, i, i]) + arm_d[i]
            diag[i] = v if (v >= 0.0 or v != v) else 0.0
        e = 0
        for i in range(n):
            for j in range(i, n):
                t = D_tran[k, i, j]
                r = D_rot[k, i, j]
                s_tran[e] += abs(t)
                s_rot[e] += abs(r + arm[e])
                peak_tran[e] = _peak(peak_tran[e], abs(t))
                peak_rot[e] = _peak(peak_rot[e], abs(r))
                peak_total[e] = _peak(peak_total[e], abs((t + r) + arm[e]))
                scale_D[e] = _peak(scale_D[e], np.sqrt(diag[i] * diag[j]))
                e += 1
        for i in range(n):
            t = h_tran[k, i]
            r = h_rot[k, i]
            s_tran[e] += abs(t)
            s_rot[e] += abs(r + arm[e])
            peak_tran[e] = _peak(peak_tran[e], abs(t))
            peak_rot[e] = _peak(peak_rot[e], abs(r))
            peak_total[e] = _peak(peak_total[e], abs((t + r) + arm[e]))
            peak_tau[i] = _peak(peak_tau[i], abs(tau[k, i]))
            e += 1
    for e in range(M):
        sum_tran[e] += s_tran[e]
        sum_rot[e] += s_rot[e]


@njit(cache=True, fastmath=False, nogil=True)
def part_peaks_kernel(D_tran, D_rot, h_tran, h_rot, qdd, tau, rot, elem_i, elem_j, peaks,
                      tau_peak):  # pragma: no cover - compiled
    """Add a chunk of set points to the parts' running peak contributions, in place.

    Parameters
    ----------
    D_tran, D_rot, h_tran, h_rot, qdd, tau : ndarray
        The chunk, as :meth:`gd_analyze.core.selection.budget.PartPeaks.update` takes it.
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
