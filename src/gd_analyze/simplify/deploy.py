"""The pruned recursive model the main job builds, over the region or on the
trajectory.

robot -> base parameters -> pruned recursive model within the budget over the joint-limit
region or on the trajectory -> SimplifiedModel of the recursive form, with the exact recursive
model's count beside it (:func:`build_recursive`). Which model is deployed beside the explicit
ones is :func:`gd_analyze.simplify.form_choice.deploy`'s. Nothing here prints or writes files; what is kept
between runs goes through a :class:`~gd_analyze.simplify.region_memo.Derivations`.
"""

from __future__ import annotations

import dataclasses
import json
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..cache import CacheWarning
from ..certify.certify import (
    JOINT_DIMS,
    METHOD,
    bound_methods,
    decomposed_limit,
    decomposed_pairs,
    dropped_search,
    joint_sums,
    leaf_bound,
    method_bounds,
    region_trees,
    split_joints,
)
from ..certify.certify import release as release_sums
from ..certify.positive_definite import inertia_restored
from ..certify.region import (
    REFINE_JOINTS,
    joint_region,
    missing_limits,
    sampled_error,
    worst_states,
)
from ..certify.regressor_bounds import joint_sum_arithmetic
from ..certify.screen import proved_screen, screen_region
from ..dynamics.base_parameters import base_parameters
from ..errors import one_line
from ..model.limits import DEFAULT_QDD_PER_QD, acceleration_limits
from ..ranking.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE, element_labels
from ..symbolic.drive_regressor import with_drives
from ..symbolic.pruning import part_values, prune_bounds, settle_restored, zero_parts
from ..symbolic.recursive import parts_count, recursive_program
from ..symbolic.recursive_model import RecursiveModel, recursive_model
from .budget import DEFAULT_TOLERANCE, Selection
from .guarantee import Guarantee
from .region_memo import (
    REGION_SAMPLES,
    UNKEPT,
    Derivations,
    certified,
    region_key,
    region_magnitudes,
    region_values,
)
from .region_memo import release as release_derivations
from .simplified import SimplifiedModel, total_operations

if TYPE_CHECKING:
    from ..certify.region import Region, RegionLimits
    from ..certify.screen import RegionScreen
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot
    from ..ranking.ranking import Ranking

__all__ = ["build_recursive", "recursive_simplified", "recursive_selection", "region_model",
           "region_search", "RegionSearch", "RegionSearches", "region_searches",
           "trajectory_guarantee", "certified", "robot_region",
           "guarantee_region", "REGION_SAMPLES", "restored_rebuild", "rebuilt", "SCOUT_BOXES",
           "SCOUT_RATIO", "DECOMPOSE", "DECOMPOSED_MAX_JOINTS",
           "DECOMPOSED_SCOUT_BOXES", "screened_exact", "RESTORED_MIN_SAVING", "release"]

#: A tree of boxes is kept with a region model (:attr:`Guarantee.tilings`) for the joints
#: where its bound is within this share of s_i of the model's (a thousandth of what the
#: reader allows, :data:`gd_analyze.store.model_trust.BOUND_RTOL`).
TILING_RTOL = 1e-12
#: Least share of the exact recursive model's operations (quick counts) that the pairs
#: searched under the proved bounds must save once the inertial parts the proof of D_s needs
#: are restored (:func:`gd_analyze.certify.positive_definite.inertia_restored`, the
#: restored parameters' other parts kept too where cheaper), for the pruned model to be built.
#: That count follows the built model's closely (the UR5's 1.75 %, 336 of 342, where the
#: model built saves 1.8 %, 327 of 333; a random 15-joint URDF arm's 1.28 % where it saves
#: 0.85 %), hence a bar below :data:`gd_analyze.certify.screen.MIN_SAVING`, which is for the
#: counts before the restore.
RESTORED_MIN_SAVING = 0.015
#: Boxes of the first, quick branch and bound on a dropped set's joint sum while the pairs
#: are chosen (:class:`_JointBound`), and the share of the budget above which its bound
#: rejects the set without the full one.
SCOUT_BOXES, SCOUT_RATIO = 2048, 1.5
#: Boxes of the scout on the first links' pairs of a set bounded by the decomposition
#: (:class:`_JointBound`), which rejects the set above :data:`SCOUT_RATIO` times ``enough``.
DECOMPOSED_SCOUT_BOXES = 4096
#: Whether the region search also searches with the decomposed bound
#: (:func:`gd_analyze.certify.certify.decomposed_bound`, :func:`_region_pruning`); False:
#: the search before it alone.
DECOMPOSE = True
#: The most joints an arm may have for the region search to search with the decomposed bound
#: as well. It pays on the Panda (7 joints: 545 -> 535 operations at EPS 0.01); on random
#: chains of 12 and 15 joints one search with it took longer than the whole main job without
#: it (a 12-joint chain's job 23 s -> 43 s of CPU, a 15-joint chain's 38 s -> 81 s and its
#: peak 1.5 -> 2.2 GiB, analysis/main_job_scaling.py), for models the screens then replaced
#: by the exact one.
DECOMPOSED_MAX_JOINTS = 8


def robot_region(robot: Robot, limits: RegionLimits | None = None
                 ) -> tuple[Region | None, str]:
    """The region of a model's guarantee: the robot's limits, or the user's within them; or
    None and why not.

    Parameters
    ----------
    robot : Robot
    limits : RegionLimits, optional
        The user's limits (:class:`gd_analyze.certify.region.RegionLimits`), each in
        place of the robot's and clipped to them (the region's ``notes`` say which).

    Returns
    -------
    region : Region or None
        The position and velocity limits, the acceleration limits of
        :func:`gd_analyze.model.limits.acceleration_limits` (the robot's, or the planner's
        default where it has none, flagged as assumed) unless the user gives them; None when a
        limit is missing.
    missing : str
        The missing limit (:func:`gd_analyze.certify.region.missing_limits`), or "".

    Raises
    ------
    ValueError
        If the user's limits do not fit the robot (one or n values; a position range wholly
        outside the robot's), naming the option.
    """
    why = missing_limits(robot, limits)
    if why:
        return None, why
    with_qd = robot if limits is None or limits.qd_max is None else dataclasses.replace(
        robot, qd_max=joint_region(robot, np.ones(robot.n), limits).qd_max)
    try:
        qdd_max, _ = acceleration_limits(with_qd)
    except ValueError as exc:
        return None, str(exc)
    assumed = ~np.isfinite(np.asarray(robot.qdd_max, float))
    return joint_region(robot, qdd_max, limits, qdd_assumed=assumed,
                        qdd_rule=f"{DEFAULT_QDD_PER_QD:g} s^-1 x qd max"), ""


