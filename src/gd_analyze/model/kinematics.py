"""Forward kinematics of a serial chain of revolute and prismatic joints, batched over set points.

The joint model is that of :mod:`gd_analyze.model.robot`: joint i has a fixed placement (P_i,
t_i) in body frame i-1 and then turns about (revolute) or slides along (prismatic) the placed
frame's z axis, so::

    ^{i-1}T_i = [[P_i Rot_z(q_i), t_i], [0, 1]]              (revolute)
    ^{i-1}T_i = [[P_i, t_i + q_i P_i e_z], [0, 1]]            (prismatic)

with e_z = (0, 0, 1). Joint i's axis is z of body frame i, through its origin. For a standard
DH robot the link frames (body frame i moved by the fixed pose L_i) are the DH frames of
Eq. (3.2-5), and :func:`link_matrices` gives the DH link matrices ^{i-1}A_i.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError, expect
from .limits import real_values
from .robot import Robot

__all__ = ["as_states", "transforms_core", "joint_frames", "joint_transforms", "body_frames",
           "link_matrices", "frames", "centres_of_mass"]


def as_states(robot: Robot, *arrays: ArrayLike, names: Sequence[str] | None = None,
              finite: bool = True) -> tuple[np.ndarray, ...]:
    """Check joint arrays against the robot and give them a leading set-point axis.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    *arrays : array_like, shape (N, n) or (n,)
        Joint positions [rad or m], velocities [rad/s or m/s] or accelerations [rad/s^2 or
        m/s^2].
    names : sequence of str, optional
        The arrays' names for the messages (default ``q``, ``qd``, ``qdd`` in order).
    finite : bool, optional
        Refuse NaN and inf (default); False for a kernel that keeps a NaN state out of its
        peaks (:func:`gd_analyze.dynamics.regressor_kernels.contribution_peaks`).

    Returns
    -------
    tuple of ndarray, each shape (N, n)
        Float arrays; a single state (n,) becomes (1, n).

    Raises
    ------
    InputError
        If ``robot`` is not a :class:`~gd_analyze.model.robot.Robot`, an array's last axis is
        not n, it has more than two axes, the arrays do not all have the same number of set
        points N, an array holds complex or non-numeric values
        (:func:`~gd_analyze.model.limits.real_values`), or NaN or inf (``finite``): one line
        naming the argument, and for NaN or inf the first set point k (counted from 0) and
        joint j (from 1) that holds one.
    """
    expect(robot, Robot, "robot", "a Robot (from load_robot)")
    out = []
    names = [*(names or ()), *["q", "qd", "qdd"][len(names or ()):], *["array"] * len(arrays)]
    for name, x in zip(names, arrays):
        x = real_values(name, x)
        x = x[None, :] if x.ndim == 1 else x            # one state: one set point
        if x.ndim != 2 or x.shape[1] != robot.n:
            raise InputError(f"{name}: expected shape (N, {robot.n}) for {robot.name}, got {x.shape}")
        # a finite sum: every value finite (one pass, no temporary array); else look closer
        if finite and not (np.isfinite(x.sum()) or np.isfinite(x).all()):
            k, j = np.argwhere(~np.isfinite(x))[0]
            raise InputError(f"{name}: {x[k, j]} at set point {k}, joint {j + 1}: must be finite")
        out.append(x)
    if len({x.shape[0] for x in out}) > 1:
        raise InputError("arrays disagree on the number of set points: " + ", ".join(
            f"{name} {x.shape}" for name, x in zip(names, out)))
    return tuple(out)


def transforms_core(P: np.ndarray, t: np.ndarray, prismatic: Sequence[bool] | np.ndarray, c: np.ndarray,
                    s: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation and translation of every ^{i-1}T_i; float or object (counting) arrays alike.

    Parameters
    ----------
    P : ndarray, shape (n, 3, 3)
        Placement rotations P_i.
    t : ndarray, shape (n, 3)
        Placement translations t_i [m].
    prismatic : sequence of bool, length n
        The joint types.
    c, s : ndarray, shape (N, n)
        cos q_i and sin q_i (read for revolute joints only).
    q : ndarray, shape (N, n)
        Joint positions (read for prismatic joints only) [m].

    Returns
    -------
    R : ndarray, shape (N, n, 3, 3)
        ^{i-1}R_i.
    p : ndarray, shape (N, n, 3)
        Origin of body frame i in body frame i-1 [m].
    """
    N, n = q.shape
    R = np.empty((N, n, 3, 3), dtype=q.dtype)
    p = np.empty((N, n, 3), dtype=q.dtype)
    for i in range(n):
        Pi = P[i]
        if prismatic[i]:
            R[:, i] = Pi
            p[:, i] = t[i] + q[:, i, None] * Pi[:, 2]
        else:
            ci, si = c[:, i, None], s[:, i, None]
            R[:, i, :, 0] = ci * Pi[:, 0] + si * Pi[:, 1]
            R[:, i, :, 1] = ci * Pi[:, 1] - si * Pi[:, 0]
            R[:, i, :, 2] = Pi[:, 2]
            p[:, i] = t[i]
    return R, p


