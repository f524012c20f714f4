"""Trajectories: reading and writing trajectory CSV files, and the quintic planner.

A trajectory CSV has a header ``t,q1..qn,qd1..qdn,qdd1..qddn`` in [s], [rad], [rad/s] and
[rad/s^2], one set point per row. A file with only ``t,q1..qn`` is accepted too: its velocities
and accelerations then come from a not-a-knot cubic spline through the positions, and the
trajectory records that (``derivatives = "cubic-spline"``).

Rows are counted as a spreadsheet counts them: the header is row 1, the first set point row 2.
"""

from __future__ import annotations

import dataclasses

import csv
import hashlib
import math
import os
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import file_sha256

__all__ = [
    "Trajectory", "random_trajectories", "read_trajectory", "write_trajectory", "trajectory_columns",
    "quintic_duration", "plan_quintic", "JointLimitWarning", "DEFAULT_START_DEG",
    "DEFAULT_GOAL_DEG", "DEFAULT_SETPOINTS",
]

#: Start of the default planned PUMA 560 motion [deg].
DEFAULT_START_DEG = (-60.0, 20.0, -150.0, -80.0, -60.0, -120.0)
#: Goal of the default planned PUMA 560 motion [deg].
DEFAULT_GOAL_DEG = (60.0, 110.0, -60.0, 80.0, 60.0, 120.0)
#: Set points of a planned trajectory, as in Sec. 3.4.1.
DEFAULT_SETPOINTS = 31
#: Files larger than this [bytes] are parsed by pandas first; the validating parser runs only
#: to locate an error.
FAST_PARSE_BYTES = 1 << 18


class JointLimitWarning(UserWarning):
    """A position along the trajectory lies outside a joint's limits."""


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A joint trajectory sampled at N set points.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Time of each set point, strictly increasing [s].
    q : ndarray, shape (N, n)
        Joint positions [rad].
    qd : ndarray, shape (N, n)
        Joint velocities [rad/s].
    qdd : ndarray, shape (N, n)
        Joint accelerations [rad/s^2].
    derivatives : str
        ``"file"`` if qd and qdd were read, ``"cubic-spline"`` if they were derived from q,
        ``"quintic"`` if planned.
    source : str
        The file read, or a description of how the trajectory was made.
    sha256 : str
        SHA-256 of the file's bytes ("" for a trajectory not read from a file).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    derivatives: str = "file"
    source: str = ""
    sha256: str = ""

    @property
    def n_setpoints(self):
        """int: the number of set points N."""
        return int(self.t.shape[0])


def trajectory_columns(n, derivatives=True):
    """Column names of a trajectory CSV for n joints.

    Parameters
    ----------
    n : int
        Number of joints.
    derivatives : bool, optional
        Include ``qd1..qdn`` and ``qdd1..qddn``.

    Returns
    -------
    list of str
        ``["t", "q1", ..., "qn", "qd1", ..., "qddn"]``.
    """
    cols = ["t"] + [f"q{i}" for i in range(1, n + 1)]
    if derivatives:
        cols += [f"qd{i}" for i in range(1, n + 1)] + [f"qdd{i}" for i in range(1, n + 1)]
    return cols


def _parse_header(header, path):
    names = [c.strip() for c in header]
    if not names or names[0] != "t":
        raise InputError(f"the header must start with 't', got {names[0]!r}" if names else
                         "empty header", path, row=1, column=names[0] if names else None)
    qs = [c for c in names if c.startswith("q") and c[1:].isdigit()]
    n = len(qs)
    if n == 0:
        raise InputError("no joint position columns q1..qn in the header", path, row=1)
    for cols in (trajectory_columns(n, True), trajectory_columns(n, False)):
        if names == cols:
            return names, n
    # Name the first column that differs from the expected layout.
    full = trajectory_columns(n, True)
    expected = full if len(names) > n + 1 else trajectory_columns(n, False)
    for k, (got, want) in enumerate(zip(names, expected)):
        if got != want:
            raise InputError(f"expected column {want!r}, got {got!r}", path, row=1,
                             column=f"{k + 1} ({got})")
    if len(names) > len(expected):
        raise InputError(f"extra column {names[len(expected)]!r} (expected "
                         f"t,q1..q{n}[,qd1..qd{n},qdd1..qdd{n}])", path, row=1,
                         column=names[len(expected)])
    missing = expected[len(names)]
    raise InputError(f"missing column {missing!r} (expected t,q1..q{n},qd1..qd{n},qdd1..qdd{n})",
                     path, row=1, column=missing)


