"""The independent reference engine: the same chain built in Pinocchio.

Pinocchio (Carpentier et al., "The Pinocchio C++ library", SII 2019) computes the inertia matrix
with the composite rigid body algorithm (``crba``), the Coriolis, centrifugal and gravity
torques with the recursive Newton-Euler algorithm (``nonLinearEffects``, ``rnea``) and gravity
alone with ``computeGeneralizedGravity``. Dynamics are linear in the link inertias, so a model
whose rotational inertias are all zero gives the translational G-D parts, and one whose masses
are all zero (rotational inertias kept) gives the rotational parts.

The model is built from the robot's joint model (:mod:`gd_analyze.model.robot`), whatever
its source (standard or modified DH, URDF): Pinocchio joint i is a ``JointModelRZ`` (revolute) or
``JointModelPZ`` (prismatic) whose placement in joint i-1's frame is the SE3 (P_i, t_i), and
link i's inertia is appended in joint i's frame (the body frame) at its body-frame centre of
mass with its body-frame inertia tensor.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..config import ROUND_OFF_EPS
from ..model.kinematics import as_states
from .dalembert import assemble_tau

if TYPE_CHECKING:
    import pinocchio

    from ..model.robot import Robot


__all__ = ["pinocchio_model", "ReferenceTerms", "reference_terms", "relative_error",
           "natural_scales", "natural_relative_error", "measured_relative_error"]


def _pin():
    import pinocchio

    return pinocchio


def pinocchio_model(robot: Robot, part: str = "full") -> pinocchio.Model:
    """Build the robot as a Pinocchio model.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    part : {"full", "tran", "rot"}, optional
        ``"full"``: the robot as it is, with its drives' armature in ``model.armature``.
        ``"tran"``: every rotational inertia set to zero (point masses at the centres of mass).
        ``"rot"``: every mass set to zero, rotational inertias kept. Neither part has armature.

    Returns
    -------
    pinocchio.Model
        n revolute (``JointModelRZ``) or prismatic (``JointModelPZ``) joints; ``model.gravity`` is the robot's gravity [m/s^2].

    Raises
    ------
    ValueError
        If part is not one of the three names.
    """
    pin = _pin()
    if part not in ("full", "tran", "rot"):
        raise ValueError(f"part must be 'full', 'tran' or 'rot', got {part!r}")
    model = pin.Model()
    model.name = robot.name
    com, inertia = robot.body_com, robot.body_inertia
    for i in range(robot.n):        # a chain: joint i + 1's parent is joint i (0: the universe)
        placement = pin.SE3(np.array(robot.rotation[i]), np.array(robot.translation[i]))
        joint = pin.JointModelPZ() if robot.prismatic[i] else pin.JointModelRZ()
        jid = model.addJoint(i, joint, placement, f"joint{i + 1}")
        body = pin.Inertia(0.0 if part == "rot" else float(robot.mass[i]), np.array(com[i]),
                           np.zeros((3, 3)))
        # the tensor as read: Inertia() refuses a diagonal round-off below 0 (iCub's -5e-20)
        body.inertia = np.zeros((3, 3)) if part == "tran" else np.array(inertia[i])
        model.appendBodyToJoint(jid, body, pin.SE3.Identity())
    model.gravity = pin.Motion(np.array(robot.gravity, dtype=float), np.zeros(3))
    if part == "full":
        model.armature = np.array(robot.armature, dtype=float)
    return model


@dataclass(frozen=True, eq=False)
class ReferenceTerms:
    """Pinocchio's terms at N set points, split as the G-D terms are.

    Attributes
    ----------
    D_tran, D_rot : ndarray, shape (N, n, n)
        ``crba`` of the zero-rotational-inertia and zero-mass models [kg m^2].
    h_tran, h_rot : ndarray, shape (N, n)
        ``nonLinearEffects`` of the same models with gravity set to zero [N m].
    D : ndarray, shape (N, n, n)
        ``crba`` of the full model [kg m^2].
    h : ndarray, shape (N, n)
        ``nonLinearEffects`` of the full model with gravity zero [N m].
    c : ndarray, shape (N, n)
        ``computeGeneralizedGravity`` of the full model [N m].
    """

    D_tran: np.ndarray
    D_rot: np.ndarray
    h_tran: np.ndarray
    h_rot: np.ndarray
    D: np.ndarray
    h: np.ndarray
    c: np.ndarray


def _crba_nle(model, q, qd, gravity_free=True):
    pin = _pin()
    if gravity_free:
        model = model.copy()
        model.gravity = pin.Motion.Zero()
    data = model.createData()
    N, n = q.shape
    D = np.empty((N, n, n))
    h = np.empty((N, n))
    for k in range(N):
        M = pin.crba(model, data, q[k])
        D[k] = np.triu(M) + np.triu(M, 1).T
        h[k] = pin.nonLinearEffects(model, data, q[k], qd[k])
    return D, h


def reference_terms(robot: Robot, q: ArrayLike, qd: ArrayLike) -> ReferenceTerms:
    """Pinocchio's D, h and c and their translational and rotational split.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : array_like, shape (N, n)
        Joint positions [rad].
    qd : array_like, shape (N, n)
        Joint velocities [rad/s].

    Returns
    -------
    ReferenceTerms

    Raises
    ------
    ValueError
        If q or qd does not have shape (N, n).

    Notes
    -----
    One Python call per set point and algorithm: use it to verify, not to compute in bulk.
    """
    pin = _pin()
    q, qd = as_states(robot, q, qd)
    full = pinocchio_model(robot, "full")
    D, h = _crba_nle(full, q, qd)
    D_tran, h_tran = _crba_nle(pinocchio_model(robot, "tran"), q, qd)
    D_rot, h_rot = _crba_nle(pinocchio_model(robot, "rot"), q, qd)
    data = full.createData()
    c = np.array([pin.computeGeneralizedGravity(full, data, qk) for qk in q]).reshape(q.shape)
    return ReferenceTerms(D_tran, D_rot, h_tran, h_rot, D, h, c)


def relative_error(value: ArrayLike, reference: ArrayLike) -> float:
    """Largest absolute difference, relative to the reference's largest magnitude.

    Parameters
    ----------
    value, reference : array_like, same shape
        The arrays to compare (any units, the same for both).

    Returns
    -------
    float
        ``max|value - reference| / max(max|reference|, tiny)``; 0 for empty arrays.
    """
    value, reference = np.asarray(value, dtype=float), np.asarray(reference, dtype=float)
    if value.size == 0:
        return 0.0
    scale = max(float(np.max(np.abs(reference))), np.finfo(float).tiny)
    return float(np.max(np.abs(value - reference)) / scale)


#: The absolute floor of :func:`natural_relative_error`, in units of machine epsilon times the
#: overall scale of the quantity: the round-off rule's
#: (:data:`gd_analyze.config.ROUND_OFF_EPS`).
FLOOR_EPS = ROUND_OFF_EPS


def natural_scales(robot: Robot, ref: ReferenceTerms, qd: np.ndarray,
                   qdd: np.ndarray | None = None) -> dict[str, Any]:
    """The natural scale of each G-D quantity over the set points.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (for the size of gravity's torque).
    ref : ReferenceTerms
        Pinocchio's terms at N set points: D (N, n, n) [kg m^2], h and c (N, n) [N m].
    qd : ndarray, shape (N, n)
        Joint velocities [rad/s].
    qdd : ndarray, shape (N, n), optional
        Joint accelerations [rad/s^2] (zero if not given).

    Returns
    -------
    dict
        ``"D"``: shape (n, n), peak sqrt(D_ii D_jj) [kg m^2]; ``"tau"``: shape (n,), peak
        |tau_i| with tau = D qdd + h + c [N m]; ``"floor_D"``, ``"floor_tau"``: the absolute
        floors FLOOR_EPS * eps times the overall scale: the largest D scale, and the largest of
        the torque scales, of D's scale times the largest qd^2, and of gravity's torque
        |g| sum_i m_i (reach + max |r_i|), the reach being sum_i (|a_i| + |d_i|) (or the sum
        of the placements' translations for a general chain).

    Notes
    -----
    The engineering standard of the project: an element D_ij is compared on the scale
    sqrt(D_ii D_jj) (Cauchy-Schwarz bound for a positive-definite D), a torque component on its
    joint's peak |tau_i|; NaN propagates through every reduction.
    """
    D = np.asarray(ref.D, dtype=float)
    diag = np.abs(np.diagonal(D, axis1=1, axis2=2))                  # (N, n)
    s_D = np.max(np.sqrt(diag[:, :, None] * diag[:, None, :]), axis=0)
    qdd = np.zeros_like(ref.h) if qdd is None else np.asarray(qdd, dtype=float)
    tau = assemble_tau(D, ref.h, ref.c, qdd)
    s_tau = np.max(np.abs(tau), axis=0)
    qd2 = np.max(np.asarray(qd, dtype=float) ** 2)
    # the arm's reach: DH lengths, or the placements' translations of a general chain (whose
    # DH columns are NaN)
    placements = getattr(robot, "translation", None)
    reach = float(np.nansum(np.abs(robot.a)) + np.nansum(np.abs(robot.d))
                  + (np.nansum(np.abs(placements)) if placements is not None else 0.0)
                  + np.max(np.abs(robot.com)))
    s_g = float(np.linalg.norm(robot.gravity)) * float(np.sum(robot.mass)) * reach
    eps = np.finfo(float).eps
    big_D = np.max(s_D)
    return {"D": s_D, "tau": s_tau, "floor_D": FLOOR_EPS * eps * big_D,
            "floor_tau": FLOOR_EPS * eps * np.max([np.max(s_tau), big_D * qd2, s_g])}


def natural_relative_error(value: ArrayLike, reference: ArrayLike, scale: ArrayLike,
                           floor: float) -> float:
    """Largest difference over the set points, relative to each element's natural scale.

    Parameters
    ----------
    value, reference : array_like, shape (N, ...)
        The arrays to compare, set points first.
    scale : array_like, shape (...)
        The natural scale of each element (see :func:`natural_scales`), >= 0.
    floor : float
        Absolute floor: differences up to it count as zero, and no scale is taken below it.

    Returns
    -------
    float
        ``max over elements of max(max_k |value - reference| - floor, 0) / max(scale, floor)``;
        NaN if any value is NaN (it then fails every tolerance); 0 for empty arrays.

    Examples
    --------
    >>> import numpy as np
    >>> natural_relative_error(np.array([[1.0, 1e-20]]), np.array([[1.0, 0.0]]),
    ...                        np.array([2.0, 2.0]), 1e-14)
    0.0
    >>> natural_relative_error(np.array([[1.0, np.nan]]), np.zeros((1, 2)), np.ones(2), 0.0)
    nan
    """
    return _relative(value, reference, scale, floor, past_floor=True)


def _relative(value, reference, scale, floor, past_floor):
    value, reference = np.asarray(value, dtype=float), np.asarray(reference, dtype=float)
    if value.size == 0:
        return 0.0
    diff = np.max(np.abs(value - reference), axis=0)                 # NaN propagates
    floor = max(float(floor), np.finfo(float).tiny)
    if past_floor:
        diff = np.maximum(diff - floor, 0.0)
    return float(np.max(diff / np.maximum(scale, floor)))


def measured_relative_error(value: ArrayLike, reference: ArrayLike, scale: ArrayLike,
                            floor: float) -> float:
    """Largest difference over the set points relative to each element's natural scale, as
    measured: round-off included (:func:`natural_relative_error` counts only what is past the
    floor).

    Parameters
    ----------
    value, reference, scale, floor
        As :func:`natural_relative_error` (no scale is taken below ``floor``).

    Returns
    -------
    float
        ``max over elements of max_k |value - reference| / max(scale, floor)``; NaN if any
        value is NaN; 0 for empty arrays.

    Examples
    --------
    >>> import numpy as np
    >>> measured_relative_error(np.array([[1.0, 1e-20]]), np.array([[1.0, 0.0]]),
    ...                         np.array([2.0, 2.0]), 1e-14)
    5e-21
    """
    return _relative(value, reference, scale, floor, past_floor=False)
