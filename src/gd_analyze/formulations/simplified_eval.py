"""A fused evaluator of the simplified G-D model that computes only the kept parts.

:meth:`gd_analyze.core.simplified.SimplifiedModel.torque` computes every G-D term with
:func:`~gd_analyze.core.dalembert.gd_terms` and then masks the parts it drops, so it costs as much
as the full model. Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) keeps the dominant parts "at a
reduced computation time"; :func:`simplified_tau` is the evaluator that delivers the reduction::

    tau_s = D_s qdd + h_s + c,   D_s = M_tran * D_tran + M_rot * D_rot,
                                 h_s = m_tran * h_tran + m_rot * h_rot          (Eq. 3.4-24)

It is one pass per set point (a numba kernel, :func:`simplified_kernel`, with the structure of
``gd_analyze.core.kernels``) that skips, from a plan made once per model:

- D_tran(i, j), Eq. (3.4-25) 2nd term: a_i . u_j + b_i . v_j (the Plücker form of
  :mod:`gd_analyze.core.kernels`) only for kept translational elements, the column sums
  u_j, v_j only for the columns they use and the mass moments only down to the first of them;
- D_rot(i, j), Eq. (3.4-25) 1st term: a_i . (Ic_j a_j) only for kept rotational elements, with
  Ic_j a_j formed once per column j (not once per element) and the base-frame inertias
  Ib_s = R_s I_s R_s^T only for the links that some kept rotational part needs;
- h_tran, Eq. (3.4-26): the outward recursion of the origin accelerations and the link forces
  only if some h element keeps its translational part, the inward moment sums only down to the
  first such joint;
- h_rot, Eq. (3.4-27): the link moments Ib_s wd_s + w_s x Ib_s w_s only from the first joint
  that keeps a rotational part down the chain; the velocity recursion is skipped if no h
  element is kept at all;
- c, Eq. (3.4-28), is always computed whole (the simplified model keeps gravity);
- the products D_s(i, j) qdd_j only for elements that are kept.

Operation counts use the project's counting scalar (:mod:`gd_analyze.formulations.opcount`): the kernel's
Python source (``simplified_kernel.py_func``) runs on one set point of
:class:`~gd_analyze.formulations.opcount.Counted` values, with the counting rule of that module, so the
counts cannot drift from the code that is timed.
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit

from ..core.kernels import body_frames_at, plucker_axes
from ..core.kinematics import as_states
from ..core.simplified import choice_masks

__all__ = ["simplified_kernel", "evaluation_plan", "full_choices", "simplified_tau",
           "count_simplified_operations", "evaluation_cost", "COST_SETPOINTS", "COST_REPEAT"]

#: Random set points per batched timing call of :func:`evaluation_cost`.
COST_SETPOINTS = 20000
#: Timed repetitions; the best (smallest) time is kept.
COST_REPEAT = 9


@njit(cache=True, fastmath=False, nogil=True)
def simplified_kernel(q, qd, qdd, Rp, tp, pris, mass, com, inertia, gravity,
                      keep_Dt, keep_Dr, keep_ht, keep_hr, need_uv, need_Icz,
                      s_rot0, s_m0, s_Ic0, jt0, jr0, tau):  # pragma: no cover - compiled
    """Fill tau (N, n) [N m] with the simplified model's torques, computing kept parts only.

    Parameters
    ----------
    q, qd, qdd : ndarray, shape (N, n)
        Joint positions [rad or m], velocities [rad/s or m/s] and accelerations [rad/s^2 or
        m/s^2].
    Rp : ndarray, shape (n, 3, 3)
        Placement rotations of the joints in the previous body frames.
    tp : ndarray, shape (n, 3)
        Placement translations [m].
    pris : ndarray of int, shape (n,)
        1 for a prismatic joint.
    mass : ndarray, shape (n,)
        Link masses [kg].
    com : ndarray, shape (n, 3)
        Centres of mass in the body frames [m].
    inertia : ndarray, shape (n, 3, 3)
        Inertia tensors about the centres of mass, body-frame axes [kg m^2].
    gravity : ndarray, shape (3,)
        Gravity in the base frame [m/s^2].
    keep_Dt, keep_Dr : ndarray of int, shape (n, n)
        1 where D_tran(i, j), D_rot(i, j) is kept (upper triangle i <= j is read).
    keep_ht, keep_hr : ndarray of int, shape (n,)
        1 where h_tran(i), h_rot(i) is kept.
    need_uv : ndarray of int, shape (n,)
        1 for the columns j whose translational sums u_j, v_j a kept D_tran element uses.
    need_Icz : ndarray of int, shape (n,)
        1 for the columns j whose Ic_j a_j is used by a kept D_rot element.
    s_rot0, s_m0, s_Ic0, jt0, jr0 : int
        First link whose Ib_s is needed, first column needing the mass moments, first column
        needing Ic_j, first joint keeping h_tran, first joint keeping h_rot (n for none).
    tau : ndarray, shape (N, n)
        Output, overwritten.

    Notes
    -----
    Eqs. (3.4-24) to (3.4-28) of Fu, Gonzalez & Lee (1987) in the Plücker form of
    :mod:`gd_analyze.core.kernels` (same kinematics and recursions), kept parts only.
    """
    N, n = q.shape
    R = np.empty((n, 3, 3))
    o = np.empty((n, 3))
    rbar = np.empty((n, 3))
    Ib = np.empty((n, 3, 3))
    F = np.empty((n, 3))
    f = np.empty((n, 3))
    A = np.empty((n, 3))
    B = np.empty((n, 3))
    U = np.empty((n, 3))
    V = np.empty((n, 3))
    W = np.empty((n, 3))
    M = np.empty((3, 3))
    tmp = np.empty((3, 3))
    ht = np.empty(n)
    hr = np.empty(n)
    cg = np.empty(n)
    need_vel = jt0 < n or jr0 < n
    for k in range(N):
        body_frames_at(q, k, Rp, tp, pris, com, M, R, o, rbar)
        # base-frame inertia tensors, only for the links a kept rotational part needs
        for s in range(s_rot0, n):
            for r in range(3):
                for u in range(3):
                    tmp[r, u] = (R[s, r, 0] * inertia[s, 0, u] + R[s, r, 1] * inertia[s, 1, u]
                                 + R[s, r, 2] * inertia[s, 2, u])
            for r in range(3):
                for u in range(r, 3):
                    v = tmp[r, 0] * R[s, u, 0] + tmp[r, 1] * R[s, u, 1] + tmp[r, 2] * R[s, u, 2]
                    Ib[s, r, u] = v
                    Ib[s, u, r] = v
        # outward recursion (qdd = 0), only if some h element is kept
        if need_vel:
            wx = wy = wz = 0.0
            ex = ey = ez = 0.0          # dJw/dt qd
            ax = ay = az = 0.0          # acceleration of the origin o_s
            for s in range(n):
                zx, zy, zz = R[s, 0, 2], R[s, 1, 2], R[s, 2, 2]
                if jt0 < n:
                    if s == 0:
                        vx, vy, vz = o[0, 0], o[0, 1], o[0, 2]
                    else:
                        vx = o[s, 0] - o[s - 1, 0]
                        vy = o[s, 1] - o[s - 1, 1]
                        vz = o[s, 2] - o[s - 1, 2]
                    cx = wy * vz - wz * vy
                    cy = wz * vx - wx * vz
                    cz = wx * vy - wy * vx
                    ax += ey * vz - ez * vy + wy * cz - wz * cy
                    ay += ez * vx - ex * vz + wz * cx - wx * cz
                    az += ex * vy - ey * vx + wx * cy - wy * cx
                    if pris[s] != 0:
                        u2 = 2.0 * qd[k, s]
                        ax += u2 * (wy * zz - wz * zy)
                        ay += u2 * (wz * zx - wx * zz)
                        az += u2 * (wx * zy - wy * zx)
                if pris[s] == 0:
                    ux, uy, uz = qd[k, s] * zx, qd[k, s] * zy, qd[k, s] * zz
                    ex += wy * uz - wz * uy
                    ey += wz * ux - wx * uz
                    ez += wx * uy - wy * ux
                    wx += ux
                    wy += uy
                    wz += uz
                if jt0 < n and s >= jt0:
                    vx, vy, vz = rbar[s, 0] - o[s, 0], rbar[s, 1] - o[s, 1], rbar[s, 2] - o[s, 2]
                    cx = wy * vz - wz * vy
                    cy = wz * vx - wx * vz
                    cz = wx * vy - wy * vx
                    F[s, 0] = mass[s] * (ax + ey * vz - ez * vy + wy * cz - wz * cy)
                    F[s, 1] = mass[s] * (ay + ez * vx - ex * vz + wz * cx - wx * cz)
                    F[s, 2] = mass[s] * (az + ex * vy - ey * vx + wx * cy - wy * cx)
                if s >= jr0:
                    Iwx = Ib[s, 0, 0] * wx + Ib[s, 0, 1] * wy + Ib[s, 0, 2] * wz
                    Iwy = Ib[s, 1, 0] * wx + Ib[s, 1, 1] * wy + Ib[s, 1, 2] * wz
                    Iwz = Ib[s, 2, 0] * wx + Ib[s, 2, 1] * wy + Ib[s, 2, 2] * wz
                    f[s, 0] = (Ib[s, 0, 0] * ex + Ib[s, 0, 1] * ey + Ib[s, 0, 2] * ez
                               + wy * Iwz - wz * Iwy)
                    f[s, 1] = (Ib[s, 1, 0] * ex + Ib[s, 1, 1] * ey + Ib[s, 1, 2] * ez
                               + wz * Iwx - wx * Iwz)
                    f[s, 2] = (Ib[s, 2, 0] * ex + Ib[s, 2, 1] * ey + Ib[s, 2, 2] * ez
                               + wx * Iwy - wy * Iwx)
        plucker_axes(R, o, pris, A, B)
        # inward suffix sums: gravity (all joints), kept h parts, the column sums kept D uses
        Mx = My = Mz = Sx = Sy = Sz = 0.0
        Gx = Gy = Gz = Tx = Ty = Tz = 0.0
        fx = fy = fz = 0.0
        ms = px = py = pz = 0.0
        q00 = q11 = q22 = q01 = q02 = q12 = 0.0
        i00 = i11 = i22 = i01 = i02 = i12 = 0.0
        for j in range(n - 1, -1, -1):
            rx, ry, rz = rbar[j, 0], rbar[j, 1], rbar[j, 2]
            ax_, ay_, az_ = A[j, 0], A[j, 1], A[j, 2]
            bx, by, bz = B[j, 0], B[j, 1], B[j, 2]
            mgx, mgy, mgz = mass[j] * gravity[0], mass[j] * gravity[1], mass[j] * gravity[2]
            Gx += ry * mgz - rz * mgy
            Gy += rz * mgx - rx * mgz
            Gz += rx * mgy - ry * mgx
            Tx += mgx
            Ty += mgy
            Tz += mgz
            cg[j] = -(ax_ * Gx + ay_ * Gy + az_ * Gz + bx * Tx + by * Ty + bz * Tz)
            if j >= jt0:
                Mx += ry * F[j, 2] - rz * F[j, 1]
                My += rz * F[j, 0] - rx * F[j, 2]
                Mz += rx * F[j, 1] - ry * F[j, 0]
                Sx += F[j, 0]
                Sy += F[j, 1]
                Sz += F[j, 2]
                if keep_ht[j] != 0:
                    ht[j] = ax_ * Mx + ay_ * My + az_ * Mz + bx * Sx + by * Sy + bz * Sz
            if j >= jr0:
                fx += f[j, 0]
                fy += f[j, 1]
                fz += f[j, 2]
                if keep_hr[j] != 0:
                    hr[j] = ax_ * fx + ay_ * fy + az_ * fz
            if j >= s_m0:
                mx, my, mz = mass[j] * rx, mass[j] * ry, mass[j] * rz
                ms += mass[j]
                px += mx
                py += my
                pz += mz
                q00 += mx * rx
                q11 += my * ry
                q22 += mz * rz
                q01 += mx * ry
                q02 += mx * rz
                q12 += my * rz
                if need_uv[j] != 0:
                    tr = q00 + q11 + q22
                    U[j, 0] = (tr - q00) * ax_ - q01 * ay_ - q02 * az_ - (by * pz - bz * py)
                    U[j, 1] = (tr - q11) * ay_ - q01 * ax_ - q12 * az_ - (bz * px - bx * pz)
                    U[j, 2] = (tr - q22) * az_ - q02 * ax_ - q12 * ay_ - (bx * py - by * px)
                    V[j, 0] = ms * bx - (py * az_ - pz * ay_)
                    V[j, 1] = ms * by - (pz * ax_ - px * az_)
                    V[j, 2] = ms * bz - (px * ay_ - py * ax_)
            if j >= s_Ic0:
                i00 += Ib[j, 0, 0]
                i11 += Ib[j, 1, 1]
                i22 += Ib[j, 2, 2]
                i01 += Ib[j, 0, 1]
                i02 += Ib[j, 0, 2]
                i12 += Ib[j, 1, 2]
                if need_Icz[j] != 0:
                    W[j, 0] = i00 * ax_ + i01 * ay_ + i02 * az_
                    W[j, 1] = i01 * ax_ + i11 * ay_ + i12 * az_
                    W[j, 2] = i02 * ax_ + i12 * ay_ + i22 * az_
        # tau = c + h_s + D_s qdd, kept parts only; D_s symmetric, each element formed once
        for i in range(n):
            ti = cg[i]
            if keep_ht[i] != 0:
                ti = ti + ht[i]
            if keep_hr[i] != 0:
                ti = ti + hr[i]
            tau[k, i] = ti
        for i in range(n):
            for j in range(i, n):
                kt = keep_Dt[i, j] != 0
                kr = keep_Dr[i, j] != 0
                if not (kt or kr):
                    continue
                Dij = 0.0
                if kt:
                    Dij = (A[i, 0] * U[j, 0] + A[i, 1] * U[j, 1] + A[i, 2] * U[j, 2]
                           + B[i, 0] * V[j, 0] + B[i, 1] * V[j, 1] + B[i, 2] * V[j, 2])
                if kr:
                    Dij = Dij + (A[i, 0] * W[j, 0] + A[i, 1] * W[j, 1] + A[i, 2] * W[j, 2])
                tau[k, i] += Dij * qdd[k, j]
                if i != j:
                    tau[k, j] += Dij * qdd[k, i]


def full_choices(n):
    """Choices that keep every part of every element: the full model.

    Parameters
    ----------
    n : int
        Number of joints.

    Returns
    -------
    dict
        ``{"D11": "both", ..., "hn": "both"}``.
    """
    from ..core.ranking import element_labels

    return {label: "both" for label in element_labels(n)}


def evaluation_plan(choices, n):
    """What :func:`simplified_kernel` must compute for a set of choices (once per model).

    Parameters
    ----------
    choices : dict
        Element label (``"D11"`` .. ``"Dnn"``, ``"h1"`` .. ``"hn"``) -> ``"tran"``, ``"rot"``,
        ``"both"`` or ``"none"``.
    n : int
        Number of joints.

    Returns
    -------
    dict
        The kernel's structural arguments: ``keep_Dt``, ``keep_Dr`` (n, n), ``keep_ht``,
        ``keep_hr``, ``need_uv``, ``need_Icz`` (n,), all int64 0/1, and the ints ``s_rot0``,
        ``s_m0``, ``s_Ic0``, ``jt0``, ``jr0`` (n meaning "none").

    Raises
    ------
    ValueError
        As :func:`gd_analyze.core.simplified.choice_masks`.
    """
    Mt, Mr, mt, mr = choice_masks(choices, n)
    keep_Dt = np.triu(Mt).astype(np.int64)
    keep_Dr = np.triu(Mr).astype(np.int64)
    keep_ht, keep_hr = mt.astype(np.int64), mr.astype(np.int64)
    need_uv = keep_Dt.any(axis=0).astype(np.int64)       # columns j of kept D_tran(i, j)
    need_Icz = keep_Dr.any(axis=0).astype(np.int64)

    def first(flags):
        idx = np.flatnonzero(flags)
        return int(idx[0]) if idx.size else n

    s_m0, s_Ic0, jt0, jr0 = first(need_uv), first(need_Icz), first(keep_ht), first(keep_hr)
    return {"keep_Dt": keep_Dt, "keep_Dr": keep_Dr, "keep_ht": keep_ht, "keep_hr": keep_hr,
            "need_uv": need_uv, "need_Icz": need_Icz, "s_rot0": min(s_Ic0, jr0),
            "s_m0": s_m0, "s_Ic0": s_Ic0, "jt0": jt0, "jr0": jr0}


_PLAN_ORDER = ("keep_Dt", "keep_Dr", "keep_ht", "keep_hr", "need_uv", "need_Icz", "s_rot0",
               "s_m0", "s_Ic0", "jt0", "jr0")


def _robot_args(robot):
    from ..core.dalembert import kernel_arguments

    return kernel_arguments(robot)


def simplified_tau(robot, choices, q, qd, qdd, plan=None):
    """Torques of the simplified model, computing only the parts it keeps.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    choices : dict
        Element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"`` (as in
        ``simplified_model.json``).
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s].
    qdd : array_like, shape (N, n) or (n,)
        Joint accelerations [rad/s^2].
    plan : dict, optional
        :func:`evaluation_plan` of the choices, to skip rebuilding it on repeated calls.

    Returns
    -------
    ndarray, shape (N, n)
        tau_s = D_s qdd + h_s + c [N m], equal to
        :meth:`~gd_analyze.core.simplified.SimplifiedModel.torque` up to rounding.

    Raises
    ------
    ValueError
        If the arrays do not have n columns or disagree on N, or a choice is missing or
        invalid.

    Notes
    -----
    Source: Eq. (3.4-24) with the parts of Eqs. (3.4-25) to (3.4-28) the model keeps (Fu,
    Gonzalez & Lee 1987, Sec. 3.4.1). Gravity c is always computed whole.
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    if plan is None:
        plan = evaluation_plan(choices, robot.n)
    tau = np.empty(q.shape)
    c = np.ascontiguousarray
    simplified_kernel(c(q), c(qd), c(qdd), *_robot_args(robot),
                      *(plan[key] for key in _PLAN_ORDER), tau)
    return tau


