"""The Lagrange-Euler (L-E) equations of motion, Sec. 3.2, batched over set points.

The chapter writes the joint torques of an n-joint arm as Eq. (3.2-26),
``tau = D(q) qdd + h(q, qd) + c(q)``, with (1-based indices, link j, joints i, k, m)::

    U_ij  = dT_i/dq_j  = ^0T_j' Q_j ^j'T_i                          j <= i, else 0     (3.2-11)
    U_ijk = dU_ij/dq_k = ^0T_j' Q_j ^j'T_k' Q_k ^k'T_i             i >= k >= j
                       = ^0T_k' Q_k ^k'T_j' Q_j ^j'T_i             i >= j >= k, else 0 (3.2-13)
    D_ik  = sum_{j >= max(i,k)}   Tr(U_jk J_j U_ji^T)                                  (3.2-31)
    h_ikm = sum_{j >= max(i,k,m)} Tr(U_jkm J_j U_ji^T)                                 (3.2-33)
    h_i   = sum_k sum_m h_ikm qd_k qd_m                                                (3.2-32)
    c_i   = sum_{j >= i} (-m_j g^T U_ji rbar_j)                                        (3.2-34)

where the frames are the body frames of :mod:`gd_analyze.model.robot`: frame j' = body
frame j, whose z axis is joint j's axis (the role of DH frame j-1 in the book), ^j'T_i the
products of the transforms ^{i-1}T_i between body frames
(:func:`~gd_analyze.model.kinematics.joint_transforms`; the book's link matrices of
Eq. (3.2-5) with the joint at the start of its frame), Q_j the
joint matrix of Eq. (3.2-8a) (revolute) or Eq. (3.2-8b) (prismatic), J_j the 4x4
pseudo-inertia matrix of link j, Eq. (3.2-18), g = (g_x, g_y, g_z, 0) the gravity row vector
and rbar_j = (r_j, 1) the centre of mass of link j, both in body frame j.

The algorithm core (:func:`le_core`) uses nothing but array indexing, ``@``, ``+`` and ``*``,
so the very same code also runs on object arrays of counting scalars: that is how
:mod:`gd_analyze.dynamics.opcount` measures its cost per set point.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..model.kinematics import as_states, joint_transforms
from .dalembert import assemble_tau

if TYPE_CHECKING:
    from ..model.robot import Robot


__all__ = ["Q_REVOLUTE", "Q_PRISMATIC", "joint_q_matrices", "DEFAULT_CHUNK", "LETerms", "pseudo_inertia", "u_matrices", "le_terms"]

#: The matrix Q of a revolute joint, Eq. (3.2-8a): dA/dq = Q A, Eq. (3.2-9).
Q_REVOLUTE = np.array([[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]])
Q_REVOLUTE.setflags(write=False)
#: The matrix Q of a prismatic joint, Eq. (3.2-8b).
Q_PRISMATIC = np.array([[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, 0, 0]])
Q_PRISMATIC.setflags(write=False)


def joint_q_matrices(robot: Robot) -> np.ndarray:
    """The joint matrices Q_j of every joint, Eqs. (3.2-8a) and (3.2-8b).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.

    Returns
    -------
    ndarray of int, shape (n, 4, 4)
        Q_REVOLUTE or Q_PRISMATIC per joint (exact 0 and 1 entries).
    """
    return np.stack([Q_PRISMATIC if p else Q_REVOLUTE for p in robot.prismatic])

#: Set points per chunk: U_ijk has N n^3 16 entries (28 MB for 1024 set points of a 6-joint arm).
DEFAULT_CHUNK = 1024


@dataclass(frozen=True, eq=False)
class LETerms:
    """The L-E dynamic coefficients at N set points.

    Attributes
    ----------
    D : ndarray, shape (N, n, n)
        Inertia (acceleration-related) matrix, Eq. (3.2-31) [kg m^2].
    h : ndarray, shape (N, n)
        Coriolis and centrifugal torques, Eq. (3.2-32) [N m].
    c : ndarray, shape (N, n)
        Gravity loading, Eq. (3.2-34) [N m].
    h_ikm : ndarray, shape (N, n, n, n)
        Velocity coefficients h_ikm of Eq. (3.2-33), ``h_ikm[:, i, k, m]`` [kg m^2], so that
        h_i = sum_km h_ikm qd_k qd_m.

    Notes
    -----
    Source: Fu, Gonzalez & Lee (1987), Eqs. (3.2-26) to (3.2-34).
    """

    D: np.ndarray
    h: np.ndarray
    c: np.ndarray
    h_ikm: np.ndarray

    def tau(self, qdd: ArrayLike) -> np.ndarray:
        """Joint torques tau = D qdd + h + c, Eq. (3.2-26).

        Parameters
        ----------
        qdd : array_like, shape (N, n)
            Joint accelerations [rad/s^2].

        Returns
        -------
        ndarray, shape (N, n)
            Joint torques [N m].

        Raises
        ------
        ValueError
            If qdd cannot be reshaped to (N, n).
        """
        return assemble_tau(self.D, self.h, self.c, qdd)


def pseudo_inertia(robot: Robot, frame: str = "link") -> np.ndarray:
    """The pseudo-inertia matrices J_i of the links, Eq. (3.2-18).

    J_i = int r r^T dm over link i, with r = (x, y, z, 1) in link frame i. It is built from the
    link's mass m, centre of mass rbar and inertia tensor I_c about the centre of mass: the
    second moment about the centre of mass is S_c = Tr(I_c)/2 E_3 - I_c, moved to the frame
    origin with the parallel-axis theorem, S = S_c + m rbar rbar^T, and::

        J = [[S,        m rbar],
             [m rbar^T, m     ]]

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    frame : {"link", "body"}, optional
        Link frame i (DH frame i for a DH robot, as in the book) or body frame i (the frame of
        :func:`le_terms`).

    Returns
    -------
    J : ndarray, shape (n, 4, 4)
        Pseudo-inertia matrices, symmetric; [kg m^2] in the upper-left 3x3 block, [kg m] in the
        last row and column, [kg] in the corner.

    Raises
    ------
    AttributeError
        If ``robot`` lacks the inertial attributes of :class:`~gd_analyze.model.robot.Robot`.

    Notes
    -----
    Eq. (3.2-17) defines J_i; Eq. (3.2-18) writes its diagonal as (-I_xx + I_yy + I_zz)/2 etc.
    with the moments about the frame origin. ``robot.inertia`` holds tensor elements, whose
    off-diagonals are minus the products of inertia int x y dm, hence the minus sign above.
    """
    m = robot.mass
    r = robot.com if frame == "link" else robot.body_com
    Ic = robot.inertia if frame == "link" else robot.body_inertia
    trace = np.trace(Ic, axis1=1, axis2=2)
    S = (0.5 * trace[:, None, None] * np.eye(3) - Ic              # about the centre of mass
         + m[:, None, None] * r[:, :, None] * r[:, None, :])   # parallel-axis theorem
    J = np.zeros((robot.n, 4, 4))
    J[:, :3, :3] = S
    J[:, :3, 3] = m[:, None] * r
    J[:, 3, :3] = m[:, None] * r
    J[:, 3, 3] = m
    return J


def _chain(A):
    """P[a][b] = ^aT_b = A_{a+1} ... A_b for 0 <= a <= b <= n (P[a][a] is the identity)."""
    N, n = A.shape[:2]
    eye = np.zeros((N, 4, 4), dtype=A.dtype)
    for d in range(4):
        eye[:, d, d] = 1
    P = [[None] * (n + 1) for _ in range(n + 1)]
    for a in range(n + 1):
        P[a][a] = eye
        for b in range(a + 1, n + 1):
            P[a][b] = A[:, b - 1] if b == a + 1 else P[a][b - 1] @ A[:, b - 1]
    return P


def _u_core(A, Q):
    """U_ij and U_ijk, Eqs. (3.2-11) and (3.2-13), from the body transforms A (N, n, 4, 4) and
    the joint matrices Q (n, 4, 4).

    0-based: ``U[:, i, j]`` = dT_{i+1}/dq_{j+1}; ``U3[:, i, j, k]`` = d^2 T_{i+1}/dq_{j+1}dq_{k+1}.
    """
    N, n = A.shape[:2]
    Q = Q.astype(A.dtype)
    P = _chain(A)
    U = np.zeros((N, n, n, 4, 4), dtype=A.dtype)
    U3 = np.zeros((N, n, n, n, 4, 4), dtype=A.dtype)
    TQ = [P[0][j + 1] @ Q[j] for j in range(n)]               # ^0T_j' Q_j
    for j in range(n):
        for i in range(j, n):
            U[:, i, j] = TQ[j] @ P[j + 1][i + 1]               # Eq. (3.2-11)
        for k in range(j, n):
            TQTQ = TQ[j] @ P[j + 1][k + 1] @ Q[k]              # ^0T_j' Q_j ^j'T_k' Q_k
            for i in range(k, n):
                U3[:, i, j, k] = TQTQ @ P[k + 1][i + 1]        # Eq. (3.2-13), i >= k >= j
                U3[:, i, k, j] = U3[:, i, j, k]                # i >= j >= k: same product
    return U, U3


def le_core(A: np.ndarray, Q: np.ndarray, J: np.ndarray, gm: np.ndarray, rbar: np.ndarray,
            qd: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """D, h_ikm, h and c of Eqs. (3.2-31) to (3.2-34) for body transforms A (N, n, 4, 4).

    Q (n, 4, 4): joint matrices; J (n, 4, 4): pseudo-inertias; gm (n, 4): the row vectors
    -m_j g^T; rbar (n, 4): homogeneous centres of mass; qd (N, n). Works on float and on
    object arrays alike.
    """
    N, n = A.shape[:2]
    U, U3 = _u_core(A, Q)
    D = np.zeros((N, n, n), dtype=A.dtype)
    H = np.zeros((N, n, n, n), dtype=A.dtype)
    c = np.zeros((N, n), dtype=A.dtype)
    for j in range(n):
        s = slice(0, j + 1)                                    # i, k, m <= j
        Uj = U[:, j, s].reshape(N, j + 1, 16)                  # rows: U_ji flattened
        UJ = (U[:, j, s] @ J[j]).reshape(N, j + 1, 16)         # U_jk J_j
        # Tr(X Y^T) = sum_ab X_ab Y_ab: D_ik += Tr(U_jk J_j U_ji^T), Eq. (3.2-31)
        D[:, s, s] = D[:, s, s] + Uj @ np.swapaxes(UJ, -1, -2)
        U3J = (U3[:, j, s, s] @ J[j]).reshape(N, (j + 1) ** 2, 16)      # U_jkm J_j
        Hj = (Uj @ np.swapaxes(U3J, -1, -2)).reshape(N, j + 1, j + 1, j + 1)
        H[:, s, s, s] = H[:, s, s, s] + Hj                     # Eq. (3.2-33)
        c[:, s] = c[:, s] + (U[:, j, s] @ rbar[j]) @ gm[j]     # Eq. (3.2-34)
    Hq = (H @ qd[:, None, :, None])[..., 0]                    # sum_m h_ikm qd_m
    h = (Hq @ qd[:, :, None])[..., 0]                          # Eq. (3.2-32)
    return D, H, h, c


def le_constants(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-robot constants of the L-E core: J (n, 4, 4), -m g^T (n, 4), rbar (n, 4)."""
    g = np.append(np.asarray(robot.gravity, dtype=float), 0.0)
    gm = -robot.mass[:, None] * g
    rbar = np.concatenate([robot.body_com, np.ones((robot.n, 1))], axis=1)
    return pseudo_inertia(robot, "body"), gm, rbar


