"""Closed-loop use of the simplified model: computed-torque control of the full-model arm.

Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) builds the simplified G-D model "for control purpose".
This module puts it in the loop. The plant is the arm with its full G-D dynamics, Eq. (3.4-24),
integrated forward in time with::

    qdd = D(q)^-1 (tau - h(q, qd) - c(q))                                  (forward_dynamics)

and three controllers track a desired motion q_d(t), one at a time (:func:`track`; side by
side and collected: :func:`run_control`):

- ``"full"``: computed torque (Fu, Gonzalez & Lee 1987, Ch. 5, computed-torque technique) with
  the full G-D model, tau = D(q) v + h(q, qd) + c(q);
- ``"simplified"``: computed torque with the simplified model of ``simplified_model.json``,
  tau = D_s(q) v + h_s(q, qd) + c_s(q) (c_s = c where the model keeps gravity whole), evaluated
  in its explicit form
  (:meth:`gd_analyze.simplify.simplified.SimplifiedModel.torque`: only the kept terms are computed);
- ``"pd_gravity"``: PD control with gravity compensation, tau = Kp_pd e + Kv_pd ed + c(q)
  (on a controlled arm without gravity, c = 0: plain PD, and named so, :func:`control_law`);

where e = q_d - q, ed = qd_d - qd and v = qdd_d + Kv ed + Kp e. With the full model the
closed loop is exactly e'' + Kv e' + Kp e = 0, so the error starting on the trajectory stays at
the integrator's tolerance; a model error tau_m - tau_exact enters as a forcing
D^-1 (tau_m - tau_exact) of that linear error equation.

Gains (settable; :func:`control_gains`)
---------------------------------------
Computed torque: Kp = wn^2 [s^-2] and Kv = 2 zeta wn [s^-1] per joint, default wn = 20 rad/s and
zeta = 1 (critically damped, no overshoot). 20 rad/s (3.2 Hz, time constant 1/wn = 0.05 s)
is fast against the shipped 4.2 s motion (its rest-to-rest quintic has no content above
~1 Hz) and modest for an industrial arm's position loop; the simulation has no structural
flexibility, actuator limit, sampling or friction that would bound it, so it is a stated
choice, not a tuned one. PD + gravity acts on torque, not acceleration, so its gains are
scaled by the diagonal of the inertia matrix at the start of the motion:
Kp_pd = diag(D(q_d(0))) wn^2 [N m/rad; N/m on a prismatic joint], Kv_pd = diag(D(q_d(0)))
2 zeta wn [N m s/rad; N s/m]; each
joint then has the same wn and zeta as long as the inertia stays near its starting value and the
coupling is ignored.

Desired motion (:func:`desired_motion`)
---------------------------------------
Between set points, q_d is the piecewise quintic Hermite polynomial through (q, qd, qdd) at both
ends of each interval (``scipy.interpolate.BPoly.from_derivatives``, converted to a ``PPoly``):
q_d, qd_d = dq_d/dt and qdd_d = d^2q_d/dt^2 are consistent, match the file's q, qd and qdd at
every set point, and are continuous up to qdd_d (C2). A quintic trajectory such as the shipped
one is reproduced exactly. (A cubic spline through q alone would not honour the file's qd and
qdd; separate Hermite splines on q and on qd would make qd_d differ from dq_d/dt.)

Integration
-----------
``scipy.integrate.solve_ivp`` (default DOP853, rtol = 1e-8, atol = 1e-10) of the state
(q, qd), starting at q(0) = q_d(0) + offset, qd(0) = qd_d(0). The solution is sampled at the set
points and on a fine grid (:data:`DEFAULT_GRID_POINTS` evenly spaced times, set points added);
the applied torques are recomputed at those samples from the sampled states with the same
control law.

Integrator noise of the torque difference (:func:`difference_noise`)
--------------------------------------------------------------------
The closed-loop torque difference tau_s - tau_f is the difference of two runs, each with the
integrator's error in its state; the gains turn a state error into a torque error
(D Kp dq + D Kv dqd, Kp = 400 s^-2), so its noise is far above rtol times the torque. It is
measured, not estimated: both computed-torque runs are integrated again with rtol and atol
divided by :data:`NOISE_TIGHTEN`, and the peak over the run of
|(tau_s - tau_f)(rtol) - (tau_s - tau_f)(rtol / 100)| is the noise of the difference drawn.
Both runs are repeated because their noises neither cancel nor add in a fixed way (the shipped
PUMA 560: the difference's noise is half of each run's; the UR5's joint 5: twice the
full-model run's). The floor below which the difference is noise, not data, is
:data:`NOISE_FACTOR` times that peak (a margin for the tight run's own error: the same
measurement against rtol / 10^4 agrees with it to within 5 % on the shipped PUMA 560,
Stanford and UR5 runs and on a 5,000-set-point PUMA 560 run), and at least
max(rtol, 1e-12) times the full-model controller's peak |tau| (:attr:`ControlResult.tau_noise_floor`).
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..certify.region import VALUE_EPS
from ..dynamics.dalembert import gd_terms, one_state_terms, qdd_from_terms
from ..dynamics.opcount import operation_counts
from ..model.drives import COULOMB_BAND, friction_torque
from ..ranking.labels import element_units
from ..ranking.ranking import ROUND_OFF
from ..simplify.explicit_model import full_program
from ..simplify.simplified import choice_masks, json_safe
from ..store import explicit_cache
from ..store.control_dataset import pd_name, peak_rms
from ..symbolic.drive_regressor import with_drives
from ..symbolic.explicit_estimate import is_expensive
from ..symbolic.recursive import recursive_program
from ..trajectory.planning import joint_title
from ..trajectory.trajectory import Trajectory
from .evaluate import coverage, coverages, model_torque

if TYPE_CHECKING:                       # for the type hints only
    import os

    from numpy.typing import NDArray
    from scipy.interpolate import PPoly

    from ..dynamics.dalembert import GDTerms
    from ..model.robot import Robot
    from ..simplify.simplified import SimplifiedModel

__all__ = ["CONTROLLERS", "CONTROLLER_DESCRIPTIONS", "PD_WITHOUT_GRAVITY", "control_law",
           "DEFAULT_WN", "DEFAULT_ZETA", "GAIN_RANGES",
           "DEFAULT_RTOL", "DEFAULT_ATOL", "DEFAULT_METHOD", "MAX_STIFFNESS_STEPS",
           "MAX_RHS_EVALS", "DENSE_SETPOINTS", "RHS_PER_STEP", "closed_loop_rates",
           "singular_inertia", "Gains", "control_gains", "desired_motion", "motion_round_off",
           "HERMITE_QUINTIC", "ROUNDINGS",
           "controller_torque", "TrackingRun", "track", "DEFAULT_GRID_POINTS", "CONTROL_FILE",
           "NOISE_TIGHTEN", "NOISE_FACTOR", "ControlResult", "run_control", "difference_noise",
           "model_cost", "model_facts"]


#: The controllers compared, in table order.
CONTROLLERS = ("full", "simplified", "pd_gravity")


#: One line per controller, for tables and the dataset.
CONTROLLER_DESCRIPTIONS = {
    "full": "computed torque, full G-D model: D v + h + c",
    "simplified": "computed torque, simplified model: D_s v + h_s + c",
    "pd_gravity": "PD + gravity compensation: Kp_pd e + Kv_pd ed + c",
}


#: The PD controller's line where the controlled arm has no gravity: c is then identically 0
#: (linear in g, Eq. (3.4-24)), and the law plain PD (:func:`control_law`).
PD_WITHOUT_GRAVITY = "PD without gravity term (g = 0, so c = 0): Kp_pd e + Kv_pd ed"


def control_law(controller: str, robot: Robot) -> str:
    """One controller's law in one line, true of the arm it controls.

    Parameters
    ----------
    controller : {"full", "simplified", "pd_gravity"}
        The controller.
    robot : Robot
        The controlled arm (the plant, whose gravity loading c the PD controller adds).

    Returns
    -------
    str
        :data:`CONTROLLER_DESCRIPTIONS`' line; for ``"pd_gravity"`` on an arm without gravity
        (every component of its gravity 0), :data:`PD_WITHOUT_GRAVITY`, named as
        :func:`gd_analyze.store.control_dataset.pd_name` names it.
    """
    if controller == "pd_gravity" and pd_name(robot.gravity) == "PD":
        return PD_WITHOUT_GRAVITY
    return CONTROLLER_DESCRIPTIONS[controller]


#: Default undamped natural frequency of the error dynamics [rad/s].
DEFAULT_WN = 20.0


#: Default damping ratio (critical damping).
DEFAULT_ZETA = 1.0


#: The natural frequency wn [rad/s] and damping ratio zeta [1] accepted, by the command line's
#: --wn and --zeta and :func:`run_control` alike: below 0.01 rad/s an
#: error takes minutes to decay, above 1e4 rad/s (1.6 kHz) no drive follows; below zeta 0.01
#: the loop rings undamped, above 100 its slow mode, about wn / (2 zeta), stalls.
GAIN_RANGES = {"wn": (0.01, 1e4), "zeta": (0.01, 100.0)}      # in this order


#: Default relative tolerance of the integrator.
DEFAULT_RTOL = 1e-8


#: Default absolute tolerance of the integrator [rad, rad/s].
DEFAULT_ATOL = 1e-10


#: Default integration method of ``scipy.integrate.solve_ivp``.
DEFAULT_METHOD = "DOP853"


#: Most integrator steps the gains may demand (see :func:`closed_loop_rates`); stiffer gains
#: are refused before integrating.
MAX_STIFFNESS_STEPS = 20_000


#: Most right-hand-side evaluations of one controller's run: a bound on the integration's time.
MAX_RHS_EVALS = 500_000

#: Set points above which a run stopped by :data:`MAX_RHS_EVALS` says their number: the
#: desired motion is C2 at each set point, and the integrator's steps follow them (the full
#: controller on the PUMA 560's planned motion: 3,473 evaluations at 1,000 set points, 8,696
#: at 10,000, 47,441 at 30,000).
DENSE_SETPOINTS = 10_000

#: Right-hand-side evaluations per step of DOP853 (12 stages; Hairer, Norsett & Wanner,
#: *Solving ODEs I*, Sec. II.10): with :data:`MAX_RHS_EVALS`, the most steps a run can take.
RHS_PER_STEP = 12


def singular_inertia(robot: Robot, D: np.ndarray, rtol: float = 1e-12) -> str | None:
    """Where D is singular: the joint that moves no inertia, for the message.

    Parameters
    ----------
    robot : Robot
        The arm (joint types for the units, URDF names for the joints).
    D : ndarray, shape (N, n, n)
        The inertia matrix at N set points [kg m^2; kg m, kg with prismatic joints].
    rtol : float, optional
        D is singular at a set point where its smallest eigenvalue is at most rtol times its
        largest.

    Returns
    -------
    str or None
        None if D is invertible at every set point; else one line naming the set point, the
        joint (the largest entry of the eigenvector of the smallest eigenvalue) and its D_ii.

    Notes
    -----
    Computed-torque and PD control integrate qdd = D^-1 (tau - h - c) (Fu, Gonzalez & Lee
    1987, Eq. (3.4-24)); a joint whose axis moves no mass and no inertia (D_ii = 0) makes it
    impossible.
    """

    D = np.asarray(D, dtype=float)
    D = 0.5 * (D + np.swapaxes(D, -1, -2))
    w, v = np.linalg.eigh(D)
    big = np.abs(w).max(axis=1)
    bad = np.flatnonzero(~(w[:, 0] > rtol * big))
    if not bad.size:
        return None
    k = int(bad[0])
    j = int(np.argmax(np.abs(v[k, :, 0])))
    units = element_units("D", j, j, robot.prismatic)
    return (f"the inertia matrix D is singular at set point {k + 1}: {joint_title(robot, j)} has "
            f"D_{j + 1}{j + 1} = {float(D[k, j, j]):.3g} {units.replace('m2', 'm^2')} (of "
            f"largest eigenvalue {float(big[k]):.3g}): " + ("no inertia moves with it" if D[k, j, j]
            <= rtol * big[k] else "it moves only what the other joints move") + ", so the arm "
            "cannot be simulated; give that link a mass or inertia (or the joint an armature)")


def closed_loop_rates(robot: Robot, gains: Gains, D: np.ndarray) -> dict[str, float]:
    """The fastest root of each controller's linearised error dynamics.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    gains : Gains
        The controllers' gains.
    D : ndarray, shape (N, n, n)
        The inertia matrix at the set points the loop passes [kg m^2].

    Returns
    -------
    dict of str to float
        Controller (:data:`CONTROLLERS`) -> largest |s| [rad/s]: for computed torque, the roots
        of s^2 + 2 zeta wn s + wn^2 per joint; for PD + gravity, the eigenvalues of
        [[0, E], [-D^-1 Kp_pd, -D^-1 Kv_pd]] at each set point, whose coupling through D^-1 can
        be much faster than wn.

    Notes
    -----
    Source: linearisation of Eq. (3.4-24) about the desired motion with qd = 0 (Fu, Gonzalez
    & Lee 1987, Ch. 5); an explicit Runge-Kutta method needs steps below about 3 / |s|.
    """
    # |s| = wn (z + sqrt(z^2 - 1)) with z = max(zeta, 1) (underdamped: |s| = wn), the root as
    # sqrt(z - 1) sqrt(z + 1): z^2 overflows from z = 1.3e154
    wn, z = np.asarray(gains.wn, float), np.maximum(np.asarray(gains.zeta, float), 1.0)
    ct = float(np.max(wn * (z + np.sqrt(z - 1.0) * np.sqrt(z + 1.0))))
    n = robot.n
    D = np.asarray(D, dtype=float)
    Kp, Kv = np.diag(gains.Kp_pd), np.diag(gains.Kv_pd)
    pd = 0.0 if np.isfinite(Kp).all() and np.isfinite(Kv).all() else math.inf
    for Dk in D if pd == 0.0 else ():
        Dinv = np.linalg.inv(Dk)
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Dinv @ Kp, -Dinv @ Kv]])
        pd = max(pd, float(np.abs(np.linalg.eigvals(A)).max()))
    return {"full": ct, "simplified": ct, "pd_gravity": pd}


@dataclass(frozen=True, eq=False)
class Gains:
    """Gains of the three controllers.

    Attributes
    ----------
    wn : ndarray, shape (n,)
        Undamped natural frequency of each joint's error dynamics [rad/s].
    zeta : ndarray, shape (n,)
        Damping ratio of each joint [1].
    Kp : ndarray, shape (n,)
        Computed-torque position gain, wn^2 [s^-2].
    Kv : ndarray, shape (n,)
        Computed-torque velocity gain, 2 zeta wn [s^-1].
    inertia_scale : ndarray, shape (n,)
        diag(D(q_ref)), the inertia the PD gains are scaled by [kg m^2].
    Kp_pd : ndarray, shape (n,)
        PD + gravity position gain, inertia_scale wn^2 [N m/rad].
    Kv_pd : ndarray, shape (n,)
        PD + gravity velocity gain, inertia_scale 2 zeta wn [N m s/rad].
    """

    wn: np.ndarray
    zeta: np.ndarray
    Kp: np.ndarray
    Kv: np.ndarray
    inertia_scale: np.ndarray
    Kp_pd: np.ndarray
    Kv_pd: np.ndarray


def control_gains(robot: Robot, q_ref: ArrayLike, wn: float | ArrayLike = DEFAULT_WN,
                  zeta: float | ArrayLike = DEFAULT_ZETA) -> Gains:
    """Gains for a chosen natural frequency and damping ratio.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q_ref : array_like, shape (n,)
        Configuration whose inertia diagonal scales the PD gains, normally q_d(0) [rad].
    wn : float or array_like, shape (n,), optional
        Undamped natural frequency [rad/s], within :data:`GAIN_RANGES` (0.01 to 1e4).
    zeta : float or array_like, shape (n,), optional
        Damping ratio [1], within :data:`GAIN_RANGES` (0.01 to 100).

    Returns
    -------
    Gains
        Kp = wn^2, Kv = 2 zeta wn; Kp_pd = diag(D(q_ref)) wn^2, Kv_pd = diag(D(q_ref)) 2 zeta wn.

    Raises
    ------
    ValueError
        If wn or zeta is outside :data:`GAIN_RANGES` (NaN too), or not a scalar or n values.

    Notes
    -----
    Computed torque decouples the joints into e'' + Kv e' + Kp e = 0 (Fu, Gonzalez & Lee 1987,
    Ch. 5), whose characteristic polynomial s^2 + 2 zeta wn s + wn^2 gives the gains.
    """
    n = robot.n
    out = []
    for (name, (lo, hi)), value in zip(GAIN_RANGES.items(), (wn, zeta)):   # --wn's, --zeta's
        arr = np.asarray(value, dtype=float)
        if arr.ndim > 1 or (arr.ndim == 1 and arr.shape != (n,)):
            raise ValueError(f"{name} must be a number or {n} numbers, got shape {arr.shape}")
        arr = np.broadcast_to(arr, (n,)).astype(float)
        if not ((arr >= lo) & (arr <= hi)).all():
            raise ValueError(f"{name} must be in [{lo:g}, {hi:g}], got {arr.tolist()}")
        out.append(arr)
    wn, zeta = out
    q_ref = np.asarray(q_ref, dtype=float).reshape(1, n)
    scale = np.diagonal(gd_terms(robot, q_ref, np.zeros_like(q_ref)).D[0]).copy()
    return Gains(wn=wn, zeta=zeta, Kp=wn**2, Kv=2 * zeta * wn, inertia_scale=scale,
                 Kp_pd=scale * wn**2, Kv_pd=scale * 2 * zeta * wn)


def desired_motion(trajectory: Trajectory) -> PPoly:
    """The desired motion between set points: piecewise quintic Hermite through (q, qd, qdd).

    Parameters
    ----------
    trajectory : Trajectory
        Set points t (N,) [s] and q, qd, qdd (N, n) [rad, rad/s, rad/s^2].

    Returns
    -------
    scipy.interpolate.PPoly
        Degree 5 in each of the N - 1 intervals, values of shape (n,): ``pp(t)`` is q_d [rad],
        ``pp(t, 1)`` qd_d [rad/s], ``pp(t, 2)`` qdd_d [rad/s^2]; it matches q, qd and qdd at
        every set point and is C2.

    Raises
    ------
    ValueError
        If there are fewer than 2 set points or the times are not strictly increasing.
    """
    from scipy.interpolate import BPoly, PPoly

    t = np.asarray(trajectory.t, dtype=float)
    if t.shape[0] < 2 or not (np.diff(t) > 0).all():
        raise ValueError("the desired motion needs >= 2 set points with increasing times")
    ends = np.stack([trajectory.q, trajectory.qd, trajectory.qdd], axis=1)     # (N, 3, n)
    return PPoly.from_bernstein_basis(BPoly.from_derivatives(t, ends))


#: The quintic Hermite basis on s in [0, 1] in powers of s: row m holds the coefficients of
#: s^m in the basis functions of q_0, h qd_0, h^2 qdd_0, q_1, h qd_1 and h^2 qdd_1 (h the step).
HERMITE_QUINTIC = np.array([[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 0.5, 0, 0, 0],
                            [-10, -6, -1.5, 10, -4, 0.5], [15, 8, 1.5, -15, 7, -1],
                            [-6, -3, -0.5, 6, -3, 0.5]])
#: Roundings counted on any path of :func:`motion_round_off`'s sums, more than occur: at most
#: 13 in evaluating a term of a degree-5 power sum (x - x_i, five powers, two products, five
#: additions), as many in a residual at x_i + h, 6 in the commanded acceleration.
ROUNDINGS = 32
#: gamma_K = K u / (1 - K u), u = eps / 2, K = :data:`ROUNDINGS` (Higham 2002, Lemma 3.1).
_GAMMA = ROUNDINGS * np.finfo(float).eps / 2 / (1 - ROUNDINGS * np.finfo(float).eps / 2)


def motion_round_off(motion: PPoly, trajectory: Trajectory, t: ArrayLike) -> np.ndarray:
    """A bound on the round-off of the desired motion at given times: how far ``motion(t, k)``
    may lie from the exact quintic Hermite interpolant Q of the set points.

    Parameters
    ----------
    motion : scipy.interpolate.PPoly
        :func:`desired_motion` of the trajectory.
    trajectory : Trajectory
        The set points, q, qd, qdd (N, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    t : array_like, shape (M,)
        Times within the set points' [s].

    Returns
    -------
    ndarray, shape (3, M, n)
        For k = 0, 1, 2 a bound on |motion(t, k) - Q^(k)(t)| [rad, rad/s, rad/s^2; m, m/s,
        m/s^2].

    Notes
    -----
    On an interval [x_i, x_i + h] the motion is P(x) = sum_m C_m (x - x_i)^m with the stored
    coefficients C_m. P - Q is the quintic Hermite interpolant of P's residuals r_j at the
    ends (its value and first two derivatives there minus the set point's), so
    |P^(k) - Q^(k)| <= h^-k sum_j |B_j^(k)(s)| h^d_j |r_j|, s = (x - x_i) / h, d_j the
    order of end condition j and B_j basis function j (column j of H =
    :data:`HERMITE_QUINTIC`), evaluated with gamma_K sum_m m!/(m-k)! |H_mj| added. The
    residuals are measured, not assumed: at x_i exactly (j! C_j), at x_i + h in floating point
    plus gamma_K times the sum of the |terms|; each set point's value y adds
    :data:`~gd_analyze.certify.region.VALUE_EPS` eps |y|,
    the round-off it may carry (as where it is checked itself). Evaluating P^(k)(x) errs by at
    most gamma_K sum_m m!/(m-k)! |C_m| |x - x_i|^(m-k) (Higham 2002, Sec. 3.1; K =
    :data:`ROUNDINGS`), and the bound's own arithmetic by a factor 1 + gamma_K. The bound so
    follows the magnitudes that entered the evaluation, about eps max|q| / h^k, not the limits.
    """
    from scipy.interpolate import PPoly

    c, x = np.asarray(motion.c, float)[::-1], np.asarray(motion.x, float)   # C_m: power m
    h = np.diff(x)[:, None]
    y = np.stack([trajectory.q, trajectory.qd, trajectory.qdd]).astype(float)   # (3, N, n)
    own = VALUE_EPS * np.finfo(float).eps * np.abs(y)
    r = np.empty((6, *c.shape[1:]))
    for d in range(3):
        terms = np.stack([math.perm(m, d) * c[m] * h ** (m - d) for m in range(d, 6)])
        r[d] = (np.abs(math.factorial(d) * c[d] - y[d, :-1]) + own[d, :-1]) * h ** d
        r[3 + d] = (np.abs(terms.sum(0) - y[d, 1:]) + _GAMMA * np.abs(terms).sum(0)
                    + own[d, 1:]) * h ** d
    t = np.asarray(t, float)
    i = np.clip(np.searchsorted(x, t, side="right") - 1, 0, len(h) - 1)   # scipy's interval
    u = ((t - x[i]) / h[i, 0])[:, None] ** np.arange(6)                  # s^0 .. s^5
    size = PPoly(np.abs(motion.c), x)
    out = np.empty((3, t.size, c.shape[2]))
    for k in range(3):          # row m - k: the coefficients of s^(m - k) in B_j^(k)
        basis = np.array([math.perm(m, k) for m in range(k, 6)])[:, None] * HERMITE_QUINTIC[k:]
        at = np.abs(u[:, :6 - k] @ basis) + _GAMMA * np.abs(basis).sum(0)  # (M, 6)
        out[k] = np.einsum("mj,jmn->mn", at, r[:, i]) / h[i] ** k + _GAMMA * size(t, k)
    return (1 + _GAMMA) * out


def controller_torque(controller: str, robot: Robot, gains: Gains, q_d: np.ndarray,
                      qd_d: np.ndarray, qdd_d: np.ndarray, q: np.ndarray, qd: np.ndarray,
                      choices: SimplifiedModel | None = None, terms: GDTerms | None = None,
                      model_torque: Callable[..., Any] | None = None) -> np.ndarray:
    """Torque a controller applies at given desired and actual states.

    Parameters
    ----------
    controller : {"full", "simplified", "pd_gravity"}
        The control law (see the module docstring).
    robot : Robot
        The arm, with n joints.
    gains : Gains
        The gains.
    q_d, qd_d, qdd_d : ndarray, shape (N, n)
        Desired positions [rad], velocities [rad/s] and accelerations [rad/s^2].
    q, qd : ndarray, shape (N, n)
        Actual positions [rad] and velocities [rad/s].
    choices : SimplifiedModel, optional
        The simplified model (its :meth:`~gd_analyze.simplify.simplified.SimplifiedModel.torque`,
        the explicit form); required for ``"simplified"``.
    terms : GDTerms, optional
        The full G-D terms at (q, qd), if already computed (used by ``"full"`` and
        ``"pd_gravity"``).
    model_torque : callable, optional
        ``model_torque(q, qd, v)`` -> shape (N, n): the simplified model's torques, if not
        ``choices.torque`` (the closed loop's one-state evaluation,
        :meth:`~gd_analyze.simplify.simplified.SimplifiedModel.torque_at`).

    Returns
    -------
    ndarray, shape (N, n)
        Joint torques tau [N m].

    Raises
    ------
    ValueError
        If the controller is unknown, or ``"simplified"`` is asked for without choices.

    Notes
    -----
    Computed torque (Fu, Gonzalez & Lee 1987, Ch. 5): tau = D_m(q) [qdd_d + Kv (qd_d - qd) +
    Kp (q_d - q)] + h_m(q, qd) + c_m(q), the model terms from Eq. (3.4-24) (full) or from its
    kept parts (simplified, Sec. 3.4.1). PD + gravity: tau = Kp_pd e + Kv_pd ed + c(q).
    """
    if controller not in CONTROLLERS:
        raise ValueError(f"controller must be one of {CONTROLLERS}, got {controller!r}")
    e, ed = q_d - q, qd_d - qd
    v = qdd_d + gains.Kv * ed + gains.Kp * e
    if controller == "simplified":
        if choices is None or not hasattr(choices, "torque"):
            raise ValueError("the simplified controller needs the simplified model")
        return (model_torque or choices.torque)(q, qd, v)
    terms = gd_terms(robot, q, qd) if terms is None else terms
    if controller == "pd_gravity":
        return gains.Kp_pd * e + gains.Kv_pd * ed + terms.c
    return terms.tau(v)


@dataclass(frozen=True, eq=False)
class TrackingRun:
    """One controller's closed-loop run along the desired motion.

    Attributes
    ----------
    controller : str
        ``"full"``, ``"simplified"`` or ``"pd_gravity"``.
    t : ndarray, shape (M,)
        Sample times: the set points and the fine grid [s].
    q, qd : ndarray, shape (M, n)
        Joint positions [rad] and velocities [rad/s] of the plant.
    tau : ndarray, shape (M, n)
        Torques the controller applied [N m].
    error : ndarray, shape (M, n)
        Tracking error e = q_d - q [rad].
    nfev : int
        Right-hand side evaluations of the integrator.
    success : bool
        Whether the integrator reached the end.
    message : str
        The integrator's message.
    """

    controller: str
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    error: np.ndarray
    nfev: int
    success: bool
    message: str


def track(robot: Robot, controller: str, gains: Gains, desired: PPoly, t_eval: ArrayLike,
          q0_offset: float | ArrayLike = 0.0, choices: SimplifiedModel | None = None,
          rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL, method: str = DEFAULT_METHOD
          ) -> TrackingRun:
    """Integrate the full-model arm under one controller along a desired motion.

    Parameters
    ----------
    robot : Robot
        The arm (the plant, with its full G-D dynamics), n joints.
    controller : {"full", "simplified", "pd_gravity"}
        The control law.
    gains : Gains
        The gains.
    desired : scipy.interpolate.PPoly
        The desired motion, as :func:`desired_motion` gives it.
    t_eval : array_like, shape (M,)
        Increasing sample times [s]; the run goes from t_eval[0] to t_eval[-1].
    q0_offset : float or array_like, shape (n,), optional
        Initial position error, q(0) = q_d(0) + q0_offset [rad]; qd(0) = qd_d(0).
    choices : SimplifiedModel, optional
        The simplified model (for ``"simplified"``).
    rtol, atol : float, optional
        Tolerances of ``scipy.integrate.solve_ivp``.
    method : str, optional
        Its method, e.g. ``"DOP853"`` or ``"RK45"``.

    Returns
    -------
    TrackingRun

    Raises
    ------
    ValueError
        If the controller is unknown or its choices are missing or invalid.

    Notes
    -----
    Plant: qdd = D^-1 (tau - h - c - tau_f), Eq. (3.4-24) with the drives' armature in D and
    friction tau_f (:mod:`gd_analyze.model.drives`, its Coulomb part linear within
    :data:`~gd_analyze.model.drives.COULOMB_BAND`; the controllers' laws keep sign(qd)); the G-D terms at the current
    state are computed once per right-hand-side call and serve both the plant and the
    full-model and PD laws; the simplified law evaluates its model at that one state in floats
    (:meth:`~gd_analyze.simplify.simplified.SimplifiedModel.torque_at`: its program's
    operations in the same order as the emitted numpy model's). The torques returned at
    ``t_eval`` are computed afterwards, for all samples at once, by ``choices.torque``.
    """
    from scipy.integrate import solve_ivp
    from scipy.interpolate import PPoly

    n = robot.n
    t_eval = np.asarray(t_eval, dtype=float)
    d1, d2 = desired.derivative(1), desired.derivative(2)
    # integrated in the time since t_eval[0]: the same polynomials on shifted breakpoints (the
    # differences of nearby floats are exact), so that the steps keep their resolution where
    # the stamps are far from 0 (Unix time stamps: 2.4e-7 s apart at 1.7e9 s)
    t0 = t_eval[0]
    motion = _stacked(desired, d1, d2)             # q_d, qd_d, qdd_d: one evaluation a call
    motion = PPoly.construct_fast(motion.c, motion.x - t0, motion.extrapolate)
    state_terms = one_state_terms(robot)
    calls, band = [0], bool(np.any(robot.coulomb))
    at = getattr(choices, "torque_at", None) if controller == "simplified" else None
    # the simplified model at the one state of a call (choices.torque without torque_at)
    one_state = None if at is None else (lambda q, qd, v: at(q[0], qd[0], v[0])[None])

    def rhs(t, y):
        calls[0] += 1
        if calls[0] > MAX_RHS_EVALS:
            raise _TooManyEvals
        q, qd = y[None, :n], y[None, n:]
        terms = state_terms(q, qd)
        m = motion(t)[None]
        tau = controller_torque(controller, robot, gains, m[:, :n], m[:, n:2 * n],
                                m[:, 2 * n:], q, qd, choices=choices, terms=terms,
                                model_torque=one_state)
        plant = replace(terms, tau_f=friction_torque(robot, qd, COULOMB_BAND)) if band else terms
        return np.concatenate([y[n:], qdd_from_terms(plant, tau)[0]])

    y0 = np.concatenate([desired(t0) + np.broadcast_to(np.asarray(q0_offset, float), (n,)),
                         d1(t0)])
    try:
        sol = solve_ivp(rhs, (0.0, t_eval[-1] - t0), y0, method=method, t_eval=t_eval - t0,
                        rtol=rtol, atol=atol)
    except _TooManyEvals:
        cause = "the gains, the trajectory or the plant's friction make it too stiff (lower wn)"
        knots = desired.x.size
        if knots > DENSE_SETPOINTS:
            cause += (f"; the desired motion passes through {knots} set points "
                      f"({(desired.x[-1] - desired.x[0]) / (knots - 1):.3g} s apart) and the "
                      "integrator's steps follow its joins: a coarser trajectory (every k-th "
                      "set point) takes fewer")
        raise ValueError(f"the {controller} controller's run did not finish within "
                         f"{MAX_RHS_EVALS} evaluations of the dynamics: {cause}") from None
    # the samples reached (all of them unless the run failed), NaN after them: the shapes kept
    q, qd = np.full((t_eval.size, n), np.nan), np.full((t_eval.size, n), np.nan)
    m = sol.y.shape[1]
    q[:m], qd[:m] = sol.y[:n].T, sol.y[n:].T
    q_d, qd_d, qdd_d = desired(t_eval), d1(t_eval), d2(t_eval)
    ok = np.isfinite(q).all(axis=1)
    tau = np.full_like(q, np.nan)
    if ok.any():
        tau[ok] = controller_torque(controller, robot, gains, q_d[ok], qd_d[ok], qdd_d[ok],
                                    q[ok], qd[ok], choices=choices)
    return TrackingRun(controller=controller, t=t_eval, q=q, qd=qd, tau=tau, error=q_d - q,
                       nfev=int(sol.nfev), success=bool(sol.success), message=str(sol.message))


def _stacked(*polys):
    """One PPoly of the given PPolys' values side by side, on their common breakpoints: the
    lower degrees padded with leading zero coefficients, so that its values are exactly
    theirs (Horner's rule adds the zeros exactly)."""
    from scipy.interpolate import PPoly

    k = max(p.c.shape[0] for p in polys)
    c = [np.concatenate([np.zeros((k - p.c.shape[0],) + p.c.shape[1:]), p.c]) for p in polys]
    return PPoly(np.concatenate(c, axis=-1), polys[0].x)


class _TooManyEvals(Exception):
    """The integration exceeded MAX_RHS_EVALS."""


#: Default number of evenly spaced samples of the fine grid (set points are added).
DEFAULT_GRID_POINTS = 2001
#: Default file name of the stored control dataset.
CONTROL_FILE = "control.h5"
#: The tolerances of the runs that measure the integrator noise are rtol and atol over this.
NOISE_TIGHTEN = 100.0
#: The noise floor of the torque difference is this many times its measured noise.
NOISE_FACTOR = 2.0


@dataclass(frozen=True, eq=False)
class ControlResult:
    """The closed-loop comparison of :func:`run_control`.

    Attributes
    ----------
    robot : Robot
        The arm, with n joints.
    choices : dict
        The simplified model's choices.
    gains : Gains
        The gains used.
    t : ndarray, shape (M,)
        Sample times, set points and fine grid [s].
    is_setpoint : ndarray of bool, shape (M,)
        True at the trajectory's set points.
    q_d, qd_d, qdd_d : ndarray, shape (M, n)
        The desired motion at the samples [rad, rad/s, rad/s^2].
    runs : dict
        Controller name -> :class:`TrackingRun`, in
        :data:`CONTROLLERS` order.
    cost : dict or None
        :func:`model_cost` of the model, if asked for.
    provenance : dict
        Files and their SHA-256, solver settings, initial offset.
    tau_noise : ndarray, shape (n,), or None
        Measured integrator noise of :attr:`tau_difference` per joint (:func:`difference_noise`)
        [N m; N on a prismatic joint]; None unless both computed-torque controllers ran.
    """

    robot: Robot
    choices: dict
    gains: Gains
    t: np.ndarray
    is_setpoint: np.ndarray
    q_d: np.ndarray
    qd_d: np.ndarray
    qdd_d: np.ndarray
    runs: dict
    cost: dict | None = None
    provenance: dict = field(default_factory=dict)
    tau_noise: np.ndarray | None = None

    @property
    def tau_noise_floor(self) -> np.ndarray | None:
        """ndarray, shape (n,), or None: per joint, the level at or below which the closed-loop
        torque difference is integrator noise, not data [N m; N on a prismatic joint].

        max(:data:`NOISE_FACTOR` x :attr:`tau_noise`, max(rtol, 1e-12) x the full-model
        controller's peak |tau|); without a measured noise, the second term alone. None
        without a full-model run.
        """
        if "full" not in self.runs:
            return None
        tol = max(float(self.provenance.get("rtol", 0.0)), ROUND_OFF)
        noise = 0.0 if self.tau_noise is None else NOISE_FACTOR * np.asarray(self.tau_noise, float)
        return np.maximum(noise, tol * np.nanmax(np.abs(self.runs["full"].tau), axis=0))

    @property
    def descriptions(self) -> dict[str, str]:
        """dict: controller name -> its control law in one line
        (:func:`control_law`: plain PD on an arm without gravity), the simplified model's
        gravity term c_s where the model drops part of c (its ``gravity_dropped`` parameters,
        or fewer ``c_terms_kept`` than ``c_terms``), else c; the computed-torque laws with the
        drives' friction tau_f where the arm has it."""
        m = self.provenance.get("model", {})
        part = bool(m.get("gravity_dropped")) or -1 < m.get("c_terms_kept", -1) != m.get("c_terms")
        return {c: control_law(c, self.robot) + "_s" * (c == "simplified" and part)
                + " + tau_f" * (c != "pd_gravity" and self.robot.has_friction) for c in self.runs}

    @property
    def controllers(self) -> list[str]:
        """list of str: the controllers run, in table order."""
        return list(self.runs)

    def error_figures(self, controller: str) -> dict[str, list[float]]:
        """Tracking error figures of one controller.

        Parameters
        ----------
        controller : str
            A name of :attr:`runs`.

        Returns
        -------
        dict
            Lists of n floats [rad]: ``peak_setpoints``, ``rms_setpoints`` (|e| at the set
            points) and ``peak_grid``, ``rms_grid`` (on all samples).

        Raises
        ------
        KeyError
            If the controller was not run.
        """
        e = self.runs[controller].error
        (ps, rs), (pg, rg) = peak_rms(e[self.is_setpoint]), peak_rms(e)
        return {"peak_setpoints": ps.tolist(), "rms_setpoints": rs.tolist(),
                "peak_grid": pg.tolist(), "rms_grid": rg.tolist()}

    @property
    def tau_difference(self) -> np.ndarray | None:
        """ndarray, shape (M, n), or None: tau of "simplified" minus tau of "full" [N m].

        Each from its own closed-loop run, at the same sample times; None unless both ran.
        """
        if "full" in self.runs and "simplified" in self.runs:
            return self.runs["simplified"].tau - self.runs["full"].tau
        return None

    def summary(self) -> dict[str, Any]:
        """The figures as plain JSON-ready data.

        Returns
        -------
        dict
            ``robot``, ``wn``, ``zeta``, ``tracking`` (controller -> :meth:`error_figures`
            [rad]), ``tau_difference`` (``peak``, ``rms`` per joint [N m], or None),
            ``cost`` (or None) and ``guarantee`` (the model's ``scope`` sentence, its
            ``kind`` and whether it ``covered`` the desired motion and, for a region, its every
            sample and the simplified-model controller's closed loop: q, qd and the commanded
            acceleration v at which it evaluates the model; with the ``reason``).
        """
        td = None if (diff := self.tau_difference) is None else {
            k: v.tolist() for k, v in zip(("peak", "rms"), peak_rms(diff))}
        return {"robot": self.robot.name, "wn": self.gains.wn.tolist(),
                "zeta": self.gains.zeta.tolist(),
                "tracking": {c: self.error_figures(c) for c in self.runs},
                "nfev": {c: r.nfev for c, r in self.runs.items()},
                "tau_difference": td, "cost": self.cost,
                "guarantee": {k: m.get(f) for k, f in (
                    ("statement", "scope"), ("kind", "guarantee_kind"),
                    ("covered", "guarantee_covered"), ("reason", "guarantee_coverage"))
                    if (m := self.provenance.get("model", {})) is not None}}


def model_cost(model: SimplifiedModel) -> dict[str, Any]:
    """The counted operations per set point of a simplified model, beside the full model's.

    Parameters
    ----------
    model : SimplifiedModel
        The model. Both costs are counted here, never read from a file: the simplified
        model's on the straight-line program of its own terms, the full explicit model's on
        the program of all the terms of its robot (:func:`gd_analyze.store.explicit_cache.explicit_terms`).

    Returns
    -------
    dict
        ``evaluators`` (names), ``multiplications`` and ``additions`` (lists of int per set
        point): the simplified model, the exact recursive model
        (:func:`gd_analyze.symbolic.recursive.recursive_program`, or the same program
        its builder kept in ``choice_cache``), the full explicit model
        (unless the model is recursive and the expansion expensive,
        :func:`gd_analyze.symbolic.explicit_estimate.is_expensive`) and the project's Newton-Euler
        as implemented (:func:`gd_analyze.dynamics.opcount.operation_counts`, the arm's one
        count), last;
        ``dropped`` of ``parts``: what the model drops, ``what`` names them (parts of D and h,
        or (base parameter, part) pairs), ``dropped_pairs`` lists the pairs of a recursive model.

    Notes
    -----
    Counts, not times: they do not depend on the machine. Sources: Sec. 3.4.1 of Fu, Gonzalez &
    Lee (1987) (a simplified model "at a reduced computation time"), Table 3.5 (N-E), and
    Armstrong, Khatib & Burdick (1986) for the explicit form.
    """
    robot: Robot = model.robot
    built = model.choice_cache or ()    # the exact program its builder made, where it kept it
    exact = built[2] if len(built) > 2 else recursive_program(robot)
    counted = [(f"simplified model ({model.form} form)", model.program().cost()),
               ("exact recursive model", with_drives(exact, robot).cost())]
    if model.form == "explicit" or not is_expensive(robot):
        terms, _ = explicit_cache.explicit_terms(robot)
        counted.append(("full explicit model", full_program(robot, terms).cost()))
    counted.append(("Newton-Euler (as implemented)", operation_counts(robot)["newton-euler"]))
    counts = {"evaluators": [name for name, _ in counted],
              **{k: [int(c[k]) for _, c in counted] for k in ("multiplications", "additions")}}
    facts = model_facts(model)
    if model.recursive is not None:
        return {**counts, "dropped": facts["pairs_dropped"], "parts": facts["pairs"],
                "what": "(base parameter, part) pairs of the recursive model",
                "dropped_pairs": facts["dropped_pairs"]}
    Mt, Mr, mt, mr = choice_masks(model.choices, robot.n)
    parts = 2 * (robot.n * (robot.n + 1) // 2 + robot.n)
    kept = int(np.triu(Mt).sum() + np.triu(Mr).sum() + mt.sum() + mr.sum())
    return {**counts, "dropped": parts - kept, "parts": parts,
            "what": "translational/rotational parts of D and h", "dropped_pairs": ""}


def model_facts(model: SimplifiedModel) -> dict[str, Any]:
    """What the reports state about a simplified model, read from the model itself.

    Parameters
    ----------
    model : SimplifiedModel
        A model as built, or read from ``simplified_model.json``.

    Returns
    -------
    dict
        ``form`` (recursive or explicit), ``rule`` (budget or chapter), ``tolerance``;
        for the recursive form ``base_parameters`` (count), ``pairs`` and ``pairs_dropped``
        (the (parameter, part) pairs that contribute on the trajectories the model was built
        on, and those dropped), ``dropped_pairs`` (``"XY2 (inertial), ..."``) and
        ``gravity_dropped`` (the parameters whose gravity part is dropped, comma-separated),
        ``pairs_known`` (1 if the model records which pairs contribute, else every pair counts)
        (:meth:`gd_analyze.symbolic.recursive_model.RecursiveModel.stated_facts`, the
        count of the main report); for the explicit form of the budget rule ``c_terms_kept``
        and ``c_terms`` (its terms of c and the full model's; -1 when the full model is not
        derived); ``scope``, the model's guarantee in one sentence
        (:meth:`~gd_analyze.simplify.simplified.SimplifiedModel.scope`), and
        ``guarantee_kind`` (``"region"``, ``"trajectory"`` or ``"none"``); ``gravity``, that
        of the arm the model was built for, in its base frame [m/s^2]. Sources: Fu,
        Gonzalez & Lee (1987), Sec. 3.4.1 and Eq. (3.4-24).
    """
    out = {"form": model.form, "rule": str(model.rule), "tolerance": float(model.tolerance),
           "scope": model.scope(), "gravity": [float(v) for v in model.robot.gravity],
           "guarantee_kind": "none" if model.guarantee is None else model.guarantee.kind,
           "base_parameters": -1, "pairs": -1, "pairs_dropped": -1, "dropped_pairs": "",
           "gravity_dropped": "", "pairs_known": 0, "c_terms_kept": -1, "c_terms": -1}
    if model.recursive is not None:
        f = model.recursive.stated_facts()
        out.update(base_parameters=len(model.recursive.names), pairs=f["pairs"],
                   pairs_dropped=f["dropped"],
                   dropped_pairs=", ".join(f"{a} ({b})" for a, b in f["dropped_pairs"]),
                   gravity_dropped=", ".join(f["gravity_dropped"]), pairs_known=int(f["known"]))
    elif model.rule == "budget" and model.terms is not None:
        out["c_terms_kept"] = int(np.sum(np.asarray(model.terms.kind) == "c"))
        if not is_expensive(model.robot):
            full, _ = explicit_cache.explicit_terms(model.robot)
            out["c_terms"] = int(np.sum(np.asarray(full.kind) == "c"))
    return out

def _sample_times(t_set, grid_points):
    """Set-point times and an even grid, merged; grid points within 1e-9 T of a set point go."""
    t_set = np.asarray(t_set, dtype=float)
    grid = np.linspace(t_set[0], t_set[-1], max(2, int(grid_points)))
    tol = 1e-9 * max(t_set[-1] - t_set[0], 1e-300)
    idx = np.clip(np.searchsorted(t_set, grid), 1, t_set.size - 1)
    near = np.minimum(np.abs(grid - t_set[idx - 1]), np.abs(grid - t_set[idx])) <= tol
    t = np.union1d(t_set, grid[~near])
    return t, np.isin(t, t_set)


def run_control(model: SimplifiedModel, trajectory: Trajectory,
                wn: ArrayLike = DEFAULT_WN, zeta: ArrayLike = DEFAULT_ZETA,
                q0_offset: ArrayLike = 0.0,
                controllers: Sequence[str] = CONTROLLERS,
                grid_points: int = DEFAULT_GRID_POINTS, rtol: float = DEFAULT_RTOL,
                atol: float = DEFAULT_ATOL, method: str = DEFAULT_METHOD,
                t_end: float | None = None, cost: bool = True,
                model_path: str | os.PathLike[str] | None = None,
                model_sha256: str | None = None, plant: Robot | None = None,
                verdict_tolerance: tuple[float, float] | None = None) -> ControlResult:
    """Track a trajectory with the full-model, simplified-model and PD + gravity controllers.

    Parameters
    ----------
    model : SimplifiedModel
        The simplified model; its robot is the plant.
    trajectory : Trajectory
        The set points to track.
    wn : float or array_like, shape (n,), optional
        Undamped natural frequency of the error dynamics [rad/s] (default 20), within
        :data:`GAIN_RANGES` (0.01 to 1e4, as ``--wn``).
    zeta : float or array_like, shape (n,), optional
        Damping ratio (default 1), within :data:`GAIN_RANGES` (0.01 to
        100, as ``--zeta``).
    q0_offset : float or array_like, shape (n,), optional
        Initial position error q(0) - q_d(0) [rad] (default 0: start on the trajectory).
    controllers : sequence of str, optional
        Which of :data:`CONTROLLERS` to run.
    grid_points : int, optional
        Evenly spaced samples of the fine grid (the set points are added).
    rtol, atol : float, optional
        Integrator tolerances.
    method : str, optional
        ``solve_ivp`` method.
    t_end : float, optional
        Stop at this time [s] (set points after it are left out); default: the last set point.
    cost : bool, optional
        Also record the counted operations of the model (:func:`model_cost`).
    model_path : str or os.PathLike, optional
        The file the model was read from, recorded in the provenance.
    model_sha256 : str, optional
        That file's SHA-256 (:func:`gd_analyze.files.file_sha256`); without a file, the SHA-256
        of the model's canonical JSON is recorded.
    plant : Robot, optional
        The controlled arm, which the full-model and PD + gravity controllers also use
        (default: the model's robot), e.g. mounted otherwise
        (:func:`gd_analyze.model.mounting.with_mounting`); the simplified model keeps its own.
    verdict_tolerance : tuple of (float, float), optional
        The report's verdict tolerance on the simplified-model controller's peak tracking
        error: revolute joints [rad], prismatic joints [m] (recorded for the report, not used
        here; default: not recorded, the report's
        :data:`gd_analyze.report.control.VERDICT_TOLERANCE`).

    Returns
    -------
    ControlResult

    Raises
    ------
    ValueError
        If the trajectory's joint count differs from the robot's, t_end leaves fewer than 2
        set points, a controller is unknown, wn or zeta is outside
        :data:`GAIN_RANGES` (as ``--wn``, ``--zeta``;
        :func:`control_gains`), the gains so stiff that the
        integration would need more than
        :data:`MAX_STIFFNESS_STEPS` steps
        (:func:`closed_loop_rates`, every controller), D is singular
        (:func:`singular_inertia`), or a run exceeds
        :data:`MAX_RHS_EVALS` evaluations.
    InputError
        If the model's torque is not finite on a set point (:func:`~gd_analyze.jobs.evaluate.model_torque`),
        or its trajectory guarantee does not hold on its own trajectory, measured again
        (:func:`~gd_analyze.jobs.evaluate.check_trajectory_claim`).

    Notes
    -----
    Sources: Fu, Gonzalez & Lee (1987), Eq. (3.4-24) (plant and model), Sec. 3.4.1
    (simplified model), Ch. 5 (computed-torque control).
    """
    model_file = "<in memory>" if model_path is None else str(model_path)
    model_sha = model_sha256 or ("" if model_path is not None else hashlib.sha256(json.dumps(
        json_safe(model.to_dict()), sort_keys=True).encode()).hexdigest())
    robot: Robot = model.robot if plant is None else plant
    if trajectory.q.shape[1] != robot.n:
        raise ValueError(f"the trajectory has {trajectory.q.shape[1]} joints, the robot "
                         f"{robot.n}")
    if not controllers or not set(controllers) <= set(CONTROLLERS):
        raise ValueError(f"controllers must be among {CONTROLLERS}, got "
                         f"{list(controllers)}")
    choice_masks(model.choices, robot.n)            # validate
    model_torque(model, trajectory.q, trajectory.qd, trajectory.qdd)    # finite on the set points
    covers = coverage(model, trajectory, plant=robot, path=model_file)  # a claim checked first
    t_set = np.asarray(trajectory.t, dtype=float)
    if t_end is not None:
        t_set = t_set[t_set <= float(t_end) * (1 + 1e-12)]
        if t_set.size < 2:
            raise ValueError(f"t_end = {t_end} s leaves fewer than 2 set points")
    desired = desired_motion(trajectory)
    t, is_set = _sample_times(t_set, grid_points)
    # D at (up to 64 of) the set points: invertible, and the loops' speed for every controller
    pick = np.unique(np.linspace(0, len(trajectory.t) - 1, 64).round().astype(int))
    D = gd_terms(robot, trajectory.q[pick], np.zeros_like(trajectory.q[pick])).D
    if singular := singular_inertia(robot, D):
        raise ValueError(singular)
    gains = control_gains(robot, desired(t[0]), wn, zeta)
    rates = closed_loop_rates(robot, gains, D)
    for name in (c for c in CONTROLLERS if c in controllers):
        # computed torque: the gains' own bound; PD + gravity: what a run can evaluate
        most = (MAX_STIFFNESS_STEPS if name != "pd_gravity"
                else MAX_RHS_EVALS // RHS_PER_STEP)
        steps = rates[name] * float(t[-1] - t[0]) / 3.0
        if steps > most:
            law = (pd_name(robot.gravity) if name == "pd_gravity"
                   else control_law(name, robot).split(":")[0])
            raise ValueError(
                f"wn = {np.max(gains.wn):g} rad/s and zeta = {np.max(gains.zeta):g} make the "
                f"{law} loop ({name}) too "
                f"stiff: its fastest mode, {rates[name]:.3g} rad/s, needs about {steps:.3g} "
                f"integrator steps over {t[-1] - t[0]:g} s (at most {most}); lower wn or zeta")
    offset = np.broadcast_to(np.asarray(q0_offset, dtype=float), (robot.n,)).copy()
    runs = {name: track(robot, name, gains, desired, t, q0_offset=offset,
                                 choices=model, rtol=rtol, atol=atol, method=method)
            for name in CONTROLLERS if name in controllers}
    q_d, qd_d, qdd_d = desired(t), desired(t, 1), desired(t, 2)
    if covers["covered"] and covers["kind"] == "region":    # a "yes" names what it checked
        e = motion_round_off(desired, trajectory, t)    # what round-off may not take outside
        states: list[tuple[str, str, tuple[Any, ...], tuple[Any, ...]]] = [
            ("desired motion between the set points", "|qdd|", (q_d, qd_d, qdd_d), tuple(e))]
        if (loop := runs.get("simplified")) is not None:     # its model's state: q, qd and v
            terms = (qdd_d, gains.Kv * (qd_d - loop.qd), gains.Kp * (q_d - loop.q))
            e_v = e[2] + gains.Kv * e[1] + gains.Kp * e[0] + _GAMMA * sum(map(np.abs, terms))
            states.append(("closed loop of the simplified-model controller", "commanded |qdd|",
                           (loop.q, loop.qd, sum(terms)), (0.0, 0.0, (1 + _GAMMA) * e_v)))
        covers["reason"] = f"every set point, and at the {t.size} output times " + " and ".join(
            f"the {w} (q, |qd|, {a})" for w, a, *_ in states) + ", lie in the model's region"
        said = coverages(model, [Trajectory(t, *x) for _, _, x, _ in states], robot, model_file,
                         round_off=[err for *_, err in states])
        covers = next(({**d, "reason": f"the {who} is " + d["reason"].replace("|qdd|", qdd)}
                       for (who, qdd, *_), d in zip(states, said) if not d["covered"]), covers)
    noise, unmeasured = None, ""
    if "full" in runs and "simplified" in runs:
        try:
            noise, nfev = difference_noise(robot, model, gains, desired, t, runs, offset,
                                           rtol=rtol, atol=atol, method=method)
        except ValueError as err:       # the tighter runs did not finish: the rtol floor
            unmeasured = str(err)
    cost_figures = model_cost(model) if cost else None
    provenance = {
        "trajectory_file": Path(trajectory.source).name if trajectory.source else "",
        "trajectory_path": str(trajectory.source), "trajectory_sha256": trajectory.sha256,
        "trajectory_derivatives": trajectory.derivatives,
        "model_file": Path(model_file).name if model_file != "<in memory>" else model_file,
        "model_path": model_file, "model_sha256": model_sha,
        "model_trajectory_sha256": model.trajectory_sha256,
        "rtol": float(rtol), "atol": float(atol), "method": str(method),
        "grid_points": int(grid_points), "q0_offset": offset.tolist(),
        "t_end": float(t[-1]), "gravity_base": [float(v) for v in robot.gravity],
        "model": {**model_facts(model), "guarantee_covered": int(covers["covered"]),
                  "guarantee_coverage": covers["reason"]},  # desired motion and closed loop
        **({"noise_unmeasured": unmeasured} if unmeasured else {}),
    }
    if noise is not None:
        provenance.update(noise_rtol=float(rtol) / NOISE_TIGHTEN,
                          noise_atol=float(atol) / NOISE_TIGHTEN,
                          noise_factor=NOISE_FACTOR, noise_nfev=nfev)
    if verdict_tolerance is not None:
        provenance["verdict_tolerance"] = [float(v) for v in verdict_tolerance]
    return ControlResult(robot=robot, choices=dict(model.choices), gains=gains, t=t,
                         is_setpoint=is_set, q_d=q_d, qd_d=qd_d, qdd_d=qdd_d, runs=runs,
                         cost=cost_figures, provenance=provenance, tau_noise=noise)


def difference_noise(robot: Robot, model: SimplifiedModel, gains: Gains, desired: PPoly,
                     t: NDArray[np.float64], runs: dict[str, TrackingRun],
                     q0_offset: NDArray[np.float64], rtol: float = DEFAULT_RTOL,
                     atol: float = DEFAULT_ATOL, method: str = DEFAULT_METHOD
                     ) -> tuple[np.ndarray, int]:
    """Measured integrator noise of the closed-loop torque difference, simplified-model minus
    full-model computed torque.

    Parameters
    ----------
    robot : Robot
        The plant, n joints.
    model : SimplifiedModel
        The simplified model (the ``"simplified"`` controller).
    gains : Gains
        The gains of the runs.
    desired : scipy.interpolate.PPoly
        The desired motion (:func:`desired_motion`).
    t : ndarray, shape (M,)
        The sample times of the runs [s].
    runs : dict
        The ``"full"`` and ``"simplified"`` :class:`TrackingRun`
        at (rtol, atol).
    q0_offset : ndarray, shape (n,)
        Their initial position error [rad; m on a prismatic joint].
    rtol, atol : float, optional
        The runs' tolerances; the measuring runs use them over :data:`NOISE_TIGHTEN`.
    method : str, optional
        The ``solve_ivp`` method.

    Returns
    -------
    noise : ndarray, shape (n,)
        Per joint, the peak over the samples of |(tau_s - tau_f) - (tau_s' - tau_f')| [N m; N],
        primes for the runs at the tight tolerances.
    nfev : int
        Right-hand-side evaluations of the two measuring runs together.

    Raises
    ------
    ValueError
        If a measuring run does not finish (the message names the tolerance).

    Notes
    -----
    See the module docstring ("Integrator noise of the torque difference"). Source: the
    difference of two solutions at tolerances a factor 100 apart as the global error of the
    looser one, the usual check of an adaptive integrator's result (Hairer, Norsett & Wanner,
    *Solving ODEs I*, Ch. II).
    """
    tight = {}
    for name in ("full", "simplified"):
        try:
            tight[name] = track(robot, name, gains, desired, t, q0_offset=q0_offset,
                                choices=model, rtol=rtol / NOISE_TIGHTEN,
                                atol=atol / NOISE_TIGHTEN, method=method)
            if not tight[name].success:
                raise ValueError(f"the {name} controller's run failed: {tight[name].message}")
        except ValueError as err:
            raise ValueError(f"measuring the integrator noise (rtol = "
                             f"{rtol / NOISE_TIGHTEN:g}): {err}") from None
    loose, fine = (r["simplified"].tau - r["full"].tau for r in (runs, tight))
    return (np.nanmax(np.abs(loose - fine), axis=0),
            int(tight["full"].nfev + tight["simplified"].nfev))