def count_simplified_operations(robot, choices, q=None, qd=None, qdd=None):
    """Multiplications and additions of one set point of :func:`simplified_tau`.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    choices : dict
        Element label -> kept part; :func:`full_choices` counts the full model in the same
        evaluator.
    q, qd, qdd : array_like, shape (n,), optional
        The set point [rad], [rad/s], [rad/s^2]; random if omitted (the counts depend only on
        n and the choices).

    Returns
    -------
    OpCount
        ``multiplications``, ``additions`` (int) and ``tau`` (ndarray, shape (n,)) [N m], the
        torques the counted run computed.

    Raises
    ------
    ValueError
        If a state does not have shape (n,) or a choice is invalid.

    Notes
    -----
    The counting rule is that of :mod:`gd_analyze.formulations.opcount` (used for
    :func:`~gd_analyze.formulations.opcount.count_operations`): sines and cosines of theta_i are inputs,
    operations on robot parameters only are free, exact 0 and 1 structural constants are
    free. The Python source of :func:`simplified_kernel` runs on counting scalars, as
    ``count_operations(robot, "gd")`` runs the compiled G-D engine's.
    """
    from .counting import OpLedger, _consts, _value, _vars, counting_clone
    from .opcount import OpCount

    n = robot.n
    rng = np.random.default_rng(1)
    q, qd, qdd = (rng.uniform(-1, 1, n) if x is None else x for x in (q, qd, qdd))
    q, qd, qdd = (x[0] for x in as_states(robot, q, qd, qdd))
    plan = evaluation_plan(choices, n)
    kernel = counting_clone(simplified_kernel)
    led = OpLedger()
    tau = np.zeros((1, n), dtype=object)
    # q is the input: cos q and sin q are not counted (the rule)
    Rp, tp, pris, mass, com, inertia, gravity = _robot_args(robot)
    kernel(_vars(led, q)[None], _vars(led, qd)[None], _vars(led, qdd)[None],
           _consts(led, Rp), _consts(led, tp), pris, _consts(led, mass), _consts(led, com),
           _consts(led, inertia), _consts(led, gravity),
           *(plan[key] for key in _PLAN_ORDER), tau)
    return OpCount(int(led.multiplications), int(led.additions),
                   np.array([_value(t) for t in tau[0]]))


