"""The generalized d'Alembert (G-D) equations of motion, Sec. 3.4.

The G-D equations, Eq. (3.4-24), write the joint torques (forces, for a prismatic joint) as::

    tau = (D_tran + D_rot) qdd + h_tran + h_rot + c

where the "tran" parts come from the translational motion of the link masses and the "rot"
parts from the rotational motion of the link inertias, Eqs. (3.4-25) to (3.4-28). In Jacobian
form, with z_j and o_j the axis and origin of body frame j (joint j's axis, see
:mod:`gd_analyze.model.robot`), rbar_s the centre of mass of link s, Ib_s = R_s I_s R_s^T,
and for j <= s (columns j > s are zero)::

    revolute j:   Jv_s[:, j] = z_j x (rbar_s - o_j),   Jw_s[:, j] = z_j
    prismatic j:  Jv_s[:, j] = z_j,                    Jw_s[:, j] = 0

    D_tran = sum_s m_s Jv_s^T Jv_s                                   (3.4-25), 2nd term
    D_rot  = sum_s Jw_s^T Ib_s Jw_s                                  (3.4-25), 1st term
    h_tran = sum_s m_s Jv_s^T (dJv_s/dt qd)                          (3.4-26)
    h_rot  = sum_s Jw_s^T (Ib_s (dJw_s/dt qd) + w_s x Ib_s w_s)      (3.4-27)
    c      = -sum_s m_s Jv_s^T g                                     (3.4-28)

A prismatic joint moves every frame beyond it and adds no angular velocity. The
velocity-product accelerations dJv_s/dt qd and dJw_s/dt qd come from the outward recursion of
the link velocities (Eqs. 3.4-1 to 3.4-7 with qdd = 0; a prismatic joint adds the Coriolis
term 2 w x qd z to the origins beyond it), and the sums over links s >= j from suffix sums.
The terms are computed by a compiled kernel (:mod:`gd_analyze.dynamics.kernels`), one
pass per set point, O(n^2) work; the tests keep the Jacobian form as written in array code
(O(n^3) per set point) as its oracle, beside Pinocchio. Everything is batched over set points.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import expect
from ..model.drives import friction_torque
from ..model.kinematics import as_states

if TYPE_CHECKING:
    from ..model.robot import Robot


__all__ = ["assemble_tau", "forward_dynamics", "GDTerms", "gd_terms", "allocate_terms",
           "kernel_arguments", "one_state_terms"]


def assemble_tau(D: np.ndarray, h: np.ndarray, c: np.ndarray, qdd: ArrayLike) -> np.ndarray:
    """Joint torques tau = D qdd + h + c at N set points, Eq. (3.2-26) / Eq. (3.4-24).

    The one assembly of the equations of motion from their terms, whatever the formulation
    that computed them (G-D, L-E, N-E probing, Pinocchio) or the simplified model's D_s, h_s.

    Parameters
    ----------
    D : ndarray, shape (N, n, n)
        Inertia matrix [kg m^2 between revolute joints, kg m between a revolute and a
        prismatic one, kg between prismatic ones].
    h : ndarray, shape (N, n)
        Coriolis and centrifugal torques [N m, or N at a prismatic joint].
    c : ndarray, shape (N, n)
        Gravity loading [N m, or N at a prismatic joint].
    qdd : array_like, shape (N, n)
        Joint accelerations [rad/s^2, or m/s^2 at a prismatic joint].

    Returns
    -------
    ndarray, shape (N, n)
        Joint torques [N m], forces [N] at prismatic joints.

    Raises
    ------
    ValueError
        If qdd cannot be reshaped to (N, n).

    Examples
    --------
    >>> import numpy as np
    >>> assemble_tau(np.eye(2)[None], np.array([[1.0, 0.0]]), np.array([[0.0, 2.0]]),
    ...              [[3.0, 4.0]])
    array([[4., 6.]])
    """
    qdd = np.asarray(qdd, dtype=float).reshape(np.shape(c))
    return np.einsum("kij,kj->ki", D, qdd) + h + c


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
    armature : ndarray, shape (n,) or None
        The drives' reflected rotor inertias Ia [kg m^2]: D_arm = diag(Ia), the third part of
        D (:mod:`gd_analyze.model.drives`); None means zero.
    tau_f : ndarray, shape (N, n) or None
        Joint friction F_v qd + F_c sign(qd) [N m]; None means zero.

    Notes
    -----
    Source: Fu, Gonzalez & Lee (1987), Eqs. (3.4-24) to (3.4-28); Lee, Lee & Nigam (1983).
    The drive terms are outside the chapter's model: tau = (D_tran + D_rot + D_arm) qdd +
    h_tran + h_rot + c + tau_f.
    """

    D_tran: np.ndarray
    D_rot: np.ndarray
    h_tran: np.ndarray
    h_rot: np.ndarray
    c: np.ndarray
    armature: np.ndarray | None = None
    tau_f: np.ndarray | None = None

    @property
    def D_arm(self) -> np.ndarray:
        """ndarray, shape (N, n, n): the armature part of D, diag(Ia) at every set point
        [kg m^2] (a read-only broadcast view; zeros without drives)."""
        n = self.c.shape[-1]
        arm = np.zeros(n) if self.armature is None else np.asarray(self.armature, float)
        return np.broadcast_to(np.diag(arm), (self.c.shape[0], n, n))

    @property
    def D(self) -> np.ndarray:
        """ndarray, shape (N, n, n): the inertia matrix D = D_tran + D_rot + D_arm [kg m^2]."""
        D = self.D_tran + self.D_rot
        if self.armature is not None and np.any(self.armature):
            idx = np.arange(D.shape[-1])
            D[:, idx, idx] += self.armature
        return D

    def rows(self, index: slice | np.ndarray) -> GDTerms:
        """The terms at some of the set points.

        Parameters
        ----------
        index : slice or array_like of int
            Set points to take (a slice gives views).

        Returns
        -------
        GDTerms
        """
        return GDTerms(self.D_tran[index], self.D_rot[index], self.h_tran[index],
                       self.h_rot[index], self.c[index], self.armature,
                       None if self.tau_f is None else self.tau_f[index])

    @staticmethod
    def concatenate(parts: Sequence[GDTerms]) -> GDTerms:
        """The terms of consecutive chunks as one.

        Parameters
        ----------
        parts : list of GDTerms
            Chunks of the same robot, in order (at least one).

        Returns
        -------
        GDTerms
        """
        D_tran, D_rot, h_tran, h_rot, c = (np.concatenate([getattr(t, f) for t in parts])
                                           for f in ("D_tran", "D_rot", "h_tran", "h_rot", "c"))
        tau_f = None if parts[0].tau_f is None else np.concatenate([t.tau_f for t in parts])
        return GDTerms(D_tran, D_rot, h_tran, h_rot, c, parts[0].armature, tau_f)

    @property
    def h(self) -> np.ndarray:
        """ndarray, shape (N, n): Coriolis and centrifugal torques h = h_tran + h_rot [N m]."""
        return self.h_tran + self.h_rot

    def tau(self, qdd: ArrayLike, D: np.ndarray | None = None,
            h: np.ndarray | None = None) -> np.ndarray:
        """Joint torques tau = D qdd + h + c, Eq. (3.4-24).

        Parameters
        ----------
        qdd : array_like, shape (N, n)
            Joint accelerations [rad/s^2].
        D, h : ndarray, optional
            :attr:`D` and :attr:`h`, if the caller holds them already (not formed again).

        Returns
        -------
        ndarray, shape (N, n)
            Joint torques [N m], with the drives' armature and friction where the robot has
            them.
        """
        tau = assemble_tau(self.D if D is None else D, self.h if h is None else h, self.c,
                           qdd)
        if self.tau_f is not None:
            tau += self.tau_f
        return tau