def u_matrices(robot: Robot, q: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The derivative matrices U_ij and U_ijk at N set points, Eqs. (3.2-11) and (3.2-13).

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad or m].

    Returns
    -------
    U : ndarray, shape (N, n, n, 4, 4)
        ``U[:, i, j]`` = d(^0T_i)/dq_j of body frame i (0-based link i and joint j; zero
        for j > i); [m/rad] in the last column, [1/rad] elsewhere (revolute joint j); [1]
        in the last column, 0 elsewhere (prismatic joint j).
    U3 : ndarray, shape (N, n, n, n, 4, 4)
        ``U3[:, i, j, k]`` = d(U_ij)/dq_k (zero if j > i or k > i), symmetric in j and k.

    Raises
    ------
    ValueError
        If q does not have n columns.
    """
    return _u_core(joint_transforms(robot, q), joint_q_matrices(robot))


def le_terms(robot: Robot, q: ArrayLike, qd: ArrayLike, chunk: int = DEFAULT_CHUNK) -> LETerms:
    """The L-E coefficients D, h, c and h_ikm at N set points, Eqs. (3.2-31) to (3.2-34).

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad or m].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s or m/s].
    chunk : int, optional
        Set points processed at once; bounds the temporaries (U_ijk), not the result.

    Returns
    -------
    LETerms
        D (N, n, n) [kg m^2], h and c (N, n) [N m], h_ikm (N, n, n, n) [kg m^2].

    Raises
    ------
    ValueError
        If q or qd does not have shape (N, n), or they disagree on N.

    Notes
    -----
    Vectorised over set points; the loops run over links only. The cost per set point grows as
    n^4 (the traces of Eq. (3.2-33)); see :mod:`gd_analyze.dynamics.opcount`.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.dynamics.lagrange_euler import le_terms
    >>> terms = le_terms(load_robot("two-link"), np.zeros(2), np.zeros(2))
    >>> round(float(terms.D[0, 1, 1]), 6)   # m2 l^2 / 3
    0.333333
    """
    q, qd = as_states(robot, q, qd)
    N, n = q.shape
    J, gm, rbar = le_constants(robot)
    Q = joint_q_matrices(robot)
    out = (np.empty((N, n, n)), np.empty((N, n)), np.empty((N, n)), np.empty((N, n, n, n)))
    chunk = max(1, int(chunk))
    for start in range(0, N, chunk):
        sl = slice(start, start + chunk)
        D, H, h, c = le_core(joint_transforms(robot, q[sl]), Q, J, gm, rbar, qd[sl])
        for dst, src in zip(out, (D, h, c, H)):
            dst[sl] = src
    return LETerms(*out)
