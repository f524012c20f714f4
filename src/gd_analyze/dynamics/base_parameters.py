"""Standard and base inertial parameters, and the joint-torque regressor.

The dynamics of a serial arm are linear in the standard inertial parameters of its links
(Khalil & Kleinfinger, "Minimum operations and minimum parameters of the dynamic models of
tree structure robots", IEEE J. Robotics and Automation 3(6), 1987). Per link i, in body frame
i (the joint model of :mod:`gd_analyze.model.robot`) and about its origin::

    phi_i = (XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M)

with J_i = [[XX, XY, XZ], [XY, YY, YZ], [XZ, YZ, ZZ]] = I_c + m (r^T r 1 - r r^T) the inertia
tensor about the origin, MS_i = (MX, MY, MZ) = m r the first moment and M = m the mass, so that
tau = W(q, qd, qdd) phi with the regressor W of :func:`regressor`. Some columns of W are zero
or combinations of others: the base parameters (Gautier, "Numerical calculation of the base
inertial parameters of robots", ICRA 1990) are the independent columns' parameters plus the
dependent ones regrouped into them, beta = phi_B + K phi_D with W_D = W_B K, and
tau = W_B beta (:func:`base_parameters`).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..model.kinematics import as_states, joint_frames

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["PARAMETER_NAMES", "standard_parameters", "regressor", "BaseParameters",
           "base_parameters", "random_states", "base_regressor", "shortest_decimal",
           "K_DECIMAL_EPS", "PHI_DECIMAL_EPS", "one_blas_thread"]

#: The BLAS controller of :func:`one_blas_thread` and how many modules were loaded when it was
#: made: ``[(count, controller)]``, or empty before the first call.
_BLAS: list[tuple[int, Any]] = []


def one_blas_thread() -> Any:
    """A context manager that runs its block on one BLAS thread: ``threadpoolctl``'s
    ``threadpool_limits(1, "blas")``, with its controller made once a process.

    Making a ``threadpoolctl.ThreadpoolController`` lists the loaded shared libraries (it reads
    ``/proc/self/maps`` on Linux, 2 to 10 ms in a process that has loaded numba's and
    Pinocchio's): ``threadpool_limits`` makes one on every entry, and the identification
    enters its limit some hundreds of times a fit. The controller kept here is made again only
    when modules have been imported since (an import may load another BLAS library), so that
    the limit reaches the same libraries as ``threadpool_limits(1, "blas")`` would.

    Returns
    -------
    contextlib.AbstractContextManager
        ``ThreadpoolController.limit(limits=1, user_api="blas")``: on leaving the block, each
        library's threads are as they were.
    """
    from threadpoolctl import ThreadpoolController

    loaded = len(sys.modules)
    if not _BLAS or _BLAS[0][0] != loaded:
        _BLAS[:] = [(loaded, ThreadpoolController())]
    return _BLAS[0][1].limit(limits=1, user_api="blas")


#: The ten standard inertial parameters of a link, in the order of phi_i.
PARAMETER_NAMES = ("XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M")

#: Greedy selection order within a link: these first, then YY, MZ, M (the parameters Khalil's
#: regrouping eliminates for a revolute joint).
_FIRST = (0, 1, 2, 4, 5, 6, 7)
_LAST = (3, 8, 9)
#: Symmetric inertia index pairs of XX, XY, XZ, YY, YZ, ZZ.
_J_INDEX = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def standard_parameters(robot: Robot) -> np.ndarray:
    """The standard inertial parameters of every link, body frame, about its origin.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.

    Returns
    -------
    ndarray, shape (n, 10)
        Row i: (XX, XY, XZ, YY, YZ, ZZ [kg m^2], MX, MY, MZ [kg m], M [kg]) of link i.

    Notes
    -----
    J = I_c + m (r^T r 1 - r r^T) (parallel-axis theorem), MS = m r, with the centre of mass r
    and the inertia tensor I_c of :attr:`~gd_analyze.model.robot.Robot.body_com` and
    :attr:`~gd_analyze.model.robot.Robot.body_inertia`
    (Khalil & Kleinfinger 1987).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> standard_parameters(load_robot("two-link")).shape
    (2, 10)
    """
    m = np.asarray(robot.mass, float)
    r = np.asarray(robot.body_com, float)
    Ic = np.asarray(robot.body_inertia, float)
    J = Ic + m[:, None, None] * (np.einsum("ia,ia->i", r, r)[:, None, None] * np.eye(3)
                                 - r[:, :, None] * r[:, None, :])
    out = np.empty((robot.n, 10))
    for k, (a, b) in enumerate(_J_INDEX):
        out[:, k] = J[:, a, b]
    out[:, 6:9] = m[:, None] * r
    out[:, 9] = m
    return out


def _skew(v):
    """skew(v) with v of shape (..., 3): skew(v) x = v x x."""
    z = np.zeros(v.shape[:-1])
    return np.stack([np.stack([z, -v[..., 2], v[..., 1]], -1),
                     np.stack([v[..., 2], z, -v[..., 0]], -1),
                     np.stack([-v[..., 1], v[..., 0], z], -1)], -2)


def _forward(robot, q, qd, qdd, gravity):
    """Body-frame w, wd, vd (N, n, 3) and the transforms R (N, n, 3, 3), p (N, n, 3)."""
    N, n = q.shape
    R, p = joint_frames(robot, q)
    w = np.zeros((N, n, 3))
    wd = np.zeros((N, n, 3))
    vd = np.zeros((N, n, 3))
    w0, wd0 = np.zeros((N, 3)), np.zeros((N, 3))
    vd0 = np.broadcast_to(-np.asarray(gravity, float), (N, 3))
    for j in range(n):
        Rt = np.swapaxes(R[:, j], -1, -2)
        pj = p[:, j]
        a = vd0 + np.cross(wd0, pj) + np.cross(w0, np.cross(w0, pj))
        vd[:, j] = np.einsum("kab,kb->ka", Rt, a)
        wp = np.einsum("kab,kb->ka", Rt, w0)
        w[:, j] = wp
        wd[:, j] = np.einsum("kab,kb->ka", Rt, wd0)
        if robot.prismatic[j]:
            vd[:, j, 2] += qdd[:, j]
            vd[:, j] += 2.0 * np.cross(wp, qd[:, j, None] * np.array([0.0, 0.0, 1.0]))
        else:
            w[:, j, 2] += qd[:, j]
            wd[:, j] += np.cross(wp, qd[:, j, None] * np.array([0.0, 0.0, 1.0]))
            wd[:, j, 2] += qdd[:, j]
        w0, wd0, vd0 = w[:, j], wd[:, j], vd[:, j]
    return R, p, w, wd, vd


def _link_wrenches(w, wd, vd):
    """A (N, 6, 10): the wrench (F, N) of a link per unit standard parameter, Eq. (3.3-26)."""
    N = w.shape[0]
    A = np.zeros((N, 6, 10))
    U = _skew(wd) + _skew(w) @ _skew(w)
    for k, (a, b) in enumerate(_J_INDEX):
        E = np.zeros((3, 3))
        E[a, b] = E[b, a] = 1.0
        A[:, 3:, k] = wd @ E.T + np.cross(w, w @ E.T)
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1.0
        A[:, :3, 6 + k] = U[:, :, k]
        A[:, 3:, 6 + k] = np.cross(e, vd)
    A[:, :3, 9] = vd
    return A


def regressor(robot: Robot, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike,
              gravity: ArrayLike | None = None) -> np.ndarray:
    """The joint-torque regressor W with tau = W phi, phi the standard parameters.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (its inertial parameters are not read).
    q, qd, qdd : array_like, shape (N, n)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    gravity : array_like, shape (3,), optional
        Gravity in the base frame [m/s^2]; default the robot's.

    Returns
    -------
    ndarray, shape (N, n, 10 n)
        ``W[k, i, 10 j + c]``: torque of joint i [N m or N] per unit standard parameter c
        (:data:`PARAMETER_NAMES`) of link j at set point k.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n), or one holds NaN or inf (named with its first
        such set point and joint: :func:`~gd_analyze.model.kinematics.as_states`).

    Notes
    -----
    The recursive Newton-Euler algorithm (Fu, Gonzalez & Lee 1987, Table 3.3; Khalil &
    Kleinfinger 1987) in body frames, linear in the parameters: the base acceleration is -g
    (Eq. (3.3-46)); link j's wrench F_j = M vd_j + U_j MS_j, N_j = J_j wd_j + w_j x (J_j w_j)
    + MS_j x vd_j with U = skew(wd) + skew(w)^2 is carried to every joint i <= j by
    f_{i-1} = R_i f_i, n_{i-1} = R_i n_i + p_i x (R_i f_i).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("two-link")
    >>> W = regressor(robot, np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2)))
    >>> W.shape
    (1, 2, 20)
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    g = robot.gravity if gravity is None else gravity
    R, p, w, wd, vd = _forward(robot, q, qd, qdd, g)
    N, n = q.shape
    W = np.zeros((N, n, 10 * n))
    for j in range(n):
        A = _link_wrenches(w[:, j], wd[:, j], vd[:, j])
        f, m = A[:, :3], A[:, 3:]
        for i in range(j, -1, -1):
            W[:, i, 10 * j:10 * j + 10] = f[:, 2] if robot.prismatic[i] else m[:, 2]
            if i == 0:
                break
            f = R[:, i] @ f
            m = R[:, i] @ m + np.cross(p[:, i][:, :, None], f, axis=1)
    return W


