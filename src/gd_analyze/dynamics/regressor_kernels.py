"""The regressor recursion: the base parameters' part contributions, or their peaks.

The torques are linear in the base parameters, tau = Y_b(q, qd, qdd) beta, and each column of
Y_b splits into an inertial part Y_b(q, 0, qdd; g = 0), a velocity part Y_b(q, qd, 0; g = 0)
and a gravity part Y_b(q, 0, 0; g) (:mod:`gd_analyze.symbolic.pruning`). :func:`part_contributions` gives the
contributions Y_p[k, i, m] beta_m of a batch of set points, :func:`contribution_peaks` their
running peaks (abs max) without storing them, so that memory stays O(n b) whatever N is.

Both evaluate the recursion of :func:`.base_parameters.regressor` (Khalil & Kleinfinger 1987;
Fu, Gonzalez & Lee 1987, Table 3.3) on the asked columns only: per part, the outward recursion
of w, wd, vd in body frames (base acceleration -g for the gravity part, Eq. (3.3-46)), the
wrench of every link per unit parameter, F = M vd + U MS, N = J wd + w x (J w) + MS x vd with
U = skew(wd) + skew(w)^2, carried inward f_{i-1} = R_i f_i, n_{i-1} = R_i n_i + p_i x f_{i-1}
and read on every joint's axis, in the numba loop :func:`.regressor_compiled._contributions_kernel`
(imported by the first call). :func:`regressor_columns` is the same recursion as array code
over blocks of :data:`BLOCK` set points (every column of a link carried inward together), for
the callers that want whole regressor columns. :func:`link_channels` gives the regressor's
coefficient functions of q per link (gravity, inertial and velocity channels), compiled
(:func:`.regressor_compiled._channels_kernel`).
"""

from __future__ import annotations

import numpy as np

from ..model.kinematics import as_states

__all__ = ["part_contributions", "contribution_peaks", "stacked_contribution_peaks", "part_regressor", "regressor_columns",
           "link_channels", "BLOCK"]

#: Set points per block of :func:`regressor_columns`: bounds its temporaries (O(BLOCK n m) floats).
BLOCK = 2048
#: (row, column) of the inertia-tensor entry of the parameters XX, XY, XZ, YY, YZ, ZZ.
_JA = (0, 0, 0, 1, 1, 2)
_JB = (0, 1, 2, 1, 2, 2)


def _frames(robot, q, top=None):
    """Per joint ^{i-1}R_i (3 x 3 entries) and ^{i-1}p_i (3 entries), each (N,) or a float,
    of the first ``top`` joints (default all)."""
    Rp = np.asarray(robot.rotation, float)
    tp = np.asarray(robot.translation, float)
    out = []
    for i in range(robot.n if top is None else top):
        P = Rp[i]
        if robot.prismatic[i]:
            R = [[P[r, 0], P[r, 1], P[r, 2]] for r in range(3)]
            p = [tp[i, r] + q[:, i] * P[r, 2] for r in range(3)]
        else:
            ci, si = np.cos(q[:, i]), np.sin(q[:, i])
            R = [[ci * P[r, 0] + si * P[r, 1], ci * P[r, 1] - si * P[r, 0], P[r, 2]]
                 for r in range(3)]
            p = [tp[i, r] for r in range(3)]
        out.append((R, p))
    return out


def _outward(frames, prismatic, qd, qdd, gravity):
    """Body-frame w, wd, vd of every link, each a list of 3 arrays (N,)."""
    N = qd.shape[0]
    z = np.zeros(N)
    w0, e0 = [z, z, z], [z, z, z]
    v0 = [np.full(N, -float(g)) for g in gravity]
    out = []
    for j, (R, p) in enumerate(frames):
        px, py, pz = p
        cx = w0[1] * pz - w0[2] * py
        cy = w0[2] * px - w0[0] * pz
        cz = w0[0] * py - w0[1] * px
        a = (v0[0] + (e0[1] * pz - e0[2] * py) + (w0[1] * cz - w0[2] * cy),
             v0[1] + (e0[2] * px - e0[0] * pz) + (w0[2] * cx - w0[0] * cz),
             v0[2] + (e0[0] * py - e0[1] * px) + (w0[0] * cy - w0[1] * cx))
        vd = [R[0][r] * a[0] + R[1][r] * a[1] + R[2][r] * a[2] for r in range(3)]
        w = [R[0][r] * w0[0] + R[1][r] * w0[1] + R[2][r] * w0[2] for r in range(3)]
        wd = [R[0][r] * e0[0] + R[1][r] * e0[1] + R[2][r] * e0[2] for r in range(3)]
        u, acc = qd[:, j], qdd[:, j]
        if prismatic[j]:
            vd[2] = vd[2] + acc
            vd[0] = vd[0] + 2.0 * (w[1] * u)
            vd[1] = vd[1] + 2.0 * (-(w[0] * u))
        else:
            wd[0] = wd[0] + w[1] * u
            wd[1] = wd[1] + (-(w[0] * u))
            wd[2] = wd[2] + acc
            w[2] = w[2] + u
        out.append((w, wd, vd))
        w0, e0, v0 = w, wd, vd
    return out