def joint_frames(robot: Robot, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """^{i-1}R_i and ^{i-1}p_i of every joint: :func:`transforms_core` for a robot.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : ndarray, shape (N, n)
        Joint positions [rad or m], already checked (see :func:`as_states`).

    Returns
    -------
    R : ndarray, shape (N, n, 3, 3)
        ^{i-1}R_i [1].
    p : ndarray, shape (N, n, 3)
        Origin of body frame i in body frame i-1 [m].

    Raises
    ------
    ValueError
        If q does not have n columns (numpy's broadcasting error); check q with
        :func:`as_states` first.

    Notes
    -----
    The rotation and translation parts of ^{i-1}T_i, the joint matrices of Eqs. (3.2-8a) and
    (3.2-8b) of Fu, Gonzalez & Lee (1987): P_i Rot(z, q_i) for a revolute joint, P_i Trans(0,
    0, q_i) for a prismatic one.
    """
    return transforms_core(robot.rotation, robot.translation, robot.prismatic, np.cos(q),
                           np.sin(q), q)


def joint_transforms(robot: Robot, q: ArrayLike) -> np.ndarray:
    """The transforms ^{i-1}T_i between consecutive body frames.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n)
        Joint positions [rad or m].

    Returns
    -------
    T : ndarray, shape (N, n, 4, 4)
        ``T[k, i]`` is the homogeneous transform from body frame i+1 to body frame i (0-based
        i; body frame 0 is the base) at set point k; lengths in [m].

    Raises
    ------
    ValueError
        If q does not have n columns.

    Notes
    -----
    The revolute form is P_i Rot(z, q_i), the prismatic one P_i Trans(0, 0, q_i): the
    motions of the joint matrices Q of Eqs. (3.2-8a) and (3.2-8b).
    """
    (q,) = as_states(robot, q)
    return _homogeneous(*joint_frames(robot, q))


def body_frames(robot: Robot, q: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Orientation and origin of every body frame in the base frame.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n)
        Joint positions [rad or m].

    Returns
    -------
    R : ndarray, shape (N, n, 3, 3)
        ``R[k, i]`` is ^0R of body frame i+1; its column 2 is joint i+1's axis z.
    o : ndarray, shape (N, n, 3)
        ``o[k, i]`` is the origin of body frame i+1 [m], a point on joint i+1's axis.

    Raises
    ------
    ValueError
        If q does not have n columns.
    """
    (q,) = as_states(robot, q)
    Rr, pr = joint_frames(robot, q)
    N, n = q.shape
    R = np.empty((N, n, 3, 3))
    o = np.empty((N, n, 3))
    R[:, 0], o[:, 0] = Rr[:, 0], pr[:, 0]
    for i in range(1, n):
        R[:, i] = R[:, i - 1] @ Rr[:, i]
        o[:, i] = o[:, i - 1] + np.einsum("kab,kb->ka", R[:, i - 1], pr[:, i])
    return R, o


def _homogeneous(R, t):
    T = np.zeros(np.shape(R)[:-2] + (4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = t
    T[..., 3, 3] = 1.0
    return T


def link_matrices(robot: Robot, q: ArrayLike) -> np.ndarray:
    """The transforms ^{i-1}A_i between consecutive link frames (DH matrices for DH robots).

    Link frame i is where link i's centre of mass and inertia are given: DH frame i for a
    standard-DH robot, so that ``A`` is the link matrix of Eq. (3.2-5); modified-DH frame i
    (Craig) for a modified-DH robot; body frame i for a general chain.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n)
        Joint positions [rad or m].

    Returns
    -------
    A : ndarray, shape (N, n, 4, 4)
        ``A[k, i]`` is the homogeneous transform from link frame i+1 to link frame i (0-based
        i; frame 0 is the base) at set point k; lengths in [m].

    Raises
    ------
    ValueError
        If q does not have n columns.
    """
    T = joint_transforms(robot, q)
    L = _homogeneous(robot.link_rotation, robot.link_translation)          # (n, 4, 4)
    Linv = np.linalg.inv(L)
    left = np.concatenate([np.eye(4)[None], Linv[:-1]], axis=0)            # L_{i-1}^-1
    return left @ T @ L


def frames(robot: Robot, q: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Orientation and origin of every link frame in the base frame.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n)
        Joint positions [rad or m].

    Returns
    -------
    R : ndarray, shape (N, n+1, 3, 3)
        ``R[k, i]`` is ^0R_i, the rotation from link frame i to the base frame (``R[:, 0]``
        is the identity). For a standard-DH robot these are the DH frames, and column 2 of
        ^0R_{j-1} is the axis z_{j-1} of joint j.
    p : ndarray, shape (N, n+1, 3)
        ``p[k, i]`` is the origin p_i of link frame i in the base frame [m] (``p[:, 0]`` is 0).

    Raises
    ------
    ValueError
        If q does not have n columns.

    Notes
    -----
    ^0T_i = ^0A_1 ^1A_2 ... ^{i-1}A_i, Eq. (3.2-6).
    """
    Rb, ob = body_frames(robot, q)
    N, n = Rb.shape[:2]
    R = np.empty((N, n + 1, 3, 3))
    p = np.empty((N, n + 1, 3))
    R[:, 0] = np.eye(3)
    p[:, 0] = 0.0
    R[:, 1:] = Rb @ robot.link_rotation
    p[:, 1:] = ob + np.einsum("ksab,sb->ksa", Rb, robot.link_translation)
    return R, p


def centres_of_mass(robot: Robot, R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Centres of mass of the links in the base frame.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    R : ndarray, shape (N, n+1, 3, 3)
        Link frame orientations from :func:`frames`.
    p : ndarray, shape (N, n+1, 3)
        Link frame origins from :func:`frames` [m].

    Returns
    -------
    rbar : ndarray, shape (N, n, 3)
        ``rbar[k, s]`` is the centre of mass of link s+1, p_s + ^0R_s r_s, Eq. (3.4-3) [m].
    """
    return p[:, 1:] + np.einsum("ksab,sb->ksa", R[:, 1:], robot.com)