def random_states(robot: Robot, count: int,
                  seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random set points for identification: q within the limits (else +-pi), qd, qdd in +-2.

    Parameters
    ----------
    robot : Robot
    count : int
        Number of set points N.
    seed : int, optional
        Seed of :func:`numpy.random.default_rng`.

    Returns
    -------
    q, qd, qdd : ndarray, shape (N, n)
        [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    """
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, np.pi)
    n = robot.n
    return (rng.uniform(lo, hi, (count, n)), rng.uniform(-2, 2, (count, n)),
            rng.uniform(-2, 2, (count, n)))


@dataclass(frozen=True, eq=False)
class BaseParameters:
    """The base inertial parameters of an arm (Gautier 1990).

    Attributes
    ----------
    standard : ndarray, shape (n, 10)
        phi: the standard parameters per link (:func:`standard_parameters`).
    independent : ndarray of bool, shape (n, 10)
        The columns of the regressor kept as independent (B); the others (D) are zero or
        combinations of earlier kept ones.
    K : ndarray, shape (b, 10 n - b)
        The regrouping: W_D = W_B K, with B and D in the flat order of ``independent``
        (link-major, :data:`PARAMETER_NAMES` within a link). Entries below ~1e-12 of the
        largest are exactly 0.
    beta : ndarray, shape (b,)
        Base parameter values beta = phi_B + K phi_D (exactly 0 where the sum cancels to
        rounding) [kg m^2, kg m, kg].
    rank : int
        b, the number of base parameters.
    """

    standard: np.ndarray
    independent: np.ndarray
    K: np.ndarray
    beta: np.ndarray
    rank: int

    @property
    def values(self) -> np.ndarray:
        """ndarray, shape (n, 10): beta in the independent slots, 0 in the dependent ones.

        The recursive model evaluated with these values computes tau = W_B beta, the same
        torques as with the standard parameters.
        """
        out = np.zeros(self.standard.shape)
        out[self.independent] = self.beta
        return out

    def names(self) -> list[str]:
        """Labels of the base parameters, e.g. ``["ZZ1", "XX2", ...]`` (links from 1).

        Returns
        -------
        list of str, length b
        """
        n = self.standard.shape[0]
        return [f"{PARAMETER_NAMES[c]}{j + 1}" for j in range(n) for c in range(10)
                if self.independent[j, c]]


#: Relative size below which a regrouping coefficient or a regrouped value is exactly 0.
SNAP = 1e-12


def _kind_scales(phi):
    """(10,): per parameter the largest |value| of its kind (J, MS or M) over the links."""
    J, MS, M = (float(np.abs(phi[:, sl]).max(initial=0.0)) for sl in
                (slice(0, 6), slice(6, 9), slice(9, 10)))
    out = np.array([J] * 6 + [MS] * 3 + [M])
    return np.where(out > 0, out, 1e-300)


#: A regrouping coefficient K_ij is its shortest decimal within this many eps of
#: max(|K_ij|, 1) (:func:`shortest_decimal`): the least-squares K carries up to about 25 eps of
#: noise from the random set points and the LAPACK build (PUMA 560, Panda, UR5, Stanford arm,
#: eight seeds each), and its true entries are products of the robot file's decimals.
K_DECIMAL_EPS = 64
#: A standard parameter is its shortest decimal within this many eps of its size: a product
#: such as m r_x of the robot file's decimals (1.1832000000000003 for 17.4 x 0.068).
PHI_DECIMAL_EPS = 4


def shortest_decimal(values: ArrayLike, tol: ArrayLike) -> np.ndarray:
    """Each value as the decimal of the fewest significant digits within ``tol`` of it.

    Parameters
    ----------
    values : array_like
        The values.
    tol : array_like
        Broadcast against ``values``: how far [the values' unit] each may move.

    Returns
    -------
    ndarray, the shape of ``values``
        The nearest double of that decimal (the value itself when no shorter decimal lies
        within ``tol``; 0 stays 0).

    Notes
    -----
    Rounding noise of a few eps differs between random set points, BLAS and LAPACK builds
    and platforms; where the exact value is a short decimal, as it is for products of the
    robot file's numbers, every noisy copy within ``tol`` of it is read as that decimal, so
    the base parameters, and the operation counts of the models built on them (which share a
    product only where two coefficients are equal), are the same on every machine.

    Examples
    --------
    >>> shortest_decimal([0.00288 + 4e-18, 0.1 + 0.2, 1 / 3], 1e-16).tolist()
    [0.00288, 0.3, 0.3333333333333333]
    """
    values = np.asarray(values, float)
    tol = np.broadcast_to(np.asarray(tol, float), values.shape)
    out = values.copy()
    for idx in zip(*np.nonzero(np.isfinite(values) & (values != 0.0))):
        x, t = float(values[idx]), float(tol[idx])
        for digits in range(1, 17):
            r = float(f"{x:.{digits}g}")
            if abs(r - x) <= t:
                out[idx] = r
                break
    return out


def _decimal_columns(K, WB, WD):
    """K with each column its entries' shortest decimals (within K_DECIMAL_EPS eps of
    max(|K_ij|, 1)) where those fit the stacked regressor as well as the least-squares
    column, ||W_D,j - W_B K_j|| larger by at most eps of the largest column norm of W_B (both
    at rounding level): the decimals are then the exact regrouping; a general chain's
    irrational coefficients, whose decimals fit worse, keep their least-squares values."""
    eps = np.finfo(float).eps
    dec = shortest_decimal(K, K_DECIMAL_EPS * eps * np.maximum(np.abs(K), 1.0))
    with one_blas_thread():
        fit = np.linalg.norm(WD - WB @ K, axis=0)
        fit_dec = np.linalg.norm(WD - WB @ dec, axis=0)
    slack = eps * np.linalg.norm(WB, axis=0).max(initial=0.0)
    return np.where((fit_dec <= fit + slack)[None, :], dec, K)


def _snap_standard(phi):
    """Standard parameters with rounding noise (below SNAP of their kind's scale) set to 0,
    the others their shortest decimal within PHI_DECIMAL_EPS eps of their size."""
    phi = np.where(np.abs(phi) <= SNAP * _kind_scales(phi)[None, :], 0.0, phi)
    return shortest_decimal(phi, PHI_DECIMAL_EPS * np.finfo(float).eps * np.abs(phi))


def base_parameters(robot: Robot, count: int | None = None, seed: int = 0,
                    tol: float = 1e-8) -> BaseParameters:
    """The base parameters of an arm by the QR decomposition of Gautier (1990).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    count : int, optional
        Number of random set points of the stacked regressor; default max(20, 4 n).
    seed : int, optional
        Seed of the random set points (:func:`random_states`).
    tol : float, optional
        Column j is independent when |R_jj| > tol max|R| in the QR of the stacked regressor.

    Returns
    -------
    BaseParameters

    Notes
    -----
    Columns are ordered link by link from the base, within a link (XX, XY, XZ, YZ, ZZ, MX,
    MY) before (YY, MZ, M), so that the greedy selection keeps the parameters of Khalil &
    Kleinfinger's regrouping (1987): YY_j, MZ_j and M_j of a revolute joint j are regrouped
    into XX_j, ZZ_j and the parameters of link j-1. W is stacked at random set points, its
    QR taken without pivoting, a column kept when its diagonal entry is not negligible, and
    K solves R_BB K = R_BD (Gautier 1990). Each standard parameter, and each column of K
    whose decimals fit W as well, is then its shortest decimal within a few eps
    (:func:`shortest_decimal`), and each beta an exactly rounded sum, so that beta has the
    same bits for any seed, BLAS or platform where the robot file's numbers are decimals.
    Both factorisations run on one BLAS thread (a stacked regressor of 4 n^2 rows and 10 n
    columns: threaded LAPACK is several times slower on a busy machine, and its result can
    depend on the thread count in the last bits).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> base_parameters(load_robot("puma560")).rank
    36
    """
    n = robot.n
    count = max(20, 4 * n) if count is None else count
    q, qd, qdd = random_states(robot, count, seed)
    W = regressor(robot, q, qd, qdd).reshape(count * n, 10 * n)
    # the mass columns carry g (~10): scale the columns to unit norm first
    order = np.array([10 * j + c for j in range(n) for c in _FIRST + _LAST])
    Wo = W[:, order]
    norms = np.linalg.norm(Wo, axis=0)
    zero = norms <= tol * norms.max(initial=0.0)          # rounding noise: a zero column
    with one_blas_thread():     # a small factor: threads only cost
        Rm = np.linalg.qr(np.where(zero, 0.0, Wo / np.where(zero, 1.0, norms)), mode="r")
    diag = np.abs(np.diag(Rm))
    keep_o = diag > tol * max(diag.max(), 1e-300)
    independent = np.zeros(10 * n, bool)
    independent[order[keep_o]] = True
    B = np.flatnonzero(independent)
    D = np.flatnonzero(~independent)
    WB, WD = W[:, B], W[:, D]
    with one_blas_thread():
        K = np.linalg.lstsq(WB, WD, rcond=None)[0] if D.size else np.zeros((B.size, 0))
    phi = _snap_standard(standard_parameters(robot))
    scale = np.tile(_kind_scales(phi), n)
    K = np.where(np.abs(K) * scale[D][None, :] <= SNAP * scale[B][:, None], 0.0, K)
    K = _decimal_columns(K, WB, WD)
    flat = phi.reshape(-1)
    terms = np.abs(flat[B]) + np.abs(K * flat[D][None, :]).sum(axis=1)
    # each sum exact, then rounded once: the same bits whatever the BLAS's order of addition
    beta = np.array([math.fsum([flat[b], *(K[i] * flat[D])]) for i, b in enumerate(B)])
    beta = np.where(np.abs(beta) <= SNAP * np.maximum(terms, scale[B]), 0.0, beta)
    return BaseParameters(standard=phi, independent=independent.reshape(n, 10), K=K,
                          beta=beta, rank=int(B.size))


#: Set points per block of :func:`base_regressor` (bounds the full regressor's memory).
REGRESSOR_BLOCK = 4096


def base_regressor(robot: Robot, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike,
                   base: BaseParameters | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The base regressor Y_b and the base parameters beta, with tau = Y_b beta.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd, qdd : array_like, shape (N, n) or (n,)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2 for
        a prismatic joint].
    base : BaseParameters, optional
        The arm's base parameters (:func:`base_parameters`), if already computed.

    Returns
    -------
    Y : ndarray, shape (N, n, b)
        ``Y[k, i, m]``: torque of joint i [N m or N] per unit base parameter m at set point k
        (the independent columns of :func:`regressor`, with the robot's gravity); a single
        state (n,) gives N = 1.
    beta : ndarray, shape (b,)
        The base parameter values [kg m^2, kg m, kg], named by
        ``base_parameters(robot).names()``.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n) or (n,), or one holds NaN or inf: one line
        naming the array and its first such set point and joint
        (:func:`~gd_analyze.model.kinematics.as_states`).

    Notes
    -----
    ``Y @ beta`` is the torque of the rigid links, Pinocchio's ``rnea``: a robot's drives
    (armature, friction; :mod:`gd_analyze.model.drives`) are not in it. Source: Khalil &
    Kleinfinger (1987) for the regressor, Gautier (1990) for the base parameters
    (:func:`base_parameters`). Computed in blocks of :data:`REGRESSOR_BLOCK` set points.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("puma560")
    >>> Y, beta = base_regressor(robot, np.zeros((3, 6)), np.zeros((3, 6)), np.zeros((3, 6)))
    >>> Y.shape, beta.shape
    ((3, 6, 36), (36,))
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)        # the robot's type checked first
    base = base_parameters(robot) if base is None else base
    columns = np.flatnonzero(base.independent.reshape(-1))
    N = q.shape[0]
    Y = np.empty((N, robot.n, columns.size))
    for a in range(0, N, REGRESSOR_BLOCK):
        b = slice(a, a + REGRESSOR_BLOCK)
        Y[b] = regressor(robot, q[b], qd[b], qdd[b])[:, :, columns]
    return Y, base.beta
