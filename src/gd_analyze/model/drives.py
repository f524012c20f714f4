"""Drive-side dynamics: reflected rotor inertia (armature) and joint friction.

A geared drive adds to joint i, on the link side of its gearbox,

- the armature Ia_i = J_m,i G_i^2 [kg m^2] (prismatic: [kg]): the rotor inertia J_m,i
  reflected through a gear of ratio G_i (motor turns per joint turn). The rotor spins about
  the joint axis at G_i qd_i, so its kinetic energy 1/2 J_m G^2 qd_i^2 adds Ia_i to D_ii only
  (the rotor's own gyroscopic coupling with the links is neglected, as in the Robotics
  Toolbox's ``rne`` and Pinocchio's ``model.armature``): D = D_tran + D_rot + diag(Ia);
- the friction torque tau_f,i = F_v,i qd_i + F_c,i sign(qd_i) [N m] (prismatic: [N]), viscous
  F_v [N m s/rad] (N s/m) and Coulomb F_c [N m] (N), both >= 0 and symmetric in the direction
  of motion (sign(0) = 0: no stiction model), plus a constant torque offset tau_0,i [N m]
  (prismatic: [N]) of either sign: an identified sensor or gravity-compensation bias, which
  system identification fits per joint as a column of ones (Swevers et al., "Optimal robot
  excitation and identification", IEEE Trans. Robot. Automat. 13(5), 1997).

The torque of Eq. (3.4-24) becomes tau = (D_tran + D_rot + D_arm) qdd + h_tran + h_rot + c +
tau_f, tau_f = F_v qd + F_c sign(qd) + tau_0. Motor-side data reflect to the link side as Ia = J_m G^2, F_v = B G^2, F_c = T_c |G|
(Corke, *Robotics, Vision and Control*, 2nd ed. 2017, Sec. 9.1.4; the Robotics Toolbox's
``Link.friction``). Pure: no files are read here.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from .limits import LIMITS

if TYPE_CHECKING:
    from .robot import Robot

__all__ = ["DRIVE_KEYS", "DRIVE_FIELDS", "COULOMB_BAND", "drive_values", "drive_dict", "friction_torque",
           "has_drives", "rigid_links"]

#: The optional per-link keys of a robot file for the drive: armature [kg m^2] (or rotor
#: inertia [kg m^2] and gear ratio [-], armature = rotor_inertia * gear_ratio^2), viscous
#: [N m s/rad] and coulomb [N m] friction, and the constant torque_offset [N m] (prismatic:
#: kg, N s/m, N, N). ``offset`` is taken: it is the DH joint offset of a prismatic link.
DRIVE_KEYS = ("armature", "rotor_inertia", "gear_ratio", "viscous", "coulomb", "torque_offset")

#: The :class:`~gd_analyze.model.robot.Robot` fields of the drive, one value per joint.
DRIVE_FIELDS = ("armature", "viscous", "coulomb", "torque_offset")


def _value(link, key, path, column, lo=0.0):
    value = link[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"expected a number, got {value!r:.60}", path, column=column)
    v = float(value)
    if not math.isfinite(v) or v < lo or abs(v) > LIMITS["inertia"]:
        raise InputError(f"expected a finite number >= {lo:g} and at most "
                         f"{LIMITS['inertia']:g}, got {v:g}", path, column=column)
    return v


def drive_values(link: dict[str, Any], path: str, where: str) -> tuple[float, float, float, float]:
    """The drive of one link table of a robot file, validated.

    Parameters
    ----------
    link : dict
        The link table; its keys of :data:`DRIVE_KEYS` are read, all optional.
    path : str
        The robot file, for messages.
    where : str
        The link's key prefix, e.g. ``"link[2]"``.

    Returns
    -------
    armature, viscous, coulomb, torque_offset : float
        Ia [kg m^2], F_v [N m s/rad], F_c [N m] and tau_0 [N m] (prismatic: kg, N s/m, N, N);
        0 when not given.

    Raises
    ------
    InputError
        If a value is not a finite number >= 0 (``gear_ratio``: not 0; ``torque_offset``:
        any finite number), if ``armature`` is given together with
        ``rotor_inertia`` or ``gear_ratio``, or if only one of those two is given. One line
        naming the key.

    Examples
    --------
    >>> values = drive_values({"rotor_inertia": 2e-4, "gear_ratio": -62.6111}, "f.toml", "link[1]")
    >>> round(values[0], 6)     # 2e-4 * 62.6111^2
    0.78403
    """
    given = [k for k in ("rotor_inertia", "gear_ratio") if k in link]
    if "armature" in link and given:
        raise InputError("give either 'armature' or 'rotor_inertia' and 'gear_ratio', not "
                         "both (armature = rotor_inertia * gear_ratio^2)", path,
                         column=f"{where}.{given[0]}")
    if len(given) == 1:
        other = ({"rotor_inertia", "gear_ratio"} - set(given)).pop()
        raise InputError(f"'{given[0]}' needs '{other}' (armature = rotor_inertia * "
                         f"gear_ratio^2)", path, column=f"{where}.{other}")
    if given:
        jm = _value(link, "rotor_inertia", path, f"{where}.rotor_inertia")
        g = _value(link, "gear_ratio", path, f"{where}.gear_ratio", lo=-math.inf)
        if g == 0.0:
            raise InputError("a gear ratio of 0 turns the motor not at all (armature = "
                             "rotor_inertia * gear_ratio^2 would be 0): give the ratio of "
                             "motor turns per joint turn, or leave the drive out", path,
                             column=f"{where}.gear_ratio")
        armature = jm * g * g
        if armature > LIMITS["inertia"]:
            raise InputError(f"armature rotor_inertia * gear_ratio^2 = {armature:g} is beyond "
                             f"{LIMITS['inertia']:g}", path, column=f"{where}.gear_ratio")
    else:
        armature = _value(link, "armature", path, f"{where}.armature") if "armature" in link \
            else 0.0
    return (armature,) + tuple(_value(link, k, path, f"{where}.{k}") if k in link else 0.0
                               for k in ("viscous", "coulomb")) \
        + (_value(link, "torque_offset", path, f"{where}.torque_offset", lo=-math.inf)
           if "torque_offset" in link else 0.0,)


def has_drives(robot: Robot) -> bool:
    """Whether a robot has any armature, friction or torque offset.

    Parameters
    ----------
    robot : Robot
        The arm.

    Returns
    -------
    bool
    """
    return any(bool(np.any(getattr(robot, k))) for k in DRIVE_FIELDS)


def drive_dict(robot: Robot, i: int) -> dict[str, Any]:
    """Joint i's nonzero drive keys in the robot-file layout (for ``Robot.to_dict``).

    Parameters
    ----------
    robot : Robot
        The arm.
    i : int
        Joint index, 0-based.

    Returns
    -------
    dict
        ``armature``, ``viscous``, ``coulomb``, ``torque_offset`` where nonzero (an arm
        without drives writes none, so its parameters' SHA-256 is unchanged).
    """
    return {k: float(getattr(robot, k)[i]) for k in DRIVE_FIELDS if getattr(robot, k)[i] != 0.0}


#: Where a simulated plant's Coulomb friction F_c sign(qd) is linear, |qd| < COULOMB_BAND
#: [rad/s; m/s] (:func:`friction_torque`'s ``band``; ``gd-analyze control``'s plant): with
#: sign(qd) itself, a closed loop whose qd crosses 0 switches the torque at every step (the PD +
#: gravity run on the PUMA 560 with drives did not finish in 500,000 evaluations; 5.7 s with
#: this band, 21 s with 1e-4, unfinished with 1e-5).
COULOMB_BAND = 1e-3


def friction_torque(robot: Robot, qd: np.ndarray, band: float = 0.0) -> np.ndarray | None:
    """Joint friction and offset tau_f = F_v qd + F_c sign(qd) + tau_0.

    The one formula of the drives' velocity-dependent torque: every engine and the emitted
    programs (:func:`gd_analyze.symbolic.drive_regressor.with_drives`) use it; identification's
    drive columns and its robot file's drive torque follow it (sign(0) = 0).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (``viscous``, ``coulomb``, ``torque_offset``).
    qd : ndarray, shape (N, n)
        Joint velocities [rad/s or m/s].
    band : float, optional
        Where positive, sign(qd) is regularised as clip(qd / band, -1, 1): linear within
        |qd| < band [rad/s or m/s], as a simulated plant needs it (a closed loop crossing
        qd = 0 would otherwise switch the torque at every step); 0 (default): sign(qd).

    Returns
    -------
    ndarray, shape (N, n) or None
        Friction torques plus offsets [N m] (prismatic: [N]); None when the robot has no
        friction and no offset (the term is then zero and costs nothing).

    Notes
    -----
    The viscous plus Coulomb model of Armstrong-Helouvry, Dupont & Canudas de Wit, "A survey of
    models, analysis tools and compensation methods for the control of machines with
    friction", Automatica 30(7), 1994; sign(0) = 0. The regularised sign is the
    "linear viscous band" of simulation (Karnopp's stick band without its stick state).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("puma560-drives")
    >>> friction_torque(robot, np.zeros((1, 6))).tolist()
    [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
    >>> bool(np.allclose(friction_torque(robot, np.full((1, 6), 5e-4), band=1e-3),
    ...                  0.5 * friction_torque(robot, np.full((1, 6), 1.0)) - 0.5 * robot.viscous
    ...                  + 5e-4 * robot.viscous))
    True
    """
    if not robot.has_friction:
        return None
    qd = np.asarray(qd, dtype=float)
    sign = np.sign(qd) if band <= 0 else np.clip(qd / band, -1.0, 1.0)
    return robot.viscous * qd + robot.coulomb * sign + robot.torque_offset


def rigid_links(robot: Robot) -> Robot:
    """The robot without its drives: the rigid links the chapter models.

    Parameters
    ----------
    robot : Robot
        The arm.

    Returns
    -------
    Robot
        The same robot (the same object when it has no drives) with zero armature,
        friction and torque offset.
    """
    if not has_drives(robot):
        return robot
    import dataclasses

    zero = np.zeros(robot.n)
    zeros: dict[str, Any] = dict.fromkeys(DRIVE_FIELDS, zero)
    return dataclasses.replace(robot, **zeros)