def read_trajectory(path, n_joints=None):
    """Read and validate a trajectory CSV file.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file: header ``t,q1..qn,qd1..qdn,qdd1..qddn`` or ``t,q1..qn`` in [s], [rad],
        [rad/s], [rad/s^2].
    n_joints : int, optional
        The robot's number of joints n; the file must have as many.

    Returns
    -------
    Trajectory
        With ``derivatives = "cubic-spline"`` when the file has positions only.

    Raises
    ------
    InputError
        If the file is missing, unreadable or empty; has no header, missing or extra columns,
        or a ragged row; has a cell that is not a finite number; if time is not strictly
        increasing; if there are fewer than 2 set points; or if the joint count differs from
        n_joints. The message names the file, the row (header = row 1) and the column.
    """
    path = str(path)
    if not os.path.isfile(path):
        raise InputError("no such file", path)
    values = None
    if os.path.getsize(path) > FAST_PARSE_BYTES:
        values, names, n = _fast_values(path, n_joints)
    if values is None:
        values, names, n = _validated_values(path, n_joints)
    t = values[:, 0]
    q = values[:, 1:n + 1]
    if len(names) == 3 * n + 1:
        qd, qdd = values[:, n + 1:2 * n + 1], values[:, 2 * n + 1:]
        how = "file"
    else:
        from scipy.interpolate import CubicSpline

        spline = CubicSpline(t, q, axis=0, bc_type="not-a-knot")
        qd, qdd = spline(t, 1), spline(t, 2)
        how = "cubic-spline"
    return Trajectory(t=t, q=q, qd=qd, qdd=qdd, derivatives=how, source=path,
                      sha256=file_sha256(path))


def _fast_values(path, n_joints):
    """Parse a large, well-formed file with pandas; None if anything is off."""
    import pandas as pd

    with open(path, newline="", encoding="utf-8", errors="replace") as fh:
        first = next((r for r in csv.reader(fh) if any(c.strip() for c in r)), None)
    if first is None:
        return None, None, None
    try:
        names, n = _parse_header(first, path)
    except InputError:
        return None, None, None
    if n_joints is not None and n != n_joints:
        return None, None, None
    try:
        frame = pd.read_csv(path, dtype=float, skip_blank_lines=True, engine="c",
                            skipinitialspace=True)
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError):
        return None, None, None
    values = frame.to_numpy()
    if (values.shape[1] != len(names) or values.shape[0] < 2 or not np.isfinite(values).all()
            or not (np.diff(values[:, 0]) > 0).all()):
        return None, None, None
    return values, names, n


def _validated_values(path, n_joints):
    """Parse cell by cell; raise an InputError naming the row and column of the first fault."""
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.reader(fh))
    except UnicodeDecodeError:
        raise InputError("not a UTF-8 text file", path) from None
    except (OSError, csv.Error) as exc:
        raise InputError(f"cannot read: {exc}", path) from None
    # Blank lines (including a trailing one) are not set points.
    numbered = [(k + 1, r) for k, r in enumerate(rows) if any(c.strip() for c in r)]
    if not numbered:
        raise InputError("empty file", path)
    header_row, header = numbered[0]
    try:
        [float(c) for c in header]
        looks_numeric = True
    except ValueError:
        looks_numeric = False
    if looks_numeric:
        raise InputError("no header (expected t,q1..qn[,qd1..qdn,qdd1..qddn])", path,
                         row=header_row)
    names, n = _parse_header(header, path)
    if n_joints is not None and n != n_joints:
        raise InputError(f"the file has {n} joints, the robot has {n_joints}", path,
                         row=header_row)
    data = numbered[1:]
    if len(data) < 2:
        raise InputError(f"fewer than 2 set points ({len(data)})", path)
    values = np.empty((len(data), len(names)))
    for k, (row_no, row) in enumerate(data):
        if len(row) != len(names):
            raise InputError(f"ragged row: {len(row)} cells, the header has {len(names)}", path,
                             row=row_no)
        for j, cell in enumerate(row):
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"not a number: {cell.strip()!r}", path, row=row_no,
                                 column=names[j]) from None
            if not math.isfinite(v):
                raise InputError(f"not a finite number: {cell.strip()!r}", path, row=row_no,
                                 column=names[j])
            values[k, j] = v
    t = values[:, 0]
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        k = int(bad[0]) + 1
        raise InputError(f"time not strictly increasing ({t[k]} after {t[k - 1]})", path,
                         row=data[k][0], column="t")
    return values, names, n


