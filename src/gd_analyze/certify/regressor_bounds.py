"""The regressor's coefficient functions of q, enclosed over boxes of joint positions.

The joint torques are linear in the inertial parameters, tau = W(q, qd, qdd) phi
(:func:`gd_analyze.dynamics.base_parameters.regressor`), and each column of W splits into

    W(q, qd, qdd) = sum_j A_j(q) qdd_j + sum_{j, l} C_jl(q) qd_j qd_l + G(q)

(inertial, velocity and gravity parts: the D qdd, h and c of Eq. (3.4-24)). This module runs
the recursive Newton-Euler regressor recursion (Fu, Gonzalez & Lee 1987, Table 3.3; Khalil &
Kleinfinger 1987) once per *channel*: gravity G (qd = qdd = 0), the inertial channels A_j
(qdd = e_j, g = 0) and the bilinear velocity channels C_jl (the coefficient of qd_j qd_l,
g = 0), over a batch of boxes of q, in midpoint-radius balls (:mod:`.ball_kernels`) and
interval boxes (:mod:`.box_kernels`), rounded outward. The result encloses every coefficient
over its box; at points (:func:`channel_values`) the same recursion runs in plain floating
point.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from . import balls
from . import intervals as iv
from .ball_kernels import backward_kernel, forward_kernel, inertia_kernel
from .box_kernels import both_backward_kernel, box_forward_kernel
from .vertex_kernel import vertex_extremes

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["channel_count", "channel_values", "pair_magnitudes", "inertia_enclosure",
           "inertia_form_enclosure", "channel_enclosures", "channel_magnitudes", "combined_bound",
           "BOX_MAX_JOINTS", "joint_sum_arithmetic"]


def channel_count(n: int) -> int:
    """Number of channels of an n-joint arm: 1 gravity + n inertial + n^2 velocity.

    Parameters
    ----------
    n : int

    Returns
    -------
    int

    Examples
    --------
    >>> channel_count(2)
    7
    """
    return 1 + n + n * n


def _sym(x, ab):
    """E x for the symmetric unit matrix E of the index pair ab, on point vectors (..., 3)."""
    i, j = ab
    y = np.zeros_like(x)
    y[..., i] = x[..., j]
    if i != j:
        y[..., j] = x[..., i]
    return y


class _Point:
    """Plain floating point at points (q_lo = q_hi), for :func:`channel_values`: a vector is
    (x, x), one array twice, so that :func:`_column_groups` runs unchanged. Samples, not
    enclosures: nothing proved is computed in it."""

    @staticmethod
    def add(a, b):
        r = a[0] + b[0]
        return r, r

    @staticmethod
    def scale(a, c):
        r = a[0] * c
        return r, r

    @staticmethod
    def cross(a, b):
        r = np.cross(a[0], b[0])
        return r, r

    @staticmethod
    def matvec(M, v):
        r = v[0] @ np.asarray(M, float).T
        return r, r

    @staticmethod
    def point(x):
        x = np.asarray(x, float)
        return x, x

    @staticmethod
    def zeros(shape):
        z = np.zeros(tuple(shape) + (3,))
        return z, z

    @staticmethod
    def put_point(a, index, value):
        for x in a:
            x[:, index] = value

    @staticmethod
    def unit_z(a, index):
        a[0][:, index, 2] += 1.0
        if a[1] is not a[0]:
            a[1][:, index, 2] += 1.0

    @staticmethod
    def sym(a, ab):
        y = _sym(a[0], ab)
        return y, y

    @staticmethod
    def z(a):
        r = a[0][..., 2]
        return r, r

    def __init__(self, q_lo, q_hi):
        self.c, self.s = np.cos(q_lo), np.sin(q_lo)
        self.q = q_lo

    def rotz(self, k, v, transpose):
        c, s = self.c[:, k, None], self.s[:, k, None]
        x, y = v[0][..., 0], v[0][..., 1]
        if transpose:
            r = np.stack([c * x + s * y, c * y - s * x, v[0][..., 2]], -1)
        else:
            r = np.stack([c * x - s * y, s * x + c * y, v[0][..., 2]], -1)
        return r, r

    def slide(self, k, t, dz):
        r = t + self.q[:, k, None, None] * np.asarray(dz, float)
        return r, r

    def fixed(self, t, B):
        base = np.broadcast_to(t, (B, 1, 3))
        return base, base


class _Ball:
    """Midpoint-radius balls (:mod:`.balls`): a vector is (centre (..., 3), radius (...))."""

    add, scale = staticmethod(balls.add), staticmethod(balls.scale)
    cross, matvec, point = (staticmethod(balls.cross), staticmethod(balls.matvec),
                            staticmethod(balls.point))

    @staticmethod
    def zeros(shape):
        return balls.zeros(shape)

    @staticmethod
    def unit_z(a, index):
        a[0][:, index, 2] += 1.0

    @staticmethod
    def put_point(a, index, value):
        a[0][:, index] = value
        a[1][:, index] = 0.0

    @staticmethod
    def sym(a, ab):
        return _sym(a[0], ab), a[1]

    z = staticmethod(balls.z_interval)

    def __init__(self, q_lo, q_hi):
        self.mid = 0.5 * (q_lo + q_hi)
        self.half = 0.5 * (q_hi - q_lo) * (1 + 1e-15) + 1e-300
        self.q = (q_lo, q_hi)

    def rotz(self, k, v, transpose):
        return balls.rot_z(v, self.mid[:, k], self.half[:, k], transpose)

    def slide(self, k, t, dz):
        c = t + self.mid[:, k, None, None] * dz                       # (B, 1, 3)
        r = self.half[:, k, None] * np.linalg.norm(dz) * (1 + 1e-15)
        return c, r + 1e-15 * np.linalg.norm(c, axis=-1)

    def fixed(self, t, B):
        c = np.broadcast_to(t, (B, 1, 3))
        return c, np.zeros((B, 1))


def _take(a, index):
    return tuple(x[:, index] for x in a)


def _put(a, index, value):
    for x, v in zip(a, value):
        x[:, index] = v


class _Chain:
    """The joint geometry over a batch of boxes: R_k v, R_k^T v and p_k as enclosures."""

    def __init__(self, robot, q_lo, q_hi, algebra):
        self.robot = robot
        self.A = algebra(q_lo, q_hi)
        self.P = np.asarray(robot.rotation, float)
        self.t = np.asarray(robot.translation, float)
        self.pris = np.asarray(robot.prismatic, bool)
        self.B = q_lo.shape[0]

    def rot_t(self, k, v):
        """R_k^T v = Rz(q_k)^T P_k^T v (revolute) or P_k^T v (prismatic)."""
        u = self.A.matvec(self.P[k].T, v)
        return u if self.pris[k] else self.A.rotz(k, u, True)

    def rot(self, k, v):
        """R_k v = P_k Rz(q_k) v (revolute) or P_k v (prismatic)."""
        if not self.pris[k]:
            v = self.A.rotz(k, v, False)
        return self.A.matvec(self.P[k], v)

    def p(self, k):
        """p_k, shape (B, 1, 3): t_k, plus q_k P_k z for a prismatic joint."""
        if not self.pris[k]:
            return self.A.fixed(self.t[k], self.B)
        return self.A.slide(k, self.t[k], self.P[k][:, 2])


def _unit(c):
    e = np.zeros(3)
    e[c] = 1.0
    return e


def _forward(chain, gravity, links=None):
    """Per link k of the first ``links`` (n: all), on the channels of their joints only
    (those of later joints are exactly zero there): w (B, links, 3) per velocity j, and wd,
    vd (B, C, 3) per channel, C = :func:`channel_count` (links)."""
    A = chain.A
    n = chain.robot.n if links is None else links
    B = chain.B
    C = channel_count(n)
    jj, ll = np.divmod(np.arange(n * n), n)
    vel = 1 + n + np.arange(n * n)
    w = A.zeros((B, n))
    wd = A.zeros((B, C))
    vd = A.zeros((B, C))
    g = -np.asarray(gravity, float)
    A.put_point(vd, 0, g)
    out = []
    for k in range(n):
        p = chain.p(k)
        a = A.add(vd, A.cross(wd, p))
        wj, wl = _take(w, jj), _take(w, ll)
        _put(a, vel, A.add(_take(a, vel), A.cross(wj, A.cross(wl, p))))
        vd = chain.rot_t(k, a)
        wp = chain.rot_t(k, w)
        wd = chain.rot_t(k, wd)
        zk = A.cross(_take(wp, jj[ll == k]), A.point(np.array([0.0, 0.0, 1.0])))
        target = vel[ll == k]
        if chain.pris[k]:
            A.unit_z(vd, 1 + k)
            _put(vd, target, A.add(_take(vd, target), A.scale(zk, 2.0)))
        else:
            A.unit_z(wd, 1 + k)
            _put(wd, target, A.add(_take(wd, target), zk))
            A.unit_z(wp, k)
        w = wp
        out.append((w, wd, vd))
    return out


def _wrench(A, c, w, wd, vd, jj, ll, vel):
    """Force and moment of a link per unit standard parameter c, per channel (B, C, 3)."""
    shape = wd[0].shape[:2]
    zero = A.zeros(shape)
    wa, wb = A.zeros(shape), A.zeros(shape)
    _put(wa, vel, _take(w, jj))
    _put(wb, vel, _take(w, ll))
    if c < 6:
        ab = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))[c]
        return zero, A.add(A.sym(wd, ab), A.cross(wa, A.sym(wb, ab)))
    if c < 9:
        e = A.point(_unit(c - 6))
        force = A.add(A.cross(wd, e), A.cross(wa, A.cross(wb, e)))
        return force, A.cross(e, vd)
    return vd, zero


def _links(columns, top, n):
    """Per link k < ``top`` that has columns: k, the positions in ``columns`` of its columns,
    the joint pairs (j, l) of joints 0..k (two arrays, j major) and the link's own channels'
    indices in :func:`channel_values`' layout of n joints (gravity, the accelerations of joints
    0..k, the velocity pairs)."""
    for k in range(top):
        ms = np.flatnonzero(columns // 10 == k)
        if ms.size:
            kk = k + 1
            jv, lv = np.divmod(np.arange(kk * kk), kk)
            yield k, ms, jv, lv, np.concatenate([[0], 1 + np.arange(kk), 1 + n + jv * n + lv])


def _column_groups(robot, q_lo, q_hi, columns, gravity, algebra):
    """Per link k and joint i <= k: (the positions in ``columns`` of the link's columns, i,
    enclosure of their torques at joint i per channel, each of shape (B, C, g)).

    The backward recursion is linear in the wrench, so the g columns of one link run through
    it together, stacked along the channel axis (one pass per link, not per column), and only
    on the link's 1 + (k + 1) + (k + 1)^2 channels of joints up to k: the others are exactly
    zero at link k (no velocity or acceleration of a later joint reaches it) and stay zero."""
    chain = _Chain(robot, q_lo, q_hi, algebra)
    A = chain.A
    n = robot.n
    C = channel_count(n)
    columns = np.asarray(columns, int)
    top = int(columns.max()) // 10 + 1 if columns.size else 0    # the links the columns need
    links = _forward(chain, robot.gravity if gravity is None else gravity, top)
    for k, ms, jv, lv, ch in _links(columns, top, n):
        kk = k + 1
        w, wd, vd = links[k]
        own = np.concatenate([[0], 1 + np.arange(kk), 1 + top + jv * top + lv])
        wd, vd = _take(wd, own), _take(vd, own)
        parts = [_wrench(A, int(columns[m]) % 10, w, wd, vd, jv, lv, 1 + kk + np.arange(kk * kk))
                 for m in ms]
        f = tuple(np.concatenate([p[0][e] for p in parts], axis=1) for e in range(2))
        mom = tuple(np.concatenate([p[1][e] for p in parts], axis=1) for e in range(2))
        for i in range(k, -1, -1):
            z = A.z(mom if not chain.pris[i] else f)                  # (B, g Ck)
            B = z[0].shape[0]
            full = []
            for x in z:
                y = np.zeros((B, C, ms.size))
                y[:, ch] = x.reshape(B, ms.size, ch.size).transpose(0, 2, 1)
                full.append(y)
            yield ms, i, tuple(full)
            if i == 0:
                break
            f = chain.rot(i, f)
            mom = A.add(chain.rot(i, mom), A.cross(chain.p(i), f))


def _forward_balls(robot, q_lo, q_hi, columns, gravity):
    """What the backward kernels take of the ball forward recursion: (top, the balls
    (:class:`_Ball`), P, t, pris, the norms of P, gravity, and
    :func:`.ball_kernels.forward_kernel`'s (W, WD, VD) on the first ``top`` links, those the
    columns need), or None where there are no columns."""
    columns = np.asarray(columns, int)
    top = int(columns.max()) // 10 + 1 if columns.size else 0
    if top == 0:
        return None
    A = _Ball(q_lo, q_hi)
    P, t, pris = _geometry(robot)
    g = np.array(robot.gravity if gravity is None else gravity, float)
    _before(forward_kernel)
    W = forward_kernel(A.mid, A.half, P, _norms(P.transpose(0, 2, 1)), t, pris, g, top)
    return top, A, P, t, pris, _norms(P), g, W


def _ball_links(robot, q_lo, q_hi, columns, gravity):
    """Per link k that has columns: (k, the positions in ``columns`` of its g columns, its
    channels' indices in :func:`channel_values`' layout (Ck), and the enclosures (lo, hi) of
    their torques, each (B, k + 1, g, Ck): per box, joint i <= k, column and channel of the
    link). :func:`_column_groups`' values in the ball arithmetic, by the compiled kernels of
    :mod:`.ball_kernels`, link by link and in the link's own channels (gravity, the
    accelerations of joints 0..k, the velocity pairs of joints 0..k), which are the only ones
    not exactly zero at link k. The forward recursion is :func:`_forward`'s, compiled
    (:func:`.ball_kernels.forward_kernel`)."""
    forward = _forward_balls(robot, q_lo, q_hi, columns, gravity)
    if forward is None:
        return
    top, A, P, t, pris, norms, _, (W, WD, VD) = forward
    columns = np.asarray(columns, int)
    _before(backward_kernel)
    for k, ms, _, _, ch in _links(columns, top, robot.n):
        lo, hi = backward_kernel(k, np.ascontiguousarray(columns[ms] % 10), W[k], WD[k], VD[k],
                                 A.mid, A.half, P, norms, t, pris, top)
        yield k, ms, ch, lo, hi


def _dot(x, w):
    """x @ w for x (B, P), w (P,), summed in the same order in every row whatever B (a
    matrix-vector product's order may depend on the number of rows)."""
    return (x * w).sum(axis=1)


class _QuadraticBound:
    """max |qd^T C qd| over |qd_j| <= a_j for interval coefficients C_jl (j, l = 1..n).

    qd^T C qd = sum_j C_jj qd_j^2 + sum_{j < l} S_jl qd_j qd_l with S_jl = C_jl + C_lj. The
    off-diagonal part is affine in each qd_j, so its extremes over the box are at vertices
    (half of them: v and -v give the same value); the diagonal part lies within
    [sum min(0, C_jj) a_j^2, sum max(0, C_jj) a_j^2]. Each is taken over the intervals.

    Only the joints whose coefficients are not all exactly zero in the batch (the support S:
    a column of link k has none beyond joint k) take part, so the vertices are 2^(|S| - 1),
    not 2^(n - 1); the other joints change no value. Beyond :attr:`VERTEX_LIMIT` joints in S
    the centre is bounded by sum |S_jl| a_j a_l instead of searched. The search is
    :func:`.vertex_kernel.vertex_extremes`'s, in Gray-code order, with its round-off bounded.
    """

    #: Largest support searched over its vertices.
    VERTEX_LIMIT = 13

    def __init__(self, n, a):
        self.n, self.a = n, np.asarray(a, float)
        self._plans = {}

    def _plan(self, support):
        plan = self._plans.get(support)
        if plan is None:
            n, S = self.n, np.asarray(support, int)
            j, l = np.triu_indices(S.size, 1)
            plan = (S[j] * n + S[l], S[l] * n + S[j], S * (n + 1), self.a[S[j]] * self.a[S[l]],
                    self.a[S] ** 2, j, l)
            self._plans[support] = plan
        return plan

    def __call__(self, lo, hi):
        """lo, hi (B, n^2): the channels C_jl; returns (B,) upper bounds."""
        bottom, top, searched = self._range(lo, hi)
        out = np.maximum(top, -bottom) * (1 + 1e-12)
        return out + 1e-300 if searched else out

    def range(self, lo, hi):
        """lo, hi (B, n^2): the channels C_jl; returns (bottom, top), each (B,), with
        bottom <= qd^T C qd <= top over the box of qd (the rounding margin of
        :meth:`__call__` included)."""
        bottom, top, _ = self._range(lo, hi)
        return (np.minimum(bottom * (1 + 1e-12), bottom * (1 - 1e-12)) - 1e-300,
                np.maximum(top * (1 + 1e-12), top * (1 - 1e-12)) + 1e-300)

    def _range(self, lo, hi):
        """(bottom, top, whether the vertices were searched) of :meth:`range`, unrounded."""
        n = self.n
        used = ((lo != 0) | (hi != 0)).any(axis=0).reshape(n, n)
        support = tuple(int(x) for x in np.flatnonzero(used.any(axis=0) | used.any(axis=1)))
        off, mirror, diag, w_off, w_diag, j, l = self._plan(support)
        s_lo = lo[:, off] + lo[:, mirror]
        s_hi = hi[:, off] + hi[:, mirror]
        mid, rad = 0.5 * (s_lo + s_hi), 0.5 * (s_hi - s_lo)
        # row by row (:func:`_dot`): a box's bound does not depend on the batch it is in
        d_hi = _dot(np.maximum(hi[:, diag], 0.0), w_diag)
        d_lo = _dot(np.minimum(lo[:, diag], 0.0), w_diag)
        spread = _dot(rad, w_off)
        if len(support) > self.VERTEX_LIMIT:
            top = _dot(np.abs(mid), w_off) + spread
            return -top + d_lo, top + d_hi, False
        c_max, c_min = vertex_extremes(mid, j, l, w_off, max(len(support), 1))
        return c_min - spread + d_lo, c_max + spread + d_hi, True


def channel_values(robot: Robot, q: np.ndarray, columns: ArrayLike,
                   gravity: ArrayLike | None = None) -> np.ndarray:
    """The coefficient functions at points q: every channel, joint and column.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : ndarray, shape (B, n)
        Joint positions [rad or m].
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c (link k, :data:`gd_analyze.dynamics.base_parameters.PARAMETER_NAMES` c).
    gravity : array_like, shape (3,), optional
        [m/s^2]; default the robot's.

    Returns
    -------
    ndarray, shape (B, C, n, m)
        Channel 0: G(q) [N m or N per unit parameter]; channel 1 + j: A_j(q); channel
        1 + n + n j + l: C_jl(q) (not symmetrized), C = :func:`channel_count`.

    Raises
    ------
    ValueError
        If q does not have n columns.

    Notes
    -----
    W(q, qd, qdd) = sum_j A_j qdd_j + sum_{j, l} C_jl qd_j qd_l + G, with the regressor W of
    :func:`gd_analyze.dynamics.base_parameters.regressor`.
    """
    q = np.asarray(q, float)
    if q.ndim != 2 or q.shape[1] != robot.n:
        raise ValueError(f"q must have shape (B, {robot.n}), got {q.shape}")
    columns = np.asarray(columns, int)
    out = np.zeros((q.shape[0], channel_count(robot.n), robot.n, columns.size))
    for ms, i, (value, _) in _column_groups(robot, q, q, columns, gravity, algebra=_Point):
        out[:, :, i, ms] = value
    return out


def _boxes(robot, q_lo, q_hi):
    """The boxes as float arrays, checked: shape (B, n) each, lo <= hi."""
    q_lo, q_hi = np.asarray(q_lo, float), np.asarray(q_hi, float)
    n = robot.n
    if q_lo.shape != q_hi.shape or q_lo.ndim != 2 or q_lo.shape[1] != n:
        raise ValueError(f"boxes must have shape (B, {n})")
    if np.any(q_lo > q_hi):
        raise ValueError("a box has lo > hi")
    return q_lo, q_hi


def pair_magnitudes(robot: Robot, q_lo: np.ndarray, q_hi: np.ndarray, columns: ArrayLike,
                    qd_max: ArrayLike, qdd_max: ArrayLike, gravity: ArrayLike | None = None
                    ) -> np.ndarray:
    """Upper bounds of each column's three parts over boxes of q and the velocity and
    acceleration limits, per joint.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q_lo, q_hi : ndarray, shape (B, n)
        The boxes [rad or m], q_lo <= q_hi.
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c.
    qd_max, qdd_max : array_like, shape (n,)
        Velocity and acceleration limits [rad/s, m/s; rad/s^2, m/s^2].
    gravity : array_like, shape (3,), optional
        [m/s^2]; default the robot's.

    Returns
    -------
    ndarray, shape (B, 3, n, m)
        ``U[b, p, i, m]`` >= |part p of column m at joint i| for every q in box b, |qd| <=
        qd_max and |qdd| <= qdd_max: p = 0 inertial, sum_j max|A_j| qdd_max_j; p = 1
        velocity, max over the velocity box of |qd^T C qd| (:class:`_QuadraticBound`); p = 2
        gravity, max|G| [N m or N per unit parameter].

    Raises
    ------
    ValueError
        If the boxes do not have n columns or lo > hi somewhere.

    Notes
    -----
    qdd enters linearly and qd quadratically, so both enter through their bounds exactly;
    over q the bound is the enclosure of the recursion in midpoint-radius balls
    (:mod:`.balls`: rotations do not wrap), evaluated link by link, in the link's own
    channels, by the compiled kernels of :mod:`.ball_kernels` (Moore, Kearfott & Cloud 2009),
    rounded outward.
    """
    q_lo, q_hi = _boxes(robot, q_lo, q_hi)
    n = robot.n
    qd_max, qdd_max = np.asarray(qd_max, float), np.asarray(qdd_max, float)
    columns = np.asarray(columns, int)
    out = np.zeros((q_lo.shape[0], 3, n, columns.size))
    quads: dict[int, _QuadraticBound] = {}
    for k, ms, _, lo_k, hi_k in _ball_links(robot, q_lo, q_hi, columns, gravity):
        kk = k + 1
        quad_k = quads.setdefault(kk, _QuadraticBound(kk, qd_max[:kk]))
        for i in range(k, -1, -1):
            lo, hi = lo_k[:, i].transpose(0, 2, 1), hi_k[:, i].transpose(0, 2, 1)
            out[:, :, i, ms] = _parts(lo, hi, quad_k, qdd_max[:kk])
    return out * (1.0 + 8 * iv.ROUNDING * (2 * n + 2))


def _parts(lo, hi, quad, qdd_max):
    """The three parts' magnitudes (B, 3, ...) of channel enclosures (B, C, ...) over the
    velocity and acceleration limits, before :func:`pair_magnitudes`'s rounding margin."""
    n = qdd_max.size
    B, rest = lo.shape[0], lo.shape[2:]
    vel = [np.moveaxis(x[:, 1 + n:], 1, -1).reshape(-1, n * n) for x in (lo, hi)]
    return np.stack([
        np.einsum("bj...,j->b...", iv.magnitude((lo[:, 1:1 + n], hi[:, 1:1 + n])), qdd_max),
        quad(*vel).reshape((B,) + rest),
        iv.magnitude((lo[:, 0], hi[:, 0]))], axis=1)


def channel_magnitudes(lo: np.ndarray, hi: np.ndarray, qd_max: ArrayLike,
                       qdd_max: ArrayLike) -> np.ndarray:
    """:func:`pair_magnitudes` from the channel enclosures of :func:`channel_enclosures`.

    Parameters
    ----------
    lo, hi : ndarray, shape (B, C, n, m)
        Enclosures of the channels of m columns over B boxes (C = :func:`channel_count`)
        [N m or N per unit parameter].
    qd_max, qdd_max : array_like, shape (n,)
        Velocity and acceleration limits [rad/s, m/s; rad/s^2, m/s^2].

    Returns
    -------
    ndarray, shape (B, 3, n, m)
        As :func:`pair_magnitudes` (without ``vertices``): per box, part (inertial,
        velocity, gravity), joint and column, an upper bound of |part| over the box and the
        limits, with the same rounding margin.
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    n = lo.shape[2]
    qd_max, qdd_max = np.asarray(qd_max, float), np.asarray(qdd_max, float)
    return _parts(lo, hi, _QuadraticBound(n, qd_max), qdd_max) * (
        1.0 + 8 * iv.ROUNDING * (2 * n + 2))


#: Arms of at most this many joints have their channels enclosed in both arithmetics,
#: intersected (:func:`channel_enclosures`); longer chains in balls alone (the boxes wrap far
#: down a chain, and their recursion's cost grows as the balls' does).
BOX_MAX_JOINTS = 8

#: Called with each compiled kernel of the enclosures before it runs: none by default; the
#: shell's wait for a second process compiling the kernel ahead on a first run
#: (:func:`gd_analyze.jobs.compile_ahead.ready`). Nothing is computed differently.
BEFORE_KERNEL: list[Callable[[Any], None]] = []


def _before(kernel):
    for hook in BEFORE_KERNEL:
        hook(kernel)


def joint_sum_arithmetic(n: int) -> str:
    """The arithmetic of :func:`channel_enclosures` (the joint sums' enclosures) on n joints.

    Parameters
    ----------
    n : int
        The arm's joints.

    Returns
    -------
    str
        ``"both"`` (balls and interval boxes, intersected) up to :data:`BOX_MAX_JOINTS`
        joints, else ``"ball"``.

    Examples
    --------
    >>> joint_sum_arithmetic(6), joint_sum_arithmetic(12)
    ('both', 'ball')
    """
    return "both" if n <= BOX_MAX_JOINTS else "ball"


def channel_enclosures(robot: Robot, q_lo: np.ndarray, q_hi: np.ndarray, columns: ArrayLike,
                       gravity: ArrayLike | None = None, arithmetic: str | None = None
                       ) -> tuple[np.ndarray, np.ndarray]:
    """Signed enclosures of every channel of each column over boxes of q.

    Parameters
    ----------
    robot, q_lo, q_hi, columns, gravity
        As :func:`pair_magnitudes`: the arm (n joints), the boxes (B, n) [rad or m], the m
        flat standard-parameter indices 10 k + c, and gravity (3,) [m/s^2], default the
        robot's.
    arithmetic : {"ball", "box", "both"}, optional
        Midpoint-radius balls, interval boxes, or both intersected; default both on arms of at
        most :data:`BOX_MAX_JOINTS` joints, else balls.

    Returns
    -------
    lo, hi : ndarray, shape (B, C, n, m)
        lo <= channel <= hi for every q in each box (channels as :func:`channel_values`, C =
        :func:`channel_count`) [N m or N per unit parameter], by midpoint-radius evaluation of
        the recursion (:func:`pair_magnitudes`'s, without its final rounding margin), compiled
        (:mod:`.ball_kernels`), and by its interval evaluation, compiled
        (:mod:`.box_kernels`).

    Raises
    ------
    ValueError
        If the boxes do not have n columns, lo > hi somewhere, or the arithmetic is unknown.

    Notes
    -----
    These are what :func:`pair_magnitudes` takes the magnitudes of; kept signed, the
    enclosures of several columns can be added before the velocity and acceleration limits
    are applied (:func:`combined_bound`), so that contributions of opposite signs cancel.
    Each arithmetic encloses every channel, so their intersection does (Moore, Kearfott &
    Cloud 2009, Ch. 6); the balls are the tighter on gravity and far down a chain, the boxes
    on the inertial and velocity channels near the column's own joint (a ball gives a
    vector's three components one radius).
    """
    q_lo, q_hi = _boxes(robot, q_lo, q_hi)
    n = robot.n
    if arithmetic is None:
        arithmetic = joint_sum_arithmetic(n)
    if arithmetic not in ("ball", "box", "both"):
        raise ValueError(f"arithmetic must be 'ball', 'box' or 'both', got {arithmetic!r}")
    columns = np.asarray(columns, int)
    shape = (q_lo.shape[0], channel_count(n), n, columns.size)
    lo, hi = np.zeros(shape), np.zeros(shape)
    if arithmetic != "ball":
        _boxes_and_balls(robot, q_lo, q_hi, columns, gravity, arithmetic == "box", lo, hi)
        return lo, hi
    for k, ms, ch, lo_k, hi_k in _ball_links(robot, q_lo, q_hi, columns, gravity):
        for i in range(k + 1):
            lo[:, ch[:, None], i, ms[None, :]] = lo_k[:, i].transpose(0, 2, 1)
            hi[:, ch[:, None], i, ms[None, :]] = hi_k[:, i].transpose(0, 2, 1)
    return lo, hi


def _boxes_and_balls(robot, q_lo, q_hi, columns, gravity, alone, lo, hi):
    """:func:`channel_enclosures` in both arithmetics, intersected (or, ``alone``, in boxes
    alone), written into ``lo`` and ``hi`` (B, C, n, m): the forward recursions compiled
    apart (the boxes intersected with the balls link by link), the backward ones together,
    link by link (:func:`.box_kernels.both_backward_kernel`). In boxes alone, the array code
    of :func:`_column_groups` in the box algebra of ``tests/interval_oracle.py`` is the
    kernels' test oracle."""
    forward = _forward_balls(robot, q_lo, q_hi, columns, gravity)
    if forward is None:
        return
    top, A, P, t, pris, norms, g, (W, WD, VD) = forward
    columns = np.asarray(columns, int)
    q_lo, q_hi = np.ascontiguousarray(q_lo), np.ascontiguousarray(q_hi)
    _before(box_forward_kernel)
    X, XD, XV = box_forward_kernel(q_lo, q_hi, P, t, pris, g, top,
                                   None if alone else (W, WD, VD))
    _before(both_backward_kernel)
    for k, ms, _, _, ch in _links(columns, top, robot.n):
        both_backward_kernel(k, np.ascontiguousarray(columns[ms] % 10), ms, ch,
                             (W[k], WD[k], VD[k]), (X[k], XD[k], XV[k]), A.mid, A.half, norms,
                             q_lo, q_hi, P, t, pris, top, alone, lo, hi)


def combined_bound(mid: np.ndarray, rad: np.ndarray, qd_max: ArrayLike,
                   qdd_max: ArrayLike) -> np.ndarray:
    """Upper bound of |G + sum_j A_j qdd_j + qd^T C qd| over boxes of q and the velocity and
    acceleration limits, from enclosures of the channels in midpoint-radius form.

    Parameters
    ----------
    mid, rad : ndarray, shape (B, C, n)
        Per box, channel (:func:`channel_values`' order) and joint: every value of the channel
        over the box lies in [mid - rad, mid + rad] [N m or N], rad >= 0.
    qd_max, qdd_max : array_like, shape (n,)
        [rad/s, m/s; rad/s^2, m/s^2].

    Returns
    -------
    ndarray, shape (B, n)
        >= |tau_i| for the torque of these coefficients at every q of the box, |qd| <= qd_max,
        |qdd| <= qdd_max [N m or N].

    Notes
    -----
    Over the box, G <= mid_G + rad_G, sum_j A_j qdd_j <= a = sum_j max|A_j| qdd_max_j and
    qd^T C qd <= top (:class:`_QuadraticBound`), and the same from below, so |tau| <=
    max(G_hi + a + top, -(G_lo - a + bottom)): the parts are bounded together, not each in
    absolute value. An absolute margin of (8 n^2 + 32) machine epsilons times the terms'
    magnitudes covers the round-off of the sums (Higham 2002, Sec. 3.1).
    """
    mid, rad = np.asarray(mid, float), np.asarray(rad, float)
    B, _, n = mid.shape
    qd_max, qdd_max = np.asarray(qd_max, float), np.asarray(qdd_max, float)
    mag = np.abs(mid) + rad
    g_lo, g_hi = mid[:, 0] - rad[:, 0], mid[:, 0] + rad[:, 0]                 # (B, n)
    a = np.einsum("bji,j->bi", mag[:, 1:1 + n], qdd_max)
    vel = (slice(None), slice(1 + n, None))
    c_lo = (mid[vel] - rad[vel]).transpose(0, 2, 1).reshape(B * n, n * n)
    c_hi = (mid[vel] + rad[vel]).transpose(0, 2, 1).reshape(B * n, n * n)
    bottom, top = _QuadraticBound(n, qd_max).range(c_lo, c_hi)
    bottom, top = bottom.reshape(B, n), top.reshape(B, n)
    form = np.einsum("bci,c->bi", mag[vel], np.outer(qd_max, qd_max).reshape(-1))
    slack = (8 * n * n + 32) * iv.ROUNDING * (np.abs(mag[:, 0]) + a + form)
    out = np.maximum(g_hi + a + top, -(g_lo - a + bottom))
    return np.maximum(out, 0.0) * (1 + 8 * iv.ROUNDING * (2 * n + 4)) + slack


def _inertia_tensors(values):
    """Per link, the symmetric inertia tensor (3, 3) of its XX, XY, XZ, YY, YZ, ZZ."""
    v = np.asarray(values, float)
    return np.stack([v[:, [0, 1, 2]], v[:, [1, 3, 4]], v[:, [2, 4, 5]]], axis=1)


def _geometry(robot):
    """The joints' placements P (n, 3, 3), translations t (n, 3) [m] and prismatic flags (n,),
    as new writable C arrays: the compiled kernels see one array type whatever the robot
    holds (one compilation each)."""
    return (np.array(robot.rotation, float), np.array(robot.translation, float),
            np.array(robot.prismatic, bool))


def _norms(matrices):
    """Upper bounds of the spectral norms of (m, 3, 3) matrices, as :func:`.balls.matvec`
    takes them."""
    return np.array([balls.spectral_norm(np.asarray(M)) * (1 + 1e-12) for M in matrices])


def inertia_enclosure(robot: Robot, q_lo: np.ndarray, q_hi: np.ndarray, values: np.ndarray,
                      armature: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Enclosures of the inertia matrix D(q) over boxes of joint positions.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q_lo, q_hi : ndarray, shape (B, n)
        The boxes [rad or m], q_lo <= q_hi (q_lo = q_hi: D at points).
    values : ndarray, shape (n, 10)
        Per link, the inertial parameters the matrix is built of, in the order of
        :data:`gd_analyze.dynamics.base_parameters.PARAMETER_NAMES` (XX, XY, XZ, YY, YZ,
        ZZ about the link frame's origin [kg m^2], MX, MY, MZ [kg m], M [kg]): the standard
        parameters give D, the base parameters in their independent slots the same D, and a
        pruned model's kept inertial values its D_s.
    armature : array_like, shape (n,), optional
        Added on the diagonal [kg m^2 or kg]; default the robot's.

    Returns
    -------
    lo, hi : ndarray, shape (B, n, n)
        lo <= D(q) <= hi element by element for every q in each box, symmetric [kg m^2; kg m;
        kg].

    Raises
    ------
    ValueError
        If the boxes do not have n columns, lo > hi somewhere, or values is not (n, 10).

    Notes
    -----
    Column j of D is the torque of the Newton-Euler recursion at qd = 0, qdd = e_j and g = 0
    (Walker & Orin 1982, method 1; Fu, Gonzalez & Lee 1987, Table 3.3), run once for all
    columns in midpoint-radius balls (:mod:`.balls`), rounded outward; each link's wrench is f = m vd +
    wd x (m c) and n = I wd + (m c) x vd with its own parameters (Featherstone 2008, Eq. 2.63
    at zero velocity), so the links' contributions are summed as wrenches before the joints
    take their components. D_ij and D_ji are enclosed separately; their intersection is
    returned. The recursion runs compiled, box by box (:func:`.ball_kernels.inertia_kernel`).
    """
    q_lo, q_hi = _boxes(robot, q_lo, q_hi)
    n = robot.n
    values = np.asarray(values, float)
    if values.shape != (n, 10):
        raise ValueError(f"values must have shape ({n}, 10), got {values.shape}")
    A = _Ball(q_lo, q_hi)
    P, t, pris = _geometry(robot)
    inertia = np.ascontiguousarray(_inertia_tensors(values))
    _before(inertia_kernel)
    lo, hi = inertia_kernel(A.mid, A.half, P, _norms(P), _norms(P.transpose(0, 2, 1)), t,
                            pris, np.array(values, float), inertia, _norms(inertia))
    arm = np.asarray(robot.armature if armature is None else armature, float)
    idx = np.arange(n)
    lo[:, idx, idx] = np.nextafter(lo[:, idx, idx] + arm, -np.inf)
    hi[:, idx, idx] = np.nextafter(hi[:, idx, idx] + arm, np.inf)
    return np.maximum(lo, np.swapaxes(lo, 1, 2)), np.minimum(hi, np.swapaxes(hi, 1, 2))


def _ball_dots(a, b):
    """Enclosures of a_k . b_l for balls a, b of shape (B, C, 3): (lo, hi) of shape (B, C, C)."""
    ca, ra = a
    cb, rb = b
    na, nb = np.linalg.norm(ca, axis=-1), np.linalg.norm(cb, axis=-1)
    c = ca @ np.swapaxes(cb, 1, 2)
    r = (na[:, :, None] * rb[:, None, :] + ra[:, :, None] * nb[:, None, :]
         + ra[:, :, None] * rb[:, None, :]) * (1 + 8 * iv.ROUNDING) \
        + 8 * iv.ROUNDING * na[:, :, None] * nb[:, None, :]
    return c - r, c + r


def inertia_form_enclosure(robot: Robot, q_lo: np.ndarray, q_hi: np.ndarray,
                           values: np.ndarray, X: np.ndarray, armature: ArrayLike | None = None
                           ) -> tuple[np.ndarray, np.ndarray]:
    """Enclosures of X D(q) X^T over boxes of joint positions, for given matrices X.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q_lo, q_hi : ndarray, shape (B, n)
        The boxes [rad or m], q_lo <= q_hi.
    values : ndarray, shape (n, 10)
        Per link, the inertial parameters D is built of (as :func:`inertia_enclosure`).
    X : ndarray, shape (B, C, n)
        Per box, C joint-velocity directions x_k (rows).
    armature : array_like, shape (n,), optional
        Added on D's diagonal [kg m^2 or kg]; default the robot's.

    Returns
    -------
    lo, hi : ndarray, shape (B, C, C)
        lo <= x_k^T D(q) x_l <= hi for every q in each box.

    Raises
    ------
    ValueError
        If the shapes do not match.

    Notes
    -----
    x_k^T D x_l is the polarised kinetic energy (Fu, Gonzalez & Lee 1987, Eq. 3.2-27):
    sum over links of V_k^T M V_l, with V_k = (omega, v) the link's angular velocity and the
    velocity of its frame's origin at qd = x_k (the recursion of Table 3.3 without
    accelerations) and M its spatial inertia about that origin: m v_k . v_l + v_k . (omega_l x
    m c) + v_l . (omega_k x m c) + omega_k . I omega_l. The velocities are midpoint-radius
    balls (:mod:`.balls`), so the cancellations of a direction x in which D is nearly
    singular happen on vectors before any component is taken: the enclosure of x^T D x is
    then narrow where D's elements' enclosures are wide.
    """
    q_lo, q_hi = np.asarray(q_lo, float), np.asarray(q_hi, float)
    n = robot.n
    X = np.asarray(X, float)
    if q_lo.shape != q_hi.shape or q_lo.ndim != 2 or q_lo.shape[1] != n:
        raise ValueError(f"boxes must have shape (B, {n})")
    if np.any(q_lo > q_hi):
        raise ValueError("a box has lo > hi")
    if X.ndim != 3 or X.shape[0] != q_lo.shape[0] or X.shape[2] != n:
        raise ValueError(f"X must have shape ({q_lo.shape[0]}, C, {n})")
    values = np.asarray(values, float)
    if values.shape != (n, 10):
        raise ValueError(f"values must have shape ({n}, 10), got {values.shape}")
    chain = _Chain(robot, q_lo, q_hi, _Ball)
    A, B, C = chain.A, chain.B, X.shape[1]
    w, v = A.zeros((B, C)), A.zeros((B, C))
    lo, hi = np.zeros((B, C, C)), np.zeros((B, C, C))
    for k in range(n):
        v = chain.rot_t(k, A.add(v, A.cross(w, chain.p(k))))
        w = chain.rot_t(k, w)
        unit = np.zeros((B, C, 3))
        unit[..., 2] = X[:, :, k]
        if chain.pris[k]:
            v = A.add(v, A.point(unit))
        else:
            w = A.add(w, A.point(unit))
        p = values[k]
        if not np.any(p):
            continue
        inertia = np.array([[p[0], p[1], p[2]], [p[1], p[3], p[4]], [p[2], p[4], p[5]]])
        g = A.cross(w, A.point(p[6:9]))                           # omega x m c
        vv = iv.scale(_ball_dots(v, v), p[9])
        vg = _ball_dots(v, g)
        term = iv.add(iv.add(vv, vg), (np.swapaxes(vg[0], 1, 2), np.swapaxes(vg[1], 1, 2)))
        term = iv.add(term, _ball_dots(w, A.matvec(inertia, w)))
        lo, hi = iv.add((lo, hi), term)
    arm = np.asarray(robot.armature if armature is None else armature, float)
    if np.any(arm):
        Xa = X * arm[None, None, :]
        c = Xa @ np.swapaxes(X, 1, 2)
        r = 4 * (n + 2) * iv.ROUNDING * (np.abs(Xa) @ np.swapaxes(np.abs(X), 1, 2))
        lo, hi = iv.add((lo, hi), (c - r, c + r))
    return np.maximum(lo, np.swapaxes(lo, 1, 2)), np.minimum(hi, np.swapaxes(hi, 1, 2))
