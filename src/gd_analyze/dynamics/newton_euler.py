"""The recursive Newton-Euler (N-E) equations of motion in link coordinates, Sec. 3.3.

Every vector of link i is expressed in its own frame (the book's ^iR_0 w_i etc.), as in
Table 3.3 and Algorithm 3.1 (Luh, Walker & Paul 1980), for revolute and prismatic joints. The
frames are the body frames of :mod:`gd_analyze.model.robot`: joint i's axis is
z0 = (0, 0, 1) of frame i itself, R_i = ^{i-1}R_i, and p_i = ^{i-1}p_i is the origin of frame
i seen from frame
i-1 in frame i-1 (it grows with q_i for a prismatic joint); sbar_i and I_i are link i's centre
of mass and inertia tensor about it in frame i. With the joint at the start of its link, the
outward step carries the origin's acceleration across link i-1 before rotating into frame i
(the book's p*_i term, Eq. (3.3-52), taken one frame earlier, as in Craig's outward equations).

Forward recursion, i = 1..n (w_0 = wd_0 = 0, vd_0 = -g to include gravity, Eq. (3.3-46)),
u_i = R_i^T w_{i-1}::

    revolute:  w_i  = u_i + z0 qd_i                                                (3.3-50)
               wd_i = R_i^T wd_{i-1} + z0 qdd_i + u_i x z0 qd_i                    (3.3-51)
    prismatic: w_i  = u_i,   wd_i = R_i^T wd_{i-1}               (Table 3.3, prismatic rows)
    vd_i   = R_i^T (vd_{i-1} + wd_{i-1} x p_i + w_{i-1} x (w_{i-1} x p_i))         (3.3-52)
             [prismatic: + z0 qdd_i + 2 w_i x z0 qd_i]
    abar_i = wd_i x sbar_i + w_i x (w_i x sbar_i) + vd_i                           (3.3-53)

Backward recursion, i = n..1 (f_{n+1}, n_{n+1}: force and moment the hand exerts on a load)::

    F_i = m_i abar_i,   N_i = I_i wd_i + w_i x (I_i w_i)                   (3.3-54), (3.3-55)
    f_i = R_{i+1} f_{i+1} + F_i                                                    (3.3-56)
    n_i = R_{i+1} n_{i+1} + p_{i+1} x (R_{i+1} f_{i+1}) + sbar_i x F_i + N_i        (3.3-57)
    tau_i = n_i . z0 + b_i qd_i (revolute),  f_i . z0 + b_i qd_i (prismatic)       (3.3-58)

The recursion core (:func:`ne_core`) uses only indexing, ``@``, ``+``, ``-`` and ``*``, so it
runs unchanged on object arrays of counting scalars (:mod:`gd_analyze.dynamics.opcount`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..model.kinematics import as_states, joint_frames

if TYPE_CHECKING:
    from ..model.robot import Robot


__all__ = ["ne_tau", "ne_terms", "link_constants", "joint_frames"]


def ne_cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b along the last axis (broadcasting), for float and object arrays."""
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _mv(M, v):
    """M v along the last axes: M (..., 3, 3), v (..., 3)."""
    return (M @ v[..., None])[..., 0]


def link_constants(robot: Robot) -> dict[str, Any]:
    """The per-link constants of the recursion in link (body-frame) coordinates.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.

    Returns
    -------
    dict
        ``sbar`` (n, 3): centre of mass in body frame i [m]; ``mass`` (n,) [kg]; ``inertia``
        (n, 3, 3): I_i about the centre of mass, body-frame axes [kg m^2]; ``vd0`` (3,): -g,
        the base acceleration that stands for gravity, Eq. (3.3-46) [m/s^2].

    Raises
    ------
    AttributeError
        If ``robot`` lacks the attributes of :class:`~gd_analyze.model.robot.Robot`.
    """
    return {"sbar": np.array(robot.body_com, dtype=float),
            "mass": np.array(robot.mass, dtype=float),
            "inertia": np.array(robot.body_inertia, dtype=float),
            "vd0": -np.asarray(robot.gravity, dtype=float)}


def ne_core(R: np.ndarray, p: np.ndarray, prismatic: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
            k: dict[str, Any], f_end: np.ndarray | None = None, n_end: np.ndarray | None = None,
            b: np.ndarray | None = None) -> np.ndarray:
    """Table 3.3 for rotations R (N, n, 3, 3) = ^{i-1}R_i and origins p (N, n, 3) = ^{i-1}p_i.

    prismatic: n bools; qd, qdd (N, n); constants k. Returns tau (N, n). Works on float and on
    object arrays alike.
    """
    N, n = qd.shape
    dt = R.dtype
    z0 = np.zeros(3, dtype=dt)
    z0[2] = 1
    w = np.zeros((N, 3), dtype=dt)
    wd = np.zeros((N, 3), dtype=dt)
    vd = k["vd0"]
    F, NN = [], []                                               # F_i, N_i
    for i in range(n):                                           # forward, i = 1..n
        Rt = np.swapaxes(R[:, i], -1, -2)                        # ^iR_{i-1}
        pi = p[:, i]
        vd = _mv(Rt, vd + ne_cross(wd, pi) + ne_cross(w, ne_cross(w, pi)))    # Eq. (3.3-52)
        u = _mv(Rt, w)
        if prismatic[i]:
            w = u
            wd = _mv(Rt, wd)
            vd = vd + z0 * qdd[:, i, None] + ne_cross(w, z0 * (2 * qd[:, i, None]))
        else:
            zq = z0 * qd[:, i, None]
            wd = _mv(Rt, wd) + z0 * qdd[:, i, None] + ne_cross(u, zq)      # Eq. (3.3-51)
            w = u + zq                                                   # Eq. (3.3-50)
        s = k["sbar"][i]
        abar = ne_cross(wd, s) + ne_cross(w, ne_cross(w, s)) + vd              # Eq. (3.3-53)
        I = k["inertia"][i]
        F.append(k["mass"][i] * abar)                                    # Eq. (3.3-54)
        NN.append(_mv(I, wd) + ne_cross(w, _mv(I, w)))                     # Eq. (3.3-55)
    f = np.zeros((N, 3), dtype=dt) if f_end is None else f_end
    nm = np.zeros((N, 3), dtype=dt) if n_end is None else n_end
    tau: list[Any] = [None] * n
    for i in range(n - 1, -1, -1):                               # backward, i = n..1
        if i < n - 1:                                            # R_{n+1} is the identity
            f, nm = _mv(R[:, i + 1], f), _mv(R[:, i + 1], nm)
            nm = nm + ne_cross(p[:, i + 1], f)
        nm = nm + ne_cross(k["sbar"][i], F[i]) + NN[i]                                 # (3.3-57)
        f = f + F[i]                                                                 # (3.3-56)
        t = f[:, 2] if prismatic[i] else nm[:, 2]                # f_i . z0 or n_i . z0
        tau[i] = t if b is None else t + b[i] * qd[:, i]         # Eq. (3.3-58)
    return np.stack(tau, axis=-1)


