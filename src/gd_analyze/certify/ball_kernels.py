"""Compiled midpoint-radius enclosures of the regressor recursion, box by box.

The enclosures of :func:`gd_analyze.certify.regressor_bounds.channel_enclosures` and
:func:`~gd_analyze.certify.regressor_bounds.pair_magnitudes` run the Newton-Euler regressor
recursion (Khalil & Kleinfinger 1987) in the ball arithmetic of :mod:`.balls` over every box of
joint positions. Its backward half, which runs every column of a link through every joint
below it, is most of the work: as array code over a batch of boxes it is a long sequence of
small array operations; here it is one compiled pass per box, with the very operations of
:mod:`.balls` (each centre operation as there, each radius with the same rounding slack), so it
encloses what the array code encloses. The forward half (the links' velocities and
accelerations) stays array code. The array code of both (``regressor_bounds._column_groups``
with the ball algebra) is the tests' oracle of this kernel.

A ball is four numbers: a centre (3) and a radius, stored along the last axis of length 4.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .balls import ARC_LIMIT, ROUNDING

__all__ = ["backward_kernel", "forward_kernel", "inertia_kernel", "summed_kernel"]

_SLACK = 32 * ROUNDING
_ROT_SLACK = 4 * _SLACK + 1e-15


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _norm(c0, c1, c2):
    return math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _add(a, b):
    """a + b (:func:`.balls.add`)."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2],
            a[3] + b[3] + _SLACK * (_norm(a[0], a[1], a[2]) + _norm(b[0], b[1], b[2])))


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _scale(a, s):
    """s a (:func:`.balls.scale`)."""
    return (a[0] * s, a[1] * s, a[2] * s,
            abs(s) * a[3] * (1 + _SLACK) + _SLACK * abs(s) * _norm(a[0], a[1], a[2]))


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _cross(a, b):
    """a x b (:func:`.balls.cross`)."""
    na, nb = _norm(a[0], a[1], a[2]), _norm(b[0], b[1], b[2])
    r = na * b[3] + a[3] * nb + a[3] * b[3]
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0],
            r * (1 + _SLACK) + _SLACK * na * nb)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _matvec(M, norm, a):
    """M a for a point matrix M (3, 3) of spectral norm at most ``norm``
    (:func:`.balls.matvec`)."""
    return (M[0, 0] * a[0] + M[0, 1] * a[1] + M[0, 2] * a[2],
            M[1, 0] * a[0] + M[1, 1] * a[1] + M[1, 2] * a[2],
            M[2, 0] * a[0] + M[2, 1] * a[1] + M[2, 2] * a[2],
            norm * a[3] * (1 + _SLACK) + _SLACK * norm * _norm(a[0], a[1], a[2]))


