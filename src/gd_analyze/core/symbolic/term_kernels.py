"""Compiled peaks of the explicit model's atoms along a trajectory.

:func:`gd_analyze.core.symbolic.explicit.term_peaks` reduces the contributions of the explicit
terms (Fu, Gonzalez & Lee 1987, Eqs. (3.4-24) to (3.4-28) in their Fourier form,
:mod:`.trigpoly`) to one peak per (atom, joint). :func:`atom_peaks_kernel` does it in one pass
per set point without storing the (N, terms) contributions: the distinct cos or sin of the
harmonics once, the velocity columns [qdd, qd_a qd_b, 1] once, then per (atom, joint) group
the sum of its entries' coefficient x harmonic x velocity column, abs, max.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["atom_peaks_kernel"]


@njit(cache=True, fastmath=False, nogil=True)
def atom_peaks_kernel(theta, qd, qdd, Ku, Su, lin, hidx, coef, e_term, e_vcol, starts,
                      group_peak):  # pragma: no cover - compiled
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
    """
    N, n = theta.shape
    H = Ku.shape[0]
    E = e_term.shape[0]
    G = starts.shape[0]
    trig = np.empty(H)
    e_harm = np.empty(E, np.int64)            # per entry: its term's harmonic and coefficient
    e_coef = np.empty(E)
    for e in range(E):
        e_harm[e] = hidx[e_term[e]]
        e_coef[e] = coef[e_term[e]]
    vel = np.empty(n + n * n + 1)
    for k in range(N):
        for h in range(H):
            ang = 0.0
            for m in range(n):
                if not lin[m]:
                    ang += Ku[h, m] * theta[k, m]
            v = np.sin(ang) if Su[h] else np.cos(ang)
            for m in range(n):
                if lin[m]:
                    for _ in range(Ku[h, m]):
                        v *= theta[k, m]
            trig[h] = v
        for a in range(n):
            vel[a] = qdd[k, a]
            for b in range(n):
                vel[n + a * n + b] = qd[k, a] * qd[k, b]
        vel[n + n * n] = 1.0
        for g in range(G):
            end = starts[g + 1] if g + 1 < G else E
            s = 0.0
            for e in range(starts[g], end):
                s += (trig[e_harm[e]] * e_coef[e]) * vel[e_vcol[e]]
            s = abs(s)
            if s > group_peak[g]:
                group_peak[g] = s
