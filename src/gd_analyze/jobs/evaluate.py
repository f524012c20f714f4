"""Evaluate a simplified model on a trajectory: its torque error against the full model.

``gd-analyze evaluate MODEL.json TRAJECTORY.csv`` checks a model made on one trajectory along
another, optionally with the arm carrying a load the model does not know. Source: Sec. 3.4.1 of
Fu, Gonzalez & Lee (1987), whose simplified model "depends on the specific trajectory being
considered"; terms from Eqs. (3.4-24) to (3.4-28).

The gate: by default the model's own promise, |tau_s - tau| <= EPS s_i on every
joint with s_i the scale of its guarantee (:class:`~gd_analyze.simplify.guarantee.Guarantee`);
``--max-error REL`` replaces it by a relative error. Round-off
(:func:`~gd_analyze.ranking.ranking.is_round_off`) passes; NaN or inf never does.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.dalembert import gd_terms
from ..errors import InputError
from ..model.limits import check_finite
from ..ranking.labels import joint_torque_units
from ..ranking.ranking import arm_scales, is_round_off
from ..simplify.guarantee import within_bound
from ..simplify.simplified import parameters_sha256
from ..simplify.torque_error import TorqueErrorAccumulator
from ..store.model_trust import check_guarantee

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import ArrayLike, NDArray

    from ..model.robot import Robot
    from ..simplify.simplified import SimplifiedModel
    from ..trajectory.trajectory import Trajectory

__all__ = ["evaluate", "model_torque", "model_scale", "coverage", "coverages", "gate",
           "round_off", "check_trajectory_claim", "TRAJECTORY_SCALE_RTOL"]


def model_torque(model: SimplifiedModel, q: NDArray[np.float64], qd: NDArray[np.float64],
                 qdd: NDArray[np.float64], first: int = 0) -> np.ndarray:
    """A simplified model's torques, refused where they are not finite.

    Parameters
    ----------
    model : SimplifiedModel
        The model (e.g. read from a hand-edited file).
    q, qd, qdd : ndarray, shape (N, n)
        Set points [rad, rad/s, rad/s^2].
    first : int, optional
        The index of the first set point in the trajectory (a block of it), for the message.

    Returns
    -------
    ndarray, shape (N, n)
        tau_s [N m], all finite.

    Raises
    ------
    InputError
        If a torque is NaN or inf: the model's coefficients (``explicit_terms.coef``) are
        beyond the range of a float once multiplied out (a coefficient of 1e308, say).

    Notes
    -----
    Source: the simplified model tau_s = D_s qdd + h_s + c of Fu, Gonzalez & Lee (1987),
    Sec. 3.4.1, Eq. (3.4-24).
    """
    with np.errstate(over="ignore", invalid="ignore"):
        tau = np.asarray(model.torque(q, qd, qdd), float)
    bad = ~np.isfinite(tau)
    if bad.any():
        k, j = (int(v[0]) for v in np.nonzero(bad))
        raise InputError(f"the model's torque is not finite at set point {first + k + 1}, "
                         f"joint {j + 1}: "
                         "its explicit_terms.coef are beyond the range of a float")
    return tau


#: Set points per block where a model's torques are compared with the full model's along a
#: trajectory (:func:`evaluate`, :func:`check_trajectory_claim`): memory stays a few blocks.
EVALUATE_BLOCK = 8192


def _torque_errors(model, trajectory, plant):
    """The model's torque error against the plant's full torque (G-D terms, Eq. (3.4-24))
    along the trajectory, block by block: a :class:`TorqueErrorAccumulator`."""
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    errors = TorqueErrorAccumulator(plant.n)
    for a in range(0, q.shape[0], EVALUATE_BLOCK):
        b = slice(a, a + EVALUATE_BLOCK)
        tau = check_finite("tau", gd_terms(plant, q[b], qd[b]).tau(qdd[b]), first=a)
        errors.update(model_torque(model, q[b], qd[b], qdd[b], first=a), tau)
    return errors


def evaluate(model: SimplifiedModel, trajectory: Trajectory,
             plant: Robot | None = None) -> dict[str, Any]:
    """The torque error of a simplified model along a trajectory.

    Parameters
    ----------
    model : SimplifiedModel
        The model (its robot and its explicit kept terms, evaluated by
        :meth:`~gd_analyze.simplify.simplified.SimplifiedModel.torque`).
    trajectory : Trajectory
        q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2].
    plant : Robot, optional
        The arm that really moves (e.g. the model's robot carrying a payload, see
        :func:`gd_analyze.model.robot.with_payload`); default the model's robot.

    Returns
    -------
    dict
        :func:`gd_analyze.simplify.simplified.torque_error` of the model's torque against the
        plant's full torque (per joint ``peak_abs_error``, ``rms_error``, ``peak_tau`` [N m],
        ``relative_peak_error``, ``relative_rms_error``), with ``scale``, the model's s_i
        (:func:`model_scale`; None without one), ``relative_to`` per joint (``"peak |tau|"``;
        ``"s_i"`` where the reference torque is 0 along the trajectory; ``"none"`` where s_i is
        0 or unknown too: the relative error is then 0 for round-off, else inf, never 0/0), and
        ``max_relative_peak_error``, the largest relative peak error over the joints.

    Raises
    ------
    ValueError
        If the trajectory does not have n columns.
    InputError
        If the torques are not finite (inputs beyond :data:`gd_analyze.model.limits.LIMITS`, or
        the model's coefficients beyond a float: :func:`model_torque`).
    """
    robot: Robot = model.robot
    err = _torque_errors(model, trajectory, robot if plant is None else plant).result()
    peak, rms = (np.asarray(err[k], float) for k in ("peak_abs_error", "rms_error"))
    peak_tau = np.asarray(err["peak_tau"], float)
    scale = model_scale(model)
    s = np.zeros(robot.n) if scale is None else scale
    denominator = np.where(peak_tau > 0, peak_tau, np.where(s > 0, s, 0.0))
    off = round_off(peak, denominator, np.maximum(peak_tau, s), robot)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(denominator > 0, peak / denominator, np.where(off, 0.0, np.inf))
        rel_rms = np.where(denominator > 0, rms / denominator, np.where(off, 0.0, np.inf))
    err.update(relative_peak_error=rel.tolist(), relative_rms_error=rel_rms.tolist(),
               relative_to=["peak |tau|" if p > 0 else "s_i" if v > 0 else "none"
                            for p, v in zip(peak_tau, s)],
               scale=None if scale is None else scale.tolist(),
               max_relative_peak_error=float(rel.max(initial=0.0)))
    return err


def round_off(peak: ArrayLike, scale: ArrayLike, arm: ArrayLike, robot: Robot) -> np.ndarray:
    """Per joint, whether an error is round-off of its scale or of the arm's largest scale in
    the same units (:func:`~gd_analyze.ranking.ranking.is_round_off`).

    Parameters
    ----------
    peak, scale, arm : array_like, shape (n,) or (K, n)
        Peak errors, their scales and the torques whose largest per unit is the arm's scale
        [N m or N].
    robot : Robot
        The arm, n joints (the joints' units).

    Returns
    -------
    ndarray of bool, shape of ``peak``
    """
    units = [joint_torque_units(bool(p)) for p in robot.prismatic]
    return np.asarray(is_round_off(peak, scale, arm_scale=arm_scales(arm, units)), bool)


def model_scale(model: SimplifiedModel) -> np.ndarray | None:
    """The model's scale s_i per joint: what its tolerance is relative to.

    Parameters
    ----------
    model : SimplifiedModel

    Returns
    -------
    ndarray, shape (n,), or None
        The guarantee's ``scale`` [N m or N]; for a model without a guarantee (chapter rule,
        older files), max(peak |tau_i| on the trajectory it was built on, torque floor) from
        its ``validation``; None if it records neither.
    """
    if model.guarantee is not None:
        return np.asarray(model.guarantee.scale, float)
    peak = np.array((model.validation or {}).get("peak_tau") or [], float)    # null: NaN
    return np.maximum(peak, float(model.torque_floor)) if peak.shape == (model.robot.n,) else None


def coverage(model: SimplifiedModel, trajectory: Trajectory, plant: Robot | None = None,
             path: str = "<model>") -> dict[str, Any]:
    """Whether the model's guarantee covers a trajectory, and its scope in words.

    Parameters
    ----------
    model : SimplifiedModel
    trajectory : Trajectory
        q, qd, qdd (N, n) and the file's ``sha256``.
    plant : Robot, optional
        The reference arm; a guarantee holds for the model's own robot only (not with a
        payload or another mounting).
    path : str, optional
        The model file, for messages.

    Returns
    -------
    dict
        ``kind`` (``"region"``, ``"trajectory"`` or None without a guarantee), ``statement``
        (:meth:`~gd_analyze.simplify.simplified.SimplifiedModel.scope`), ``covered``
        (bool) and ``reason`` (a clause, :meth:`~gd_analyze.simplify.guarantee.Guarantee.covers`).

    Raises
    ------
    InputError
        For a region guarantee that does not hold for the model's robot
        (:func:`gd_analyze.store.model_trust.check_guarantee`, also for a model built in memory);
        for a trajectory-kind guarantee on the very trajectory it was built on (same
        SHA-256), when its claim does not hold there, measured again
        (:func:`check_trajectory_claim`): one line naming the key, e.g. ``guarantee.bound``.
    """
    return coverages(model, [trajectory], plant, path)[0]


def coverages(model: SimplifiedModel, trajectories: Sequence[Trajectory],
              plant: Robot | None = None, path: str = "<model>",
              round_off: Sequence[Sequence[ArrayLike]] | None = None) -> list[dict[str, Any]]:
    """:func:`coverage` of each of several trajectories, the model's claim checked once.

    Parameters
    ----------
    model : SimplifiedModel
    trajectories : sequence of Trajectory
        K trajectories, each q, qd, qdd (N_k, n) and its file's ``sha256``.
    plant : Robot, optional
        The reference arm, as :func:`coverage` takes it.
    path : str, optional
        The model file, for messages.
    round_off : sequence of K sequences of 3 array_like, optional
        Per trajectory, bounds on the round-off of its q, qd and qdd, each broadcastable to
        (N_k, n) (:meth:`~gd_analyze.simplify.guarantee.Guarantee.covers`); default: the
        set points are data, as given.

    Returns
    -------
    list of dict
        K dicts, each as :func:`coverage` returns it, in the trajectories' order.

    Raises
    ------
    InputError
        As :func:`coverage`: a region claim that does not hold for the model's robot (checked
        once, before any trajectory), or a trajectory-kind claim that does not hold on its own
        trajectory.
    """
    g = model.guarantee
    out = {"kind": None if g is None else g.kind, "statement": model.scope()}
    if g is None:
        return [{**out, "covered": False, "reason": "the model carries no guarantee"}
                for _ in trajectories]
    if g.kind == "region":  # a model built in memory, or read: checked
        check_guarantee(model, path)        # (once per certification and process)
    robot: Robot = model.robot
    if plant is not None and plant is not robot and \
            parameters_sha256(plant.to_dict()) != parameters_sha256(robot.to_dict()):
        return [{**out, "covered": False,
                 "reason": "the reference arm is not the model's robot (a payload or another "
                           "mounting): the guarantee is for the model's own robot"}
                for _ in trajectories]
    # a revolute joint without limits, or with more than a turn, has the full circle
    # [-pi, pi] in the region (certify.region): its q counts modulo 2 pi
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    with np.errstate(invalid="ignore"):
        continuous = ~np.asarray(robot.prismatic, bool) & (
            ~(np.isfinite(lo) & np.isfinite(hi)) | (hi - lo > 2 * np.pi))
    said = []
    for trajectory, err in zip(trajectories, round_off or [(0.0, 0.0, 0.0)] * len(trajectories)):
        covered, reason = g.covers(trajectory.q, trajectory.qd, trajectory.qdd,
                                   trajectory_sha256=trajectory.sha256, continuous=continuous,
                                   prismatic=robot.prismatic, round_off=err)
        if covered and g.kind == "trajectory":
            check_trajectory_claim(model, trajectory, path)
        said.append({**out, "covered": bool(covered), "reason": reason})
    return said


#: A trajectory model's s_i must equal max(peak |tau_i|, torque floor) on its trajectory, to
#: this share of s_i (plus the round-off allowance of
#: :func:`~gd_analyze.simplify.guarantee.within_bound`) [1].
TRAJECTORY_SCALE_RTOL = 1e-9


def check_trajectory_claim(model: SimplifiedModel, trajectory: Trajectory,
                           path: str = "<model>") -> None:
    """Refuse a trajectory-kind guarantee that does not hold on its own trajectory.

    Parameters
    ----------
    model : SimplifiedModel
        With a guarantee of kind ``"trajectory"``.
    trajectory : Trajectory
        The file the model was built on (its SHA-256 is the guarantee's): q, qd, qdd of shape
        (N, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    path : str, optional
        The model file, for messages.

    Raises
    ------
    InputError
        One line naming the key: ``guarantee.bound`` where the model's peak |tau_s - tau|,
        measured again against the model's robot, exceeds the stored bound (up to round-off,
        :func:`~gd_analyze.simplify.guarantee.within_bound`, and an error that is
        round-off of its torque passes, as in :func:`gate`); ``guarantee.scale`` (a
        model of one trajectory) where s_i is not max(peak |tau_i|, torque floor) there.

    Notes
    -----
    The bound of a model pruned on a trajectory is the triangle inequality over its dropped
    terms' peak contributions there (Fu, Gonzalez & Lee 1987, Sec. 3.4.1: the simplified
    model "depends on the specific trajectory being considered"), so it is at least the
    error measured on that trajectory.
    """
    g = model.guarantee
    robot: Robot = model.robot
    errors = _torque_errors(model, trajectory, robot)
    peak, peak_tau = errors.peak, errors.peak_tau
    scale, bound = np.asarray(g.scale, float), np.asarray(g.bound, float)  # type: ignore[union-attr, type-var]  # the guarantee is not None here
    own = np.maximum(peak_tau, scale)
    ok = within_bound(peak, bound, scale) | round_off(peak, own, own, robot)   # as the gate
    if not ok.all():
        j = int(np.argmax(np.where(ok, -np.inf, peak - bound)))
        raise InputError(f"is below the error measured again on its own trajectory (joint "
                         f"{j + 1}: {bound[j]:.4g} < {peak[j]:.4g})", path,
                         column="guarantee.bound")
    if g.trajectories_sha256:  # type: ignore[union-attr]  # the guarantee is not None here
        return                      # a sweep's model: s_i is each trajectory's
    expected = np.maximum(peak_tau, float(model.torque_floor))
    ok = within_bound(np.abs(expected - scale), TRAJECTORY_SCALE_RTOL * np.abs(expected),
                      expected)
    if not ok.all():
        j = int(np.argmax(~ok))
        raise InputError(f"is not max(peak |tau_i|, torque floor) on its own trajectory "
                         f"(joint {j + 1}: {scale[j]:.6g} stated, {expected[j]:.6g} measured "
                         "again)", path, column="guarantee.scale")


def gate(err: Mapping[str, Any], model: SimplifiedModel,
         max_error: float | None = None) -> dict[str, Any]:
    """The evaluate gate: does the model's error on a trajectory pass?

    Parameters
    ----------
    err : dict
        :func:`evaluate`'s result.
    model : SimplifiedModel
    max_error : float, optional
        ``--max-error``: every joint's relative peak error at most this (``relative_to`` says
        relative to what). Default: the model's promise, peak |tau_s - tau| <= EPS s_i with
        s_i its guarantee's scale; no gate for a model without a guarantee.

    Returns
    -------
    dict
        ``by`` (``"model"``, ``"--max-error"`` or None), ``limit`` per joint (EPS s_i [N m or
        N], or ``max_error`` [1]; None without a gate), ``exceeded`` (bool), ``worst_joint``
        (1-based, the joint furthest beyond its limit; None if none exceeds) and ``message``
        (one line naming it, "" if none). Round-off passes; NaN or inf fails.
    """
    robot: Robot = model.robot
    peak = np.asarray(err["peak_abs_error"], float)
    g, promise = model.guarantee, max_error is None     # the model's promise, or --max-error
    if promise and g is None:
        return {"by": None, "limit": None, "exceeded": False, "worst_joint": None,
                "message": ""}
    s = np.asarray(g.scale if promise else (err.get("scale") or np.zeros(robot.n)), float)  # type: ignore[union-attr]  # the guarantee is not None here
    own = np.maximum(np.asarray(err["peak_tau"], float), s)
    off = round_off(peak, own, own, robot)
    limit = g.tolerance * s if promise else np.full(robot.n, float(max_error))  # type: ignore[union-attr, arg-type]  # the guarantee, or max_error, is not None here
    measure = peak if promise else np.asarray(err["relative_peak_error"], float)
    within = within_bound(peak, limit, s) if promise else measure <= limit  # up to round-off
    fails = ~within & ~off                                  # NaN never passes
    out = {"by": "model" if promise else "--max-error", "limit": limit.tolist(),
           "exceeded": bool(fails.any()), "worst_joint": None, "message": ""}
    if not fails.any():
        return out
    with np.errstate(divide="ignore", invalid="ignore"):
        over = np.where(fails, np.nan_to_num(measure / limit, nan=np.inf, posinf=np.inf), -1.0)
    j = int(np.argmax(over))
    u = joint_torque_units(bool(robot.prismatic[j]))
    return {**out, "worst_joint": j + 1, "message": (
        f"joint {j + 1}'s torque error {peak[j]:.4g} {u} exceeds the model's "
        f"tolerance x scale, {g.tolerance:g} x {s[j]:.4g} {u} = "  # type: ignore[union-attr]  # the guarantee is not None here
        f"{limit[j]:.4g} {u}" if promise else
        f"joint {j + 1}'s relative torque error {measure[j]:.3e} (of "
        f"{err['relative_to'][j]}) exceeds --max-error {max_error:g}")}