@njit(cache=True, fastmath=False, nogil=True)
def _trig(mid, half):
    """Per joint of a box, what :func:`_rot_z` needs: cos and sin of the mid point, and the
    arc's factors k = cos(d) and s = sin(d) of the half-width d (0 and 1 beyond
    :data:`.balls.ARC_LIMIT`, where the centre is enclosed about the axis); shape (n, 4)."""
    out = np.empty((mid.shape[0], 4))
    for j in range(mid.shape[0]):
        if half[j] <= ARC_LIMIT:
            d = min(half[j], np.pi / 2)
            out[j, 2], out[j, 3] = math.cos(d), math.sin(d)
        else:
            out[j, 2], out[j, 3] = 0.0, 1.0
        out[j, 0], out[j, 1] = math.cos(mid[j]), math.sin(mid[j])
    return out


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _rot_z(a, trig, transpose):
    """Rz(theta) a, or Rz(theta)^T a, for every theta in [mid - half, mid + half]
    (:func:`.balls.rot_z`; ``trig`` the joint's row of :func:`_trig`)."""
    cm, sm, k, s = trig[0], trig[1], trig[2], trig[3]
    if transpose:
        sm = -sm
    x, y = k * a[0], k * a[1]
    rho = math.hypot(a[0], a[1])
    return (cm * x - sm * y, sm * x + cm * y, a[2],
            (a[3] + rho * s) * (1 + _SLACK) + _ROT_SLACK * (rho + _norm(a[0], a[1], a[2])))


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _get(A, index):
    return (A[index, 0], A[index, 1], A[index, 2], A[index, 3])


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _set(A, index, a):
    A[index, 0], A[index, 1], A[index, 2], A[index, 3] = a[0], a[1], a[2], a[3]


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _position(k, mid, half, t, P, pris):
    """p_k as a ball: t_k, plus q_k P_k z for a prismatic joint (``_Ball.slide``)."""
    if not pris[k]:
        return (t[k, 0], t[k, 1], t[k, 2], 0.0)
    dz0, dz1, dz2 = P[k, 0, 2], P[k, 1, 2], P[k, 2, 2]
    c0, c1, c2 = t[k, 0] + mid[k] * dz0, t[k, 1] + mid[k] * dz1, t[k, 2] + mid[k] * dz2
    r = half[k] * _norm(dz0, dz1, dz2) * (1 + 1e-15)
    return (c0, c1, c2, r + 1e-15 * _norm(c0, c1, c2))


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _rot(k, a, trig, P, norms, pris):
    """R_k a = P_k Rz(q_k) a (revolute) or P_k a (prismatic)."""
    if not pris[k]:
        a = _rot_z(a, trig[k], False)
    return _matvec(P[k], norms[k], a)


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _sym(a, i, j):
    """E a for the symmetric unit matrix E of the index pair (i, j) (``_Ball.sym``)."""
    return (a[j] if i == 0 else (a[i] if j == 0 else 0.0),
            a[j] if i == 1 else (a[i] if j == 1 else 0.0),
            a[j] if i == 2 else (a[i] if j == 2 else 0.0), a[3])


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _own(k, top):
    """Link k's channels (gravity, the accelerations of joints 0..k, the velocity pairs of
    joints 0..k) as indices into the forward recursion's layout of ``top`` links, (Ck,)."""
    kk = k + 1
    own = np.empty(1 + kk + kk * kk, np.int64)
    own[0] = 0
    for j in range(kk):
        own[1 + j] = 1 + j
    for j in range(kk):
        for l in range(kk):
            own[1 + kk + j * kk + l] = 1 + top + j * top + l
    return own


