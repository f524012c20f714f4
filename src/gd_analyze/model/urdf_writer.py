"""Writing a robot as a URDF: the chain of the robot model, joint by joint.

Each joint i becomes a ``<joint>`` whose ``<origin>`` is the placement (P_i, t_i) of
:mod:`gd_analyze.model.robot` (rpy of P_i in the URDF convention R = Rz(y) Ry(p) Rx(r)) with
``<axis xyz="0 0 1"/>``, so its child link's frame is body frame i; the link's ``<inertial>``
holds the body-frame centre of mass and inertia tensor. Limits are written where given
(``velocity="0"`` and ``effort="0"``, ROS's "unset", otherwise), a joint without position limits
as ``continuous``. The URDF format has no armature and no torque offset, and gd-analyze's URDF
reader takes no friction from it: the drives are in the robot file (TOML) only. Every name is
XML-escaped (:func:`xml.sax.saxutils.quoteattr`); comments cannot close themselves.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING
from xml.sax.saxutils import quoteattr

import numpy as np

if TYPE_CHECKING:
    from .robot import Robot

__all__ = ["robot_urdf"]


def _rpy(R):
    """Roll, pitch, yaw with R = Rz(y) Ry(p) Rx(r)."""
    import warnings

    from scipy.spatial.transform import Rotation

    with warnings.catch_warnings():     # at pitch +-90 deg the angles still give R
        warnings.simplefilter("ignore")
        return Rotation.from_matrix(np.asarray(R, float)).as_euler("xyz")


def _num(values):
    return " ".join(repr(float(v)) for v in np.atleast_1d(values))


#: What an XML 1.0 comment cannot hold: characters outside XML's ``Char`` (control characters,
#: lone surrogates of a file name that is not UTF-8, U+FFFE, U+FFFF).
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _comment(text):
    body = _NOT_XML.sub(lambda m: m.group().encode("unicode_escape").decode("ascii"),
                        str(text).replace("\n", " "))
    return "<!-- " + re.sub("-(?=-)", "- ", body) + " -->"


def robot_urdf(robot: Robot, comments: Sequence[str] = ()) -> str:
    """The robot as URDF text.

    Parameters
    ----------
    robot : Robot
        The arm (its placements, joint types, limits and link inertial parameters).
    comments : sequence of str, optional
        Lines written as XML comments at the top.

    Returns
    -------
    str

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> "<robot name=" in robot_urdf(load_robot("two-link"))
    True
    """
    joints = robot.joint_names()
    lines = ['<?xml version="1.0"?>'] + [_comment(c) for c in comments]
    if not np.allclose(robot.gravity, [0.0, 0.0, -9.81]):
        lines.append(_comment(f"gravity in the robot file: {_num(robot.gravity)} m/s^2 (a URDF "
                              f"holds none)"))
    lines += [f"<robot name={quoteattr(robot.name)}>", '  <link name="base_link"/>']
    com, inertia = robot.body_com, robot.body_inertia
    parent = "base_link"
    for i in range(robot.n):
        child = f"link{i + 1}"
        lo, hi = float(robot.q_min[i]), float(robot.q_max[i])
        pris = bool(robot.prismatic[i])
        kind = "prismatic" if pris else ("continuous" if not (math.isfinite(lo) and
                                                              math.isfinite(hi)) else "revolute")
        vel = float(robot.qd_max[i]) if math.isfinite(robot.qd_max[i]) else 0.0
        eff = float(robot.tau_max[i]) if math.isfinite(robot.tau_max[i]) else 0.0
        limit = f'effort="{eff!r}" velocity="{vel!r}"'
        if kind != "continuous":
            limit = f'lower="{lo!r}" upper="{hi!r}" ' + limit
        I = inertia[i]
        lines += [
            f"  <joint name={quoteattr(joints[i])} type=\"{kind}\">",
            f"    <parent link=\"{parent}\"/><child link=\"{child}\"/>",
            f"    <origin xyz=\"{_num(robot.translation[i])}\" rpy=\"{_num(_rpy(robot.rotation[i]))}\"/>",
            "    <axis xyz=\"0 0 1\"/>",
            f"    <limit {limit}/>",
            "  </joint>",
            f"  <link name=\"{child}\"><inertial>",
            f"    <origin xyz=\"{_num(com[i])}\" rpy=\"0 0 0\"/>",
            f"    <mass value=\"{float(robot.mass[i])!r}\"/>",
            f"    <inertia ixx=\"{float(I[0, 0])!r}\" ixy=\"{float(I[0, 1])!r}\" "
            f"ixz=\"{float(I[0, 2])!r}\" "
            f"iyy=\"{float(I[1, 1])!r}\" iyz=\"{float(I[1, 2])!r}\" izz=\"{float(I[2, 2])!r}\"/>",
            "  </inertial></link>"]
        parent = child
    lines.append("</robot>")
    return "\n".join(lines) + "\n"