def guarantee_region(robot: Robot, guarantee: str = "auto", limits: RegionLimits | None = None
                     ) -> tuple[Region | None, str, bool]:
    """The region, and whether a budget model's bound is proved over it.

    Parameters
    ----------
    robot : Robot
    guarantee : {"auto", "region", "trajectory"}, optional
        The ``--guarantee`` choice: ``"trajectory"`` never proves over the region; ``"auto"``
        and ``"region"`` do where the robot (or the user) gives position and velocity limits
        for every joint, and fall back to the trajectory otherwise (the guarantee then names
        the missing limit).
    limits : RegionLimits, optional
        The user's region (:func:`robot_region`).

    Returns
    -------
    region : Region or None
        :func:`robot_region`'s (also under ``"trajectory"``: a trajectory model's error is
        sampled on it); None when a limit is missing.
    missing : str
        The missing limit, or "".
    proved : bool
        Prune on bounds proved over ``region`` (a guarantee of kind ``"region"``).
    """
    region, missing = robot_region(robot, limits)
    return region, missing, region is not None and guarantee != "trajectory"


def region_model(robot: Robot, base: BaseParameters, region: Region, tolerance: float,
                 torque_floor: float = 0.0, derive: Derivations = UNKEPT
                 ) -> tuple[RecursiveModel, Guarantee]:
    """The recursive model pruned on bounds proved over a joint-limit region.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters.
    region : Region
        R = {q_min <= q <= q_max, |qd| <= qd_max, |qdd| <= qdd_max}.
    tolerance : float
        EPS.
    torque_floor : float, optional
        [N m or N].
    derive : Derivations, optional
        Where the certification is kept between runs
        (:class:`~gd_analyze.simplify.region_memo.Derivations`; default nowhere).

    Returns
    -------
    model : RecursiveModel
        Dropped pairs whose proved bound together is at most EPS s_i per joint; ``scale`` is
        s_i over R, ``bound`` that bound [N m or N]
        (:func:`gd_analyze.certify.certify.region_bound`: the least of the largest over
        the certification's final boxes of the sum of the dropped pairs' bounds there or of
        their joint sum, and a branch and bound on their joint sum).
    guarantee : Guarantee
        Of kind ``"region"``: |tau_s - tau| <= bound_i <= EPS s_i at every state of R (up to
        round-off), with the sampled error, the scale and where it was found.

    Notes
    -----
    tau = Y_b beta is linear in the base parameters (Khalil & Kleinfinger 1987; Gautier
    1990), so the dropped pairs change tau_i by the sum of their contributions at the same
    state; bounds by :func:`gd_analyze.certify.certify.certify` and
    :func:`gd_analyze.certify.certify.region_bound`.
    """
    pb = certified(robot, base, region, torque_floor, derive)
    return _region_model(robot, base, region, tolerance, pb, _region_pruning(base, pb, robot,
                                                                            region, tolerance))


def _region_pruning(base, pb, robot, region, tolerance, chosen=None, worth=None):
    """:func:`~gd_analyze.symbolic.pruning.prune_bounds` on a region's certification
    (``chosen``: an earlier search's pairs, checked against the budget; ValueError if over),
    the trees of boxes its bound is derived again on and how each joint's bound was obtained
    (:meth:`_JointBound.tilings`).

    The pairs are searched twice where the arm has more than :data:`JOINT_DIMS` joints that
    coefficients depend on, and at most :data:`DECOMPOSED_MAX_JOINTS` joints: without the decomposition
    (:func:`~gd_analyze.certify.certify.decomposed_bound`) and with it; the search with it
    is kept only where its pairs cost fewer operations (quick counts, once the proof of D_s
    has restored what it needs: :func:`_restored_count`): the greedy search is
    not monotone, and a bound that admits a pair early can shut out cheaper ones later.
    ``worth(pruning)``, where given, says whether the search without the decomposition found
    a region model worth building; where it did not (the exact model is deployed), the
    search with it is not run (on random chains of 12 and 15 joints, whose region models
    save too little either way, it took 2.4 and 3.9 times the main job's time).
    ``chosen`` pairs are checked without it first, then with it."""

    joint = _JointBound(robot, base, region, pb, tolerance)

    def search(decompose):
        joint.decompose = decompose
        return prune_bounds(robot, base, pb.scale, pb.bound,
                            pb.leaves.sum(axis=1).max(axis=1), tolerance, pieces=pb.leaves,
                            chosen=chosen, zero=pb.zero, joint=joint)

    if not DECOMPOSE or robot.n > DECOMPOSED_MAX_JOINTS or split_joints(
            robot, base, np.ones(pb.zero.shape, bool)).sum() <= JOINT_DIMS:
        pr = search(False)              # no set has a decomposition
    elif chosen is not None:
        try:
            pr = search(False)
        except ValueError:              # found with the decomposition: checked with it
            pr = search(True)
    else:
        pr = search(False)
        if worth is not None and not worth(pr):
            return pr, *joint.tilings(pr.dropped, pr.bound)
        other = search(True)
        if _restored_count(robot, base, region, pb, other) < \
                _restored_count(robot, base, region, pb, pr):
            pr = other
        else:
            joint.decompose = False
    return pr, *joint.tilings(pr.dropped, pr.bound)


def _relative_bounds(pb):
    """Each pair's largest bound over the region relative to its joint's s_i, shape (b, 3)
    (inf where s_i is 0 and the bound is not)."""
    scale = np.asarray(pb.scale, float)
    safe = np.where(scale > 0, scale, 1.0)
    return np.where(scale > 0, pb.bound / safe, np.where(pb.bound > 0, np.inf, 0.0)).max(2)


def _restored_count(robot, base, region, pb, pr):
    """Multiplications + additions of a pruning's program, quick (no common subexpressions,
    one form: :func:`~gd_analyze.symbolic.recursive.parts_count`), once the proof that D_s is
    positive definite has restored the inertial parts it needs (the trials of
    :func:`gd_analyze.certify.positive_definite.inertia_restored`; a restored parameter's other
    parts kept too where that is cheaper, as :func:`_proved_exact` counts them): the searches
    without and with the decomposed bound are compared by what the model will cost, not by
    what they drop before that proof (on the PUMA 560 under a torque floor of 1 N m the one
    with it dropped more and, ZZ6 restored, cost 4 operations more)."""
    dropped = np.asarray(pr.dropped, bool)
    if not np.any(dropped[:, 0] & ~pb.zero[:, 0]):
        return parts_count(robot, part_values(base, dropped))
    kept = inertia_restored(robot, base, dropped, _relative_bounds(pb), region.q_min,
                            region.q_max)
    whole = kept.copy()
    whole[dropped[:, 0] & ~kept[:, 0]] = False
    return min(parts_count(robot, part_values(base, d)) for d in (kept, whole))


