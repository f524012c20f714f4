"""Compiled engine for the G-D terms: one pass per set point, O(n^2) work, caller-owned output.

The G-D terms of :mod:`gd_analyze.dynamics.dalembert` (Eqs. 3.4-24 to 3.4-28 in Jacobian
form, revolute and prismatic joints), written as scalar loops that numba compiles:

- forward kinematics of the body frames (placement P_i, t_i, then the joint's motion);
- outward recursion of the velocities w_s, the velocity-product accelerations of the
  angular velocities and of the body origins (qdd = 0), the link forces F_s and moments f_s;
- inward suffix sums over s >= j: moments of the forces and of gravity, composite rotational
  inertias Ic_j = sum Ib_s, and the mass moments M_j = sum m_s, Pm_j = sum m_s rbar_s and
  Theta_j = sum m_s (|rbar_s|^2 E - rbar_s rbar_s^T).

With joint j's axis in Plücker coordinates, a_j = z_j, b_j = o_j x z_j (revolute) or a_j = 0,
b_j = z_j (prismatic), the Jacobian columns are Jv_s[:, j] = b_j - rbar_s x a_j and
Jw_s[:, j] = a_j, and every element (i <= j) is O(1) from the column-j sums::

    D_tran(i, j) = sum_{s>=j} m_s Jv_s[:, i] . Jv_s[:, j] = a_i . u_j + b_i . v_j,
        u_j = Theta_j a_j - b_j x Pm_j,   v_j = M_j b_j - Pm_j x a_j
    D_rot(i, j)  = a_i . (Ic_j a_j)
    h_tran(j) = a_j . sum_{s>=j} rbar_s x F_s + b_j . sum_{s>=j} F_s     (c likewise, -m_s g)
    h_rot(j)  = a_j . sum_{s>=j} f_s

so D_tran costs O(n^2) per set point like D_rot (Eq. (3.4-25)); the whole kernel is O(n^2).

The outputs are arrays the caller owns (:func:`gd_analyze.dynamics.dalembert.gd_terms` takes them as
``out``), so streamed chunks reuse the same memory.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["gd_kernel", "body_frames_at", "plucker_axes"]


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def body_frames_at(q: np.ndarray, k: int, Rp: np.ndarray, tp: np.ndarray, pris: np.ndarray,
                   com: np.ndarray, M: np.ndarray, R: np.ndarray, o: np.ndarray,
                   rbar: np.ndarray) -> None:  # pragma: no cover - compiled
    """Body frames and centres of mass at set point k, into R (n, 3, 3), o, rbar (n, 3).

    Parameters
    ----------
    q : ndarray, shape (N, n)
        Joint positions [rad or m].
    k : int
        The set point.
    Rp, tp, pris : ndarray
        Placements (n, 3, 3), (n, 3) [m] and prismatic flags (n,) of the joint model.
    com : ndarray, shape (n, 3)
        Centres of mass in the body frames [m].
    M : ndarray, shape (3, 3)
        Scratch.
    R, o, rbar : ndarray
        Outputs: ^0R of body frame i, its origin o_i [m] and the centre of mass of link i [m].
    """
    n = q.shape[1]
    # forward kinematics of the body frames: R_i = R_{i-1} P_i Motion(q_i)
    for i in range(n):
        for r in range(3):
            for u in range(3):
                if i == 0:
                    M[r, u] = Rp[i, r, u]
                else:
                    M[r, u] = (R[i - 1, r, 0] * Rp[i, 0, u] + R[i - 1, r, 1] * Rp[i, 1, u]
                               + R[i - 1, r, 2] * Rp[i, 2, u])
        for r in range(3):
            if i == 0:
                v = tp[i, r]
            else:
                v = o[i - 1, r] + (R[i - 1, r, 0] * tp[i, 0] + R[i - 1, r, 1] * tp[i, 1]
                                   + R[i - 1, r, 2] * tp[i, 2])
            if pris[i] != 0:
                o[i, r] = v + q[k, i] * M[r, 2]
                R[i, r, 0] = M[r, 0]
                R[i, r, 1] = M[r, 1]
            else:
                o[i, r] = v
        if pris[i] == 0:
            ct = np.cos(q[k, i])
            st = np.sin(q[k, i])
            for r in range(3):
                R[i, r, 0] = ct * M[r, 0] + st * M[r, 1]
                R[i, r, 1] = ct * M[r, 1] - st * M[r, 0]
        for r in range(3):
            R[i, r, 2] = M[r, 2]
    for s in range(n):
        for r in range(3):
            rbar[s, r] = o[s, r] + (R[s, r, 0] * com[s, 0] + R[s, r, 1] * com[s, 1]
                                    + R[s, r, 2] * com[s, 2])


@njit(cache=True, fastmath=False, nogil=True, inline="always")
def plucker_axes(R: np.ndarray, o: np.ndarray, pris: np.ndarray, A: np.ndarray,
                 B: np.ndarray) -> None:  # pragma: no cover - compiled
    """Joint axes in Plücker coordinates: A[j] = z_j, B[j] = o_j x z_j (revolute) or A[j] = 0,
    B[j] = z_j (prismatic), so that Jv_s[:, j] = B[j] - rbar_s x A[j] and Jw_s[:, j] = A[j].

    Parameters
    ----------
    R, o : ndarray, shape (n, 3, 3), (n, 3)
        Body frames from :func:`body_frames_at`.
    pris : ndarray of int, shape (n,)
        1 for a prismatic joint.
    A, B : ndarray, shape (n, 3)
        Outputs.
    """
    n = o.shape[0]
    # joint j's axis in Plücker coordinates: Jv_s[:, j] = b_j - rbar_s x a_j, Jw_s[:, j] = a_j
    for j in range(n):
        zx, zy, zz = R[j, 0, 2], R[j, 1, 2], R[j, 2, 2]
        if pris[j] != 0:
            A[j, 0], A[j, 1], A[j, 2] = 0.0, 0.0, 0.0
            B[j, 0], B[j, 1], B[j, 2] = zx, zy, zz
        else:
            ox, oy, oz = o[j, 0], o[j, 1], o[j, 2]
            A[j, 0], A[j, 1], A[j, 2] = zx, zy, zz
            B[j, 0] = oy * zz - oz * zy
            B[j, 1] = oz * zx - ox * zz
            B[j, 2] = ox * zy - oy * zx


@njit(cache=True, fastmath=False, nogil=True)
def gd_kernel(q: np.ndarray, qd: np.ndarray, Rp: np.ndarray, tp: np.ndarray, pris: np.ndarray,
              mass: np.ndarray, com: np.ndarray, inertia: np.ndarray, gravity: np.ndarray,
              D_tran: np.ndarray, D_rot: np.ndarray, h_tran: np.ndarray, h_rot: np.ndarray,
              c: np.ndarray) -> None:  # pragma: no cover - compiled
    """Fill rows 0..N-1 of D_tran, D_rot (N, n, n) [kg m^2] and h_tran, h_rot, c (N, n) [N m].

    Parameters
    ----------
    q, qd : ndarray, shape (N, n)
        Joint positions [rad or m] and velocities [rad/s or m/s].
    Rp : ndarray, shape (n, 3, 3)
        Placement rotations P_i of the joints in the previous body frames.
    tp : ndarray, shape (n, 3)
        Placement translations t_i [m].
    pris : ndarray of int, shape (n,)
        1 for a prismatic joint, 0 for a revolute one.
    mass : ndarray, shape (n,)
        Link masses [kg].
    com : ndarray, shape (n, 3)
        Centres of mass in the body frames [m].
    inertia : ndarray, shape (n, 3, 3)
        Inertia tensors about the centres of mass, body-frame axes [kg m^2].
    gravity : ndarray, shape (3,)
        Gravity in the base frame [m/s^2].
    D_tran, D_rot, h_tran, h_rot, c : ndarray
        Outputs with at least N rows, overwritten.
    """
    N, n = q.shape
    R = np.empty((n, 3, 3))
    o = np.empty((n, 3))
    rbar = np.empty((n, 3))
    Ib = np.empty((n, 3, 3))
    F = np.empty((n, 3))
    f = np.empty((n, 3))
    A = np.empty((n, 3))        # a_j: z_j (revolute) or 0 (prismatic)
    B = np.empty((n, 3))        # b_j: o_j x z_j (revolute) or z_j (prismatic)
    U = np.empty((n, 3))
    V = np.empty((n, 3))
    W = np.empty((n, 3))
    M = np.empty((3, 3))
    tmp = np.empty((3, 3))
    for k in range(N):
        body_frames_at(q, k, Rp, tp, pris, com, M, R, o, rbar)
        # base-frame inertia tensors Ib = R I R^T
        for s in range(n):
            for r in range(3):
                for u in range(3):
                    tmp[r, u] = (R[s, r, 0] * inertia[s, 0, u] + R[s, r, 1] * inertia[s, 1, u]
                                 + R[s, r, 2] * inertia[s, 2, u])
            for r in range(3):
                for u in range(r, 3):
                    v = tmp[r, 0] * R[s, u, 0] + tmp[r, 1] * R[s, u, 1] + tmp[r, 2] * R[s, u, 2]
                    Ib[s, r, u] = v
                    Ib[s, u, r] = v
        # outward recursion of velocities and velocity-product accelerations (qdd = 0)
        wx = wy = wz = 0.0
        ex = ey = ez = 0.0          # dJw/dt qd
        ax = ay = az = 0.0          # acceleration of the origin o_s
        for s in range(n):
            zx, zy, zz = R[s, 0, 2], R[s, 1, 2], R[s, 2, 2]
            # origin o_s, carried by body s-1 (w, e are still w_{s-1}, e_{s-1})
            if s == 0:
                vx, vy, vz = o[0, 0], o[0, 1], o[0, 2]
            else:
                vx, vy, vz = o[s, 0] - o[s - 1, 0], o[s, 1] - o[s - 1, 1], o[s, 2] - o[s - 1, 2]
            cx = wy * vz - wz * vy
            cy = wz * vx - wx * vz
            cz = wx * vy - wy * vx
            ax += ey * vz - ez * vy + wy * cz - wz * cy
            ay += ez * vx - ex * vz + wz * cx - wx * cz
            az += ex * vy - ey * vx + wx * cy - wy * cx
            if pris[s] != 0:        # Coriolis term of the slide: 2 w x qd z
                u2 = 2.0 * qd[k, s]
                ax += u2 * (wy * zz - wz * zy)
                ay += u2 * (wz * zx - wx * zz)
                az += u2 * (wx * zy - wy * zx)
            else:
                ux, uy, uz = qd[k, s] * zx, qd[k, s] * zy, qd[k, s] * zz
                ex += wy * uz - wz * uy
                ey += wz * ux - wx * uz
                ez += wx * uy - wy * ux
                wx += ux
                wy += uy
                wz += uz
            # centre of mass of link s: a + e x rc + w x (w x rc)
            vx, vy, vz = rbar[s, 0] - o[s, 0], rbar[s, 1] - o[s, 1], rbar[s, 2] - o[s, 2]
            cx = wy * vz - wz * vy
            cy = wz * vx - wx * vz
            cz = wx * vy - wy * vx
            F[s, 0] = mass[s] * (ax + ey * vz - ez * vy + wy * cz - wz * cy)
            F[s, 1] = mass[s] * (ay + ez * vx - ex * vz + wz * cx - wx * cz)
            F[s, 2] = mass[s] * (az + ex * vy - ey * vx + wx * cy - wy * cx)
            # rotational: Ib e + w x (Ib w)
            Iwx = Ib[s, 0, 0] * wx + Ib[s, 0, 1] * wy + Ib[s, 0, 2] * wz
            Iwy = Ib[s, 1, 0] * wx + Ib[s, 1, 1] * wy + Ib[s, 1, 2] * wz
            Iwz = Ib[s, 2, 0] * wx + Ib[s, 2, 1] * wy + Ib[s, 2, 2] * wz
            f[s, 0] = Ib[s, 0, 0] * ex + Ib[s, 0, 1] * ey + Ib[s, 0, 2] * ez + wy * Iwz - wz * Iwy
            f[s, 1] = Ib[s, 1, 0] * ex + Ib[s, 1, 1] * ey + Ib[s, 1, 2] * ez + wz * Iwx - wx * Iwz
            f[s, 2] = Ib[s, 2, 0] * ex + Ib[s, 2, 1] * ey + Ib[s, 2, 2] * ez + wx * Iwy - wy * Iwx
        plucker_axes(R, o, pris, A, B)
        # inward suffix sums over s >= j
        Mx = My = Mz = Sx = Sy = Sz = 0.0
        Gx = Gy = Gz = Tx = Ty = Tz = 0.0
        fx = fy = fz = 0.0
        ms = px = py = pz = 0.0
        q00 = q11 = q22 = q01 = q02 = q12 = 0.0
        i00 = i11 = i22 = i01 = i02 = i12 = 0.0
        for j in range(n - 1, -1, -1):
            rx, ry, rz = rbar[j, 0], rbar[j, 1], rbar[j, 2]
            Mx += ry * F[j, 2] - rz * F[j, 1]
            My += rz * F[j, 0] - rx * F[j, 2]
            Mz += rx * F[j, 1] - ry * F[j, 0]
            Sx += F[j, 0]
            Sy += F[j, 1]
            Sz += F[j, 2]
            mgx, mgy, mgz = mass[j] * gravity[0], mass[j] * gravity[1], mass[j] * gravity[2]
            Gx += ry * mgz - rz * mgy
            Gy += rz * mgx - rx * mgz
            Gz += rx * mgy - ry * mgx
            Tx += mgx
            Ty += mgy
            Tz += mgz
            fx += f[j, 0]
            fy += f[j, 1]
            fz += f[j, 2]
            ax_, ay_, az_ = A[j, 0], A[j, 1], A[j, 2]
            bx, by, bz = B[j, 0], B[j, 1], B[j, 2]
            # h_tran = Jv . sum F = a.(sum rbar x F) + b.(sum F); c likewise with -m g
            h_tran[k, j] = ax_ * Mx + ay_ * My + az_ * Mz + bx * Sx + by * Sy + bz * Sz
            c[k, j] = -(ax_ * Gx + ay_ * Gy + az_ * Gz + bx * Tx + by * Ty + bz * Tz)
            h_rot[k, j] = ax_ * fx + ay_ * fy + az_ * fz
            # mass moments M = sum m, Pm = sum m rbar, Qm = sum m rbar rbar^T; Ic = sum Ib
            mx, my, mz = mass[j] * rx, mass[j] * ry, mass[j] * rz
            ms += mass[j]
            px += mx
            py += my
            pz += mz
            q00 += mx * rx
            q11 += my * ry
            q22 += mz * rz
            q01 += mx * ry
            q02 += mx * rz
            q12 += my * rz
            i00 += Ib[j, 0, 0]
            i11 += Ib[j, 1, 1]
            i22 += Ib[j, 2, 2]
            i01 += Ib[j, 0, 1]
            i02 += Ib[j, 0, 2]
            i12 += Ib[j, 1, 2]
            # u_j = Theta a_j - b_j x Pm, v_j = M b_j - Pm x a_j, w_j = Ic a_j, with
            # Theta = tr(Qm) E - Qm = sum m (|rbar|^2 E - rbar rbar^T)
            tr = q00 + q11 + q22
            U[j, 0] = (tr - q00) * ax_ - q01 * ay_ - q02 * az_ - (by * pz - bz * py)
            U[j, 1] = (tr - q11) * ay_ - q01 * ax_ - q12 * az_ - (bz * px - bx * pz)
            U[j, 2] = (tr - q22) * az_ - q02 * ax_ - q12 * ay_ - (bx * py - by * px)
            V[j, 0] = ms * bx - (py * az_ - pz * ay_)
            V[j, 1] = ms * by - (pz * ax_ - px * az_)
            V[j, 2] = ms * bz - (px * ay_ - py * ax_)
            W[j, 0] = i00 * ax_ + i01 * ay_ + i02 * az_
            W[j, 1] = i01 * ax_ + i11 * ay_ + i12 * az_
            W[j, 2] = i02 * ax_ + i12 * ay_ + i22 * az_
        # D_tran(i, j) = a_i.u_j + b_i.v_j and D_rot(i, j) = a_i.w_j, i <= j: O(n^2)
        for j in range(n):
            for i in range(j + 1):
                dt = (A[i, 0] * U[j, 0] + A[i, 1] * U[j, 1] + A[i, 2] * U[j, 2]
                      + B[i, 0] * V[j, 0] + B[i, 1] * V[j, 1] + B[i, 2] * V[j, 2])
                dr = A[i, 0] * W[j, 0] + A[i, 1] * W[j, 1] + A[i, 2] * W[j, 2]
                D_tran[k, i, j] = dt
                D_tran[k, j, i] = dt
                D_rot[k, i, j] = dr
                D_rot[k, j, i] = dr
