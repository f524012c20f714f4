"""Trigonometric polynomials in the joint angles: the algebra behind the explicit model.

A trigonometric polynomial in theta = (theta_1, ..., theta_n) is held in its canonical Fourier
form::

    f(theta) = sum_r  C_r * cos(k_r . theta)   or   C_r * sin(k_r . theta)

with integer harmonic vectors k_r whose first nonzero entry is positive. The form is unique, so
equal functions have equal representations: products of sines and cosines of the DH angles
collapse to sums of harmonics, and the compound angles of parallel axes (theta_2 + theta_3 on
the PUMA 560) appear by themselves. Derivatives are exact and cheap,
d cos(k . theta) / d theta_m = -k_m sin(k . theta).

Prismatic joints: a joint variable that is a length d_m (marked in ``lin``) enters the
kinematics polynomially, so its column of a row holds the power p_m >= 0 of d_m instead of a
harmonic: a row is C_r * prod_{m in lin} d_m^p_m * cos or sin(k_r . theta), the dot product
over the revolute columns only. The form stays unique (canonical sign over the revolute
columns; powers add in products; d/d d_m lowers p_m).
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["TrigPoly", "evaluate_rows"]


def evaluate_rows(K: np.ndarray, S: np.ndarray, theta: np.ndarray,
                  lin: ArrayLike | None = None) -> np.ndarray:
    """cos or sin(k_r . theta) times the powers of the polynomial columns, per row.

    Parameters
    ----------
    K : ndarray of int, shape (M, n)
        Harmonics (revolute columns) and powers (polynomial columns).
    S : ndarray of bool, shape (M,)
        sin (True) or cos (False).
    theta : ndarray, shape (N, n)
        Joint variables [rad; m in the polynomial columns].
    lin : ndarray of bool, shape (n,), optional
        The polynomial (prismatic) columns.

    Returns
    -------
    ndarray, shape (N, M)
    """
    if lin is None or not np.any(lin):
        ang = theta @ K.T
        return np.where(S, np.sin(ang), np.cos(ang))
    lin = np.asarray(lin, bool)
    rev = ~lin
    ang = theta[:, rev] @ K[:, rev].T
    out = np.where(S, np.sin(ang), np.cos(ang))
    for m in np.flatnonzero(lin):
        p = K[:, m]
        if p.any():
            out = out * theta[:, m:m + 1] ** p
    return out

#: Coefficients below this fraction of a result's largest one are rounding residue, dropped.
CLEAN = 1e-14


def _unique_rows(key: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(key, axis=0, return_inverse=True)`` of an integer array (m, k): the distinct
    rows in lexicographic order and each row's index among them, shape (m,); the same arrays,
    from one ``np.lexsort`` of the columns (a few times faster on the small arrays of a
    polynomial than the structured view that ``np.unique`` sorts)."""
    order = np.lexsort(key.T[::-1])
    ks = key[order]
    start = np.empty(ks.shape[0], bool)
    start[:1] = True
    np.any(ks[1:] != ks[:-1], axis=1, out=start[1:])
    inv = np.empty(key.shape[0], np.int64)
    inv[order] = np.cumsum(start) - 1
    return ks[start], inv


