"""Robot model: a serial chain of revolute and prismatic joints.

One joint model serves every source (Fu, Gonzalez & Lee 1987, Secs. 2.2.10 and 3.2; Craig,
*Introduction to Robotics*, Sec. 3.4; the URDF joint model). Joint i (1-based) has

- a fixed placement (rotation P_i, translation t_i) from body frame i-1 (the base frame for
  i = 1), and then
- a motion about or along the z axis of that placed frame: a rotation by q_i [rad] (revolute)
  or a translation by q_i [m] (prismatic).

Body frame i is the placed frame after the motion, so the homogeneous transform from body
frame i-1 to body frame i is::

    ^{i-1}T_i = [P_i t_i; 0 1] Rot(z, q_i)      (revolute)
    ^{i-1}T_i = [P_i t_i; 0 1] Trans(0, 0, q_i)  (prismatic)

Joint i's axis is the z axis of body frame i and passes through its origin. Per link the model
holds the mass m_i, the centre of mass r_i and the inertia tensor I_i about it in *link frame
i*, the frame the source gives them in, which sits at a fixed pose (L_R, L_t) in body frame i:

- standard DH (Eq. (3.2-5)): link frame i is DH frame i at the far end of link i;
  ^{i-1}A_i = Rot(z, theta_i) Trans(0, 0, d_i) Trans(a_i, 0, 0) Rot(x, alpha_i). Body frame i is
  DH frame i-1 moved by joint i, so L_i = Rot(z, theta0_i) Trans(0, 0, d0_i) Trans(a_i, 0, 0)
  Rot(x, alpha_i) with the constant parts theta0, d0, and the placement of joint i is L_{i-1}
  (the identity for i = 1);
- modified DH (Craig): link i's row holds alpha_{i-1}, a_{i-1}, d_i, theta_i;
  ^{i-1}T_i = Rot(x, alpha_{i-1}) Trans(a_{i-1}, 0, 0) Rot(z, theta_i) Trans(0, 0, d_i). Body
  frame i is modified-DH frame i (L_i is the identity) and the placement of joint i is
  Rot(x, alpha_{i-1}) Trans(a_{i-1}, 0, 0) Rot(z, theta0_i) Trans(0, 0, d0_i);
- a general chain (URDF): placements given, link frame i = body frame i.

In both DH conventions the constant parts are theta0_i = offset_i and d0_i = d_i; the joint
variable adds to theta (revolute: theta_i = q_i + offset_i) or to d (prismatic:
d_i = q_i + d_i, theta_i = offset_i fixed).
"""

from __future__ import annotations

import dataclasses
import math
import types
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from .drives import drive_dict
from .limits import LIMITS

__all__ = ["Robot", "make_robot",
           "with_payload", "dh_placements", "rot_x", "rot_z", "CONVENTIONS", "JOINT_TYPES"]

#: How a robot's placements were given: standard DH, modified DH (Craig) or a general chain.
CONVENTIONS = ("standard", "modified", "chain")
#: Joint types: rotation about, or translation along, the joint's z axis.
JOINT_TYPES = ("revolute", "prismatic")


def _readonly(x, dtype=float):
    arr = np.array(x, dtype=dtype)
    arr.setflags(write=False)
    return arr


