"""The robot-file layout: validation of a robot specification (TOML or JSON dictionary).

:func:`robot_from_dict` checks every key of the three layouts (standard DH, modified DH and a
general chain of placements; revolute and prismatic joints) and builds a
:class:`~gd_analyze.model.robot.Robot`. Every mistake is reported as one :class:`InputError`
line that names the file, the link and the key. Pure: no files are read here.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import types
import warnings
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError, InputWarning
from .drives import DRIVE_FIELDS, DRIVE_KEYS, drive_values
from .limits import LIMITS, exact_text
from .robot import CONVENTIONS, JOINT_TYPES, Robot, make_robot

if TYPE_CHECKING:
    pass

__all__ = ["robot_from_dict", "robot_from_chain"]


#: Top-level keys of a robot file; others are ignored with an InputWarning.
_TOP_KEYS = {"name", "description", "reference", "gravity", "convention", "link"}


def _number(value, path, column, finite=True, limit=None):
    """A float; ``limit`` names the entry of LIMITS its magnitude may not exceed (when finite)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"expected a number, got {_short(value)}", path, column=column)
    try:
        v = float(value)
    except OverflowError:
        raise InputError("number too large for a float", path, column=column) from None
    if finite and not math.isfinite(v):
        raise InputError(f"expected a finite number, got {v:g}", path, column=column)
    if limit is not None and math.isfinite(v) and abs(v) > LIMITS[limit]:
        raise InputError(f"{exact_text(v)} is beyond the supported magnitude "
                         f"{LIMITS[limit]:g} (see docs/limits-and-safety.md)", path, column=column)
    return v


def _short(value):
    """repr of a value for a message, at most 60 characters; numbers plain (no numpy repr)."""
    if isinstance(value, np.generic):
        value = value.item()
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _vector(value, length, path, column, limit=None):
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)) or len(value) != length:
        raise InputError(f"expected a list of {length} numbers, got {_short(value)}", path,
                         column=column)
    return [_number(v, path, column, limit=limit) for v in value]


def _text(spec, key, path, required=False, column=None, printable=True):
    """A string: a name (``required``) of at most 200 characters, one line of printable ones
    unless not ``printable`` (a joint's name, which a URDF may give with a tab or a newline);
    a description or reference at most 100,000 characters; none with NUL (HDF5 attributes
    cannot hold one)."""
    value, column = spec.get(key, ""), column or key
    if not isinstance(value, str) or (required and not value):
        raise InputError(f"expected a {'non-empty ' if required else ''}string, got "
                         f"{_short(value)}", path, column=column)
    if required and (len(value) > 200 or printable and not value.isprintable()):
        raise InputError("expected at most 200 " + ("printable characters (no control "
                         "characters such as NUL or newline)" if printable else "characters"),
                         path, column=column)
    if len(value) > 100_000 or "\x00" in value:
        raise InputError("expected at most 100000 characters and no NUL", path, column=column)
    return value


def _joint_names(links, path):
    """The links' ``joint_name`` keys: on every link or none, each a name, no two alike."""
    names = [_text(link, "joint_name", path, True, f"link[{i}].joint_name", printable=False)
             if "joint_name" in link else None for i, link in enumerate(links, start=1)]
    for i, name in enumerate(names, start=1):
        if any(names) and (name is None or name in names[:i - 1]):
            raise InputError("joint_name is given on other links: give it on every link or none"
                             if name is None else f"joint_name {name!r} is that of "
                             f"link[{names.index(name) + 1}]", path, column=f"link[{i}].joint_name")
    return names if any(names) else ()


def _degrees(link, key, path, where, default=None):
    """An angle in degrees [deg] -> [rad]; warns when the value looks like radians (1.5708
    typed for 90: within 1e-3 of a nonzero multiple of pi/2, and not an integer)."""
    deg = _number(link.get(key, default) if default is not None else link[key], path,
                  f"{where}.{key}", limit="angle_deg")
    k = round(deg / (math.pi / 2))
    if k != 0 and abs(deg - k * math.pi / 2) < 1e-3 and deg != round(deg):
        warnings.warn(f"{path}: key {where}.{key}: {deg:g} looks like radians ({k} pi/2); "
                      f"the value is read in degrees", InputWarning, stacklevel=3)
    return math.radians(deg)