class _JointBound:
    """The bound of a dropped set's joint sum over the region, for
    :func:`~gd_analyze.symbolic.pruning.prune_bounds` (``joint``), from the region's
    certification ``pb`` (:func:`.region_memo.certified`) and the budget EPS s_i.

    ``joint(dropped, enough)`` -> ndarray (n,) [N m or N]: with ``enough`` None,
    :func:`gd_analyze.certify.certify.region_bound` (the pairs that fit the budget alone held
    in the joint sums on the certification's final boxes), which
    :func:`gd_analyze.store.model_trust.reproved_bound` derives again. With ``enough`` (only
    whether the set fits matters), a bound that decides it more cheaply where one does:
    :func:`~gd_analyze.certify.certify.leaf_bound` when it fits, or when the dropped set's
    largest error found at the certification's sampled states exceeds ``enough`` (no bound
    can then fit), or when a branch and bound of :data:`SCOUT_BOXES` boxes ends above
    :data:`SCOUT_RATIO` times ``enough``; where it does not, the full branch and bound
    (:func:`gd_analyze.certify.certify.region_trees`) goes on from that one's last level
    instead of evaluating its boxes again (the same bound and tree). A set on more than
    :data:`JOINT_DIMS` joints is bounded, where ``decompose`` is True, by the decomposition
    (:func:`gd_analyze.certify.certify.decomposed_bound`) after the same rejections, cheapest
    first: the final boxes' bound of the pairs outside its first links already above
    ``enough`` where the final boxes' bound of the whole set is (its branch and bound only
    adds), the error found at the sampled states, then the scout of
    :data:`DECOMPOSED_SCOUT_BOXES` boxes on the first links' pairs with the limit the full one
    has.
    Results, and the trees of boxes each bound was found on (:meth:`tilings`), are kept per
    dropped set (but its pairs proved zero) and ``decompose`` where the set has a
    decomposition (a set on at most :data:`JOINT_DIMS` joints has the same bound either
    way); the final boxes' bounds, the sampled errors and the scouts' rejections are kept per
    set as well, so that the searches without and with the decomposition, :meth:`quick` and
    the full call evaluate each once. ``quick`` is the cheap answer for the search.
    """

    def __init__(self, robot, base, region, pb, tolerance, decompose=True):
        self.robot, self.base, self.region, self.pb = robot, base, region, pb
        self.decompose = decompose
        self.budget = tolerance * np.asarray(pb.scale, float)
        alone = np.all(pb.bound <= self.budget[None, None, :], axis=2) & ~pb.zero
        self.sums = joint_sums(robot, base, region, pb.split_joint, pb.split_at, alone,
                               pb.zero)
        self.beta = np.asarray(base.beta, float)[None, :]
        self.memo = {}
        self.leaves, self.errors, self.rejected = {}, {}, {}

    def _leaf_bound(self, dropped):
        """:func:`~gd_analyze.certify.certify.leaf_bound` of a dropped set on the final boxes,
        kept per set (its very pairs: the same array each time it is asked, by either search
        and by :meth:`quick` and the full call alike)."""
        dropped = np.asarray(dropped, bool)
        key = dropped.tobytes()
        if key not in self.leaves:
            self.leaves[key] = leaf_bound(self.pb, self.sums, dropped)
            self.leaves[key].setflags(write=False)
        return self.leaves[key]

    def _leaf(self, dropped, enough):
        """The final boxes' bound (:func:`~gd_analyze.certify.certify.leaf_bound`), whether
        it is the answer, and the pairs of the decomposition with the final boxes' bound of
        the rest (or None): it is the answer where it fits, or where the set depends on more
        than :data:`JOINT_DIMS` joints and either has no decomposition
        (:func:`~gd_analyze.certify.certify.decomposed_pairs`) or its rest's bound alone
        exceeds ``enough`` on a joint where the final boxes' bound does (no bound found can
        then fit)."""
        first = self._leaf_bound(dropped)
        if np.all(first <= enough) or split_joints(
                self.robot, self.base, dropped, self.pb.zero).sum() <= JOINT_DIMS:
            return first, bool(np.all(first <= enough)), None
        if not self.decompose:
            return first, True, None
        head = decomposed_pairs(self.robot, self.base, dropped, self.pb.zero)
        if head is None:
            return first, True, None
        other = self._leaf_bound(dropped & ~self.pb.zero & ~head)
        return first, bool(np.any((first > enough) & (other > enough))), (head, other)

    def _key(self, dropped):
        """The memo's key of a dropped set: ``decompose`` and the pairs not proved zero
        (those give the same bound and trees whatever pairs proved zero are dropped with
        them: their final boxes' bounds are 0, and every sum and search leaves them out)."""
        live = np.asarray(dropped, bool) & ~self.pb.zero
        # a set on at most JOINT_DIMS joints has no decomposition: the same bound either way
        return self.decompose and split_joints(self.robot, self.base, live).sum() > \
            JOINT_DIMS, live.tobytes()

    def _found(self, dropped):
        """(n,): the dropped set's largest error found at the certification's sampled
        states (a lower bound of its largest over the region) [N m or N]; kept per set (its
        very pairs)."""
        key = np.asarray(dropped, bool).tobytes()
        if key not in self.errors:
            self.errors[key] = worst_states(self.pb.values, self.beta * dropped.T,
                                            self.region.qd_max, self.region.qdd_max
                                            )[0].max(axis=0)
            self.errors[key].setflags(write=False)
        return self.errors[key]

    def quick(self, dropped, enough):
        """The bound ``self(dropped, enough)`` returns when it is the final boxes' own, else
        None (:meth:`_leaf`)."""
        first, decided, _ = self._leaf(dropped, enough)
        return first if decided else None

    def __call__(self, dropped, enough=None):
        robot, base, region, pb = self.robot, self.base, self.region, self.pb
        key = self._key(dropped)
        if key in self.memo:
            return self.memo[key][0]
        resume = None
        if enough is not None:
            first, decided, parts = self._leaf(dropped, enough)
            if decided:
                return first
            found = self._found(dropped)
            if np.any(found > enough):
                return first
            seen = key + (np.asarray(dropped, bool).tobytes(),
                          np.asarray(enough, float).tobytes())
            if seen in self.rejected:   # its scout ran already (the other search's)
                return self.rejected[seen]
            kept = {}
            if parts is None:
                scout = dropped_search(robot, base, region, dropped, self.budget, SCOUT_BOXES,
                                       pb.zero, kept)[0]
            else:               # the decomposition's branch and bound, as region_trees runs it
                head, other = parts
                scout = np.minimum(first, np.nextafter(other + dropped_search(
                    robot, base, region, head, decomposed_limit(self.budget, other),
                    DECOMPOSED_SCOUT_BOXES, pb.zero, kept)[0], np.inf))
            if np.any(scout > SCOUT_RATIO * enough):
                self.rejected[seen] = np.minimum(first, scout)
                self.rejected[seen].setflags(write=False)
                return self.rejected[seen]
            resume = kept           # the full branch and bound goes on from the scout's
        self.memo[key] = region_trees(robot, base, region, pb, dropped, self.budget,
                                      self.sums, resume, self.decompose)
        return self.memo[key][0]

    def tilings(self, dropped, bound):
        """The trees whose final boxes give a dropped set's ``bound`` (n,) again, within
        :data:`TILING_RTOL` of s_i on every joint: the joint sum's branch and bound's, or the
        decomposition's pair of trees (its branch and bound's on the first links' pairs, the
        certification's for the rest), first (:func:`gd_analyze.certify.certify.region_trees`),
        the certification's where the first does not reach it or where a joint's bound is
        its final boxes' (so that a reader finds each joint's way again on the trees kept);
        () when nothing but pairs
        proved zero is dropped, or when they do not reach it. A pair is a tuple of two
        arrays, a tree an array. And per joint how ``bound`` was obtained
        (:func:`gd_analyze.certify.certify.bound_methods` within :data:`TILING_RTOL`)."""
        dropped = np.asarray(dropped, bool)
        if not (dropped & ~self.pb.zero).any():
            return (), bound_methods(bound, {}, self.pb.scale)
        key = self._key(dropped)
        if key not in self.memo:
            self(dropped)
        how = bound_methods(bound, method_bounds(self.pb, dropped, self.memo[key][1]),
                            self.pb.scale, TILING_RTOL)
        reach = np.asarray(bound, float) + TILING_RTOL * np.abs(np.asarray(self.pb.scale))
        chosen, covered = [], np.zeros(reach.shape, bool)
        boxes = {"pairs", "joint sum"} & set(how)     # the certification's tree gives them
        for tree, tree_bound in reversed(self.memo[key][1]):
            if np.any(~covered & (tree_bound <= reach)) or (
                    boxes and tree is self.memo[key][1][0][0]):
                chosen.append(tree)
                covered |= tree_bound <= reach
        return (tuple(chosen) if covered.all() else ()), how


