"""Compiled engine for the G-D terms: one pass per set point, O(n^2) work, no temporaries.

This is the same computation as :func:`gd_analyze.core.dalembert._gd_chunk` (Eqs. 3.4-24 to 3.4-28 in
Jacobian form, outward velocity recursion, inward suffix sums), written as scalar loops that
numba compiles. It is used by :func:`gd_analyze.core.dalembert.gd_terms` for long trajectories; the
tests check both engines against Pinocchio.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["gd_kernel"]


@njit(cache=True, fastmath=False, nogil=True)
def gd_kernel(q, qd, d, a, alpha, offset, mass, com, inertia, gravity,
              D_tran, D_rot, h_tran, h_rot, c):  # pragma: no cover - compiled
    """Fill D_tran, D_rot (N, n, n) [kg m^2] and h_tran, h_rot, c (N, n) [N m] in place.

    Parameters
    ----------
    q, qd : ndarray, shape (N, n)
        Joint positions [rad] and velocities [rad/s].
    d, a, alpha, offset, mass : ndarray, shape (n,)
        DH parameters [m, m, rad, rad] and link masses [kg].
    com : ndarray, shape (n, 3)
        Centres of mass in the link frames [m].
    inertia : ndarray, shape (n, 3, 3)
        Inertia tensors about the centres of mass [kg m^2].
    gravity : ndarray, shape (3,)
        Gravity in the base frame [m/s^2].
    D_tran, D_rot, h_tran, h_rot, c : ndarray
        Outputs, overwritten.
    """
    N, n = q.shape
    ca = np.cos(alpha)
    sa = np.sin(alpha)
    R = np.empty((n + 1, 3, 3))
    p = np.empty((n + 1, 3))
    rbar = np.empty((n, 3))
    Ib = np.empty((n, 3, 3))
    Ic = np.empty((n, 3, 3))
    Jv = np.empty((n, n, 3))
    F = np.empty((n, 3))
    f = np.empty((n, 3))
    tmp = np.empty((3, 3))
    for k in range(N):
        # forward kinematics, Eq. (3.2-5)
        for r in range(3):
            for s in range(3):
                R[0, r, s] = 1.0 if r == s else 0.0
            p[0, r] = 0.0
        for i in range(n):
            th = q[k, i] + offset[i]
            ct = np.cos(th)
            st = np.sin(th)
            A00, A01, A02 = ct, -ca[i] * st, sa[i] * st
            A10, A11, A12 = st, ca[i] * ct, -sa[i] * ct
            A21, A22 = sa[i], ca[i]
            px, py, pz = a[i] * ct, a[i] * st, d[i]
            for r in range(3):
                R0, R1, R2 = R[i, r, 0], R[i, r, 1], R[i, r, 2]
                R[i + 1, r, 0] = R0 * A00 + R1 * A10
                R[i + 1, r, 1] = R0 * A01 + R1 * A11 + R2 * A21
                R[i + 1, r, 2] = R0 * A02 + R1 * A12 + R2 * A22
                p[i + 1, r] = p[i, r] + R0 * px + R1 * py + R2 * pz
        # centres of mass and base-frame inertia tensors Ib = R I R^T
        for s in range(n):
            for r in range(3):
                rbar[s, r] = p[s + 1, r] + (R[s + 1, r, 0] * com[s, 0] + R[s + 1, r, 1] * com[s, 1]
                                            + R[s + 1, r, 2] * com[s, 2])
            for r in range(3):
                for u in range(3):
                    tmp[r, u] = (R[s + 1, r, 0] * inertia[s, 0, u] + R[s + 1, r, 1] * inertia[s, 1, u]
                                 + R[s + 1, r, 2] * inertia[s, 2, u])
            for r in range(3):
                for u in range(r, 3):
                    v = (tmp[r, 0] * R[s + 1, u, 0] + tmp[r, 1] * R[s + 1, u, 1]
                         + tmp[r, 2] * R[s + 1, u, 2])
                    Ib[s, r, u] = v
                    Ib[s, u, r] = v
        # outward recursion of velocities and velocity-product accelerations (qdd = 0)
        wx = wy = wz = 0.0
        ex = ey = ez = 0.0          # dJw/dt qd
        ax = ay = az = 0.0          # acceleration of origin p_s
        for s in range(n):
            zx, zy, zz = R[s, 0, 2], R[s, 1, 2], R[s, 2, 2]
            ux, uy, uz = qd[k, s] * zx, qd[k, s] * zy, qd[k, s] * zz
            ex += wy * uz - wz * uy
            ey += wz * ux - wx * uz
            ez += wx * uy - wy * ux
            wx += ux
            wy += uy
            wz += uz
            for which in range(2):
                if which == 0:
                    vx = p[s + 1, 0] - p[s, 0]
                    vy = p[s + 1, 1] - p[s, 1]
                    vz = p[s + 1, 2] - p[s, 2]
                else:
                    vx = rbar[s, 0] - p[s + 1, 0]
                    vy = rbar[s, 1] - p[s + 1, 1]
                    vz = rbar[s, 2] - p[s + 1, 2]
                # e x v + w x (w x v)
                cx = wy * vz - wz * vy
                cy = wz * vx - wx * vz
                cz = wx * vy - wy * vx
                gx = ey * vz - ez * vy + wy * cz - wz * cy
                gy = ez * vx - ex * vz + wz * cx - wx * cz
                gz = ex * vy - ey * vx + wx * cy - wy * cx
                if which == 0:
                    ax += gx
                    ay += gy
                    az += gz
                else:
                    F[s, 0] = mass[s] * (ax + gx)
                    F[s, 1] = mass[s] * (ay + gy)
                    F[s, 2] = mass[s] * (az + gz)
            # rotational: Ib e + w x (Ib w)
            Iwx = Ib[s, 0, 0] * wx + Ib[s, 0, 1] * wy + Ib[s, 0, 2] * wz
            Iwy = Ib[s, 1, 0] * wx + Ib[s, 1, 1] * wy + Ib[s, 1, 2] * wz
            Iwz = Ib[s, 2, 0] * wx + Ib[s, 2, 1] * wy + Ib[s, 2, 2] * wz
            f[s, 0] = Ib[s, 0, 0] * ex + Ib[s, 0, 1] * ey + Ib[s, 0, 2] * ez + wy * Iwz - wz * Iwy
            f[s, 1] = Ib[s, 1, 0] * ex + Ib[s, 1, 1] * ey + Ib[s, 1, 2] * ez + wz * Iwx - wx * Iwz
            f[s, 2] = Ib[s, 2, 0] * ex + Ib[s, 2, 1] * ey + Ib[s, 2, 2] * ez + wx * Iwy - wy * Iwx
        # inward suffix sums: moments about each joint axis, composite inertias
        Mx = My = Mz = Sx = Sy = Sz = 0.0
        Gx = Gy = Gz = Tx = Ty = Tz = 0.0
        fx = fy = fz = 0.0
        for r in range(3):
            for u in range(3):
                tmp[r, u] = 0.0
        for j in range(n - 1, -1, -1):
            Mx += rbar[j, 1] * F[j, 2] - rbar[j, 2] * F[j, 1]
            My += rbar[j, 2] * F[j, 0] - rbar[j, 0] * F[j, 2]
            Mz += rbar[j, 0] * F[j, 1] - rbar[j, 1] * F[j, 0]
            Sx += F[j, 0]
            Sy += F[j, 1]
            Sz += F[j, 2]
            mgx, mgy, mgz = mass[j] * gravity[0], mass[j] * gravity[1], mass[j] * gravity[2]
            Gx += rbar[j, 1] * mgz - rbar[j, 2] * mgy
            Gy += rbar[j, 2] * mgx - rbar[j, 0] * mgz
            Gz += rbar[j, 0] * mgy - rbar[j, 1] * mgx
            Tx += mgx
            Ty += mgy
            Tz += mgz
            fx += f[j, 0]
            fy += f[j, 1]
            fz += f[j, 2]
            for r in range(3):
                for u in range(3):
                    tmp[r, u] += Ib[j, r, u]
                    Ic[j, r, u] = tmp[r, u]
            zx, zy, zz = R[j, 0, 2], R[j, 1, 2], R[j, 2, 2]
            px, py, pz = p[j, 0], p[j, 1], p[j, 2]
            h_tran[k, j] = (zx * (Mx - (py * Sz - pz * Sy)) + zy * (My - (pz * Sx - px * Sz))
                            + zz * (Mz - (px * Sy - py * Sx)))
            c[k, j] = -(zx * (Gx - (py * Tz - pz * Ty)) + zy * (Gy - (pz * Tx - px * Tz))
                        + zz * (Gz - (px * Ty - py * Tx)))
            h_rot[k, j] = zx * fx + zy * fy + zz * fz
        # Jacobian columns of the centres of mass: Jv[s, j] = z_j x (rbar_s - p_j), j <= s
        for s in range(n):
            for j in range(s + 1):
                zx, zy, zz = R[j, 0, 2], R[j, 1, 2], R[j, 2, 2]
                vx = rbar[s, 0] - p[j, 0]
                vy = rbar[s, 1] - p[j, 1]
                vz = rbar[s, 2] - p[j, 2]
                Jv[s, j, 0] = zy * vz - zz * vy
                Jv[s, j, 1] = zz * vx - zx * vz
                Jv[s, j, 2] = zx * vy - zy * vx
        for i in range(n):
            for j in range(i, n):
                acc = 0.0
                for s in range(j, n):
                    acc += mass[s] * (Jv[s, i, 0] * Jv[s, j, 0] + Jv[s, i, 1] * Jv[s, j, 1]
                                      + Jv[s, i, 2] * Jv[s, j, 2])
                D_tran[k, i, j] = acc
                D_tran[k, j, i] = acc
                zx, zy, zz = R[j, 0, 2], R[j, 1, 2], R[j, 2, 2]
                v0 = Ic[j, 0, 0] * zx + Ic[j, 0, 1] * zy + Ic[j, 0, 2] * zz
                v1 = Ic[j, 1, 0] * zx + Ic[j, 1, 1] * zy + Ic[j, 1, 2] * zz
                v2 = Ic[j, 2, 0] * zx + Ic[j, 2, 1] * zy + Ic[j, 2, 2] * zz
                acc = R[i, 0, 2] * v0 + R[i, 1, 2] * v1 + R[i, 2, 2] * v2
                D_rot[k, i, j] = acc
                D_rot[k, j, i] = acc
