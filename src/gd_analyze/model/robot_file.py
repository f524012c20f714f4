"""Writing a robot file: a :class:`~gd_analyze.model.robot.Robot` as TOML text.

The layout is the robot-file format :func:`gd_analyze.model.robots.load_robot` reads
(:meth:`gd_analyze.model.robot.Robot.to_dict`), so the main job, ``plan`` and the API
accept the file as it is. Every number is written with ``repr`` (the shortest text that reads back as the same float); every
string as a TOML basic string with its non-ASCII and control characters escaped, so that no
name from an input file can break the file. Limits that are not given (NaN) or infinite
position ranges are left out (the loader's defaults are the same). A robot whose joints have
names (a URDF's) writes each as its link's ``joint_name``, by which recordings may name their
columns.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .robot import Robot

__all__ = ["robot_toml"]


def _value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=True)
    if isinstance(v, (int, float)):
        f = float(v)
        if math.isnan(f):
            return "nan"
        if math.isinf(f):
            return "inf" if f > 0 else "-inf"
        return repr(f)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _given(key, value):
    """Whether a link key is written: no NaN limits, no infinite position range."""
    if key.startswith(("qd_max", "qdd_max")):
        return isinstance(value, float) and math.isfinite(value)
    if key.startswith("q_limits"):
        return all(math.isfinite(x) for x in value)
    return True


def robot_toml(robot: Robot, comments: Sequence[str] = ()) -> str:
    """The robot as robot-file TOML text.

    Parameters
    ----------
    robot : Robot
        The arm, with its drives.
    comments : sequence of str, optional
        Lines written as ``#`` comments at the top (each made one line, control characters
        escaped).

    Returns
    -------
    str

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> print(robot_toml(load_robot("two-link"), ["made by a test"]).splitlines()[0])
    # made by a test
    """
    spec = robot.to_dict()
    lines = ["# " + json.dumps(str(c), ensure_ascii=True)[1:-1] for c in comments]
    for key in ("name", "description", "reference", "convention", "gravity"):
        lines.append(f"{key} = {_value(spec[key])}")
    names = robot.metadata.get("urdf_joints") and robot.joint_names()   # a URDF's, say
    for i, link in enumerate(spec["link"]):
        lines += ["", "[[link]]"] + ([f"joint_name = {_value(names[i])}"] if names else [])
        for key, value in link.items():
            if _given(key, value):
                lines.append(f"{key} = {_value(value)}")
    return "\n".join(lines) + "\n"