def _region_model(robot, base, region, tolerance, pb, pruned, sampled=True):
    """:func:`region_model`'s model and guarantee from the certification and the pruning
    with its trees of boxes (:func:`_region_pruning`; ``sampled=False``: the model only, the
    guarantee None, its error not sampled)."""
    pr, trees, how = pruned
    tilings = tuple(t for t in trees if not isinstance(t, tuple))
    decomposed = tuple(t for t in trees if isinstance(t, tuple))

    single = pr.dropped & ~pr.whole[:, None]
    by_part = np.stack([np.einsum("bln,b->ln", pb.leaves[:, p], single[:, p]).max(axis=0)
                        for p in range(3)]
                       + [np.einsum("bpln,b->ln", pb.leaves, pr.whole).max(axis=0)])
    safe = np.where(pb.scale > 0, pb.scale, 1.0)
    rel = np.where(pb.scale > 0, pb.bound / safe, np.where(pb.bound > 0, np.inf, 0.0)).max(2)
    rec = RecursiveModel(names=tuple(base.names()), beta=np.array(base.beta, float),
                         dropped=np.array(pr.dropped, bool), scale=np.array(pb.scale, float),
                         bound=np.array(pr.bound, float), bound_by_part=by_part,
                         relative_peak=rel)
    if not sampled:
        return rec, None
    weights = np.asarray(base.beta, float)[None, :] * pr.dropped.T          # (3, b)
    err = worst_states(pb.values, weights, region.qd_max, region.qdd_max)[0].max(axis=0)
    guarantee = Guarantee(
        "region", float(tolerance), bound=rec.bound, scale=rec.scale, q_min=region.q_min,
        q_max=region.q_max, qd_max=region.qd_max, qdd_max=region.qdd_max,
        scale_state=pb.scale_state, sampled_error=err, region=region, tilings=tilings,
        decomposed=decomposed, bound_method=how,
        joint_sum_arithmetic=joint_sum_arithmetic(robot.n),
        scale_positions=pb.positions.shape[0], scale_polished=robot.n <= REFINE_JOINTS)
    return rec, dataclasses.replace(guarantee, method=f"{METHOD}; {pb.boxes} boxes; scale s_i: "
                                                      f"{guarantee.scale_source()}")


def trajectory_guarantee(robot: Robot, base: BaseParameters, rec: RecursiveModel,
                         tolerance: float, trajectory_sha256: str = "",
                         region: Region | None = None, region_missing: str = "") -> Guarantee:
    """The guarantee of a model pruned on a trajectory, its error sampled over the region.

    Parameters
    ----------
    robot : Robot
    base : BaseParameters
    rec : RecursiveModel
        The pruned model (its ``dropped`` pairs, ``bound`` and trajectory ``scale``).
    tolerance : float
        EPS.
    trajectory_sha256 : str, optional
    region : Region, optional
        The robot's region, on which the model's error is sampled (None: not sampled).
    region_missing : str, optional
        Why there is no region.

    Returns
    -------
    Guarantee
        Of kind ``"trajectory"``; ``region_sampled_error``: the largest error found over the
        region relative to s_i there (the largest |tau_i| found), or None
        (:func:`gd_analyze.certify.region.sampled_error` at the positions of
        :func:`.region_memo.region_values`: sampling only, no certification).
    """
    sampled = None
    if region is not None:
        sampled = sampled_error(base, region, rec.dropped, region_values(robot, base, region))[0]
    return Guarantee("trajectory", float(tolerance), bound=np.asarray(rec.bound, float),
                     scale=np.asarray(rec.scale, float), trajectory_sha256=trajectory_sha256,
                     region_sampled_error=sampled, region_missing=region_missing,
                     region=region,
                     method="sum of the dropped pairs' peak contributions on the trajectory "
                            "(triangle inequality)")


