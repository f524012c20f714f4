"""Compiled regressor recursion: the base parameters' part contributions, or their peaks.

The torques are linear in the base parameters, tau = Y_b(q, qd, qdd) beta, and each column of
Y_b splits into an inertial part Y_b(q, 0, qdd; g = 0), a velocity part Y_b(q, qd, 0; g = 0)
and a gravity part Y_b(q, 0, 0; g) (:mod:`.pruning`). :func:`part_contributions` gives the
contributions Y_p[k, i, m] beta_m of a batch of set points, :func:`contribution_peaks` their
running peaks (abs max) without storing them, so that memory stays O(n b) whatever N is.

Both run :func:`_contributions_kernel`, a numba loop over set points of the recursion of
:func:`.base_parameters.regressor` (Khalil & Kleinfinger 1987; Fu, Gonzalez & Lee 1987, Table
3.3), restricted to the independent columns: per part, the outward recursion of w, wd, vd in
body frames (base acceleration -g for the gravity part, Eq. (3.3-46)), the wrench of every
link per unit base parameter, F = M vd + U MS, N = J wd + w x (J w) + MS x vd with
U = skew(wd) + skew(w)^2, carried inward f_{i-1} = R_i f_i, n_{i-1} = R_i n_i + p_i x f_{i-1}
and read on every joint's axis.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..model.kinematics import as_states

__all__ = ["part_contributions", "contribution_peaks", "part_regressor"]

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


def _arguments(robot, columns, beta, q, qd, qdd):
    """The kernel's arguments but the outputs, with the states checked."""
    q, qd, qdd = as_states(robot, q, qd, qdd)
    columns = np.asarray(columns, np.int64).reshape(-1)
    c = np.ascontiguousarray
    return (c(q, float), c(qd, float), c(qdd, float), c(robot.rotation, float),
            c(robot.translation, float), np.asarray(robot.prismatic, np.int64),
            c(robot.gravity, float), columns // 10, columns % 10, c(beta, float))


def part_regressor(robot, columns, q, qd, qdd):
    """Columns of the regressor, split into parts, compiled: the contributions at unit beta.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (its inertial parameters are not read).
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c (link k, parameter c of
        :data:`.base_parameters.PARAMETER_NAMES`).
    q, qd, qdd : array_like, shape (N, n)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2].

    Returns
    -------
    ndarray, shape (N, 3, n, m)
        ``W[k, p, i, c]``: torque of joint i [N m or N] per unit parameter ``columns[c]`` in
        part p (inertial: W(q, 0, qdd) with g = 0; velocity: W(q, qd, 0) with g = 0;
        gravity: W(q, 0, 0) with the robot's gravity); summed over p it is
        :func:`.base_parameters.regressor`'s ``W[k, i, columns[c]]``.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n), or a column is out of range.

    Notes
    -----
    The recursion of :func:`part_contributions` (Khalil & Kleinfinger 1987) with beta = 1.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("two-link")
    >>> z = np.zeros((1, 2))
    >>> W = part_regressor(robot, [9, 19], z, z, z)     # the two link masses
    >>> W.shape, bool(np.all(W[:, :2] == 0))
    ((1, 3, 2, 2), True)
    """
    columns = np.asarray(columns, np.int64).reshape(-1)
    if columns.size and (columns.min() < 0 or columns.max() >= 10 * robot.n):
        raise ValueError(f"columns must lie in [0, {10 * robot.n}), got {columns.tolist()}")
    args = _arguments(robot, columns, np.ones(columns.size), q, qd, qdd)
    N, n = args[0].shape
    m = columns.size
    out = np.empty((N, 3, n, m))
    _contributions_kernel(*args, True, out, np.zeros(n), np.zeros((m, 3, n)), np.zeros((m, n)))
    return out


def part_contributions(robot, base, q, qd, qdd):
    """Contribution of every (part, base parameter) to every joint torque, compiled.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters, b of them (:func:`.base_parameters.base_parameters`).
    q, qd, qdd : array_like, shape (N, n)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2].

    Returns
    -------
    ndarray, shape (3, N, n, b)
        ``C[p, k, i, m]`` = Y_p[k, i, m] beta_m [N m or N] for the parts p of
        :data:`.recursive.PARTS` (inertial: Y_b(q, 0, qdd) with g = 0; velocity:
        Y_b(q, qd, 0) with g = 0; gravity: Y_b(q, 0, 0) with the robot's gravity); summed
        over p and m it is tau. A view of an array laid out (N, 3, n, b).

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n).

    Notes
    -----
    The regressor of :func:`.base_parameters.regressor` (Khalil & Kleinfinger 1987; Fu,
    Gonzalez & Lee 1987, Table 3.3) on the independent columns, times beta (Gautier 1990),
    in one compiled pass per set point.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.core.symbolic.base_parameters import base_parameters
    >>> robot = load_robot("two-link")
    >>> base = base_parameters(robot)
    >>> z = np.zeros((4, 2))
    >>> part_contributions(robot, base, z, z, z).shape == (3, 4, 2, base.rank)
    True
    """
    args = _arguments(robot, np.flatnonzero(base.independent.reshape(-1)), base.beta, q, qd,
                      qdd)
    N, n = args[0].shape
    b = base.rank
    out = np.empty((N, 3, n, b))
    _contributions_kernel(*args, True, out, np.zeros(n), np.zeros((b, 3, n)),
                          np.zeros((b, n)))
    return out.transpose(1, 0, 2, 3)


def contribution_peaks(robot, base, q, qd, qdd, out=None):
    """Running peaks of the joint torques and of every part contribution, compiled.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters, b of them.
    q, qd, qdd : array_like, shape (N, n)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2]:
        a whole trajectory or one chunk of it.
    out : tuple of ndarray, optional
        ``(tau_peak, peak, whole_peak)`` from an earlier call (earlier chunks), updated in
        place by maximum; new zero arrays by default.

    Returns
    -------
    tau_peak : ndarray, shape (n,)
        Peak |tau_i| [N m or N].
    peak : ndarray, shape (b, 3, n)
        Peak |contribution| of each (base parameter, part) to each joint torque.
    whole_peak : ndarray, shape (b, n)
        Peak |contribution| of each base parameter, all parts together.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n), or ``out`` has the wrong shapes.

    Notes
    -----
    The contributions of :func:`part_contributions`, reduced per set point as they are
    computed, so memory is O(n b) whatever N is. Peaks combine over chunks (and over
    trajectories) by maximum.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.core.symbolic.base_parameters import base_parameters
    >>> robot = load_robot("two-link")
    >>> base = base_parameters(robot)
    >>> q = np.array([[0.3, -0.2], [1.0, 0.5]])
    >>> tau_peak, peak, whole = contribution_peaks(robot, base, q, 0 * q, 0 * q)
    >>> peak.shape == (base.rank, 3, 2), bool(np.all(peak[:, :2] == 0))   # at rest: gravity
    (True, True)
    """
    args = _arguments(robot, np.flatnonzero(base.independent.reshape(-1)), base.beta, q, qd,
                      qdd)
    n, b = robot.n, base.rank
    if out is None:
        out = (np.zeros(n), np.zeros((b, 3, n)), np.zeros((b, n)))
    shapes = ((n,), (b, 3, n), (b, n))
    if len(out) != 3 or any(np.shape(x) != s for x, s in zip(out, shapes)):
        raise ValueError(f"out must be arrays of shapes {shapes}")
    _contributions_kernel(*args, False, np.empty((0, 3, n, b)), *out)
    return out