class TrigPoly:
    """A trigonometric polynomial in n angles, in canonical Fourier form.

    Parameters
    ----------
    K : array_like of int, shape (M, n)
        Harmonic vectors k_r.
    S : array_like of bool, shape (M,)
        True for sin(k_r . theta), False for cos(k_r . theta).
    C : array_like of float, shape (M,)
        Coefficients.
    canonical : bool, optional
        The rows are already canonical and unique.
    lin : array_like of bool, shape (n,), optional
        Polynomial (prismatic) columns: K holds the power of that variable (default: none).

    Examples
    --------
    >>> p = TrigPoly.cos(2, 0) * TrigPoly.cos(2, 0)      # cos^2 = 1/2 + cos(2 theta)/2
    >>> sorted((tuple(int(v) for v in k), bool(s), float(c)) for k, s, c in p.rows())
    [((0, 0), False, 0.5), ((2, 0), False, 0.5)]
    >>> lin = [False, True]                               # theta_1 and a length d_2
    >>> d = TrigPoly.var(2, 1, lin)
    >>> r = (d * TrigPoly.cos(2, 0, lin)) * d             # d_2^2 cos(theta_1)
    >>> [(tuple(int(v) for v in k), bool(s), float(c)) for k, s, c in r.diff(1).rows()]
    [((1, 1), False, 2.0)]
    """

    __slots__ = ("K", "S", "C", "n", "lin")

    def __init__(self, K: ArrayLike, S: ArrayLike, C: ArrayLike, canonical: bool = False,
                 lin: ArrayLike | None = None) -> None:
        K = np.asarray(K, dtype=np.int64).reshape(-1, np.shape(K)[-1] if np.ndim(K) == 2 else 0)
        self.n = K.shape[1]
        self.lin = np.zeros(self.n, bool) if lin is None else np.asarray(lin, bool)
        self.K, self.S, self.C = K, np.asarray(S, bool).reshape(-1), \
            np.asarray(C, float).reshape(-1)
        if not canonical:
            self._canonicalise()

    # -- construction -------------------------------------------------------------------
    @classmethod
    def zero(cls, n: int, lin: ArrayLike | None = None) -> TrigPoly:
        """The zero polynomial in n variables (``lin``: the polynomial columns)."""
        return cls(np.zeros((0, n), np.int64), np.zeros(0, bool), np.zeros(0), canonical=True,
                   lin=lin)

    @classmethod
    def const(cls, n: int, value: float, lin: ArrayLike | None = None) -> TrigPoly:
        """The constant ``value``."""
        if value == 0:
            return cls.zero(n, lin)
        return cls(np.zeros((1, n), np.int64), [False], [float(value)], canonical=True,
                   lin=lin)

    @classmethod
    def cos(cls, n: int, i: int, lin: ArrayLike | None = None) -> TrigPoly:
        """cos(theta_i), i 0-based (a revolute column)."""
        K = np.zeros((1, n), np.int64)
        K[0, i] = 1
        return cls(K, [False], [1.0], canonical=True, lin=lin)

    @classmethod
    def sin(cls, n: int, i: int, lin: ArrayLike | None = None) -> TrigPoly:
        """sin(theta_i), i 0-based (a revolute column)."""
        K = np.zeros((1, n), np.int64)
        K[0, i] = 1
        return cls(K, [True], [1.0], canonical=True, lin=lin)

    @classmethod
    def var(cls, n: int, i: int, lin: ArrayLike) -> TrigPoly:
        """The length d_i itself, i 0-based (a polynomial column of ``lin``)."""
        if not np.asarray(lin, bool)[i]:
            raise ValueError(f"column {i} is not polynomial")
        K = np.zeros((1, n), np.int64)
        K[0, i] = 1
        return cls(K, [False], [1.0], canonical=True, lin=lin)

    # -- canonical form -----------------------------------------------------------------
    def _canonicalise(self):
        K, S, C = self.K, self.S, self.C
        if K.shape[0]:
            nz = (K != 0) & ~self.lin
            first = np.where(nz.any(axis=1), nz.argmax(axis=1), 0)
            neg = (K[np.arange(K.shape[0]), first] < 0) & nz.any(axis=1)
            K = np.where(neg[:, None] & ~self.lin, -K, K)     # powers keep their sign
            C = np.where(neg & S, -C, C)
            zero = ~nz.any(axis=1)
            keep = ~(zero & S)
            K, S, C = K[keep], S[keep], C[keep]
            key = np.concatenate([S[:, None].astype(np.int64), K], axis=1)
            uniq, inv = _unique_rows(key)
            C = np.bincount(inv, weights=C, minlength=uniq.shape[0])
            S, K = uniq[:, 0].astype(bool), uniq[:, 1:]
            big = np.abs(C).max() if C.size else 0.0
            keep = np.abs(C) > CLEAN * big
            K, S, C = K[keep], S[keep], C[keep]
        self.K, self.S, self.C = K, S, C

    # -- arithmetic ---------------------------------------------------------------------
    def __add__(self, other):
        if not isinstance(other, TrigPoly):
            other = TrigPoly.const(self.n, other, self.lin)
        return TrigPoly(np.concatenate([self.K, other.K]), np.concatenate([self.S, other.S]),
                        np.concatenate([self.C, other.C]), lin=self.lin | other.lin)

    __radd__ = __add__

    def __neg__(self):
        return TrigPoly(self.K, self.S, -self.C, canonical=True, lin=self.lin)

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        if not isinstance(other, TrigPoly):
            other = float(other)
            if other == 0:
                return TrigPoly.zero(self.n, self.lin)
            return TrigPoly(self.K, self.S, self.C * other, canonical=True, lin=self.lin)
        lin = self.lin | other.lin
        if not self.C.size or not other.C.size:
            return TrigPoly.zero(self.n, lin)
        K1, K2 = self.K[:, None, :], other.K[None, :, :]
        s1, s2 = self.S[:, None], other.S[None, :]
        c = 0.5 * self.C[:, None] * other.C[None, :]
        # cos a cos b = (cos(a+b) + cos(a-b))/2      sin a sin b = (cos(a-b) - cos(a+b))/2
        # sin a cos b = (sin(a+b) + sin(a-b))/2      cos a sin b = (sin(a+b) - sin(a-b))/2
        kind = s1 ^ s2
        f_plus = np.where(s1 & s2, -1.0, 1.0)
        f_minus = np.where(~s1 & s2, -1.0, 1.0)
        shape = (K1.shape[0], K2.shape[1], self.n)
        Kp = np.broadcast_to(K1 + K2, shape).reshape(-1, self.n)
        # powers of the polynomial columns add in both products
        Km = np.broadcast_to(np.where(lin, K1 + K2, K1 - K2), shape).reshape(-1, self.n)
        kind = np.broadcast_to(kind, c.shape).reshape(-1)
        return TrigPoly(np.concatenate([Kp, Km]), np.concatenate([kind, kind]),
                        np.concatenate([(c * f_plus).reshape(-1), (c * f_minus).reshape(-1)]),
                        lin=lin)

    __rmul__ = __mul__

    def diff(self, m: int) -> TrigPoly:
        """The derivative d/d theta_m (d/d d_m for a polynomial column).

        Parameters
        ----------
        m : int
            The variable, 0-based.

        Returns
        -------
        TrigPoly
        """
        k = self.K[:, m].astype(float)
        if self.lin[m]:
            has = self.K[:, m] > 0
            K = self.K[has].copy()
            K[:, m] -= 1
            return TrigPoly(K, self.S[has], self.C[has] * k[has], lin=self.lin)
        return TrigPoly(self.K, ~self.S, np.where(self.S, k, -k) * self.C, lin=self.lin)

    # -- inspection ---------------------------------------------------------------------
    def rows(self) -> Iterator[tuple]:
        """Iterate over (k, is_sin, coefficient)."""
        return zip(self.K, self.S, self.C)

    def __len__(self):
        return int(self.C.size)

    def constant(self) -> float:
        """The constant term (the coefficient of cos(0) with no power of a length)."""
        zero = ~(self.K != 0).any(axis=1) & ~self.S
        return float(self.C[zero].sum())

    def __call__(self, theta):
        """Evaluate at theta, shape (N, n) [rad; m in the polynomial columns]; shape (N,)."""
        theta = np.atleast_2d(np.asarray(theta, float))
        if not self.C.size:
            return np.zeros(theta.shape[0])
        return evaluate_rows(self.K, self.S, theta, self.lin) @ self.C

    def __repr__(self):
        return f"TrigPoly(n={self.n}, terms={len(self)})"
