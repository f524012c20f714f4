"""The joint-limit region of an arm, the torque scale over it, and a model's error sampled on it.

R = {q_min <= q <= q_max, |qd| <= qd_max, |qdd| <= qdd_max} (issue 29). Over R the torque of
joint i is, per point q,

    tau_i = sum_j a_ij(q) qdd_j + sum_{j, l} C_ijl(q) qd_j qd_l + g_i(q)

(:mod:`gd_analyze.core.dynamics.regressor_bounds`), so its largest |value| over qdd is reached
with qdd_j = sign(a_ij) qdd_max_j exactly, and over qd it is sought at the vertices qd_j =
+-qd_max_j. The same formula with the dropped pairs' parameters gives the error of a pruned
model (Khalil & Kleinfinger 1987: tau = Y_b beta).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ..dynamics.dalembert import compiled_engine
from ..dynamics.regressor_bounds import channel_count
from ..symbolic.regressor_kernels import part_regressor, regressor_columns

__all__ = ["Region", "joint_region", "missing_limits", "sample_positions", "channel_values",
           "worst_states", "region_scale", "qd_vertices", "region_samples",
           "sampled_error"]


def channel_values(robot, q, columns, chunk=512, engine="auto"):
    """The coefficient functions of the regressor at points q, every channel.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : ndarray, shape (B, n)
        Joint positions [rad or m].
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c.
    chunk : int, optional
        Positions per call of the regressor (memory O(chunk n^3 m)).
    engine : {"auto", "numpy", "compiled"}, optional
        ``"auto"``: compiled from
        :data:`gd_analyze.core.dynamics.dalembert.COMPILED_MIN_SETPOINTS` positions B on,
        else array code (:func:`gd_analyze.core.symbolic.regressor_kernels.regressor_columns`,
        each part only at the states it is read at), which never imports numba; the same
        values to round-off.

    Returns
    -------
    ndarray, shape (B, C, n, m)
        As :func:`gd_analyze.core.dynamics.regressor_bounds.channel_values` (channel 0
        gravity, 1 + j inertial, 1 + n + n j + l velocity), with the velocity channels
        symmetrized: C_jl = C_lj, half the coefficient of qd_j qd_l (j != l).

    Raises
    ------
    ValueError
        If q does not have n columns, or the engine is unknown.

    Notes
    -----
    The regressor (:func:`gd_analyze.core.symbolic.base_parameters.regressor`, as
    :func:`gd_analyze.core.symbolic.regressor_kernels.part_regressor`) split into parts, at
    n (n + 1) / 2 states per point: (qd, qdd) = (e_j, e_j) gives C_jj and the inertial
    channel A_j (g = 0), qd = e_j + e_l (j < l) gives C_jl + C_lj + C_jj + C_ll (g = 0), and
    any of them the gravity channel G = W(q, 0, 0).
    """
    q = np.asarray(q, float)
    n = robot.n
    if q.ndim != 2 or q.shape[1] != n:
        raise ValueError(f"q must have shape (B, {n}), got {q.shape}")
    columns = np.asarray(columns, int)
    eye = np.eye(n)
    jj, ll = np.triu_indices(n)                               # j <= l; the diagonal first
    order = np.argsort(jj != ll, kind="stable")
    jj, ll = jj[order], ll[order]
    qd_units = eye[jj] + eye[ll] * (jj != ll)[:, None]        # e_j + e_l, or e_j
    qdd_units = eye[jj] * (jj == ll)[:, None]                 # e_j on the diagonal
    S = jj.size
    out = np.empty((q.shape[0], channel_count(n), n, columns.size))
    compiled = compiled_engine(engine, q.shape[0])
    for a in range(0, q.shape[0], chunk):
        qc = q[a:a + chunk]
        B = qc.shape[0]
        if compiled:
            W = part_regressor(robot, columns, np.repeat(qc, S, axis=0),
                               np.tile(qd_units, (B, 1)), np.tile(qdd_units, (B, 1)),
                               engine="compiled").reshape(B, S, 3, n, -1)
            grav, inertial, velocity = W[:, 0, 2], W[:, :n, 0], W[:, :, 1]
        else:       # each part at the states it is read at only: 1 + n + S per position
            grav, inertial, velocity = _channel_parts(robot, columns, qc, qd_units, qdd_units)
        diag = velocity[:, :n]                                # C_jj: (B, j, i, m)
        Cm = out[a:a + B, 1 + n:].reshape((B, n, n) + diag.shape[2:])     # a view of out
        Cm[:, np.arange(n), np.arange(n)] = diag
        off = 0.5 * (velocity[:, n:] - diag[:, jj[n:]] - diag[:, ll[n:]])
        Cm[:, jj[n:], ll[n:]] = off
        Cm[:, ll[n:], jj[n:]] = off
        out[a:a + B, 0] = grav
        out[a:a + B, 1:1 + n] = inertial
    return out


def _channel_parts(robot, columns, qc, qd_units, qdd_units):
    """The numpy engine of :func:`channel_values` on B positions: the gravity part at rest
    (B, n, m), the inertial part at qdd = e_j (B, n, n, m) and the velocity part at every
    state's qd (B, S, n, m), all with g = 0 but gravity's."""
    B, n = qc.shape
    S = qd_units.shape[0]
    z, g0 = np.zeros((B * S, n)), np.zeros(3)
    grav = regressor_columns(robot, columns, qc, z[:B], z[:B])
    qn = np.repeat(qc, n, axis=0)
    inertial = regressor_columns(robot, columns, qn, z[:B * n], np.tile(qdd_units[:n], (B, 1)),
                                 gravity=g0)
    velocity = regressor_columns(robot, columns, np.repeat(qc, S, axis=0),
                                 np.tile(qd_units, (B, 1)), z, gravity=g0)
    m = columns.size
    return grav, inertial.reshape(B, n, n, m), velocity.reshape(B, S, n, m)


@dataclass(frozen=True, eq=False)
class Region:
    """A box of joint positions with velocity and acceleration limits.

    Attributes
    ----------
    q_min, q_max : ndarray, shape (n,)
        [rad or m]; a continuous joint is [-pi, pi].
    qd_max : ndarray, shape (n,)
        [rad/s or m/s].
    qdd_max : ndarray, shape (n,)
        [rad/s^2 or m/s^2].
    """

    q_min: np.ndarray
    q_max: np.ndarray
    qd_max: np.ndarray
    qdd_max: np.ndarray

    def contains(self, q, qd, qdd, rtol=1e-9):
        """Whether every state lies in the region (up to rtol of each limit).

        Parameters
        ----------
        q, qd, qdd : ndarray, shape (N, n)
            [rad, rad/s, rad/s^2; m, m/s, m/s^2].
        rtol : float, optional
            Relative slack for limits reached exactly.

        Returns
        -------
        ndarray of bool, shape (3, n)
            Per quantity (q, qd, qdd) and joint: all set points within the limit.
        """
        span = np.maximum(np.abs(self.q_max - self.q_min), 1e-300)
        return np.stack([
            np.all((q >= self.q_min - rtol * span) & (q <= self.q_max + rtol * span), axis=0),
            np.all(np.abs(qd) <= self.qd_max * (1 + rtol), axis=0),
            np.all(np.abs(qdd) <= self.qdd_max * (1 + rtol), axis=0)])


def missing_limits(robot):
    """Why an arm has no region: the first joint without a position or velocity limit.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    str
        e.g. "joint 2 has no velocity limit"; "" when every joint has both (a revolute joint
        without position limits is continuous and covers the full circle).
    """
    for j in range(robot.n):
        if robot.prismatic[j] and not (np.isfinite(robot.q_min[j])
                                       and np.isfinite(robot.q_max[j])):
            return f"joint {j + 1} has no position limit"
        if not (np.isfinite(robot.qd_max[j]) and robot.qd_max[j] > 0):
            return f"joint {j + 1} has no velocity limit"
    return ""


def joint_region(robot, qdd_max):
    """The region of an arm's own limits.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    qdd_max : array_like, shape (n,)
        Acceleration limits [rad/s^2 or m/s^2] (the robot's, or the planner's default where it
        has none: :func:`gd_analyze.io.planning.acceleration_limits`).

    Returns
    -------
    Region

    Raises
    ------
    ValueError
        If a limit is missing (:func:`missing_limits`) or qdd_max is not finite and positive.
    """
    why = missing_limits(robot)
    if why:
        raise ValueError(why)
    qdd_max = np.asarray(qdd_max, float)
    if qdd_max.shape != (robot.n,) or not (np.isfinite(qdd_max).all() and (qdd_max > 0).all()):
        raise ValueError("acceleration limits must be finite and positive, one per joint")
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, np.pi)
    full = (hi - lo) > 2 * np.pi                    # more than a turn: the full circle
    rev = ~np.asarray(robot.prismatic, bool)
    lo = np.where(rev & full, -np.pi, lo)
    hi = np.where(rev & full, np.pi, hi)
    return Region(q_min=lo.astype(float), q_max=hi.astype(float),
                  qd_max=np.asarray(robot.qd_max, float).copy(), qdd_max=qdd_max.copy())


def sample_positions(region, count, seed=0):
    """Joint positions in the region: uniform, plus every joint at its limits in turn.

    Parameters
    ----------
    region : Region
    count : int
        Uniform samples.
    seed : int, optional

    Returns
    -------
    ndarray, shape (M, n)
        [rad or m], M = count + 2 n + 2 (each joint at either limit with the others uniform,
        and all joints at their lower and upper limits).
    """
    rng = np.random.default_rng(seed)
    n = region.q_min.size
    q = rng.uniform(region.q_min, region.q_max, (count, n))
    ext = rng.uniform(region.q_min, region.q_max, (2 * n, n))
    for j in range(n):
        ext[2 * j, j], ext[2 * j + 1, j] = region.q_min[j], region.q_max[j]
    return np.vstack([q, ext, region.q_min, region.q_max])


def qd_vertices(qd_max):
    """The vertices of the velocity box, one of each pair x, -x.

    Parameters
    ----------
    qd_max : ndarray, shape (n,)
        Velocity limits [rad/s or m/s].

    Returns
    -------
    ndarray, shape (K, n)
        The 2^(n-1) sign patterns whose first sign is + times qd_max, or 4,096 random ones
        beyond 13 joints. A quadratic form takes the same value at x and -x
        (x^T C x = (-x)^T C (-x)), so its largest |value| over the vertices is reached at
        one of these: the velocity terms h are such forms in qd (Eq. (3.4-27)).

    Examples
    --------
    >>> qd_vertices(np.array([1.0, 2.0])).tolist()
    [[1.0, -2.0], [1.0, 2.0]]
    """
    n = qd_max.size
    if n > 13:                                       # 4,096 vertices at most: random signs
        signs = np.random.default_rng(0).choice([-1.0, 1.0], (4096, n))
    else:
        signs = np.array(list(itertools.product([-1.0, 1.0], repeat=n - 1)),
                         float).reshape(2 ** (n - 1), n - 1)  # one joint: one empty pattern
        signs = np.hstack([np.ones((signs.shape[0], 1)), signs])
    return signs * qd_max


def worst_states(V, weights, qd_max, qdd_max):
    """The largest |torque| of weighted columns over the velocity and acceleration limits, at
    each sampled position.

    Parameters
    ----------
    V : ndarray, shape (B, C, n, m)
        :func:`gd_analyze.core.dynamics.regressor_bounds.channel_values` at B positions.
    weights : ndarray, shape (3, m)
        Per part (inertial, velocity, gravity) the parameter value of each column (0: left
        out) [kg m^2, kg m, kg].
    qd_max, qdd_max : ndarray, shape (n,)
        [rad/s, rad/s^2; m/s, m/s^2].

    Returns
    -------
    value : ndarray, shape (B, n)
        max over qd vertices and |qdd| <= qdd_max of |tau_i| [N m or N].
    qd : ndarray, shape (B, n, n)
        Per position and joint i, the velocity vertex reached.
    qdd : ndarray, shape (B, n, n)
        Per position and joint i, the acceleration reached: sign(a_ij) qdd_max_j.
    """
    B, C, n, m = V.shape
    g = V[:, 0] @ weights[2]                                    # (B, n)
    a = np.einsum("bjim,m->bij", V[:, 1:1 + n], weights[0])     # (B, n, n)
    Cq = V[:, 1 + n:] @ weights[1]                              # (B, n n, n)
    verts = qd_vertices(np.asarray(qd_max, float))                # (K, n)
    outer = (verts[:, :, None] * verts[:, None, :]).reshape(-1, n * n)
    quad = np.swapaxes(outer @ Cq, 1, 2) + g[:, :, None]        # (B, n, K): qd^T C_i qd
    k = np.abs(quad).argmax(axis=2)                             # (B, n)
    lin = np.abs(a) @ qdd_max
    value = np.take_along_axis(np.abs(quad), k[:, :, None], 2)[:, :, 0] + lin
    sign = np.sign(np.take_along_axis(quad, k[:, :, None], 2))       # (B, n, 1)
    sign = np.where(sign == 0, 1.0, sign)
    qdd = np.sign(a) * sign * qdd_max
    return value, verts[k], np.where(qdd == 0, qdd_max, qdd)


def region_scale(robot, region, columns, beta, torque_floor=0.0, samples=1000, seed=0,
                 refine=1, values=None):
    """s_i = max(largest |tau_i| found over the region, torque floor), and where.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    region : Region
    columns : ndarray of int, shape (m,)
        The base parameters' flat standard indices.
    beta : ndarray, shape (m,)
        Their values.
    torque_floor : float, optional
        [N m or N].
    samples : int, optional
        Uniform position samples (plus the extremes of :func:`sample_positions`).
    seed : int, optional
    refine : int, optional
        Best samples per joint (0: none) polished by a local maximisation over q
        (scipy.optimize.minimize, L-BFGS-B within the position limits).
    values : (ndarray, ndarray), optional
        Positions (B, n) and their :func:`channel_values`, when already sampled.

    Returns
    -------
    scale : ndarray, shape (n,)
        [N m or N]. A found maximum is a lower bound of the true one, so a bound relative to
        it errs on the safe side.
    state : ndarray, shape (n, 3 n)
        Per joint, (q, qd, qdd) where |tau_i| reaches the found maximum.
    """
    from scipy.optimize import minimize

    n = robot.n
    W = np.tile(np.asarray(beta, float), (3, 1))
    q, V = values if values is not None else (None, None)
    if q is None:
        q = sample_positions(region, samples, seed)
        V = channel_values(robot, q, columns)
    value, qd, qdd = worst_states(V, W, region.qd_max, region.qdd_max)
    best = value.max(axis=0)
    state = np.zeros((n, 3 * n))
    for i in range(n):
        order = np.argsort(-value[:, i])[:max(1, refine)]
        k = order[0]
        state[i] = np.concatenate([q[k], qd[k, i], qdd[k, i]])

        def neg(x, i=i):                # -|tau_i| and its forward-difference gradient
            pts = np.vstack([x, x + 1e-6 * np.eye(n)])
            v = worst_states(channel_values(robot, pts, columns), W, region.qd_max,
                             region.qdd_max)[0][:, i]
            return -v[0], -(v[1:] - v[0]) / 1e-6
        for k in order[:refine]:
            res = minimize(neg, q[k], jac=True, method="L-BFGS-B",
                           bounds=list(zip(region.q_min, region.q_max - 1e-6)),
                           options={"maxiter": 10})
            x = np.clip(res.x, region.q_min, region.q_max)
            v, vqd, vqdd = worst_states(channel_values(robot, x[None, :], columns), W,
                                        region.qd_max, region.qdd_max)
            if v[0, i] > best[i]:
                best[i] = v[0, i]
                state[i] = np.concatenate([x, vqd[0, i], vqdd[0, i]])
    return np.maximum(best, torque_floor), state


def region_samples(robot, base, region, samples=1000, seed=0):
    """The sampled positions of a region, their channel values, and the scale found there.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        The base parameters whose columns and values are read (b of them).
    region : Region
    samples : int, optional
        Uniform position samples (plus the extremes of :func:`sample_positions`).
    seed : int, optional

    Returns
    -------
    tuple
        ``(positions (B, n) [rad or m], channel values (B, C, n, b)`` (:func:`channel_values`),
        ``scale (n,) [N m or N], scale_state (n, 3 n))``: :func:`region_scale` without a
        floor; what :func:`gd_analyze.core.selection.certify.certify` computes before its
        branch and bound, for the same samples and seed.
    """
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = sample_positions(region, samples, seed)
    V = channel_values(robot, q, cols)
    scale, scale_state = region_scale(robot, region, cols, np.asarray(base.beta, float),
                                      values=(q, V))
    return q, V, scale, scale_state


def sampled_error(base, region, dropped, values):
    """The largest error of a pruned model found over the region, relative to s_i there.

    Sampling only: no bound is proved (that is
    :func:`gd_analyze.core.selection.certify.certify`, which samples the same positions).

    Parameters
    ----------
    base : BaseParameters
        The arm's b base parameters.
    region : Region
    dropped : ndarray of bool, shape (b, 3)
        The pairs (base parameter, part: inertial, velocity, gravity) the model leaves out
        (:class:`gd_analyze.core.symbolic.recursive_model.RecursiveModel`).
    values : tuple
        :func:`region_samples` (or the same from a certification with torque floor 0).

    Returns
    -------
    error : ndarray, shape (n,)
        max over the sampled positions, the velocity vertices and |qdd| <= qdd_max of
        |tau_i - tau_s,i| (the dropped pairs' torque, tau = Y_b beta), divided by s_i, the
        largest |tau_i| found over the region (a joint with s_i = 0 gives 0) [1]. A largest
        value found: a lower bound of the true maximum, not a proved bound.
    state : ndarray, shape (n, 3 n)
        Per joint i, the state (q, qd, qdd) where that error was found.
    """
    q, V, scale, _ = values
    weights = np.asarray(base.beta, float)[None, :] * np.asarray(dropped, float).T   # (3, b)
    err, qd, qdd = worst_states(V, weights, region.qd_max, region.qdd_max)
    k = err.argmax(axis=0)                                            # (n,)
    joints = np.arange(q.shape[1])
    state = np.hstack([q[k], qd[k, joints], qdd[k, joints]])
    return err[k, joints] / np.where(scale > 0, scale, np.inf), state