def _wrench(w, wd, vd, prm, z):
    """The wrench (f, m) of a link per unit standard parameter ``prm`` (0..9), in its frame."""
    wx, wy, wz = w
    ex, ey, ez = wd
    if prm < 6:                 # inertia tensor entry: N = E wd + w x (E w)
        ia, ib = _JA[prm], _JB[prm]
        m, a = [z, z, z], [z, z, z]
        m[ia], m[ib] = wd[ib], wd[ia]
        a[ia], a[ib] = w[ib], w[ia]
        m = [m[0] + (wy * a[2] - wz * a[1]), m[1] + (wz * a[0] - wx * a[2]),
             m[2] + (wx * a[1] - wy * a[0])]
        return [z, z, z], m
    if prm == 6:                # first moment: F = U e, N = e x vd
        return ([-(wy * wy) - wz * wz, ez + wx * wy, -ey + wx * wz], [z, -vd[2], vd[1]])
    if prm == 7:
        return ([-ez + wx * wy, -(wx * wx) - wz * wz, ex + wy * wz], [vd[2], z, -vd[0]])
    if prm == 8:
        return ([ey + wx * wz, -ex + wy * wz, -(wx * wx) - wy * wy], [-vd[1], vd[0], z])
    return list(vd), [z, z, z]  # mass: F = vd


def _block_columns(robot, frames, link, param, qd, qdd, gravity):
    """:func:`regressor_columns` of one block, columns sorted by link, laid out (n, m, N)."""
    N, n = qd.shape
    m = link.size
    z = np.zeros(N)
    motion = _outward(frames, robot.prismatic, qd, qdd, gravity)
    F = np.empty((3, m, N))                 # a column's rows contiguous
    M = np.empty((3, m, N))
    for c in range(m):
        f, mo = _wrench(*motion[link[c]], param[c], z)
        for r in range(3):
            F[r, c] = f[r]
            M[r, c] = mo[r]
    W = np.zeros((n, m, N))
    first = np.searchsorted(link, np.arange(n))            # the columns of links >= i
    for i in range(n - 1, -1, -1):
        s = first[i]
        if s == m:
            continue
        f, mo = F[:, s:], M[:, s:]
        W[i, s:] = f[2] if robot.prismatic[i] else mo[2]
        if i == 0:
            break
        R, (px, py, pz) = frames[i]
        f0 = R[0][0] * f[0] + R[0][1] * f[1] + R[0][2] * f[2]
        f1 = R[1][0] * f[0] + R[1][1] * f[1] + R[1][2] * f[2]
        f2 = R[2][0] * f[0] + R[2][1] * f[1] + R[2][2] * f[2]
        m0 = R[0][0] * mo[0] + R[0][1] * mo[1] + R[0][2] * mo[2]
        m1 = R[1][0] * mo[0] + R[1][1] * mo[1] + R[1][2] * mo[2]
        m2 = R[2][0] * mo[0] + R[2][1] * mo[1] + R[2][2] * mo[2]
        M[0, s:] = m0 + (py * f2 - pz * f1)
        M[1, s:] = m1 + (pz * f0 - px * f2)
        M[2, s:] = m2 + (px * f1 - py * f0)
        F[0, s:], F[1, s:], F[2, s:] = f0, f1, f2
    return W


