"""Planning: quintic rest-to-rest trajectories within a robot's limits, random ones for sweeps.

:func:`plan_quintic` makes the ``gd-analyze plan`` trajectory: a quintic polynomial in time per
joint, from rest to rest, at the shortest duration within the velocity and acceleration limits
(:func:`quintic_duration`), sampled at N set points (31, as in Sec. 3.4.1 of Fu, Gonzalez & Lee
1987). :func:`random_trajectories` draws many for a sweep; :func:`write_provenance` records how
a planned file was made.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..files import atomic_path, file_sha256, read_regular
from ..model.limits import acceleration_limits
from .trajectory import Trajectory

if TYPE_CHECKING:                       # for the type hints only
    import os

    from numpy.typing import ArrayLike

    from ..model.robot import Robot

__all__ = ["DEFAULT_START_DEG", "DEFAULT_GOAL_DEG", "DEFAULT_SETPOINTS",
           "quintic_duration", "quintic_min_durations", "default_motion", "default_motion_range",
           "user_positions", "plan_quintic", "quintic_plan", "QuinticPlan", "SampledMotion", "CHUNK_SETPOINTS", "random_trajectories",
           "provenance_path", "write_provenance", "read_provenance", "provenance_mismatch",
           "joint_title", "check_velocity_limits",
           "PLACEHOLDER_QD"]

#: Start of the default planned PUMA 560 motion [deg].
DEFAULT_START_DEG = (-60.0, 20.0, -150.0, -80.0, -60.0, -120.0)
#: Goal of the default planned PUMA 560 motion [deg].
DEFAULT_GOAL_DEG = (60.0, 110.0, -60.0, 80.0, 60.0, 120.0)
#: Set points of a planned trajectory, as in Sec. 3.4.1.
DEFAULT_SETPOINTS = 31
#: A velocity limit above this [rad/s; m/s for a prismatic joint] is beyond physical sense for
#: an arm's joint: a placeholder (e.g. URDF ``velocity="1000"``), warned about by ``plan``.
PLACEHOLDER_QD = 100.0


def joint_title(robot: Robot, j: int | np.integer[Any]) -> str:
    """How messages name joint j: its number, and its URDF name where the robot has one.

    Parameters
    ----------
    robot : Robot
        The arm (``robot.metadata["urdf_joints"]`` names a URDF chain's joints).
    j : int
        Zero-based joint index.

    Returns
    -------
    str
        E.g. ``"joint 1 ('joint1')"`` or ``"joint 1"``.
    """
    names = robot.metadata.get("urdf_joints") or ()  # type: ignore[union-attr]  # never None (Robot.__post_init__)
    return f"joint {j + 1} ({str(names[j])!r})" if j < len(names) else f"joint {j + 1}"


def check_velocity_limits(robot: Robot, instead: str = "") -> str | None:
    """Check that a robot has the velocity limits planning needs, and find placeholders.

    Parameters
    ----------
    robot : Robot
        The arm, with qd_max, shape (n,) [rad/s or m/s], NaN where not given.
    instead : str, optional
        What the command offers in place of the limit, ending the refusal (e.g. ``"give
        --duration with --ignore-limits"``; nothing where it offers nothing).

    Returns
    -------
    str or None
        A warning (one line) naming the joints whose limit exceeds :data:`PLACEHOLDER_QD`, or
        None.

    Raises
    ------
    InputError
        One line naming the first joint without a velocity limit and the key that gives one.
    """

    qd = np.asarray(robot.qd_max, dtype=float)
    pris = np.asarray(robot.prismatic, bool)
    for j in range(robot.n):
        if not (math.isfinite(qd[j]) and qd[j] > 0):
            key = ("<limit velocity> in a URDF" if robot.convention == "chain"
                   else "qd_max" if pris[j] else "qd_max_deg")
            raise InputError(f"{joint_title(robot, j)} has no velocity limit: planning needs "
                             f"one ({key})" + (instead and f", or {instead}"), robot.source)
    high = np.flatnonzero(qd > PLACEHOLDER_QD)
    if not high.size:
        return None
    shown = ", ".join(f"{joint_title(robot, j)} {float(qd[j]):g} "
                      f"{'m/s' if pris[j] else 'rad/s'}" for j in high)
    return (f"velocity limits above {PLACEHOLDER_QD:g} rad/s (m/s) look like placeholders, "
            f"not physical limits: {shown}; the plan is as fast as they allow (give --duration "
            f"for a realistic one)")


def quintic_duration(robot: Robot, q_start: ArrayLike, q_goal: ArrayLike) -> float:
    """Shortest duration of a rest-to-rest quintic motion within the velocity and acceleration limits.

    Parameters
    ----------
    robot : Robot
        The arm, with limits qd_max [rad/s] and qdd_max [rad/s^2], shape (n,); where qdd_max
        is NaN (a URDF robot), :func:`gd_analyze.model.limits.acceleration_limits` supplies the
        default ``DEFAULT_QDD_PER_QD * qd_max``.
    q_start, q_goal : array_like, shape (n,)
        Start and goal positions [rad].

    Returns
    -------
    float
        Duration T [s]; 0 if start and goal coincide.

    Raises
    ------
    ValueError
        If a joint has neither an acceleration nor a finite velocity limit.

    Notes
    -----
    With s(u) = 10 u^3 - 15 u^4 + 6 u^5, u = t/T, the peak speed is 15/8 |dq|/T (at u = 1/2)
    and the peak acceleration 10/sqrt(3) |dq|/T^2 (at u = 1/2 -+ sqrt(3)/6), so
    T = max_i max(15 |dq_i| / (8 qd_max_i), sqrt(10 |dq_i| / (sqrt(3) qdd_max_i))).
    Fu, Gonzalez & Lee (1987), Ch. 4, plan joint-interpolated motion with the same limits.
    """
    t_vel, t_acc = quintic_min_durations(robot, q_start, q_goal)
    return float(max(t_vel.max(), t_acc.max()))


def quintic_min_durations(robot: Robot, q_start: ArrayLike, q_goal: ArrayLike
                          ) -> tuple[np.ndarray, np.ndarray]:
    """Per joint, the shortest quintic duration within its velocity and its acceleration limit.

    Parameters
    ----------
    robot, q_start, q_goal
        As for :func:`quintic_duration`: the arm with its limits, and start and goal
        positions, shape (n,) [rad].

    Returns
    -------
    t_vel, t_acc : ndarray, shape (n,)
        15 |dq_i| / (8 qd_max_i) and sqrt(10 |dq_i| / (sqrt(3) qdd_max_i)) [s] (see
        :func:`quintic_duration`).
    """
    dq = np.abs(np.asarray(q_goal, float) - np.asarray(q_start, float))
    t_vel = 15.0 * dq / (8.0 * robot.qd_max)
    t_acc = np.sqrt(10.0 * dq / (math.sqrt(3.0) * acceleration_limits(robot)[0]))
    return t_vel, t_acc


def default_motion(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """The default start and goal of ``gd-analyze plan`` for a robot.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints and position limits q_min, q_max [rad or m].

    Returns
    -------
    q_start, q_goal : ndarray, shape (n,)
        [rad or m]. The PUMA 560 gets :data:`DEFAULT_START_DEG` -> :data:`DEFAULT_GOAL_DEG`.
        Any other robot moves joint k (k = 0, 1, ...) between the fractions
        ``low = 0.20 + 0.04 (k mod 5)`` and ``high = 0.80 - 0.04 ((3 k + 1) mod 5)`` of its
        range, upwards for even k and downwards for odd k; a joint without finite limits takes
        the range [-120, 120] deg (revolute) or [-0.1, 0.3] m (prismatic).

    Notes
    -----
    The fractions, and so the spans, differ within any five joints, and joints five apart move
    in opposite directions, so no two of the first ten joints move alike even with equal limits: with one motion for all of them, as a
    plain quarter-to-three-quarters plan gives, terms in sin(q_i - q_j) vanish along the whole
    trajectory, and a simplified model fit to it would drop them for nothing.
    """
    if robot.name in ("puma560", "puma560-drives") and robot.n == len(DEFAULT_START_DEG):
        return np.radians(DEFAULT_START_DEG), np.radians(DEFAULT_GOAL_DEG)
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    finite = np.isfinite(lo) & np.isfinite(hi)
    pris = np.asarray(robot.prismatic, bool)
    lo = np.where(finite, lo, np.where(pris, -0.1, -2 * math.pi / 3))
    hi = np.where(finite, hi, np.where(pris, 0.3, 2 * math.pi / 3))
    k = np.arange(robot.n)
    low = 0.20 + 0.04 * (k % 5)
    high = 0.80 - 0.04 * ((3 * k + 1) % 5)
    down = k % 2 == 1
    return (lo + np.where(down, high, low) * (hi - lo),
            lo + np.where(down, low, high) * (hi - lo))


def user_positions(robot: Robot, values: ArrayLike) -> np.ndarray:
    """Joint positions given by a user in degrees (revolute) and metres (prismatic), in SI.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    values : sequence of float, length n
        [deg] for a revolute joint, [m] for a prismatic one.

    Returns
    -------
    ndarray, shape (n,)
        [rad or m].
    """
    values = np.asarray(values, dtype=float)
    return np.where(np.asarray(robot.prismatic, bool), values, np.radians(values))


#: Set points computed and written at a time by :meth:`SampledMotion.chunks` (for 6 joints
#: about 75 MB of arrays, and some 250 MB with their CSV text: ``plan puma560 --setpoints
#: 10000000`` peaks at 465 MiB, ``analysis/plan_memory.py``), so that ``plan --setpoints
#: 100000000`` runs in bounded memory.
CHUNK_SETPOINTS = 2**19


@dataclasses.dataclass(frozen=True)
class SampledMotion:
    """A motion over [0, T] sampled on demand at N set points evenly spaced in time, piece by
    piece (:class:`QuinticPlan`, :class:`~gd_analyze.trajectory.excitation.Excitation`).

    Attributes
    ----------
    duration : float
        T [s], > 0.
    n_setpoints : int
        N >= 2, both ends included.
    source : str
        How the motion was made.
    """

    duration: float
    n_setpoints: int
    source: str

    def times(self, start: int, stop: int) -> np.ndarray:
        """Times of set points start to stop - 1, bit for bit ``numpy.linspace(0, T, N)[start:stop]``.

        Parameters
        ----------
        start, stop : int
            0 <= start < stop <= N.

        Returns
        -------
        ndarray, shape (stop - start,)
            [s].
        """
        T, N = self.duration, self.n_setpoints
        t = np.arange(start, stop, dtype=float) * (T / (N - 1)) + 0.0   # numpy.linspace's
        if stop == N:
            t[-1] = T
        return t

    def rows(self, start: int, stop: int) -> Trajectory:
        """Set points start to stop - 1, at :meth:`times` (each subclass gives its own).

        Parameters
        ----------
        start, stop : int
            0 <= start < stop <= N.

        Returns
        -------
        Trajectory
            t (stop - start,) [s], q, qd, qdd (stop - start, n) [rad, rad/s, rad/s^2].
        """
        raise NotImplementedError

    def chunks(self, size: int | None = None) -> Iterator[Trajectory]:
        """The set points in consecutive pieces of at most ``size``.

        Parameters
        ----------
        size : int, optional
            Set points per piece, >= 1 (default :data:`CHUNK_SETPOINTS`).

        Yields
        ------
        Trajectory
            :meth:`rows` of each piece, in order.
        """
        size = CHUNK_SETPOINTS if size is None else int(size)
        for start in range(0, self.n_setpoints, size):
            yield self.rows(start, min(start + size, self.n_setpoints))

    @property
    def trajectory(self) -> Trajectory:
        """Trajectory: every set point at once, in the memory of all N (:meth:`chunks` needs
        that of one piece)."""
        return self.rows(0, self.n_setpoints)


@dataclasses.dataclass(frozen=True)
class QuinticPlan(SampledMotion):
    """A quintic rest-to-rest motion, sampled on demand at N set points evenly spaced in time.

    Attributes
    ----------
    q_start, q_goal : ndarray, shape (n,)
        Start and goal positions [rad; m for a prismatic joint].
    duration : float
        T [s], > 0.
    n_setpoints : int
        N >= 2, both ends included.
    source : str
        How the motion was made, e.g. ``"quintic [-60.0] -> [60.0] deg, T = 2 s"``.
    """

    q_start: np.ndarray
    q_goal: np.ndarray

    def rows(self, start: int, stop: int) -> Trajectory:
        """Set points start to stop - 1, bit for bit those of the whole motion sampled at once.

        Parameters
        ----------
        start, stop : int
            0 <= start < stop <= N.

        Returns
        -------
        Trajectory
            t (stop - start,) [s] (:meth:`~SampledMotion.times`), q, qd, qdd (stop - start, n)
            [rad, rad/s, rad/s^2]; s(u) = 10 u^3 - 15 u^4 + 6 u^5 with u = t / T,
            q = q_start + s (q_goal - q_start).
        """
        T, t = self.duration, self.times(start, stop)
        u = (t / T)[:, None]
        s = u**3 * (10 - 15 * u + 6 * u**2)
        sd = 30 * u**2 * (1 - u) ** 2 / T
        sdd = 60 * u * (1 - u) * (1 - 2 * u) / T**2
        dq = self.q_goal - self.q_start
        return Trajectory(t=t, q=self.q_start + s * dq, qd=sd * dq, qdd=sdd * dq,
                          derivatives="quintic", source=self.source)


def quintic_plan(robot: Robot, q_start: ArrayLike, q_goal: ArrayLike,
                 n_setpoints: int = DEFAULT_SETPOINTS,
                 duration: float | None = None) -> QuinticPlan:
    """Quintic joint-interpolated rest-to-rest motion at the shortest admissible duration,
    not yet sampled (:meth:`QuinticPlan.chunks` samples it piece by piece).

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
    QuinticPlan

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
    pris = np.asarray(getattr(robot, "prismatic", np.zeros(robot.n, bool)), bool)

    def show(x):            # degrees for revolute joints, metres for prismatic ones
        return np.where(pris, x, np.degrees(x)).round(6).tolist()

    units = "deg or m" if pris.any() else "deg"
    return QuinticPlan(q_start=q_start, q_goal=q_goal, duration=T, n_setpoints=int(n_setpoints),
                       source=f"quintic {show(q_start)} -> {show(q_goal)} {units}, "
                              f"T = {T:.6g} s")


def plan_quintic(robot: Robot, q_start: ArrayLike, q_goal: ArrayLike,
                 n_setpoints: int = DEFAULT_SETPOINTS, duration: float | None = None
                 ) -> Trajectory:
    """Quintic joint-interpolated rest-to-rest motion at the shortest admissible duration,
    sampled at once (:func:`quintic_plan`, then its :attr:`~SampledMotion.trajectory`).

    Parameters
    ----------
    robot, q_start, q_goal, n_setpoints, duration
        As :func:`quintic_plan`.

    Returns
    -------
    Trajectory
        t (N,) [s], q, qd, qdd (N, n) [rad, rad/s, rad/s^2]; zero velocity and acceleration at
        both ends; ``derivatives = "quintic"``.

    Raises
    ------
    ValueError
        As :func:`quintic_plan`.
    """
    return quintic_plan(robot, q_start, q_goal, n_setpoints, duration).trajectory


def default_motion_range(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """Position range for drawing random motions: the limits, or a stand-in where infinite.

    Parameters
    ----------
    robot : Robot
        The arm, with limits q_min, q_max [rad or m] (may be infinite) and ``prismatic``.

    Returns
    -------
    lo, hi : ndarray, shape (n,)
        The limits where finite; -pi, pi for a revolute and 0, 0.2 m for a prismatic joint
        where not.
    """
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    pris = np.asarray(getattr(robot, "prismatic", np.zeros(robot.n, bool)), bool)
    lo = np.where(np.isfinite(lo), lo, np.where(pris, 0.0, -math.pi))
    hi = np.where(np.isfinite(hi), hi, np.where(pris, 0.2, math.pi))
    return lo, hi


def random_trajectories(robot: Robot, k: int, seed: int = 0,
                        n_setpoints: int = 31) -> list[Trajectory]:
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
        (:func:`plan_quintic`); t (N,) [s], q, qd, qdd (N, n) [rad,
        rad/s, rad/s^2]; its ``source`` is ``"random-<seed>-<i>"`` and its ``sha256`` is "".

    Raises
    ------
    ValueError
        If k < 1, n_setpoints < 2, or the seed is not a non-negative integer.

    Notes
    -----
    Where a position limit is infinite (a continuous joint), the draw is within -+180 deg
    (revolute) or 0 to 0.2 m (prismatic).
    The quintic's peak speed and acceleration are reached between set points in general, so
    the sampled |qd| and |qdd| stay within the limits. Source: Sec. 3.4.1 of Fu, Gonzalez &
    Lee (1987) ranks one preplanned PUMA 560 trajectory of 31 set points; a sweep repeats that
    over many.
    """
    k = int(k)
    if k < 1:
        raise ValueError(f"the number of trajectories must be >= 1, got {k}")
    if isinstance(seed, bool) or int(seed) != seed or int(seed) < 0:
        raise ValueError(f"the seed must be a non-negative integer, got {seed!r}")
    seed = int(seed)
    rng = np.random.default_rng(seed)
    lo, hi = default_motion_range(robot)
    # each plan's start, then its goal (arguments run left to right)
    return [dataclasses.replace(plan_quintic(robot, rng.uniform(lo, hi), rng.uniform(lo, hi),
                                             n_setpoints=int(n_setpoints)),
                                source=f"random-{seed}-{i}", sha256="") for i in range(k)]


def provenance_path(csv_path: str | os.PathLike[str]) -> Path:
    """The provenance file written beside a planned trajectory: ``<stem>.provenance.json``.

    Parameters
    ----------
    csv_path : str or os.PathLike

    Returns
    -------
    pathlib.Path

    Examples
    --------
    >>> provenance_path("data/panda_trajectory.csv").name
    'panda_trajectory.provenance.json'
    """
    p = Path(csv_path)
    return p.with_name(p.stem + ".provenance.json")


#: Largest provenance sidecar read [bytes]; the tool's own are about 2 KB.
PROVENANCE_LIMIT = 1 << 20


def read_provenance(csv_path: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The provenance written beside a planned trajectory, if there is a readable one.

    Parameters
    ----------
    csv_path : str or os.PathLike
        The trajectory CSV.

    Returns
    -------
    dict or None
        The record of :func:`write_provenance`, or None when there is no such file, it is not
        a regular file of at most :data:`PROVENANCE_LIMIT` bytes (a FIFO would hang the run,
        ``/dev/zero`` fill its memory) or it is not a JSON object (a provenance is advice,
        never a reason to refuse a trajectory).
    """
    side = provenance_path(csv_path)
    try:
        record = json.loads(read_regular(side, PROVENANCE_LIMIT).decode("utf-8"))
    except (OSError, ValueError, RecursionError):
        return None
    return record if isinstance(record, dict) else None


def provenance_mismatch(csv_path: str | os.PathLike[str], robot: Robot) -> str | None:
    """A one-line warning when a trajectory was planned for another robot than this one.

    Parameters
    ----------
    csv_path : str or os.PathLike
        The trajectory CSV; its provenance is ``<stem>.provenance.json`` beside it.
    robot : Robot
        The robot the trajectory is used with (e.g. a simplified model's); a ``+payload``
        suffix of its name is not a difference.

    Returns
    -------
    str or None
        None when there is no provenance, or it names this robot with this robot file's
        SHA-256 (or none); else the warning, naming both robots.
    """
    record = read_provenance(csv_path)
    if record is None or not isinstance(record.get("robot"), str):
        return None
    theirs, ours = record["robot"], robot.name.split("+payload")[0]
    side = provenance_path(csv_path).name
    if theirs != ours:
        return (f"{csv_path}: planned for robot {theirs[:80]!r} (says {side}), not for "
                f"{ours!r}: the torques compare another robot's motion")
    sha = record.get("robot_sha256")
    if isinstance(sha, str) and sha and robot.sha256 and sha != robot.sha256:
        return (f"{csv_path}: planned for another version of robot {ours!r} (its robot file's "
                f"SHA-256 differs from {side}'s)")
    return None


def write_provenance(csv_path: str | os.PathLike[str], record: Mapping[str, Any]) -> Path:
    """Write a planned trajectory's provenance beside it, atomically, as JSON.

    Parameters
    ----------
    csv_path : str or os.PathLike
        The trajectory CSV (already written: its SHA-256 is recorded).
    record : dict
        Tool, command, robot and settings (JSON-serialisable).

    Returns
    -------
    pathlib.Path
        The file written (:func:`provenance_path`).
    """
    out = provenance_path(csv_path)
    doc = {**record, "output": Path(csv_path).name, "output_sha256": file_sha256(csv_path)}
    with atomic_path(out) as tmp:
        Path(tmp).write_text(json.dumps(doc, indent=2, allow_nan=False) + "\n")
    return out
