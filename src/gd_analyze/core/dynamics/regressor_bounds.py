"""The regressor's coefficient functions of q, enclosed over boxes of joint positions.

The joint torques are linear in the inertial parameters, tau = W(q, qd, qdd) phi
(:func:`gd_analyze.core.symbolic.base_parameters.regressor`), and each column of W splits into

    W(q, qd, qdd) = sum_j A_j(q) qdd_j + sum_{j, l} C_jl(q) qd_j qd_l + G(q)

(inertial, velocity and gravity parts: the D qdd, h and c of Eq. (3.4-24)). This module runs
the recursive Newton-Euler regressor recursion (Fu, Gonzalez & Lee 1987, Table 3.3; Khalil &
Kleinfinger 1987) once per *channel*: gravity G (qd = qdd = 0), the inertial channels A_j
(qdd = e_j, g = 0) and the bilinear velocity channels C_jl (the coefficient of qd_j qd_l,
g = 0), in the interval arithmetic of :mod:`.intervals`, over a batch of boxes of q. The result
encloses every coefficient over its box; with degenerate boxes it evaluates them at points.
"""

from __future__ import annotations

import numpy as np

from . import intervals as iv

__all__ = ["channel_count", "channel_values", "pair_magnitudes"]


def channel_count(n):
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


def _zeros(shape):
    z = np.zeros(shape)
    return z, z.copy()


def _take(a, index):
    return a[0][:, index], a[1][:, index]


def _put(a, index, value):
    a[0][:, index], a[1][:, index] = value


def _rotz(c, s, v, transpose):
    """Rz(q) v or Rz(q)^T v for interval cos c and sin s of shape (B,), v (B, C, 3)."""
    cb = (c[0][:, None], c[1][:, None])
    sb = (s[0][:, None], s[1][:, None])
    x, y = (v[0][..., 0], v[1][..., 0]), (v[0][..., 1], v[1][..., 1])
    if transpose:
        nx = iv.add(iv.mul(cb, x), iv.mul(sb, y))
        ny = iv.sub(iv.mul(cb, y), iv.mul(sb, x))
    else:
        nx = iv.sub(iv.mul(cb, x), iv.mul(sb, y))
        ny = iv.add(iv.mul(sb, x), iv.mul(cb, y))
    return (np.stack([nx[0], ny[0], v[0][..., 2]], -1),
            np.stack([nx[1], ny[1], v[1][..., 2]], -1))


class _Chain:
    """The joint geometry over a batch of boxes: R_k v, R_k^T v and p_k as intervals."""

    def __init__(self, robot, q_lo, q_hi):
        self.robot = robot
        self.P = np.asarray(robot.rotation, float)
        self.t = np.asarray(robot.translation, float)
        self.pris = np.asarray(robot.prismatic, bool)
        self.cs = iv.cos_sin(q_lo, q_hi)
        self.q = (q_lo, q_hi)

    def _trig(self, k):
        (clo, chi), (slo, shi) = self.cs
        return (clo[:, k], chi[:, k]), (slo[:, k], shi[:, k])

    def rot_t(self, k, v):
        """R_k^T v = Rz(q_k)^T P_k^T v (revolute) or P_k^T v (prismatic)."""
        u = iv.matvec(self.P[k].T, v)
        if self.pris[k]:
            return u
        c, s = self._trig(k)
        return _rotz(c, s, u, transpose=True)

    def rot(self, k, v):
        """R_k v = P_k Rz(q_k) v (revolute) or P_k v (prismatic)."""
        if not self.pris[k]:
            c, s = self._trig(k)
            v = _rotz(c, s, v, transpose=False)
        return iv.matvec(self.P[k], v)

    def p(self, k):
        """p_k, shape (B, 1, 3): t_k, plus q_k P_k z for a prismatic joint."""
        B = self.q[0].shape[0]
        base = np.broadcast_to(self.t[k], (B, 1, 3))
        if not self.pris[k]:
            return base, base
        dz = self.P[k][:, 2]
        ql, qh = self.q[0][:, k, None, None], self.q[1][:, k, None, None]
        lo = np.minimum(ql * dz, qh * dz)
        hi = np.maximum(ql * dz, qh * dz)
        return iv.add((base, base), (lo, hi))


def _unit(c):
    e = np.zeros(3)
    e[c] = 1.0
    return e


def _forward(chain, gravity):
    """Per link k: w (B, n, 3) per velocity j, and wd, vd (B, C, 3) per channel."""
    robot = chain.robot
    n = robot.n
    B = chain.q[0].shape[0]
    C = channel_count(n)
    jj, ll = np.divmod(np.arange(n * n), n)
    vel = 1 + n + np.arange(n * n)
    z = np.array([0.0, 0.0, 1.0])
    w = _zeros((B, n, 3))
    wd = _zeros((B, C, 3))
    vd = _zeros((B, C, 3))
    g = -np.asarray(gravity, float)
    vd[0][:, 0], vd[1][:, 0] = g, g
    out = []
    for k in range(n):
        p = chain.p(k)
        a = iv.add(vd, iv.cross(wd, p))
        wj, wl = _take(w, jj), _take(w, ll)
        _put(a, vel, iv.add(_take(a, vel), iv.cross(wj, iv.cross(wl, p))))
        vd = chain.rot_t(k, a)
        wp = chain.rot_t(k, w)
        wd = chain.rot_t(k, wd)
        zk = iv.cross(_take(wp, jj[ll == k]), iv.point(z))      # (R^T w^(j)) x z, channel (j, k)
        target = vel[ll == k]
        if chain.pris[k]:
            vd[0][:, 1 + k, 2] += 1.0
            vd[1][:, 1 + k, 2] += 1.0
            _put(vd, target, iv.add(_take(vd, target), iv.scale(zk, 2.0)))
            w = wp
        else:
            wd[0][:, 1 + k, 2] += 1.0
            wd[1][:, 1 + k, 2] += 1.0
            _put(wd, target, iv.add(_take(wd, target), zk))
            wp[0][:, k, 2] += 1.0
            wp[1][:, k, 2] += 1.0
            w = wp
        out.append((w, wd, vd))
    return out


