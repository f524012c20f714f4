"""The independent reference engine: the same chain built in Pinocchio.

Pinocchio (Carpentier et al., "The Pinocchio C++ library", SII 2019) computes the inertia matrix
with the composite rigid body algorithm (``crba``), the Coriolis, centrifugal and gravity
torques with the recursive Newton-Euler algorithm (``nonLinearEffects``, ``rnea``) and gravity
alone with ``computeGeneralizedGravity``. Dynamics are linear in the link inertias, so a model
whose rotational inertias are all zero gives the translational G-D parts, and one whose masses
are all zero (rotational inertias kept) gives the rotational parts.

Each Pinocchio joint i is a revolute joint about the z axis of DH frame i-1. Its placement in
joint i-1 is the rest of link i-1's transform, Trans(0,0,d) Trans(a,0,0) Rot(x, alpha), then the
offset Rot(z, offset_i); link i's inertia sits in joint i's frame at the same remaining
transform Trans(0,0,d_i) Trans(a_i,0,0) Rot(x, alpha_i).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.kinematics import as_states

__all__ = ["pinocchio_model", "ReferenceTerms", "reference_terms", "relative_error"]


def _pin():
    import pinocchio

    return pinocchio


def pinocchio_model(robot, part="full"):
    """Build the robot as a Pinocchio model.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    part : {"full", "tran", "rot"}, optional
        ``"full"``: the robot as it is. ``"tran"``: every rotational inertia set to zero (point
        masses at the centres of mass). ``"rot"``: every mass set to zero, rotational inertias
        kept.

    Returns
    -------
    pinocchio.Model
        n revolute joints; ``model.gravity`` is the robot's gravity [m/s^2].

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
    parent = 0
    placement = pin.SE3.Identity()
    for i in range(robot.n):
        rest = (pin.SE3(np.eye(3), np.array([robot.a[i], 0.0, robot.d[i]]))
                * pin.SE3(_rot_x(robot.alpha[i]), np.zeros(3)))
        joint_placement = placement * pin.SE3(_rot_z(robot.offset[i]), np.zeros(3))
        jid = model.addJoint(parent, pin.JointModelRZ(), joint_placement, f"joint{i + 1}")
        mass = 0.0 if part == "rot" else float(robot.mass[i])
        inertia = np.zeros((3, 3)) if part == "tran" else np.array(robot.inertia[i])
        body = pin.Inertia(mass, np.array(robot.com[i]), inertia)
        model.appendBodyToJoint(jid, rest.act(body), pin.SE3.Identity())
        parent, placement = jid, rest
    model.gravity = pin.Motion(np.array(robot.gravity, dtype=float), np.zeros(3))
    return model


def _rot_x(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rot_z(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


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


def reference_terms(robot, q, qd):
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


def relative_error(value, reference):
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
    value = np.asarray(value, dtype=float)
    reference = np.asarray(reference, dtype=float)
    if value.size == 0:
        return 0.0
    scale = max(float(np.max(np.abs(reference))), np.finfo(float).tiny)
    return float(np.max(np.abs(value - reference)) / scale)
