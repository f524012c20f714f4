"""Ball (midpoint-radius) arithmetic for 3-vectors: enclosures that rotations do not inflate.

A ball vector is a pair ``(c, r)``: centres of shape (..., 3) and Euclidean radii of shape
(...), the set {c + e : |e| <= r}. A rotation preserves the radius, so a chain of rotations by
uncertain joint angles grows the radius additively, where the boxes of :mod:`.intervals` grow
by wrapping (Moore's wrapping effect; Rump, "Fast and parallel interval arithmetic", BIT 39,
1999, for midpoint-radius arithmetic). A rotation about z by an angle in [m - d, m + d] maps a
centre onto an arc, enclosed exactly by the ball of centre cos(d) times the arc's mid point and
radius rho sin(d) (rho: the centre's distance from the axis; d > pi/2: centre on the axis,
radius rho). Every operation adds a radius for floating-point rounding: 32 units of round-off of
the magnitudes it combines, far above the few roundings each performs.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: A batch of balls: (centres, radii), radii >= 0 [the centres' units].
_Ball = tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]

__all__ = ["point", "zeros", "add", "scale", "cross", "matvec", "rot_z", "z_interval",
           "spectral_norm", "ROUNDING"]

#: Unit round-off of a float [1].
ROUNDING = np.finfo(float).eps / 2
_SLACK = 32 * ROUNDING
#: Half-widths above which a rotated centre is enclosed about the axis (radius rho).
ARC_LIMIT = np.pi / 2


def _norm(c):
    """|c| over the last axis (3): it only scales the rounding slack of a radius."""
    x, y, z = c[..., 0], c[..., 1], c[..., 2]
    return np.sqrt(x * x + y * y + z * z)


def _cross(a, b):
    """a x b over the last axis (3), broadcast: the products and differences of
    :func:`numpy.cross`, in its order (the same floats), without its axis handling."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack(np.broadcast_arrays(a1 * b2 - a2 * b1, a2 * b0 - a0 * b2,
                                        a0 * b1 - a1 * b0), axis=-1)


#: ||M||_2 of the point matrices :func:`matvec` has met, by their bytes: a chain's few
#: constant rotations and inertia tensors, met again on every batch of boxes.
_NORMS: dict[bytes, float] = {}


def spectral_norm(M: npt.NDArray[np.float64]) -> float:
    """||M||_2 of a (3, 3) matrix, as :func:`numpy.linalg.norm` (ord 2) gives it, kept by the
    matrix's bytes (at most 4,096 kept).

    Parameters
    ----------
    M : ndarray, shape (3, 3)

    Returns
    -------
    float
        The largest singular value of M [M's unit].

    Raises
    ------
    numpy.linalg.LinAlgError
        If the singular values do not converge (a matrix with NaN or inf).

    Notes
    -----
    The same value as ``numpy.linalg.norm(M, 2)``; a chain's constant rotations and inertia
    tensors are met on every batch of boxes, so each is decomposed once per process.
    """
    key = M.tobytes()
    norm = _NORMS.get(key)
    if norm is None:
        norm = float(np.linalg.norm(M, 2))
        if len(_NORMS) < 4096:
            _NORMS[key] = norm
    return norm


def point(c: npt.ArrayLike) -> _Ball:
    """The ball of radius 0 about c.

    Parameters
    ----------
    c : array_like, shape (..., 3)

    Returns
    -------
    (ndarray, ndarray)
        Centres (..., 3) and radii (...).
    """
    c = np.asarray(c, float)
    return c, np.zeros(c.shape[:-1])


def zeros(shape: tuple[int, ...]) -> _Ball:
    """Balls at the origin of radius 0.

    Parameters
    ----------
    shape : tuple
        The batch shape (...,); the centres get (..., 3).

    Returns
    -------
    (ndarray, ndarray)
    """
    return np.zeros(tuple(shape) + (3,)), np.zeros(tuple(shape))