def rot_x(angle: float) -> np.ndarray:
    """Rotation matrix about x.

    Parameters
    ----------
    angle : float
        Angle [rad].

    Returns
    -------
    ndarray, shape (3, 3)
    """
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_z(angle: float) -> np.ndarray:
    """Rotation matrix about z.

    Parameters
    ----------
    angle : float
        Angle [rad].

    Returns
    -------
    ndarray, shape (3, 3)
    """
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def dh_placements(convention: str, d: np.ndarray, a: np.ndarray, alpha: np.ndarray,
                  offset: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Joint placements and link-frame poses of a DH chain.

    Parameters
    ----------
    convention : {"standard", "modified"}
        Standard DH (Eq. (3.2-5)) or Craig's modified DH.
    d, a, alpha, offset : array_like, shape (n,)
        The rows' constant d [m], a [m], alpha [rad] and theta offset [rad] (in the modified
        convention a and alpha are Craig's a_{i-1} and alpha_{i-1}).

    Returns
    -------
    rotation : ndarray, shape (n, 3, 3)
        P_i, the rotation of joint i's placement in body frame i-1.
    translation : ndarray, shape (n, 3)
        t_i, its translation [m].
    link_rotation : ndarray, shape (n, 3, 3)
        L_R of link frame i in body frame i.
    link_translation : ndarray, shape (n, 3)
        L_t of link frame i in body frame i [m].

    Raises
    ------
    ValueError
        If the convention is neither DH convention.
    """
    n = len(d)
    P, t = np.zeros((n, 3, 3)), np.zeros((n, 3))
    LR, Lt = np.zeros((n, 3, 3)), np.zeros((n, 3))
    if convention == "standard":
        for i in range(n):
            Rz = rot_z(offset[i])
            LR[i] = Rz @ rot_x(alpha[i])
            Lt[i] = Rz @ np.array([a[i], 0.0, 0.0]) + np.array([0.0, 0.0, d[i]])
            P[i], t[i] = (np.eye(3), np.zeros(3)) if i == 0 else (LR[i - 1], Lt[i - 1])
    elif convention == "modified":
        for i in range(n):
            Rx = rot_x(alpha[i])
            P[i] = Rx @ rot_z(offset[i])
            t[i] = np.array([a[i], 0.0, 0.0]) + Rx @ np.array([0.0, 0.0, d[i]])
            LR[i], Lt[i] = np.eye(3), np.zeros(3)
    else:
        raise ValueError(f"not a DH convention: {convention!r}")
    return P, t, LR, Lt


@dataclass(frozen=True, eq=False)
class Robot:
    """A serial arm of n revolute or prismatic joints with link inertial parameters.

    Every array is read-only. Build one with :func:`~gd_analyze.model.robots.load_robot`,
    :func:`~gd_analyze.model.robot_spec.robot_from_dict` or
    :func:`~gd_analyze.model.robot_spec.robot_from_chain`. The joint model is in the module
    docstring.

    Attributes
    ----------
    name : str
        The robot's name, e.g. ``"puma560"``.
    d, a, alpha, offset : ndarray, shape (n,)
        DH parameters of a DH robot [m, m, rad, rad]: the rows of the robot file (standard:
        d_i, a_i, alpha_i, theta offset_i; modified: d_i, a_{i-1}, alpha_{i-1}, theta
        offset_i). For a prismatic joint ``offset`` is the fixed theta_i and ``d`` the constant
        added to q_i. NaN for a general chain (``convention == "chain"``), whose geometry is
        in ``rotation`` and ``translation`` only.
    mass : ndarray, shape (n,)
        Link masses m_i [kg].
    com : ndarray, shape (n, 3)
        Centre of mass r_i of link i in link frame i [m] (DH frame i for a DH robot).
    inertia : ndarray, shape (n, 3, 3)
        Inertia tensor I_i of link i about its centre of mass, axes parallel to link frame i,
        symmetric [kg m^2].
    q_min, q_max : ndarray, shape (n,)
        Joint position limits [rad] or [m]; -inf, inf where there is none (a continuous
        joint) or none is given.
    qd_max : ndarray, shape (n,)
        Joint velocity limits [rad/s] or [m/s]; NaN where not given (only planning needs them).
    qdd_max : ndarray, shape (n,)
        Joint acceleration limits [rad/s^2] or [m/s^2]; NaN where unknown (URDF).
    gravity : ndarray, shape (3,)
        Gravity vector g in the base frame [m/s^2], e.g. (0, 0, -9.8062).
    description, reference : str
        A line of text about the robot; where the parameters come from.
    source : str
        The file the robot was read from, or ``"<dict>"``.
    sha256 : str
        SHA-256 of that file's bytes (of the canonical JSON of the dictionary otherwise).
    convention : {"standard", "modified", "chain"}
        How the placements were given.
    prismatic : ndarray of bool, shape (n,)
        True for a prismatic joint (q [m]), False for a revolute one (q [rad]).
    rotation : ndarray, shape (n, 3, 3)
        P_i: rotation of joint i's placement in body frame i-1 (for a DH robot always derived
        from d, a, alpha and offset, so that ``dataclasses.replace`` cannot leave it stale).
    translation : ndarray, shape (n, 3)
        t_i: translation of joint i's placement in body frame i-1 [m].
    link_rotation : ndarray, shape (n, 3, 3)
        Orientation of link frame i in body frame i (identity for modified DH and chains).
    link_translation : ndarray, shape (n, 3)
        Origin of link frame i in body frame i [m].
    tau_max : ndarray, shape (n,)
        Joint effort limits |tau_i| <= tau_max_i [N m] or [N] (prismatic); NaN where not
        given (default: none given).
    metadata : mapping
        Read-only extra facts from the builder (e.g. a URDF's base and tip links).
    armature : ndarray, shape (n,)
        Reflected rotor inertia Ia_i = J_m G^2 of joint i's drive [kg m^2] (prismatic: [kg]);
        zero by default. It adds diag(Ia) to D (:mod:`gd_analyze.model.drives`).
    viscous, coulomb : ndarray, shape (n,)
        Joint friction F_v [N m s/rad] (N s/m) and F_c [N m] (N), tau_f = F_v qd + F_c sign(qd)
        + tau_0; zero by default.
    torque_offset : ndarray, shape (n,)
        Constant joint torque offset tau_0 [N m] (prismatic: [N]), of either sign, part of
        tau_f; zero by default (an identified robot's, :mod:`gd_analyze.model.drives`).

    Notes
    -----
    Source: Fu, Gonzalez & Lee (1987), Secs. 2.2.10 and 3.2 (standard DH, Eq. (3.2-5), the
    joint matrices Q of Eqs. (3.2-8a) and (3.2-8b)); Craig (1989), Sec. 3.4 (modified DH).
    The dynamics engines read the body-frame quantities :attr:`body_com` and
    :attr:`body_inertia` with ``rotation``, ``translation`` and ``prismatic``.
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
    convention: str = "standard"
    # the fields below default to None for make_robot to fill (tau_max with NaN); __post_init__
    # rejects a None (but tau_max's), so they are typed as what every Robot holds
    prismatic: np.ndarray = None  # type: ignore[assignment]
    rotation: np.ndarray = None  # type: ignore[assignment]
    translation: np.ndarray = None  # type: ignore[assignment]
    link_rotation: np.ndarray = None  # type: ignore[assignment]
    link_translation: np.ndarray = None  # type: ignore[assignment]
    metadata: types.MappingProxyType = None  # type: ignore[assignment]
    tau_max: np.ndarray = None  # type: ignore[assignment]
    armature: np.ndarray = None  # type: ignore[assignment]
    viscous: np.ndarray = None  # type: ignore[assignment]
    coulomb: np.ndarray = None  # type: ignore[assignment]
    torque_offset: np.ndarray = None  # type: ignore[assignment]

    def __post_init__(self):
        # Validation only: a frozen value is never changed after construction. Build a robot
        # with make_robot (or robot_from_dict / robot_from_chain), which normalises its fields.
        if self.convention not in CONVENTIONS:
            raise ValueError(f"convention must be one of {CONVENTIONS}, got {self.convention!r}")
        n = len(self.mass)
        for key in ("armature", "viscous", "coulomb"):      # drives: finite, >= 0, (n,)
            v = getattr(self, key)
            if v is None or v.shape != (n,) or not (np.isfinite(v) & (v >= 0)).all():
                raise ValueError(f"{key} must be {n} finite numbers >= 0")
        t0 = self.torque_offset
        if t0 is None or t0.shape != (n,) or not np.isfinite(t0).all():
            raise ValueError(f"torque_offset must be {n} finite numbers")
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, (list, tuple)):
                raise TypeError(f"Robot.{f.name} must be an ndarray (build with make_robot)")
            if isinstance(value, np.ndarray):
                value.setflags(write=False)         # the array, not the frozen value
        if self.prismatic is None or self.prismatic.dtype != bool:
            raise TypeError("Robot.prismatic must be a bool ndarray (build with make_robot)")
        if not isinstance(self.metadata, types.MappingProxyType):
            raise TypeError("Robot.metadata must be a read-only mapping (build with make_robot)")
        if any(getattr(self, k) is None for k in _PLACEMENTS):
            raise TypeError("Robot placements missing (build with make_robot)")
        if self.convention != "chain":      # always from the DH rows: never stale
            derived = dh_placements(self.convention, self.d, self.a, self.alpha, self.offset)
            if not all(np.array_equal(getattr(self, k), v)
                       for k, v in zip(_PLACEMENTS, derived)):
                raise ValueError("Robot placements differ from its DH rows (a DH robot's "
                                 "placements are derived: build it with make_robot)")

    @property
    def n(self) -> int:
        """int: the number of joints (degrees of freedom)."""
        return int(self.mass.shape[0])

    @cached_property
    def has_armature(self) -> bool:
        """bool: True if a drive adds armature inertia to some joint (``armature`` not all
        0); computed once per robot (a closed loop asks at every step)."""
        return self.armature is not None and bool(np.any(self.armature))

    @cached_property
    def has_friction(self) -> bool:
        """bool: True if some joint has viscous or Coulomb friction or a torque offset
        (``viscous``, ``coulomb`` or ``torque_offset`` not all 0: tau_f is then not zero);
        computed once per robot."""
        return any(v is not None and bool(np.any(v))
                   for v in (self.viscous, self.coulomb, self.torque_offset))

    @property
    def joint_types(self) -> tuple[str, ...]:
        """tuple of str: ``"revolute"`` or ``"prismatic"`` per joint."""
        return tuple(JOINT_TYPES[int(p)] for p in self.prismatic)

    @property
    def body_com(self) -> np.ndarray:
        """ndarray, shape (n, 3): centres of mass in the body frames, L_R r_i + L_t [m]."""
        return np.einsum("sab,sb->sa", self.link_rotation, self.com) + self.link_translation

    @property
    def body_inertia(self) -> np.ndarray:
        """ndarray, shape (n, 3, 3): inertia tensors about the centres of mass, body-frame
        axes, L_R I_i L_R^T [kg m^2]."""
        LR = self.link_rotation
        return LR @ self.inertia @ np.swapaxes(LR, -1, -2)

    def joint_names(self) -> list[str]:
        """The joints' names: a URDF's or Pinocchio model's own, else ``"joint1"`` .. ``"jointn"``.

        Returns
        -------
        list of str, length n
            ``metadata["urdf_joints"]`` where the robot was read from a URDF or a
            ``pinocchio.Model``; otherwise ``"joint1"``, ... as Pinocchio names the joints of
            :func:`gd_analyze.dynamics.pinocchio.pinocchio_model`.
        """
        names = list(self.metadata.get("urdf_joints") or ())
        if len(names) == self.n:
            return [str(v) for v in names]
        return [f"joint{i + 1}" for i in range(self.n)]

    def to_dict(self) -> dict[str, Any]:
        """The robot as a dictionary in the robot-file layout.

        Returns
        -------
        dict
            Keys ``name``, ``description``, ``reference``, ``gravity``, ``convention`` and
            ``link`` (a list of per-link dictionaries, degrees for revolute angles);
            ``robot_from_dict(robot.to_dict())`` rebuilds the robot. A general chain writes
            its placements (``rotation``, ``translation``) and limits in SI units.
        """
        links = []
        for i in range(self.n):
            I = self.inertia[i]
            link: dict[str, Any] = {"joint": self.joint_types[i]}
            pris = bool(self.prismatic[i])
            if self.convention == "chain":
                link.update(rotation=self.rotation[i].tolist(),
                            translation=self.translation[i].tolist())
            elif pris:
                link.update(theta_deg=math.degrees(self.offset[i]), a=float(self.a[i]),
                            alpha_deg=math.degrees(self.alpha[i]), offset=float(self.d[i]))
            else:
                link.update(d=float(self.d[i]), a=float(self.a[i]),
                            alpha_deg=math.degrees(self.alpha[i]),
                            offset_deg=math.degrees(self.offset[i]))
            link.update(mass=float(self.mass[i]), com=[float(v) for v in self.com[i]],
                        inertia=[float(I[0, 0]), float(I[1, 1]), float(I[2, 2]),
                                 float(I[0, 1]), float(I[0, 2]), float(I[1, 2])])
            if pris or self.convention == "chain":      # SI units: m or rad
                link.update(q_limits=[float(self.q_min[i]), float(self.q_max[i])],
                            qd_max=float(self.qd_max[i]), qdd_max=float(self.qdd_max[i]))
            else:
                link.update(q_limits_deg=[math.degrees(self.q_min[i]),
                                          math.degrees(self.q_max[i])],
                            qd_max_deg=math.degrees(self.qd_max[i]),
                            qdd_max_deg=math.degrees(self.qdd_max[i]))
            if math.isfinite(self.tau_max[i]):
                link["tau_max"] = float(self.tau_max[i])
            link.update(drive_dict(self, i))
            links.append(link)
        return {"name": self.name, "description": self.description,
                "reference": self.reference, "gravity": [float(v) for v in self.gravity],
                "convention": self.convention, "link": links}

    def with_inertial(self, mass: np.ndarray | None = None, com: np.ndarray | None = None,
                      inertia: np.ndarray | None = None) -> Robot:
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


#: The placement fields, derived from the DH rows for a DH robot.
_PLACEMENTS = ("rotation", "translation", "link_rotation", "link_translation")


def make_robot(**fields: Any) -> Robot:
    """Build a :class:`Robot` from its fields, normalised.

    Parameters
    ----------
    **fields
        The fields of :class:`Robot` (array-likes welcome). ``prismatic`` defaults to all
        revolute, ``metadata`` to an empty mapping; for a DH robot the placements are derived
        from d, a, alpha and offset (:func:`dh_placements`), for a chain ``rotation`` and
        ``translation`` are given and the link frames default to the body frames.

    Returns
    -------
    Robot
        Every array read-only.

    Raises
    ------
    ValueError
        If the convention is unknown.

    Notes
    -----
    Source: the joint model of this module's docstring (Fu, Gonzalez & Lee 1987, Eq. (3.2-5);
    Craig 1989, Sec. 3.4).

    Examples
    --------
    >>> import numpy as np
    >>> r = make_robot(name="one", d=[0.0], a=[1.0], alpha=[0.0], offset=[0.0], mass=[1.0],
    ...                com=[[-0.5, 0, 0]], inertia=[np.eye(3) * 0.01], q_min=[-1.0],
    ...                q_max=[1.0], qd_max=[1.0], qdd_max=[1.0], gravity=[0, -9.81, 0])
    >>> r.n, r.translation[0].tolist(), r.mass.flags.writeable
    (1, [0.0, 0.0, 0.0], False)
    """
    convention = fields.get("convention", "standard")
    if convention not in CONVENTIONS:
        raise ValueError(f"convention must be one of {CONVENTIONS}, got {convention!r}")
    n = len(fields["mass"])
    prismatic = fields.get("prismatic")
    fields["prismatic"] = _readonly(np.zeros(n, bool) if prismatic is None else prismatic, bool)
    fields["metadata"] = types.MappingProxyType(dict(fields.get("metadata") or {}))
    if convention != "chain":
        fields.update(zip(_PLACEMENTS, dh_placements(convention, fields["d"], fields["a"],
                                                     fields["alpha"], fields["offset"])))
    if fields.get("link_rotation") is None:
        fields["link_rotation"] = np.broadcast_to(np.eye(3), (n, 3, 3))
    if fields.get("link_translation") is None:
        fields["link_translation"] = np.zeros((n, 3))
    if fields.get("tau_max") is None:
        fields["tau_max"] = np.full(n, np.nan)
    for key in ("armature", "viscous", "coulomb", "torque_offset"):     # drives: none unless given
        if fields.get(key) is None:
            fields[key] = np.zeros(n)
    for key, value in fields.items():
        if key not in ("prismatic", "metadata") and isinstance(value, (np.ndarray, list,
                                                                         tuple)):
            fields[key] = _readonly(value)
    return Robot(**fields)


def with_payload(robot: Robot, mass: float, com: ArrayLike = (0.0, 0.0, 0.0),
                 inertia: ArrayLike = (0.0, 0.0, 0.0)) -> Robot:
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
    if not math.isfinite(mass) or mass < 0 or mass > LIMITS["mass"]:
        raise InputError(f"payload mass must be a number in [0, {LIMITS['mass']:g}] kg, got "
                         f"{mass:g}", column="--payload")
    com_p = np.asarray(com, dtype=float).reshape(3)
    I_p = np.asarray(inertia, dtype=float)
    for opt, vals, lim in (("--payload-com", com_p, "length"),
                           ("--payload-inertia", I_p, "inertia")):
        if not (np.abs(vals) <= LIMITS[lim]).all():
            raise InputError(f"values beyond the supported magnitude {LIMITS[lim]:g}",
                             column=opt)
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