def _inertia_tensor(raw, path, column):
    """A symmetric positive semi-definite tensor from 3 or 6 numbers or a 3x3 array."""
    arr = np.asarray(raw, dtype=object) if not isinstance(raw, (int, float)) else None
    if arr is not None and arr.shape == (3, 3):
        I = np.array(_vector(arr.ravel().tolist(), 9, path, column, "inertia")).reshape(3, 3)
        if not np.allclose(I, I.T, rtol=0, atol=1e-12 * max(1.0, np.abs(I).max())):
            raise InputError("inertia tensor is not symmetric", path, column=column)
        I = 0.5 * (I + I.T)
    else:
        n_in = len(raw) if isinstance(raw, (list, tuple)) else 0
        vals = _vector(raw, 6 if n_in == 6 else 3, path, column, "inertia")
        ixx, iyy, izz = vals[:3]
        ixy, ixz, iyz = vals[3:] if len(vals) == 6 else (0.0, 0.0, 0.0)
        I = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    tol = 1e-12 * max(1.0, float(np.abs(I).max()))
    if np.linalg.eigvalsh(I).min() < -tol:
        raise InputError("inertia tensor is not positive semi-definite", path, column=column)
    return I


def _inertial(link, path, where):
    """mass, com, inertia of one link table (or joint dict), validated."""
    m = _number(link["mass"], path, f"{where}.mass", limit="mass")
    if m < 0:
        raise InputError(f"negative mass {m}", path, column=f"{where}.mass")
    com = _vector(link["com"], 3, path, f"{where}.com", "length")
    return m, com, _inertia_tensor(link["inertia"], path, f"{where}.inertia")


def _limits(link, path, where, keys, scale=1.0):
    """q_min, q_max, qd_max, qdd_max in SI units from a link's three limit keys ``keys``.

    Every limit is optional (only planning needs them): a missing position range (None) is
    (-inf, inf), a missing velocity or acceleration limit NaN."""
    klim, kqd, kqdd = keys
    lo_hi, qd, qdd = (link.get(k) for k in keys)
    lim = [None, None] if lo_hi is None else lo_hi
    if isinstance(lim, np.ndarray):
        lim = lim.tolist()
    if not isinstance(lim, (list, tuple)) or len(lim) != 2:
        raise InputError(f"expected a list of 2 numbers, got {_short(lim)}", path,
                         column=f"{where}.{klim}")
    # no limit (a continuous joint): inf in TOML, null in JSON (which has no inf)
    lo, hi = (sign * math.inf if v is None else
              _number(v, path, f"{where}.{klim}", finite=False, limit="angle_deg")
              for sign, v in zip((-1, 1), lim))
    if math.isnan(lo) or math.isnan(hi) or lo >= hi:
        raise InputError(f"lower limit {lo:g} not below upper limit {hi:g} (leave the key out "
                         "where the joint has no position limits)", path,
                         column=f"{where}.{klim}")
    out = []
    for value, key in ((qd, kqd), (qdd, kqdd)):
        v = _number(value, path, f"{where}.{key}", finite=False, limit="angle_deg") \
            if value is not None else math.nan
        if math.isnan(v):                      # not given (null in a model file's JSON)
            out.append(math.nan)
            continue
        if math.isinf(v):
            raise InputError("expected a finite number, got inf (leave the key out where "
                             "there is no limit)", path, column=f"{where}.{key}")
        if v <= 0:
            raise InputError(f"limit must be positive, got {v:g} (leave the key out where "
                             "there is none)", path, column=f"{where}.{key}")
        out.append(v)
    return lo * scale, hi * scale, out[0] * scale, out[1] * scale


