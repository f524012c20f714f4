"""Mounting: a robot's gravity vector and the orientation of its base in the world.

A robot file gives gravity in its base frame for one mounting (usually upright). An arm on a
wall or a ceiling has its base turned in the world; gravity in the base frame is then the
world's gravity turned back, g_base = R^T g_world (:func:`with_mounting`, the options
``--gravity`` and ``--base-rpy``).

A mounted robot records its mounting (:func:`mounting_of`: the base's roll, pitch, yaw and the
world's gravity) in its ``metadata``, and a model file stores it beside its robot, so a mounting
is applied once: the options give the arm's mounting in the world, not a turn on top of the
one it was built with.
"""

from __future__ import annotations

import dataclasses
import math
import types
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from .limits import LIMITS, exact_text

if TYPE_CHECKING:
    from .robot import Robot

__all__ = ["rpy_matrix", "with_mounting", "mounting_of", "as_mounted", "MOUNTING_KEY"]

#: The key of ``Robot.metadata`` (and of a model file) that records a robot's mounting.
MOUNTING_KEY = "mounting"


def _cos_sin(angle, degrees):
    """cos and sin of an angle, exact (0, +-1) at multiples of 90 deg given in degrees."""
    if degrees and float(angle) % 90.0 == 0.0:
        k = int(round(float(angle) / 90.0)) % 4
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[k]
    a = math.radians(angle) if degrees else float(angle)
    return math.cos(a), math.sin(a)


def rpy_matrix(roll: float, pitch: float, yaw: float, degrees: bool = False) -> np.ndarray:
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