def add(a: _Ball, b: _Ball) -> _Ball:
    """a + b.

    Parameters
    ----------
    a, b : (ndarray, ndarray)
        Balls of broadcastable shapes.

    Returns
    -------
    (ndarray, ndarray)

    Examples
    --------
    >>> c, r = add(point([1.0, 0, 0]), (np.zeros(3), np.array(0.5)))
    >>> c.tolist(), bool(r >= 0.5)
    ([1.0, 0.0, 0.0], True)
    """
    c = a[0] + b[0]
    return c, a[1] + b[1] + _SLACK * (_norm(a[0]) + _norm(b[0]))


def scale(a: _Ball, s: float) -> _Ball:
    """s a for a point number s.

    Parameters
    ----------
    a : (ndarray, ndarray)
    s : float

    Returns
    -------
    (ndarray, ndarray)
    """
    return a[0] * s, abs(s) * a[1] * (1 + _SLACK) + _SLACK * abs(s) * _norm(a[0])


def cross(a: _Ball, b: _Ball) -> _Ball:
    """a x b: centre ca x cb, radius |ca| rb + ra |cb| + ra rb.

    Parameters
    ----------
    a, b : (ndarray, ndarray)
        Balls of broadcastable shapes.

    Returns
    -------
    (ndarray, ndarray)
    """
    na, nb = _norm(a[0]), _norm(b[0])
    c = _cross(a[0], b[0])
    r = na * b[1] + a[1] * nb + a[1] * b[1]
    return c, np.asarray(r * (1 + _SLACK) + _SLACK * na * nb, float)


def matvec(M: npt.NDArray[np.float64], a: _Ball) -> _Ball:
    """M a for a point matrix M: centre M c, radius ||M||_2 r.

    Parameters
    ----------
    M : ndarray, shape (3, 3)
    a : (ndarray, ndarray)

    Returns
    -------
    (ndarray, ndarray)
    """
    M = np.asarray(M, float)
    norm = spectral_norm(M) * (1 + 1e-12)
    return a[0] @ M.T, norm * a[1] * (1 + _SLACK) + _SLACK * norm * _norm(a[0])


def rot_z(a: _Ball, mid: npt.NDArray[np.float64], half: npt.NDArray[np.float64],
          transpose: bool = False) -> _Ball:
    """Rz(theta) a (or Rz(theta)^T a) for every theta in [mid - half, mid + half].

    Parameters
    ----------
    a : (ndarray, ndarray)
        Balls, centres (B, ..., 3).
    mid, half : ndarray, shape (B,)
        The angles' mid points and half-widths [rad], half >= 0.
    transpose : bool, optional

    Returns
    -------
    (ndarray, ndarray)
        An enclosure of the rotated balls.

    Examples
    --------
    >>> c, r = rot_z(point(np.array([[1.0, 0.0, 2.0]])), np.array([np.pi / 2]), np.array([0.1]))
    >>> bool(abs(c[0, 1] - np.cos(0.1)) < 1e-12 and abs(r[0] - np.sin(0.1)) < 1e-12)
    True
    """
    c, r = a
    extra = (1,) * (c.ndim - 2)
    m = (-mid if transpose else mid).reshape((-1,) + extra)
    d = half.reshape((-1,) + extra)
    small = d <= ARC_LIMIT
    k = np.where(small, np.cos(np.minimum(d, np.pi / 2)), 0.0)
    s = np.where(small, np.sin(np.minimum(d, np.pi / 2)), 1.0)
    cm, sm = np.cos(m), np.sin(m)
    x, y = k * c[..., 0], k * c[..., 1]
    out = np.empty_like(c)
    out[..., 0] = cm * x - sm * y
    out[..., 1] = sm * x + cm * y
    out[..., 2] = c[..., 2]
    rho = np.hypot(c[..., 0], c[..., 1])
    return out, (r + rho * s) * (1 + _SLACK) + (4 * _SLACK + 1e-15) * (rho + _norm(c))


def z_interval(a: _Ball) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The z components of balls as intervals.

    Parameters
    ----------
    a : (ndarray, ndarray)

    Returns
    -------
    (ndarray, ndarray)
        lo, hi of shape (...).
    """
    return a[0][..., 2] - a[1], a[0][..., 2] + a[1]
