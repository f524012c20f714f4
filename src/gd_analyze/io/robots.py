"""Loading a robot from any source: a built-in name, a TOML robot file or a URDF file.

TOML robot files and the TOML built-ins are read by :func:`gd_analyze.core.robot.load_robot`; URDF
files (suffix ``.urdf``) and the URDF built-ins (``panda``, ``ur5``) by
:func:`gd_analyze.io.urdf.load_urdf`, which needs Pinocchio's parser and therefore lives above
the core.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..core.robot import builtin_robots as _toml_builtins
from ..core.robot import load_robot as _load_toml
from .urdf import URDF_BUILTIN, load_urdf

__all__ = ["load_robot", "builtin_robots", "is_urdf"]


def is_urdf(name_or_path):
    """Whether a robot argument names a URDF robot.

    Parameters
    ----------
    name_or_path : str or os.PathLike
        A built-in robot's name or a robot file's path.

    Returns
    -------
    bool
        True for a URDF built-in or a path ending in ``.urdf`` (any case).

    Examples
    --------
    >>> is_urdf("panda"), is_urdf("arm.URDF"), is_urdf("puma560")
    (True, True, False)
    """
    key = str(name_or_path)
    return key in URDF_BUILTIN or Path(key).suffix.lower() == ".urdf"


def builtin_robots():
    """Names of all built-in robots, TOML and URDF.

    Returns
    -------
    list of str
        Sorted, e.g. ``["panda", "puma560", "two-link", "ur5"]``.
    """
    return sorted(set(_toml_builtins()) | set(URDF_BUILTIN))


def load_robot(name_or_path, base=None, tip=None):
    """Load a built-in robot by name, a TOML robot file or a URDF file (dispatch on ``.urdf``).

    Parameters
    ----------
    name_or_path : str or os.PathLike
        A built-in name (:func:`builtin_robots`), a TOML robot file or a ``.urdf`` file.
    base, tip : str, optional
        A URDF chain's base and tip links (``--base``, ``--tip``).

    Returns
    -------
    Robot

    Raises
    ------
    InputError
        If the robot cannot be read (see :func:`gd_analyze.core.robot.load_robot` and
        :func:`gd_analyze.io.urdf.read_urdf_chain`), or base or tip is given for a robot that is
        not a URDF.
    """
    if is_urdf(name_or_path):
        return load_urdf(name_or_path, base, tip)
    if base is not None or tip is not None:
        raise InputError("--base and --tip apply to a URDF robot only", str(name_or_path),
                         column="--base" if base is not None else "--tip")
    return _load_toml(name_or_path)
