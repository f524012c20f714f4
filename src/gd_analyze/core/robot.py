"""Robot model: a serial chain of revolute joints in standard Denavit-Hartenberg form.

A robot is read from a TOML file (see ``src/gd_analyze/data/*.toml``), validated and held in a
frozen :class:`Robot`. Link frame i is attached to the far end of link i, as in Fu, Gonzalez &
Lee (1987), Sec. 2.2.10; joint i turns about z_{i-1}, and the homogeneous transform from frame
i-1 to frame i is Eq. (3.2-5)::

    ^{i-1}A_i = Rot(z, theta_i) Trans(0, 0, d_i) Trans(a_i, 0, 0) Rot(x, alpha_i),
    theta_i = q_i + offset_i.

Per link the model holds the mass m_i, the centre of mass r_i in link frame i, the inertia
tensor I_i about the centre of mass (axes parallel to link frame i), and the joint's position,
velocity and acceleration limits.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from ..errors import InputError

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["Robot", "load_robot", "builtin_robots", "robot_from_dict", "with_payload"]

_BUILTIN = {"puma560": "puma560.toml", "two-link": "two-link.toml"}
_LINK_KEYS = {
    "d", "a", "alpha_deg", "offset_deg", "mass", "com", "inertia",
    "q_limits_deg", "qd_max_deg", "qdd_max_deg",
}


def _readonly(x):
    arr = np.array(x, dtype=float)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class Robot:
    """A serial arm of n revolute joints, standard DH form, with link inertial parameters.

    Every array is read-only. Build one with :func:`load_robot` or :func:`robot_from_dict`.

    Attributes
    ----------
    name : str
        The robot's name, e.g. ``"puma560"``.
    d : ndarray, shape (n,)
        DH link offsets d_i [m].
    a : ndarray, shape (n,)
        DH link lengths a_i [m].
    alpha : ndarray, shape (n,)
        DH twist angles alpha_i [rad].
    offset : ndarray, shape (n,)
        Joint angle offsets, theta_i = q_i + offset_i [rad].
    mass : ndarray, shape (n,)
        Link masses m_i [kg].
    com : ndarray, shape (n, 3)
        Centre of mass r_i of link i in link frame i [m].
    inertia : ndarray, shape (n, 3, 3)
        Inertia tensor I_i of link i about its centre of mass, axes parallel to link frame i,
        symmetric [kg m^2].
    q_min, q_max : ndarray, shape (n,)
        Joint position limits [rad].
    qd_max : ndarray, shape (n,)
        Joint velocity limits [rad/s].
    qdd_max : ndarray, shape (n,)
        Joint acceleration limits [rad/s^2].
    gravity : ndarray, shape (3,)
        Gravity vector g in the base frame [m/s^2], e.g. (0, 0, -9.8062).
    description : str
        A line of text about the robot.
    reference : str
        Where the parameters come from.
    source : str
        The file the robot was read from, or ``"<dict>"``.
    sha256 : str
        SHA-256 of that file's bytes (of the canonical JSON of the dictionary otherwise).

    Notes
    -----
    Source: Fu, Gonzalez & Lee (1987), Secs. 2.2.10 and 3.2; the convention of link frame i at
    the far end of link i is that of the chapter's Eq. (3.2-5).
    """

    name: str
    d: np.ndarray
    a: np.ndarray
    alpha: np.ndarray
    offset: np.ndarray
    mass: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    q_min: np.ndarray
    q_max: np.ndarray
    qd_max: np.ndarray
    qdd_max: np.ndarray
    gravity: np.ndarray
    description: str = ""
    reference: str = ""
    source: str = "<dict>"
    sha256: str = ""

    def __post_init__(self):
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, (np.ndarray, list, tuple)):
                object.__setattr__(self, f.name, _readonly(value))

    @property
    def n(self):
        """int: the number of joints (degrees of freedom)."""
        return int(self.d.shape[0])

    def joint_names(self):
        """Joint labels ``["1", ..., "n"]``.

        Returns
        -------
        list of str
        """
        return [str(i + 1) for i in range(self.n)]

    def to_dict(self):
        """The robot as a dictionary in the robot-file layout (degrees for angles).

        Returns
        -------
        dict
            Keys ``name``, ``description``, ``reference``, ``gravity`` and ``link`` (a list of
            per-link dictionaries); ``robot_from_dict(robot.to_dict())`` rebuilds the robot.
        """
        links = []
        for i in range(self.n):
            I = self.inertia[i]
            links.append({
                "d": float(self.d[i]), "a": float(self.a[i]),
                "alpha_deg": math.degrees(self.alpha[i]),
                "offset_deg": math.degrees(self.offset[i]),
                "mass": float(self.mass[i]), "com": [float(v) for v in self.com[i]],
                "inertia": [float(I[0, 0]), float(I[1, 1]), float(I[2, 2]),
                            float(I[0, 1]), float(I[0, 2]), float(I[1, 2])],
                "q_limits_deg": [math.degrees(self.q_min[i]), math.degrees(self.q_max[i])],
                "qd_max_deg": math.degrees(self.qd_max[i]),
                "qdd_max_deg": math.degrees(self.qdd_max[i]),
            })
        return {"name": self.name, "description": self.description,
                "reference": self.reference, "gravity": [float(v) for v in self.gravity],
                "link": links}

    def with_inertial(self, mass=None, com=None, inertia=None):
        """A copy with some inertial parameters replaced.

        Parameters
        ----------
        mass : array_like, shape (n,), optional
            Link masses [kg].
        com : array_like, shape (n, 3), optional
            Centres of mass in the link frames [m].
        inertia : array_like, shape (n, 3, 3), optional
            Inertia tensors about the centres of mass [kg m^2].

        Returns
        -------
        Robot
        """
        return dataclasses.replace(
            self,
            mass=self.mass if mass is None else mass,
            com=self.com if com is None else com,
            inertia=self.inertia if inertia is None else inertia,
        )


def with_payload(robot, mass, com=(0.0, 0.0, 0.0), inertia=(0.0, 0.0, 0.0)):
    """The robot carrying a rigid load fixed to its last link.

    The load's mass, centre of mass and inertia are merged into link n: the combined centre of
    mass is the mass-weighted mean, and both inertia tensors are carried to it with the
    parallel-axis theorem, I_c = sum_b [I_b + m_b (|d_b|^2 E - d_b d_b^T)], d_b = r_b - r_c.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    mass : float
        Load mass [kg], >= 0.
    com : array_like, shape (3,), optional
        Load centre of mass in link frame n [m].
    inertia : array_like, shape (3,) or (3, 3), optional
        Load inertia about its centre of mass, axes parallel to link frame n: principal moments
        (Ixx, Iyy, Izz) or a full symmetric tensor [kg m^2].

    Returns
    -------
    Robot
        A copy whose last link includes the load; its ``name`` gets a ``+payload`` suffix and
        its ``description`` states the load.

    Raises
    ------
    InputError
        If the mass is negative or not finite, or the inertia is not symmetric positive
        semi-definite.

    Notes
    -----
    Torques depend on the load the arm carries (Fu, Gonzalez & Lee 1987, Sec. 3.1); the load
    enters the G-D terms through link n's mass, centre of mass and inertia tensor.
    """
    mass = float(mass)
    if not math.isfinite(mass) or mass < 0:
        raise InputError(f"payload mass must be a finite number >= 0, got {mass}",
                         column="--payload")
    com_p = np.asarray(com, dtype=float).reshape(3)
    I_p = np.asarray(inertia, dtype=float)
    I_p = np.diag(I_p) if I_p.shape == (3,) else I_p.reshape(3, 3)
    if not np.isfinite(I_p).all() or not np.allclose(I_p, I_p.T) \
            or np.linalg.eigvalsh(I_p).min() < -1e-12:
        raise InputError("payload inertia must be symmetric positive semi-definite",
                         column="--payload-inertia")
    if mass == 0.0 and not I_p.any():
        return robot
    m_l, r_l, I_l = float(robot.mass[-1]), np.array(robot.com[-1]), np.array(robot.inertia[-1])
    m_c = m_l + mass
    r_c = (m_l * r_l + mass * com_p) / m_c if m_c > 0 else r_l

    def shift(m, dvec):
        return m * (dvec @ dvec * np.eye(3) - np.outer(dvec, dvec))

    I_c = I_l + shift(m_l, r_l - r_c) + I_p + shift(mass, com_p - r_c)
    masses, coms, inertias = np.array(robot.mass), np.array(robot.com), np.array(robot.inertia)
    masses[-1], coms[-1], inertias[-1] = m_c, r_c, I_c
    return dataclasses.replace(
        robot, name=f"{robot.name}+payload", mass=masses, com=coms, inertia=inertias,
        description=(f"{robot.description}; payload {mass:g} kg at {com_p.tolist()} m, "
                     f"inertia diag {np.diag(I_p).tolist()} kg m^2").lstrip("; "))


def builtin_robots():
    """Names of the built-in robots.

    Returns
    -------
    list of str
        ``["puma560", "two-link"]``.
    """
    return sorted(_BUILTIN)


def _number(value, path, column):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"expected a number, got {value!r}", path, column=column)
    if not math.isfinite(value):
        raise InputError(f"expected a finite number, got {value!r}", path, column=column)
    return float(value)


def _vector(value, length, path, column):
    if not isinstance(value, (list, tuple)) or len(value) != length:
        raise InputError(f"expected a list of {length} numbers, got {value!r}", path, column=column)
    return [_number(v, path, column) for v in value]


def robot_from_dict(spec, source="<dict>", sha256=None):
    """Validate a robot specification and build a :class:`Robot`.

    Parameters
    ----------
    spec : dict
        The robot-file layout: ``name`` (str), ``gravity`` (3 numbers [m/s^2]), optional
        ``description`` and ``reference``, and ``link``: a list of tables with ``d`` [m], ``a``
        [m], ``alpha_deg`` [deg], optional ``offset_deg`` [deg], ``mass`` [kg], ``com`` (3
        numbers [m]), ``inertia`` (3 numbers Ixx, Iyy, Izz or 6 numbers Ixx, Iyy, Izz, Ixy, Ixz,
        Iyz [kg m^2]), ``q_limits_deg`` (2 numbers [deg]), ``qd_max_deg`` [deg/s] and
        ``qdd_max_deg`` [deg/s^2].
    source : str, optional
        Where the specification came from, for error messages and provenance.
    sha256 : str, optional
        SHA-256 of the source file; by default that of the specification's canonical JSON.

    Returns
    -------
    Robot

    Raises
    ------
    InputError
        On a missing or unknown key, a value that is not a finite number, a negative mass, an
        inertia tensor that is not positive semi-definite, or limits in the wrong order.
        (The triangle inequality is not enforced: published models such as the PUMA 560's lump
        rotor inertia into a link, e.g. I_1 = diag(0, 0.35, 0).) The message names the source and the key (as
        ``link[i].key``).
    """
    if sha256 is None:
        import json

        sha256 = hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()
    path = source
    if not isinstance(spec, dict):
        raise InputError("a robot file must be a table", path)
    name = spec.get("name")
    if not isinstance(name, str) or not name:
        raise InputError("missing robot name", path, column="name")
    if "gravity" not in spec:
        raise InputError("missing gravity vector", path, column="gravity")
    gravity = _vector(spec["gravity"], 3, path, "gravity")
    links = spec.get("link")
    if not isinstance(links, list) or not links:
        raise InputError("no [[link]] tables", path, column="link")
    cols = {k: [] for k in ("d", "a", "alpha", "offset", "mass", "com", "inertia",
                            "q_min", "q_max", "qd_max", "qdd_max")}
    for i, link in enumerate(links, start=1):
        where = f"link[{i}]"
        if not isinstance(link, dict):
            raise InputError("expected a table", path, column=where)
        unknown = set(link) - _LINK_KEYS
        if unknown:
            raise InputError(f"unknown key {sorted(unknown)[0]!r}", path, column=where)
        for key in _LINK_KEYS - {"offset_deg"}:
            if key not in link:
                raise InputError("missing key", path, column=f"{where}.{key}")
        cols["d"].append(_number(link["d"], path, f"{where}.d"))
        cols["a"].append(_number(link["a"], path, f"{where}.a"))
        cols["alpha"].append(math.radians(_number(link["alpha_deg"], path, f"{where}.alpha_deg")))
        cols["offset"].append(math.radians(_number(link.get("offset_deg", 0.0), path,
                                                   f"{where}.offset_deg")))
        m = _number(link["mass"], path, f"{where}.mass")
        if m < 0:
            raise InputError(f"negative mass {m}", path, column=f"{where}.mass")
        cols["mass"].append(m)
        cols["com"].append(_vector(link["com"], 3, path, f"{where}.com"))
        raw = link["inertia"]
        n_in = len(raw) if isinstance(raw, (list, tuple)) else 0
        vals = _vector(raw, 6 if n_in == 6 else 3, path, f"{where}.inertia")
        ixx, iyy, izz = vals[:3]
        ixy, ixz, iyz = vals[3:] if len(vals) == 6 else (0.0, 0.0, 0.0)
        I = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        eig = np.linalg.eigvalsh(I)
        tol = 1e-12 * max(1.0, float(np.abs(I).max()))
        if eig.min() < -tol:
            raise InputError("inertia tensor is not positive semi-definite", path,
                             column=f"{where}.inertia")
        cols["inertia"].append(I)
        lim = _vector(link["q_limits_deg"], 2, path, f"{where}.q_limits_deg")
        if lim[0] >= lim[1]:
            raise InputError("lower limit not below upper limit", path,
                             column=f"{where}.q_limits_deg")
        cols["q_min"].append(math.radians(lim[0]))
        cols["q_max"].append(math.radians(lim[1]))
        for key, col in (("qd_max_deg", "qd_max"), ("qdd_max_deg", "qdd_max")):
            v = _number(link[key], path, f"{where}.{key}")
            if v <= 0:
                raise InputError("limit must be positive", path, column=f"{where}.{key}")
            cols[col].append(math.radians(v))
    return Robot(name=name, gravity=gravity, description=str(spec.get("description", "")),
                 reference=str(spec.get("reference", "")), source=str(source), sha256=sha256,
                 **cols)


def load_robot(name_or_path):
    """Load a built-in robot by name, or a robot file by path.

    Parameters
    ----------
    name_or_path : str or os.PathLike
        ``"puma560"``, ``"two-link"``, or the path of a TOML robot file (layout in
        :func:`robot_from_dict`).

    Returns
    -------
    Robot

    Raises
    ------
    InputError
        If the name is not a built-in robot and no such file exists, if the file is not valid
        TOML, or if it fails validation.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> load_robot("puma560").n
    6
    """
    key = str(name_or_path)
    if key in _BUILTIN:
        res = resources.files("gd_analyze").joinpath("data", _BUILTIN[key])
        raw = res.read_bytes()
        source = key
    else:
        path = Path(key)
        if not path.is_file():
            raise InputError(
                f"unknown robot (built-in: {', '.join(builtin_robots())}) and no such file", key)
        try:
            raw = path.read_bytes()
        except OSError as exc:
            raise InputError(f"cannot read: {exc.strerror}", key) from None
        source = str(path)
    try:
        spec = tomllib.loads(raw.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"not a valid TOML robot file: {exc}", source) from None
    return robot_from_dict(spec, source=source, sha256=hashlib.sha256(raw).hexdigest())