def _put(dst, W, back):
    """Write W (n, m, N), columns sorted, into dst (N, n, m) in the columns' own order."""
    if back is not None:
        W = W[:, back]
    dst[...] = W.transpose(2, 0, 1)


def _checked_columns(robot, columns):
    """The columns as int64, checked against the links."""
    columns = np.asarray(columns, np.int64).reshape(-1)
    if columns.size and (columns.min() < 0 or columns.max() >= 10 * robot.n):
        raise ValueError(f"columns must lie in [0, {10 * robot.n}), got {columns.tolist()}")
    return columns


def regressor_columns(robot, columns, q, qd, qdd, gravity=None):
    """Columns of the joint-torque regressor at N states, as array code (no numba).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (its inertial parameters are not read).
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c (link k, parameter c of
        :data:`.base_parameters.PARAMETER_NAMES`).
    q, qd, qdd : array_like, shape (N, n)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    gravity : array_like, shape (3,), optional
        Gravity in the base frame [m/s^2]; default the robot's.

    Returns
    -------
    ndarray, shape (N, n, m)
        ``W[k, i, c]``: torque of joint i [N m or N] per unit parameter ``columns[c]``, i.e.
        :func:`.base_parameters.regressor`'s ``W[k, i, columns[c]]``.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n), or a column is out of range.

    Notes
    -----
    The recursion of :func:`.base_parameters.regressor` (Khalil & Kleinfinger 1987; Fu,
    Gonzalez & Lee 1987, Table 3.3) in the arithmetic of the compiled kernel, over blocks of
    :data:`BLOCK` set points, every asked column of a link carried inward at once.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("two-link")
    >>> z = np.zeros((1, 2))
    >>> W = regressor_columns(robot, [9, 19], z, z, z)   # the masses at rest: gravity only
    >>> W.shape
    (1, 2, 2)
    """
    columns = _checked_columns(robot, columns)
    q, qd, qdd = as_states(robot, q, qd, qdd, finite=False)
    g = np.asarray(robot.gravity if gravity is None else gravity, float).reshape(3)
    # the columns sorted by link: (link, parameter, where each column went, or None)
    order = np.argsort(columns // 10, kind="stable")
    back = None if np.all(order == np.arange(columns.size)) else np.argsort(order)
    link, param = columns[order] // 10, columns[order] % 10
    N = q.shape[0]
    out = np.empty((N, robot.n, columns.size))
    top = int(link.max()) + 1 if link.size else 0      # the links the columns can see
    for a in range(0, N, BLOCK):
        sl = slice(a, a + BLOCK)
        _put(out[sl], _block_columns(robot, _frames(robot, q[sl], top), link, param, qd[sl],
                                     qdd[sl], g), back)
    return out


def link_channels(robot, columns, q):
    """The coefficient functions of the regressor at positions q, per link, compiled.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (its inertial parameters are not read).
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c (link k, parameter c of
        :data:`.base_parameters.PARAMETER_NAMES`).
    q : array_like, shape (B, n)
        Joint positions [rad or m].

    Returns
    -------
    tuple of (int, ndarray of int, ndarray)
        Per link k with columns, ascending: M = k + 1, the indices in 0..m-1 of its columns
        (ascending), and their values V, shape (B, P, M, m_k), P = 1 + M + M (M + 1) / 2:
        ``V[b, 0, i, c]`` the gravity torque W(q, 0, 0) of joint i per unit parameter,
        ``V[b, 1 + j, i, c]`` the coefficient A_ij of qdd_j and ``V[b, 1 + M + t, i, c]`` the
        symmetrized coefficient C_ijl = C_ilj of qd_j qd_l, t the index of j <= l in
        ``numpy.triu_indices(M)``, so that W(q, qd, qdd) = G + A qdd + qd^T C qd on the joints
        i < M (the other joints' torques, and the other velocities and accelerations, do not
        involve link k) [N m or N per unit parameter, per rad/s^2 or m/s^2, per (rad/s)^2].

    Raises
    ------
    ValueError
        If q is not of shape (B, n), or a column is out of range.

    Notes
    -----
    One pass per position, in the compiled loop
    :func:`.regressor_compiled._channels_kernel`: the frames once, then outward the body-frame
    Jacobian of every link (its angular velocity w and its origin's velocity per unit qd_j,
    which are also the angular and linear accelerations per unit qdd_j at qd = 0) and the
    symmetrized coefficients of qd_j qd_l in its angular and linear accelerations at qdd = 0
    (the recursion of :func:`regressor_columns`, Khalil & Kleinfinger 1987, expanded in the
    products of velocities: it is linear in qdd and quadratic in qd). A link's wrench per unit
    parameter at each channel's state (the bilinear terms w x (E w) and w x (w x e)
    symmetrized in the two velocities) is read on each joint through its Jacobian column,
    tau_i = J_w,i . N + J_v,i . F (the inward recursion's moment about joint i's axis).
    The values equal those of :func:`regressor_columns` at the states (q, e_j, e_j) and (q,
    e_j + e_l, 0) to round-off, and each position's values do not depend on the others.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("two-link")
    >>> [(M, V.shape) for M, _, V in link_channels(robot, [9, 19], np.zeros((4, 2)))]
    [(1, (4, 3, 1, 1)), (2, (4, 6, 2, 1))]
    """
    columns = _checked_columns(robot, columns)
    q = np.ascontiguousarray(q, dtype=float)
    n = robot.n
    if q.ndim != 2 or q.shape[1] != n:
        raise ValueError(f"q must have shape (B, {n}), got {q.shape}")
    links = columns // 10
    order = np.argsort(links, kind="stable")
    counts = np.bincount(links, minlength=n)
    start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    B = q.shape[0]
    M = np.arange(1, n + 1)
    sizes = B * (1 + M + M * (M + 1) // 2) * M * counts
    offset = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    out = np.empty(int(sizes.sum()))
    top = int(links.max()) + 1 if columns.size else 0
    if B and top:
        from .regressor_compiled import _channels_kernel

        _channels_kernel(q, np.ascontiguousarray(robot.rotation, float),
                         np.ascontiguousarray(robot.translation, float),
                         np.asarray(robot.prismatic, np.int64),
                         np.ascontiguousarray(robot.gravity, float).reshape(3), top, start,
                         np.ascontiguousarray(columns[order] % 10), offset, out)
    groups = []
    for k in np.flatnonzero(counts):
        Mk = int(k) + 1
        block = out[offset[k]:offset[k] + sizes[k]].reshape(B, 1 + Mk + Mk * (Mk + 1) // 2, Mk,
                                                            int(counts[k]))
        groups.append((Mk, np.sort(order[start[k]:start[k + 1]]), block))
    return tuple(groups)


def _arguments(robot, columns, beta, q, qd, qdd):
    """The kernel's arguments but the outputs, with the states checked (a NaN state kept:
    the peak kernels pass over it)."""
    q, qd, qdd = as_states(robot, q, qd, qdd, finite=False)
    columns = np.asarray(columns, np.int64).reshape(-1)
    c = np.ascontiguousarray
    return (c(q, float), c(qd, float), c(qdd, float), c(robot.rotation, float),
            c(robot.translation, float), np.asarray(robot.prismatic, np.int64),
            c(robot.gravity, float), columns // 10, columns % 10, c(beta, float))


def part_regressor(robot, columns, q, qd, qdd):
    """Columns of the regressor, split into parts: the contributions at unit beta.

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
    columns = _checked_columns(robot, columns)
    return _contributions(_arguments(robot, columns, np.ones(columns.size), q, qd, qdd))


def _contributions(args):
    """The compiled kernel's contributions, shape (N, 3, n, m), on :func:`_arguments`."""
    (N, n), m = args[0].shape, args[-1].size
    out = np.empty((N, 3, n, m))
    from .regressor_compiled import _contributions_kernel

    _contributions_kernel(*args, True, out, np.zeros(n), np.zeros((m, 3, n)), np.zeros((m, n)))
    return out


def part_contributions(robot, base, q, qd, qdd):
    """Contribution of every (part, base parameter) to every joint torque.

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
        :data:`gd_analyze.symbolic.recursive.PARTS` (inertial: Y_b(q, 0, qdd) with g = 0; velocity:
        Y_b(q, qd, 0) with g = 0; gravity: Y_b(q, 0, 0) with the robot's gravity); summed
        over p and m it is tau. A view of an array laid out (N, 3, n, b).

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n).

    Notes
    -----
    The regressor of :func:`.base_parameters.regressor` (Khalil & Kleinfinger 1987; Fu,
    Gonzalez & Lee 1987, Table 3.3) on the independent columns, times beta (Gautier 1990).

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.dynamics.base_parameters import base_parameters
    >>> robot = load_robot("two-link")
    >>> base = base_parameters(robot)
    >>> z = np.zeros((4, 2))
    >>> part_contributions(robot, base, z, z, z).shape == (3, 4, 2, base.rank)
    True
    """
    columns = np.flatnonzero(base.independent.reshape(-1))
    return _contributions(_arguments(robot, columns, base.beta, q, qd, qdd)).transpose(1, 0, 2, 3)


def contribution_peaks(robot, base, q, qd, qdd, out=None):
    """Running peaks of the joint torques and of every part contribution.

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
    The contributions of :func:`part_contributions`, reduced as they are computed, set point
    by set point, so memory is O(n b) whatever N is. Peaks combine over chunks (and over trajectories) by maximum; a NaN
    contribution is never kept as a peak.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.dynamics.base_parameters import base_parameters
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
    from .regressor_compiled import _contributions_kernel

    _contributions_kernel(*args, False, np.empty((0, 3, n, b)), *out)
    return out


def stacked_contribution_peaks(robot, base, q, qd, qdd, lengths):
    """:func:`contribution_peaks` of each of K trajectories stacked one after the other.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters, b of them.
    q, qd, qdd : ndarray, shape (N, n)
        The K trajectories one after the other, N = sum(lengths), as :func:`as_states` gives
        them [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    lengths : sequence of int
        The set points of each trajectory, each >= 1, summing to N.

    Returns
    -------
    tau_peak : ndarray, shape (K, n)
        Peak |tau_i| on each trajectory [N m or N].
    peak : ndarray, shape (K, b, 3, n)
        Peak |contribution| of each (base parameter, part) on each trajectory [N m or N].
    whole_peak : ndarray, shape (K, b, n)
        The same for each base parameter, all parts together [N m or N].

    Notes
    -----
    One call of :func:`contribution_peaks` per trajectory, into its rows of the results. A
    NaN contribution is never a peak, and a trajectory whose every value is NaN keeps 0.
    """
    lengths = np.asarray([int(k) for k in lengths], dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(lengths)])
    K, n, b = lengths.size, robot.n, base.rank
    tau_peak, peak = np.zeros((K, n)), np.zeros((K, b, 3, n))
    whole_peak = np.zeros((K, b, n))
    q, qd, qdd = as_states(robot, q, qd, qdd, finite=False)
    for k in range(K):
        sl = slice(starts[k], starts[k + 1])
        contribution_peaks(robot, base, q[sl], qd[sl], qdd[sl],
                           out=(tau_peak[k], peak[k], whole_peak[k]))
    return tau_peak, peak, whole_peak


def _cross(a, b):
    """a x b over the first axis (length 3) of broadcastable arrays."""
    shape = np.broadcast_shapes(a.shape, b.shape)
    out = np.empty(shape)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


def _dot(a, b):
    """a . b over the first axis (length 3)."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def regressor_columns_pullback(robot, columns, q, qd, qdd, gravity=None):
    """:func:`regressor_columns` and its pullback: the weighted sum's gradient in the states.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (its inertial parameters are not read).
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c, as in :func:`regressor_columns`.
    q, qd, qdd : array_like, shape (N, n)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    gravity : array_like, shape (3,), optional
        Gravity in the base frame [m/s^2]; default the robot's.

    Returns
    -------
    W : ndarray, shape (N, n, m)
        :func:`regressor_columns` of the states.
    pullback : callable
        ``pullback(G)``, G of shape (N, n, m) (the weight of each entry of W), returns
        ``(gq, gqd, gqdd)``, each (N, n): gq[k, j] = sum_{i, c} G[k, i, c] dW[k, i, c] /
        dq[k, j], and likewise for qd and qdd [units of G W per rad, rad/s, rad/s^2].

    Notes
    -----
    Reverse-mode differentiation of the recursion (the adjoints of the outward velocities and
    accelerations, of the wrenches per unit parameter and of their inward transport, then of
    the frames' rotations in q): the gradient of every set point costs about three evaluations
    of the regressor, whatever n is, where forward differences cost 3 n + 1.
    """
    columns = _checked_columns(robot, columns)
    q, qd, qdd = as_states(robot, q, qd, qdd)
    g = np.asarray(robot.gravity if gravity is None else gravity, float).reshape(3)
    order = np.argsort(columns // 10, kind="stable")
    link, param = columns[order] // 10, columns[order] % 10
    N, n = q.shape
    m = columns.size
    prismatic = np.asarray(robot.prismatic, bool)
    Pr = np.asarray(robot.rotation, float)
    tp = np.asarray(robot.translation, float)
    # frames: R[j] (3, 3, N), R[j][r, c] = ^{j-1}R_j, and p[j] (3, N)
    R = np.empty((n, 3, 3, N))
    p = np.empty((n, 3, N))
    for j in range(n):
        P = Pr[j]
        if prismatic[j]:
            R[j] = P[:, :, None]
            p[j] = tp[j][:, None] + P[:, 2][:, None] * q[:, j]
        else:
            c, s = np.cos(q[:, j]), np.sin(q[:, j])
            R[j, :, 0] = np.outer(P[:, 0], c) + np.outer(P[:, 1], s)
            R[j, :, 1] = np.outer(P[:, 1], c) - np.outer(P[:, 0], s)
            R[j, :, 2] = P[:, 2][:, None]
            p[j] = tp[j][:, None]
    # outward: body-frame w, wd, vd of every link, and what their adjoints need
    top = int(link.max()) + 1 if m else 0
    z3 = np.zeros((3, N))
    prev = (z3, z3, np.repeat(-g[:, None], N, 1))
    tape, motion = [], []
    for j in range(top):
        w0, e0, v0 = prev
        a = v0 + _cross(e0, p[j]) + _cross(w0, _cross(w0, p[j]))
        Rt = R[j]
        wp = np.einsum("krN,kN->rN", Rt, w0)
        wd = np.einsum("krN,kN->rN", Rt, e0)
        vd = np.einsum("krN,kN->rN", Rt, a)
        u, acc = qd[:, j], qdd[:, j]
        w = wp.copy()
        if prismatic[j]:
            vd[2] += acc
            vd[0] += 2.0 * wp[1] * u
            vd[1] -= 2.0 * wp[0] * u
        else:
            wd[0] += wp[1] * u
            wd[1] -= wp[0] * u
            wd[2] += acc
            w[2] += u
        tape.append((w0, e0, v0, a, wp))
        motion.append((w, wd, vd))
        prev = (w, wd, vd)
    # every column's wrench per unit parameter at once: E the unit inertia tensor of an
    # inertia column, e the unit first moment of a first-moment column, mass 1 for a mass one
    E = np.zeros((m, 3, 3))
    e = np.zeros((3, m, 1))
    for c in range(m):
        if param[c] < 6:
            E[c, _JA[param[c]], _JB[param[c]]] = E[c, _JB[param[c]], _JA[param[c]]] = 1.0
        elif param[c] < 9:
            e[param[c] - 6, c] = 1.0
    mass = (param == 9)[:, None].astype(float)
    wl, wdl, vdl = (np.stack([mo[k] for mo in motion], 1)[:, link] for k in range(3))
    Ew = np.einsum("cab,bcN->acN", E, wl)
    F = _cross(wdl, e) + wl * _dot(wl, e) - e * _dot(wl, wl) + vdl * mass
    M = np.einsum("cab,bcN->acN", E, wdl) + _cross(wl, Ew) + _cross(e, vdl)
    W = np.zeros((n, m, N))
    first = np.searchsorted(link, np.arange(n))
    saved = {}
    for i in range(n - 1, -1, -1):
        s = first[i]
        if s == m:
            continue
        W[i, s:] = F[2, s:] if prismatic[i] else M[2, s:]
        if i == 0:
            break
        saved[i] = (F[:, s:].copy(), M[:, s:].copy())
        f = np.einsum("rkN,kcN->rcN", R[i], F[:, s:])
        M[:, s:] = np.einsum("rkN,kcN->rcN", R[i], M[:, s:]) + _cross(p[i][:, None], f)
        F[:, s:] = f
    back = np.argsort(order)
    Y = W[:, back].transpose(2, 0, 1)
    onehot = (link[:, None] == np.arange(top)).astype(float)      # (m, top)

    def pullback(G):
        G = np.asarray(G, float).reshape(N, n, m)[:, :, order].transpose(1, 2, 0)
        Fb = np.zeros((3, m, N))
        Mb = np.zeros((3, m, N))
        Rb = np.zeros((n, 3, 3, N))
        pb = np.zeros((n, 3, N))
        for i in range(n):
            s = first[i]
            if s == m:
                break
            if i > 0:
                Fi, Mi = saved[i]
                mb = Mb[:, s:]
                fpb = Fb[:, s:] + _cross(mb, p[i][:, None])
                f = np.einsum("rkN,kcN->rcN", R[i], Fi)
                Rb[i] += np.einsum("rcN,kcN->rkN", mb, Mi) + np.einsum("rcN,kcN->rkN", fpb, Fi)
                pb[i] += _cross(f, mb).sum(1)
                Mb[:, s:] = np.einsum("rkN,rcN->kcN", R[i], mb)
                Fb[:, s:] = np.einsum("rkN,rcN->kcN", R[i], fpb)
            (Fb if prismatic[i] else Mb)[2, s:] += G[i, s:]
        # the wrenches' adjoints, every column at once, summed per link
        wdb_c = np.einsum("cab,bcN->acN", E, Mb) + _cross(e, Fb)
        wb_c = (_cross(Ew, Mb) + np.einsum("cab,bcN->acN", E, _cross(Mb, wl))
                + Fb * _dot(wl, e) + e * _dot(Fb, wl) - 2.0 * _dot(Fb, e) * wl)
        vdb_c = _cross(Mb, e) + Fb * mass
        wb, wdb, vdb = (np.einsum("ck,acN->kaN", onehot, x) for x in (wb_c, wdb_c, vdb_c))
        gq = np.zeros((N, n))
        gqd = np.zeros((N, n))
        gqdd = np.zeros((N, n))
        for j in range(top - 1, -1, -1):
            w0, e0, v0, a, wp = tape[j]
            Rt = R[j]
            wpb = wb[j].copy()
            u = qd[:, j]
            if prismatic[j]:
                d = vdb[j]
                gqdd[:, j] += d[2]
                wpb[1] += 2.0 * d[0] * u
                wpb[0] -= 2.0 * d[1] * u
                gqd[:, j] += 2.0 * (d[0] * wp[1] - d[1] * wp[0])
            else:
                d = wdb[j]
                gqd[:, j] += wb[j][2] + d[0] * wp[1] - d[1] * wp[0]
                gqdd[:, j] += d[2]
                wpb[1] += d[0] * u
                wpb[0] -= d[1] * u
            ab = np.einsum("krN,rN->kN", Rt, vdb[j])
            e0b = np.einsum("krN,rN->kN", Rt, wdb[j])
            w0b = np.einsum("krN,rN->kN", Rt, wpb)
            Rb[j] += (np.einsum("kN,rN->krN", a, vdb[j]) + np.einsum("kN,rN->krN", e0, wdb[j])
                      + np.einsum("kN,rN->krN", w0, wpb))
            e0b += _cross(p[j], ab)
            pb[j] += _cross(ab, e0) + w0 * _dot(ab, w0) - ab * _dot(w0, w0)
            w0b += ab * _dot(w0, p[j]) + p[j] * _dot(ab, w0) - 2.0 * _dot(ab, p[j]) * w0
            if j > 0:
                wb[j - 1] += w0b
                wdb[j - 1] += e0b
                vdb[j - 1] += ab
        for j in range(n):
            P = Pr[j]
            if prismatic[j]:
                gq[:, j] += P[:, 2] @ pb[j]
            else:
                c, s = np.cos(q[:, j]), np.sin(q[:, j])
                d0 = np.outer(P[:, 1], c) - np.outer(P[:, 0], s)      # dR[:, 0] / dq
                d1 = -np.outer(P[:, 0], c) - np.outer(P[:, 1], s)     # dR[:, 1] / dq
                gq[:, j] += (Rb[j, :, 0] * d0).sum(0) + (Rb[j, :, 1] * d1).sum(0)
        return gq, gqd, gqdd

    return Y, pullback