def build_recursive(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                    tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                    ranking: Ranking | None = None, trajectory_sha256: str = "",
                    provenance: dict | None = None, region: Region | None = None,
                    sample_region: Region | None = None, region_missing: str = "",
                    contributions: tuple[BaseParameters, tuple[np.ndarray, ...]] | None = None,
                    derive: Derivations = UNKEPT, searches: RegionSearches | None = None
                    ) -> tuple[SimplifiedModel, Selection]:
    """The pruned customized recursive Newton-Euler model within the budget.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd, qdd : ndarray, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2]: the bound holds on it.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    ranking : Ranking, optional
        For the thresholds s and e recorded with the model.
    trajectory_sha256 : str, optional
    provenance : dict, optional
    region : Region, optional
        Prune on bounds proved over this joint-limit region
        (:func:`gd_analyze.certify.certify.certify`) instead of the trajectory's peaks:
        the model's guarantee is then of kind ``"region"``. Where the sampled pre-screen finds
        that no such model could save enough (:func:`screened_exact`), the exact recursive
        model is built instead, without certification, and its provenance holds the screen
        (``region_screen``: :meth:`gd_analyze.certify.screen.RegionScreen.to_dict`); the same
        where the pairs searched under the proved bounds save less than the threshold
        (:func:`region_search`; the screen's ``proved`` True).
    sample_region : Region, optional
        For a trajectory model: the region on which its error is sampled
        (``region_sampled_error`` of its guarantee).
    region_missing : str, optional
        Why a trajectory model has no region (a missing limit), for its guarantee.
    contributions : (BaseParameters, tuple of ndarray), optional
        The robot's base parameters and their
        :func:`gd_analyze.symbolic.pruning.contribution_peaks` on this trajectory, if the
        caller computed them already (:func:`gd_analyze.jobs.peak_jobs.contribution_job`);
        computed here otherwise.
    derive : Derivations, optional
        Where certifications and searches are kept between runs
        (:class:`~gd_analyze.simplify.region_memo.Derivations`; default nowhere).
    searches : RegionSearches, optional
        :func:`region_searches` of this robot, ``base``, ``region``, ``tolerance`` and
        ``torque_floor``, if the caller made them already (the main job makes them beside its
        pass over the G-D terms); made here otherwise.

    Returns
    -------
    model : SimplifiedModel
        Of the recursive form, ``validation`` empty; ``costs["exact recursive"]`` holds the
        exact recursive model's count.
    selection : Selection
        Its scale and bound, the bound split by part (``"D"``: inertial, ``"h"``: velocity,
        ``"c"``: gravity, ``"whole"``: parameters dropped whole) [N m].

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger
    1987; Gautier 1990), pruned as :func:`gd_analyze.symbolic.recursive_model.recursive_model`.
    """
    base, peaks = (base_parameters(robot), None) if contributions is None else contributions
    if region is None:
        rec = recursive_model(robot, q, qd, qdd, tolerance, torque_floor, base=base,
                              peaks=peaks)
        found = RegionSearch(rec, trajectory_guarantee(robot, base, rec, tolerance,
                                                       trajectory_sha256, sample_region,
                                                       region_missing))
        candidates: list[RegionSearch | None] = [found]
    else:
        if searches is None:
            searches = region_searches(robot, base, region, tolerance, torque_floor,
                                       derive=derive)
        found = searches.found
        if found.screen is not None:    # no region model saves enough: the exact one built
            provenance = {**(provenance or {}), "region_screen": found.screen.to_dict()}
        candidates = [found, searches.floor_zero]
    models = [recursive_simplified(robot, c.rec, base, tolerance=tolerance,
                                   torque_floor=torque_floor, ranking=ranking,
                                   trajectory_sha256=trajectory_sha256, provenance=provenance,
                                   guarantee=c.guarantee, forms=c.forms, searched=c.store)
              for c in candidates if c is not None]
    model = min(models, key=lambda m: total_operations(m.cost))     # the first on a tie
    return model, recursive_selection(model)


def recursive_selection(model: SimplifiedModel) -> Selection:
    """A recursive model's scale and bound as the explicit model's selection gives them.

    Parameters
    ----------
    model : SimplifiedModel
        Of the recursive form (its ``recursive`` not None), with n joints.

    Returns
    -------
    Selection
        Of the budget rule, ``kept`` None; ``scale``, ``bound`` and ``bound_by_kind``
        (``"D"``: inertial, ``"h"``: velocity, ``"c"``: gravity, ``"whole"``: parameters
        dropped whole) of :class:`~gd_analyze.symbolic.recursive_model.RecursiveModel`
        [N m or N]; ``element_bound`` NaN.
    """
    rec: Any = model.recursive
    return Selection(rule="budget", tolerance=float(model.tolerance), choices=model.choices,
                     kept=None, scale=rec.scale, bound=rec.bound,
                     bound_by_kind=dict(zip(("D", "h", "c", "whole"), rec.bound_by_part)),
                     element_bound=np.full(model.robot.n, np.nan))


@dataclass(frozen=True)
class RegionSearches:
    """The region searches a main job's recursive model and its tolerance ladder take
    (:func:`region_searches`).

    Attributes
    ----------
    found : RegionSearch
        :func:`region_search` at the model's EPS.
    floor_zero : RegionSearch or None
        With a torque floor TAU > 0 and a pruned model found: the pairs the search drops
        without the floor, proved under the floor's certification, where they fit; else None.
    rungs : dict of float to RegionSearch
        :func:`region_search` (``sampled`` False) at each other EPS of the ladder asked for;
        empty where ``found`` is the exact model the sampled pre-screen chose (no ladder is
        certified then).
    """

    found: RegionSearch
    floor_zero: RegionSearch | None = None
    rungs: Mapping[float, RegionSearch] = dataclasses.field(default_factory=dict)


def region_searches(robot: Robot, base: BaseParameters, region: Region, tolerance: float,
                    torque_floor: float = 0.0, ladder: Sequence[float] = (),
                    derive: Derivations = UNKEPT) -> RegionSearches:
    """The region searches of a main job's recursive model and of its tolerance ladder.

    They depend on the robot, its base parameters, the region, EPS and TAU, not on the
    trajectory, so the main job makes them on a thread beside its pass over the G-D terms
    (:func:`gd_analyze.jobs.peak_jobs.start_peaks`) and hands them to
    :func:`build_recursive` and :func:`gd_analyze.simplify.recursive_ladder.recursive_ladder`.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    region : Region
        The joint-limit region the bounds are proved over.
    tolerance : float
        EPS >= 0 of the model.
    torque_floor : float, optional
        TAU [N m or N].
    ladder : sequence of float, optional
        EPS of the ladder's rungs; the model's own EPS among them is not searched again.
    derive : Derivations, optional
        Where certifications and searches are kept between runs (default nowhere).

    Returns
    -------
    RegionSearches

    Raises
    ------
    ValueError
        If a tolerance is negative or not finite (:func:`region_search`).

    Notes
    -----
    The same calls, in the same order, as :func:`build_recursive` and the ladder made
    themselves: a search's outcome does not depend on the thread that makes it.
    """
    found = region_search(robot, base, region, tolerance, torque_floor, derive=derive)
    floor_zero = _floor_zero_choice(robot, base, region, tolerance, torque_floor, derive) \
        if found.screen is None and torque_floor > 0 else None
    if found.screen is not None and not found.screen.proved:
        return RegionSearches(found)            # the sampled pre-screen: no ladder
    rungs = {float(eps): region_search(robot, base, region, float(eps), torque_floor,
                                       sampled=False, derive=derive)
             for eps in ladder if float(eps) != float(tolerance)}
    return RegionSearches(found, floor_zero, rungs)


def _floor_zero_choice(robot, base, region, tolerance, torque_floor, derive):
    """The pairs the search drops without a torque floor, proved under the floor's
    certification (a :class:`RegionSearch`), or None if they do not fit.

    With a floor every s_i only grows, so the budget only grows and those pairs fit it; the
    greedy search under the larger budget may end dearer (a pair it drops first, restored
    later for the proof that D_s is positive definite), so a floor is never to cost more than
    this choice.
    """
    rec0 = region_search(robot, base, region, tolerance, sampled=False, screen=False,
                         derive=derive).rec
    pb = certified(robot, base, region, torque_floor, derive)
    try:
        pr = _fitting(np.asarray(rec0.dropped, bool),
                      lambda c: _region_pruning(base, pb, robot, region, tolerance, c))
    except ValueError:
        return None
    return RegionSearch(*_region_model(robot, base, region, tolerance, pb, pr))