def check_joint_limits(robot, trajectory):
    """Warn for every joint whose position leaves its limits along the trajectory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints and limits q_min, q_max [rad].
    trajectory : Trajectory
        Positions q, shape (N, n) [rad].

    Returns
    -------
    list of str
        One message per offending joint (also issued as :class:`JointLimitWarning`).
    """
    messages = []
    q = trajectory.q
    for j in range(robot.n):
        out = np.nonzero((q[:, j] < robot.q_min[j]) | (q[:, j] > robot.q_max[j]))[0]
        if out.size:
            k = int(out[0])
            msg = (f"{trajectory.source}: row {k + 2}, column q{j + 1}: joint {j + 1} at "
                   f"{math.degrees(q[k, j]):.1f} deg is outside its limits "
                   f"[{math.degrees(robot.q_min[j]):.0f}, {math.degrees(robot.q_max[j]):.0f}] "
                   f"deg ({out.size} set points)")
            warnings.warn(msg, JointLimitWarning, stacklevel=2)
            messages.append(msg)
    return messages


__all__.append("check_joint_limits")


def write_trajectory(trajectory, path):
    """Write a trajectory CSV file atomically (temporary name, then rename).

    Parameters
    ----------
    trajectory : Trajectory
        The set points; t [s], q [rad], qd [rad/s], qdd [rad/s^2].
    path : str or os.PathLike
        Destination; ``"-"`` writes to standard output.

    Raises
    ------
    OSError
        If the file cannot be written.
    """
    import pandas as pd

    n = trajectory.q.shape[1]
    table = np.column_stack([trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd])
    frame = pd.DataFrame(table, columns=trajectory_columns(n, True))
    if str(path) == "-":
        import sys

        frame.to_csv(sys.stdout, index=False, float_format="%.17g")
        return
    from ..files import atomic_path

    with atomic_path(path) as tmp:
        frame.to_csv(tmp, index=False, float_format="%.17g")


def quintic_duration(robot, q_start, q_goal):
    """Shortest duration of a rest-to-rest quintic motion within the velocity and acceleration limits.

    Parameters
    ----------
    robot : Robot
        The arm, with limits qd_max [rad/s] and qdd_max [rad/s^2], shape (n,).
    q_start, q_goal : array_like, shape (n,)
        Start and goal positions [rad].

    Returns
    -------
    float
        Duration T [s]; 0 if start and goal coincide.

    Notes
    -----
    With s(u) = 10 u^3 - 15 u^4 + 6 u^5, u = t/T, the peak speed is 15/8 |dq|/T (at u = 1/2)
    and the peak acceleration 10/sqrt(3) |dq|/T^2 (at u = 1/2 -+ sqrt(3)/6), so
    T = max_i max(15 |dq_i| / (8 qd_max_i), sqrt(10 |dq_i| / (sqrt(3) qdd_max_i))).
    Fu, Gonzalez & Lee (1987), Ch. 4, plan joint-interpolated motion with the same limits.
    """
    dq = np.abs(np.asarray(q_goal, float) - np.asarray(q_start, float))
    t_vel = 15.0 * dq / (8.0 * robot.qd_max)
    t_acc = np.sqrt(10.0 * dq / (math.sqrt(3.0) * robot.qdd_max))
    return float(max(t_vel.max(), t_acc.max()))


