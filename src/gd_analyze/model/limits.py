"""Sane magnitudes: the largest values gd-analyze accepts at its boundaries.

Every number that enters the tool (robot file, trajectory CSV, command-line option, model JSON)
is checked against these limits, so that the G-D terms, which grow as m l^2 qd^2, stay far from
overflow: with every input at its limit, the largest torque is about 1e6 kg * (1e3 m)^2 *
(1e4 rad/s)^2 = 1e20 N m, well inside the range of a float (1.8e308). Every computed array is
checked for being finite as well (:func:`check_finite`).

The README's "Limits" section lists the same values.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError, is_number

if TYPE_CHECKING:
    from .robot import Robot

__all__ = ["LIMITS", "check_finite", "first_beyond", "exact_text", "real_values",
           "DEFAULT_QDD_PER_QD", "acceleration_limits"]

#: Largest accepted magnitude of each input quantity, in SI units.
LIMITS = {
    "t": 1e10,          # |time| [s]: Unix time stamps (1.8e9 s in 2027) as ROS logs write them
    "q": 1e4,           # |joint position| [rad]
    "qd": 1e4,          # |joint velocity| [rad/s]
    "qdd": 1e8,         # |joint acceleration| [rad/s^2]
    "length": 1e3,      # |d|, |a|, |centre of mass coordinate|, |payload com| [m]
    "mass": 1e6,        # link or payload mass [kg]
    "inertia": 1e9,     # |inertia tensor element| [kg m^2]
    "gravity": 1e3,     # |gravity vector component| [m/s^2]
    "duration": 1e9,    # planned duration [s]
    "min_duration": 1e-6,   # shortest planned duration [s]
    # the least time step of a trajectory [s]: control's desired motion, a quintic per step,
    # divides by the step's fifth power, 0 in doubles below about 1e-62 s (numpy's warnings,
    # then NaN); a plan's steps are at least 1e-14 s (min_duration over 10^8 set points)
    "min_step": 1e-60,
    "angle_deg": 1e6,   # |an angle or angular limit given in degrees| [deg]
    # the least velocity or acceleration limit of a region, as the command line reads it [deg/s,
    # deg/s^2; m/s, m/s^2]: a smaller one overflows a planned duration (15 |dq| / (8 qd_max))
    # or underflows the motions it allows; certify.region.RegionLimits (SI) takes its radians
    "least_rate": 1e-9,
    # a URDF's size, checked before Pinocchio's parser reads it: its parser recurses once per
    # link down the tree and overflows the C stack (SIGSEGV) on a chain of 4,000 links
    "urdf_links": 10_000,   # <link> elements
    "urdf_joints": 10_000,  # <joint> elements
    "urdf_depth": 1_000,    # links on the longest path from the root (the root is depth 0)
}


def exact_text(value: float) -> str:
    """A number in as few significant digits as give it back exactly (at least 6), so that a
    value just beyond a limit never prints as the limit.

    Parameters
    ----------
    value : float

    Returns
    -------
    str

    Examples
    --------
    >>> exact_text(1.0000001e8), exact_text(1e8), exact_text(0.1)
    ('1.0000001e+08', '1e+08', '0.1')
    """
    v = float(value)
    for digits in range(6, 18):
        text = f"{v:.{digits}g}"
        if float(text) == v or not np.isfinite(v):
            return text
    return repr(v)


def first_beyond(values: ArrayLike, limit: float) -> tuple[int, ...] | None:
    """Index of the first value whose magnitude exceeds ``limit`` (or is not finite).

    Parameters
    ----------
    values : array_like
        Any shape; searched in C order.
    limit : float
        The largest accepted magnitude.

    Returns
    -------
    tuple of int or None
        The index (as from ``np.unravel_index``) of the first offending value, or None.

    Examples
    --------
    >>> first_beyond([1.0, -3.0, 2.0], 2.5)
    (1,)
    >>> first_beyond([1.0, float("nan")], 2.5)
    (1,)
    >>> first_beyond([1.0, -float("inf")], float("inf"))
    (1,)
    >>> first_beyond([1.0], 2.5) is None
    True
    """
    arr = np.asarray(values, dtype=float)
    if arr.size and -limit <= arr.min() and arr.max() <= limit and limit < math.inf:
        return None                 # min and max are NaN when any value is, and fail here
    # NaN compares False, so it is caught; +-inf is caught even under an infinite limit
    bad = ~(np.abs(arr) <= limit) | ~np.isfinite(arr)
    if not bad.any():
        return None
    flat = int(np.argmax(bad.ravel()))
    return tuple(int(i) for i in np.unravel_index(flat, arr.shape))


def real_values(name: str, values: ArrayLike) -> np.ndarray:
    """An array of real numbers as floats; complex or non-numeric values refused.

    Parameters
    ----------
    name : str
        The array's name, for the message (e.g. ``"qd"``).
    values : array_like
        Any shape: numbers (integers or floats, or objects that are real numbers).

    Returns
    -------
    ndarray of float
        The same shape.

    Raises
    ------
    InputError
        (A ValueError.) If the values are complex (numpy would drop the imaginary part with a
        warning only), text, booleans or anything else that is not a real number.

    Examples
    --------
    >>> real_values("q", [1, 2.5]).tolist()
    [1.0, 2.5]
    >>> real_values("q", [1 + 2j])
    Traceback (most recent call last):
    ...
    gd_analyze.errors.InputError: q must hold real numbers, got complex128 values
    """
    arr = np.asarray(values)
    kind = arr.dtype.kind
    if kind == "O":             # objects: each a real number (int, float, Fraction...)
        if not all(is_number(v) for v in arr.ravel()):
            raise InputError(f"{name} must hold real numbers, got objects that are not")
        return arr.astype(float)
    if kind not in "iuf":
        raise InputError(f"{name} must hold real numbers, got {arr.dtype} values")
    return arr.astype(float, copy=False)


def check_finite(name: str, values: ArrayLike, what: str = "computed",
                 first: int = 0) -> np.ndarray:
    """Raise if an array holds NaN or inf.

    Parameters
    ----------
    name : str
        The array's name, for the message (e.g. ``"D"``).
    values : array_like
        The array; axis 0 is the set point where it has one.
    what : str, optional
        How the array came about, for the message.
    first : int, optional
        The index of the array's first set point in the trajectory (a block of it), for the
        message.

    Returns
    -------
    ndarray
        The array, unchanged.

    Raises
    ------
    InputError
        If any element is not finite. Inputs within :data:`LIMITS` never give one, so the
        message points at the inputs.
    """
    arr = np.asarray(values)
    if arr.dtype.kind in "fc" and not np.isfinite(arr).all():
        idx = first_beyond(arr, np.inf)
        where = f" at set point {first + idx[0]}" if idx and arr.ndim > 1 else ""
        raise InputError(f"the {what} {name} is not finite{where}: the inputs are beyond the "
                         f"magnitudes gd-analyze supports (see docs/limits-and-safety.md)")
    return arr


#: Where a robot gives no acceleration limit (a URDF has none), ``plan`` and the region take
#: qdd_max_i = DEFAULT_QDD_PER_QD * qd_max_i [1/s]: full speed in 0.5 s. (The Panda's published
#: limits give ratios of 2.9 to 7.7 s^-1, so the default is on the cautious side.)
DEFAULT_QDD_PER_QD = 2.0


def acceleration_limits(robot: Robot, qdd_max: ArrayLike | None = None
                        ) -> tuple[np.ndarray, str]:
    """The acceleration limits a plan uses, and where they come from.

    Parameters
    ----------
    robot : Robot
        The arm: velocity limits qd_max and acceleration limits qdd_max (NaN where unknown),
        shape (n,) [rad/s, rad/s^2; m/s, m/s^2 for a prismatic joint].
    qdd_max : array_like, shape (n,), optional
        Limits given by the user, in SI units [rad/s^2 or m/s^2]; they replace the robot's.

    Returns
    -------
    qdd_max : ndarray, shape (n,)
        The limits [rad/s^2 or m/s^2].
    source : str
        ``"robot"``, ``"--qdd-max"``, or the default's rule and the joints it applies to.

    Raises
    ------
    ValueError
        If given limits do not have n entries or are not finite and positive, or a joint with
        no acceleration limit has no finite velocity limit either.
    """
    n = robot.n
    if qdd_max is not None:
        qdd: np.ndarray = np.asarray(qdd_max, dtype=float).reshape(-1)
        if qdd.shape != (n,):
            raise ValueError(f"{qdd.size} acceleration limits for {n} joints")
        if not (np.isfinite(qdd).all() and (qdd > 0).all()):
            raise ValueError("acceleration limits must be finite and positive")
        return qdd, "--qdd-max"
    qdd = np.array(robot.qdd_max, dtype=float)
    missing = ~np.isfinite(qdd)
    if not missing.any():
        return qdd, "robot"
    qd = np.asarray(robot.qd_max, dtype=float)
    bad = missing & ~(np.isfinite(qd) & (qd > 0))
    if bad.any():
        raise ValueError(f"joint {int(np.argmax(bad)) + 1} has neither an acceleration nor a "
                         "finite velocity limit")
    qdd[missing] = DEFAULT_QDD_PER_QD * qd[missing]
    joints = ", ".join(str(j + 1) for j in np.flatnonzero(missing))
    joints = f"joint {joints}" if missing.sum() == 1 else f"joints {joints}"
    return qdd, (f"default {DEFAULT_QDD_PER_QD:g} s^-1 x qd_max for {joints} (the robot "
                 "gives no acceleration limits)")
