"""Where a simplified model's bound holds: over the joint-limit region (proved), or on the
trajectories it was built on only.

A :class:`Guarantee` travels with every simplified model: in ``simplified_model.json`` (key
``guarantee``), in the headers of the emitted code, in the CLI summary and in the reports. Its
:meth:`Guarantee.statement` is the one sentence all of them print, generated from the model's
own numbers.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..certify.region import REFINE_JOINTS, Region, beyond_limits
from ..dynamics.dalembert import gd_terms
from ..errors import InputError
from ..ranking.ranking import ROUND_OFF_CLAUSE

if TYPE_CHECKING:                       # for the type hints only
    from ..model.robot import Robot

__all__ = ["Guarantee", "KINDS", "ROUND_OFF_EPS", "ROUND_OFF_CLAUSE", "within_bound",
           "encode_tree", "decode_tree", "TREE_CODE"]

#: The two scopes of a bound.
KINDS = ("region", "trajectory")
#: Floating-point round-off allowed on top of a bound, in machine epsilons of the arm's largest
#: scale (the verification's floor): the pruned and the exact program round differently, and a
#: small joint inherits the rounding of the large ones.
ROUND_OFF_EPS = 64
#: Set points per block where :meth:`Guarantee.with_scale_states` computes the torques.
STATE_BLOCK = 8192


def within_bound(error: ArrayLike, bound: ArrayLike, scale: ArrayLike) -> np.ndarray:
    """Whether errors are within their bounds up to floating-point round-off: the one test by
    which every check of a guaranteed bound judges (:data:`ROUND_OFF_CLAUSE`).

    Parameters
    ----------
    error, bound : array_like, shape (n,)
        Peak |tau_s - tau| and its bound per joint [N m or N].
    scale : array_like, shape (n,)
        The joints' scales s_i [N m or N]; the allowance is :data:`ROUND_OFF_EPS` machine
        epsilons of the largest.

    Returns
    -------
    ndarray of bool, shape (n,)
        ``error <= bound + 64 eps max_i s_i``; NaN never passes.

    Examples
    --------
    >>> within_bound([0.002400359948032, 1.1e-16], [0.002400359948026, 0.0], [0.24, 50.5])
    array([ True,  True])
    >>> within_bound([0.0025], [0.0024], [50.5])
    array([False])
    """
    s = np.abs(np.asarray(scale, float))
    allowance = ROUND_OFF_EPS * np.finfo(float).eps * (float(s.max()) if s.size else 0.0)
    return np.asarray(error, float) <= np.asarray(bound, float) + allowance


#: The characters of a tree's code (:func:`encode_tree`): a final box, then joints 1 to 36.
TREE_CODE = ".0123456789abcdefghijklmnopqrstuvwxyz"


def encode_tree(split_joint: ArrayLike) -> str:
    """A bisection tree as the text ``simplified_model.json`` keeps (key ``tilings``).

    Parameters
    ----------
    split_joint : array_like of int, shape (N,)
        Per box, level by level, the joint (from 0) it is halved along, or -1 (a final box).

    Returns
    -------
    str
        One character a box: ``.`` for a final box, else :data:`TREE_CODE` [joint + 1]
        (``0`` for joint 1); "" when a joint is beyond 36 or below -1 (not encoded).

    Examples
    --------
    >>> encode_tree([1, -1, 0, -1, -1])
    '1.0..'
    >>> decode_tree('1.0..').tolist()
    [1, -1, 0, -1, -1]
    """
    joints = np.asarray(split_joint, np.int64).reshape(-1)
    if joints.size == 0 or np.any(joints < -1) or np.any(joints >= len(TREE_CODE) - 1):
        return ""
    return "".join(np.array(list(TREE_CODE))[joints + 1])


def decode_tree(code: str) -> np.ndarray:
    """The ``split_joint`` array of :func:`encode_tree`'s text.

    Parameters
    ----------
    code : str
        Characters of :data:`TREE_CODE` (the schema's pattern).

    Returns
    -------
    ndarray of int, shape (len(code),)
        -1 for ``.``, else the joint (from 0); -2 for any other character (never a tree).
    """
    table = np.full(128, -2, np.int64)
    table[[ord(c) for c in TREE_CODE]] = np.arange(-1, len(TREE_CODE) - 1)
    raw = np.frombuffer(str(code).encode("ascii", "replace"), np.uint8)
    return table[np.minimum(raw, 127)]


def _floats(values):
    return None if values is None else [None if v is None or not np.isfinite(v) else float(v)
                                        for v in np.asarray(values, float).reshape(-1)]


@dataclass(frozen=True, eq=False)
class Guarantee:
    """The scope of a simplified model's bound |tau_s - tau| <= bound_i <= EPS s_i.

    Attributes
    ----------
    kind : {"region", "trajectory"}
        ``"region"``: proved at every state of R = {q_min <= q <= q_max, |qd| <= qd_max,
        |qdd| <= qdd_max}; ``"trajectory"``: on the trajectories the model was built on only.
    tolerance : float
        EPS [1].
    bound : ndarray, shape (n,)
        The bound per joint [N m or N].
    scale : ndarray, shape (n,)
        s_i [N m or N]: over R, max(largest |tau_i| found, torque floor), the largest found a
        lower bound of R's largest (how it was found: ``scale_positions``,
        ``scale_polished``); on trajectories, max(peak |tau_i|, torque floor).
    q_min, q_max, qd_max, qdd_max : ndarray, shape (n,), optional
        The region (region kind) [rad, m; rad/s, m/s; rad/s^2, m/s^2]; a continuous joint
        is given as [-pi, pi].
    scale_state : ndarray, shape (n, 3 n), optional
        Per joint, the state (q, qd, qdd) where |tau_i| = scale_i was found (over R, or on
        the trajectories: :meth:`with_scale_states`), where a reader computes s_i again.
    sampled_error : ndarray, shape (n,), optional
        Region kind: the worst |tau_s - tau| found by sampling R [N m or N].
    region_sampled_error : ndarray, shape (n,), optional
        Trajectory kind: the worst error found by sampling the robot's R, relative to s_i
        over R [1]; None when the robot gives no limits.
    method : str
        How the bound and the scale were obtained.
    trajectory_sha256 : str
        The trajectory file (trajectory kind; "" for several).
    trajectories_sha256 : tuple of str
        The trajectory files of a sweep's merged model.
    region_missing : str
        Why there is no region guarantee (trajectory kind), e.g. "joint 2 has no velocity
        limit"; "" if the region was not asked for.
    region : Region, optional
        The region itself (:class:`gd_analyze.certify.region.Region`): the region kind's
        R, or the region a trajectory kind's error was sampled over; with which acceleration
        limits are assumed and which revolute joints span a full turn.
    tilings : tuple of ndarray of int, shape (N,) each
        Region kind: bisection trees of the position box (``split_joint`` of
        :func:`gd_analyze.certify.certify.tiling`: per box, level by level, the joint
        it is halved along at its middle, or -1 for a final box) on whose final boxes the
        bound is derived again without search
        (:func:`gd_analyze.certify.certify.tree_bound`); () when none is kept. Not
        trusted: a reader checks that each tiles the region and re-evaluates it.
    decomposed : tuple of (ndarray of int, ndarray of int)
        Region kind: pairs of such trees on which the decomposed bound
        (:func:`gd_analyze.certify.certify.decomposed_bound`) is derived again without
        search (:func:`gd_analyze.certify.certify.decomposed_tree_bound`): the first bounds
        the dropped pairs of the first links (its branch and bound's tree), the second the
        rest (the certification's tree); () when none is kept. Not trusted, as ``tilings``.
    bound_method : tuple of str, length n, or ()
        Region kind: per joint, how its bound was obtained, a name of
        :data:`gd_analyze.certify.certify.BOUND_METHODS`
        (:func:`gd_analyze.certify.certify.bound_methods`); () where not stored (a file
        written before it was). Not trusted: a reader derives each joint's way again.
    joint_sum_arithmetic : str
        Region kind: the enclosures the joint sums were added on,
        :func:`gd_analyze.certify.regressor_bounds.joint_sum_arithmetic` (``"both"``: balls
        and interval boxes intersected; ``"ball"``); "" where not stored.
    scale_positions : int
        Region kind: the sampled positions of R at which s_i was searched (at each, the worst
        velocity vertex and acceleration); 0 where not stored (a file written before it was).
    scale_polished : bool or None
        Region kind: whether the best samples were then polished by local maximisation
        over q (:data:`gd_analyze.certify.region.REFINE_JOINTS`); None where not stored.
    read_back : bool
        Read from a model file (:meth:`from_dict`): a trajectory kind's
        ``region_sampled_error`` is the file's figure, not measured again (that is the main
        job's sampling of the region), and :meth:`statement` says so.

    Notes
    -----
    The bound follows from the triangle inequality over the dropped (base parameter, part)
    pairs of tau = Y_b beta (Khalil & Kleinfinger 1987; Gautier 1990), each pair's
    |contribution| bounded from above; Armstrong, Khatib & Burdick (1986) judged each term's
    significance over the workspace in the same way.
    """

    kind: str
    tolerance: float
    bound: np.ndarray
    scale: np.ndarray
    q_min: np.ndarray | None = None
    q_max: np.ndarray | None = None
    qd_max: np.ndarray | None = None
    qdd_max: np.ndarray | None = None
    scale_state: np.ndarray | None = None
    sampled_error: np.ndarray | None = None
    region_sampled_error: np.ndarray | None = None
    method: str = ""
    trajectory_sha256: str = ""
    trajectories_sha256: tuple = ()
    region_missing: str = ""
    region: Region | None = None
    tilings: tuple = ()
    decomposed: tuple = ()
    bound_method: tuple = ()
    joint_sum_arithmetic: str = ""
    scale_positions: int = 0
    scale_polished: bool | None = None
    read_back: bool = False

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {self.kind!r}")

    @property
    def proved(self) -> bool:
        """bool: the bound holds at every state of the region (kind ``"region"``)."""
        return self.kind == "region"

    def sampled_percent(self) -> float | None:
        """The largest sampled error over the region relative to s_i [%], or None.

        Returns
        -------
        float or None
            Region kind: max_i sampled_error_i / scale_i; trajectory kind: max_i of
            ``region_sampled_error``; None when not measured.
        """
        scale = np.asarray(self.scale, float)
        if self.kind == "region" and self.sampled_error is not None:
            rel = np.asarray(self.sampled_error, float) / np.where(scale > 0, scale, np.inf)
            return float(100.0 * rel.max(initial=0.0))
        rel = np.asarray(np.nan if self.kind == "region" or self.region_sampled_error is None
                         else self.region_sampled_error, float)
        return float(100.0 * np.nanmax(rel)) if np.isfinite(rel).any() else None

    def scale_source(self) -> str:
        """How a region kind's s_i was found, in one clause, as the outputs print it.

        Returns
        -------
        str
            From :attr:`scale_positions` and :attr:`scale_polished`: the largest |tau_i| found
            at the sampled positions, polished by local maximisation or not, always "a lower
            bound of the region's largest" (a search, not a proof; so the budget EPS s_i is
            at most EPS times the region's true largest, an absolute bound all the same);
            without them (a file written before they were stored) the clause without the
            search's details; "" for the trajectory kind.

        Examples
        --------
        >>> g = Guarantee("region", 0.01, np.zeros(1), np.ones(1), scale_positions=1014,
        ...               scale_polished=False)
        >>> g.scale_source()
        "the largest |tau_i| at 1,014 sampled positions of the region, not polished by local maximisation (done up to 7 joints), a lower bound of the region's largest"
        """
        if self.kind != "region":
            return ""
        lower = "a lower bound of the region's largest"
        if not self.scale_positions or self.scale_polished is None:
            return f"the largest |tau_i| found over the region, {lower}"
        where = f"{self.scale_positions:,} sampled positions of the region"
        return (f"the largest |tau_i| found at {where} and polished by local maximisation, "
                f"{lower}" if self.scale_polished else
                f"the largest |tau_i| at {where}, not polished by local maximisation (done up "
                f"to {REFINE_JOINTS} joints), {lower}")

    def statement(self) -> str:
        """The scope of the bound in one sentence, as every output prints it.

        Returns
        -------
        str
            ``"within EPS x s_i at every state of the region (proved)"`` or ``"on this
            trajectory only; sampled over the region: X %"`` with the model's numbers, the
            figure said to be the model file's where it was read from one (:attr:`read_back`).

        Examples
        --------
        >>> g = Guarantee("trajectory", 0.01, np.zeros(1), np.ones(1),
        ...               region_sampled_error=np.array([0.0513]))
        >>> g.statement()
        'within 1 % of s_i on this trajectory only; sampled over the region: 5.13 % of s_i'
        """
        eps = f"{100.0 * self.tolerance:.4g} %"
        if self.kind == "region":
            return (f"within {eps} of s_i at every state of the region (proved; up to "
                    f"round-off, {ROUND_OFF_EPS} eps of the largest s_i)")
        where = ("on this trajectory only" if not self.trajectories_sha256 else
                 f"on the {len(self.trajectories_sha256)} swept trajectories only")
        pct, why = self.sampled_percent(), self.region_missing and f" ({self.region_missing})"
        said = " (as the model file states, not measured again)" if self.read_back else ""
        tail = f"not checked over a region{why}" if pct is None else \
            f"sampled over the region: {pct:.3g} % of s_i{said}"
        return f"within {eps} of s_i {where}; {tail}"

    def covers(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, trajectory_sha256: str = "",
               continuous: ArrayLike | None = None, prismatic: ArrayLike | None = None,
               round_off: Sequence[ArrayLike] = (0.0, 0.0, 0.0)) -> tuple[bool, str]:
        """Whether the bound holds along a trajectory, and why.

        Parameters
        ----------
        q, qd, qdd : array_like, shape (N, n)
            The trajectory's set points [rad, m; rad/s, m/s; rad/s^2, m/s^2].
        trajectory_sha256 : str, optional
            SHA-256 of the trajectory file (what a trajectory-kind bound is tied to).
        continuous : array_like of bool, shape (n,), optional
            Joints without position limits, whose region is [-pi, pi]: their q is taken
            modulo 2 pi (the torque is periodic in it).
        prismatic : array_like of bool, shape (n,), optional
            The prismatic joints, for the units of the reason (default: all revolute).
        round_off : sequence of 3 array_like, each broadcastable to (N, n), optional
            Bounds on the round-off of q, qd and qdd where they were computed, not read
            (:func:`gd_analyze.jobs.control.motion_round_off`) [rad, rad/s, rad/s^2; m, m/s,
            m/s^2]; default 0: data as given.

        Returns
        -------
        covered : bool
            Region kind: every state lies in R up to its round-off
            (:func:`gd_analyze.certify.region.beyond_limits`: ``round_off`` and 4 machine
            epsilons of the limit, a planner's that ends exactly on it); trajectory kind: the
            file is one the model was built on (by SHA-256).
        reason : str
            One clause saying why, naming the first joint and quantity outside R, its extreme
            and how far beyond its limit, in the joint's unit.

        Examples
        --------
        >>> g = Guarantee("region", 0.01, np.zeros(1), np.ones(1), q_min=np.array([-1.0]),
        ...               q_max=np.array([1.0]), qd_max=np.array([2.0]),
        ...               qdd_max=np.array([5.0]), scale_state=np.zeros((1, 3)))
        >>> g.covers([[0.5]], [[2.5]], [[0.0]])[1][28:]
        "joint 1's |qd| reaches 2.5 rad/s, 0.5 rad/s above its limit 2 rad/s"
        """
        if self.kind == "trajectory":
            own = tuple(self.trajectories_sha256) or (self.trajectory_sha256,)
            if trajectory_sha256 and trajectory_sha256 in own:
                return True, "it is a trajectory the model was built on (same SHA-256)"
            return False, ("it is not the trajectory the model was built on (SHA-256 differs)"
                           if any(own) else "the model file stores no SHA-256 of its own "
                           "trajectory to compare") + ": a trajectory-kind bound holds there only"
        q, qd, qdd = (np.atleast_2d(np.asarray(v, float)) for v in (q, qd, qdd))
        wrap = np.zeros_like(q[0], bool) | (continuous is not None and np.asarray(continuous, bool))
        if self.region is not None and self.q_min is not None:    # a turn of its own box
            span = np.asarray(self.q_max, float) - np.asarray(self.q_min, float)
            wrap |= np.asarray(self.region.full_turn, bool) & (span >= 2 * np.pi * (1 - 1e-12))
        q = np.where(wrap, np.mod(q + np.pi, 2 * np.pi) - np.pi, q)
        checks: tuple[tuple[str, np.ndarray, Any, Any], ...] = (
            ("q", q, self.q_min, self.q_max), ("|qd|", np.abs(qd), None, self.qd_max),
            ("|qdd|", np.abs(qdd), None, self.qdd_max))
        for (name, x, lo, hi), err in zip(checks, round_off):
            below, above = beyond_limits(x, None if lo is None else np.asarray(lo, float),
                                         np.asarray(hi, float), np.asarray(err, float))
            for bad, which, limit in ((below, "below", lo), (above, "above", hi)):
                if bad.any():
                    j = int(np.nonzero(bad)[1][0])
                    # the true extreme of that joint, not its first set point outside
                    top = float(x[:, j].min() if which == "below" else x[:, j].max())
                    u = ("m" if prismatic is not None and np.asarray(prismatic)[j] else "rad") \
                        + {"q": "", "|qd|": "/s", "|qdd|": "/s^2"}[name]
                    return False, (f"outside the model's region: joint {j + 1}'s {name} reaches "
                                   f"{top:.6g} {u}, {abs(top - float(limit[j])):.3g} {u} {which} "
                                   f"its limit {float(limit[j]):.6g} {u}")
        return True, "every set point lies in the model's region (positions, velocities and accelerations within its limits)"

    def with_scale_states(self, robot: Robot, trajectories: Sequence[Any]) -> Guarantee:
        """This trajectory-kind guarantee with its scale states: where s_i was found.

        Parameters
        ----------
        robot : Robot
            The model's robot.
        trajectories : sequence of Trajectory
            The trajectories the model was built on, each q, qd, qdd of shape (N_k, n)
            [rad, rad/s, rad/s^2; m, m/s, m/s^2].

        Returns
        -------
        Guarantee
            ``scale_state`` (n, 3 n): per joint i, the set point (q, qd, qdd) of the
            trajectories with the largest |tau_i| (:func:`gd_analyze.dynamics.dalembert.gd_terms`
            of the robot, as s_i = max(peak |tau_i|, torque floor) is measured), where a reader
            computes |tau_i| again (:func:`gd_analyze.store.model_trust.check_region`); a
            region-kind guarantee is returned as it is.
        """
        if self.kind != "trajectory":
            return self
        n = robot.n
        best, states = np.full(n, -np.inf), np.zeros((n, 3 * n))
        for t in trajectories:
            for a in range(0, t.q.shape[0], STATE_BLOCK):
                x = np.hstack([v[a:a + STATE_BLOCK] for v in (t.q, t.qd, t.qdd)])
                tau = np.abs(gd_terms(robot, x[:, :n], x[:, n:2 * n]).tau(x[:, 2 * n:]))
                k = np.argmax(tau, axis=0)
                new = tau[k, np.arange(n)] > best
                states[new], best[new] = x[k[new]], tau[k[new], np.arange(n)[new]]
        return dataclasses.replace(self, scale_state=states)

    def to_dict(self) -> dict:
        """The ``guarantee`` key of ``simplified_model.json`` (SI units).

        Returns
        -------
        dict
        """
        out = {"kind": self.kind, "statement": self.statement(),
               "bound": _floats(self.bound), "scale": _floats(self.scale),
               "method": self.method}
        states = None if self.scale_state is None else [_floats(r) for r in self.scale_state]
        if self.kind == "region":
            out.update(q_min=_floats(self.q_min), q_max=_floats(self.q_max),
                       qd_max=_floats(self.qd_max), qdd_max=_floats(self.qdd_max),
                       scale_state=states, sampled_error=_floats(self.sampled_error))
        else:
            out.update(trajectory_sha256=self.trajectory_sha256, scale_state=states)
            if self.trajectories_sha256:
                out["trajectories_sha256"] = list(self.trajectories_sha256)
            out["region_sampled_error"] = _floats(self.region_sampled_error)
            if self.region_missing:
                out["region_missing"] = self.region_missing
        if self.region is not None:
            out["region"] = self.region.to_dict()
        codes = [encode_tree(t) for t in self.tilings] if self.kind == "region" else []
        if codes and all(codes):
            out["tilings"] = codes
        pairs = [[encode_tree(t) for t in pair] for pair in self.decomposed] \
            if self.kind == "region" else []
        if pairs and all(all(pair) for pair in pairs):
            out["decomposed_tilings"] = pairs
        if self.kind == "region" and self.bound_method:
            out.update(bound_method=list(self.bound_method),
                       joint_sum_arithmetic=self.joint_sum_arithmetic)
        if self.kind == "region" and self.scale_positions and self.scale_polished is not None:
            out.update(scale_positions=int(self.scale_positions),
                       scale_polished=bool(self.scale_polished))
        return out

    @classmethod
    def from_dict(cls, spec: dict, n: int, tolerance: float, path: str = "<model>"
                  ) -> Guarantee:
        """Read the ``guarantee`` key of a model file (already checked by the schema).

        Parameters
        ----------
        spec : dict
            As :meth:`to_dict` writes it.
        n : int
            The robot's number of joints.
        tolerance : float
            The model's EPS.
        path : str, optional
            The file, for messages.

        Returns
        -------
        Guarantee

        Raises
        ------
        InputError
            If a list has not n entries (``scale_state``: n lists of 3 n), a key of its kind
            is missing (``scale_state`` for either kind), or a stored bound exceeds EPS s_i. One line naming the key.
        """
        def arr(key, width=None, required=True):
            said = spec.get(key)
            if said is None and not required:
                return None
            try:                                # null read as NaN; ragged rows refused
                v = np.array(said, float) if isinstance(said, list) and all(
                    x is None or isinstance(x, (int, float, list)) for x in said) else None
            except (TypeError, ValueError):
                v = None
            if v is None or v.shape != ((n,) if width is None else (n, width)):
                raise InputError("missing for a guarantee of this kind" if said is None else
                                 f"expected {n} numbers" if width is None else
                                 f"expected {n} lists of {width} numbers", path,
                                 column=f"guarantee.{key}")
            return v
        kind = spec["kind"]
        region = None
        if spec.get("region") is not None:
            try:
                region = Region.from_dict(spec["region"], n)
            except ValueError as exc:
                key, _, why = str(exc).partition(": ")
                raise InputError(why, path, column=f"guarantee.{key}") from None
        bound, scale = arr("bound"), arr("scale")
        if np.isfinite(tolerance) and not np.all(bound <= tolerance * scale * (1 + 1e-12)):
            raise InputError("a bound exceeds tolerance x scale", path, column="guarantee.bound")
        common = dict(kind=kind, tolerance=float(tolerance), bound=bound, scale=scale,
                      method=spec.get("method", ""), region=region,
                      scale_state=arr("scale_state", 3 * n))
        if kind == "region":
            limits = {k: arr(k) for k in ("q_min", "q_max", "qd_max", "qdd_max")}
            if region is not None and not all(np.array_equal(getattr(region, k), v)
                                              for k, v in limits.items()):
                raise InputError("does not match the guarantee's q_min, q_max, qd_max and "
                                 "qdd_max", path, column="guarantee.region")
            method = tuple(spec.get("bound_method") or ())
            if method and len(method) != n:
                raise InputError(f"expected {n} names", path, column="guarantee.bound_method")
            return cls(**common, **limits, bound_method=method,
                       joint_sum_arithmetic=str(spec.get("joint_sum_arithmetic", "")),
                       scale_positions=int(spec.get("scale_positions", 0)),
                       scale_polished=spec.get("scale_polished"),
                       sampled_error=arr("sampled_error", required=False),
                       tilings=tuple(decode_tree(c) for c in spec.get("tilings") or ()),
                       decomposed=tuple((decode_tree(a), decode_tree(b)) for a, b in
                                        spec.get("decomposed_tilings") or ()))
        return cls(**common, trajectory_sha256=spec.get("trajectory_sha256", ""),
                   trajectories_sha256=tuple(spec.get("trajectories_sha256") or ()),
                   region_sampled_error=arr("region_sampled_error", required=False),
                   region_missing=spec.get("region_missing", ""), read_back=True)
