"""The joint-limit region of an arm, the torque scale over it, and a model's error sampled on it.

R = {q_min <= q <= q_max, |qd| <= qd_max, |qdd| <= qdd_max}. Over R the torque of
joint i is, per point q,

    tau_i = sum_j a_ij(q) qdd_j + sum_{j, l} C_ijl(q) qd_j qd_l + g_i(q)

(:mod:`gd_analyze.certify.regressor_bounds`), so its largest |value| over qdd is reached
with qdd_j = sign(a_ij) qdd_max_j exactly, and over qd it is sought at the vertices qd_j =
+-qd_max_j. The same formula with the dropped pairs' parameters gives the error of a pruned
model (Khalil & Kleinfinger 1987: tau = Y_b beta).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..dynamics.regressor_kernels import link_channels
from ..model.limits import LIMITS, real_values

__all__ = ["Region", "RegionLimits", "Excursion", "FULL_TURN", "VALUE_EPS", "beyond_limits", "joint_region", "missing_limits", "sample_positions", "channel_values",
           "packed_channel_count", "velocity_channels", "full_channels", "ChannelValues",
           "worst_states", "worst_above", "region_scale", "qd_vertices", "velocity_vertices", "region_samples",
           "sampled_error", "REFINE_JOINTS"]


def packed_channel_count(n: int) -> int:
    """Channels of :func:`channel_values`' packed layout: 1 gravity + n inertial + n (n + 1) / 2
    velocity (each symmetric pair j, l stored once).

    Parameters
    ----------
    n : int
        Joints of the arm.

    Returns
    -------
    int
        P, the second axis of :func:`channel_values`.

    Examples
    --------
    >>> packed_channel_count(6)
    28
    """
    return 1 + n + n * (n + 1) // 2


def velocity_channels(n: int) -> np.ndarray:
    """Where each velocity channel of the full layout is in the packed one.

    Parameters
    ----------
    n : int

    Returns
    -------
    ndarray of int, shape (n n,)
        For the full channel 1 + n + n j + l (the coefficient C_jl of qd_j qd_l), its packed
        velocity channel k (channel 1 + n + k of :func:`channel_values`): pair (min(j, l),
        max(j, l)) in the order of ``numpy.triu_indices(n)``, so that C_jl and C_lj are the
        same stored value.

    Examples
    --------
    >>> velocity_channels(2).tolist()
    [0, 1, 1, 2]
    """
    k = np.empty((n, n), int)
    jj, ll = np.triu_indices(n)
    k[jj, ll] = np.arange(jj.size)
    k[ll, jj] = k[jj, ll]
    return k.reshape(-1)


def _first_joints(n: int, M: int) -> np.ndarray:
    """The packed channels of an n-joint arm that involve only its first M joints, in the
    packed order of an M-joint arm: gravity, inertial j < M, velocity j <= l < M."""
    jj, ll = np.triu_indices(M)
    return np.concatenate([np.arange(1 + M),
                           1 + n + velocity_channels(n).reshape(n, n)[jj, ll]])


@dataclass(frozen=True)
class ChannelValues:
    """:func:`channel_values` at B positions, stored by link: a column of link k moves only
    the torques of joints 1..k+1 and depends only on their velocities and accelerations, so
    it is held on those rows and channels alone (the others are 0).

    Attributes
    ----------
    n : int
        Joints of the arm.
    columns : int
        m, the columns.
    groups : tuple of (int, ndarray of int, ndarray)
        Per link with columns: M (its joints, link index + 1), the columns' indices in
        0..m-1 (ascending), and their values, shape (B, P_M, M, m_M), P_M =
        :func:`packed_channel_count` (M), in the packed layout of an M-joint arm.

    Notes
    -----
    The rows and channels beyond each column's link are not stored: on a random 15-joint
    chain (86 base parameters) this holds 30 % of the packed dense array (B, P, n, m), and
    17 % of the full layout (B, 1 + n + n^2, n, m).
    """

    n: int
    columns: int
    groups: tuple

    @property
    def positions(self) -> int:
        """int: B, the positions."""
        return int(self.groups[0][2].shape[0]) if self.groups else 0

    def packed(self) -> np.ndarray:
        """The dense packed layout.

        Returns
        -------
        ndarray, shape (B, P, n, m)
            P = :func:`packed_channel_count` (n): channel 0 gravity, 1 + j inertial and
            1 + n + k velocity (:func:`velocity_channels`); zero beyond each column's link.
        """
        out = np.zeros((self.positions, packed_channel_count(self.n), self.n, self.columns))
        for M, idx, Vm in self.groups:
            out[:, _first_joints(self.n, M)[:, None], :M, idx[None, :]] = (
                Vm.transpose(1, 3, 0, 2))
        return out

    def weighted(self, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The weighted sums of the columns' channels, per part.

        Parameters
        ----------
        weights : ndarray, shape (3, m)
            Per part (inertial, velocity, gravity) each column's weight.

        Returns
        -------
        g : ndarray, shape (B, n)
            sum_m G_im w_2m.
        a : ndarray, shape (B, n, n)
            a[:, i, j] = sum_m A_jim w_0m.
        Cq : ndarray, shape (B, n n, n)
            Cq[:, n j + l, i] = sum_m C_jlim w_1m (= Cq[:, n l + j, i]).
        """
        n, B = self.n, self.positions
        g, a = np.zeros((B, n)), np.zeros((B, n, n))
        Cp = np.zeros((B, n * (n + 1) // 2, n))
        for M, idx, Vm in self.groups:
            w = weights[:, idx]
            if w[2].any():
                g[:, :M] += Vm[:, 0] @ w[2]
            if w[0].any():
                a[:, :M, :M] += np.einsum("bjim,m->bij", Vm[:, 1:1 + M], w[0])
            if w[1].any():
                Cp[:, _first_joints(n, M)[1 + M:] - 1 - n, :M] += Vm[:, 1 + M:] @ w[1]
        return g, a, Cp[:, velocity_channels(n)]


def full_channels(V: ChannelValues) -> np.ndarray:
    """:func:`channel_values` in the full layout of
    :func:`gd_analyze.certify.regressor_bounds.channel_values`.

    Parameters
    ----------
    V : ChannelValues
        Of an n-joint arm, m columns, B positions.

    Returns
    -------
    ndarray, shape (B, 1 + n + n^2, n, m)
        Channel 0 gravity, 1 + j inertial, 1 + n + n j + l velocity C_jl (= C_lj).
    """
    n = V.n
    return V.packed()[:, np.concatenate([np.arange(1 + n), 1 + n + velocity_channels(n)])]


def channel_values(robot, q, columns):
    """The coefficient functions of the regressor at points q, every channel.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q : ndarray, shape (B, n)
        Joint positions [rad or m].
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c.

    Returns
    -------
    ChannelValues
        By link (:class:`ChannelValues`); :meth:`ChannelValues.packed` gives the dense packed
        layout, P = :func:`packed_channel_count` (n): channel 0 gravity, 1 + j inertial, and
        1 + n + k velocity, k the pair j <= l in the order of ``numpy.triu_indices(n)``
        (:func:`velocity_channels`), the symmetrized C_jl = C_lj, half the coefficient of
        qd_j qd_l (j != l). :func:`full_channels` gives the layout of
        :func:`gd_analyze.certify.regressor_bounds.channel_values`.

    Raises
    ------
    ValueError
        If q does not have n columns.

    Notes
    -----
    The regressor (:func:`gd_analyze.dynamics.base_parameters.regressor`) is linear in qdd and
    quadratic in qd, W(q, qd, qdd) = G(q) + sum_j A_j(q) qdd_j + sum_{j, l} C_jl(q) qd_j qd_l;
    :func:`gd_analyze.dynamics.regressor_kernels.link_channels` computes G, A_j and C_jl
    of each link's columns directly, each position's frames and Jacobians once (memory: the
    values alone, O(B n^3 m)). They equal, to round-off, the regressor at the states
    (qd, qdd) = (e_j, e_j) (C_jj + A_j), qd = e_j + e_l (C_jj + C_ll + 2 C_jl) and
    (0, 0) (G), and every position's values are computed alone, so they do not depend on
    the batch.
    """
    q = np.asarray(q, float)
    n = robot.n
    if q.ndim != 2 or q.shape[1] != n:
        raise ValueError(f"q must have shape (B, {n}), got {q.shape}")
    columns = np.asarray(columns, int)
    return ChannelValues(n=n, columns=int(columns.size),
                         groups=link_channels(robot, columns, q))


#: How a revolute joint whose region spans a full turn (2 pi or more) is stored and printed.
FULL_TURN = "any angle (full turn)"


def _per_joint(values, n, name):
    """A user's limits, one for all joints or one per joint, as an array of n."""
    v = np.asarray(values, float)
    v = np.repeat(v, n, axis=0) if v.shape[0] == 1 else v
    if v.shape[0] != n:
        raise ValueError(f"{name}: {v.shape[0]} values for {n} joints (give one for all or one "
                         "per joint)")
    return v


@dataclass(frozen=True)
class RegionLimits:
    """The region a user sets, in place of the robot's own limits (None: the robot's).

    Attributes
    ----------
    q_limits : tuple of (float, float), optional
        (lo, hi) per joint, or one pair for all joints [rad or m].
    qd_max : tuple of float, optional
        One per joint, or one for all [rad/s or m/s].
    qdd_max : tuple of float, optional
        One per joint, or one for all [rad/s^2 or m/s^2].

    Raises
    ------
    ValueError
        If a value is not a real number (a bool, a str), NaN or infinite, a velocity or acceleration limit is below the command
        line's least (``LIMITS["least_rate"]`` of :mod:`gd_analyze.model.limits`, 1e-9 deg/s,
        taken in rad/s: 1.745e-11), or a position range has lo >= hi; the message names the
        option (``--q-limits``, ``--qd-max``, ``--qdd-max``).

    Examples
    --------
    >>> RegionLimits(qd_max=(1.0,)).settings()
    {'region_qd_max': [1.0]}
    """

    q_limits: tuple | None = None
    qd_max: tuple | None = None
    qdd_max: tuple | None = None

    def __post_init__(self):
        rates = self._given()
        if (pairs := rates.pop("q_limits", None)) is not None:
            if not pairs.size or not np.isfinite(pairs).all():
                raise ValueError("--q-limits: every limit must be a finite number")
            if not (pairs[:, 0] < pairs[:, 1]).all():
                raise ValueError("--q-limits: each range LO:HI needs LO < HI")
        least = np.radians(LIMITS["least_rate"])    # the command line's least, deg/s in rad/s
        for name, v in rates.items():
            if not v.size or not (np.isfinite(v) & (v >= least)).all():
                raise ValueError(f"--{name.replace('_', '-')}: every limit must be finite and at "
                                 f"least {least:.4g}, got {', '.join(f'{x:g}' for x in v)}")

    def settings(self):
        """The limits as the provenance stores them (SI units; only those given).

        Returns
        -------
        dict
            ``region_q_limits`` [[lo, hi], ...], ``region_qd_max``, ``region_qdd_max``.
        """
        return {f"region_{name}": v.tolist() for name, v in self._given().items()}

    def _given(self):
        """The limits given, by field name, as float arrays: q_limits of shape (m, 2), the
        velocity and acceleration limits of shape (m,)."""
        return {k: real_values("--" + k.replace("_", "-"), v).reshape((-1, 2) if k == "q_limits"
                                                                     else -1)
                for k in ("q_limits", "qd_max", "qdd_max") if (v := getattr(self, k)) is not None}


@dataclass(frozen=True)
class Excursion:
    """Where a trajectory leaves a region the most.

    Attributes
    ----------
    joint : int
        0-based.
    quantity : {"q", "qd", "qdd"}
    value : float
        Its extreme along the trajectory (|qd|, |qdd|; q itself) [rad, m; /s; /s^2].
    limit : float
        The limit it passes (q: the bound on that side).
    ratio : float
        qd, qdd: value / limit; q: the excess over the bound relative to the range.
    prismatic : bool
    """

    joint: int
    quantity: str
    value: float
    limit: float
    ratio: float
    prismatic: bool = False

    def text(self):
        """One clause naming the joint, the quantity and the amount (degrees for a revolute
        joint, as the summary prints the region).

        Returns
        -------
        str

        Examples
        --------
        >>> Excursion(0, "qd", 4.1, 2.05, 2.0).text()
        'joint 1 qd reaches 2x its limit (234.9 deg/s > 117.5 deg/s)'
        """
        unit = {"q": "", "qd": "/s", "qdd": "/s^2"}[self.quantity]
        unit = ("m" if self.prismatic else "deg") + unit
        show = (lambda v: v) if self.prismatic else math.degrees
        if self.quantity == "q":
            side = ">" if self.value > self.limit else "<"
            return (f"joint {self.joint + 1} q reaches {show(self.value):.4g} {unit}, beyond its "
                    f"limit ({show(self.value):.4g} {unit} {side} {show(self.limit):.4g} {unit})")
        return (f"joint {self.joint + 1} {self.quantity} reaches {self.ratio:.3g}x its limit "
                f"({show(self.value):.4g} {unit} > {show(self.limit):.4g} {unit})")


#: Machine epsilons of its limit by which a value may pass it: the round-off of the data
#: checked (a planner that ends exactly on a limit rounds a few times).
VALUE_EPS = 4


def beyond_limits(x: np.ndarray, lo: np.ndarray | None, hi: np.ndarray | None,
                  round_off: np.ndarray | float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Where values pass their limits by more than their round-off: the one test of whether a
    trajectory stays in a region (:meth:`Region.excursion`,
    :meth:`gd_analyze.simplify.guarantee.Guarantee.covers`).

    Parameters
    ----------
    x : ndarray, shape (N, n)
        The values: q [rad, m], |qd| [rad/s, m/s] or |qdd| [rad/s^2, m/s^2].
    lo, hi : ndarray, shape (n,), or None
        Their lower and upper limits in x's unit; None: no limit on that side.
    round_off : ndarray or float, broadcastable to (N, n), optional
        A bound on |x - x_exact| [x's unit], the round-off of computing x (e.g.
        :func:`gd_analyze.jobs.control.motion_round_off`); 0 for data as given.

    Returns
    -------
    below, above : ndarray of bool, shape (N, n)
        x < lo - a and x > hi + a, a = round_off + :data:`VALUE_EPS` eps |limit|; NaN (or a
        round-off that is not finite) is both.

    Examples
    --------
    >>> beyond_limits(np.array([[1.0 + 2e-16, 1.0 + 1e-9]]), None, np.ones(2))[1]
    array([[False,  True]])
    """
    def allowance(limit):               # an infinite limit allows nothing more
        size = np.abs(np.where(np.isfinite(limit), limit, 0.0))
        a = np.asarray(round_off, float) + VALUE_EPS * np.finfo(float).eps * size
        return np.where(np.isfinite(a), a, np.nan)
    x = np.asarray(x, float)
    above = np.zeros(x.shape, bool) if hi is None else ~(x <= hi + allowance(hi))
    below = np.zeros(x.shape, bool) if lo is None else ~(x >= lo - allowance(lo))
    return below, above


def _extremes(q, full_turn):
    """min and max per column of a non-empty (N, n) array of joint positions, each taken
    modulo 2 pi into [-pi, pi) where ``full_turn`` (:meth:`Region._wrapped`, on those
    columns only); NaN where a column holds NaN."""
    lo, hi = q.min(axis=0), q.max(axis=0)
    for j in np.flatnonzero(np.broadcast_to(full_turn, lo.shape)):
        column = _wrap(q[:, j])
        lo[j], hi[j] = column.min(), column.max()
    return lo, hi


def _wrap(angle):
    """An angle [rad] taken modulo 2 pi into [-pi, pi)."""
    return np.mod(angle + np.pi, 2 * np.pi) - np.pi


def _peak(x):
    """max |x| per column of a non-empty (N, n) array, without a temporary of its size; NaN
    where a column holds NaN."""
    return np.maximum(x.max(axis=0), -x.min(axis=0))


@dataclass(frozen=True, eq=False)
class Region:
    """A box of joint positions with velocity and acceleration limits.

    Attributes
    ----------
    q_min, q_max : ndarray, shape (n,)
        [rad or m]; a revolute joint whose range spans a full turn (2 pi or more) is given as
        [-pi, pi] (the torque is 2 pi periodic in its q) and flagged :attr:`full_turn`.
    qd_max : ndarray, shape (n,)
        [rad/s or m/s].
    qdd_max : ndarray, shape (n,)
        [rad/s^2 or m/s^2].
    prismatic : ndarray of bool, shape (n,), optional
        The prismatic joints (None: all revolute).
    qdd_assumed : ndarray of bool, shape (n,), optional
        The acceleration limits assumed (the robot gives none and the user set none).
    qdd_rule : str, optional
        The rule of the assumed ones, e.g. ``"2 s^-1 x qd max"``.
    source : str, optional
        Where the limits come from, e.g. ``"the robot's limits"``.
    notes : tuple of str, optional
        The user's limits clipped to the robot's, one clause each.
    """

    q_min: np.ndarray
    q_max: np.ndarray
    qd_max: np.ndarray
    qdd_max: np.ndarray
    prismatic: np.ndarray | None = None
    qdd_assumed: np.ndarray | None = None
    qdd_rule: str = ""
    source: str = ""
    notes: tuple = ()

    @property
    def n(self):
        """int: the number of joints."""
        return int(np.asarray(self.q_min).size)

    @property
    def is_prismatic(self):
        """ndarray of bool, shape (n,): the prismatic joints."""
        return np.zeros(self.n, bool) if self.prismatic is None else \
            np.asarray(self.prismatic, bool)

    @property
    def assumed(self):
        """ndarray of bool, shape (n,): the acceleration limits assumed."""
        return np.zeros(self.n, bool) if self.qdd_assumed is None else \
            np.asarray(self.qdd_assumed, bool)

    @property
    def full_turn(self):
        """ndarray of bool, shape (n,): revolute joints whose range spans 2 pi or more."""
        span = np.asarray(self.q_max, float) - np.asarray(self.q_min, float)
        return ~self.is_prismatic & (span >= 2 * np.pi * (1 - 1e-12))

    def contains(self, q, qd, qdd, rtol=1e-9):
        """Whether every state lies in the region (up to rtol of each limit).

        Parameters
        ----------
        q, qd, qdd : ndarray, shape (N, n)
            [rad, rad/s, rad/s^2; m, m/s, m/s^2].
        rtol : float, optional
            Relative slack for limits reached exactly.

        Returns
        -------
        ndarray of bool, shape (3, n)
            Per quantity (q, qd, qdd) and joint: all set points within the limit.
        """
        span = np.maximum(np.abs(self.q_max - self.q_min), 1e-300)
        q, qd, qdd = (np.atleast_2d(np.asarray(x, float)) for x in (q, qd, qdd))
        if not (q.shape[0] and qd.shape[0] and qdd.shape[0]):
            return np.ones((3, self.n), bool)
        # column extremes, no temporaries of the arrays' size; a NaN makes them NaN, and
        # every compare False
        lo, hi = _extremes(q, self.full_turn)
        return np.stack([
            (lo >= self.q_min - rtol * span) & (hi <= self.q_max + rtol * span),
            _peak(qd) <= self.qd_max * (1 + rtol),
            _peak(qdd) <= self.qdd_max * (1 + rtol)])

    def _wrapped(self, q):
        """q with a full-turn joint's angle taken modulo 2 pi into [-pi, pi)."""
        q = np.atleast_2d(np.asarray(q, float))
        full = self.full_turn
        if not full.any():
            return q
        return np.where(full, _wrap(q), q)

    def excursion(self, q, qd, qdd):
        """Where a trajectory leaves the region the most, or None if it stays in it.

        Parameters
        ----------
        q, qd, qdd : ndarray, shape (N, n)
            Set points [rad, rad/s, rad/s^2; m, m/s, m/s^2], judged as data
            (:func:`beyond_limits`).

        Returns
        -------
        Excursion or None
            The joint and quantity with the largest relative excess: |qd| / qd_max - 1 and
            |qdd| / qdd_max - 1, or for q the excess over its bound divided by the range.
            The value is the trajectory's true extreme (not its first set point outside).
        """
        q = self._wrapped(q)
        inside = ~np.stack([np.any(beyond_limits(q, self.q_min, self.q_max), axis=(0, 1))]
                           + [beyond_limits(np.abs(np.atleast_2d(np.asarray(x, float))), None,
                                            lim)[1].any(axis=0)
                              for x, lim in ((qd, self.qd_max), (qdd, self.qdd_max))])
        if inside.all():
            return None
        pris = self.is_prismatic
        found = []
        span = np.maximum(self.q_max - self.q_min, 1e-300)
        for j in np.flatnonzero(~inside[0]):
            hi, lo = float(q[:, j].max()), float(q[:, j].min())
            up, down = (hi - self.q_max[j]) / span[j], (self.q_min[j] - lo) / span[j]
            value, limit, excess = (hi, self.q_max[j], up) if up >= down else \
                (lo, self.q_min[j], down)
            found.append((excess, Excursion(int(j), "q", value, float(limit), 1 + excess,
                                            bool(pris[j]))))
        for k, (name, x, lim) in enumerate((("qd", qd, self.qd_max), ("qdd", qdd, self.qdd_max))):
            x = np.abs(np.atleast_2d(np.asarray(x, float)))
            for j in np.flatnonzero(~inside[k + 1]):
                top = float(x[:, j].max())
                ratio = top / float(lim[j])
                found.append((ratio - 1, Excursion(int(j), name, top, float(lim[j]), ratio,
                                                   bool(pris[j]))))
        return max(found, key=lambda f: f[0])[1]

    def parts(self):
        """The region per limit kind: a label with its units and the per-joint values.

        Returns
        -------
        list of (str, str)
            ``("q [deg]", "1 [-160, 160], ...")``, ``("qd max [deg/s]", ...)`` and
            ``("qdd max [deg/s^2]", ...)``, the last label saying which acceleration limits
            are assumed; a revolute joint spanning a full turn is :data:`FULL_TURN`.
            Revolute joints in degrees, prismatic ones in metres (each value with its unit
            when an arm has both).
        """
        pris = self.is_prismatic
        mixed = pris.any() and not pris.all()

        def show(j, v):
            return f"{v:.4g}" if pris[j] else f"{math.degrees(v):.4g}"

        def head(label, suffix):
            if mixed:
                return label
            return f"{label} [{'m' if pris.all() else 'deg'}{suffix}]"

        def unit(j, suffix):
            return f" {'m' if pris[j] else 'deg'}{suffix}" if mixed else ""

        full = self.full_turn
        q = ", ".join(f"{j + 1} {FULL_TURN}" if full[j] else
                      f"{j + 1} [{show(j, self.q_min[j])}, {show(j, self.q_max[j])}]{unit(j, '')}"
                      for j in range(self.n))
        qd = ", ".join(f"{j + 1} {show(j, self.qd_max[j])}{unit(j, '/s')}" for j in range(self.n))
        qdd = ", ".join(f"{j + 1} {show(j, self.qdd_max[j])}{unit(j, '/s^2')}"
                        for j in range(self.n))
        assumed = self.assumed
        rule = self.qdd_rule or "not given"
        if assumed.all():
            note = f" (assumed: {rule})"
        elif assumed.any():
            note = (f" (assumed for joint{'s' if assumed.sum() > 1 else ''} "
                    f"{', '.join(str(j + 1) for j in np.flatnonzero(assumed))}: {rule})")
        else:
            note = ""
        return [(f"{head('q', '')}", q), (f"{head('qd max', '/s')}", qd),
                (f"{head('qdd max', '/s^2')}{note}", qdd)]

    def lines(self):
        """The region in three lines, one per limit kind, as every output prints it.

        Returns
        -------
        list of str
            ``"region: q [deg] 1 [-160, 160], ..."``, ``"qd max [deg/s] 1 100, ..."`` and
            ``"qdd max [deg/s^2] ..."`` (:meth:`parts`).

        Examples
        --------
        >>> r = Region(np.array([-1.0, -np.pi]), np.array([1.0, np.pi]), np.array([2.0, 2.0]),
        ...            np.array([4.0, 4.0]), qdd_assumed=np.array([True, True]),
        ...            qdd_rule="2 s^-1 x qd max")
        >>> print("\\n".join(r.lines()))
        region: q [deg] 1 [-57.3, 57.3], 2 any angle (full turn)
        qd max [deg/s] 1 114.6, 2 114.6
        qdd max [deg/s^2] (assumed: 2 s^-1 x qd max) 1 229.2, 2 229.2
        """
        return [("region: " if k == 0 else "") + f"{label} {text}"
                for k, (label, text) in enumerate(self.parts())]

    def to_dict(self):
        """The region as ``simplified_model.json`` stores it (SI units).

        Returns
        -------
        dict
            ``q``: per joint [lo, hi] or :data:`FULL_TURN`; ``qd_max``, ``qdd_max``,
            ``qdd_max_assumed``, ``prismatic``, ``units``, and ``qdd_rule``, ``source``,
            ``notes`` where set.
        """
        full = self.full_turn
        out = {"units": "rad, rad/s, rad/s^2 (m, m/s, m/s^2 for a prismatic joint)",
               "q": [FULL_TURN if full[j] else [float(self.q_min[j]), float(self.q_max[j])]
                     for j in range(self.n)],
               "qd_max": [float(v) for v in self.qd_max],
               "qdd_max": [float(v) for v in self.qdd_max],
               "qdd_max_assumed": [bool(v) for v in self.assumed],
               "prismatic": [bool(v) for v in self.is_prismatic]}
        for key in ("qdd_rule", "source"):
            if getattr(self, key):
                out[key] = getattr(self, key)
        if self.notes:
            out["notes"] = list(self.notes)
        return out

    @classmethod
    def from_dict(cls, spec, n):
        """The region of :meth:`to_dict` (already checked by the schema).

        Parameters
        ----------
        spec : dict
        n : int
            The robot's number of joints.

        Returns
        -------
        Region

        Raises
        ------
        ValueError
            If a list has not n entries, a range is not [lo, hi] with lo < hi, or a limit is
            not finite and positive; the message names the key.
        """
        def vec(key, kind=float):
            v = spec.get(key)
            if not isinstance(v, list) or len(v) != n:
                raise ValueError(f"region.{key}: expected {n} entries")
            return np.array(v, kind)
        lo, hi = np.empty(n), np.empty(n)
        q = spec.get("q")
        if not isinstance(q, list) or len(q) != n:
            raise ValueError(f"region.q: expected {n} entries")
        for j, r in enumerate(q):
            if r == FULL_TURN:
                lo[j], hi[j] = -np.pi, np.pi
            elif isinstance(r, list) and len(r) == 2 and all(
                    isinstance(x, (int, float)) and math.isfinite(x) for x in r) and r[0] < r[1]:
                lo[j], hi[j] = r
            else:
                raise ValueError(f"region.q: entry {j + 1} must be [lo, hi] with lo < hi or "
                                 f"{FULL_TURN!r}")
        qd, qdd = vec("qd_max"), vec("qdd_max")
        for key, v in (("qd_max", qd), ("qdd_max", qdd)):
            if not (np.isfinite(v).all() and (v > 0).all()):
                raise ValueError(f"region.{key}: limits must be finite and positive")
        return cls(q_min=lo, q_max=hi, qd_max=qd, qdd_max=qdd,
                   prismatic=vec("prismatic", bool), qdd_assumed=vec("qdd_max_assumed", bool),
                   qdd_rule=str(spec.get("qdd_rule", "")), source=str(spec.get("source", "")),
                   notes=tuple(str(x) for x in spec.get("notes", ())))


def missing_limits(robot, limits=None):
    """Why an arm has no region: the first joint without a position or velocity limit.

    Parameters
    ----------
    robot : Robot
    limits : RegionLimits, optional
        The user's limits, which fill what the robot lacks.

    Returns
    -------
    str
        e.g. "joint 2 has no velocity limit"; "" when every joint has both (a revolute joint
        without position limits is continuous and covers the full circle).
    """
    given_q = limits is not None and limits.q_limits is not None
    given_qd = limits is not None and limits.qd_max is not None
    for j in range(robot.n):
        if robot.prismatic[j] and not given_q and not (np.isfinite(robot.q_min[j])
                                                       and np.isfinite(robot.q_max[j])):
            return f"joint {j + 1} has no position limit"
        if not given_qd and not (np.isfinite(robot.qd_max[j]) and robot.qd_max[j] > 0):
            return f"joint {j + 1} has no velocity limit"
    return ""


def _clip(values, lo, hi, what, prismatic, suffix):
    """Values clipped into [lo, hi] (NaN bounds: none), and one clause per joint clipped."""
    out = np.clip(values, np.where(np.isfinite(lo), lo, -np.inf),
                  np.where(np.isfinite(hi), hi, np.inf))
    notes = []
    for j in np.flatnonzero(out != values):
        unit = ("m" if prismatic[j] else "deg") + suffix
        show = (lambda v: v) if prismatic[j] else math.degrees
        notes.append(f"joint {j + 1}'s {what} {show(values[j]):.4g} {unit} is beyond the "
                     f"robot's limit: clipped to {show(out[j]):.4g} {unit}")
    return out, notes


def joint_region(robot, qdd_max, limits=None, qdd_assumed=None, qdd_rule=""):
    """The region of an arm's own limits, or of the user's within them.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    qdd_max : array_like, shape (n,)
        Acceleration limits [rad/s^2 or m/s^2] (the robot's, or the planner's default where it
        has none: :func:`gd_analyze.model.limits.acceleration_limits`).
    limits : RegionLimits, optional
        The user's limits, each replacing the robot's. Those beyond the robot's own position,
        velocity or (where it gives one) acceleration limits are clipped to them, and the
        region's ``notes`` say so: the region never claims states beyond the robot's limits.
    qdd_assumed : array_like of bool, shape (n,), optional
        The joints whose ``qdd_max`` is assumed (the robot gives none); a user's limit is not.
    qdd_rule : str, optional
        The rule of the assumed limits, e.g. ``"2 s^-1 x qd max"``.

    Returns
    -------
    Region

    Raises
    ------
    ValueError
        If a limit is missing (:func:`missing_limits`), qdd_max is not finite and positive,
        a user's list has neither one nor n entries, or a user's position range lies wholly
        outside the robot's (the message names the option).
    """
    why = missing_limits(robot, limits)
    if why:
        raise ValueError(why)
    n = robot.n
    qdd_max = np.asarray(qdd_max, float)
    if qdd_max.shape != (n,) or not (np.isfinite(qdd_max).all() and (qdd_max > 0).all()):
        raise ValueError("acceleration limits must be finite and positive, one per joint")
    pris = np.asarray(robot.prismatic, bool)
    assumed = np.zeros(n, bool) if qdd_assumed is None else np.asarray(qdd_assumed, bool)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi).astype(float)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, np.pi).astype(float)
    qd, qdd = np.asarray(robot.qd_max, float).copy(), qdd_max.copy()
    notes = []
    if limits is not None and limits.q_limits is not None:
        pairs = _per_joint(np.asarray(limits.q_limits, float).reshape(-1, 2), n, "--q-limits")
        ulo, nlo = _clip(pairs[:, 0], robot.q_min, robot.q_max, "lower position limit", pris, "")
        uhi, nhi = _clip(pairs[:, 1], robot.q_min, robot.q_max, "upper position limit", pris, "")
        bad = np.flatnonzero(~(ulo < uhi))
        if bad.size:
            raise ValueError(f"--q-limits: joint {bad[0] + 1}'s range lies outside the robot's "
                             "position limits")
        lo, hi, notes = ulo, uhi, notes + nlo + nhi
    if limits is not None and limits.qd_max is not None:
        qd, more = _clip(_per_joint(np.atleast_1d(limits.qd_max), n, "--qd-max"), np.full(n, np.nan),
                         np.asarray(robot.qd_max, float), "velocity limit", pris, "/s")
        notes += more
    if limits is not None and limits.qdd_max is not None:
        own = np.where(assumed, np.nan, np.asarray(robot.qdd_max, float))
        qdd, more = _clip(_per_joint(np.atleast_1d(limits.qdd_max), n, "--qdd-max"), np.full(n, np.nan), own,
                          "acceleration limit", pris, "/s^2")
        notes += more
        assumed = np.zeros(n, bool)
    full = ~pris & ((hi - lo) >= 2 * np.pi * (1 - 1e-12))     # a full turn: the whole circle
    lo = np.where(full, -np.pi, lo)
    hi = np.where(full, np.pi, hi)
    given = [] if limits is None else [k for k, v in (("--q-limits", limits.q_limits),
                                                      ("--qd-max", limits.qd_max),
                                                      ("--qdd-max", limits.qdd_max))
                                       if v is not None]
    source = ("the robot's limits" if not given else
              f"the user's {', '.join(given)}, the robot's limits otherwise")
    return Region(q_min=lo.astype(float), q_max=hi.astype(float), qd_max=qd.astype(float),
                  qdd_max=qdd.astype(float), prismatic=pris.copy(), qdd_assumed=assumed.copy(),
                  qdd_rule=qdd_rule if assumed.any() else "", source=source, notes=tuple(notes))


def sample_positions(region, count, seed=0):
    """Joint positions in the region: uniform, plus every joint at its limits in turn.

    Parameters
    ----------
    region : Region
    count : int
        Uniform samples.
    seed : int, optional

    Returns
    -------
    ndarray, shape (M, n)
        [rad or m], M = count + 2 n + 2 (each joint at either limit with the others uniform,
        and all joints at their lower and upper limits).
    """
    rng = np.random.default_rng(seed)
    n = region.q_min.size
    q = rng.uniform(region.q_min, region.q_max, (count, n))
    ext = rng.uniform(region.q_min, region.q_max, (2 * n, n))
    for j in range(n):
        ext[2 * j, j], ext[2 * j + 1, j] = region.q_min[j], region.q_max[j]
    return np.vstack([q, ext, region.q_min, region.q_max])


def qd_vertices(qd_max):
    """The vertices of the velocity box, one of each pair x, -x.

    Parameters
    ----------
    qd_max : ndarray, shape (n,)
        Velocity limits [rad/s or m/s].

    Returns
    -------
    ndarray, shape (K, n)
        The 2^(n-1) sign patterns whose first sign is + times qd_max, or 4,096 random ones
        beyond 13 joints. A quadratic form takes the same value at x and -x
        (x^T C x = (-x)^T C (-x)), so its largest |value| over the vertices is reached at
        one of these: the velocity terms h are such forms in qd (Eq. (3.4-27)).

    Examples
    --------
    >>> qd_vertices(np.array([1.0, 2.0])).tolist()
    [[1.0, -2.0], [1.0, 2.0]]
    """
    n = qd_max.size
    if n > 13:                                       # 4,096 vertices at most: random signs
        signs = np.random.default_rng(0).choice([-1.0, 1.0], (4096, n))
    else:
        signs = np.array(list(itertools.product([-1.0, 1.0], repeat=n - 1)),
                         float).reshape(2 ** (n - 1), n - 1)  # one joint: one empty pattern
        signs = np.hstack([np.ones((signs.shape[0], 1)), signs])
    return signs * qd_max


def velocity_vertices(C, qd_max):
    """The velocity vertices a family of quadratic forms needs, over the joints it involves.

    Parameters
    ----------
    C : ndarray, shape (B, n, n, n)
        C[b, j, l, i]: the coefficient of qd_j qd_l in form i at position b.
    qd_max : ndarray, shape (n,)
        Velocity limits [rad/s or m/s].

    Returns
    -------
    verts : ndarray, shape (K, n)
        Vertices of the velocity box on which every form takes its largest |value| plus any
        constant, as :func:`qd_vertices` would find it: the joints S that appear in no form
        (C[:, j, :, :] and C[:, :, j, :] all zero) keep one sign (+ for joint 1, - for the
        others), and the joints in S take every sign pattern (one of each pair x, -x when
        joint 1 is in S), in the order of :func:`qd_vertices`, so that the first vertex
        reaching a largest value is the one :func:`qd_vertices` reaches first. K = 2^(|S|-1)
        (2^|S| when joint 1 is not in S) instead of 2^(n-1); random signs as in
        :func:`qd_vertices` beyond 13 joints in S.
    used : ndarray of int, shape (s,)
        S, ascending.

    Notes
    -----
    A form sum_{j,l} C_jl qd_j qd_l does not depend on qd_j for j outside S, so its values
    over the vertices are those over S's sign patterns: the maxima are the same, found at
    2^(n - |S|) times fewer vertices.
    """
    n = qd_max.size
    nonzero = C != 0
    used = np.flatnonzero(nonzero.any(axis=(0, 2, 3)) | nonzero.any(axis=(0, 1, 3)))
    if used.size == n:
        return qd_vertices(qd_max), used
    fixed = -np.ones(n)
    fixed[0] = 1.0
    if used.size == 0:
        return (fixed * qd_max)[None, :], used
    signs = (qd_vertices(np.ones(used.size)) if used[0] == 0 or used.size > 13
             else np.array(list(itertools.product([-1.0, 1.0], repeat=used.size)), float))
    verts = np.tile(fixed, (signs.shape[0], 1))
    verts[:, used] = signs
    return verts * qd_max, used


#: Elements of each (positions, vertices, joints) product of :func:`worst_states` (32 MB).
_ELEMENTS = 1 << 22


def worst_states(V, weights, qd_max, qdd_max):
    """The largest |torque| of weighted columns over the velocity and acceleration limits, at
    each sampled position.

    Parameters
    ----------
    V : ChannelValues
        :func:`channel_values` at B positions.
    weights : ndarray, shape (3, m)
        Per part (inertial, velocity, gravity) the parameter value of each column (0: left
        out) [kg m^2, kg m, kg].
    qd_max, qdd_max : ndarray, shape (n,)
        [rad/s, rad/s^2; m/s, m/s^2].

    Returns
    -------
    value : ndarray, shape (B, n)
        max over qd vertices and |qdd| <= qdd_max of |tau_i| [N m or N].
    qd : ndarray, shape (B, n, n)
        Per position and joint i, the velocity vertex reached.
    qdd : ndarray, shape (B, n, n)
        Per position and joint i, the acceleration reached: sign(a_ij) qdd_max_j.
    """
    B, n = V.positions, V.n
    qd_max = np.asarray(qd_max, float)
    g, a, Cq = V.weighted(np.asarray(weights, float))           # (B, n), (B, n, n), (B, n n, n)
    verts, used = velocity_vertices(Cq.reshape(B, n, n, n), qd_max)   # (K, n), (s,)
    if used.size < n:                                           # the forms' joints only
        Cq = Cq.reshape(B, n, n, n)[:, used][:, :, used].reshape(B, used.size ** 2, n)
    outer = (verts[:, used, None] * verts[:, None, used]).reshape(verts.shape[0], -1)
    k = np.empty((B, n), int)
    sign = np.empty((B, n, 1))
    value = np.empty((B, n))
    rows = max(1, _ELEMENTS // (verts.shape[0] * n))           # bounded memory: positions a go
    for r in range(0, B, rows):     # one matrix product (K, s s) @ (s s, rows n)
        Cr = Cq[r:r + rows]
        quad = (outer @ Cr.transpose(1, 0, 2).reshape(Cr.shape[1], Cr.shape[0] * n)).reshape(
            -1, Cr.shape[0], n) + g[None, r:r + rows]                   # qd^T C_i qd: (K, rows, n)
        k[r:r + rows] = np.abs(quad).argmax(axis=0)                     # (rows, n)
        at = np.take_along_axis(quad, k[None, r:r + rows], 0)[0]        # (rows, n)
        value[r:r + rows] = np.abs(at)
        sign[r:r + rows] = np.sign(at)[:, :, None]
    value += np.abs(a) @ qdd_max
    sign = np.where(sign == 0, 1.0, sign)
    qdd = np.sign(a) * sign * qdd_max
    return value, verts[k], np.where(qdd == 0, qdd_max, qdd)


def worst_above(V: ChannelValues, weights: np.ndarray, qd_max: np.ndarray,
                qdd_max: np.ndarray, limit: np.ndarray) -> np.ndarray:
    """The largest |tau_i| of :func:`worst_states` over the positions, where it may exceed a
    limit: searched over the velocity vertices only at the positions where a cheap upper
    bound exceeds the limit.

    Parameters
    ----------
    V, weights, qd_max, qdd_max
        As :func:`worst_states` takes them: the channel values at B positions, the weights
        (3, m) and the limits (n,) [rad/s, rad/s^2; m/s, m/s^2].
    limit : ndarray, shape (n,)
        [N m or N].

    Returns
    -------
    ndarray, shape (n,)
        Per joint i: ``worst_states(...)[0][:, i].max()`` if it exceeds ``limit[i]``,
        otherwise a value at most ``limit[i]`` (-inf where no position needed the search)
        [N m or N].

    Notes
    -----
    At a vertex of the velocity box qd_j^2 = qd_max_j^2, so |tau_i| <= |G_i + sum_j C_jj
    qd_max_j^2| + sum_{j != l} |C_jl| qd_max_j qd_max_l + sum_j |A_ij| qdd_max_j, the largest
    over the vertices bounded without searching them (widened by 1e-12 for its round-off).
    """
    n = V.n
    qd_max, qdd_max = np.asarray(qd_max, float), np.asarray(qdd_max, float)
    g, a, Cq = V.weighted(np.asarray(weights, float))
    w = np.outer(qd_max, qd_max).reshape(-1)
    diag = np.zeros(n * n, bool)
    diag[np.arange(n) * (n + 1)] = True
    cheap = (np.abs(g + np.einsum("bci,c->bi", Cq[:, diag], w[diag]))
             + np.einsum("bci,c->bi", np.abs(Cq[:, ~diag]), w[~diag])
             + np.abs(a) @ qdd_max) * (1 + 1e-12)                          # (B, n)
    rows = np.flatnonzero((cheap > np.asarray(limit, float)[None, :]).any(axis=1))
    if rows.size == 0:
        return np.full(n, -np.inf)
    sub = ChannelValues(n, V.columns, tuple((M, idx, Vm[rows]) for M, idx, Vm in V.groups))
    return worst_states(sub, weights, qd_max, qdd_max)[0].max(axis=0)


def region_scale(robot, region, columns, beta, torque_floor=0.0, samples=1000, seed=0,
                 refine=1, values=None):
    """s_i = max(largest |tau_i| found over the region, torque floor), and where.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    region : Region
    columns : ndarray of int, shape (m,)
        The base parameters' flat standard indices.
    beta : ndarray, shape (m,)
        Their values.
    torque_floor : float, optional
        [N m or N].
    samples : int, optional
        Uniform position samples (plus the extremes of :func:`sample_positions`).
    seed : int, optional
    refine : int, optional
        Best samples per joint (0: none) polished by a local maximisation over q
        (scipy.optimize.minimize, L-BFGS-B within the position limits).
    values : (ndarray, ndarray), optional
        Positions (B, n) and their :func:`channel_values`, when already sampled.

    Returns
    -------
    scale : ndarray, shape (n,)
        [N m or N]. A found maximum is a lower bound of the true one, so a bound relative to
        it errs on the safe side.
    state : ndarray, shape (n, 3 n)
        Per joint, (q, qd, qdd) where |tau_i| reaches the found maximum.
    """
    from scipy.optimize import minimize

    n = robot.n
    W = np.tile(np.asarray(beta, float), (3, 1))
    q, V = values if values is not None else (None, None)
    if q is None:
        q = sample_positions(region, samples, seed)
        V = channel_values(robot, q, columns)
    value, qd, qdd = worst_states(V, W, region.qd_max, region.qdd_max)
    best = value.max(axis=0)
    state = np.zeros((n, 3 * n))
    for i in range(n):
        order = np.argsort(-value[:, i])[:max(1, refine)]
        k = order[0]
        state[i] = np.concatenate([q[k], qd[k, i], qdd[k, i]])

        def neg(x, i=i):                # -|tau_i| and its forward-difference gradient
            pts = np.vstack([x, x + 1e-6 * np.eye(n)])
            v = worst_states(channel_values(robot, pts, columns), W, region.qd_max,
                             region.qdd_max)[0][:, i]
            return -v[0], -(v[1:] - v[0]) / 1e-6
        for k in order[:refine]:
            res = minimize(neg, q[k], jac=True, method="L-BFGS-B",
                           bounds=list(zip(region.q_min, np.maximum(region.q_max - 1e-6,
                                                                    region.q_min))),
                           options={"maxiter": 10})
            x = np.clip(res.x, region.q_min, region.q_max)
            v, vqd, vqdd = worst_states(channel_values(robot, x[None, :], columns), W,
                                        region.qd_max, region.qdd_max)
            if v[0, i] > best[i]:
                best[i] = v[0, i]
                state[i] = np.concatenate([x, vqd[0, i], vqdd[0, i]])
    return np.maximum(best, torque_floor), state


#: Most joints whose scale s_i is polished by local maximisation in :func:`region_samples`
#: (every shipped arm); beyond them s_i is the largest sampled |tau_i| (a lower bound of the
#: true maximum all the same, and the budget EPS s_i only the safer): the maximisation's
#: forward-difference gradients cost n + 1 regressor evaluations a step, each over the
#: 2^(n - 1) velocity vertices, a fifth of a 12-joint main job.
REFINE_JOINTS = 7


def region_samples(robot, base, region, samples=1000, seed=0):
    """The sampled positions of a region, their channel values, and the scale found there.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        The base parameters whose columns and values are read (b of them).
    region : Region
    samples : int, optional
        Uniform position samples (plus the extremes of :func:`sample_positions`).
    seed : int, optional

    Returns
    -------
    tuple
        ``(positions (B, n) [rad or m], channel values`` (:class:`ChannelValues`, :func:`channel_values`),
        ``scale (n,) [N m or N], scale_state (n, 3 n))``: :func:`region_scale` without a
        floor, its best sample polished for arms of at most :data:`REFINE_JOINTS` joints;
        what :func:`gd_analyze.certify.certify.certify` computes before its branch and
        bound, for the same samples and seed.
    """
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = sample_positions(region, samples, seed)
    V = channel_values(robot, q, cols)
    scale, scale_state = region_scale(robot, region, cols, np.asarray(base.beta, float),
                                      refine=int(robot.n <= REFINE_JOINTS), values=(q, V))
    return q, V, scale, scale_state


def sampled_error(base, region, dropped, values):
    """The largest error of a pruned model found over the region, relative to s_i there.

    Sampling only: no bound is proved (that is
    :func:`gd_analyze.certify.certify.certify`, which samples the same positions).

    Parameters
    ----------
    base : BaseParameters
        The arm's b base parameters.
    region : Region
    dropped : ndarray of bool, shape (b, 3)
        The pairs (base parameter, part: inertial, velocity, gravity) the model leaves out
        (:class:`gd_analyze.symbolic.recursive_model.RecursiveModel`).
    values : tuple
        :func:`region_samples` (or the same from a certification with torque floor 0).

    Returns
    -------
    error : ndarray, shape (n,)
        max over the sampled positions, the velocity vertices and |qdd| <= qdd_max of
        |tau_i - tau_s,i| (the dropped pairs' torque, tau = Y_b beta), divided by s_i, the
        largest |tau_i| found over the region (a joint with s_i = 0 gives 0) [1]. A largest
        value found: a lower bound of the true maximum, not a proved bound.
    state : ndarray, shape (n, 3 n)
        Per joint i, the state (q, qd, qdd) where that error was found.
    """
    q, V, scale, _ = values
    weights = np.asarray(base.beta, float)[None, :] * np.asarray(dropped, float).T   # (3, b)
    err, qd, qdd = worst_states(V, weights, region.qd_max, region.qdd_max)
    k = err.argmax(axis=0)                                            # (n,)
    joints = np.arange(q.shape[1])
    state = np.hstack([q[k], qd[k, joints], qdd[k, joints]])
    return err[k, joints] / np.where(scale > 0, scale, np.inf), state