def mounting_of(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """The mounting a robot was built with: its base's roll, pitch, yaw and the world's gravity.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    base_rpy_deg : ndarray, shape (3,)
        Roll, pitch, yaw of the base in the world [deg]; 0, 0, 0 for a robot never mounted.
    gravity_world : ndarray, shape (3,)
        Gravity in the world frame [m/s^2], R g_base (``robot.gravity`` for a robot never
        mounted: its file's gravity is the world's, the upright mounting).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> rpy, g = mounting_of(with_mounting(load_robot("two-link"), base_rpy=(0, 0, 180)))
    >>> rpy.tolist(), g.tolist()
    ([0.0, 0.0, 180.0], [0.0, -9.8062, 0.0])
    """
    said = (getattr(robot, "metadata", None) or {}).get(MOUNTING_KEY)
    if not said:
        return np.zeros(3), np.asarray(robot.gravity, dtype=float).copy()
    return (np.asarray(said["base_rpy_deg"], dtype=float).copy(),
            np.asarray(said["gravity_world"], dtype=float).copy())


def as_mounted(robot: Robot, base_rpy_deg: ArrayLike,
               gravity_world: ArrayLike | None = None) -> Robot:
    """The robot with its mounting recorded, as a model file states it (no turn applied).

    Parameters
    ----------
    robot : Robot
        The arm, ``gravity`` already in its base frame (g_base).
    base_rpy_deg : array_like, shape (3,)
        Roll, pitch, yaw of the base in the world it was built with [deg].
    gravity_world : array_like, shape (3,), optional
        Gravity in the world frame [m/s^2]; default R g_base.

    Returns
    -------
    Robot
        The same robot where the mounting is 0, 0, 0 with the world's gravity its own; else a
        copy with ``metadata["mounting"]`` (:func:`mounting_of` reads it).

    Raises
    ------
    ValueError
        If a vector has not 3 finite numbers, or R^T g_world is not the robot's gravity.
    """
    rpy = np.asarray(base_rpy_deg, dtype=float).reshape(3) + 0.0
    R = rpy_matrix(rpy[0], rpy[1], rpy[2], degrees=True)
    g_base = np.asarray(robot.gravity, dtype=float)
    g_world = (R @ g_base if gravity_world is None
               else np.asarray(gravity_world, dtype=float).reshape(3)) + 0.0
    if not (np.isfinite(rpy).all() and np.isfinite(g_world).all()):
        raise ValueError("expected finite numbers")
    if not np.allclose(R.T @ g_world, g_base, rtol=0.0,
                       atol=1e-12 * max(1.0, float(np.abs(g_world).max()))):
        raise ValueError("its gravity in the world, turned by its base roll, pitch, yaw, is "
                         "not the robot's gravity")
    if not rpy.any() and np.array_equal(g_world, g_base):
        return robot
    metadata = {**(robot.metadata or {}),
                MOUNTING_KEY: {"base_rpy_deg": tuple(float(v) for v in rpy),
                               "gravity_world": tuple(float(v) for v in g_world)}}
    return dataclasses.replace(robot, metadata=types.MappingProxyType(metadata))


def _checked(opt, raw, lim):
    try:
        v = np.asarray(raw, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise InputError(f"expected 3 numbers, got {raw!r}", column=opt) from None
    if not (np.isfinite(v).all() and (np.abs(v) <= lim).all()):
        raise InputError(f"expected 3 finite numbers of magnitude at most {lim:g}, got "
                         f"{', '.join(exact_text(x) for x in v)}", column=opt)
    return v + 0.0


def with_mounting(robot: Robot, gravity: ArrayLike | None = None,
                  base_rpy: ArrayLike | None = None) -> Robot:
    """The robot mounted otherwise: another gravity vector, or its base turned in the world.

    The base frame is turned by R = Rz(Y) Ry(P) Rx(R) (URDF rpy) from the world frame, so
    gravity in the base frame is g_base = R^T g_world. The options give the arm's mounting in
    the world, not a turn on top of the one the robot was built with (:func:`mounting_of`):
    what is not given keeps the robot's own, and mounting a robot again as it is mounted
    changes nothing.

    Parameters
    ----------
    robot : Robot
        The arm as its robot file gives it, or as mounted before (a model file's robot).
    gravity : array_like, shape (3,), optional
        Gravity in the world frame [m/s^2] (default: the robot's world gravity, for a robot
        file the file's gravity vector); ``(0, 0, 0)`` for no gravity.
    base_rpy : array_like, shape (3,), optional
        Roll, pitch, yaw of the base in the world frame [deg] (default: the robot's own, 0,
        0, 0 for a robot file), e.g. ``(0, 180, 0)`` for a ceiling, ``(0, 90, 0)`` for a wall.

    Returns
    -------
    Robot
        A copy with ``gravity`` = g_base and its mounting in ``metadata["mounting"]``; its
        description states the mounting. The same robot if neither is given, or if the
        mounting is the robot's own.

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
    >>> turned = with_mounting(robot, base_rpy=(0, 0, 180))
    >>> with_mounting(turned, base_rpy=(0, 0, 180)) is turned      # applied once
    True
    """
    if gravity is None and base_rpy is None:
        return robot
    rpy0, g0 = mounting_of(robot)
    g_world = g0 if gravity is None else _checked("--gravity", gravity, LIMITS["gravity"])
    rpy = rpy0 if base_rpy is None else _checked("--base-rpy", base_rpy, LIMITS["angle_deg"])
    if np.array_equal(g_world, g0) and np.array_equal(rpy, rpy0):
        return robot
    g_base = rpy_matrix(rpy[0], rpy[1], rpy[2], degrees=True).T @ g_world + 0.0          # no -0.0
    said = ", ".join(f"{float(v):g}" for v in g_world)
    turn = ", ".join(f"{float(v):g}" for v in rpy)
    own = robot.description.partition("mounted with gravity (")[0].rstrip("; ")
    metadata = {**(robot.metadata or {}),
                MOUNTING_KEY: {"base_rpy_deg": tuple(float(v) for v in rpy),
                               "gravity_world": tuple(float(v) for v in g_world)}}
    return dataclasses.replace(
        robot, gravity=g_base, metadata=types.MappingProxyType(metadata),
        description=(f"{own}; mounted with gravity ({said}) m/s^2 in the world "
                     f"and base roll, pitch, yaw ({turn}) deg").lstrip("; "))