def plan_quintic(robot, q_start, q_goal, n_setpoints=DEFAULT_SETPOINTS, duration=None):
    """Quintic joint-interpolated rest-to-rest motion at the shortest admissible duration.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints and velocity/acceleration limits.
    q_start, q_goal : array_like, shape (n,)
        Start and goal positions [rad].
    n_setpoints : int, optional
        Number of set points N, evenly spaced in time, both ends included (default 31).
    duration : float, optional
        Duration [s]; by default :func:`quintic_duration`.

    Returns
    -------
    Trajectory
        t (N,) [s], q, qd, qdd (N, n) [rad, rad/s, rad/s^2]; zero velocity and acceleration at
        both ends; ``derivatives = "quintic"``.

    Raises
    ------
    ValueError
        If n_setpoints < 2, the positions do not have n entries, or start equals goal with no
        duration given.
    """
    q_start = np.asarray(q_start, dtype=float)
    q_goal = np.asarray(q_goal, dtype=float)
    if q_start.shape != (robot.n,) or q_goal.shape != (robot.n,):
        raise ValueError(f"start and goal need {robot.n} joint positions")
    if int(n_setpoints) < 2:
        raise ValueError("a trajectory needs at least 2 set points")
    T = quintic_duration(robot, q_start, q_goal) if duration is None else float(duration)
    if T <= 0:
        raise ValueError("start and goal coincide: give a positive duration")
    t = np.linspace(0.0, T, int(n_setpoints))
    u = (t / T)[:, None]
    s = u**3 * (10 - 15 * u + 6 * u**2)
    sd = 30 * u**2 * (1 - u) ** 2 / T
    sdd = 60 * u * (1 - u) * (1 - 2 * u) / T**2
    dq = q_goal - q_start
    return Trajectory(t=t, q=q_start + s * dq, qd=sd * dq, qdd=sdd * dq, derivatives="quintic",
                      source=f"quintic {np.degrees(q_start).round(6).tolist()} -> "
                             f"{np.degrees(q_goal).round(6).tolist()} deg, T = {T:.6g} s")


def random_trajectories(robot, k, seed=0, n_setpoints=31):
    """K random rest-to-rest quintic trajectories inside the joint limits.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints, position limits q_min, q_max [rad] and velocity and
        acceleration limits qd_max [rad/s], qdd_max [rad/s^2].
    k : int
        Number of trajectories K, >= 1.
    seed : int, optional
        Seed of the :class:`numpy.random.Generator` (``numpy.random.default_rng(seed)``).
    n_setpoints : int, optional
        Set points N per trajectory, >= 2 (31, as in Sec. 3.4.1).

    Returns
    -------
    list of Trajectory
        Trajectory i goes from a start to a goal drawn uniformly inside [q_min, q_max] (start
        and goal of every trajectory drawn in turn, shape (n,) each) in the shortest time
        within the velocity and acceleration limits
        (:func:`gd_analyze.io.trajectory.plan_quintic`); t (N,) [s], q, qd, qdd (N, n) [rad,
        rad/s, rad/s^2]; its ``source`` is ``"random-<seed>-<i>"`` and its ``sha256`` is "".

    Raises
    ------
    ValueError
        If k < 1, n_setpoints < 2, or the seed is not a non-negative integer.

    Notes
    -----
    The quintic's peak speed and acceleration are reached between set points in general, so
    the sampled |qd| and |qdd| stay within the limits. Source: Sec. 3.4.1 of Fu, Gonzalez &
    Lee (1987) ranks one preplanned PUMA 560 trajectory of 31 set points; a sweep repeats that
    over many.
    """
    k = int(k)
    if k < 1:
        raise ValueError(f"the number of trajectories must be >= 1, got {k}")
    if int(n_setpoints) < 2:
        raise ValueError("a trajectory needs at least 2 set points")
    if isinstance(seed, bool) or int(seed) != seed or int(seed) < 0:
        raise ValueError(f"the seed must be a non-negative integer, got {seed!r}")
    seed = int(seed)
    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    out = []
    for i in range(k):
        q_start = rng.uniform(lo, hi)
        q_goal = rng.uniform(lo, hi)
        traj = plan_quintic(robot, q_start, q_goal, n_setpoints=int(n_setpoints))
        out.append(dataclasses.replace(traj, source=f"random-{seed}-{i}", sha256=""))
    return out
