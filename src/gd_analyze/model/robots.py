"""Loading a robot from any source: a built-in name, a TOML or URDF file, URDF text, a Pinocchio
model.

TOML robot files and the TOML built-ins are read by :func:`load_toml_robot` (the layout is
checked by :func:`gd_analyze.model.robot_spec.robot_from_dict`); URDF
files (suffix ``.urdf``) and the URDF built-ins (``panda``, ``ur5``) by
:func:`gd_analyze.model.urdf.load_urdf`, which needs Pinocchio's parser and therefore lives above
the core; URDF text (a ``robot_description``) by :func:`gd_analyze.model.urdf.load_urdf_text` and a
``pinocchio.Model`` by :func:`gd_analyze.model.urdf.load_pinocchio_model`.
"""

from __future__ import annotations

import hashlib
import os
import warnings
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError, InputNote, expect, regular_file
from .robot_spec import robot_from_dict
from .urdf import URDF_BUILTIN, is_urdf_text, load_pinocchio_model, load_urdf, load_urdf_text

if TYPE_CHECKING:                       # for the type hints only
    import pinocchio

    from .robot import Robot

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

__all__ = ["load_robot", "load_toml_robot", "builtin_robots", "is_urdf", "TOML_BUILTIN",
           "unknown_robot", "robots_text"]

#: The built-in TOML robots: name -> file in gd_analyze/data, every ``*.toml`` there, named by
#: its stem (a new built-in TOML robot is one new file in that folder).
TOML_BUILTIN = {p.name[:-len(".toml")]: p.name
                for p in sorted(resources.files("gd_analyze").joinpath("data").iterdir(),
                                key=lambda p: p.name)
                if p.name.endswith(".toml")}


def is_urdf(name_or_path: str | os.PathLike[str]) -> bool:
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


def builtin_robots() -> list[str]:
    """Names of all built-in robots, TOML and URDF.

    Returns
    -------
    list of str
        Sorted, e.g. ``["panda", "puma560", "two-link", "ur5"]``.
    """
    return sorted(set(TOML_BUILTIN) | set(URDF_BUILTIN))


def robots_text() -> str:
    """The built-in robots as the help, the errors and the README list them.

    Returns
    -------
    str
        E.g. ``"panda, puma560, stanford, two-link, ur5"``: :func:`builtin_robots`, joined.
    """
    return ", ".join(builtin_robots())


def unknown_robot(name: str) -> InputError:
    """The error for a robot argument that is neither a built-in robot nor a file.

    Parameters
    ----------
    name : str
        The argument as given.

    Returns
    -------
    InputError
        ``unknown robot 'pand': did you mean 'panda'? (no such file; built-in: ...; or a
        TOML or URDF robot file)``; without the question when no built-in name is close.
    """
    import difflib

    name = str(name)
    close = difflib.get_close_matches(name, builtin_robots(), n=1, cutoff=0.6)
    guess = f": did you mean {close[0]!r}?" if close else ""
    shown = name if len(name) <= 80 else name[:77] + "..."
    return InputError(f"unknown robot {shown!r}{guess} (no such file; built-in: "
                      f"{robots_text()}; or a TOML or URDF robot file)")


