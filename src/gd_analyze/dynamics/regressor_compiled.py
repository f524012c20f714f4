"""Compiled regressor recursion: the numba kernel of the regressor contributions.

:func:`_contributions_kernel` is a numba loop over set points of the recursion of
:func:`.base_parameters.regressor` (Khalil & Kleinfinger 1987; Fu, Gonzalez & Lee 1987, Table
3.3), restricted to the independent columns: per part, the outward recursion of w, wd, vd in
body frames (base acceleration -g for the gravity part, Eq. (3.3-46)), the wrench of every
link per unit base parameter, F = M vd + U MS, N = J wd + w x (J w) + MS x vd with
U = skew(wd) + skew(w)^2, carried inward f_{i-1} = R_i f_i, n_{i-1} = R_i n_i + p_i x f_{i-1}
and read on every joint's axis.

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
        # joint frames ^{i-1}R_i, ^{i-1}p_i (kinematics.transforms_core)
        for i in range(n):
            if pris[i] != 0:
                for r in range(3):
                    for u in range(3):
                        R[i, r, u] = Rp[i, r, u]
                    p[i, r] = tp[i, r] + q[k, i] * Rp[i, r, 2]
            else:
                ci, si = np.cos(q[k, i]), np.sin(q[k, i])
                for r in range(3):
                    R[i, r, 0] = ci * Rp[i, r, 0] + si * Rp[i, r, 1]
                    R[i, r, 1] = ci * Rp[i, r, 1] - si * Rp[i, r, 0]
                    R[i, r, 2] = Rp[i, r, 2]
                    p[i, r] = tp[i, r]
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