@njit(cache=True, fastmath=False, nogil=True)
def backward_kernel(k, types, W, WD, VD, mid, half, P, norms, t, pris, top):
    """The backward recursion of link k's columns, every box: their torques' enclosures.

    Parameters
    ----------
    k : int
        The link.
    types : ndarray of int, shape (g,)
        Its columns' standard parameters (0-5 the inertia XX..ZZ, 6-8 the first moments, 9
        the mass).
    W, WD, VD : ndarray, shapes (B, top, 4), (B, C, 4) and (B, C, 4)
        The forward recursion's balls at link k (``regressor_bounds._forward``, centre and
        radius along the last axis): per unit qd_j the angular velocity of every joint j, and
        per channel (C = 1 + top + top^2, that function's layout) the angular and linear
        accelerations.
    mid, half : ndarray, shape (B, n)
        The boxes' mid points and half-widths [rad or m] (``regressor_bounds._Ball``'s,
        widened).
    P : ndarray, shape (n, 3, 3)
        The joints' fixed placements.
    norms : ndarray, shape (n,)
        Upper bounds of their spectral norms.
    t : ndarray, shape (n, 3)
        The placements' translations [m].
    pris : ndarray of bool, shape (n,)
    top : int
        The links the forward recursion ran.

    Returns
    -------
    lo, hi : ndarray, shape (B, k + 1, g, Ck)
        Per box, joint i <= k, column and channel of the link (Ck = 1 + (k + 1) + (k + 1)^2:
        gravity, the accelerations of joints 0..k, the velocity pairs (j, l) of joints 0..k),
        lo <= torque <= hi [N m or N per unit parameter].

    Raises
    ------
    None: the caller (``regressor_bounds._ball_links``) passes checked boxes.

    Notes
    -----
    Source: the backward recursion of the Newton-Euler equations (Fu, Gonzalez & Lee 1987,
    Table 3.3) written per standard parameter, as the regressor of Khalil & Kleinfinger (1987):
    f_{i-1} = R_i f_i, n_{i-1} = R_i n_i + p_i x f_i, and tau_i the z component of n_i (of f_i
    for a prismatic joint), in the ball arithmetic of :mod:`.balls`.
    """
    B = mid.shape[0]
    kk = k + 1
    Ck = 1 + kk + kk * kk
    g = types.shape[0]
    lo = np.zeros((B, kk, g, Ck))
    hi = np.zeros((B, kk, g, Ck))
    own = _own(k, top)
    pairs = np.array([[0, 0], [0, 1], [0, 2], [1, 1], [1, 2], [2, 2]])
    zero = (0.0, 0.0, 0.0, 0.0)
    for b in range(B):
        f = np.zeros((g, Ck, 4))
        mom = np.zeros((g, Ck, 4))
        m, h = mid[b], half[b]
        trig = _trig(m, h)
        for q in range(g):
            c = types[q]
            for x in range(Ck):
                wd = _get(WD[b], own[x])
                vd = _get(VD[b], own[x])
                vel = x >= 1 + kk
                if vel:
                    wa = _get(W[b], (x - 1 - kk) // kk)
                    wb = _get(W[b], (x - 1 - kk) % kk)
                else:
                    wa, wb = zero, zero
                if c < 6:
                    i, j = pairs[c, 0], pairs[c, 1]
                    _set(f[q], x, zero)
                    _set(mom[q], x, _add(_sym(wd, i, j), _cross(wa, _sym(wb, i, j))))
                elif c < 9:
                    e = (1.0 if c == 6 else 0.0, 1.0 if c == 7 else 0.0,
                         1.0 if c == 8 else 0.0, 0.0)
                    _set(f[q], x, _add(_cross(wd, e), _cross(wa, _cross(wb, e))))
                    _set(mom[q], x, _cross(e, vd))
                else:
                    _set(f[q], x, vd)
                    _set(mom[q], x, zero)
        for i in range(k, -1, -1):
            src = f if pris[i] else mom
            for q in range(g):
                for x in range(Ck):
                    lo[b, i, q, x] = src[q, x, 2] - src[q, x, 3]
                    hi[b, i, q, x] = src[q, x, 2] + src[q, x, 3]
            if i == 0:
                break
            p = _position(i, m, h, t, P, pris)
            for q in range(g):
                # an inertia column's force is exactly the zero ball throughout: its rotation
                # and p x f are the zero ball, and adding it only adds the slack of the sum
                inertial = types[q] < 6
                for x in range(Ck):
                    moved = _rot(i, _get(mom[q], x), trig, P, norms, pris)
                    if inertial:
                        _set(mom[q], x, _add(moved, zero))
                    else:
                        fi = _rot(i, _get(f[q], x), trig, P, norms, pris)
                        _set(f[q], x, fi)
                        _set(mom[q], x, _add(moved, _cross(p, fi)))
    return lo, hi


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _copy(dst, src):
    """dst[:] = src for two (m, w) arrays (balls, or :mod:`.box_kernels`' boxes), element by
    element (a slice assignment would compile numba's shape-mismatch message formatting into
    the kernel)."""
    for i in range(src.shape[0]):
        for c in range(src.shape[1]):
            dst[i, c] = src[i, c]


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _zero(dst):
    """dst[:] = 0 for an (m, w) array, element by element."""
    for i in range(dst.shape[0]):
        for c in range(dst.shape[1]):
            dst[i, c] = 0.0


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _rot_t(k, a, trig, P, norms_t, pris):
    """R_k^T a = Rz(q_k)^T P_k^T a (revolute) or P_k^T a (prismatic)."""
    u = _matvec(P[k].T, norms_t[k], a)
    if pris[k]:
        return u
    return _rot_z(u, trig[k], True)


@njit(cache=True, fastmath=False, nogil=True)
def inertia_kernel(mid, half, P, norms, norms_t, t, pris, values, inertia, inertia_norms):
    """Enclosures of the inertia matrix's columns over every box, before the armature.

    Parameters
    ----------
    mid, half : ndarray, shape (B, n)
        The boxes' mid points and half-widths [rad or m] (``regressor_bounds._Ball``'s,
        widened).
    P : ndarray, shape (n, 3, 3)
        The joints' fixed placements.
    norms, norms_t : ndarray, shape (n,)
        Upper bounds of the spectral norms of P_k and of P_k^T.
    t : ndarray, shape (n, 3)
        The placements' translations [m].
    pris : ndarray of bool, shape (n,)
    values : ndarray, shape (n, 10)
        Per link XX, XY, XZ, YY, YZ, ZZ [kg m^2], MX, MY, MZ [kg m], M [kg].
    inertia : ndarray, shape (n, 3, 3)
        Per link, the symmetric inertia tensor of ``values`` [kg m^2].
    inertia_norms : ndarray, shape (n,)
        Upper bounds of their spectral norms.

    Returns
    -------
    lo, hi : ndarray, shape (B, n, n)
        ``[b, i, j]``: lo <= D_ij(q) <= hi over box b, without the armature and before D_ij and
        D_ji are intersected [kg m^2; kg m; kg].

    Raises
    ------
    None: the caller (``regressor_bounds.inertia_enclosure``) passes checked arrays.

    Notes
    -----
    Column j of D is the torque of the Newton-Euler recursion at qd = 0, qdd = e_j and g = 0
    (Walker & Orin 1982, method 1; Fu, Gonzalez & Lee 1987, Table 3.3): forward, the links'
    angular and linear accelerations per column; backward, the links' wrenches
    f = m vd + wd x (m c), n = I wd + (m c) x vd summed from the tip, in the ball arithmetic
    of :mod:`.balls`, with the operations of ``regressor_bounds.inertia_enclosure``'s
    array code in the same order.
    """
    B, n = mid.shape
    lo = np.zeros((B, n, n))
    hi = np.zeros((B, n, n))
    WD = np.zeros((n, n, 4))            # per link k, column j: the balls of wd and vd
    VD = np.zeros((n, n, 4))
    f = np.zeros((n, 4))
    mom = np.zeros((n, 4))
    for b in range(B):
        m, h = mid[b], half[b]
        trig = _trig(m, h)
        wd = np.zeros((n, 4))
        vd = np.zeros((n, 4))
        for k in range(n):
            p = _position(k, m, h, t, P, pris)
            for j in range(n):
                a = _add(_get(vd, j), _cross(_get(wd, j), p))
                _set(vd, j, _rot_t(k, a, trig, P, norms_t, pris))
                _set(wd, j, _rot_t(k, _get(wd, j), trig, P, norms_t, pris))
            if pris[k]:
                vd[k, 2] += 1.0
            else:
                wd[k, 2] += 1.0
            _copy(WD[k], wd)
            _copy(VD[k], vd)
        for k in range(n - 1, -1, -1):
            v = values[k]
            mc = (v[6], v[7], v[8], 0.0)
            for j in range(n):
                wdj, vdj = _get(WD[k], j), _get(VD[k], j)
                fk = _add(_scale(vdj, v[9]), _cross(wdj, mc))
                mk = _add(_matvec(inertia[k], inertia_norms[k], wdj), _cross(mc, vdj))
                if k == n - 1:
                    _set(f, j, fk)
                    _set(mom, j, mk)
                else:
                    _set(f, j, _add(fk, _get(f, j)))
                    _set(mom, j, _add(mk, _get(mom, j)))
                src = f if pris[k] else mom
                lo[b, k, j] = src[j, 2] - src[j, 3]
                hi[b, k, j] = src[j, 2] + src[j, 3]
            if k:
                p = _position(k, m, h, t, P, pris)
                for j in range(n):
                    fj = _rot(k, _get(f, j), trig, P, norms, pris)
                    _set(f, j, fj)
                    _set(mom, j, _add(_rot(k, _get(mom, j), trig, P, norms, pris),
                                      _cross(p, fj)))
    return lo, hi


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def _forward_arrays(B, n, width):
    """The forward recursion's arrays, zero, for B boxes, n links and vectors of ``width``
    numbers: its results W (n, B, n, width), WD and VD (n, B, C, width), and its working
    rows w, wp (n, width), wd, vd, a (C, width), C = 1 + n + n^2."""
    C = 1 + n + n * n
    return (np.zeros((n, B, n, width)), np.zeros((n, B, C, width)),
            np.zeros((n, B, C, width)), np.zeros((n, width)), np.zeros((n, width)),
            np.zeros((C, width)), np.zeros((C, width)), np.zeros((C, width)))


@njit(cache=True, fastmath=False, nogil=True)
def _active(n):
    """Per link k of n, the channels of joints 0..k in the forward recursion's layout
    (gravity, the accelerations of joints 0..k, the velocity pairs of joints 0..k): the
    array (n, 1 + n + n^2) of their indices and their counts (n,)."""
    active = np.zeros((n, 1 + n + n * n), np.int64)
    count = np.zeros(n, np.int64)
    for k in range(n):
        x = 1
        for j in range(k + 1):
            active[k, x] = 1 + j
            x += 1
        for j in range(k + 1):
            for l in range(k + 1):
                active[k, x] = 1 + n + j * n + l
                x += 1
        count[k] = x
    return active, count


@njit(cache=True, fastmath=False, nogil=True)
def forward_kernel(mid, half, P, norms_t, t, pris, gravity, top):
    """The forward recursion of the regressor's channels, every box: the links' angular
    velocities per unit joint velocity and their accelerations per channel, as balls.

    Parameters
    ----------
    mid, half : ndarray, shape (B, n)
        The boxes' mid points and half-widths [rad or m] (``regressor_bounds._Ball``'s,
        widened).
    P : ndarray, shape (n, 3, 3)
        The joints' fixed placements.
    norms_t : ndarray, shape (n,)
        Upper bounds of the spectral norms of P_k^T.
    t : ndarray, shape (n, 3)
        The placements' translations [m].
    pris : ndarray of bool, shape (n,)
    gravity : ndarray, shape (3,)
        [m/s^2].
    top : int
        The links to run, the first ``top``.

    Returns
    -------
    W : ndarray, shape (top, B, top, 4)
        Per link k and box, the angular velocity of link k per unit qd_j, j < top (centre and
        radius along the last axis).
    WD, VD : ndarray, shape (top, B, C, 4)
        Per link k and box, its angular and linear accelerations per channel (C = 1 + top +
        top^2: gravity, qdd_j, the velocity pairs qd_j qd_l), in the layout of
        ``regressor_bounds._forward``, whose array code (the tests' oracle) performs the same
        operations over all boxes at once.

    Raises
    ------
    None: the caller (``regressor_bounds._ball_links``) passes checked arrays.

    Notes
    -----
    Source: the forward recursion of the Newton-Euler equations (Fu, Gonzalez & Lee 1987,
    Table 3.3) per channel, as the regressor of Khalil & Kleinfinger (1987), in the ball
    arithmetic of :mod:`.balls`.
    """
    B, n = mid.shape[0], top
    W, WD, VD, w, wp, wd, vd, a = _forward_arrays(B, n, 4)
    ez = (0.0, 0.0, 1.0, 0.0)
    active, count = _active(n)
    for b in range(B):
        m, h = mid[b], half[b]
        trig = _trig(m, h)
        _zero(w)
        _zero(wp)
        _zero(wd)
        _zero(vd)
        vd[0, 0], vd[0, 1], vd[0, 2] = -gravity[0], -gravity[1], -gravity[2]
        for k in range(n):
            p = _position(k, m, h, t, P, pris)
            # only the channels of joints 0..k: the others are the zero ball up to link k,
            # and every operation below keeps a zero ball zero (its radius slack is relative)
            for x in range(count[k]):
                c = active[k, x]
                _set(a, c, _add(_get(vd, c), _cross(_get(wd, c), p)))
            for j in range(k + 1):
                for l in range(k + 1):
                    c = 1 + n + j * n + l
                    _set(a, c, _add(_get(a, c), _cross(_get(w, j), _cross(_get(w, l), p))))
            for x in range(count[k]):
                c = active[k, x]
                _set(vd, c, _rot_t(k, _get(a, c), trig, P, norms_t, pris))
            for j in range(k + 1):
                _set(wp, j, _rot_t(k, _get(w, j), trig, P, norms_t, pris))
            for x in range(count[k]):
                c = active[k, x]
                _set(wd, c, _rot_t(k, _get(wd, c), trig, P, norms_t, pris))
            if pris[k]:
                vd[1 + k, 2] += 1.0
                for j in range(k + 1):
                    c = 1 + n + j * n + k
                    zk = _cross(_get(wp, j), ez)
                    _set(vd, c, _add(_get(vd, c), _scale(zk, 2.0)))
            else:
                wd[1 + k, 2] += 1.0
                for j in range(k + 1):
                    c = 1 + n + j * n + k
                    zk = _cross(_get(wp, j), ez)
                    _set(wd, c, _add(_get(wd, c), zk))
                wp[k, 2] += 1.0
            _copy(w, wp)
            _copy(W[k, b], w)
            _copy(WD[k, b], wd)
            _copy(VD[k, b], vd)
    return W, WD, VD


@njit(cache=True, fastmath=False, nogil=True)
def summed_kernel(c_lo, c_hi, beta, weight, slack):
    """Channel enclosures of k columns added per box, channel and joint, in midpoint-radius
    form: :func:`gd_analyze.certify.certify._scaled` and
    :meth:`gd_analyze.certify.certify.JointSums.sums` in one pass.

    Parameters
    ----------
    c_lo, c_hi : ndarray, shape (B, C, n, k)
        The columns' channel enclosures [lo, hi] on B boxes (unscaled).
    beta : ndarray, shape (k,)
        The columns' base parameter values.
    weight : ndarray, shape (C, n, k)
        1 where the column's pair of the channel's part is summed at the joint, else 0.
    slack : float
        The relative round-off allowance of each scaled enclosure (``_slack(n, k)``).

    Returns
    -------
    mid, rad : ndarray, shape (B, C, n)
        Per box, channel and joint: the sum over the weighted columns of beta times the
        enclosure's centre, and of |beta| times its radius widened by ``slack`` (and by
        ``slack`` times the centre's magnitude), not yet widened by the sum's own round-off
        (the caller's, as ``JointSums.sums``) [N m or N].

    Notes
    -----
    Each term is the very expression of ``_scaled`` (the same operations in the same
    order); the terms are added in column order.
    """
    B, C, n, k = c_lo.shape
    mid = np.zeros((B, C, n))
    rad = np.zeros((B, C, n))
    for b in range(B):
        for c in range(C):
            for i in range(n):
                m = 0.0
                r = 0.0
                for j in range(k):
                    if weight[c, i, j] != 0.0:
                        centre = (c_lo[b, c, i, j] + c_hi[b, c, i, j]) * 0.5
                        radius = (c_hi[b, c, i, j] - c_lo[b, c, i, j]) * 0.5
                        radius = radius * (1 + slack) + abs(centre) * slack
                        m += centre * beta[j] * weight[c, i, j]
                        r += radius * abs(beta[j]) * weight[c, i, j]
                mid[b, c, i] = m
                rad[b, c, i] = r
    return mid, rad
