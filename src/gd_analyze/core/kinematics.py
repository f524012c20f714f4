"""Forward kinematics of a DH chain, batched over set points.

Frame 0 is the base frame; link frame i (i = 1..n) sits at the far end of link i. The transform
from frame i-1 to frame i is the link matrix of Eq. (3.2-5)::

    ^{i-1}A_i = [[C_i, -cos(alpha_i) S_i,  sin(alpha_i) S_i, a_i C_i],
                 [S_i,  cos(alpha_i) C_i, -sin(alpha_i) C_i, a_i S_i],
                 [0,    sin(alpha_i),      cos(alpha_i),      d_i    ],
                 [0,    0,                 0,                 1      ]]

with C_i = cos(theta_i), S_i = sin(theta_i), theta_i = q_i + offset_i.
"""

from __future__ import annotations

import numpy as np

__all__ = ["as_states", "link_matrices", "frames", "centres_of_mass"]


def as_states(robot, *arrays):
    """Check joint arrays against the robot and give them a leading set-point axis.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    *arrays : array_like, shape (N, n) or (n,)
        Joint positions [rad], velocities [rad/s] or accelerations [rad/s^2].

    Returns
    -------
    tuple of ndarray, each shape (N, n)
        Float arrays; a single state (n,) becomes (1, n).

    Raises
    ------
    ValueError
        If an array's last axis is not n, if it has more than two axes, or if the arrays do not
        all have the same number of set points N.
    """
    out = []
    for x in arrays:
        x = np.asarray(x, dtype=float)
        if x.ndim == 1:
            x = x[None, :]
        if x.ndim != 2 or x.shape[1] != robot.n:
            raise ValueError(f"expected shape (N, {robot.n}) for {robot.name}, got {x.shape}")
        out.append(x)
    if len({x.shape[0] for x in out}) > 1:
        raise ValueError(f"arrays disagree on the number of set points: {[x.shape for x in out]}")
    return tuple(out)


def link_matrices(robot, q):
    """The link matrices ^{i-1}A_i for every set point, Eq. (3.2-5).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n)
        Joint positions [rad].

    Returns
    -------
    A : ndarray, shape (N, n, 4, 4)
        ``A[k, i]`` is the homogeneous transform from frame i to frame i+1 (0-based i) at set
        point k; lengths in [m].

    Raises
    ------
    ValueError
        If q does not have n columns.
    """
    (q,) = as_states(robot, q)
    theta = q + robot.offset
    ct, st = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(robot.alpha), np.sin(robot.alpha)
    A = np.zeros(q.shape + (4, 4))
    A[..., 0, 0] = ct
    A[..., 0, 1] = -ca * st
    A[..., 0, 2] = sa * st
    A[..., 0, 3] = robot.a * ct
    A[..., 1, 0] = st
    A[..., 1, 1] = ca * ct
    A[..., 1, 2] = -sa * ct
    A[..., 1, 3] = robot.a * st
    A[..., 2, 1] = sa
    A[..., 2, 2] = ca
    A[..., 2, 3] = robot.d
    A[..., 3, 3] = 1.0
    return A


def frames(robot, q):
    """Orientation and origin of every link frame in the base frame.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n)
        Joint positions [rad].

    Returns
    -------
    R : ndarray, shape (N, n+1, 3, 3)
        ``R[k, i]`` is ^0R_i, the rotation from frame i to the base frame (``R[:, 0]`` is the
        identity). Column 2 of ^0R_{j-1} is the joint axis z_{j-1}.
    p : ndarray, shape (N, n+1, 3)
        ``p[k, i]`` is the origin p_i of frame i in the base frame [m] (``p[:, 0]`` is 0).

    Raises
    ------
    ValueError
        If q does not have n columns.

    Notes
    -----
    ^0T_i = ^0A_1 ^1A_2 ... ^{i-1}A_i, Eq. (3.2-6).
    """
    A = link_matrices(robot, q)
    N, n = A.shape[:2]
    R = np.empty((N, n + 1, 3, 3))
    p = np.empty((N, n + 1, 3))
    R[:, 0] = np.eye(3)
    p[:, 0] = 0.0
    for i in range(n):
        R[:, i + 1] = R[:, i] @ A[:, i, :3, :3]
        p[:, i + 1] = p[:, i] + np.einsum("kab,kb->ka", R[:, i], A[:, i, :3, 3])
    return R, p


def centres_of_mass(robot, R, p):
    """Centres of mass of the links in the base frame.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    R : ndarray, shape (N, n+1, 3, 3)
        Frame orientations from :func:`frames`.
    p : ndarray, shape (N, n+1, 3)
        Frame origins from :func:`frames` [m].

    Returns
    -------
    rbar : ndarray, shape (N, n, 3)
        ``rbar[k, s]`` is the centre of mass of link s+1, p_s + ^0R_s r_s, Eq. (3.4-3) [m].
    """
    return p[:, 1:] + np.einsum("ksab,sb->ksa", R[:, 1:], robot.com)