def _best_times(fns, repeat):
    """Smallest wall time of each function over ``repeat`` rounds, the calls interleaved so that
    a change in machine load affects every function alike."""
    best = [np.inf] * len(fns)
    for _ in range(max(1, int(repeat))):
        for k, fn in enumerate(fns):
            t0 = time.perf_counter()
            fn()
            best[k] = min(best[k], time.perf_counter() - t0)
    return best


def evaluation_cost(model, setpoints=COST_SETPOINTS, repeat=COST_REPEAT, seed=0):
    """Cost per set point of the simplified model against the full model.

    Three evaluators of tau at one set point are compared:

    - ``full_gd_terms``: the project's full model, ``gd_terms(engine="compiled")`` then
      ``GDTerms.tau`` (counted with ``count_operations(robot, "gd")``);
    - ``full_fused``: :func:`simplified_tau` with every part kept (:func:`full_choices`), the
      same code as the simplified evaluator, so the difference to it is due to the dropped
      parts alone;
    - ``simplified``: :func:`simplified_tau` with the model's choices.

    Parameters
    ----------
    model : SimplifiedModel
        The simplified model (its robot and choices).
    setpoints : int, optional
        Random set points per batched call for the timing.
    repeat : int, optional
        Timed calls per evaluator; the smallest time is kept.
    seed : int, optional
        Seed of the random states (q in [-pi, pi] rad, qd, qdd in [-3, 3]).

    Returns
    -------
    dict
        ``evaluators`` (list of the three names), ``multiplications``, ``additions`` (lists of
        int per set point), ``time_per_setpoint_us`` (list of float [us], batched), ``dropped``
        (number of parts dropped out of 2 (n (n + 1) / 2 + n)), ``setpoints`` and ``repeat``.

    Raises
    ------
    ValueError
        If the model's choices are invalid.

    Notes
    -----
    Times are wall-clock, single thread, after a warm-up call (numba compilation excluded),
    the smallest of ``repeat`` interleaved rounds; they depend on the machine and its load, the
    counts do not.
    """
    from ..core.dalembert import gd_terms
    from .opcount import count_operations

    robot = model.robot
    n = robot.n
    full = full_choices(n)
    counts = [count_operations(robot, "gd")[:2],
              count_simplified_operations(robot, full)[:2],
              count_simplified_operations(robot, model.choices)[:2]]
    rng = np.random.default_rng(seed)
    N = max(1, int(setpoints))
    q = rng.uniform(-np.pi, np.pi, (N, n))
    qd, qdd = rng.uniform(-3, 3, (N, n)), rng.uniform(-3, 3, (N, n))
    plan_full = evaluation_plan(full, n)
    plan_s = evaluation_plan(model.choices, n)
    fns = [lambda: gd_terms(robot, q, qd, engine="compiled").tau(qdd),
           lambda: simplified_tau(robot, full, q, qd, qdd, plan=plan_full),
           lambda: simplified_tau(robot, model.choices, q, qd, qdd, plan=plan_s)]
    for fn in fns:       # warm-up: numba compilation or cache load
        fn()
    times = [t / N * 1e6 for t in _best_times(fns, repeat)]
    Mt, Mr, mt, mr = choice_masks(model.choices, n)
    parts = 2 * (n * (n + 1) // 2 + n)
    kept = int(np.triu(Mt).sum() + np.triu(Mr).sum() + mt.sum() + mr.sum())
    return {"evaluators": ["full_gd_terms", "full_fused", "simplified"],
            "multiplications": [int(c[0]) for c in counts],
            "additions": [int(c[1]) for c in counts],
            "time_per_setpoint_us": [float(t) for t in times],
            "dropped": parts - kept, "parts": parts,
            "setpoints": N, "repeat": int(repeat)}