def _fitting(dropped, select):
    """``select((dropped, whole))`` with the parameters whose parts are all dropped counted
    whole, else pair by pair where that does not fit; ValueError if neither does."""
    for whole in (dropped.all(axis=1), np.zeros(dropped.shape[0], bool)):
        try:
            return select((dropped, whole))
        except ValueError:
            continue
    raise ValueError("the pairs do not fit the budget")


def recursive_simplified(robot: Robot, rec: RecursiveModel, base: BaseParameters,
                         tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                         ranking: Ranking | None = None, trajectory_sha256: str = "",
                         provenance: Mapping[str, Any] | None = None,
                         guarantee: Guarantee | None = None,
                         forms: tuple | None = None, searched: Callable[..., Any] | None = None
                         ) -> SimplifiedModel:
    """A pruned recursive model as a :class:`SimplifiedModel`, its program and counts built.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    rec : RecursiveModel
        The pruned model (:func:`gd_analyze.symbolic.recursive_model.recursive_model`, or
        :func:`~gd_analyze.symbolic.recursive_model.sweep_recursive_model` for a sweep).
    base : BaseParameters
        The robot's base parameters, those of ``rec``.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    ranking : Ranking, optional
        For the thresholds s and e recorded with the model.
    trajectory_sha256 : str, optional
    provenance : dict, optional
    guarantee : Guarantee, optional
        Where its bound holds (:class:`gd_analyze.simplify.guarantee.Guarantee`).
    forms : (sequence of str, sequence of str or None), optional
        The forms of the links' inertial moments of the exact and of the pruned program
        (:attr:`gd_analyze.symbolic.codegen.Program.forms`) from an earlier search with
        the same inputs: the programs are built with them, without the searches.
    searched : callable, optional
        Called with those forms of the programs built (the pruned program's None when the
        exact one is deployed).

    Returns
    -------
    SimplifiedModel
        Of the recursive form, ``validation`` empty, ``bound`` = ``rec.bound`` [N m];
        ``cost`` counted on its program (the exact recursive program when pruning would
        cost more, :func:`gd_analyze.symbolic.pruning.pruned_program`), and
        ``costs["exact recursive"]`` the exact recursive model's count.

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger
    1987; Gautier 1990).
    """
    exact_forms, pruned_forms = forms if forms is not None else (None, None)
    exact_program = recursive_program(robot, base.values, forms=exact_forms)
    exact = with_drives(exact_program, robot).cost()
    choice = rec.choice(robot, exact=exact_program,          # built once, kept with the model
                        forms=pruned_forms if rec.dropped.any() else None)
    if searched is not None:
        searched(exact_program.forms, None if choice[0] is exact_program else choice[0].forms)
    program = with_drives(choice[0], robot)
    choices = {lab: "both" for lab in element_labels(robot.n)}
    model = SimplifiedModel(
        robot=robot, choices=choices,
        dominance_threshold=float(getattr(ranking, "dominance_threshold", DEFAULT_DOMINANCE)),
        negligible_threshold=float(getattr(ranking, "negligible_threshold", DEFAULT_NEGLIGIBLE)),
        trajectory_sha256=trajectory_sha256, provenance=dict(provenance or {}), rule="budget",
        tolerance=float(tolerance), torque_floor=float(torque_floor), terms=None,
        recursive=rec, bound=[float(v) for v in rec.bound],
        costs={"exact recursive": exact}, program_cache=program,
        choice_cache=(*choice, exact_program),
        guarantee=guarantee)
    return dataclasses.replace(model, cost=dict(program.cost()))


@dataclass(frozen=True)
class RegionSearch:
    """A region model at one EPS as :func:`region_search` found it.

    Attributes
    ----------
    rec : RecursiveModel
    guarantee : Guarantee or None
        Of kind ``"region"``; None where it was not asked for (``sampled=False``).
    forms : (exact forms, pruned forms) or None
        The programs' forms read from the derivation cache.
    store : callable or None
        ``store(exact_forms, pruned_forms)`` keeps a new search's outcome in the cache (or
        the forms of the exact model the sampled pre-screen chose).
    screen : RegionScreen or None
        The screen where it chose the exact model: the sampled pre-screen (the region not
        certified), or the screen of the pairs searched under the proved bounds
        (:attr:`~gd_analyze.certify.screen.RegionScreen.proved`: the pruned model's programs
        not built); None where the pruned model is deployed.
    """

    rec: RecursiveModel
    guarantee: Guarantee | None
    forms: tuple | None = None
    store: Callable[..., Any] | None = None
    screen: RegionScreen | None = None


#: Searches made in this process (:func:`region_search`), by their inputs and stored entry.
_SEARCHED: dict = {}
#: Searches :data:`_SEARCHED` keeps (a main job makes up to five: its EPS, the ladder's other
#: rungs, the torque floor's second choice).
_SEARCHED_MAX = 12


def release() -> None:
    """Forget the region searches (:func:`region_search`), the region derivations
    (:func:`gd_analyze.simplify.region_memo.release`) and the joint sums' enclosures
    (:func:`gd_analyze.certify.certify.release`) kept in this process.

    Their certifications hold the channel values of the region's sampled positions (about
    415 MB for a 15-joint arm); a later model of the same arm derives them again or reads them
    from the derivation cache.

    Examples
    --------
    >>> release()
    >>> _SEARCHED
    {}
    """
    _SEARCHED.clear()
    release_derivations()
    release_sums()


def region_search(robot: Robot, base: BaseParameters, region: Region, tolerance: float,
                  torque_floor: float = 0.0, sampled: bool = True, screen: bool = True,
                  derive: Derivations = UNKEPT) -> RegionSearch:
    """The region model at one EPS as the main job deploys it: the exact recursive model
    where the sampled pre-screen finds that no region model could save enough
    (:func:`screened_exact`), else the model searched (:func:`region_model`), its searches
    taken from ``derive``'s store where an entry passes its checks; and the exact recursive model again where
    the pairs searched under the proved bounds save less than
    :data:`gd_analyze.certify.screen.MIN_SAVING` of its operations by the quick counts
    (:func:`gd_analyze.certify.screen.proved_screen`; with ``sampled``, those of the pairs
    left once the model's proof of D_s positive definite has restored what it needs), so that
    the pruned model's programs are not built.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    region : Region
    tolerance : float
        EPS >= 0.
    torque_floor : float, optional
        TAU [N m or N].
    sampled : bool, optional
        False: a searched model's guarantee is not built (None) and its error over the region
        not sampled (the tolerance ladder's rungs).
    screen : bool, optional
        False: the model is searched and built without either screen.
    derive : Derivations, optional
        Where certifications and searches are kept between runs
        (:class:`~gd_analyze.simplify.region_memo.Derivations`; default nowhere).

    Returns
    -------
    RegionSearch

    Notes
    -----
    A search kept by ``derive`` was made by a run whose screen chose to search: the
    screen only chooses between two sound paths, so it is not run again (the entry itself is
    checked: its pairs must pass the budget, its forms only choose among programs that compute
    the same torques). A bad entry is ignored with a warning. Where the sampled pre-screen
    chooses the exact model, its programs' forms are kept by ``derive`` apart
    (``screened``), used where that entry drops the very pairs proved identically zero.

    A search is made once per process for the same arm, base parameters, region (with its
    source and notes), EPS, TAU, flags (and :data:`DECOMPOSE`) and store, and the same
    stored entry (its content,
    read again each time): a second analysis of the arm in one session (the Python API, a
    test run) takes the first one's result. One made after a bad entry's warning is not kept,
    so that the warning is given again while the entry stays.
    """
    found, where = derive.read_search(robot, region, tolerance, torque_floor, REGION_SAMPLES,
                                      robot.n, base.rank)
    key = None if isinstance(found, str) else (
        region_key(robot, region, torque_floor), json.dumps(region.to_dict(), sort_keys=True),
        np.asarray(base.beta, float).tobytes(),
        np.asarray(base.independent, bool).tobytes(), float(tolerance), bool(sampled),
        bool(screen), derive, _entry_key(found), DECOMPOSE)
    if key in _SEARCHED:
        return _SEARCHED[key]
    result, kept = _region_search(robot, base, region, tolerance, torque_floor, sampled,
                                  screen, derive, found, where)
    if kept and key is not None:
        while len(_SEARCHED) >= _SEARCHED_MAX:
            _SEARCHED.pop(next(iter(_SEARCHED)))
        _SEARCHED[key] = result
    return result


