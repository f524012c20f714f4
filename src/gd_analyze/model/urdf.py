"""URDF import: the serial chain from a base link to a tip link, read through Pinocchio.

The file is parsed by Pinocchio's URDF parser (``pinocchio.buildModelFromXML`` on the file's
bytes, the parser of ``buildModelFromUrdf``; Carpentier et al., "The Pinocchio C++ library", SII
2019), which already merges the links of fixed joints into their parent link. That parser drops
an ``<inertial>`` it cannot read and goes on, so the file is first read by
:mod:`gd_analyze.model.urdf_xml`, which refuses broken inertials, document type declarations and
``<mimic>`` joints the chain would get wrong, and checks the inertias Pinocchio loaded. The chain kept runs from ``base`` to ``tip``; every other moving joint (side
branches such as a gripper's fingers, links beyond the tip, joints above the base) is locked at
q = 0 and its links are carried rigidly by the chain link they hang from
(``pinocchio.buildReducedModel``).

Each moving joint of the chain becomes one joint of the gd-analyze joint model: a fixed placement
(rotation R_i, translation p_i) from the previous body frame (body i-1 after its joint's motion;
the base link's frame for i = 1), then a motion about (revolute) or along (prismatic) the local
z axis. A URDF joint whose axis is not +z gets its body frame turned by the smallest rotation A_i
that takes z onto the axis: the placement becomes A_{i-1}^T P_i A_i (B^{-1} P_1 A_1 for the
first joint, B the base link's frame) and the centre of mass and inertia tensor are expressed in
the turned frame (A_i^T r_i, A_i^T I_i A_i). A continuous joint is a revolute joint without
position limits. URDF has no acceleration limits: ``qdd_max`` is None. ROS's placeholders for an
unset limit mean "not given": ``lower = upper`` (no position limits), ``velocity="0"`` and
``effort="0"`` (NaN), and so does a position limit beyond any joint's travel (SDF's 1e16); only
planning needs the limits.

A placement's rotation whose every entry lies within :data:`RIGHT_ANGLE_TOL` of 0 or +-1 is
taken as that exact signed permutation (:func:`right_angle_rotation`): URDF files write pi and
pi/2 with a few digits (``rpy="0 3.14159265359 0"``: sin is -2.1e-13, not 0), and such a turn is
meant as an exact one. Left as read, the regressor's columns that the turn makes dependent are
dependent only to 1e-12, so the base parameters' regrouping (Gautier 1990) would be exact for
another arm than the one the models are checked against. The G-D terms, Pinocchio's reference
(built from the same placements) and every model use the turn as taken.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import os
import re
import tempfile
import threading
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeGuard

import numpy as np

from ..errors import InputError, regular_file
from .limits import LIMITS, exact_text
from .mounting import MOUNTING_KEY
from .robot_spec import robot_from_chain
from .urdf_xml import check_inertias, check_mimic, read_urdf_xml

if TYPE_CHECKING:                       # for the type hints only
    import pinocchio
    from numpy.typing import ArrayLike

    from .robot import Robot

__all__ = ["UrdfChain", "read_urdf_chain", "load_urdf", "URDF_BUILTIN", "axis_rotation",
           "right_angle_rotation", "RIGHT_ANGLE_TOL", "builtin_urdf_path"]

#: Built-in robots vendored as URDF files in ``gd_analyze/data`` (``data/robots/`` in the
#: repository): file, chain and the text the reports show.
URDF_BUILTIN: dict[str, dict[str, Any]] = {
    "panda": {
        "file": "panda.urdf", "base": "panda_link0", "tip": "panda_hand",
        "description": (
            "Franka Emika Panda, 7 revolute joints; the flange (panda_link8), the hand and both "
            "fingers are merged into link 7, fingers locked at q = 0; full inertia tensors"),
        "reference": (
            "panda.urdf of example-robot-data 6.0.0 (PyPI; upstream franka_ros "
            "franka_description, Apache-2.0), read with pinocchio.buildModelFromUrdf"),
    },
    "ur5": {
        "file": "ur5.urdf", "base": "base_link", "tip": "wrist_3_link",
        "description": (
            "Universal Robots UR5, 6 revolute joints (ee_link and tool0 merged into link 6). "
            "Simplified inertials: diagonal inertia tensors and centres of mass at the link "
            "origins (upper arm and forearm: on the link axis, 0.28 m and 0.25 m out), not "
            "measured values"),
        "reference": (
            "ur5_robot.urdf of example-robot-data 6.0.0 (PyPI; upstream ros-industrial "
            "universal_robot ur_description, BSD), read with pinocchio.buildModelFromUrdf"),
        # its inertia tensors are the URDF's cylinder stand-ins, not measured: the reports say
        # so wherever they state what the rotational parts do
        "placeholder_inertia": True,
    },
}

_TOL = 1e-12
#: Entries of a placement's rotation within this of 0 or +-1 make it an exact right-angle turn
#: (:func:`right_angle_rotation`): 1e-10 takes pi and pi/2 written with 11 or more digits, and
#: keeps the arm within 1e-10 of the file's (a turn 1.8e-9 off, pi/2 as 1.570796325, stays).
RIGHT_ANGLE_TOL = 1e-10
#: One thread at a time sends the C stderr (file descriptor 2) to a file while urdfdom parses.
_C_STDERR = threading.Lock()


def right_angle_rotation(R: ArrayLike) -> np.ndarray:
    """A rotation matrix, as the exact signed permutation it is within :data:`RIGHT_ANGLE_TOL`.

    Parameters
    ----------
    R : array_like, shape (3, 3)
        A rotation matrix (a URDF placement's).

    Returns
    -------
    ndarray, shape (3, 3)
        Every entry rounded to 0 or +-1 when every entry lies within :data:`RIGHT_ANGLE_TOL` of
        one of them and the rounded matrix is a rotation (orthogonal, determinant +1); R
        unchanged otherwise.

    Examples
    --------
    >>> import numpy as np
    >>> c, s = np.cos(3.14159265359), np.sin(3.14159265359)      # pi to 12 digits
    >>> right_angle_rotation([[c, 0, s], [0, 1, 0], [-s, 0, c]]).tolist()
    [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]
    >>> t = 0.3                                                 # a turn of 0.3 rad stays
    >>> R = [[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1]]
    >>> bool(np.array_equal(right_angle_rotation(R), R))
    True
    """
    R = np.asarray(R, float)
    rounded = np.round(R)
    if (np.abs(R - rounded).max(initial=0.0) <= RIGHT_ANGLE_TOL
            and np.array_equal(rounded @ rounded.T, np.eye(3))
            and round(float(np.linalg.det(rounded))) == 1):
        return rounded + 0.0                                    # no -0.0
    return R


def _pin():
    import pinocchio

    return pinocchio


@dataclass(frozen=True, eq=False)
class UrdfChain:
    """The serial chain read from a URDF file, in the gd-analyze joint model.

    Attributes
    ----------
    name : str
        The robot's name (the URDF ``<robot name>``, or as given).
    joints : tuple of dict
        One per moving joint from the base: ``type`` ("revolute" or "prismatic"), ``rotation``
        (ndarray, shape (3, 3)) and ``translation`` (ndarray, shape (3,) [m]): the fixed
        placement from the previous body frame; ``mass`` [kg]; ``com`` (shape (3,) [m]) and
        ``inertia`` (shape (3, 3) [kg m^2], about the centre of mass), both in this joint's
        body frame; ``q_min``, ``q_max`` [rad or m] (infinite for a continuous joint);
        ``qd_max`` [rad/s or m/s] (NaN where not given); ``qdd_max`` None (URDF has no
        acceleration limits); ``tau_max`` [N m or N], the ``effort`` limit (NaN where not
        given).
    gravity : ndarray, shape (3,)
        Gravity in the base link's frame [m/s^2].
    joint_names, link_names : tuple of str
        The URDF names of the chain's joints and of the link each one moves.
    base, tip : str
        The base and tip links.
    locked : tuple of str
        Moving URDF joints off the chain, locked at q = 0 and merged.
    metadata : dict
        ``description``, ``reference``, ``source`` and ``sha256`` (of the file's bytes), and
        ``base_link``, ``tip_link``, ``urdf_joints`` (the chain's joint names) and
        ``locked_joints``, for :func:`gd_analyze.model.robot_spec.robot_from_chain`.
    """

    name: str
    joints: tuple
    gravity: np.ndarray
    joint_names: tuple
    link_names: tuple
    base: str
    tip: str
    locked: tuple = ()
    metadata: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        """int: the number of joints of the chain."""
        return len(self.joints)


def axis_rotation(axis: ArrayLike) -> np.ndarray:
    """The smallest rotation that takes the z axis onto a unit axis.

    Parameters
    ----------
    axis : array_like, shape (3,)
        The joint axis (normalised here).

    Returns
    -------
    ndarray, shape (3, 3)
        A with ``A @ (0, 0, 1) = axis``; exactly the identity for +z and diag(1, -1, -1) for -z.

    Raises
    ------
    ValueError
        If the axis is zero or not finite.

    Notes
    -----
    Rodrigues' formula about k = z x a / |z x a| with cos = z . a and sin = |z x a|, so axes
    along x or y give rotations with exact 0 and +-1 entries.

    Examples
    --------
    >>> axis_rotation([0, 1, 0]) @ [0, 0, 1]
    array([0., 1., 0.])
    """
    a: np.ndarray = np.asarray(axis, dtype=float).reshape(3)
    norm = float(np.linalg.norm(a))
    if not math.isfinite(norm) or norm == 0.0:
        raise ValueError(f"not a joint axis: {a.tolist()}")
    a = a / norm
    v = np.array([-a[1], a[0], 0.0])                           # z x a
    s = float(np.linalg.norm(v))
    c = float(a[2])
    if s < _TOL:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = v / s
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def _parse_model(raw, label):
    """Pinocchio's model of a URDF document's bytes, and the document as read by
    :mod:`gd_analyze.model.urdf_xml`; ``label`` names the document in errors. A document
    urdfdom refuses is refused with urdfdom's first reason, which it prints on the C stderr
    (captured here: the error stays one line); what it prints about a file it reads is
    passed on."""
    pin = _pin()
    doc = read_urdf_xml(raw, label)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text (byte {exc.start + 1})", label) from None
    with _C_STDERR, tempfile.TemporaryFile() as said:  # urdfdom's reasons, on the C stderr
        saved = os.dup(2)
        os.dup2(said.fileno(), 2)
        try:
            # the bytes just checked, not the file again (it could have changed since)
            model = pin.buildModelFromXML(text)
        except (ValueError, RuntimeError, OSError) as exc:
            said.seek(0)
            why = (re.findall(r"Error:[ \t]*(.+)", said.read().decode(errors="replace"))
                   + str(exc).strip().splitlines() + [type(exc).__name__])
            raise InputError(f"not a valid URDF file: {why[0].strip()}", label) from None
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        said.seek(0)
        os.write(2, said.read())        # a warning about a file it reads
    check_inertias(doc, model, label)
    return model, raw, doc


def _joint_body(model, links, j):
    """The link that joint j moves (the BODY frame right after its JOINT frame)."""
    pin = _pin()
    jf = model.getFrameId(model.names[j], pin.FrameType.JOINT)
    return next((name for name, k in links.items() if model.frames[k].parentFrame == jf),
                model.names[j])


def _root_link(model, links):
    roots = [name for name, k in links.items()
             if model.frames[k].parentJoint == 0 and model.frames[k].parentFrame == 0]
    return (roots or list(links))[0]


def _link(links, name, option, path):
    if name not in links:
        near = ", ".join(sorted(links)[:12])
        raise InputError(f"no link {name!r} in the URDF (links: {near}"
                         f"{', ...' if len(links) > 12 else ''})", path, column=option)
    return links[name]


def _select_chain(model, links, base, tip, path):
    """Joint ids of the chain from base to tip, and the base and tip link names."""
    base = base if base is not None else _root_link(model, links)
    jb = model.frames[_link(links, base, "--base", path)].parentJoint
    if tip is None:
        below = [j for j in range(1, model.njoints)
                 if j != jb and jb in list(model.supports[j])]
        leaves = [j for j in below if not list(model.children[j])]
        if not leaves:
            raise InputError(f"no moving joint below the base link {base!r}", path,
                             column="--base")
        if len(leaves) > 1:
            names = ", ".join(_joint_body(model, links, j) for j in leaves)
            raise InputError(f"the URDF has {len(leaves)} chains below {base!r}: give --tip "
                             f"LINK (candidate tips: {names})", path, column="--tip")
        jt = leaves[0]
        tip = _joint_body(model, links, jt)
    else:
        jt = model.frames[_link(links, tip, "--tip", path)].parentJoint
    support = list(model.supports[jt])
    if jb not in support or jt == jb:
        raise InputError(f"no moving joint between the base link {base!r} and the tip link "
                         f"{tip!r} (the tip must lie beyond the base)", path, column="--tip")
    return support[support.index(jb) + 1:], base, tip


def _joint_kind(model, data, j, path):
    """('revolute' | 'prismatic', unit axis in the joint frame, continuous?) of joint j."""
    name = model.names[j]
    if model.nvs[j] != 1 or model.nqs[j] not in (1, 2):
        raise InputError(f"joint {name!r} ({model.joints[j].shortname()}) is not a revolute, "
                         "continuous or prismatic joint", path)
    S = np.asarray(data.joints[j].S, dtype=float).reshape(6)
    lin, ang = S[:3], S[3:]
    if np.linalg.norm(ang) < _TOL and abs(np.linalg.norm(lin) - 1.0) < 1e-9:
        return "prismatic", lin, False
    if np.linalg.norm(lin) < _TOL and abs(np.linalg.norm(ang) - 1.0) < 1e-9:
        return "revolute", ang, model.nqs[j] == 2
    if not S.any():     # urdfdom keeps an axis of zero length (it normalises any other)
        raise InputError("an axis of zero length", path, column=f"joint {name!r} <axis xyz>")
    raise InputError(f"joint {name!r} ({model.joints[j].shortname()}) is neither a pure "
                     "rotation nor a pure translation", path)


def read_urdf_chain(path: str | os.PathLike[str], base: str | None = None,
                    tip: str | None = None, name: str | None = None,
                    description: str | None = None, reference: str | None = None,
                    source: str | None = None) -> UrdfChain:
    """Read the serial chain from base to tip of a URDF file.

    Parameters
    ----------
    path : str or os.PathLike
        The URDF file. Meshes are not read (no geometry model is built).
    base : str, optional
        The base link (default: the URDF's root link).
    tip : str, optional
        The tip link (default: the end of the only chain below the base).
    name : str, optional
        The robot's name (default: the URDF's ``<robot name>``, else the file's stem).
    description, reference : str, optional
        Text for the reports (default: a description of the chain, and the file read).
    source : str, optional
        What to record as the robot's source (default: the path).

    Returns
    -------
    UrdfChain

    Raises
    ------
    InputError
        If the file is missing or not a valid URDF; a link is unknown; the tip is not beyond
        the base; there are several chains and no tip (the message names the candidate tips); a
        chain joint is neither revolute, continuous nor prismatic (floating, planar, ...); an ``<inertial>`` is broken or not the one Pinocchio
        loaded, or a ``<mimic>`` joint is on the chain or follows it (see
        :func:`gd_analyze.model.urdf_xml.read_urdf_xml`, :func:`~gd_analyze.model.urdf_xml.check_mimic`).

    Notes
    -----
    Source: the URDF specification (wiki.ros.org/urdf/XML) and Pinocchio's parser; the joint
    model is the fixed placement plus a motion about z described in this module's docstring.
    """
    regular_file(path, "a robot file")
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", path) from None
    model, raw, doc = _parse_model(raw, str(path))
    return _chain(model, doc, hashlib.sha256(raw).hexdigest(), base, tip, str(path),
                  name or model.name or Path(path).stem, description,
                  reference if reference is not None else
                  f"URDF {Path(path).name} read with pinocchio.buildModelFromUrdf "
                  f"(Pinocchio {_pin().__version__})",
                  str(source if source is not None else path))


def _chain(model, doc, sha256, base, tip, label, robot_name, description, reference, source,
           origin="URDF"):
    """The chain from base to tip of a Pinocchio model (doc: the URDF read by
    :mod:`gd_analyze.model.urdf_xml`, None for a model given as it is)."""
    pin = _pin()
    # link name -> frame id, for every link (BODY frame) of the model
    links = {f.name: k for k, f in enumerate(model.frames) if f.type == pin.FrameType.BODY}
    chain, base, tip = _select_chain(model, links, base, tip, label)
    locked = [j for j in range(1, model.njoints) if j not in chain]
    at = {} if doc is None else check_mimic(doc, [model.names[j] for j in chain],
                                            [model.names[j] for j in locked], label)
    q_locked = pin.neutral(model)
    for name, q in at.items():  # a locked <mimic> joint where its offset puts it
        joint = model.joints[model.getJointId(name)]    # a continuous joint's q is (cos, sin)
        q_locked[joint.idx_q:joint.idx_q + joint.nq] = [q] if joint.nq == 1 else [
            math.cos(q), math.sin(q)]
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    kinds = [_joint_kind(model, data, j, label) for j in chain]
    reduced = (pin.buildReducedModel(_unique_frame_names(model, locked), locked, q_locked)
               if locked else model)
    ids = [reduced.getJointId(model.names[j]) for j in chain]
    if ids != list(range(1, len(chain) + 1)):  # pragma: no cover - Pinocchio's ordering
        raise RuntimeError(f"unexpected joint order after reduction: {ids}")
    base_frame = reduced.frames[reduced.getFrameId(base, pin.FrameType.BODY)]
    B = base_frame.placement if base_frame.parentJoint == 0 else None
    if B is None:  # pragma: no cover - the base's joint is locked or the universe
        raise RuntimeError("base link still attached to a moving joint")
    joints = []
    prev = B
    for k, (j, (kind, axis, continuous)) in enumerate(zip(chain, kinds), start=1):
        A = pin.SE3(axis_rotation(axis), np.zeros(3))
        placement = prev.inverse() * reduced.jointPlacements[k] * A
        inertia = reduced.inertias[k]
        R = A.rotation
        iq, iv = model.idx_qs[j], model.idx_vs[j]
        lo, hi = ((-math.inf, math.inf) if continuous else
                  (_bound(model.lowerPositionLimit[iq]), _bound(model.upperPositionLimit[iq])))
        if lo > hi:
            raise InputError(f"joint {model.names[j]!r} <limit>: lower {exact_text(lo)} is above "
                             f"upper {exact_text(hi)}", label)
        if not lo < hi:                     # ROS's "unset" lower = upper (= 0): not given
            lo, hi = -math.inf, math.inf
        joints.append({
            "type": kind,
            "rotation": right_angle_rotation(placement.rotation),
            "translation": np.array(placement.translation),
            "mass": float(inertia.mass),
            "com": R.T @ np.array(inertia.lever),
            "inertia": R.T @ np.array(inertia.inertia) @ R,
            "q_min": lo, "q_max": hi,
            "qd_max": _given(model.velocityLimit[iv]),
            "qdd_max": None,
            "tau_max": _given(model.effortLimit[iv]),
        })
        prev = A
    gravity = B.rotation.T @ np.array(reduced.gravity.linear)
    joint_names = tuple(model.names[j] for j in chain)
    link_names = tuple(_joint_body(model, links, j) for j in chain)
    locked_names = tuple(model.names[j] for j in locked if chain[0] in list(model.supports[j]))
    if description is None:
        description = (f"{robot_name} from {origin}: {len(chain)} joints "
                       f"({', '.join(joint_names)}), base {base}, tip {tip}; fixed joints "
                       "merged into their links")
        if locked_names:
            offsets = "".join(f" ({name} at {exact_text(q)}, its <mimic> offset)"
                              for name, q in at.items() if name in locked_names)
            description += f"; {', '.join(locked_names)} locked at q = 0{offsets} and merged"
    metadata = {"description": description, "reference": reference, "source": source,
                "sha256": sha256, "base_link": base, "tip_link": tip,
                "urdf_joints": list(joint_names), "locked_joints": list(locked_names)}
    if not np.array_equal(B.rotation, np.eye(3)):
        # a base link turned in the URDF's root frame (--base): the arm is mounted by that
        # turn, gravity in the world stays the root's (mounting_of reads both back)
        metadata[MOUNTING_KEY] = {
            "base_rpy_deg": tuple(float(v) + 0.0 for v in np.degrees(pin.rpy.matrixToRpy(
                B.rotation))),
            "gravity_world": tuple(float(v) + 0.0 for v in reduced.gravity.linear)}
    return UrdfChain(name=robot_name, joints=tuple(joints), gravity=gravity,
                     joint_names=joint_names, link_names=link_names, base=base, tip=tip,
                     locked=locked_names, metadata=metadata)


def _unique_frame_names(model, locked):
    """A copy of the model whose frames that share a link's name (a URDF may name a joint as
    its child link) are renamed "NAME (joint)", and so are the ``locked`` joints of such a name
    (buildReducedModel makes each a frame of its name): Pinocchio's buildReducedModel looks
    frames up by name alone and refuses a name two frames hold; the links keep theirs."""
    pin = _pin()
    bodies = {f.name for f in model.frames if f.type == pin.FrameType.BODY}
    clash = [k for k, f in enumerate(model.frames)
             if f.type != pin.FrameType.BODY and f.name in bodies]
    model = pin.Model(model)
    for k in clash:
        frame = model.frames[k]
        frame.name += " (joint)"
        model.frames[k] = frame
    for j in locked:
        model.names[j] += " (joint)" * (model.names[j] in bodies)
    return model


def _bound(limit):
    """A position limit, infinite where Pinocchio holds the largest float (no limit given) or
    the file a placeholder beyond any joint's travel (above ``LIMITS["q"]``, 1e4 rad or m:
    SDF's default 1e16, which Gazebo's URDF export writes for a joint without limits)."""
    v = float(limit)
    return math.copysign(math.inf, v) if abs(v) > LIMITS["q"] else v


def _given(limit):
    """A URDF limit, or NaN where it is not given: ROS's placeholder 0 (``velocity="0"``,
    ``effort="0"``) or what Pinocchio sets for a missing one (0, inf or the largest float)."""
    return float(limit) if 0 < limit < 1e300 else math.nan


def builtin_urdf_path(name: str) -> Path:
    """The vendored URDF file of a built-in robot.

    Parameters
    ----------
    name : str
        A key of :data:`URDF_BUILTIN` (``"panda"``, ``"ur5"``).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    KeyError
        If the name is not a URDF built-in.
    """
    return Path(str(resources.files("gd_analyze").joinpath("data").joinpath(URDF_BUILTIN[name]["file"])))


def load_urdf(path: str | os.PathLike[str], base: str | None = None,
              tip: str | None = None) -> Robot:
    """A robot from a URDF file, or a built-in URDF robot by name.

    Parameters
    ----------
    path : str or os.PathLike
        A URDF file, or ``"panda"`` / ``"ur5"``.
    base, tip : str, optional
        The chain's base and tip links (see :func:`read_urdf_chain`); a built-in robot has its
        own (``panda``: panda_link0 to panda_hand; ``ur5``: base_link to wrist_3_link), which
        these override.

    Returns
    -------
    Robot
        Built by :func:`gd_analyze.model.robot_spec.robot_from_chain`.

    Raises
    ------
    InputError
        As :func:`read_urdf_chain`.
    """
    key = str(path)
    if key in URDF_BUILTIN:
        spec = URDF_BUILTIN[key]
        chain = read_urdf_chain(builtin_urdf_path(key), base or spec["base"],
                                tip or spec["tip"], name=key,
                                description=spec["description"], reference=spec["reference"],
                                source=key)
        if spec.get("placeholder_inertia"):
            chain = dataclasses.replace(chain, metadata={**chain.metadata,
                                                         "placeholder_inertia": True})
    else:
        chain = read_urdf_chain(path, base, tip)
    return _robot(chain)


def _robot(chain):
    return robot_from_chain(chain.name, [dict(j) for j in chain.joints], chain.gravity,
                            **chain.metadata)


#: What errors call a URDF given as text.
URDF_TEXT = "URDF text"
#: A URDF given as text: optional blanks, XML declaration and comments, then ``<robot``.
_URDF_TEXT = re.compile(r"\A\ufeff?\s*(?:<\?xml[^>]*\?>\s*)?(?:<!--.*?-->\s*)*<robot(?:[\s>/]|\Z)",
                        re.DOTALL)


def is_urdf_text(value: object) -> TypeGuard[str]:
    """Whether a robot argument is a URDF document given as text (a ``robot_description``).

    Parameters
    ----------
    value : object
        A robot argument.

    Returns
    -------
    bool
        True for a str that begins, after optional blanks, an XML declaration and comments,
        with ``<robot``.

    Examples
    --------
    >>> is_urdf_text('<?xml version="1.0"?>\\n<robot name="arm"></robot>'), is_urdf_text("panda")
    (True, False)
    """
    return isinstance(value, str) and _URDF_TEXT.match(value) is not None


def load_urdf_text(text: str, base: str | None = None, tip: str | None = None) -> Robot:
    """A robot from a URDF document given as text, e.g. a ROS ``robot_description``.

    Parameters
    ----------
    text : str
        The URDF document (:func:`is_urdf_text`); read as a URDF file's bytes are, with the
        same checks (:func:`read_urdf_chain`).
    base, tip : str, optional
        The chain's base and tip links.

    Returns
    -------
    Robot
        Named by the ``<robot name>`` (``"urdf"`` if empty); ``source`` is ``"URDF text"`` and
        ``sha256`` that of the text's UTF-8 bytes without its leading blanks.

    Raises
    ------
    InputError
        As :func:`read_urdf_chain`, the document named ``URDF text``.
    """
    try:
        # an XML declaration must open the document: the blanks before it go
        raw = str(text).lstrip("\ufeff \t\r\n").encode("utf-8")
    except UnicodeEncodeError:
        raise InputError("not UTF-8 text (a lone surrogate)", URDF_TEXT) from None
    model, raw, doc = _parse_model(raw, URDF_TEXT)
    name = model.name or "urdf"
    return _robot(_chain(model, doc, hashlib.sha256(raw).hexdigest(), base, tip, URDF_TEXT,
                         name, None, f"URDF text read with pinocchio.buildModelFromXML "
                         f"(Pinocchio {_pin().__version__})", URDF_TEXT))


def load_pinocchio_model(model: pinocchio.Model, base: str | None = None,
                         tip: str | None = None) -> Robot:
    """A robot from a Pinocchio model, e.g. one a notebook built or loaded itself.

    Parameters
    ----------
    model : pinocchio.Model
        Revolute, continuous or prismatic joints on the chain; the model is not changed.
        Limits it does not give (Pinocchio's defaults, the largest float) are "not given".
    base, tip : str, optional
        The chain's base and tip links (BODY frames); a model without frames has one link per
        joint, named as the joint, and the base link ``"universe"``.

    Returns
    -------
    Robot
        Named by ``model.name`` (``"pinocchio"`` if empty), joints named by ``model.names``;
        ``source`` is ``"pinocchio.Model"`` and ``sha256`` that of the model's serialisation
        (``model.saveToString()``).

    Raises
    ------
    InputError
        As :func:`read_urdf_chain` (a link is unknown, a joint is not revolute, continuous or
        prismatic, a mass or inertia is invalid); the model is named ``pinocchio.Model``.
    """
    label = "pinocchio.Model"
    # a copy of the model with a JOINT frame for every joint, a BODY frame after it (named as
    # the joint where it has none) and a BODY frame on the universe ("universe"), as a
    # model built from a URDF has them
    pin = _pin()
    model = model.copy()
    frames = {(f.name, f.type) for f in model.frames}
    if not any(f.type == pin.FrameType.BODY and f.parentJoint == 0 and f.parentFrame == 0
               for f in model.frames):
        model.addBodyFrame("universe", 0, pin.SE3.Identity(), 0)
    for j in range(1, model.njoints):
        name = model.names[j]
        if (name, pin.FrameType.JOINT) not in frames:
            parent = model.parents[j]
            above = (model.getFrameId(model.names[parent], pin.FrameType.JOINT)
                     if parent else 0)
            model.addJointFrame(j, above)
        jf = model.getFrameId(name, pin.FrameType.JOINT)
        if not any(f.type == pin.FrameType.BODY and f.parentFrame == jf for f in model.frames):
            body = name if (name, pin.FrameType.BODY) not in frames else f"{name}_body"
            model.addBodyFrame(body, j, pin.SE3.Identity(), jf)
    sha256 = hashlib.sha256(model.saveToString().encode("utf-8")).hexdigest()
    name = model.name or "pinocchio"
    return _robot(_chain(model, None, sha256, base, tip, label, name, None,
                         f"pinocchio.Model (Pinocchio {_pin().__version__})", label,
                         origin="a Pinocchio model"))


__all__ += ["is_urdf_text", "load_urdf_text", "load_pinocchio_model", "URDF_TEXT"]