def allocate_terms(N: int, n: int) -> GDTerms:
    """Output buffers for :func:`gd_terms`, to be reused across streamed chunks.

    Parameters
    ----------
    N : int
        Set points the buffers hold (the largest chunk).
    n : int
        Number of joints.

    Returns
    -------
    GDTerms
        Uninitialised arrays: D_tran, D_rot (N, n, n), h_tran, h_rot, c (N, n).
    """
    return GDTerms(*(np.empty(shape) for shape in [(N, n, n)] * 2 + [(N, n)] * 3))


def kernel_arguments(robot: Robot) -> tuple[Any, ...]:
    """The robot's constants as the compiled kernels take them (contiguous float arrays).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.

    Returns
    -------
    tuple
        Placement rotations (n, 3, 3), translations (n, 3) [m], prismatic flags (n,) int64,
        masses (n,) [kg], body-frame centres of mass (n, 3) [m] and inertia tensors (n, 3, 3)
        [kg m^2], gravity (3,) [m/s^2].
    """
    c = np.ascontiguousarray
    return (c(robot.rotation, dtype=float), c(robot.translation, dtype=float),
            c(robot.prismatic, dtype=np.int64), c(robot.mass, dtype=float),
            c(robot.body_com, dtype=float), c(robot.body_inertia, dtype=float),
            c(robot.gravity, dtype=float))