def _effort(link, path, where):
    """The effort limit tau_max [N m or N], NaN where not given."""
    value = link.get("tau_max")
    v = (math.nan if value is None else
         _number(value, path, f"{where}.tau_max", finite=False, limit="mass"))
    if value is None:
        return math.nan
    if not math.isfinite(v):            # NaN is not "no limit": leave the key out for that
        raise InputError(f"expected a finite number, got {v:g} (leave the key out where there "
                         "is no limit)", path, column=f"{where}.tau_max")
    if v <= 0:
        raise InputError(f"limit must be positive, got {v:g} (leave the key out where there "
                         "is none)", path, column=f"{where}.tau_max")
    return v


_INERTIAL_KEYS = {"mass", "com", "inertia"}
#: Keys every link may have whatever its layout: the joint's name.
_NAME_KEYS = {"joint_name"}
#: Keys every link may have: limits (only planning needs them) and the effort limit.
_LIMIT_KEYS = {"revolute": {"q_limits_deg", "qd_max_deg", "qdd_max_deg", "tau_max"},
               "prismatic": {"q_limits", "qd_max", "qdd_max", "tau_max"},
               "chain": {"q_limits", "qd_max", "qdd_max", "tau_max"}}
_KEYS = {
    ("standard", "revolute"): ({"d", "a", "alpha_deg"},
                               {"offset_deg", "joint"} | _LIMIT_KEYS["revolute"]),
    ("standard", "prismatic"): ({"a", "alpha_deg"},
                                {"theta_deg", "offset", "joint"} | _LIMIT_KEYS["prismatic"]),
    ("chain", "revolute"): ({"rotation", "translation"}, {"joint"} | _LIMIT_KEYS["chain"]),
}
_KEYS[("modified", "revolute")] = _KEYS[("standard", "revolute")]
_KEYS[("modified", "prismatic")] = _KEYS[("standard", "prismatic")]
_KEYS[("chain", "prismatic")] = _KEYS[("chain", "revolute")]
_HINT = {"d": "q is d for a prismatic joint (a constant part is 'offset' [m])",
         "offset_deg": "a prismatic joint's fixed angle is 'theta_deg'",
         "theta_deg": "a revolute joint's angle offset is 'offset_deg'",
         "offset": "a revolute joint's angle offset is 'offset_deg'",
         "q_limits_deg": "a prismatic joint's limits are 'q_limits' [m]",
         "qd_max_deg": "a prismatic joint's limit is 'qd_max' [m/s]",
         "qdd_max_deg": "a prismatic joint's limit is 'qdd_max' [m/s^2]",
         "q_limits": "a revolute joint's limits are 'q_limits_deg' [deg]",
         "qd_max": "a revolute joint's limit is 'qd_max_deg' [deg/s]",
         "qdd_max": "a revolute joint's limit is 'qdd_max_deg' [deg/s^2]"}


def _check_keys(link, convention, joint, path, where):
    required, optional = _KEYS[(convention, joint)]
    required = required | _INERTIAL_KEYS
    unknown = sorted(set(link) - required - optional - set(DRIVE_KEYS) - _NAME_KEYS)
    if unknown:
        key = unknown[0]
        hint = f" ({_HINT[key]})" if key in _HINT and convention != "chain" else ""
        raise InputError(f"unknown key {key!r} for a {joint} joint in the {convention} "
                         f"convention{hint}", path, column=f"{where}.{key}")
    for key in sorted(required):
        if key not in link:
            raise InputError(f"missing key for a {joint} joint", path, column=f"{where}.{key}")


