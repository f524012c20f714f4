"""Oracles: the array (numpy) copies of the compiled kernels, for the tests to compare them with.

The package computes every hot loop in a numba kernel; these are the same computations as
array code, the formulation the kernels were written from (the Jacobian form of the G-D terms
as written, the regressor's parts and their peaks; the ranking's and
the part peaks' chunk updates have theirs in ``dynamics/test_kernels.py``, the inertia
check numpy's eigenvalues at every position). The tests compare
each kernel with its copy here (bit for bit where the arithmetic is the same, to round-off
where the order differs), beside the Pinocchio comparisons.
"""

import numpy as np

from gd_analyze.dynamics import regressor_kernels
from gd_analyze.dynamics.dalembert import GDTerms
from gd_analyze.dynamics.regressor_kernels import regressor_columns
from gd_analyze.model.drives import friction_torque
from gd_analyze.model.kinematics import as_states, body_frames


def _suffix_sum(x):
    """Sum over links s >= j along axis 1: out[:, j] = sum_{s>=j} x[:, s]."""
    return np.flip(np.cumsum(np.flip(x, axis=1), axis=1), axis=1)


def _shift(x):
    """x[:, s-1] along axis 1, with zeros for s = 0 (the base is at rest)."""
    return np.concatenate([np.zeros_like(x[:, :1]), x[:, :-1]], axis=1)


def gd_chunk(robot, q, qd):
    """The G-D terms (D_tran, D_rot, h_tran, h_rot, c) at N set points, the Jacobian form as
    written (module docstring of :mod:`gd_analyze.dynamics.dalembert`), array code."""
    n = robot.n
    m = robot.mass
    pris = np.asarray(robot.prismatic, dtype=bool)
    R, o = body_frames(robot, q)            # body frame j: axis z_j, origin o_j
    z = R[..., 2]                           # (N, n, 3)
    zr = z * (~pris)[None, :, None]         # Jw columns: z_j for revolute joints, 0 else
    rbar = o + np.einsum("ksab,sb->ksa", R, robot.body_com)     # (N, n, 3)
    Ib = R @ robot.body_inertia @ np.swapaxes(R, -1, -2)        # (N, n, 3, 3)

    # --- D_tran: sum_s m_s Jv_s^T Jv_s, j <= s
    Jv = np.cross(z[:, None, :, :], rbar[:, :, None, :] - o[:, None, :, :])  # (N, s, j, 3)
    Jv = np.where(pris[None, None, :, None], z[:, None, :, :], Jv)
    Jv *= np.tril(np.ones((n, n)))[None, :, :, None]
    D_tran = np.einsum("ksia,s,ksja->kij", Jv, m, Jv, optimize=True)

    # --- D_rot: zr_i^T (sum_{s >= max(i,j)} Ib_s) zr_j
    Ic = _suffix_sum(Ib)                    # (N, n, 3, 3)
    idx = np.maximum.outer(np.arange(n), np.arange(n))
    Iz = np.einsum("ksab,kjb->ksja", Ic, zr)  # Ic_s zr_j, (N, s, j, 3)
    D_rot = np.einsum("kia,kija->kij", zr, Iz[:, idx, np.arange(n)[None, :], :])

    # --- velocities and velocity-product accelerations (qdd = 0), outward recursion
    wz = qd[:, :, None] * zr                # qd_j z_j (revolute)
    w = np.cumsum(wz, axis=1)               # w_s, (N, n, 3)
    w_prev = _shift(w)
    wd = np.cumsum(np.cross(w_prev, wz), axis=1)        # dJw_s/dt qd
    wd_prev = _shift(wd)
    dp = o - _shift(o)                      # o_s - o_{s-1}, fixed in body s-1 but for q_s
    slide = 2.0 * np.cross(w_prev, qd[:, :, None] * z) * pris[None, :, None]
    ap = np.cumsum(np.cross(wd_prev, dp) + np.cross(w_prev, np.cross(w_prev, dp)) + slide,
                   axis=1)                  # origin o_s
    rc = rbar - o
    abar = ap + np.cross(wd, rc) + np.cross(w, np.cross(w, rc))   # dJv_s/dt qd

    # --- h_tran and c: Jv_j . sum_{s>=j} F_s, with F_s = m_s a_s: revolute
    # z_j . sum_{s>=j} (rbar_s - o_j) x F_s, prismatic z_j . sum_{s>=j} F_s
    def along_axes(F):
        S = _suffix_sum(F)
        M = _suffix_sum(np.cross(rbar, F)) - np.cross(o, S)
        return np.einsum("kja,kja->kj", z, np.where(pris[None, :, None], S, M))

    h_tran = along_axes(m[None, :, None] * abar)
    c = -along_axes(np.broadcast_to(m[:, None] * robot.gravity, rbar.shape))

    # --- h_rot: zr_j . sum_{s>=j} (Ib_s wd_s + w_s x Ib_s w_s)
    Iw = np.einsum("ksab,ksb->ksa", Ib, w)
    f = np.einsum("ksab,ksb->ksa", Ib, wd) + np.cross(w, Iw)
    h_rot = np.einsum("kja,kja->kj", zr, _suffix_sum(f))
    # exactly symmetric (the sums above round the two triangles differently)
    D_tran = np.triu(D_tran) + np.swapaxes(np.triu(D_tran, 1), 1, 2)
    D_rot = np.triu(D_rot) + np.swapaxes(np.triu(D_rot, 1), 1, 2)
    return D_tran, D_rot, h_tran, h_rot, c