def _load(x, N, name):
    if x is None:
        return None
    x = np.asarray(x, dtype=float)
    if x.shape == (3,):
        x = np.broadcast_to(x, (N, 3))
    if x.shape != (N, 3):
        raise ValueError(f"{name} must have shape (3,) or ({N}, 3), got {x.shape}")
    return x


def ne_tau(robot: Robot, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, b: ArrayLike | None = None,
           f_load: ArrayLike | None = None, n_load: ArrayLike | None = None) -> np.ndarray:
    """Joint torques by the recursive N-E equations, Table 3.3 / Algorithm 3.1.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad or m].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s or m/s].
    qdd : array_like, shape (N, n) or (n,)
        Joint accelerations [rad/s^2].
    b : array_like, shape (n,), optional
        Viscous damping coefficients b_i; adds b_i qd_i to tau_i, Eq. (3.3-58) [N m s/rad].
    f_load : array_like, shape (3,) or (N, 3), optional
        f_{n+1}: the force the hand exerts on a load, in link frame n (DH frame n for a DH
        robot) [N] (step N4).
    n_load : array_like, shape (3,) or (N, 3), optional
        n_{n+1}: the moment the hand exerts on the load about the origin of link frame n, in
        link frame n [N m].

    Returns
    -------
    tau : ndarray, shape (N, n)
        Joint torques [N m].

    Raises
    ------
    ValueError
        If q, qd or qdd does not have shape (N, n) or they disagree on N, if b does not have
        shape (n,), or if a load vector has the wrong shape.

    Notes
    -----
    Source: Fu, Gonzalez & Lee (1987), Eqs. (3.3-50) to (3.3-59), Table 3.3, Algorithm 3.1.
    Vectorised over set points; the loops run over links only. With no load and no damping
    tau = D qdd + h + c of Eq. (3.2-26).

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.dynamics.newton_euler import ne_tau
    >>> tau = ne_tau(load_robot("two-link"), np.zeros(2), np.zeros(2), np.zeros(2))
    >>> round(float(tau[0, 1]), 4)          # c2 = m2 g l / 2
    4.9031
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    N = q.shape[0]
    if b is not None:
        b = np.asarray(b, dtype=float)
        if b.shape != (robot.n,):
            raise ValueError(f"b must have shape ({robot.n},), got {b.shape}")
    R, p = joint_frames(robot, q)
    f_end, n_end = _load(f_load, N, "f_load"), _load(n_load, N, "n_load")
    if f_end is not None or n_end is not None:     # from link frame n to body frame n
        LR, Lt = robot.link_rotation[-1], robot.link_translation[-1]
        f_end = np.zeros((N, 3)) if f_end is None else f_end @ LR.T
        n_end = (np.zeros((N, 3)) if n_end is None else n_end @ LR.T) + np.cross(Lt, f_end)
    return ne_core(R, p, robot.prismatic, qd, qdd, link_constants(robot), f_end, n_end, b)


def ne_terms(robot: Robot, q: ArrayLike,
             qd: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """D, h and c of Eq. (3.2-26) by probing the N-E recursion (Problems 3.11 and 3.12).

    c = NE(q, 0, 0); h = NE(q, qd, 0) - c; column j of D = NE(q, 0, e_j) - c, where NE is the
    recursion of :func:`ne_tau` without load or damping.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad or m].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s or m/s].

    Returns
    -------
    D : ndarray, shape (N, n, n)
        Inertia matrix [kg m^2].
    h : ndarray, shape (N, n)
        Coriolis and centrifugal torques [N m].
    c : ndarray, shape (N, n)
        Gravity loading [N m].

    Raises
    ------
    ValueError
        If q or qd does not have shape (N, n), or they disagree on N.

    Notes
    -----
    n + 2 batched recursions; the rotation matrices are computed once.
    """
    q, qd = as_states(robot, q, qd)
    N, n = q.shape
    R, p = joint_frames(robot, q)
    k = link_constants(robot)
    pr = robot.prismatic
    zero = np.zeros((N, n))
    c = ne_core(R, p, pr, zero, zero, k)
    h = ne_core(R, p, pr, qd, zero, k) - c
    D = np.empty((N, n, n))
    for j in range(n):
        e = np.zeros((N, n))
        e[:, j] = 1.0
        D[:, :, j] = ne_core(R, p, pr, zero, e, k) - c
    return D, h, c
