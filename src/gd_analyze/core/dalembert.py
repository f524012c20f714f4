"""The generalized d'Alembert (G-D) equations of motion, Sec. 3.4.

The G-D equations, Eq. (3.4-24), write the joint torques as::

    tau = (D_tran + D_rot) qdd + h_tran + h_rot + c

where the "tran" parts come from the translational motion of the link masses and the "rot"
parts from the rotational motion of the link inertias, Eqs. (3.4-25) to (3.4-28). In Jacobian
form, with z_{j-1} and p_{j-1} the axis and origin of frame j-1, rbar_s the centre of mass of
link s, Ib_s = R_s I_s R_s^T, and for j <= s (columns j > s are zero)::

    Jv_s[:, j] = z_{j-1} x (rbar_s - p_{j-1}),     Jw_s[:, j] = z_{j-1}

    D_tran = sum_s m_s Jv_s^T Jv_s                                   (3.4-25), 2nd term
    D_rot  = sum_s Jw_s^T Ib_s Jw_s                                  (3.4-25), 1st term
    h_tran = sum_s m_s Jv_s^T (dJv_s/dt qd)                          (3.4-26)
    h_rot  = sum_s Jw_s^T (Ib_s (dJw_s/dt qd) + w_s x Ib_s w_s)      (3.4-27)
    c      = -sum_s m_s Jv_s^T g                                     (3.4-28)

The velocity-product accelerations dJv_s/dt qd and dJw_s/dt qd are computed with the outward
recursion of the link velocities (Eqs. 3.4-1 to 3.4-7 with qdd = 0), and the sums over links
s >= j with suffix sums, so the cost is O(n^2) per set point for D and O(n) for h and c.
Everything is batched over set points and processed in chunks of bounded size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kinematics import as_states, centres_of_mass, frames

__all__ = ["forward_dynamics", "GDTerms", "gd_terms", "DEFAULT_CHUNK", "ENGINES", "COMPILED_MIN_SETPOINTS"]

#: Set points per chunk of the numpy engine: bounds its temporaries to a few tens of MB.
DEFAULT_CHUNK = 8192
#: The engines: "numpy" (array code, the Jacobian form as written) and "compiled" (numba).
ENGINES = ("auto", "numpy", "compiled")
#: With engine="auto", trajectories of at least this many set points use the compiled engine;
#: shorter ones use numpy and so never pay for importing numba or loading compiled code.
COMPILED_MIN_SETPOINTS = 2000


@dataclass(frozen=True, eq=False)
class GDTerms:
    """The G-D terms at N set points.

    Attributes
    ----------
    D_tran : ndarray, shape (N, n, n)
        Translational part of the inertia matrix, Eq. (3.4-25) [kg m^2].
    D_rot : ndarray, shape (N, n, n)
        Rotational part of the inertia matrix, Eq. (3.4-25) [kg m^2].
    h_tran : ndarray, shape (N, n)
        Translational part of the Coriolis and centrifugal torques, Eq. (3.4-26) [N m].
    h_rot : ndarray, shape (N, n)
        Rotational part of the Coriolis and centrifugal torques, Eq. (3.4-27) [N m].
    c : ndarray, shape (N, n)
        Gravity loading, Eq. (3.4-28) [N m].

    Notes
    -----
    Source: Fu, Gonzalez & Lee (1987), Eqs. (3.4-24) to (3.4-28); Lee, Lee & Nigam (1983).
    """

    D_tran: np.ndarray
    D_rot: np.ndarray
    h_tran: np.ndarray
    h_rot: np.ndarray
    c: np.ndarray

    @property
    def D(self):
        """ndarray, shape (N, n, n): the inertia matrix D = D_tran + D_rot [kg m^2]."""
        return self.D_tran + self.D_rot

    @property
    def h(self):
        """ndarray, shape (N, n): Coriolis and centrifugal torques h = h_tran + h_rot [N m]."""
        return self.h_tran + self.h_rot

    def tau(self, qdd):
        """Joint torques tau = D qdd + h + c, Eq. (3.4-24).

        Parameters
        ----------
        qdd : array_like, shape (N, n)
            Joint accelerations [rad/s^2].

        Returns
        -------
        ndarray, shape (N, n)
            Joint torques [N m].
        """
        qdd = np.asarray(qdd, dtype=float).reshape(self.c.shape)
        return np.einsum("kij,kj->ki", self.D, qdd) + self.h + self.c


def _suffix_sum(x):
    """Sum over links s >= j along axis 1: out[:, j] = sum_{s>=j} x[:, s]."""
    return np.flip(np.cumsum(np.flip(x, axis=1), axis=1), axis=1)


def _gd_chunk(robot, q, qd):
    n = robot.n
    m = robot.mass
    R, p = frames(robot, q)
    z = R[:, :n, :, 2]                      # z_{j-1}, (N, n, 3)
    p_prev = p[:, :n]                       # p_{j-1}, (N, n, 3)
    rbar = centres_of_mass(robot, R, p)     # (N, n, 3)
    Rl = R[:, 1:]                           # ^0R_s, (N, n, 3, 3)
    Ib = Rl @ robot.inertia @ np.swapaxes(Rl, -1, -2)   # (N, n, 3, 3)

    # --- D_tran: sum_s m_s Jv_s^T Jv_s, Jv[:, s, j] = z_j x (rbar_s - p_j), j <= s
    Jv = np.cross(z[:, None, :, :], rbar[:, :, None, :] - p_prev[:, None, :, :])  # (N, s, j, 3)
    Jv *= np.tril(np.ones((n, n)))[None, :, :, None]
    D_tran = np.einsum("ksia,s,ksja->kij", Jv, m, Jv, optimize=True)

    # --- D_rot: z_i^T (sum_{s >= max(i,j)} Ib_s) z_j
    Ic = _suffix_sum(Ib)                    # (N, n, 3, 3)
    idx = np.maximum.outer(np.arange(n), np.arange(n))
    Iz = np.einsum("ksab,kjb->ksja", Ic, z)  # Ic_s z_j, (N, s, j, 3)
    D_rot = np.einsum("kia,kija->kij", z, Iz[:, idx, np.arange(n)[None, :], :])

    # --- velocities and velocity-product accelerations (qdd = 0), outward recursion
    wz = qd[:, :, None] * z                 # qd_j z_{j-1}
    w = np.cumsum(wz, axis=1)               # w_s, (N, n, 3)
    w_prev = np.concatenate([np.zeros_like(w[:, :1]), w[:, :-1]], axis=1)
    wd = np.cumsum(np.cross(w_prev, wz), axis=1)        # dJw_s/dt qd
    dp = p[:, 1:] - p_prev                  # p_s - p_{s-1}
    ap = np.cumsum(np.cross(wd, dp) + np.cross(w, np.cross(w, dp)), axis=1)  # origin p_s
    rc = rbar - p[:, 1:]
    abar = ap + np.cross(wd, rc) + np.cross(w, np.cross(w, rc))   # dJv_s/dt qd

    # --- h_tran and c: z_j . sum_{s>=j} (rbar_s - p_{j-1}) x F_s, with F_s = m_s a_s
    def moment_about_axes(F):
        M = _suffix_sum(np.cross(rbar, F))
        S = _suffix_sum(F)
        return np.einsum("kja,kja->kj", z, M - np.cross(p_prev, S))

    h_tran = moment_about_axes(m[None, :, None] * abar)
    c = -moment_about_axes(np.broadcast_to(m[:, None] * robot.gravity, rbar.shape))

    # --- h_rot: z_j . sum_{s>=j} (Ib_s wd_s + w_s x Ib_s w_s)
    Iw = np.einsum("ksab,ksb->ksa", Ib, w)
    f = np.einsum("ksab,ksb->ksa", Ib, wd) + np.cross(w, Iw)
    h_rot = np.einsum("kja,kja->kj", z, _suffix_sum(f))
    return D_tran, D_rot, h_tran, h_rot, c


def gd_terms(robot, q, qd, chunk=DEFAULT_CHUNK, engine="auto"):
    """The G-D terms D_tran, D_rot, h_tran, h_rot and c at N set points.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s].
    chunk : int, optional
        Set points processed at once by the numpy engine; bounds the temporaries, not the
        result.
    engine : {"auto", "numpy", "compiled"}, optional
        ``"numpy"``: array code over chunks of set points. ``"compiled"``: a numba kernel, one
        pass per set point (about 10 times faster). ``"auto"``: compiled for N >=
        :data:`COMPILED_MIN_SETPOINTS`, numpy otherwise.

    Returns
    -------
    GDTerms
        D_tran and D_rot with shape (N, n, n) [kg m^2]; h_tran, h_rot and c with shape (N, n)
        [N m].

    Raises
    ------
    ValueError
        If q or qd does not have shape (N, n), they disagree on N, or the engine is unknown.

    Notes
    -----
    Source: Eqs. (3.4-24) to (3.4-28) of Fu, Gonzalez & Lee (1987), in the Jacobian form given
    in the module docstring. D_tran and D_rot are symmetric; their sum is the inertia matrix D
    of Eq. (3.2-31).

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot, gd_terms
    >>> robot = load_robot("two-link")
    >>> terms = gd_terms(robot, np.zeros((1, 2)), np.zeros((1, 2)))
    >>> round(float(terms.D[0, 1, 1]), 6)   # m2 l^2 / 3
    0.333333
    """
    q, qd = as_states(robot, q, qd)
    N, n = q.shape
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}, got {engine!r}")
    out = (np.empty((N, n, n)), np.empty((N, n, n)), np.empty((N, n)), np.empty((N, n)),
           np.empty((N, n)))
    if engine == "compiled" or (engine == "auto" and N >= COMPILED_MIN_SETPOINTS):
        from .kernels import gd_kernel

        c = np.ascontiguousarray
        gd_kernel(c(q), c(qd), robot.d, robot.a, robot.alpha, robot.offset, robot.mass,
                  c(robot.com), c(robot.inertia), c(robot.gravity, dtype=float), *out)
        return GDTerms(*out)
    chunk = max(1, int(chunk))
    for start in range(0, N, chunk):
        sl = slice(start, start + chunk)
        for dst, src in zip(out, _gd_chunk(robot, q[sl], qd[sl])):
            dst[sl] = src
    return GDTerms(*out)


def _qdd_from_terms(terms, tau):
    rhs = np.asarray(tau, dtype=float) - terms.h - terms.c
    return np.linalg.solve(terms.D, rhs[..., None])[..., 0]


def forward_dynamics(robot, q, qd, tau, engine="auto"):
    """Joint accelerations of the arm under given torques, qdd = D^-1 (tau - h - c).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s].
    tau : array_like, shape (N, n) or (n,)
        Joint torques [N m].
    engine : {"auto", "numpy", "compiled"}, optional
        Engine of :func:`~gd_analyze.core.dalembert.gd_terms`.

    Returns
    -------
    ndarray, shape (N, n)
        Joint accelerations qdd [rad/s^2].

    Raises
    ------
    ValueError
        If the arrays do not have n columns or disagree on N, or the engine is unknown.
    numpy.linalg.LinAlgError
        If D is singular at some set point (it is positive definite for a physical arm).

    Notes
    -----
    Eq. (3.4-24) of Fu, Gonzalez & Lee (1987) solved for qdd, with D = D_tran + D_rot and
    h = h_tran + h_rot from Eqs. (3.4-25) to (3.4-28); one ``numpy.linalg.solve`` per set
    point, batched.
    """
    q, qd, tau = as_states(robot, q, qd, tau)
    return _qdd_from_terms(gd_terms(robot, q, qd, engine=engine), tau)
