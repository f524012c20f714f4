"""Computed-torque and PD + gravity control of the full-model arm: gains, desired motion,
control laws and the closed-loop integration (one controller at a time).

The plant is the arm with its full G-D dynamics, Eq. (3.4-24) of Fu, Gonzalez & Lee (1987),
integrated with ``scipy.integrate.solve_ivp``; :func:`gd_analyze.jobs.control.run_control`
runs the three controllers side by side and collects the result. The control laws and the gains
are described in :mod:`gd_analyze.jobs.control`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..dynamics.dalembert import gd_terms, one_state_terms, qdd_from_terms
from ..model.drives import COULOMB_BAND, friction_torque
from ..ranking.labels import element_units

if TYPE_CHECKING:
    from scipy.interpolate import PPoly

    from ..dynamics.dalembert import GDTerms
    from ..model.robot import Robot
    from ..simplify.simplified import SimplifiedModel
    from ..trajectory.trajectory import Trajectory


__all__ = ["CONTROLLERS", "CONTROLLER_DESCRIPTIONS", "DEFAULT_WN", "DEFAULT_ZETA", "GAIN_RANGES",
           "DEFAULT_RTOL", "DEFAULT_ATOL", "DEFAULT_METHOD", "MAX_STIFFNESS_STEPS",
           "MAX_RHS_EVALS", "DENSE_SETPOINTS", "RHS_PER_STEP", "closed_loop_rates",
           "singular_inertia", "Gains", "control_gains", "desired_motion",
           "controller_torque", "TrackingRun", "track"]


#: The controllers compared, in table order.
CONTROLLERS = ("full", "simplified", "pd_gravity")


#: One line per controller, for tables and the dataset.
CONTROLLER_DESCRIPTIONS = {
    "full": "computed torque, full G-D model: D v + h + c",
    "simplified": "computed torque, simplified model: D_s v + h_s + c",
    "pd_gravity": "PD + gravity compensation: Kp_pd e + Kv_pd ed + c",
}


#: Default undamped natural frequency of the error dynamics [rad/s].
DEFAULT_WN = 20.0


#: Default damping ratio (critical damping).
DEFAULT_ZETA = 1.0


#: The natural frequency wn [rad/s] and damping ratio zeta [1] accepted, by the command line's
#: --wn and --zeta and :func:`gd_analyze.jobs.control.run_control` alike: below 0.01 rad/s an
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
    names = robot.metadata.get("urdf_joints") or ()
    name = f"joint {j + 1}" + (f" ({str(names[j])!r})" if j < len(names) else "")
    units = element_units("D", j, j, robot.prismatic)
    return (f"the inertia matrix D is singular at set point {k + 1}: {name} has "
            f"D_{j + 1}{j + 1} = {float(D[k, j, j]):.3g} {units.replace('m2', 'm^2')} (of "
            f"largest eigenvalue {float(big[k]):.3g}): no inertia moves with it, so the arm "
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

    def to_dict(self) -> dict[str, Any]:
        """The gains as lists of floats.

        Returns
        -------
        dict
            ``wn``, ``zeta``, ``Kp``, ``Kv``, ``inertia_scale``, ``Kp_pd``, ``Kv_pd``.
        """
        return {f.name: [float(v) for v in getattr(self, f.name)] for f in fields(self)}


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
    coeffs = []
    for j in range(trajectory.q.shape[1]):
        yi = np.column_stack([trajectory.q[:, j], trajectory.qd[:, j], trajectory.qdd[:, j]])
        coeffs.append(PPoly.from_bernstein_basis(BPoly.from_derivatives(t, yi)).c)
    return PPoly(np.stack(coeffs, axis=-1), t)


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
    if controller == "pd_gravity":
        if terms is None:
            terms = gd_terms(robot, q, qd)
        return gains.Kp_pd * e + gains.Kv_pd * ed + terms.c
    v = qdd_d + gains.Kv * ed + gains.Kp * e
    if controller == "full":
        if terms is None:
            terms = gd_terms(robot, q, qd)
        return terms.tau(v)
    if choices is None or not hasattr(choices, "torque"):
        raise ValueError("the simplified controller needs the simplified model")
    return (model_torque or choices.torque)(q, qd, v)


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