def _rotation(value, path, column):
    arr = np.asarray(value, dtype=object)
    if arr.shape != (3, 3):
        raise InputError(f"expected a 3x3 rotation matrix, got {value!r}", path, column=column)
    R = np.array(_vector(arr.ravel().tolist(), 9, path, column)).reshape(3, 3)
    if not np.allclose(R @ R.T, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise InputError("not a rotation matrix (R R^T = E, det R = +1)", path, column=column)
    return R


def robot_from_dict(spec: Mapping[str, Any], source: str = "<dict>",
                    sha256: str | None = None) -> Robot:
    """Validate a robot specification and build a :class:`~gd_analyze.model.robot.Robot`.

    Parameters
    ----------
    spec : dict
        The robot-file layout: ``name`` (str), ``gravity`` (3 numbers [m/s^2]), optional
        ``description``, ``reference`` and ``convention`` (``"standard"``, the default, or
        ``"modified"`` DH; ``"chain"`` for general placements), and ``link``: a list of
        tables, one per joint from the base, each with ``joint`` (``"revolute"``, the default,
        or ``"prismatic"``), ``mass`` [kg], ``com`` (3 numbers [m]) and ``inertia`` (3 numbers
        Ixx, Iyy, Izz, or 6 numbers Ixx, Iyy, Izz, Ixy, Ixz, Iyz, tensor elements [kg m^2]),
        both in link frame i, and

        - revolute, DH: ``d`` [m], ``a`` [m], ``alpha_deg`` [deg], optional ``offset_deg``
          [deg] (theta_i = q_i + offset), optional ``q_limits_deg`` (2 numbers [deg]),
          ``qd_max_deg`` [deg/s], ``qdd_max_deg`` [deg/s^2];
        - prismatic, DH: optional ``theta_deg`` [deg] (the fixed theta_i), ``a`` [m],
          ``alpha_deg`` [deg], optional ``offset`` [m] (d_i = q_i + offset), optional
          ``q_limits`` [m], ``qd_max`` [m/s], ``qdd_max`` [m/s^2];
        - chain: ``rotation`` (3x3) and ``translation`` (3 numbers [m]), the placement of the
          joint in the previous body frame, and optional ``q_limits``, ``qd_max``, ``qdd_max``
          in SI units (rad or m); position limits may be infinite.

        Every link may give ``tau_max``, its effort limit [N m; N for a prismatic joint].
        Limits are optional: only ``plan`` and ``sweep --random`` need velocity limits; a
        missing position range is none (-inf, inf).

        Every link may give its drive (:mod:`gd_analyze.model.drives`), all optional, >= 0:
        ``armature`` [kg m^2] (prismatic: [kg]), or instead ``rotor_inertia`` [kg m^2] and
        ``gear_ratio`` [-] (armature = rotor_inertia * gear_ratio^2); ``viscous``
        [N m s/rad] (N s/m) and ``coulomb`` [N m] (N), link-side friction, and
        ``torque_offset`` [N m] (N), a constant torque of either sign.

        In the modified convention link i's row holds Craig's alpha_{i-1}, a_{i-1}, d_i and
        theta_i (as the Robotics Toolbox's ``RevoluteMDH`` and ``PrismaticMDH`` take them), and
        the centre of mass and inertia are in modified-DH frame i.
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
        rotor inertia into a link, e.g. I_1 = diag(0, 0.35, 0).) The message names the source
        and the key (as ``link[i].key``).
    """
    if sha256 is None:
        import json

        sha256 = hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()
    path = source
    if not isinstance(spec, dict):
        raise InputError("a robot file must be a table", path)
    if "name" not in spec:
        raise InputError("missing robot name", path, column="name")
    name = _text(spec, "name", path, required=True)
    description, reference = _text(spec, "description", path), _text(spec, "reference", path)
    for key in sorted(set(spec) - _TOP_KEYS):
        warnings.warn(f"{path}: unknown key {key!r} ignored (known: "
                      f"{', '.join(sorted(_TOP_KEYS))})", InputWarning, stacklevel=2)
    if "gravity" not in spec:
        raise InputError("missing gravity vector", path, column="gravity")
    gravity = _vector(spec["gravity"], 3, path, "gravity", "gravity")
    convention = spec.get("convention", "standard")
    if convention not in CONVENTIONS:
        raise InputError(f"convention must be 'standard' or 'modified' (or 'chain'), got "
                         f"{convention!r}", path, column="convention")
    links = spec.get("link")
    if not isinstance(links, list) or not links:
        raise InputError("no [[link]] tables", path, column="link")
    cols: dict[str, list[Any]] = {k: [] for k in ("d", "a", "alpha", "offset", "mass", "com", "inertia", "q_min",
                            "q_max", "qd_max", "qdd_max", "prismatic", "rotation",
                            "translation", "tau_max", "armature", "viscous", "coulomb",
                            "torque_offset")}
    for i, link in enumerate(links, start=1):
        where = f"link[{i}]"
        if not isinstance(link, dict):
            raise InputError("expected a table", path, column=where)
        joint = link.get("joint", "revolute")
        if joint not in JOINT_TYPES:
            raise InputError(f"joint must be 'revolute' or 'prismatic', got {joint!r}", path,
                             column=f"{where}.joint")
        pris = joint == "prismatic"
        _check_keys(link, convention, joint, path, where)
        m, com, I = _inertial(link, path, where)
        if convention == "chain":
            cols["rotation"].append(_rotation(link["rotation"], path, f"{where}.rotation"))
            cols["translation"].append(_vector(link["translation"], 3, path,
                                               f"{where}.translation", "length"))
            for key in ("d", "a", "alpha", "offset"):
                cols[key].append(math.nan)
        elif pris:
            cols["d"].append(_number(link.get("offset", 0.0), path, f"{where}.offset",
                                     limit="length"))
            cols["a"].append(_number(link["a"], path, f"{where}.a", limit="length"))
            cols["alpha"].append(_degrees(link, "alpha_deg", path, where))
            cols["offset"].append(_degrees(link, "theta_deg", path, where, 0.0))
        else:
            cols["d"].append(_number(link["d"], path, f"{where}.d", limit="length"))
            cols["a"].append(_number(link["a"], path, f"{where}.a", limit="length"))
            cols["alpha"].append(_degrees(link, "alpha_deg", path, where))
            cols["offset"].append(_degrees(link, "offset_deg", path, where, 0.0))
        deg = "_deg" if convention != "chain" and not pris else ""     # DH revolute: degrees
        keys = (f"q_limits{deg}", f"qd_max{deg}", f"qdd_max{deg}")
        lims = _limits(link, path, where, keys, scale=math.pi / 180 if deg else 1.0)
        cols["prismatic"].append(pris)
        for key, v in zip(DRIVE_FIELDS, drive_values(link, path, where)):
            cols[key].append(v)
        cols["mass"].append(m)
        cols["com"].append(com)
        cols["inertia"].append(I)
        for key, v in zip(("q_min", "q_max", "qd_max", "qdd_max"), lims):
            cols[key].append(v)
        cols["tau_max"].append(_effort(link, path, where))
    if convention != "chain":
        del cols["rotation"], cols["translation"]
    names = _joint_names(links, path)
    return make_robot(name=name, gravity=gravity, description=description,
                 reference=reference, source=str(source), sha256=sha256,
                 convention=convention, **cols,
                 **({"metadata": {"urdf_joints": list(names)}} if names else {}))


def robot_from_chain(name: str, joints: Sequence[Mapping[str, Any]], gravity: ArrayLike,
                     **metadata: Any) -> Robot:
    """Build a :class:`~gd_analyze.model.robot.Robot` from general joint placements (the URDF
    route).

    Parameters
    ----------
    name : str
        The robot's name.
    joints : list of dict
        One per moving joint from the base, each with ``"type"`` (``"revolute"`` or
        ``"prismatic"``), ``"rotation"`` (3x3) and ``"translation"`` (3 [m]): the fixed
        placement of the joint in the previous body frame (the base for the first joint); the
        joint then turns about or slides along the placed frame's z axis. ``"mass"`` [kg],
        ``"com"`` (3 [m]) and ``"inertia"`` (3x3 [kg m^2], about the centre of mass), both in
        this joint's body frame; optional ``"q_min"``, ``"q_max"`` [rad or m] (may be -inf,
        inf; default none), ``"qd_max"`` [rad/s or m/s], ``"qdd_max"`` [rad/s^2 or m/s^2] and
        ``"tau_max"`` [N m or N] (None or NaN when not given); optional drive keys
        ``"armature"`` [kg m^2], ``"viscous"`` [N m s/rad], ``"coulomb"`` [N m] and
        ``"torque_offset"`` [N m] (:mod:`gd_analyze.model.drives`).
    gravity : array_like, shape (3,)
        Gravity in the base frame [m/s^2].
    **metadata
        ``description``, ``reference``, ``source`` (file, also used in error messages) and
        ``sha256`` become the robot's fields; any other key (e.g. ``base_link``,
        ``tip_link``) goes to ``Robot.metadata``.

    Returns
    -------
    Robot
        ``convention == "chain"``; the DH fields d, a, alpha, offset are NaN.

    Raises
    ------
    InputError
        On a missing key, an unknown joint type, a placement that is not a rotation, a negative
        mass, an inertia that is not symmetric positive semi-definite, or bad limits; the
        message names the key as ``joint[i].key``, and the joint's own name when
        ``urdf_joints`` is given.

    Examples
    --------
    >>> import numpy as np
    >>> robot = robot_from_chain("slider", [{
    ...     "type": "prismatic", "rotation": np.eye(3), "translation": [0, 0, 0.1],
    ...     "mass": 2.0, "com": [0, 0, 0], "inertia": np.eye(3) * 0.01,
    ...     "q_min": 0.0, "q_max": 0.5, "qd_max": 1.0, "qdd_max": None}], [0, 0, -9.81])
    >>> robot.joint_types, float(robot.qdd_max[0]) != float(robot.qdd_max[0])
    (('prismatic',), True)
    """
    fields = {k: metadata.pop(k) for k in ("description", "reference", "source", "sha256")
              if k in metadata}
    path, names = fields.get("source"), metadata.get("urdf_joints") or ()
    gravity = np.asarray(gravity, dtype=float).tolist()
    if not isinstance(joints, (list, tuple)) or not joints:
        raise InputError("a chain needs at least one moving joint", path, column="joint")
    links = []
    for i, j in enumerate(joints, start=1):
        where = f"joint[{i}]"
        for key in ("type", "rotation", "translation", "mass", "com", "inertia"):
            if key not in j:
                raise InputError("missing key", path, column=f"{where}.{key}")
        link = {"joint": j["type"], "rotation": np.asarray(j["rotation"]).tolist(),
                "translation": np.asarray(j["translation"]).tolist(), "mass": j["mass"],
                "com": np.asarray(j["com"]).tolist(),
                "inertia": np.asarray(j["inertia"], dtype=float).tolist(),
                "q_limits": [float(j.get("q_min", -math.inf)), float(j.get("q_max", math.inf))]}
        if names:   # a URDF's joint names: those a robot file takes (robot_toml writes them)
            link["joint_name"] = names[i - 1]
        given = {k: j[k] for k in ("qd_max", "qdd_max", "tau_max") if j.get(k) is not None}
        link.update({k: v for k, v in given.items()         # None or NaN: not given
                     if not (isinstance(v, float) and math.isnan(v))})
        link.update({k: float(j[k]) for k in DRIVE_FIELDS if j.get(k)})              # drives: optional, zero when absent
        links.append(link)
    spec = {"name": name, "gravity": gravity, "convention": "chain", "link": links,
            "description": fields.get("description", ""),
            "reference": fields.get("reference", "")}
    try:
        robot = robot_from_dict(spec, source=path or "<chain>", sha256=fields.get("sha256"))
    except InputError as err:
        col = (err.column or "").replace("link[", "joint[").replace(".joint_name", ".name")
        col = col.replace(".joint", ".type").replace(".q_limits", ".q_min/q_max")
        k = int(col[len("joint["):col.index("]")]) if col.startswith("joint[") else 0
        if col == "name" and names:         # a URDF's name, or a Pinocchio model's
            col = "model.name" if path == "pinocchio.Model" else "<robot name>"
        elif 1 <= k <= len(names):
            col = f"{col} (joint {str(names[k - 1])!r})"
        raise InputError(err.message, path, column=col or None) from None
    return dataclasses.replace(robot, metadata=types.MappingProxyType(metadata),
                               source=str(path) if path else "<chain>")