def _wrench(c, w, wd, vd, jj, ll, vel):
    """Force and moment of a link per unit standard parameter c, per channel (B, C, 3)."""
    zero = _zeros(wd[0].shape)
    wa = _zeros(wd[0].shape)
    wb = _zeros(wd[0].shape)
    _put(wa, vel, _take(w, jj))
    _put(wb, vel, _take(w, ll))
    if c < 6:
        a, b = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))[c]

        def E(x):                        # E x for the symmetric unit E of (a, b)
            lo, hi = np.zeros_like(x[0]), np.zeros_like(x[1])
            lo[..., a], hi[..., a] = x[0][..., b], x[1][..., b]
            if a != b:
                lo[..., b], hi[..., b] = x[0][..., a], x[1][..., a]
            return lo, hi
        return zero, iv.add(E(wd), iv.cross(wa, E(wb)))
    if c < 9:
        e = iv.point(_unit(c - 6))
        force = iv.add(iv.cross(wd, e), iv.cross(wa, iv.cross(wb, e)))
        return force, iv.cross(e, vd)
    return vd, zero


def _columns(robot, q_lo, q_hi, columns, gravity, reduce):
    chain = _Chain(robot, q_lo, q_hi)
    n = robot.n
    links = _forward(chain, robot.gravity if gravity is None else gravity)
    jj, ll = np.divmod(np.arange(n * n), n)
    vel = 1 + n + np.arange(n * n)
    for m, col in enumerate(np.asarray(columns, int)):
        k, c = divmod(int(col), 10)
        w, wd, vd = links[k]
        f, mom = _wrench(c, w, wd, vd, jj, ll, vel)
        for i in range(k, -1, -1):
            yield m, i, (mom if not chain.pris[i] else f)
            if i == 0:
                break
            f = chain.rot(i, f)
            mom = iv.add(chain.rot(i, mom), iv.cross(chain.p(i), f))


def channel_values(robot, q, columns, gravity=None):
    """The coefficient functions at points q: every channel, joint and column.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : ndarray, shape (B, n)
        Joint positions [rad or m].
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c (link k, :data:`PARAMETER_NAMES` c).
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
    :func:`gd_analyze.core.symbolic.base_parameters.regressor`.
    """
    q = np.asarray(q, float)
    if q.ndim != 2 or q.shape[1] != robot.n:
        raise ValueError(f"q must have shape (B, {robot.n}), got {q.shape}")
    columns = np.asarray(columns, int)
    out = np.zeros((q.shape[0], channel_count(robot.n), robot.n, columns.size))
    for m, i, val in _columns(robot, q, q, columns, gravity, False):
        out[:, :, i, m] = 0.5 * (val[0][..., 2] + val[1][..., 2])
    return out


def pair_magnitudes(robot, q_lo, q_hi, columns, qd_max, qdd_max, gravity=None):
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
        velocity, sum_{j <= l} max|C_jl + C_lj (j < l), C_jj| qd_max_j qd_max_l; p = 2 gravity,
        max|G| [N m or N per unit parameter].

    Raises
    ------
    ValueError
        If the boxes do not have n columns or lo > hi somewhere.

    Notes
    -----
    qdd enters linearly and qd quadratically, so both enter through their bounds exactly;
    over q the bound is the interval enclosure of :mod:`.intervals` (Moore, Kearfott & Cloud
    2009), rounded outward.
    """
    q_lo, q_hi = np.asarray(q_lo, float), np.asarray(q_hi, float)
    n = robot.n
    if q_lo.shape != q_hi.shape or q_lo.ndim != 2 or q_lo.shape[1] != n:
        raise ValueError(f"boxes must have shape (B, {n})")
    if np.any(q_lo > q_hi):
        raise ValueError("a box has lo > hi")
    qd_max, qdd_max = np.asarray(qd_max, float), np.asarray(qdd_max, float)
    columns = np.asarray(columns, int)
    jj, ll = np.divmod(np.arange(n * n), n)
    upper = jj <= ll
    sym = np.flatnonzero(upper)
    mirror = ll[sym] * n + jj[sym]                      # C_lj for each j <= l
    weight_v = qd_max[jj[sym]] * qd_max[ll[sym]]
    out = np.zeros((q_lo.shape[0], 3, n, columns.size))
    for m, i, val in _columns(robot, q_lo, q_hi, columns, gravity, True):
        lo, hi = val[0][..., 2], val[1][..., 2]                   # (B, C)
        out[:, 2, i, m] = iv.magnitude((lo[:, 0], hi[:, 0]))
        out[:, 0, i, m] = iv.magnitude((lo[:, 1:1 + n], hi[:, 1:1 + n])) @ qdd_max
        v = (lo[:, 1 + n:], hi[:, 1 + n:])
        both = iv.add((v[0][:, sym], v[1][:, sym]), (v[0][:, mirror], v[1][:, mirror]))
        diag = jj[sym] == ll[sym]
        mag = np.where(diag, iv.magnitude((v[0][:, sym], v[1][:, sym])), iv.magnitude(both))
        out[:, 1, i, m] = mag @ weight_v
    return out * (1.0 + 8 * iv.ROUNDING * (2 * n + 2))
