"""Peaks of the explicit model's atoms along a trajectory, as array code (no numba).

The numpy engine of :func:`gd_analyze.core.symbolic.explicit.term_peaks`: the arithmetic of
:func:`.term_kernels.atom_peaks_kernel` (the same arguments, the same values to round-off),
vectorised over a block of set points at a time so that its temporaries stay bounded: the cos
and sin of the joint angles, the distinct harmonics from them by the angle-addition formulas,
the velocity columns [qdd, qd_a qd_b, 1], then per (atom, joint) group the sum of its entries'
coefficient x harmonic x velocity column, abs, max. Short trajectories run it, so that they
never import numba nor load compiled code.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..dynamics.dalembert import compiled_engine

__all__ = ["atom_peaks_arrays", "peaks_kernel", "BLOCK_ELEMENTS"]

#: Floats per block of the largest temporary, (entries, set points): a block holds about
#: BLOCK_ELEMENTS / E set points (E entries), so memory stays O(E + BLOCK_ELEMENTS).
BLOCK_ELEMENTS = 1 << 20


def _harmonics(theta, Ku, Su, lin):
    """cos/sin(K_h . theta) of every harmonic h, (H, B), by the angle-addition formulas."""
    B, n = theta.shape
    H = Ku.shape[0]
    cs = np.ones((H, B))
    sn = np.zeros((H, B))
    for m in range(n):
        km = Ku[:, m]
        if lin[m]:                                  # a power of a prismatic joint's length
            x = theta[:, m]
            for step in range(int(km.max(initial=0))):
                rows = km > step
                cs[rows] *= x
                sn[rows] *= x
            continue
        c, s = np.cos(theta[:, m]), np.sin(theta[:, m])
        sg = np.where(km > 0, 1.0, -1.0)[:, None]
        reps = np.abs(km)
        for step in range(int(reps.max(initial=0))):
            rows = reps > step
            t = sg[rows] * s
            a, b = cs[rows], sn[rows]
            cs[rows], sn[rows] = a * c - b * t, b * c + a * t
    return np.where(Su[:, None], sn, cs)


def atom_peaks_arrays(theta: np.ndarray, qd: np.ndarray, qdd: np.ndarray, Ku: np.ndarray,
                      Su: np.ndarray, lin: np.ndarray, hidx: np.ndarray, coef: np.ndarray,
                      e_term: np.ndarray, e_vcol: np.ndarray, starts: np.ndarray,
                      group_peak: np.ndarray) -> None:
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
        First entry of every group (increasing, the first 0).
    group_peak : ndarray, shape (G,)
        Running peaks |sum of the group's entries| [N m or N], updated by maximum; a NaN sum
        is never kept (as in the kernel).

    Raises
    ------
    IndexError
        If the index arrays point outside the others (they must be consistent, as
        :func:`.explicit.term_peaks` builds them).

    Notes
    -----
    tau = D qdd + h + c, Eq. (3.4-24) of Fu, Gonzalez & Lee (1987), with every element a sum
    of coefficient x cos/sin(k . theta) (:mod:`.trigpoly`); cos and sin of k . theta by the
    angle-addition formulas, as :func:`.term_kernels.atom_peaks_kernel` and the emitted
    programs form them (:mod:`.codegen`). A group's entries are summed in their order.

    Examples
    --------
    One arm joint, one term 2 cos(theta_1) of c_1 (velocity columns [qdd_1, qd_1 qd_1, 1]:
    the constant column 2); its peak over theta_1 = 0 and pi is 2:

    >>> peak = np.zeros(1)
    >>> atom_peaks_arrays(np.array([[0.0], [np.pi]]), np.zeros((2, 1)), np.zeros((2, 1)),
    ...                   np.array([[1]]), np.array([False]), np.array([False]),
    ...                   np.array([0]), np.array([2.0]), np.array([0]), np.array([2]),
    ...                   np.array([0]), peak)
    >>> peak
    array([2.])
    """
    N, n = theta.shape
    E = e_term.shape[0]
    if N == 0 or E == 0:
        return
    e_harm = hidx[e_term]                       # per entry: its term's harmonic, coefficient
    e_coef = coef[e_term][:, None]
    block = max(1, BLOCK_ELEMENTS // max(E, Ku.shape[0], n * n + n + 1))
    for k0 in range(0, N, block):
        sl = slice(k0, k0 + block)
        th, v1, v2 = theta[sl], qd[sl], qdd[sl]
        B = th.shape[0]
        trig = _harmonics(th, Ku, Su, lin)                              # (H, B)
        vel = np.concatenate([v2.T, (v1[:, :, None] * v1[:, None, :]).reshape(B, n * n).T,
                              np.ones((1, B))])                         # (V, B)
        terms = (trig[e_harm] * e_coef) * vel[e_vcol]                   # (E, B)
        acc = np.add.reduceat(terms, starts, axis=0)                    # (G, B)
        # fmax: a NaN sum is skipped, as the kernel's ``if v > peak`` skips it
        np.fmax(group_peak, np.fmax.reduce(np.abs(acc), axis=1), out=group_peak)


def peaks_kernel(engine: str, count: int) -> Callable[..., Any]:
    """The atom-peaks kernel of an engine, for a trajectory of ``count`` set points.

    Parameters
    ----------
    engine : {"auto", "numpy", "compiled"}
        ``"auto"``: compiled from
        :data:`gd_analyze.core.dynamics.dalembert.COMPILED_MIN_SETPOINTS` set points on
        (:func:`gd_analyze.core.dynamics.dalembert.compiled_engine`), else array code.
    count : int
        Set points of the trajectory.

    Returns
    -------
    callable
        :func:`.term_kernels.atom_peaks_kernel` (numba, imported only then) or
        :func:`atom_peaks_arrays`; the same arguments, the same values to round-off.

    Raises
    ------
    ValueError
        If the engine is unknown.

    Examples
    --------
    >>> peaks_kernel("auto", 31) is atom_peaks_arrays
    True
    """
    if not compiled_engine(engine, count):
        return atom_peaks_arrays
    from .term_kernels import atom_peaks_kernel

    return atom_peaks_kernel