def gd_terms_numpy(robot, q, qd, chunk=8192):
    """:func:`gd_analyze.gd_terms` as array code (:func:`gd_chunk` over chunks of set points)."""
    q, qd = as_states(robot, q, qd)
    parts = [gd_chunk(robot, q[a:a + chunk], qd[a:a + chunk])
             for a in range(0, max(q.shape[0], 1), chunk)]
    D_tran, D_rot, h_tran, h_rot, c = (np.concatenate([p[k] for p in parts]) for k in range(5))
    arm = robot.armature if robot.has_armature else None
    return GDTerms(D_tran, D_rot, h_tran, h_rot, c, arm, friction_torque(robot, qd))


def part_regressor_numpy(robot, columns, q, qd, qdd):
    """:func:`part_regressor` as array code: the three parts by :func:`regressor_columns`."""
    q, qd, qdd = as_states(robot, q, qd, qdd, finite=False)
    z, g0 = np.zeros_like(q), np.zeros(3)
    parts = (regressor_columns(robot, columns, q, z, qdd, gravity=g0),
             regressor_columns(robot, columns, q, qd, z, gravity=g0),
             regressor_columns(robot, columns, q, z, z))
    return np.stack(parts, axis=1)


def part_contributions_numpy(robot, base, q, qd, qdd):
    """:func:`part_contributions` as array code, shape (3, N, n, b)."""
    cols = np.flatnonzero(base.independent.reshape(-1))
    return (part_regressor_numpy(robot, cols, q, qd, qdd) * base.beta).transpose(1, 0, 2, 3)


def contribution_peaks_numpy(robot, base, q, qd, qdd):
    """:func:`contribution_peaks` as array code, by blocks of ``regressor_kernels.BLOCK`` set
    points."""
    n, b = robot.n, base.rank
    tau_peak, peak, whole_peak = np.zeros(n), np.zeros((b, 3, n)), np.zeros((b, n))
    q, qd, qdd = as_states(robot, q, qd, qdd, finite=False)
    block = regressor_kernels.BLOCK
    for a in range(0, q.shape[0], block):
        sl = slice(a, a + block)
        val = part_contributions_numpy(robot, base, q[sl], qd[sl], qdd[sl]).transpose(1, 0, 2, 3)
        s = (val[:, 0] + val[:, 1]) + val[:, 2]                          # (B, n, b)
        # a NaN is never a peak (the kernel's ``if v > peak``): fmax skips it
        np.fmax(tau_peak, np.fmax.reduce(np.abs(s.sum(axis=2)), axis=0), out=tau_peak)
        np.fmax(whole_peak, np.fmax.reduce(np.abs(s), axis=0).T, out=whole_peak)
        np.fmax(peak, np.fmax.reduce(np.abs(val), axis=0).transpose(2, 0, 1), out=peak)
    return tau_peak, peak, whole_peak


def element_series(D_tran, D_rot, h_tran, h_rot):
    """The ranked elements' translational and rotational values, as array code (the
    ranking kernel gathers them itself).

    Parameters
    ----------
    D_tran, D_rot : ndarray, shape (N, n, n)
        Inertia matrix parts [kg m^2].
    h_tran, h_rot : ndarray, shape (N, n)
        Coriolis and centrifugal parts [N m].

    Returns
    -------
    tran, rot : ndarray, shape (N, M)
        Per set point and element, in the order of :func:`gd_analyze.ranking.ranking.element_labels`.
    """
    n = D_tran.shape[-1]
    iu = np.triu_indices(n)
    tran = np.concatenate([D_tran[:, iu[0], iu[1]], h_tran], axis=1)
    rot = np.concatenate([D_rot[:, iu[0], iu[1]], h_rot], axis=1)
    return tran, rot

