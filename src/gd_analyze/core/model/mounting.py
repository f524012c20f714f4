"""Mounting: a robot's gravity vector and the orientation of its base in the world.

A robot file gives gravity in its base frame for one mounting (usually upright). An arm on a
wall or a ceiling has its base turned in the world; gravity in the base frame is then the
world's gravity turned back, g_base = R^T g_world (:func:`with_mounting`, the options
``--gravity`` and ``--base-rpy``).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...errors import InputError
from .limits import LIMITS

__all__ = ["rpy_matrix", "with_mounting"]


def _cos_sin(angle, degrees):
    """cos and sin of an angle, exact (0, +-1) at multiples of 90 deg given in degrees."""
    if degrees and float(angle) % 90.0 == 0.0:
        k = int(round(float(angle) / 90.0)) % 4
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[k]
    a = math.radians(angle) if degrees else float(angle)
    return math.cos(a), math.sin(a)


def rpy_matrix(roll, pitch, yaw, degrees=False):
    """The rotation of URDF roll, pitch, yaw angles: R = Rz(yaw) Ry(pitch) Rx(roll).

    Parameters
    ----------
    roll, pitch, yaw : float
        Angles about the fixed x, y and z axes, applied in that order [rad; deg if
        ``degrees``].
    degrees : bool, optional
        The angles are in degrees; multiples of 90 deg then give exact 0 and +-1 entries.

    Returns
    -------
    ndarray, shape (3, 3)

    Notes
    -----
    Source: the URDF specification, ``<origin rpy>`` (wiki.ros.org/urdf/XML/joint).

    Examples
    --------
    >>> rpy_matrix(0.0, 90.0, 0.0, degrees=True) @ [0.0, 0.0, 1.0]
    array([1., 0., 0.])
    """
    (cr, sr), (cp, sp), (cy, sy) = (_cos_sin(a, degrees) for a in (roll, pitch, yaw))
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


def with_mounting(robot, gravity=None, base_rpy=None):
    """The robot mounted otherwise: another gravity vector, or its base turned in the world.

    The base frame is turned by R = Rz(Y) Ry(P) Rx(R) (URDF rpy) from the world frame, so
    gravity in the base frame is g_base = R^T g_world, where g_world is ``gravity`` or, if not
    given, the robot file's gravity vector (read as the world's: the upright mounting).

    Parameters
    ----------
    robot : Robot
        The arm as its robot file gives it.
    gravity : array_like, shape (3,), optional
        Gravity in the world frame [m/s^2] (default: ``robot.gravity``); ``(0, 0, 0)`` for no
        gravity.
    base_rpy : array_like, shape (3,), optional
        Roll, pitch, yaw of the base in the world frame [deg] (default: 0, 0, 0), e.g.
        ``(0, 180, 0)`` for a ceiling, ``(0, 90, 0)`` for a wall.

    Returns
    -------
    Robot
        A copy with ``gravity`` = g_base (the same robot if neither is given); its description
        states the mounting.

    Raises
    ------
    InputError
        If a vector has not 3 finite numbers or a gravity component is beyond the supported
        magnitude.

    Notes
    -----
    Gravity enters the dynamics only through the base's acceleration -g (Fu, Gonzalez & Lee
    1987, Sec. 3.3, the recursive N-E equations start from dv_0 = -g); turning the base turns g.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("two-link")
    >>> robot.gravity.tolist()
    [0.0, -9.8062, 0.0]
    >>> with_mounting(robot, base_rpy=(90, 0, 0)).gravity.tolist()
    [0.0, 0.0, 9.8062]
    """
    if gravity is None and base_rpy is None:
        return robot
    vecs = {}
    for opt, raw, lim in (("--gravity", gravity, LIMITS["gravity"]),
                          ("--base-rpy", base_rpy, LIMITS["angle_deg"])):
        if raw is None:
            continue
        try:
            v = np.asarray(raw, dtype=float).reshape(3)
        except (TypeError, ValueError):
            raise InputError(f"expected 3 numbers, got {raw!r}", column=opt) from None
        if not (np.isfinite(v).all() and (np.abs(v) <= lim).all()):
            raise InputError(f"expected 3 finite numbers of magnitude at most {lim:g}, got "
                             f"{', '.join(f'{float(x):g}' for x in v)}", column=opt)
        vecs[opt] = v
    g_world = vecs.get("--gravity", np.asarray(robot.gravity, dtype=float))
    rpy = vecs.get("--base-rpy", np.zeros(3))
    R = rpy_matrix(*rpy, degrees=True)
    g_base = R.T @ g_world + 0.0          # no -0.0
    said = ", ".join(f"{float(v):g}" for v in g_world)
    turn = ", ".join(f"{float(v):g}" for v in rpy)
    return dataclasses.replace(
        robot, gravity=g_base,
        description=(f"{robot.description}; mounted with gravity ({said}) m/s^2 in the world "
                     f"and base roll, pitch, yaw ({turn}) deg").lstrip("; "))