def _entry_key(found):
    """A stored search's content as a key (None: no entry)."""
    if found is None:
        return None
    return (np.asarray(found["dropped"], bool).tobytes(),
            np.asarray(found["whole"], bool).tobytes(), tuple(found["exact_forms"]),
            None if found["pruned_forms"] is None else tuple(found["pruned_forms"]))


def _region_search(robot, base, region, tolerance, torque_floor, sampled, screen, derive,
                   found, where):
    """:func:`region_search` from the stored entry read (``found``, ``where``), and whether
    its result may be kept for the process (no bad entry was warned of)."""
    exact = None if isinstance(found, dict) or not screen else screened_exact(
        robot, base, region, tolerance, torque_floor)
    if exact is not None:
        return _screened_search(robot, base, region, tolerance, torque_floor, derive, exact)
    pb = certified(robot, base, region, torque_floor, derive)
    if isinstance(found, dict):
        try:
            pr = _region_pruning(base, pb, robot, region, tolerance,
                                 (found["dropped"], found["whole"]))
        except ValueError:
            found = "holds dropped pairs over the budget"
        else:
            forms = (found["exact_forms"], found["pruned_forms"])
            proved = _proved_exact(robot, base, region, tolerance, pb, pr[0].dropped,
                                   sampled) if screen else None
            if proved is not None:          # the entry's pruned forms are another program's
                return RegionSearch(proved[0], proved[1], (forms[0], None),
                                    screen=proved[2]), True
            rec, guarantee = _region_model(robot, base, region, tolerance, pb, pr, sampled)
            return RegionSearch(rec, guarantee, forms), True
    kept = not isinstance(found, str)
    if not kept:
        warnings.warn(one_line(f"{where}: derivation cache entry {found}: "
                               "ignored, the model is searched again"), CacheWarning,
                      stacklevel=2)
    screened = {}

    def worth(plain):
        screened[id(plain)] = _proved_exact(robot, base, region, tolerance, pb, plain.dropped,
                                            sampled)
        return screened[id(plain)] is None
    pruned = _region_pruning(base, pb, robot, region, tolerance, worth=worth if screen else None)
    pr = pruned[0]

    def store(exact_forms, pruned_forms):
        derive.write_search(robot, region, tolerance, torque_floor, REGION_SAMPLES, pr.dropped,
                            pr.whole, exact_forms, pruned_forms)
    if screen:
        proved = screened[id(pr)] if id(pr) in screened else _proved_exact(
            robot, base, region, tolerance, pb, pr.dropped, sampled)
        if proved is not None:
            return RegionSearch(proved[0], proved[1], store=store, screen=proved[2]), kept
    rec, guarantee = _region_model(robot, base, region, tolerance, pb, pruned, sampled)
    return RegionSearch(rec, guarantee, store=store), kept


def _screened_search(robot, base, region, tolerance, torque_floor, derive, exact):
    """The exact model the sampled pre-screen chose (``exact``: :func:`screened_exact`'s) as
    a :class:`RegionSearch`, with its programs' forms from ``derive``'s entry of it where one
    holds its very pairs (forms only choose among programs of the same torques), else with a
    ``store`` that keeps them once built; and whether it may be kept for the process (no bad
    entry was warned of)."""
    rec, guarantee, screen = exact
    found, where = derive.read_search(robot, region, tolerance, torque_floor, REGION_SAMPLES,
                                      robot.n, base.rank, screened=True)
    if isinstance(found, dict) and not (np.array_equal(found["dropped"], rec.dropped)
                                        and not found["whole"].any()):
        found = "holds other pairs than those proved identically zero"
    if isinstance(found, dict):
        return RegionSearch(rec, guarantee, (found["exact_forms"], found["pruned_forms"]),
                            screen=screen), True
    if isinstance(found, str):
        warnings.warn(one_line(f"{where}: derivation cache entry {found}: ignored, the "
                               "model's programs are searched again"), CacheWarning,
                      stacklevel=3)

    def store(exact_forms, pruned_forms):
        derive.write_search(robot, region, tolerance, torque_floor, REGION_SAMPLES,
                            rec.dropped, np.zeros(rec.dropped.shape[0], bool), exact_forms,
                            pruned_forms, screened=True)
    return RegionSearch(rec, guarantee, store=store, screen=screen), found is None


def _proved_exact(robot, base, region, tolerance, pb, dropped, restore=True):
    """The exact model (:func:`_exact_model`) where the pairs the search dropped under the
    proved bounds save less than :data:`gd_analyze.certify.screen.MIN_SAVING` by the quick
    counts (:func:`gd_analyze.certify.screen.proved_screen`), with that screen; else None.
    With ``restore`` (a model to deploy, whose D_s is proved positive definite), where they
    save enough and drop inertial parts, the screen counts the pairs the model would keep
    dropped once its proof of D_s has restored what it needs
    (:func:`gd_analyze.certify.positive_definite.inertia_restored`, the same trials)."""
    scale = np.asarray(pb.scale, float)
    rel = _relative_bounds(pb)
    found = proved_screen(robot, base, dropped, tolerance, scale, pb.scale_state, rel)
    if restore and not found.skip and np.any(np.asarray(dropped, bool)[:, 0] & ~pb.zero[:, 0]):
        kept = inertia_restored(robot, base, dropped, rel, region.q_min, region.q_max)
        back = dropped[:, 0] & ~kept[:, 0]
        if back.any():      # the restored parameters' other parts kept too where cheaper,
            whole = kept.copy()             # as the rebuild settles them (settle_restored)
            whole[back] = False
            found = min((proved_screen(robot, base, d, tolerance, scale, pb.scale_state, rel,
                                       RESTORED_MIN_SAVING, int(back.sum()))
                         for d in (kept, whole)), key=lambda f: f.best_operations)
    return None if not found.skip else (*_exact_model(robot, base, region, tolerance, found),
                                        found)


