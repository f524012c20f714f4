"""Compiled regressor recursion: the numba kernel of the regressor contributions.

:func:`_contributions_kernel` is a numba loop over set points of the recursion of
:func:`.base_parameters.regressor` (Khalil & Kleinfinger 1987; Fu, Gonzalez & Lee 1987, Table
3.3), restricted to the independent columns: per part, the outward recursion of w, wd, vd in
body frames (base acceleration -g for the gravity part, Eq. (3.3-46)), the wrench of every
link per unit base parameter, F = M vd + U MS, N = J wd + w x (J w) + MS x vd with
U = skew(wd) + skew(w)^2, carried inward f_{i-1} = R_i f_i, n_{i-1} = R_i n_i + p_i x f_{i-1}
and read on every joint's axis. :func:`_channels_kernel` gives the same regressor's
coefficient functions of q (gravity, per unit qdd_j, per qd_j qd_l) from each position's
frames and link Jacobians, in one outward pass.

This module imports numba: :mod:`.regressor_kernels` imports it by its first call only.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = []

#: (row, column) of the inertia-tensor entry of the parameters XX, XY, XZ, YY, YZ, ZZ.
_JA = np.array([0, 0, 0, 1, 1, 2], np.int64)
_JB = np.array([0, 1, 2, 1, 2, 2], np.int64)


@njit(cache=True, fastmath=False, nogil=True)
def _frames(q, Rp, tp, pris, top, R, p):  # pragma: no cover
    """Into R (n, 3, 3) and p (n, 3): ^{i-1}R_i and ^{i-1}p_i [m] of the joints i < top at the
    position q (n,) [rad or m]."""
    for i in range(top):
        if pris[i] != 0:
            for r in range(3):
                for u in range(3):
                    R[i, r, u] = Rp[i, r, u]
                p[i, r] = tp[i, r] + q[i] * Rp[i, r, 2]
        else:
            ci, si = np.cos(q[i]), np.sin(q[i])
            for r in range(3):
                R[i, r, 0] = ci * Rp[i, r, 0] + si * Rp[i, r, 1]
                R[i, r, 1] = ci * Rp[i, r, 1] - si * Rp[i, r, 0]
                R[i, r, 2] = Rp[i, r, 2]
                p[i, r] = tp[i, r]


@njit(cache=True, fastmath=False, nogil=True)
def _contributions_kernel(q, qd, qdd, Rp, tp, pris, gravity, link, param, beta,
                          store, contrib, tau_peak, peak, whole_peak):  # pragma: no cover
    """Contributions of every (set point, part, joint, base parameter), or their peaks.

    Parameters
    ----------
    q, qd, qdd : ndarray, shape (N, n)
        Joint positions, velocities, accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    Rp, tp : ndarray, shape (n, 3, 3), (n, 3)
        Placement rotations and translations [m] of the joint model.
    pris : ndarray of int, shape (n,)
        1 for a prismatic joint.
    gravity : ndarray, shape (3,)
        Gravity in the base frame [m/s^2].
    link, param : ndarray of int, shape (b,)
        Link (0-based) and standard parameter (0..9) of every base parameter, link-major.
    beta : ndarray, shape (b,)
        Base parameter values.
    store : bool
        Write ``contrib``; else only the peaks are updated.
    contrib : ndarray, shape (N, 3, n, b)
        Output if ``store`` (else any array).
    tau_peak, peak, whole_peak : ndarray, shape (n,), (b, 3, n), (b, n)
        Running peaks, updated in place by maximum.
    """
    N, n = q.shape
    b = beta.shape[0]
    R = np.empty((n, 3, 3))
    p = np.empty((n, 3))
    w = np.empty((n, 3))
    wd = np.empty((n, 3))
    vd = np.empty((n, 3))
    f = np.empty(3)
    m = np.empty(3)
    a = np.empty(3)
    val = np.empty((3, n, b))
    for k in range(N):
        _frames(q[k], Rp, tp, pris, n, R, p)   # joint frames (kinematics.transforms_core)
        for part in range(3):
            # outward recursion (base_parameters._forward)
            w0x = w0y = w0z = e0x = e0y = e0z = 0.0
            if part == 2:
                v0x, v0y, v0z = -gravity[0], -gravity[1], -gravity[2]
            else:
                v0x = v0y = v0z = 0.0
            for j in range(n):
                px, py, pz = p[j, 0], p[j, 1], p[j, 2]
                cx = w0y * pz - w0z * py
                cy = w0z * px - w0x * pz
                cz = w0x * py - w0y * px
                a[0] = v0x + (e0y * pz - e0z * py) + (w0y * cz - w0z * cy)
                a[1] = v0y + (e0z * px - e0x * pz) + (w0z * cx - w0x * cz)
                a[2] = v0z + (e0x * py - e0y * px) + (w0x * cy - w0y * cx)
                for r in range(3):
                    vd[j, r] = R[j, 0, r] * a[0] + R[j, 1, r] * a[1] + R[j, 2, r] * a[2]
                    w[j, r] = R[j, 0, r] * w0x + R[j, 1, r] * w0y + R[j, 2, r] * w0z
                    wd[j, r] = R[j, 0, r] * e0x + R[j, 1, r] * e0y + R[j, 2, r] * e0z
                u = qd[k, j] if part == 1 else 0.0
                acc = qdd[k, j] if part == 0 else 0.0
                if pris[j] != 0:
                    vd[j, 2] += acc
                    vd[j, 0] += 2.0 * (w[j, 1] * u)
                    vd[j, 1] += 2.0 * (-(w[j, 0] * u))
                else:
                    wd[j, 0] += w[j, 1] * u
                    wd[j, 1] += -(w[j, 0] * u)
                    wd[j, 2] += acc
                    w[j, 2] += u
                w0x, w0y, w0z = w[j, 0], w[j, 1], w[j, 2]
                e0x, e0y, e0z = wd[j, 0], wd[j, 1], wd[j, 2]
                v0x, v0y, v0z = vd[j, 0], vd[j, 1], vd[j, 2]
            # per base parameter: its link's wrench per unit parameter, carried inward
            for c in range(b):
                j, prm = link[c], param[c]
                wx, wy, wz = w[j, 0], w[j, 1], w[j, 2]
                ex, ey, ez = wd[j, 0], wd[j, 1], wd[j, 2]
                if prm < 6:             # inertia tensor entry: N = E wd + w x (E w)
                    ia, ib = _JA[prm], _JB[prm]
                    for r in range(3):
                        f[r] = 0.0
                        m[r] = 0.0
                        a[r] = 0.0
                    m[ia] = wd[j, ib]
                    m[ib] = wd[j, ia]
                    a[ia] = w[j, ib]
                    a[ib] = w[j, ia]
                    m[0] += wy * a[2] - wz * a[1]
                    m[1] += wz * a[0] - wx * a[2]
                    m[2] += wx * a[1] - wy * a[0]
                elif prm < 9:           # first moment: F = U e, N = e x vd
                    e = prm - 6
                    # U = skew(wd) + skew(w) skew(w), column e
                    if e == 0:
                        f[0] = -(wy * wy) - wz * wz
                        f[1] = ez + wx * wy
                        f[2] = -ey + wx * wz
                        m[0], m[1], m[2] = 0.0, -vd[j, 2], vd[j, 1]
                    elif e == 1:
                        f[0] = -ez + wx * wy
                        f[1] = -(wx * wx) - wz * wz
                        f[2] = ex + wy * wz
                        m[0], m[1], m[2] = vd[j, 2], 0.0, -vd[j, 0]
                    else:
                        f[0] = ey + wx * wz
                        f[1] = -ex + wy * wz
                        f[2] = -(wx * wx) - wy * wy
                        m[0], m[1], m[2] = -vd[j, 1], vd[j, 0], 0.0
                else:                   # mass: F = vd
                    f[0], f[1], f[2] = vd[j, 0], vd[j, 1], vd[j, 2]
                    m[0] = m[1] = m[2] = 0.0
                for i in range(n):
                    val[part, i, c] = 0.0
                for i in range(j, -1, -1):
                    val[part, i, c] = (f[2] if pris[i] != 0 else m[2]) * beta[c]
                    if i == 0:
                        break
                    f0 = R[i, 0, 0] * f[0] + R[i, 0, 1] * f[1] + R[i, 0, 2] * f[2]
                    f1 = R[i, 1, 0] * f[0] + R[i, 1, 1] * f[1] + R[i, 1, 2] * f[2]
                    f2 = R[i, 2, 0] * f[0] + R[i, 2, 1] * f[1] + R[i, 2, 2] * f[2]
                    m0 = R[i, 0, 0] * m[0] + R[i, 0, 1] * m[1] + R[i, 0, 2] * m[2]
                    m1 = R[i, 1, 0] * m[0] + R[i, 1, 1] * m[1] + R[i, 1, 2] * m[2]
                    m2 = R[i, 2, 0] * m[0] + R[i, 2, 1] * m[1] + R[i, 2, 2] * m[2]
                    px, py, pz = p[i, 0], p[i, 1], p[i, 2]
                    m[0] = m0 + (py * f2 - pz * f1)
                    m[1] = m1 + (pz * f0 - px * f2)
                    m[2] = m2 + (px * f1 - py * f0)
                    f[0], f[1], f[2] = f0, f1, f2
        if store:
            for part in range(3):
                for i in range(n):
                    for c in range(b):
                        contrib[k, part, i, c] = val[part, i, c]
        for i in range(n):
            t = 0.0
            for c in range(b):
                s = val[0, i, c] + val[1, i, c] + val[2, i, c]
                t += s
                v = abs(s)
                if v > whole_peak[c, i]:
                    whole_peak[c, i] = v
                for part in range(3):
                    v = abs(val[part, i, c])
                    if v > peak[c, part, i]:
                        peak[c, part, i] = v
            t = abs(t)
            if t > tau_peak[i]:
                tau_peak[i] = t


@njit(cache=True, fastmath=False, nogil=True)
def _channels_kernel(q, Rp, tp, pris, gravity, top, start, param, offset,
                     out):  # pragma: no cover
    """The regressor's coefficient functions of q, per link, at every position.

    Parameters
    ----------
    q : ndarray, shape (B, n)
        Joint positions [rad or m].
    Rp, tp : ndarray, shape (n, 3, 3), (n, 3)
        Placement rotations and translations [m] of the joint model.
    pris : ndarray of int, shape (n,)
        1 for a prismatic joint.
    gravity : ndarray, shape (3,)
        Gravity in the base frame [m/s^2].
    top : int
        Links visited (the last link with columns, plus one).
    start : ndarray of int, shape (n + 1,)
        The columns of link k are ``param[start[k]:start[k + 1]]``.
    param : ndarray of int, shape (m,)
        Standard parameter (0..9) of every column, link-major.
    offset : ndarray of int, shape (n,)
        Where link k's block (B, P, M, m_k) begins in ``out`` (M = k + 1, P = 1 + M + M (M +
        1) / 2, m_k its columns), C order.
    out : ndarray, shape (total,)
        Output: per link k, channel 0 the gravity torque W(q, 0, 0), 1 + j the coefficient
        A_j of qdd_j, 1 + M + t(j, l) the symmetrized coefficient C_jl of qd_j qd_l (j <= l,
        t their index in ``numpy.triu_indices(M)``), on the joints i < M.
    """
    B, n = q.shape
    R = np.empty((n, 3, 3))
    p = np.empty((n, 3))
    Jw = np.zeros((n, 3))               # link k's angular velocity per unit qd_j, frame k
    Jv = np.zeros((n, 3))               # its origin's velocity per unit qd_j
    npair = top * (top + 1) // 2        # pair (j, l), j <= l, at l (l + 1) / 2 + j
    Wd = np.zeros((max(npair, 1), 3))   # C_jl of the angular acceleration
    Vd = np.zeros((max(npair, 1), 3))   # and of the origin's acceleration
    pj = np.empty(max(npair, 1), np.int64)
    pl = np.empty(max(npair, 1), np.int64)
    for l in range(top):
        for j in range(l + 1):
            pj[l * (l + 1) // 2 + j] = j
            pl[l * (l + 1) // 2 + j] = l
    vg = np.empty(3)
    t = np.empty(3)
    f = np.empty(3)
    mo = np.empty(3)
    wd = np.empty(3)
    vd = np.empty(3)
    ea = np.empty(3)
    ec = np.empty(3)
    for b in range(B):
        _frames(q[b], Rp, tp, pris, top, R, p)
        for r in range(3):
            vg[r] = -gravity[r]
        for k in range(top):
            px, py, pz = p[k, 0], p[k, 1], p[k, 2]
            # the pairs of earlier joints: vd + wd x p + w x (w x p), then into frame k
            for s in range(k * (k + 1) // 2):
                a0, a1, a2 = Jw[pj[s], 0], Jw[pj[s], 1], Jw[pj[s], 2]
                c0, c1, c2 = Jw[pl[s], 0], Jw[pl[s], 1], Jw[pl[s], 2]
                ap = a0 * px + a1 * py + a2 * pz
                cp = c0 * px + c1 * py + c2 * pz
                ac = a0 * c0 + a1 * c1 + a2 * c2
                e0, e1, e2 = Wd[s, 0], Wd[s, 1], Wd[s, 2]
                t[0] = Vd[s, 0] + (e1 * pz - e2 * py) + (0.5 * (c0 * ap + a0 * cp) - px * ac)
                t[1] = Vd[s, 1] + (e2 * px - e0 * pz) + (0.5 * (c1 * ap + a1 * cp) - py * ac)
                t[2] = Vd[s, 2] + (e0 * py - e1 * px) + (0.5 * (c2 * ap + a2 * cp) - pz * ac)
                for r in range(3):
                    Vd[s, r] = R[k, 0, r] * t[0] + R[k, 1, r] * t[1] + R[k, 2, r] * t[2]
                    wd[r] = R[k, 0, r] * e0 + R[k, 1, r] * e1 + R[k, 2, r] * e2
                for r in range(3):
                    Wd[s, r] = wd[r]
            for j in range(k):
                a0, a1, a2 = Jw[j, 0], Jw[j, 1], Jw[j, 2]
                t[0] = Jv[j, 0] + (a1 * pz - a2 * py)
                t[1] = Jv[j, 1] + (a2 * px - a0 * pz)
                t[2] = Jv[j, 2] + (a0 * py - a1 * px)
                for r in range(3):
                    Jv[j, r] = R[k, 0, r] * t[0] + R[k, 1, r] * t[1] + R[k, 2, r] * t[2]
                    wd[r] = R[k, 0, r] * a0 + R[k, 1, r] * a1 + R[k, 2, r] * a2
                for r in range(3):
                    Jw[j, r] = wd[r]
            for r in range(3):
                t[r] = vg[r]
            for r in range(3):
                vg[r] = R[k, 0, r] * t[0] + R[k, 1, r] * t[1] + R[k, 2, r] * t[2]
            # joint k: its own columns of the Jacobian, and its pairs with the earlier joints
            for r in range(3):
                Jw[k, r] = 0.0
                Jv[k, r] = 0.0
            s0 = k * (k + 1) // 2
            for s in range(s0, s0 + k + 1):
                for r in range(3):
                    Wd[s, r] = 0.0
                    Vd[s, r] = 0.0
            if pris[k] != 0:
                Jv[k, 2] = 1.0
                for j in range(k):          # 2 w x (qd_k z), w the rotated w of link k - 1
                    Vd[s0 + j, 0] = Jw[j, 1]
                    Vd[s0 + j, 1] = -Jw[j, 0]
            else:
                Jw[k, 2] = 1.0
                for j in range(k):          # w x (qd_k z)
                    Wd[s0 + j, 0] = 0.5 * Jw[j, 1]
                    Wd[s0 + j, 1] = 0.5 * (-Jw[j, 0])
            mk = start[k + 1] - start[k]
            if mk == 0:
                continue
            M = k + 1
            P = 1 + M + M * (M + 1) // 2
            for ch in range(P):
                # the state of the channel: velocity pair (a, c) (w = a qd_j + c qd_l), wd, vd
                if ch == 0:
                    j = l = -1
                    for r in range(3):
                        wd[r] = 0.0
                        vd[r] = vg[r]
                elif ch <= M:
                    j = l = -1
                    for r in range(3):
                        wd[r] = Jw[ch - 1, r]
                        vd[r] = Jv[ch - 1, r]
                else:
                    u = ch - 1 - M              # row j of numpy.triu_indices(M)
                    j = 0
                    while u >= M - j:
                        u -= M - j
                        j += 1
                    l = j + u
                    s = l * (l + 1) // 2 + j
                    for r in range(3):
                        wd[r] = Wd[s, r]
                        vd[r] = Vd[s, r]
                for c in range(mk):
                    prm = param[start[k] + c]
                    for r in range(3):
                        f[r] = 0.0
                        mo[r] = 0.0
                    if prm < 6:             # inertia tensor entry: N = E wd + w x (E w)
                        ia, ib = _JA[prm], _JB[prm]
                        mo[ia] = wd[ib]
                        mo[ib] = wd[ia]
                        if j >= 0:          # (a x E c + c x E a) / 2
                            a0, a1, a2 = Jw[j, 0], Jw[j, 1], Jw[j, 2]
                            c0, c1, c2 = Jw[l, 0], Jw[l, 1], Jw[l, 2]
                            for r in range(3):
                                ea[r] = 0.0
                                ec[r] = 0.0
                            ea[ia] = Jw[j, ib]
                            ea[ib] = Jw[j, ia]
                            ec[ia] = Jw[l, ib]
                            ec[ib] = Jw[l, ia]
                            mo[0] += 0.5 * ((a1 * ec[2] - a2 * ec[1]) + (c1 * ea[2] - c2 * ea[1]))
                            mo[1] += 0.5 * ((a2 * ec[0] - a0 * ec[2]) + (c2 * ea[0] - c0 * ea[2]))
                            mo[2] += 0.5 * ((a0 * ec[1] - a1 * ec[0]) + (c0 * ea[1] - c1 * ea[0]))
                    elif prm < 9:           # first moment e: F = wd x e + w x (w x e), N = e x vd
                        e = prm - 6
                        e1 = (e + 1) % 3
                        e2 = (e + 2) % 3
                        f[e1] = wd[e2]
                        f[e2] = -wd[e1]
                        mo[e1] = -vd[e2]
                        mo[e2] = vd[e1]
                        if j >= 0:          # (c a_e + a c_e) / 2 - e (a . c)
                            ae, ce = Jw[j, e], Jw[l, e]
                            ac = Jw[j, 0] * Jw[l, 0] + Jw[j, 1] * Jw[l, 1] + Jw[j, 2] * Jw[l, 2]
                            for r in range(3):
                                f[r] += 0.5 * (Jw[l, r] * ae + Jw[j, r] * ce)
                            f[e] -= ac
                    else:                   # mass: F = vd
                        for r in range(3):
                            f[r] = vd[r]
                    base = offset[k] + (b * P + ch) * M * mk + c
                    for i in range(M):      # tau_i = Jw_i . N + Jv_i . F
                        out[base + i * mk] = (Jw[i, 0] * mo[0] + Jw[i, 1] * mo[1]
                                              + Jw[i, 2] * mo[2]) + (
                            Jv[i, 0] * f[0] + Jv[i, 1] * f[1] + Jv[i, 2] * f[2])