def load_robot(name_or_path: str | os.PathLike[str] | pinocchio.Model, base: str | None = None,
               tip: str | None = None) -> Robot:
    """Load a robot: a built-in name, a TOML or URDF file, URDF text or a Pinocchio model.

    Parameters
    ----------
    name_or_path : str, os.PathLike or pinocchio.Model
        A built-in name (:func:`builtin_robots`); a TOML robot file or a ``.urdf`` file; a URDF
        document as text (after optional blanks, an XML declaration and comments, ``<robot``:
        :func:`gd_analyze.model.urdf.is_urdf_text`), read as a URDF file is; or a
        ``pinocchio.Model`` (:func:`gd_analyze.model.urdf.load_pinocchio_model`).
    base, tip : str, optional
        A URDF chain's base and tip links (``--base``, ``--tip``).

    Returns
    -------
    Robot

    Raises
    ------
    InputError
        If the argument is none of these (:func:`unknown_robot`), the robot cannot be read
        (see :func:`load_toml_robot` and :func:`gd_analyze.model.urdf.read_urdf_chain`), or base
        or tip is given for a robot that is not a URDF or a Pinocchio model.

    Examples
    --------
    >>> load_robot('<robot name="arm"><link name="a"/></robot>')
    Traceback (most recent call last):
    ...
    gd_analyze.errors.InputError: URDF text: --base: no moving joint below the base link 'a'
    """
    if _is_pinocchio_model(name_or_path):
        return load_pinocchio_model(name_or_path, base, tip)
    if is_urdf_text(name_or_path):
        return load_urdf_text(name_or_path, base, tip)
    expect(name_or_path, (str, os.PathLike), "robot", "a built-in name, a TOML or URDF file, "
           "URDF text or a pinocchio.Model")
    if str(name_or_path).lstrip().startswith("<"):
        raise InputError("not URDF text: a URDF document must begin with <robot (after "
                         "optional blanks, an XML declaration and comments)")
    if is_urdf(name_or_path):
        return load_urdf(name_or_path, base, tip)
    key = str(name_or_path)
    if key not in TOML_BUILTIN and not os.path.exists(Path(key)):     # False for a NUL, too
        raise unknown_robot(key)
    if base is not None or tip is not None:
        raise InputError("--base and --tip apply to a URDF robot only", str(name_or_path),
                         column="--base" if base is not None else "--tip")
    return load_toml_robot(name_or_path)


def _is_pinocchio_model(value):
    """Whether a value is a ``pinocchio.Model`` (without importing Pinocchio for a name)."""
    module = type(value).__module__ or ""
    if not module.startswith("pinocchio"):
        return False
    import pinocchio

    return isinstance(value, pinocchio.Model)


def load_toml_robot(name_or_path: str | os.PathLike[str]) -> Robot:
    """Load a built-in TOML robot by name, or a TOML robot file by path.

    Parameters
    ----------
    name_or_path : str or os.PathLike
        A built-in name (:data:`TOML_BUILTIN`), or the path of a TOML robot file (layout in
        :func:`robot_from_dict`).

    Returns
    -------
    Robot

    Raises
    ------
    InputError
        If the name is not a built-in robot and no such file exists, if the file is not valid
        TOML (XML, a URDF or xacro file not named ``*.urdf``, is said to be), or if it fails
        validation. A UTF-8 byte-order mark at the start of the file is
        stripped, with an :class:`~gd_analyze.errors.InputNote`.

    Examples
    --------
    >>> load_toml_robot("puma560").n
    6
    """
    key = str(name_or_path)
    if key in TOML_BUILTIN:
        raw = resources.files("gd_analyze").joinpath(f"data/{TOML_BUILTIN[key]}").read_bytes()
        source = key
    else:
        path = Path(key)
        if not key or not os.path.exists(key):     # "" is no folder, though Path("") is "."
            raise InputError(f"unknown robot (built-in: {robots_text()}) and no such file", key)
        regular_file(key, "a robot file")
        try:
            raw = path.read_bytes()
        except OSError as exc:
            raise InputError(f"cannot read: {exc.strerror}", key) from None
        source = str(path)
    if raw.startswith(b"\xef\xbb\xbf"):       # as Windows editors write it; TOML allows none
        warnings.warn(f"{source}: stripped the UTF-8 byte-order mark at the start of the file",
                      InputNote, stacklevel=2)
    try:
        spec = tomllib.loads(raw.decode("utf-8").removeprefix("\ufeff"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        why = ("XML, not TOML (a URDF file's name ends in .urdf; a xacro file needs xacro first)"
               if raw.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<") else f"not UTF-8 text (byte "
               f"{exc.start + 1})" if isinstance(exc, UnicodeDecodeError) else exc)
        raise InputError(f"not a valid TOML robot file: {why}", source) from None
    except RecursionError:
        raise InputError("not a robot file: nested too deeply", source) from None
    return robot_from_dict(spec, source=source, sha256=hashlib.sha256(raw).hexdigest())