def _check_out(out, N, n):
    # gd_terms(robot, q, qd, qdd), as regressor(robot, q, qd, qdd) is called, passes qdd here
    expect(out, GDTerms, "out", "a GDTerms from allocate_terms (the terms take no qdd)")
    shapes = ((N, n, n), (N, n, n), (N, n), (N, n), (N, n))
    arrays = (out.D_tran, out.D_rot, out.h_tran, out.h_rot, out.c)
    for name, arr, shape in zip(("D_tran", "D_rot", "h_tran", "h_rot", "c"), arrays, shapes):
        if (not isinstance(arr, np.ndarray) or arr.dtype != np.float64 or arr.ndim != len(shape)
                or arr.shape[0] < N or arr.shape[1:] != shape[1:] or not arr.flags.c_contiguous
                or not arr.flags.writeable):
            raise ValueError(f"out.{name} must be a writeable C-contiguous float64 array of "
                             f"shape (>= {N},) + {shape[1:]}")
    return tuple(arr[:N] for arr in arrays)


def gd_terms(robot, q, qd, out=None, constants=None):
    """The G-D terms D_tran, D_rot, h_tran, h_rot and c at N set points, and the drives'.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad or m].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s or m/s].
    out : GDTerms, optional
        Buffers the caller owns (:func:`allocate_terms`), with at least N rows: the terms are
        written into their first N rows, and the result's arrays are views of them. Reuse them
        across the chunks of a stream to avoid fresh allocations.
    constants : tuple, optional
        :func:`kernel_arguments` of ``robot``, computed once by a caller that evaluates the
        same robot many times (a simulation, one call per step).

    Returns
    -------
    GDTerms
        D_tran and D_rot with shape (N, n, n) [kg m^2]; h_tran, h_rot and c with shape (N, n)
        [N m for a revolute joint, N for a prismatic one]; the robot's armature (n,) and the
        friction torque tau_f (N, n), None where the robot has none.

    Raises
    ------
    InputError
        If q or qd does not have shape (N, n), they disagree on N, or one holds NaN or inf
        (named with its first such set point and joint:
        :func:`~gd_analyze.model.kinematics.as_states`), or ``out`` is not a GDTerms (a qdd
        given as a fourth argument); a ValueError if ``out`` does not fit.

    Notes
    -----
    Source: Eqs. (3.4-24) to (3.4-28) of Fu, Gonzalez & Lee (1987), in the Jacobian form given
    in the module docstring, by the compiled kernel
    :func:`gd_analyze.dynamics.kernels.gd_kernel`. D_tran and D_rot are symmetric; their
    sum is the inertia matrix D of Eq. (3.2-31).

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
    res = _check_out(allocate_terms(N, n) if out is None else out, N, n)
    from .kernels import gd_kernel  # numba: imported by the first computation only

    c = np.ascontiguousarray
    gd_kernel(c(q), c(qd), *(kernel_arguments(robot) if constants is None else constants), *res)
    arm = robot.armature if robot.has_armature else None
    return GDTerms(*res, arm, friction_torque(robot, qd))


def one_state_terms(robot: Robot) -> Callable[[np.ndarray, np.ndarray], GDTerms]:
    """:func:`gd_terms` at one state at a time, for a simulation's right-hand side.

    The robot's constants, the buffers and their checks are made once; each call then runs the
    compiled kernel alone, as :func:`gd_terms` runs it (the same values, bit for bit), without
    :func:`gd_terms`' conversions and checks of q, qd and the buffers (about 40 us a call).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.

    Returns
    -------
    callable
        ``terms(q, qd)`` with q, qd C-contiguous float64 arrays of shape (1, n) [rad or m,
        rad/s or m/s] (a state vector's slices ``y[None, :n]``, ``y[None, n:]``): the
        :class:`GDTerms` at that state, whose arrays are views of buffers the next call
        overwrites.

    Examples
    --------
    >>> import numpy as np
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("two-link")
    >>> terms = one_state_terms(robot)
    >>> y = np.array([0.1, -0.2, 0.3, 0.4])
    >>> bool(np.array_equal(terms(y[None, :2], y[None, 2:]).D,
    ...                     gd_terms(robot, y[None, :2], y[None, 2:]).D))
    True
    """
    from .kernels import gd_kernel  # numba: imported by the first computation only

    n = robot.n
    D_tran, D_rot, h_tran, h_rot, c = _check_out(allocate_terms(1, n), 1, n)
    constants = kernel_arguments(robot)
    arm = robot.armature if robot.has_armature else None

    def terms(q, qd):           # untyped: numba's dispatcher takes any arguments
        gd_kernel(q, qd, *constants, D_tran, D_rot, h_tran, h_rot, c)
        return GDTerms(D_tran, D_rot, h_tran, h_rot, c, arm, friction_torque(robot, qd))

    return terms


def qdd_from_terms(terms: GDTerms, tau: np.ndarray) -> np.ndarray:
    """Joint accelerations from G-D terms already computed, qdd = D^-1 (tau - h - c - tau_f).

    Parameters
    ----------
    terms : GDTerms
        At N set points: D of shape (N, n, n) [kg m^2; kg], h, c (and tau_f) of shape (N, n)
        [N m or N].
    tau : ndarray, shape (N, n)
        Joint torques [N m; N for a prismatic joint].

    Returns
    -------
    ndarray, shape (N, n)
        qdd [rad/s^2; m/s^2].

    Raises
    ------
    numpy.linalg.LinAlgError
        If D is singular at a set point.

    Notes
    -----
    The equations of motion tau = D(q) qdd + h(q, qd) + c(q), Eq. (3.4-25), solved for qdd.
    """
    rhs = np.asarray(tau, dtype=float) - terms.h - terms.c
    if terms.tau_f is not None:
        rhs = rhs - terms.tau_f
    return np.linalg.solve(terms.D, rhs[..., None])[..., 0]


def forward_dynamics(robot: Robot, q: ArrayLike, qd: ArrayLike, tau: ArrayLike) -> np.ndarray:
    """Joint accelerations of the arm under given torques, qdd = D^-1 (tau - h - c - tau_f).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad or m].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s or m/s].
    tau : array_like, shape (N, n) or (n,)
        Joint torques [N m] or forces [N] (prismatic).

    Returns
    -------
    ndarray, shape (N, n)
        Joint accelerations qdd [rad/s^2 or m/s^2].

    Raises
    ------
    ValueError
        If the arrays do not have n columns or disagree on N.
    numpy.linalg.LinAlgError
        If D is singular at some set point (it is positive definite for a physical arm).

    Notes
    -----
    Eq. (3.4-24) of Fu, Gonzalez & Lee (1987) solved for qdd, with D = D_tran + D_rot and
    h = h_tran + h_rot from Eqs. (3.4-25) to (3.4-28); one ``numpy.linalg.solve`` per set
    point, batched.
    """
    q, qd, tau = as_states(robot, q, qd, tau, names=("q", "qd", "tau"))
    return qdd_from_terms(gd_terms(robot, q, qd), tau)