def screened_exact(robot: Robot, base: BaseParameters, region: Region, tolerance: float,
                   torque_floor: float = 0.0
                   ) -> tuple[RecursiveModel, Guarantee, RegionScreen] | None:
    """The exact recursive model under a region guarantee, where the sampled pre-screen finds
    that no region model could save :data:`gd_analyze.certify.screen.MIN_SAVING` of
    its operations; else None.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    region : Region
    tolerance : float
        EPS.
    torque_floor : float, optional
        [N m or N].

    Returns
    -------
    (RecursiveModel, Guarantee, RegionScreen) or None
        Only the (base parameter, part) pairs that are identically zero at every joint left
        out, decided symbolically (:func:`gd_analyze.symbolic.pruning.zero_parts`), bound
        0 (the model's error is 0 at every state, a proof without search), s_i as the
        certification would use it, sampled error 0; the screen
        (:func:`gd_analyze.certify.screen.screen_region`) says why. None when the
        region is to be certified and searched.
    """
    found = screen_region(robot, base, region, region_values(robot, base, region), tolerance,
                          torque_floor, magnitudes=region_magnitudes(robot, base, region))
    if not found.skip:
        return None
    return (*_exact_model(robot, base, region, tolerance, found), found)


def _exact_model(robot, base, region, tolerance, found):
    """The exact recursive model under a region guarantee, less the pairs proved identically
    zero symbolically (bound 0), and its guarantee, where the screen ``found`` (a
    :class:`~gd_analyze.certify.screen.RegionScreen` that skips) says why."""
    n = robot.n
    zero = np.asarray(zero_parts(robot, np.flatnonzero(base.independent.reshape(-1))).all(
        axis=2), bool)
    rec = RecursiveModel(names=tuple(base.names()), beta=np.array(base.beta, float),
                         dropped=zero, scale=found.scale.copy(),
                         bound=np.zeros(n), bound_by_part=np.zeros((4, n)),
                         relative_peak=found.relative_peak)
    guarantee = Guarantee(
        "region", float(tolerance), bound=np.zeros(n), scale=found.scale.copy(),
        q_min=region.q_min, q_max=region.q_max, qd_max=region.qd_max, qdd_max=region.qdd_max,
        scale_state=found.scale_state, sampled_error=np.zeros(n), region=region,
        scale_positions=region_values(robot, base, region)[0].shape[0],
        scale_polished=n <= REFINE_JOINTS)
    return rec, dataclasses.replace(guarantee, method=(
        "the exact recursive model (only pairs proved identically zero left out: its error is "
        "0 at every state); " + found.text() + "; scale s_i: " + guarantee.scale_source()))


def restored_rebuild(q: np.ndarray | None, qd: np.ndarray | None, qdd: np.ndarray | None,
                     region: Region | None = None, sample_region: Region | None = None,
                     region_missing: str = "",
                     contributions: tuple[BaseParameters, tuple[np.ndarray, ...]] | None = None,
                     derive: Derivations = UNKEPT) -> Callable[..., SimplifiedModel]:
    """A ``rebuild`` for :func:`gd_analyze.certify.positive_definite.with_inertia_check`:
    the recursive model with exactly the given pairs dropped, its bound, guarantee (bound and
    sampled error) and cost derived again for them.

    Parameters
    ----------
    q, qd, qdd : ndarray, shape (N, n), or None
        The trajectory the model was built on [rad, rad/s, rad/s^2; m, m/s, m/s^2]; None
        for a region model (its region is used).
    region : Region, optional
        The region its bound is proved over (a region model), else None.
    sample_region : Region, optional
        A trajectory model's region of sampled errors.
    region_missing : str, optional
    contributions : (BaseParameters, tuple of ndarray), optional
        As :func:`build_recursive` takes them.
    derive : Derivations, optional
        Where certifications and searches are kept between runs
        (:class:`~gd_analyze.simplify.region_memo.Derivations`; default nowhere).

    Returns
    -------
    callable
        ``rebuild(model, dropped)`` -> SimplifiedModel: the model's settings, provenance,
        thresholds and compared costs kept, ``costs["recursive, budget"]`` its new count.

    Notes
    -----
    Fewer pairs are dropped, so the pruning's budget still holds: the bound is that of
    :func:`gd_analyze.symbolic.pruning.prune_bounds` for the chosen pairs (a parameter
    counted whole where all its parts are dropped and that fits, else pair by pair).
    """
    def rebuild(model, dropped):
        robot, tol, floor = model.robot, model.tolerance, model.torque_floor
        base = model.recursive.base(robot) if contributions is None else contributions[0]
        dropped = settle_restored(robot, base, model.recursive.dropped, dropped)
        if region is not None:
            pb = certified(robot, base, region, floor, derive)
            rec, guarantee = _region_model(robot, base, region, tol, pb, _fitting(
                dropped, lambda c: _region_pruning(base, pb, robot, region, tol, c)))
        else:
            rec = _fitting(dropped, lambda c: recursive_model(
                robot, q, qd, qdd, tol, floor, base=base, chosen=c,
                peaks=None if contributions is None else contributions[1]))
            guarantee = trajectory_guarantee(robot, base, rec, tol, model.trajectory_sha256,
                                             sample_region, region_missing)
        return rebuilt(model, rec, base, guarantee)
    return rebuild


def rebuilt(model: SimplifiedModel, rec: RecursiveModel, base: BaseParameters,
            guarantee: Guarantee | None = None) -> SimplifiedModel:
    """A recursive model with other pairs dropped, as a ``rebuild`` of
    :func:`gd_analyze.certify.positive_definite.with_inertia_check` returns it.

    Parameters
    ----------
    model : SimplifiedModel
        The model rebuilt.
    rec : RecursiveModel
        Its new pruned model.
    base : BaseParameters
        The robot's base parameters.
    guarantee : Guarantee, optional
        The new model's.

    Returns
    -------
    SimplifiedModel
        :func:`recursive_simplified` of ``rec``, with the model's settings, provenance,
        thresholds, validation and compared costs kept, ``costs["recursive, budget"]`` its
        new count.
    """
    new = recursive_simplified(model.robot, rec, base, tolerance=model.tolerance,
                               torque_floor=model.torque_floor,
                               trajectory_sha256=model.trajectory_sha256,
                               provenance=model.provenance, guarantee=guarantee)
    costs = {**model.costs, "recursive, budget": dict(new.cost)} if model.costs else \
        dict(new.costs)
    return dataclasses.replace(
        new, dominance_threshold=model.dominance_threshold,
        negligible_threshold=model.negligible_threshold, validation=model.validation,
        costs=costs, full_cost=dict(model.full_cost), program_cache=new.program())
