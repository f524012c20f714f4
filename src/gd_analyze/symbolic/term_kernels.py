"""Compiled peaks of the explicit model's atoms along a trajectory.

:func:`gd_analyze.symbolic.explicit.term_peaks` reduces the contributions of the explicit
terms (Fu, Gonzalez & Lee 1987, Eqs. (3.4-24) to (3.4-28) in their Fourier form,
:mod:`.trigpoly`) to one peak per (atom, joint). :func:`atom_peaks_kernel` does it without
storing the (N, terms) contributions, a block of set points at a time: the cos and sin of the
joint angles, the distinct harmonics from them by the angle-addition formulas, the velocity
columns [qdd, qd_a qd_b, 1], then per (atom, joint) group the sum of its entries' coefficient
x harmonic x velocity column, abs, max. The tests keep the same arithmetic as array code,
their oracle.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["atom_peaks_kernel"]

#: Set points per block of :func:`atom_peaks_kernel`'s inner loops.
_BLOCK = 64


@njit(cache=True, fastmath=False, nogil=True)
def atom_peaks_kernel(theta: np.ndarray, qd: np.ndarray, qdd: np.ndarray, Ku: np.ndarray,
                      Su: np.ndarray, lin: np.ndarray, hidx: np.ndarray, coef: np.ndarray,
                      e_term: np.ndarray, e_vcol: np.ndarray, starts: np.ndarray,
                      group_peak: np.ndarray) -> None:  # pragma: no cover - compiled
    """Running peak of every (atom, joint) group's summed contribution, in place.

    Parameters
    ----------
    theta : ndarray, shape (N, n)
        Joint variables q + offset [rad; m in the prismatic columns].
    qd, qdd : ndarray, shape (N, n)
        Joint velocities and accelerations [rad/s, rad/s^2; m/s, m/s^2].
    Ku : ndarray of int, shape (H, n)
        The distinct harmonics (revolute columns) and powers (prismatic columns).
    Su : ndarray of bool, shape (H,)
        sin (True) or cos (False) of each.
    lin : ndarray of bool, shape (n,)
        The prismatic (polynomial) columns.
    hidx : ndarray of int, shape (M,)
        The harmonic of every merged term.
    coef : ndarray, shape (M,)
        The coefficient of every merged term.
    e_term, e_vcol : ndarray of int, shape (E,)
        Per entry its term and its velocity column in [qdd (n), qd_a qd_b (n n), 1], sorted
        by group.
    starts : ndarray of int, shape (G,)
        First entry of every group.
    group_peak : ndarray, shape (G,)
        Running peaks |sum of the group's entries| [N m or N], updated by maximum.

    Raises
    ------
    None: compiled without bounds checks; the arrays must be consistent, as
    :func:`.explicit.term_peaks` builds them.

    Notes
    -----
    tau = D qdd + h + c, Eq. (3.4-24) of Fu, Gonzalez & Lee (1987), with every element a sum
    of coefficient x cos/sin(k . theta) (:mod:`.trigpoly`); cos and sin of k . theta by the
    angle-addition formulas, as the emitted programs form them (:mod:`.codegen`).

    Examples
    --------
    One arm joint, one term 2 cos(theta_1) of c_1 (velocity columns [qdd_1, qd_1 qd_1, 1]:
    the constant column 2); its peak over theta_1 = 0 and pi is 2:

    >>> import numpy as np
    >>> peak = np.zeros(1)
    >>> atom_peaks_kernel(np.array([[0.0], [np.pi]]), np.zeros((2, 1)), np.zeros((2, 1)),
    ...                   np.array([[1]]), np.array([False]), np.array([False]),
    ...                   np.array([0]), np.array([2.0]), np.array([0]), np.array([2]),
    ...                   np.array([0]), peak)
    >>> peak
    array([2.])
    """
    N, n = theta.shape
    H = Ku.shape[0]
    E = e_term.shape[0]
    G = starts.shape[0]
    B = _BLOCK
    V = n + n * n + 1
    e_harm = np.empty(E, np.int64)            # per entry: its term's harmonic and coefficient
    e_coef = np.empty(E)
    for e in range(E):
        e_harm[e] = hidx[e_term[e]]
        e_coef[e] = coef[e_term[e]]
    # a block of set points at a time: the innermost loops run over the block (SIMD)
    trig = np.empty((H, B))
    vel = np.empty((V, B))
    acc = np.empty(B)
    cj = np.empty((n, B))
    sj = np.empty((n, B))
    cs = np.empty(B)
    sn = np.empty(B)
    for k0 in range(0, N, B):
        nb = min(B, N - k0)
        # cos and sin of k . theta from the joints' by the angle-addition formulas
        for m in range(n):
            for b in range(nb):
                cj[m, b] = np.cos(theta[k0 + b, m])
                sj[m, b] = np.sin(theta[k0 + b, m])
        for h in range(H):
            for b in range(nb):
                cs[b] = 1.0
                sn[b] = 0.0
            for m in range(n):
                km = Ku[h, m]
                if lin[m]:                      # a power of a prismatic joint's length
                    for _ in range(km):
                        for b in range(nb):
                            cs[b] *= theta[k0 + b, m]
                            sn[b] *= theta[k0 + b, m]
                    continue
                sg = 1.0 if km > 0 else -1.0
                for _ in range(abs(km)):
                    for b in range(nb):
                        c, t = cj[m, b], sg * sj[m, b]
                        cs[b], sn[b] = cs[b] * c - sn[b] * t, sn[b] * c + cs[b] * t
            if Su[h]:
                for b in range(nb):
                    trig[h, b] = sn[b]
            else:
                for b in range(nb):
                    trig[h, b] = cs[b]
        for a in range(n):
            for b in range(nb):
                vel[a, b] = qdd[k0 + b, a]
            for c in range(n):
                for b in range(nb):
                    vel[n + a * n + c, b] = qd[k0 + b, a] * qd[k0 + b, c]
        for b in range(nb):
            vel[V - 1, b] = 1.0
        for g in range(G):
            end = starts[g + 1] if g + 1 < G else E
            for b in range(nb):
                acc[b] = 0.0
            for e in range(starts[g], end):
                th, cf, vc = e_harm[e], e_coef[e], e_vcol[e]
                for b in range(nb):
                    acc[b] += (trig[th, b] * cf) * vel[vc, b]
            peak = group_peak[g]
            for b in range(nb):
                v = abs(acc[b])
                if v > peak:
                    peak = v
            group_peak[g] = peak
