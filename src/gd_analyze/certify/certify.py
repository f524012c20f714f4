"""Proved bounds of every (base parameter, part) contribution over the joint-limit region,
by branch and bound on interval enclosures.

For the pair (base parameter m, part p) and joint i the contribution to tau_i over the region R
is |beta_m| times the part's coefficient function of q
(:mod:`gd_analyze.certify.regressor_bounds`), through the velocity and acceleration limits
exactly. Its maximum over the box of positions is bounded from above by ball (midpoint-radius)
evaluation of the recursion on sub-boxes,
each box split where its enclosure could still exceed what sampling found (branch and bound;
Moore, Kearfott & Cloud 2009, Ch. 6). Joints no coefficient depends on are never split (joint 1
about the gravity axis). The sampled peaks are lower bounds of the same maxima, so
``sampled <= true maximum <= bound``.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..symbolic.pruning import zero_parts
from . import intervals as iv
from .ball_kernels import summed_kernel
from .region import ChannelValues, qd_vertices, region_samples, velocity_channels
from .regressor_bounds import (
    channel_count,
    channel_enclosures,
    channel_magnitudes,
    combined_bound,
    pair_magnitudes,
)
from .vertex_kernel import found_extremes

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot
    from .region import Region

__all__ = ["PairBounds", "certify", "certify_tree", "tiling", "pair_peaks_at",
           "pair_magnitudes_at", "METHOD", "prove_dropped", "JointSums", "joint_sums",
           "JOINT_SUM_ELEMENTS", "leaf_bound", "dropped_bound", "region_bound",
           "split_joints", "JOINT_BOXES", "JOINT_DIMS", "dropped_search", "tree_bound",
           "proved_zero", "region_trees", "tilings_bound", "decomposed_bound",
           "decomposed_pairs", "decomposed_search", "decomposed_limit", "DECOMPOSED_GRID",
           "decomposed_tree_bound", "summed_tree_bound", "BOUND_METHODS", "method_bounds",
           "bound_methods", "tree_method_bounds", "unproved_way", "release"]

#: How the bounds are obtained, in words (stored with every region model).
METHOD = ("per (base parameter, part) pair: |beta| x upper bound of its coefficient over the "
          "position box by midpoint-radius (ball) evaluation of the Newton-Euler regressor "
          "recursion, rounded outward, refined by branch and bound; velocity and acceleration through "
          "their limits exactly (linear in qdd, quadratic in qd); parts of "
          "inertia parameters proved identically zero by trigonometric polynomials bounded by 0; "
          "a dropped set's bound at joint i: the largest over the final boxes of the least of "
          "the sum of its pairs' bounds there and the bound of their sum (the joint sum: the "
          "pairs' coefficient enclosures on the box added as signed intervals, beta included, "
          "before the acceleration limits, the quadratic form in qd and the gravity term are "
          "bounded together, so contributions of opposite signs cancel)")


@dataclass(frozen=True, eq=False)
class PairBounds:
    """Upper and sampled bounds of every pair's contribution over a region.

    Attributes
    ----------
    bound : ndarray, shape (b, 3, n)
        Proved upper bound of |contribution| of (base parameter, part) to tau_i over R
        [N m or N].
    sampled : ndarray, shape (b, 3, n)
        Largest |contribution| found by sampling R (a lower bound of the same maximum).
    scale : ndarray, shape (n,)
        s_i = max(largest |tau_i| found over R, torque floor) [N m or N].
    scale_state : ndarray, shape (n, 3 n)
        Where |tau_i| = s_i was found: (q, qd, qdd).
    positions : ndarray, shape (B, n)
        The sampled positions [rad or m].
    values : ChannelValues
        The coefficient functions at them (:func:`.region.channel_values`).
    boxes : int
        Boxes evaluated by the branch and bound.
    leaves : ndarray, shape (b, 3, L, n)
        The bounds on each of the L final boxes, which cover the region: a set of pairs
        changes tau_i by at most max over the boxes of the sum of its pairs' bounds there.
    leaf_boxes : ndarray, shape (L, 2, n)
        The final boxes' lower and upper position limits [rad or m].
    seconds : float
        Wall time of the certification [s].
    split_joint : ndarray of int, shape (boxes,)
        The branch and bound's tree, one entry per box evaluated, level by level in the order
        evaluated: the joint along which the box was halved, or -1 for a final box.
    split_at : ndarray, shape (boxes,)
        Where it was halved [rad or m] (0 for a final box). :func:`tiling` rebuilds the boxes
        from these two and the region.
    zero : ndarray of bool, shape (b, 3), optional
        The pairs proved identically zero: those zero at every joint by
        :func:`gd_analyze.symbolic.pruning.zero_parts` (decided symbolically; their
        enclosures are set to 0 on every box, as are those of the parts zero at some joints),
        and any pair whose enclosure is 0 on every final box. Dropping them costs nothing.
    witness : ndarray of bool, shape (boxes, n), optional
        Per box evaluated (in :attr:`split_joint`'s order) and link k: whether the box's
        enclosure of some column of link k is the one a final box's bound takes (the
        shallowest box on the final box's path that reaches the least), for some part and
        joint. :func:`certify_tree` evaluates only these (box, link) pairs and gets the same
        bounds; any other choice gives bounds at least as large, still proved.
    """

    bound: np.ndarray
    sampled: np.ndarray
    scale: np.ndarray
    scale_state: np.ndarray
    positions: np.ndarray
    values: ChannelValues
    boxes: int
    leaves: np.ndarray
    leaf_boxes: np.ndarray
    seconds: float
    split_joint: np.ndarray
    split_at: np.ndarray
    zero: np.ndarray | None = None
    witness: np.ndarray | None = None


#: Largest set of joints whose velocity vertices are all searched (:func:`.region.qd_vertices`'s).
SEARCHED_JOINTS = 13


def pair_magnitudes_at(V: ChannelValues, beta: np.ndarray, qd_max: np.ndarray,
                       qdd_max: np.ndarray) -> np.ndarray:
    """Each pair's largest |contribution| at each given position, over the velocity and
    acceleration limits.

    Parameters
    ----------
    V : ChannelValues
        :func:`.region.channel_values` of b columns at B positions.
    beta : ndarray, shape (b,)
        Base parameter values.
    qd_max, qdd_max : ndarray, shape (n,)
        [rad/s, rad/s^2; m/s, m/s^2].

    Returns
    -------
    ndarray, shape (B, b, 3, n)
        Inertial: sum_j |A_j| qdd_max_j |beta| (reached); velocity: max over the vertices of
        qd of |qd^T C qd| |beta|; gravity: |G| |beta| [N m or N].

    Notes
    -----
    A column's velocity terms involve only the joints S whose C_jl are not all zero (a column
    of link k: joints up to k), so its vertices are those of S (2^(|S| - 1)): the others change
    no value.
    """
    qd_max, qdd_max = np.asarray(qd_max, float), np.asarray(qdd_max, float)
    out = np.zeros((V.positions, V.columns, 3, V.n))
    for M, idx, Vm in V.groups:       # a column of link k: the rows and joints up to k only
        out[:, idx, :, :M] = _magnitudes(Vm, qd_max[:M], qdd_max[:M])
    return out * np.abs(beta)[None, :, None, None]


def _magnitudes(V, qd_max, qdd_max):
    """:func:`pair_magnitudes_at` of unit parameters on a dense packed block (B, P, n, b)."""
    B, C, n, b = V.shape
    out = np.zeros((B, b, 3, n))
    out[:, :, 0] = (np.abs(V[:, 1:1 + n]) * qdd_max[None, :, None, None]).sum(1).transpose(
        0, 2, 1)
    out[:, :, 2] = np.abs(V[:, 0]).transpose(0, 2, 1)
    packed = 1 + n + velocity_channels(n)                               # (n n,)
    used = _nonzero(V[:, 1 + n:])[packed - 1 - n].reshape(n, n, b)
    support = used.any(axis=0) | used.any(axis=1)                       # (n, b)
    groups = {}
    for m in range(b):                  # columns by the joints their velocity terms involve
        groups.setdefault(tuple(np.flatnonzero(support[:, m])), []).append(m)
    for S, ms in groups.items():
        if not S:
            continue                    # no velocity term: 0
        S, ms = np.asarray(S), np.asarray(ms)
        out[:, ms, 1] = _vertex_peaks(V, S, ms, packed, qd_max)
    return out


def _nonzero(V):
    """Whether each (channel, column) of V (B, C, n, b) is nonzero somewhere, shape (C, b): at
    the first position, and where it is zero there, at all of them."""
    used = (V[0] != 0).any(axis=1)
    ch, c = np.nonzero(~used)
    if ch.size:
        used[ch, c] = (V[:, ch, :, c] != 0).any(axis=(1, 2))
    return used


def _vertex_peaks(V, S, ms, packed, qd_max):
    """max |qd^T C qd| over the vertices of the velocity box of the joints S, at every
    position (B, g, n), for the columns ms: at a vertex qd_j^2 = a_j^2, so the diagonal part
    is a constant and the rest is a form in the signs, whose extremes
    :func:`.vertex_kernel.found_extremes` finds over all 2^(s-1) vertices up to
    :data:`SEARCHED_JOINTS` joints, and over the random vertices of :func:`.region.qd_vertices`
    beyond."""
    n = V.shape[2]
    j, l = np.triu_indices(S.size, 1)
    pairs, diag = packed[S[j] * n + S[l]], packed[S * (n + 1)]
    w_off, w_diag = qd_max[S[j]] * qd_max[S[l]], qd_max[S] ** 2
    d = np.einsum("bcig,c->bgi", V[:, diag][..., ms], w_diag)           # (B, g, n)
    signs = None                        # every vertex, or the random ones beyond
    if S.size > SEARCHED_JOINTS:
        signs = np.copysign(1.0, qd_vertices(qd_max[S]))
    top, bottom = found_extremes(V, j, l, w_off, S.size, channels=pairs, columns=ms,
                                 factor=2.0, vertices=signs)      # the rows (b, g, i) in place
    return np.maximum(d + top.reshape(d.shape), -(d + bottom.reshape(d.shape)))


def pair_peaks_at(V: ChannelValues, beta: np.ndarray, qd_max: np.ndarray,
                  qdd_max: np.ndarray) -> np.ndarray:
    """The largest of :func:`pair_magnitudes_at` over the positions.

    Parameters
    ----------
    V, beta, qd_max, qdd_max
        As :func:`pair_magnitudes_at` takes them: the channel values (:class:`.region.ChannelValues`), the
        base parameters' values, shape (b,), and the velocity and acceleration limits, shape
        (n,) [rad/s, rad/s^2; m/s, m/s^2].

    Returns
    -------
    ndarray, shape (b, 3, n)
        Each pair's largest |contribution| over the positions and the velocity and
        acceleration limits [N m or N].
    """
    return pair_magnitudes_at(V, beta, qd_max, qdd_max).max(axis=0)


def _sampled_peaks(values, beta, region):
    """:func:`pair_peaks_at` of the samples, or the peaks that follow them in ``values``."""
    if len(values) > 4:
        return np.asarray(values[4], float)
    return pair_peaks_at(values[1], beta, region.qd_max, region.qdd_max)


def _relevant(robot):
    """Joints whose position changes a coefficient: all but a first revolute joint about the
    gravity axis (its rotation leaves the inertial, velocity and gravity parts unchanged)."""
    rel = np.ones(robot.n, bool)
    if not robot.prismatic[0]:
        axis = np.asarray(robot.rotation[0], float)[:, 2]
        g = np.asarray(robot.gravity, float)
        if np.linalg.norm(np.cross(axis, g)) <= 1e-12 * max(np.linalg.norm(g), 1e-300):
            rel[0] = False
    return rel


def _bisect(lo, hi, rel, demand=None):
    """Boxes halved along their widest relevant joint (with ``demand`` (B, n) >= 0: the
    relevant joint of the largest width times demand): the lower halves, then the upper ones
    (copies; ``lo``, ``hi`` of shape (B, n) are not changed), the joints and the mid points."""
    width = hi - lo if demand is None else (hi - lo) * demand
    width = np.where(rel[None, :], width, -1.0)
    d = width.argmax(axis=1)
    rows = np.arange(lo.shape[0])
    mid = 0.5 * (lo[rows, d] + hi[rows, d])
    return (*_halves(lo, hi, d, mid), d, mid)


def _demand(above, cols):
    """Per box and joint, how many of the box's columns with a pair above its target depend on
    the joint (a column of link k on joints 1..k), plus 1e-3: shape (B, n) from ``above``
    (B, 3, n, b) and the columns' flat indices ``cols`` (b,)."""
    n = above.shape[2]
    depends = (cols[:, None] // 10 >= np.arange(n)[None, :]).astype(float)   # (b, n)
    return above.any(axis=(1, 2)).astype(float) @ depends + 1e-3


def _halves(lo, hi, d, at):
    """Boxes (B, n) cut along joint d[k] at at[k]: the lower parts, then the upper ones."""
    rows = np.arange(lo.shape[0])
    lo1, hi1 = lo.copy(), hi.copy()
    lo2, hi2 = lo.copy(), hi.copy()
    hi1[rows, d] = at
    lo2[rows, d] = at
    return np.vstack([lo1, lo2]), np.vstack([hi1, hi2])


#: Boxes enclosed in one call (bounded memory: about 40 MB a call at 15 joints).
_CHUNK = 128


def _enclose(robot, lo, hi, cols, region, absb, zero):
    """:func:`pair_magnitudes` times |beta| on the boxes (B, n), in chunks of :data:`_CHUNK`,
    with the parts ``zero`` (b, 3, n), proved identically zero
    (:func:`gd_analyze.symbolic.pruning.zero_parts`), set to 0; shape (B, 3, n, b)."""
    U = np.concatenate([
        pair_magnitudes(robot, lo[a:a + _CHUNK], hi[a:a + _CHUNK], cols, region.qd_max,
                        region.qdd_max) * absb
        for a in range(0, lo.shape[0], _CHUNK)])
    U[:, zero.transpose(1, 2, 0)] = 0.0
    return U


def _zero_pairs(zero, leaf):
    """(b, 3): the pairs proved zero at every joint (``zero`` (b, 3, n)) or 0 on every final
    box (``leaf`` (b, 3, L, n))."""
    return (leaf == 0).all(axis=(2, 3)) | zero.all(axis=2)


def tiling(region: Region, split_joint: np.ndarray, split_at: np.ndarray | None = None
           ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The boxes of a branch-and-bound tree, level by level, checked to tile the region.

    Parameters
    ----------
    region : Region
        Its position box is the root.
    split_joint : ndarray of int, shape (N,)
        Per box, level by level: the joint it is cut along, or -1 (a final box).
    split_at : ndarray, shape (N,), optional
        Where [rad or m]; None: at the middle of the box, 0.5 (lo + hi) (a bisection tree,
        as :func:`certify` and :func:`dropped_bound` build it).

    Returns
    -------
    list of (ndarray, ndarray, ndarray)
        Per level: the boxes' lower and upper limits (B, n) and which are cut (B,). A cut box's
        lower parts come first on the next level, then its upper parts (as in :func:`certify`).

    Raises
    ------
    ValueError
        If the arrays are not such a tree: a joint the arm does not have, a cut point not
        strictly inside its box (a box of zero volume, or overlapping ones), too few entries
        (part of the region not covered) or too many.

    Notes
    -----
    Every cut replaces a box by two whose union is the box and whose intersection is the
    face at the cut point, both with the very same float (no rounding), so the final boxes
    tile the region exactly, with no overlap of positive volume, by induction.
    """
    n = region.q_min.size
    joint = np.asarray(split_joint)
    at = None if split_at is None else np.asarray(split_at)
    if joint.ndim != 1 or joint.dtype.kind not in "iu" or (
            at is not None and (at.shape != joint.shape or at.dtype.kind != "f")):
        raise ValueError("does not hold a tree of boxes (arrays of other types or shapes)")
    if np.any(joint < -1) or np.any(joint >= n):
        raise ValueError("cuts along a joint the arm does not have")
    lo, hi = region.q_min[None, :].astype(float), region.q_max[None, :].astype(float)
    levels, p = [], 0
    while lo.shape[0]:
        B = lo.shape[0]
        if p + B > joint.size:
            raise ValueError("does not cover the region (its tree ends early)")
        d = joint[p:p + B].astype(int)
        split = d >= 0
        rows, d = np.flatnonzero(split), d[split]
        x = 0.5 * (lo[rows, d] + hi[rows, d]) if at is None else at[p:p + B][split]
        p += B
        if not (np.all(np.isfinite(x)) and np.all(lo[rows, d] < x) and np.all(x < hi[rows, d])):
            raise ValueError("cuts a box outside its interior (boxes of zero volume or "
                             "overlapping)")
        levels.append((lo, hi, split))
        lo, hi = _halves(lo[rows], hi[rows], d, x)
    if p != joint.size:
        raise ValueError("holds cuts of boxes it does not have")
    return levels


def certify(robot: Robot, base: BaseParameters, region: Region, torque_floor: float = 0.0,
            max_boxes: int = 1024, samples: int = 1000, seed: int = 0,
            open_share: float = 0.05, rtol: float = 0.1, values: tuple | None = None
            ) -> PairBounds:
    """Proved upper bounds of every pair's contribution over the region, and the scale.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    region : Region
    torque_floor : float, optional
        Least scale [N m or N].
    max_boxes : int, optional
        Boxes the branch and bound may evaluate in all (about 1.5 ms a box for six joints).
    samples : int, optional
        Uniform position samples for the scale and the sampled peaks.
    seed : int, optional
    open_share : float, optional
        A pair is refined while its bound is at most this share of s_i (pairs above it are
        kept at any tolerance below it) and above (1 + rtol) its sampled peak.
    rtol : float, optional
    values : tuple, optional
        :func:`.region.region_samples` of these ``samples`` and ``seed``, if already drawn
        (the same positions and values; the floor is applied here), optionally followed by
        their :func:`pair_peaks_at`, shape (b, 3, n), if already computed.

    Returns
    -------
    PairBounds

    Notes
    -----
    Each round splits every box whose enclosure of an open pair exceeds (1 + rtol) that
    pair's sampled peak, along the relevant joint of the largest width times the number of
    the box's columns above their targets that depend on it (a column of link k depends on
    joints 1..k, so the joints that most of the box's open columns need are halved first).
    The bound is the largest enclosure over the final boxes, so it holds whatever the
    number of rounds and wherever the boxes are cut.
    """
    t0 = time.perf_counter()
    n = robot.n
    cols = np.flatnonzero(base.independent.reshape(-1))
    beta = np.asarray(base.beta, float)
    values = values if values is not None else region_samples(robot, base, region, samples,
                                                              seed)
    q, V, scale, state = values[:4]
    scale = np.maximum(scale, torque_floor)
    sampled = _sampled_peaks(values, beta, region)
    absb = np.abs(beta)[None, None, :]                              # over (3, n, b)
    zero = zero_parts(robot, cols)
    lo = region.q_min[None, :].copy()
    hi = region.q_max[None, :].copy()
    rel = _relevant(robot)
    done_u = np.zeros((3, n, cols.size))
    leaves, boxes = [], []
    inherited = np.full((1, 3, n, cols.size), np.inf)
    source: np.ndarray = np.zeros((1, 3, n, cols.size), np.int32)   # the box each least comes from
    witness = []
    evaluated = 0
    target = (1 + rtol) * sampled.transpose(1, 2, 0) + 1e-9 * scale[None, :, None]
    joints, cuts = [], []
    while lo.shape[0]:
        # a box's bound is the least of its own enclosure and its ancestors': each holds on it
        E = _enclose(robot, lo, hi, cols, region, absb, zero)
        U = np.minimum(E, inherited)
        # on a tie the ancestor's (the shallowest box reaching the least) is the witness
        source = np.where(E < inherited, (evaluated + np.arange(
            lo.shape[0], dtype=np.int32))[:, None, None, None], source)
        del E
        evaluated += lo.shape[0]
        upper = np.maximum(done_u, U.max(axis=0))
        open_ = (upper <= open_share * scale[None, :, None]) & (upper > target)
        split = np.any((U > target[None]) & open_[None], axis=(1, 2, 3))
        joint, at = np.full(lo.shape[0], -1, np.int64), np.zeros(lo.shape[0])
        joints.append(joint)
        cuts.append(at)
        if not split.any() or evaluated + 2 * split.sum() > max_boxes:
            done_u = upper
            leaves.append(U)
            witness.append(source)
            boxes.append(np.stack([lo, hi], axis=1))
            break
        if (~split).any():
            done_u = np.maximum(done_u, U[~split].max(axis=0))
            leaves.append(U[~split])
            witness.append(source[~split])
            boxes.append(np.stack([lo[~split], hi[~split]], axis=1))
        demand = _demand((U[split] > target[None]) & open_[None], cols)
        lo, hi, joint[split], at[split] = _bisect(lo[split], hi[split], rel, demand)
        inherited = np.concatenate([U[split], U[split]])
        source = np.concatenate([source[split], source[split]])
    bound = np.maximum(done_u.transpose(2, 0, 1), sampled)
    leaf = _pair_major(leaves)                                    # (b, 3, L, n)
    return PairBounds(bound=bound, sampled=sampled, scale=scale, scale_state=state,
                      positions=q, values=V, boxes=evaluated, leaves=leaf,
                      leaf_boxes=np.concatenate(boxes),
                      seconds=time.perf_counter() - t0, split_joint=np.concatenate(joints),
                      split_at=np.concatenate(cuts), zero=_zero_pairs(zero, leaf),
                      witness=_witness(witness, evaluated, cols, zero))


def _witness(sources, boxes, cols, zero):
    """(boxes, n) bool: the (box, link) pairs some final box's bound comes from, from the
    source boxes of the final boxes' least enclosures (blocks (L_k, 3, n, b) of box indices);
    the parts proved zero (``zero`` (b, 3, n), 0 on every box) need none."""
    n = zero.shape[2]
    out = np.zeros((boxes, n), bool)
    link = np.broadcast_to(cols // 10, sources[0].shape[1:])           # (3, n, b)
    live = ~zero.transpose(1, 2, 0)
    for s in sources:
        out[s[:, live], np.broadcast_to(link[live], (s.shape[0], int(live.sum())))] = True
    return out


def certify_tree(robot: Robot, base: BaseParameters, region: Region, split_joint: np.ndarray,
                 split_at: np.ndarray, values: tuple, torque_floor: float = 0.0,
                 seconds: float = 0.0, witness: np.ndarray | None = None) -> PairBounds:
    """The bounds of :func:`certify` on a given tree of boxes, derived again without search.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    region : Region
    split_joint, split_at : ndarray, shape (N,)
        The tree (:attr:`PairBounds.split_joint`, :attr:`PairBounds.split_at`), checked by
        :func:`tiling`.
    values : tuple
        ``(positions, channel values, scale, scale state)`` as
        :func:`.region.region_samples` gives them (the floor is applied here), optionally
        followed by their :func:`pair_peaks_at`.
    torque_floor : float, optional
        Least scale [N m or N].
    seconds : float, optional
        Stored as :attr:`PairBounds.seconds`.
    witness : ndarray of bool, shape (N, n), optional
        Which (box, link) enclosures to evaluate (:attr:`PairBounds.witness`, untrusted);
        None: all of them.

    Returns
    -------
    PairBounds
        Equal to :func:`certify`'s when the tree is the one it built on the same samples
        (and the witnesses its own): the enclosures of the boxes (of the links the witnesses
        name) are evaluated again, each box's bound is the least of its own and its
        ancestors' evaluated there (+inf where none is), and the bound of a pair is the
        largest over the final boxes and its sampled peak.

    Raises
    ------
    ValueError
        If the tree does not tile the region (:func:`tiling`), or the witnesses are not one
        flag per box and joint.

    Notes
    -----
    Any tiling gives sound bounds (each final box's enclosure holds on it, and the boxes cover
    the region), so nothing but the tiling needs checking; the bounds are never read. Any
    witnesses do too: a final box's bound is the least of enclosures evaluated here on boxes
    that contain it (itself or its ancestors), so wrong witnesses can only make bounds
    larger (+inf where a final box's path has none), never smaller than what the boxes give.
    """
    levels = tiling(region, split_joint, split_at)
    n = robot.n
    cols = np.flatnonzero(base.independent.reshape(-1))
    beta = np.asarray(base.beta, float)
    q, V, scale, state = values[:4]
    scale = np.maximum(scale, torque_floor)
    sampled = _sampled_peaks(values, beta, region)
    absb = np.abs(beta)[None, None, :]
    zero = zero_parts(robot, cols)
    if witness is not None:
        witness = np.asarray(witness)
        if witness.dtype.kind != "b" or witness.shape != (int(np.asarray(split_joint).size), n):
            raise ValueError("does not hold one witness flag per box and joint")
        E = _witnessed(robot, levels, cols, region, absb, zero, witness)
    inherited = np.full((1, 3, n, cols.size), np.inf)
    leaves, boxes = [], []
    p = 0
    for lo, hi, split in levels:
        U = np.minimum(_enclose(robot, lo, hi, cols, region, absb, zero) if witness is None
                       else E[p:p + lo.shape[0]], inherited)
        p += lo.shape[0]
        leaves.append(U[~split])
        boxes.append(np.stack([lo[~split], hi[~split]], axis=1))
        inherited = np.concatenate([U[split], U[split]])
    leaf = _pair_major(leaves)                                        # (b, 3, L, n)
    bound = np.maximum(leaf.max(axis=2), sampled)
    return PairBounds(bound=bound, sampled=sampled, scale=scale, scale_state=state,
                      positions=q, values=V, boxes=int(np.asarray(split_joint).size),
                      leaves=leaf, leaf_boxes=np.concatenate(boxes),
                      seconds=float(seconds), split_joint=np.asarray(split_joint, np.int64),
                      split_at=np.asarray(split_at, float),
                      zero=_zero_pairs(zero, leaf), witness=witness)


def _witnessed(robot, levels, cols, region, absb, zero, witness):
    """The enclosures :func:`_enclose` gives, on the (box, link) pairs ``witness`` (N, n)
    names only, link by link over all boxes of the tree at once; +inf elsewhere, 0 on the
    parts proved zero; shape (N, 3, n, b)."""
    lo = np.concatenate([a for a, _, _ in levels])
    hi = np.concatenate([b for _, b, _ in levels])
    n = lo.shape[1]
    E = np.full((lo.shape[0], 3, n, cols.size), np.inf)
    for k in np.unique(cols // 10):
        ms = np.flatnonzero(cols // 10 == k)
        rows = np.flatnonzero(witness[:, k])
        for a in range(0, rows.size, _CHUNK):
            r = rows[a:a + _CHUNK]
            E[r[:, None], :, :, ms[None, :]] = (pair_magnitudes(
                robot, lo[r], hi[r], cols[ms], region.qd_max, region.qdd_max)
                * absb[..., ms]).transpose(0, 3, 1, 2)
    E[:, zero.transpose(1, 2, 0)] = 0.0
    return E


def _pair_major(leaves):
    """The final boxes' enclosures, each block (L_k, 3, n, b), as one C-ordered array
    (b, 3, L, n): a dropped set's sum over its pairs then gathers contiguous rows
    (:func:`leaf_bound`, the pruning's pieces). The blocks are released as they are copied."""
    out = np.empty((leaves[0].shape[3], 3, sum(u.shape[0] for u in leaves), leaves[0].shape[2]))
    at = 0
    while leaves:
        u = leaves.pop(0)
        out[:, :, at:at + u.shape[0], :] = u.transpose(3, 1, 0, 2)
        at += u.shape[0]
    return out



#: Most elements of each array of a :class:`JointSums` (64 MB each; its construction holds
#: about four such arrays at once): the columns beyond are not held (a set dropping one of
#: their pairs is bounded pair by pair). The shipped arms hold at most 5.5 M (the Panda's 27
#: columns on 512 boxes); a 12-joint chain's 4,000 boxes hold one column.
JOINT_SUM_ELEMENTS = 1 << 23


@dataclass(frozen=True, eq=False)
class JointSums:
    """Signed enclosures of some pairs' coefficients on boxes, for the bound of the sum of a
    dropped set's contributions on each box at each joint (the joint sum).

    Attributes
    ----------
    pairs : ndarray of bool, shape (b, 3)
        The (base parameter, part) pairs held: a dropped set with any other pair (not in
        ``zero``) has no joint sum (infinite).
    zero : ndarray of bool, shape (b, 3)
        Pairs proved identically zero over the region, left out of every sum.
    columns : ndarray of int, shape (k,)
        The base parameters held (those with a pair in ``pairs``).
    mid : ndarray, shape (L, C, n, k)
        Per box, channel (:func:`gd_analyze.certify.regressor_bounds.channel_values`'
        order), joint and parameter: beta_m times the centre of the channel's enclosure
        [N m or N].
    rad : ndarray, shape (L, C, n, k)
        |beta_m| times its radius, widened by the round-off of the recursion's intervals, of
        the product and of a sum of k terms [N m or N].
    part_zero : ndarray of bool, shape (k, 3, n)
        Parts proved identically zero at a joint
        (:func:`gd_analyze.symbolic.pruning.zero_parts`): their channels left out.
    qd_max, qdd_max : ndarray, shape (n,)
        The region's velocity and acceleration limits [rad/s, m/s; rad/s^2, m/s^2].
    """

    pairs: np.ndarray
    zero: np.ndarray
    columns: np.ndarray
    mid: np.ndarray
    rad: np.ndarray
    part_zero: np.ndarray
    qd_max: np.ndarray
    qdd_max: np.ndarray

    def bound(self, dropped: np.ndarray) -> np.ndarray:
        """Per box and joint, an upper bound of |sum of the dropped pairs' contributions|.

        Parameters
        ----------
        dropped : ndarray of bool, shape (b, 3)
            The pairs left out.

        Returns
        -------
        ndarray, shape (L, n)
            :func:`gd_analyze.certify.regressor_bounds.combined_bound` of the dropped
            pairs' channel enclosures added per box (inf everywhere when a dropped pair is
            not held) [N m or N].
        """
        L, C, n, k = self.mid.shape
        sums = self.sums(dropped)
        if sums is None:
            return np.full((L, n), np.inf)
        return combined_bound(*sums, self.qd_max, self.qdd_max)

    def sums(self, dropped: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """The dropped pairs' channel enclosures added per box, in midpoint-radius form.

        Parameters
        ----------
        dropped : ndarray of bool, shape (b, 3)
            The pairs left out.

        Returns
        -------
        (ndarray, ndarray) or None
            Centres and radii, shape (L, C, n) each, the round-off of the sums included
            [N m or N]; None when a dropped pair is not held.
        """
        dropped = np.asarray(dropped, bool) & ~self.zero
        L, C, n, k = self.mid.shape
        if np.any(dropped & ~self.pairs):
            return None
        w = dropped[self.columns].T[:, None, :] & ~self.part_zero.transpose(1, 2, 0)  # (3, n, k)
        part = np.r_[2, np.zeros(n, int), np.ones(n * n, int)]          # channel -> part
        W = w[part].astype(float)                                         # (C, n, k)
        mid = np.einsum("lcik,cik->lci", self.mid, W)
        rad = np.einsum("lcik,cik->lci", self.rad, W) * (1 + 4 * (k + 2) * iv.ROUNDING)
        return mid, rad


def joint_sums(robot: Robot, base: BaseParameters, region: Region, split_joint: np.ndarray,
               split_at: np.ndarray, pairs: np.ndarray, zero: np.ndarray | None = None
               ) -> JointSums:
    """:class:`JointSums` of some pairs on the final boxes of a branch-and-bound tree.

    Parameters
    ----------
    robot, base, region
        The arm (n joints), its b base parameters and the region.
    split_joint, split_at : ndarray, shape (N,)
        The tree (:attr:`PairBounds.split_joint`, :attr:`PairBounds.split_at`), checked by
        :func:`tiling`; its final boxes are ordered as :attr:`PairBounds.leaf_boxes`.
    pairs : ndarray of bool, shape (b, 3)
        The pairs that may be dropped; their parameters are held, in increasing order, up to
        :data:`JOINT_SUM_ELEMENTS` elements per array.
    zero : ndarray of bool, shape (b, 3), optional
        Pairs proved identically zero over the region (:attr:`PairBounds.zero`).

    Returns
    -------
    JointSums
        On the final boxes.

    Raises
    ------
    ValueError
        If the tree does not tile the region (:func:`tiling`).

    Notes
    -----
    The torque is linear in the base parameters, so the dropped pairs change tau_i by
    sum_m beta_m (part p_m of column m) at the same state: their channels' enclosures are
    added on each box as intervals (dependence across pairs is kept within the box, and
    contributions that peak in other boxes are never added). Each box's enclosure of a
    channel is intersected with its ancestors' (each holds on it), as the pairs' bounds of
    :func:`certify` are (Moore, Kearfott & Cloud 2009, Ch. 6).
    """
    levels = tiling(region, split_joint, split_at)
    pairs = np.asarray(pairs, bool)
    zero = np.zeros(pairs.shape, bool) if zero is None else np.asarray(zero, bool)
    leaves = sum(int((~split).sum()) for _, _, split in levels)
    used = _held(robot.n, leaves, pairs, zero)
    cols = np.flatnonzero(base.independent.reshape(-1))[used]
    key = b"".join(np.ascontiguousarray(a).tobytes() for a in (
        np.asarray(region.q_min, float), np.asarray(region.q_max, float),
        np.asarray(split_joint), np.asarray(split_at, float)))
    beta = np.asarray(base.beta, float)[used]
    slack = _slack(robot.n, used.size)
    kept = next(iter(_JOINT_SUMS), None)          # (another thread may replace it)
    at = np.full(used.size, -1)                    # each column's place in the kept sums
    if kept is not None and kept[0] is robot and kept[1] == key and kept[4] == slack:
        for i, (c, b) in enumerate(zip(cols, beta)):
            hit = np.flatnonzero((kept[2] == c) & (kept[3] == b))
            at[i] = hit[0] if hit.size else -1
    missing = at < 0
    if kept is not None and not missing.any() and np.array_equal(at, np.arange(
            kept[2].size)):
        mid, rad = kept[5].mid, kept[5].rad        # the very same columns: shared
    else:
        if missing.all():
            mid, rad = _scaled(list(_leaf_channels(robot, key, levels, leaves, cols)), beta,
                               slack)
        else:                                      # kept columns copied, the others evaluated
            shape = kept[5].mid.shape[:-1] + (used.size,)             # type: ignore[index]
            mid, rad = np.empty(shape), np.empty(shape)
            mid[..., ~missing] = np.take(kept[5].mid, at[~missing], axis=-1)  # type: ignore[index]
            rad[..., ~missing] = np.take(kept[5].rad, at[~missing], axis=-1)  # type: ignore[index]
            if missing.any():
                mid[..., missing], rad[..., missing] = _scaled(list(_leaf_channels(
                    robot, key, levels, leaves, cols[missing])), beta[missing], slack)
        for array in (mid, rad):
            array.flags.writeable = False           # shared by the sums of other pair sets
    sums = _joint_sums_of(robot, region, used, pairs, zero, mid, rad, cols)
    _JOINT_SUMS[:] = [(robot, key, cols, beta, slack, sums)]
    return sums


#: The last :func:`joint_sums` built: the arm, the key of its tree, the held columns, their
#: parameters' values, the round-off slack and the sums. A column's enclosures in them
#: (``mid[..., m]``, ``rad[..., m]``) are a function of the tree, the column, its value and
#: the slack alone (elementwise, whatever other pairs or columns are held, and whatever the
#: velocity limits), so the joint sums of another budget on the same certification (the
#: tolerance ladder's rungs) copy the columns they share with these instead of evaluating
#: them on the same boxes again; at most one set is kept, as large as the sums a search
#: holds anyway.
_JOINT_SUMS: list[tuple[Any, bytes, np.ndarray, np.ndarray, float, JointSums]] = []


#: Most numbers per array of the leaf enclosures kept between calls (16 MB each); for an arm
#: of at most :data:`KEPT_CHANNEL_JOINTS` joints as many as the joint sums hold
#: (:data:`JOINT_SUM_ELEMENTS`, 64 MB): a 7-joint arm's ladder asks for 20 to 36 columns on
#: 512 final boxes (4 to 7 million numbers), which the joint sums of each budget then
#: evaluate once in all instead of once per budget. Beyond that the joint sums hold only a few
#: columns, and keeping 8 million numbers raised a 12-joint chain's peak by 161 MB for no time.
KEPT_CHANNEL_ELEMENTS = 1 << 21
#: The most joints of an arm whose leaf enclosures are kept up to :data:`JOINT_SUM_ELEMENTS`.
KEPT_CHANNEL_JOINTS = 8
#: The last tree's leaf enclosures of the columns asked so far (:func:`_leaf_channels`): the
#: arm, the tree's key, the columns (increasing) and their (lo, hi).
_LEAF_CHANNELS: list[tuple[Any, bytes, np.ndarray, np.ndarray, np.ndarray]] = []


def _leaf_channels(robot, key, levels, leaves, cols):
    """The channel enclosures (lo, hi) (L, C, n, m) of the columns ``cols`` (m, increasing) on
    the L final boxes of a tree (:func:`tiling`'s ``levels``), each box's intersected with its
    ancestors'; new arrays (the caller may write in them).

    A column's enclosures do not depend on the other columns evaluated with it (each is its
    own backward recursion from the same forward one, and the intersections are elementwise),
    so those of the last tree seen are kept (the arm by identity, the tree by ``key``, at most
    :data:`KEPT_CHANNEL_ELEMENTS` numbers per array, or :data:`JOINT_SUM_ELEMENTS` for an arm
    of at most :data:`KEPT_CHANNEL_JOINTS` joints) and only columns not kept are evaluated:
    the joint sums of several budgets on one certification's tree (12 and 8 columns on the
    PUMA 560, one set inside the other) evaluate each column once.
    """
    kept = next(iter(_LEAF_CHANNELS), None)        # (another thread may replace it)
    if kept is not None and (kept[0] is not robot or kept[1] != key):
        kept = None
    have = kept[2] if kept is not None else np.zeros(0, int)
    missing = np.setdiff1d(cols, have)
    if kept is None or missing.size:
        new = _tree_channels(robot, levels, leaves, missing if kept is not None else cols)
    if kept is None:
        every, (lo, hi) = np.asarray(cols, int), new
    elif missing.size:
        every = np.union1d(have, missing)
        lo, hi = (np.empty(old.shape[:-1] + (every.size,)) for old in kept[3:])
        at_old, at_new = np.searchsorted(every, have), np.searchsorted(every, missing)
        for out, old, add in zip((lo, hi), kept[3:], new):
            out[..., at_old], out[..., at_new] = old, add
    else:
        every, lo, hi = have, kept[3], kept[4]
    if lo.size <= (JOINT_SUM_ELEMENTS if robot.n <= KEPT_CHANNEL_JOINTS
                   else KEPT_CHANNEL_ELEMENTS):
        _LEAF_CHANNELS[:] = [(robot, key, every, lo, hi)]
    else:
        _LEAF_CHANNELS.clear()
    at = np.searchsorted(every, cols)
    # copies, the caller's to write in (np.take: a tenth of the time of lo[..., at])
    return np.take(lo, at, axis=-1), np.take(hi, at, axis=-1)


def release() -> None:
    """Forget the leaf enclosures and the joint sums kept between calls of :func:`joint_sums`.

    They serve the joint sums of the other budgets on the same certification's tree (a
    tolerance ladder's rungs) and hold up to four arrays of :data:`JOINT_SUM_ELEMENTS`
    numbers (256 MB); :func:`gd_analyze.simplify.deploy.release` calls this, so that the
    main job does not carry them into the report of a long trajectory.

    Examples
    --------
    >>> release()
    >>> _LEAF_CHANNELS, _JOINT_SUMS
    ([], [])
    """
    _LEAF_CHANNELS.clear()
    _JOINT_SUMS.clear()


def _tree_channels(robot, levels, leaves, cols):
    """:func:`_leaf_channels` evaluated: level by level down the tree."""
    c_lo: Any
    c_hi: Any
    parent, c_lo, c_hi, at = None, None, None, 0
    for lo, hi, split in levels:
        ch = _channels(robot, lo, hi, cols, parent)
        if c_lo is None:                  # the leaves' enclosures, filled level by level
            c_lo, c_hi = (np.empty((leaves,) + x.shape[1:]) for x in ch)
        k = int((~split).sum())
        c_lo[at:at + k], c_hi[at:at + k] = ch[0][~split], ch[1][~split]
        at += k
        parent = tuple(np.concatenate([x[split], x[split]]) for x in ch)
        del ch
    parent = None
    return c_lo, c_hi


def _held(n, boxes, pairs, zero):
    """The parameters a :class:`JointSums` on ``boxes`` boxes holds (within its size)."""
    per_column = boxes * (1 + n + n * n) * n
    return np.flatnonzero((pairs & ~zero).any(axis=1))[:JOINT_SUM_ELEMENTS // max(per_column, 1)]


def _channels(robot, lo, hi, cols, parent=None):
    """Channel enclosures (lo, hi) (B, C, n, k) of the columns on boxes (B, n), in chunks of
    :data:`_CHUNK`, intersected with the parents' (each holds on its sub-boxes)."""
    c_lo, c_hi = _joined((channel_enclosures(robot, lo[a:a + _CHUNK], hi[a:a + _CHUNK], cols)
                          for a in range(0, lo.shape[0], _CHUNK)), lo.shape[0])
    if parent is not None:              # (an empty intersection, by round-off: its hull)
        c_lo, c_hi = _intersect(c_lo, c_hi, parent[0], parent[1], in_place=True)
    return c_lo, c_hi


def _joined(chunks, rows):
    """The (lo, hi) of consecutive blocks of rows laid end to end, ``rows`` in all: the one
    block itself, else each block copied into place as it comes (not all held at once)."""
    out: Any = None
    at = 0
    for c_lo, c_hi in chunks:
        k = c_lo.shape[0]
        if out is None:
            if k == rows:
                return c_lo, c_hi
            out = tuple(np.empty((rows,) + c.shape[1:], c.dtype) for c in (c_lo, c_hi))
        out[0][at:at + k], out[1][at:at + k] = c_lo, c_hi
        at += k
        del c_lo, c_hi
    return out


def _slack(n, k):
    """The relative round-off allowance of :func:`_scaled` for k held columns of n joints."""
    return (2 * k + 16 * n + 32) * iv.ROUNDING


def _scaled(channels, beta, slack):
    """The held columns' enclosures ``[lo, hi]`` (L, C, n, k) as beta times midpoint-radius
    (mid, rad), the radius widened by ``slack``; in place (the list is emptied and its arrays
    used up, so that ``lo`` is freed as soon as it is read)."""
    c_lo, c_hi = channels
    channels.clear()
    # in place, the same operations as centre = 0.5 (lo + hi), radius = 0.5 (hi - lo),
    # rad = (radius (1 + slack) + slack |centre|) |beta|, mid = centre beta: a few arrays of
    # JOINT_SUM_ELEMENTS at a time, not nine
    mid = np.add(c_lo, c_hi)
    mid *= 0.5
    rad = np.subtract(c_hi, c_lo, out=c_hi)
    del c_lo
    rad *= 0.5
    rad *= 1 + slack
    more = np.abs(mid)
    more *= slack
    rad += more
    del more
    rad *= np.abs(beta)
    mid *= beta
    return mid, rad


def _joint_sums(robot, base, region, used, pairs, zero, c_lo, c_hi):
    """:class:`JointSums` from the held parameters' channel enclosures (L, C, n, k); ``c_hi``
    is used up (written in), ``c_lo`` left as it is."""
    channels = [c_lo, c_hi]
    del c_lo, c_hi
    mid, rad = _scaled(channels, np.asarray(base.beta, float)[used], _slack(robot.n, used.size))
    return _joint_sums_of(robot, region, used, pairs, zero, mid, rad,
                          np.flatnonzero(base.independent.reshape(-1))[used])


def _joint_sums_of(robot, region, used, pairs, zero, mid, rad, cols):
    """:class:`JointSums` of the held parameters ``used`` (their flat columns ``cols``) from
    their scaled enclosures."""
    held = np.zeros(pairs.shape, bool)
    held[used] = pairs[used]
    return JointSums(pairs=held, zero=zero, columns=used, mid=mid, rad=rad,
                     part_zero=zero_parts(robot, cols),
                     qd_max=np.asarray(region.qd_max, float),
                     qdd_max=np.asarray(region.qdd_max, float))


def leaf_bound(pb: PairBounds, sums: JointSums | None, dropped: np.ndarray) -> np.ndarray:
    """Per joint, the bound of a dropped set over the region from a certification.

    Parameters
    ----------
    pb : PairBounds
    sums : JointSums or None
        On ``pb.leaf_boxes`` (:func:`joint_sums`); None: pair by pair only.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out.

    Returns
    -------
    ndarray, shape (n,)
        The largest over the final boxes of the least of the sum of the dropped pairs'
        bounds there and their joint sum (:meth:`JointSums.bound`) [N m or N].
    """
    dropped = np.asarray(dropped, bool)
    each = pb.leaves[dropped].sum(axis=0)           # (L, n): the dropped pairs' rows
    if sums is not None and dropped.any():
        each = np.minimum(each, sums.bound(dropped))
    return each.max(axis=0)


def dropped_bound(robot: Robot, base: BaseParameters, region: Region, dropped: np.ndarray,
                  limit: np.ndarray, max_boxes: int = 1024, zero: np.ndarray | None = None
                  ) -> np.ndarray:
    """A bound of the change of each tau_i by a set of dropped pairs over the region, by
    branch and bound on the joint sum of those pairs alone.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    region : Region
    dropped : ndarray of bool, shape (b, 3)
        The (base parameter, part) pairs left out.
    limit : ndarray, shape (n,)
        The bound sought per joint [N m or N]: a box is halved while its bound exceeds it on
        some joint.
    max_boxes : int, optional
        Boxes evaluated in all before stopping.
    zero : ndarray of bool, shape (b, 3), optional
        Pairs proved identically zero over the region (:attr:`PairBounds.zero`), left out.

    Returns
    -------
    ndarray, shape (n,)
        The largest over a tiling of the region of the boxes' joint sums
        (:meth:`JointSums.bound`): |tau_s - tau| <= it at every state of the region
        [N m or N]. It is <= ``limit`` where the search succeeded; inf if the pairs are too
        many to hold (:data:`JOINT_SUM_ELEMENTS`).

    Notes
    -----
    Only the dropped parameters' columns are evaluated, and only the joints they depend on
    (those up to their last link, but a first revolute joint about the gravity axis) are
    halved, the widest first; each box's channel enclosures are intersected with its
    ancestors' (Moore, Kearfott & Cloud 2009, Ch. 6). A deterministic function of its
    arguments: the same call gives the same bound. :func:`dropped_search` also gives the
    tree of boxes it evaluated.
    """
    return dropped_search(robot, base, region, dropped, limit, max_boxes, zero)[0]


def dropped_search(robot: Robot, base: BaseParameters, region: Region, dropped: np.ndarray,
                   limit: np.ndarray, max_boxes: int = 1024, zero: np.ndarray | None = None,
                   resume: dict | None = None) -> tuple[np.ndarray, np.ndarray | None]:
    """:func:`dropped_bound`, and the tree of boxes its branch and bound evaluated.

    Parameters
    ----------
    robot, base, region, dropped, limit, max_boxes, zero
        As :func:`dropped_bound`: the arm (n joints), its b base parameters, the region, the
        pairs left out (b, 3), the bound sought (n,) [N m or N], the boxes evaluated in all,
        and the pairs proved identically zero (b, 3).
    resume : dict, optional
        Where the search keeps the last level it evaluated, and goes on from: an empty dict
        at the first call; one later call with the same dict and the same arm, base
        parameters, region, ``dropped``, ``limit`` and ``zero`` but more ``max_boxes``
        evaluates only the boxes beyond the first call's, and returns what a call without
        ``resume`` returns (the levels before are the same: a box is halved or not by its
        own sums alone, and a level is evaluated whole or not at all). The later call takes
        the level out of the dict (and keeps its own last level there).

    Returns
    -------
    bound : ndarray, shape (n,)
        :func:`dropped_bound` [N m or N].
    split_joint : ndarray of int, shape (N,) or None
        Per box evaluated, level by level, the joint it was halved along or -1 (a final
        box): a bisection tree (:func:`tiling` with ``split_at`` None) whose final boxes
        give ``bound`` again by :func:`tree_bound`; a single -1 where no box was needed (no
        pair but those proved zero), None where the pairs are too many to hold.
    """
    n = robot.n
    dropped = np.asarray(dropped, bool)
    limit = np.asarray(limit, float)
    free = np.zeros(dropped.shape, bool) if zero is None else np.asarray(zero, bool)
    live = dropped & ~free
    used = np.flatnonzero(live.any(axis=1))
    if used.size == 0:
        return np.zeros(n), np.full(1, -1, np.int64)
    if _held(n, _CHUNK, live, free).size < used.size:
        return np.full(n, np.inf), None
    cols = np.flatnonzero(base.independent.reshape(-1))[used]
    rel = split_joints(robot, base, live)
    pending = bool(resume)          # the last level of an earlier call, evaluated
    if pending:                     # taken out: held no longer than the search's own
        lo, hi, s_lo, s_hi, total, evaluated, done = resume.pop("level")  # type: ignore[union-attr]
        joints = resume.pop("joints")                                     # type: ignore[union-attr]
    else:
        lo, hi = region.q_min[None, :].astype(float), region.q_max[None, :].astype(float)
        parent, evaluated, done, joints = None, 0, np.zeros(n), []
    while True:
        if pending:
            pending = False         # go on from the level kept
        else:
            s_lo, s_hi = _summed(robot, base, region, lo, hi, cols, used, live, free, parent)
            total = combined_bound(0.5 * (s_lo + s_hi), 0.5 * (s_hi - s_lo), region.qd_max,
                                   region.qdd_max)
            evaluated += lo.shape[0]
            joints.append(np.full(lo.shape[0], -1, np.int64))
        open_ = ~np.all(total <= limit[None, :], axis=1)                # NaN stays open
        if not open_.any() or evaluated + 2 * int(open_.sum()) > max_boxes:
            if resume is not None:
                resume["level"] = (lo, hi, s_lo, s_hi, total, evaluated, done)
                resume["joints"] = [j.copy() for j in joints]
            return np.maximum(done, total.max(axis=0)), np.concatenate(joints)
        done = np.maximum(done, total[~open_].max(axis=0, initial=0.0))
        lo, hi, joints[-1][open_] = _bisect(lo[open_], hi[open_], rel)[:3]
        parent = tuple(np.concatenate([x[open_], x[open_]]) for x in (s_lo, s_hi))


def _summed(robot, base, region, lo, hi, cols, used, live, free, parent):
    """The live pairs' channel enclosures added on boxes (B, n), in chunks of :data:`_CHUNK`
    boxes, as intervals (lo, hi) (B, C, n), intersected with the parents' sums (each holds
    on the sub-boxes; an empty intersection, by round-off, gives the hull): the sums of
    :meth:`JointSums.sums` on :func:`_joint_sums`' scaled enclosures, in one compiled pass
    (:func:`_summed_chunk`)."""
    n = robot.n
    live = live & ~free
    # per channel, joint and column: 1 where the column's pair of the channel's part is live
    w = live[used].T[:, None, :] & ~zero_parts(robot, cols).transpose(1, 2, 0)  # (3, n, k)
    weight = w[np.r_[2, np.zeros(n, int), np.ones(n * n, int)]].astype(float)  # (C, n, k)
    beta = np.asarray(base.beta, float)[used]
    slack, widen = _slack(n, used.size), 1 + 4 * (used.size + 2) * iv.ROUNDING
    s_lo, s_hi = _joined((_summed_chunk(robot, lo[a:a + _CHUNK], hi[a:a + _CHUNK], cols, beta,
                                        weight, slack, widen)
                          for a in range(0, lo.shape[0], _CHUNK)), lo.shape[0])
    if parent is not None:
        s_lo, s_hi = _intersect(s_lo, s_hi, parent[0], parent[1], in_place=True)
    return s_lo, s_hi


#: Boxes of the branch and bound on a dropped set's joint sum (:func:`region_bound`).
JOINT_BOXES = 8192
#: Most joints that branch and bound halves (:func:`region_bound`): beyond, boxes small
#: enough to gain would be too many.
JOINT_DIMS = 3


def split_joints(robot: Robot, base: BaseParameters, dropped: np.ndarray,
                 zero: np.ndarray | None = None) -> np.ndarray:
    """The joints :func:`dropped_bound` halves for a dropped set.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    dropped : ndarray of bool, shape (b, 3)
    zero : ndarray of bool, shape (b, 3), optional
        Pairs proved identically zero, left out.

    Returns
    -------
    ndarray of bool, shape (n,)
        The joints up to the last link of a dropped pair not in ``zero``, but a first
        revolute joint about the gravity axis (no coefficient depends on it).
    """
    dropped = np.asarray(dropped, bool)
    if zero is not None:
        dropped = dropped & ~np.asarray(zero, bool)
    used = np.flatnonzero(dropped.any(axis=1))
    if used.size == 0:
        return np.zeros(robot.n, bool)
    last = int(np.flatnonzero(base.independent.reshape(-1))[used].max()) // 10
    return _relevant(robot) & (np.arange(robot.n) <= last)


def decomposed_pairs(robot: Robot, base: BaseParameters, dropped: np.ndarray,
                     zero: np.ndarray | None = None) -> np.ndarray | None:
    """The part of a dropped set that :func:`decomposed_bound` bounds by branch and bound.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out.
    zero : ndarray of bool, shape (b, 3), optional
        Pairs proved identically zero, left out.

    Returns
    -------
    ndarray of bool, shape (b, 3), or None
        The dropped pairs (but those in ``zero``) of the links 1..L, for the largest L whose
        pairs depend on at most :data:`JOINT_DIMS` joints (:func:`split_joints`); None when
        the whole set does (its own branch and bound is run instead), when no such pair is
        dropped, or when every dropped pair is (nothing is left to add).
    """
    live = np.asarray(dropped, bool)
    if zero is not None:
        live = live & ~np.asarray(zero, bool)
    if split_joints(robot, base, live).sum() <= JOINT_DIMS:
        return None
    link = np.flatnonzero(base.independent.reshape(-1)) // 10       # per base parameter
    best = None
    for last in range(robot.n):
        first = live & (link <= last)[:, None]
        if split_joints(robot, base, first).sum() > JOINT_DIMS:
            break
        best = first
    return None if best is None or not best.any() else best


#: The grid, relative to the budget, that :func:`decomposed_limit` rounds down to.
DECOMPOSED_GRID = 1e-6


def decomposed_limit(limit: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """The bound :func:`decomposed_bound`'s branch and bound seeks on the first links' pairs.

    Parameters
    ----------
    limit : ndarray, shape (n,)
        The budget EPS s_i [N m or N].
    rest : ndarray, shape (n,)
        :func:`leaf_bound` of the other dropped pairs [N m or N].

    Returns
    -------
    ndarray, shape (n,)
        ``limit - rest`` rounded down to a multiple of :data:`DECOMPOSED_GRID` times
        ``limit``, at least 0 [N m or N]: the branch and bound's tree does not move with the
        last bits of ``rest`` (joint sums holding other parameters round off differently),
        so a bound derived again with other joint sums finds the same tree.
    """
    limit = np.asarray(limit, float)
    step = DECOMPOSED_GRID * np.abs(limit)
    with np.errstate(divide="ignore", invalid="ignore"):
        grid = np.where(step > 0, np.floor((limit - rest) / np.where(step > 0, step, 1.0))
                        * step, 0.0)
    return np.maximum(np.nan_to_num(grid, nan=0.0, posinf=0.0, neginf=0.0), 0.0)


def decomposed_search(robot: Robot, base: BaseParameters, region: Region, pb: PairBounds,
                      dropped: np.ndarray, limit: np.ndarray, sums: JointSums | None = None,
                      resume: dict | None = None
                      ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """:func:`decomposed_bound`, the tree of its branch and bound and the pairs it ran on.

    Parameters
    ----------
    robot, base, region, pb, dropped, limit, sums
        As :func:`decomposed_bound`.
    resume : dict, optional
        As :func:`dropped_search`'s, for the branch and bound on the first links' pairs
        with the limit :func:`decomposed_limit`.

    Returns
    -------
    bound : ndarray, shape (n,)
        :func:`decomposed_bound` [N m or N].
    tree : ndarray of int, shape (N,) or None
        The bisection tree of the branch and bound on ``first`` (:func:`dropped_search`);
        None where it did not run.
    first : ndarray of bool, shape (b, 3) or None
        :func:`decomposed_pairs`; None where the bound is inf (no split).
    """
    n = robot.n
    first = decomposed_pairs(robot, base, dropped, pb.zero)
    if first is None:
        return np.full(n, np.inf), None, None
    rest = np.asarray(dropped, bool) & ~np.asarray(pb.zero, bool) & ~first
    other = leaf_bound(pb, sums, rest)
    head, tree = dropped_search(robot, base, region, first, decomposed_limit(limit, other),
                                JOINT_BOXES, pb.zero, resume)
    # the sum rounded up: each term bounds its part, so their exact sum bounds the whole
    return np.nextafter(head + other, np.inf), tree, first


def decomposed_bound(robot: Robot, base: BaseParameters, region: Region, pb: PairBounds,
                     dropped: np.ndarray, limit: np.ndarray, sums: JointSums | None = None
                     ) -> np.ndarray:
    """A bound of a dropped set over the region as the sum of two: the branch and bound on
    the joint sum of its first links' pairs, and the certification's final boxes' bound of
    the rest.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    region : Region
    pb : PairBounds
        The region's certification.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out.
    limit : ndarray, shape (n,)
        The budget EPS s_i [N m or N]: the branch and bound on the first links' pairs seeks
        :func:`decomposed_limit` (about ``limit - leaf_bound(rest)``).
    sums : JointSums, optional
        On the final boxes of ``pb`` (:func:`joint_sums`), holding the rest's pairs; None:
        the rest pair by pair.

    Returns
    -------
    ndarray, shape (n,)
        ``dropped_bound(first) + leaf_bound(rest)`` rounded up, where ``first`` is
        :func:`decomposed_pairs` (the dropped pairs of the links 1..L that depend on at most
        :data:`JOINT_DIMS` joints) and ``rest`` the other dropped pairs not proved zero; inf
        where there is no such split [N m or N].

    Notes
    -----
    tau = Y_b beta is linear in the base parameters, so the dropped set changes tau_i by the
    sum of the two parts' changes at the same state, and by the triangle inequality
    |tau_s - tau| <= |change by first| + |change by rest| <= the sum of their bounds, each
    of which holds at every state of the region: the first by branch and bound on its joint
    sum (:func:`dropped_bound`; Moore, Kearfott & Cloud 2009, Ch. 6), the rest on the
    certification's final boxes (:func:`leaf_bound`). It is tighter than :func:`leaf_bound`
    of the whole set where the set depends on more than :data:`JOINT_DIMS` joints (too many to
    halve) but most of its error comes from pairs of the first links, whose joint sum the
    branch and bound tightens.
    """
    return decomposed_search(robot, base, region, pb, dropped, limit, sums)[0]


def region_bound(robot: Robot, base: BaseParameters, region: Region, pb: PairBounds,
                 dropped: np.ndarray, limit: np.ndarray, sums: JointSums | None = None
                 ) -> np.ndarray:
    """The bound of a dropped set over the region that the region model states.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    region : Region
    pb : PairBounds
        The region's certification.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out.
    limit : ndarray, shape (n,)
        The budget EPS s_i [N m or N].
    sums : JointSums, optional
        On the final boxes of ``pb`` (:func:`joint_sums`), holding the dropped pairs; built
        here (for the dropped pairs) when not given.

    Returns
    -------
    ndarray, shape (n,)
        The least of :func:`leaf_bound` and, where the dropped pairs (but those proved zero)
        depend on at most :data:`JOINT_DIMS` joints (:func:`split_joints`),
        :func:`dropped_bound` with ``limit`` and :data:`JOINT_BOXES` boxes, else
        :func:`decomposed_bound` (that branch and bound on the pairs of the first links, the
        final boxes' bound of the rest); each bounds |tau_s - tau| over the region, so their
        least does [N m or N].
    """
    return region_trees(robot, base, region, pb, dropped, limit, sums)[0]


def region_trees(robot: Robot, base: BaseParameters, region: Region, pb: PairBounds,
                 dropped: np.ndarray, limit: np.ndarray, sums: JointSums | None = None,
                 resume: dict | None = None, decompose: bool = True
                 ) -> tuple[np.ndarray, tuple]:
    """:func:`region_bound`, and the trees of boxes whose final boxes give it.

    Parameters
    ----------
    robot, base, region, pb, dropped, limit, sums
        As :func:`region_bound`: the arm (n joints), its b base parameters, the region, its
        certification, the pairs left out (b, 3), the budget (n,) [N m or N] and the joint
        sums on the certification's final boxes.
    resume : dict, optional
        ``resume`` of an earlier :func:`dropped_search` of the same set with the same
        ``limit`` and ``pb.zero`` and fewer boxes (where the set depends on more than
        :data:`JOINT_DIMS` joints: of :func:`decomposed_search`'s, with the same ``sums``):
        the branch and bound goes on from it (the same result, fewer boxes evaluated again).
    decompose : bool, optional
        False: without :func:`decomposed_bound` (a larger bound, never a smaller one).

    Returns
    -------
    bound : ndarray, shape (n,)
        :func:`region_bound` [N m or N].
    trees : tuple of (ndarray of int or tuple of two, ndarray)
        The bisection trees (``split_joint`` of :func:`tiling`) and their bounds (n,): the
        certification's, with :func:`leaf_bound`, and, where it ran, the branch and bound's
        on the joint sum (:func:`dropped_search`); where the decomposition ran
        (:func:`decomposed_search`), the pair (its branch and bound's tree on the first
        links' pairs, the certification's tree) with :func:`decomposed_bound`. ``bound`` is
        the least of their bounds; :func:`tree_bound` of each tree, and
        :func:`decomposed_tree_bound` of each pair, is at most its bound (up to round-off),
        so a reader re-checks ``bound`` on the trees without a search.
    """
    dropped = np.asarray(dropped, bool)
    if sums is None:
        sums = joint_sums(robot, base, region, pb.split_joint, pb.split_at, dropped, pb.zero)
    out = leaf_bound(pb, sums, dropped)
    trees: tuple = ((np.asarray(pb.split_joint, np.int64), out),)
    if split_joints(robot, base, dropped, pb.zero).sum() <= JOINT_DIMS:
        searched, tree = dropped_search(robot, base, region, dropped, limit, JOINT_BOXES,
                                        pb.zero, resume)
        if tree is not None:
            trees += ((tree, searched),)
        out = np.minimum(out, searched)
    elif decompose:
        split, tree, _ = decomposed_search(robot, base, region, pb, dropped, limit, sums,
                                           resume)
        if tree is not None:
            trees += (((tree, trees[0][0]), split),)
        out = np.minimum(out, split)
    return out, trees


#: How a dropped set's bound at a joint is obtained (:func:`bound_methods`): nothing dropped
#: acts on it (bound 0); the sum of the pairs' own bounds on the certification's final boxes
#: (triangle inequality); the least there of that and their joint sum (:func:`leaf_bound`);
#: the branch and bound on their joint sum (:func:`dropped_bound`); the decomposition
#: (:func:`decomposed_bound`).
BOUND_METHODS = ("none", "pairs", "joint sum", "branch and bound", "decomposition")


def method_bounds(pb: PairBounds, dropped: np.ndarray, trees: tuple) -> dict[str, np.ndarray]:
    """Each way of :func:`region_trees` to bound a dropped set, with its bound.

    Parameters
    ----------
    pb : PairBounds
        The region's certification.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out.
    trees : tuple
        ``trees`` of :func:`region_trees` for ``dropped``: the certification's first.

    Returns
    -------
    dict of str to ndarray, shape (n,)
        By :data:`BOUND_METHODS` name: ``"none"`` 0 where the pairs' own bounds are, else
        inf, ``"pairs"`` the largest over the
        final boxes of the sum of the pairs' own bounds, ``"joint sum"`` :func:`leaf_bound`,
        and ``"branch and bound"`` or ``"decomposition"`` where that ran [N m or N].
    """
    pairs = pb.leaves[np.asarray(dropped, bool)].sum(axis=0).max(axis=0)
    out = {"none": np.where(pairs == 0, 0.0, np.inf), "pairs": pairs,
           "joint sum": np.asarray(trees[0][1], float)}
    for tree, bound in trees[1:]:
        out["decomposition" if isinstance(tree, tuple) else "branch and bound"] = bound
    return out


def bound_methods(bound: np.ndarray, candidates: dict[str, np.ndarray], scale: np.ndarray,
                  rtol: float = 1e-12) -> tuple[str, ...]:
    """Per joint, how a dropped set's bound was obtained.

    Parameters
    ----------
    bound : ndarray, shape (n,)
        The bound stated [N m or N].
    candidates : dict of str to ndarray, shape (n,)
        :func:`method_bounds` (or :func:`tree_method_bounds`) [N m or N].
    scale : ndarray, shape (n,)
        s_i [N m or N].
    rtol : float, optional
        A way gives the bound where its own is within ``rtol`` s_i of it.

    Returns
    -------
    tuple of str, length n
        ``"none"`` where the bound is 0, else the first of :data:`BOUND_METHODS` (the
        simplest) whose bound gives it; ``""`` where none does.
    """
    bound = np.asarray(bound, float)
    reach = bound + rtol * np.abs(np.asarray(scale, float))
    return tuple("none" if bound[j] == 0 else next(
        (m for m in BOUND_METHODS[1:] if m in candidates and candidates[m][j] <= reach[j]), "")
        for j in range(bound.size))


def unproved_way(how: Sequence[str], bound: np.ndarray, found: dict[str, np.ndarray],
                 limit: np.ndarray) -> int | None:
    """The first joint whose stated way of bounding does not give its stated bound.

    Parameters
    ----------
    how : sequence of str, length n
        Per joint, a name of :data:`BOUND_METHODS` (as :func:`bound_methods` gave it).
    bound : ndarray, shape (n,)
        The bound stated [N m or N].
    found : dict of str to ndarray, shape (n,)
        Each way's bound derived again (:func:`method_bounds`, :func:`tree_method_bounds`)
        [N m or N].
    limit : ndarray, shape (n,)
        What a way's bound must be within to give the stated one [N m or N].

    Returns
    -------
    int or None
        The joint (from 0), or None where every joint's way gives it: its bound found is
        within ``limit`` (NaN never is), and the way is ``"none"`` where, and only where,
        the bound is 0.

    Examples
    --------
    >>> found = {"none": np.array([0, np.inf]), "pairs": np.array([0, 2.0])}
    >>> unproved_way(["none", "pairs"], np.array([0.0, 1.0]), found, np.array([0.0, 1.5]))
    1
    """
    for j, m in enumerate(how):
        if (m == "none") != (bound[j] == 0) or not (m in found and found[m][j] <= limit[j]):
            return j
    return None


def proved_zero(robot: Robot, base: BaseParameters, region: Region,
                dropped: np.ndarray) -> np.ndarray:
    """The dropped pairs proved identically zero over the region, from the robot alone.

    Parameters
    ----------
    robot, base, region, dropped
        As :func:`dropped_bound`: the arm (n joints), its b base parameters, the region and
        the pairs to decide (b, 3).

    Returns
    -------
    ndarray of bool, shape (b, 3)
        Dropped pairs whose part is zero at every joint by
        :func:`gd_analyze.symbolic.pruning.zero_parts`, or whose parameter's value is 0,
        or whose enclosure over the region's whole position box times |beta|
        (:func:`gd_analyze.certify.regressor_bounds.pair_magnitudes`, the parts zero by
        :func:`~gd_analyze.symbolic.pruning.zero_parts` at some joints set to 0) is 0 at
        every joint: each is 0 at every state of the region. A subset of
        :attr:`PairBounds.zero` and, on the shipped arms, all its dropped pairs.
    """
    dropped = np.asarray(dropped, bool)
    absb = np.abs(np.asarray(base.beta, float))
    out = dropped & (absb == 0)[:, None]
    used = np.flatnonzero((dropped & ~out).any(axis=1))
    if used.size == 0:
        return out
    cols = np.flatnonzero(base.independent.reshape(-1))[used]
    U = pair_magnitudes(robot, region.q_min[None, :].astype(float),
                        region.q_max[None, :].astype(float), cols, region.qd_max,
                        region.qdd_max)[0] * absb[used]                          # (3, n, k)
    nonzero = dropped[used] & ~(U == 0).all(axis=1).T
    rest = np.flatnonzero(nonzero.any(axis=1))        # decided symbolically where needed
    U[:, :, rest] = np.where(zero_parts(robot, cols[rest]).transpose(1, 2, 0), 0.0,
                             U[:, :, rest])
    out[used] = dropped[used] & (U == 0).all(axis=1).T
    return out


def tree_bound(robot: Robot, base: BaseParameters, region: Region, split_joint: np.ndarray,
               dropped: np.ndarray, zero: np.ndarray | None = None, pairs_only: bool = False
               ) -> np.ndarray:
    """The bound of a dropped set over the region on the final boxes of a given bisection
    tree, derived without search.

    Parameters
    ----------
    robot, base, region
        As :func:`dropped_bound`: the arm (n joints), its b base parameters and the region.
    split_joint : ndarray of int, shape (N,)
        Per box, level by level, the joint it is halved along at its middle, or -1 (a final
        box): checked to tile the region by :func:`tiling`.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out.
    zero : ndarray of bool, shape (b, 3), optional
        Pairs proved identically zero, left out; default :func:`proved_zero`.
    pairs_only : bool, optional
        The first of the three bounds alone (the sum of the pairs' own bounds).

    Returns
    -------
    ndarray, shape (n,)
        The largest over the final boxes of the least of three bounds of the dropped pairs'
        change of tau_i there: the sum of the pairs' own bounds (as :func:`certify`'s), their
        joint sum on the channels (as :func:`joint_sums`', where a level's channels of the
        dropped columns fit :data:`JOINT_SUM_ELEMENTS`) and their joint sum on the summed
        channels (as :func:`dropped_bound`'s) [N m or N]; each box's enclosures are
        intersected with its ancestors'. 0 where no pair but those proved zero is dropped;
        inf where the pairs are too many to hold.

    Raises
    ------
    ValueError
        If ``split_joint`` is not a bisection tree of the region's box (:func:`tiling`).

    Notes
    -----
    Each bound holds on its box and the final boxes cover the region, so |tau_s - tau| is at
    most the result at every state of the region whatever the tree. On the tree of
    :func:`certify` the result is at most :func:`leaf_bound`, on that of
    :func:`dropped_search` at most :func:`dropped_bound`: the same sums of the same
    enclosures, evaluated level by level in the same chunks.
    """
    return _tree_bounds(robot, base, region, split_joint, dropped, zero)[int(pairs_only)]


def _tree_bounds(robot, base, region, split_joint, dropped, zero):
    """:func:`tree_bound` (n,) and the same with ``pairs_only`` (n,), in one pass."""
    levels = tiling(region, np.asarray(split_joint))
    n = robot.n
    dropped = np.asarray(dropped, bool)
    free = proved_zero(robot, base, region, dropped) if zero is None else \
        np.asarray(zero, bool)
    live = dropped & ~free
    used = np.flatnonzero(live.any(axis=1))
    if used.size == 0:
        return np.zeros((2, n))
    if _held(n, _CHUNK, live, free).size < used.size:
        return np.full((2, n), np.inf)
    cols = np.flatnonzero(base.independent.reshape(-1))[used]
    held = (robot, base, region, cols, used, live, free, zero_parts(robot, cols))
    out, parent = np.zeros((2, n)), None
    for lo, hi, split in levels:
        # each column's channels kept for the sub-boxes where they fit the arrays' size
        channels = lo.shape[0] * channel_count(n) * n * used.size <= JOINT_SUM_ELEMENTS
        parts = [_tree_chunk(held, lo[a:a + _CHUNK], hi[a:a + _CHUNK], channels,
                             None if parent is None else
                             tuple(None if x is None else x[a:a + _CHUNK] for x in parent))
                 for a in range(0, lo.shape[0], _CHUNK)]
        each = np.concatenate([p[0] for p in parts], axis=1)             # (2, B, n)
        out = np.maximum(out, each[:, ~split].max(axis=1, initial=0.0))
        kept = [None if parts[0][1][e] is None else np.concatenate([p[1][e] for p in parts])
                for e in range(5)]
        parent = tuple(None if x is None else np.concatenate([x[split], x[split]])
                       for x in kept)
    return out


def summed_tree_bound(robot: Robot, base: BaseParameters, region: Region,
                      split_joint: np.ndarray, dropped: np.ndarray,
                      zero: np.ndarray | None = None) -> np.ndarray:
    """The bound of a dropped set over the region on the final boxes of a given bisection
    tree by the joint sum on the summed channels alone, as :func:`dropped_search` evaluates
    its boxes, without search.

    Parameters
    ----------
    robot, base, region, split_joint, dropped, zero
        As :func:`tree_bound`: the arm (n joints), its b base parameters, the region, the
        tree (N,) (checked to tile the region by :func:`tiling`), the pairs left out (b, 3)
        and the pairs proved identically zero (b, 3; default :func:`proved_zero`).

    Returns
    -------
    ndarray, shape (n,)
        The largest over the final boxes of the joint sum's bound there (the summed channel
        enclosures of :func:`dropped_search`, each box's intersected with its ancestors')
        [N m or N]: at least :func:`tree_bound` (one of its three bounds), and on the tree of
        :func:`dropped_search` its own bound, with a fraction of :func:`tree_bound`'s work.
        0 where no pair but those proved zero is dropped; inf where the pairs are too many
        to hold.

    Raises
    ------
    ValueError
        If ``split_joint`` is not a bisection tree of the region's box (:func:`tiling`).

    Notes
    -----
    The joint sum on a box bounds the dropped pairs' change of tau_i there (Moore, Kearfott
    & Cloud 2009, Ch. 6), and the final boxes cover the region: |tau_s - tau| is at most the
    result at every state of the region whatever the tree.
    """
    levels = tiling(region, np.asarray(split_joint))
    n = robot.n
    dropped = np.asarray(dropped, bool)
    free = proved_zero(robot, base, region, dropped) if zero is None else \
        np.asarray(zero, bool)
    live = dropped & ~free
    used = np.flatnonzero(live.any(axis=1))
    if used.size == 0:
        return np.zeros(n)
    if _held(n, _CHUNK, live, free).size < used.size:
        return np.full(n, np.inf)
    cols = np.flatnonzero(base.independent.reshape(-1))[used]
    out, parent = np.zeros(n), None
    for lo, hi, split in levels:
        s_lo, s_hi = _summed(robot, base, region, lo, hi, cols, used, live, free, parent)
        total = combined_bound(0.5 * (s_lo + s_hi), 0.5 * (s_hi - s_lo), region.qd_max,
                               region.qdd_max)
        out = np.maximum(out, total[~split].max(axis=0, initial=0.0))
        parent = tuple(np.concatenate([x[split], x[split]]) for x in (s_lo, s_hi))
    return out


def _summed_chunk(robot, lo, hi, cols, beta, weight, slack, widen):
    """The columns' channel enclosures on boxes (B, n) scaled and added per channel and joint
    (:func:`~gd_analyze.certify.ball_kernels.summed_kernel`: the terms of
    :func:`_scaled`, the sum of :meth:`JointSums.sums` with its round-off ``widen``), as
    intervals (lo, hi) (B, C, n)."""
    c_lo, c_hi = channel_enclosures(robot, lo, hi, cols)
    mid, rad = summed_kernel(c_lo, c_hi, beta, weight, slack)
    rad *= widen
    return mid - rad, mid + rad


def _tree_chunk(held, lo, hi, channels, parent):
    """:func:`tree_bound` on boxes (B, n) of one level: the least of the three bounds and the
    first alone (2, B, n), and what the sub-boxes intersect with (the pairs' bounds, the
    summed channels, and each column's channels or None), each box's intersected with its
    ``parent``'s."""
    robot, base, region, cols, used, live, free, masked = held
    c_lo, c_hi = _channels(robot, lo, hi, cols)
    U = channel_magnitudes(c_lo, c_hi, region.qd_max, region.qdd_max) * np.abs(
        np.asarray(base.beta, float)[used])
    U[:, masked.transpose(1, 2, 0)] = 0.0
    # (_joint_sums uses up the upper ends it is given: the channels are read again below and
    # are the sub-boxes' parents)
    mid, rad = _joint_sums(robot, base, region, used, live, free, c_lo, c_hi.copy()).sums(live)
    s_lo, s_hi = mid - rad, mid + rad
    if parent is not None:
        U = np.minimum(U, parent[0])
        s_lo, s_hi = _intersect(s_lo, s_hi, parent[1], parent[2])
        if channels and parent[3] is not None:
            c_lo, c_hi = _intersect(c_lo, c_hi, parent[3], parent[4])
    pairs = np.einsum("bpnk,pk->bn", U, live[used].T.astype(float))
    each = np.minimum(pairs, combined_bound(0.5 * (s_lo + s_hi), 0.5 * (s_hi - s_lo),
                                            region.qd_max, region.qdd_max))
    if not channels:
        return np.stack([each, pairs]), (U, s_lo, s_hi, None, None)
    each = np.minimum(each, _joint_sums(robot, base, region, used, live, free, c_lo,
                                        c_hi.copy()).bound(live))
    return np.stack([each, pairs]), (U, s_lo, s_hi, c_lo, c_hi)


def decomposed_tree_bound(robot: Robot, base: BaseParameters, region: Region,
                          dropped: np.ndarray, first_tree: np.ndarray, rest_tree: np.ndarray,
                          zero: np.ndarray | None = None) -> np.ndarray:
    """:func:`decomposed_bound` derived again without search, on two given bisection trees.

    Parameters
    ----------
    robot, base, region, dropped
        As :func:`dropped_bound`: the arm (n joints), its b base parameters, the region and
        the pairs left out (b, 3).
    first_tree : ndarray of int, shape (N,)
        A bisection tree (``split_joint`` of :func:`tiling`, cut at the middle) for the
        first links' pairs (:func:`decomposed_pairs` of ``dropped``), e.g. the tree of
        :func:`decomposed_search`'s branch and bound; checked to tile the region.
    rest_tree : ndarray of int, shape (M,)
        One for the other dropped pairs, e.g. the certification's; checked to tile the
        region.
    zero : ndarray of bool, shape (b, 3), optional
        Pairs proved identically zero, left out; default :func:`proved_zero`.

    Returns
    -------
    ndarray, shape (n,)
        :func:`summed_tree_bound` of the first links' pairs on ``first_tree`` (the joint
        sum the branch and bound evaluated) plus :func:`tree_bound` of the rest on
        ``rest_tree``, rounded up [N m or N]: at most :func:`decomposed_bound` where the
        trees are its own (up to round-off); inf where the set has no decomposition
        (:func:`decomposed_pairs` None).

    Raises
    ------
    ValueError
        If either tree is not a bisection tree of the region's box (:func:`tiling`).

    Notes
    -----
    Any split of the dropped pairs into two sets bounds |tau_s - tau| by the sum of the two
    sets' bounds (tau = Y_b beta is linear in the base parameters; triangle inequality), and
    each :func:`tree_bound` holds at every state of the region whatever its tree: the sum
    does. The split is derived here from ``dropped`` alone, not read.
    """
    dropped = np.asarray(dropped, bool)
    free = proved_zero(robot, base, region, dropped) if zero is None else \
        np.asarray(zero, bool)
    first = decomposed_pairs(robot, base, dropped, free)
    if first is None:
        return np.full(robot.n, np.inf)
    rest = dropped & ~free & ~first
    head = summed_tree_bound(robot, base, region, first_tree, first, free)
    other = tree_bound(robot, base, region, rest_tree, rest, free)
    return np.nextafter(head + other, np.inf)


def tilings_bound(robot: Robot, base: BaseParameters, region: Region, dropped: np.ndarray,
                  trees: Sequence[np.ndarray],
                  decomposed: Sequence[tuple[np.ndarray, np.ndarray]] = ()) -> np.ndarray:
    """The bound of a dropped set over the region on given bisection trees, without search.

    Parameters
    ----------
    robot, base, region, dropped
        As :func:`dropped_bound`: the arm (n joints), its b base parameters, the region and
        the pairs left out (b, 3).
    trees : sequence of ndarray of int, shape (N,) each
        Bisection trees (``split_joint`` of :func:`tiling`, cut at the middle), e.g. those
        of :func:`region_trees`; each is checked to tile the region.
    decomposed : sequence of (ndarray of int, ndarray of int), optional
        Pairs of such trees for the decomposition (:func:`decomposed_tree_bound`: the first
        links' pairs on the first, the rest on the second), e.g. those of
        :func:`region_trees`; each tree is checked to tile the region.

    Returns
    -------
    ndarray, shape (n,)
        Per joint, the least over the trees that tile the region of :func:`tree_bound`, and
        over the pairs whose two trees do of :func:`decomposed_tree_bound` (the pairs proved
        zero by :func:`proved_zero` left out) [N m or N]: |tau_s - tau| is at most it at
        every state of the region. 0 where no pair but those proved zero is dropped; inf
        where no tree (or pair) tiles the region.
    """
    found = tree_method_bounds(robot, base, region, dropped, trees, decomposed)
    return np.minimum(found["joint sum"], found["decomposition"])


def tree_method_bounds(robot: Robot, base: BaseParameters, region: Region, dropped: np.ndarray,
                       trees: Sequence[np.ndarray],
                       decomposed: Sequence[tuple[np.ndarray, np.ndarray]] = (),
                       methods: Mapping[str, int] | None = None) -> dict[str, np.ndarray]:
    """:func:`method_bounds` derived again on given bisection trees, without search.

    Parameters
    ----------
    robot, base, region, dropped, trees, decomposed
        As :func:`tilings_bound`.
    methods : mapping of str to int, optional
        Names of :data:`BOUND_METHODS` to derive, each with the first joint (from 0) it is
        asked for; default ``"joint sum"`` and ``"decomposition"`` from joint 0.

    Returns
    -------
    dict of str to ndarray, shape (n,)
        Per name asked, the least over the trees that tile the region (for
        ``"decomposition"``, over the pairs whose two trees do): ``"pairs"`` of
        :func:`tree_bound` with ``pairs_only``, ``"joint sum"`` of :func:`tree_bound`,
        ``"branch and bound"`` of :func:`summed_tree_bound`, ``"decomposition"`` of
        :func:`decomposed_tree_bound` (the pairs proved zero by :func:`proved_zero` left
        out), ``"none"`` 0 where no dropped pair but those acts (of a link from the joint
        on), else inf [N m or N]; each bounds |tau_s - tau| at every state of the region
        from its first joint on, where the first three leave out the pairs of the links
        before it. 0 where no pair but those proved zero is dropped; inf where no tree (or
        pair) tiles the region.

    Notes
    -----
    tau_i depends on the parameters of the links i..n alone (the Newton-Euler recursion's
    backward pass, Fu, Gonzalez & Lee 1987, Sec. 3.3), so the pairs of the links before a
    joint change no tau from it on: leaving them out bounds those joints alike, with
    fewer columns evaluated.
    """
    dropped = np.asarray(dropped, bool)
    methods = {"joint sum": 0, "decomposition": 0} if methods is None else dict(methods)
    zero = proved_zero(robot, base, region, dropped)
    link = np.flatnonzero(base.independent.reshape(-1)) // 10           # per base parameter
    last = link[(dropped & ~zero).any(axis=1)].max(initial=-1)
    out: dict[str, np.ndarray] = {m: np.full(robot.n, np.inf) for m in methods}
    if "none" in out:
        out["none"] = np.where(np.arange(robot.n) > last, 0.0, np.inf)
    if last < 0:
        return {m: np.zeros(robot.n) for m in out}
    both: dict = {}                     # per tree and first joint: the least and the pairs'

    def boxes(t, j, k):
        if (id(t), j) not in both:
            both[id(t), j] = _tree_bounds(robot, base, region, t, dropped & (
                link >= j)[:, None], zero)
        return both[id(t), j][k]
    how = {"pairs": lambda t, j: boxes(t, j, 1), "joint sum": lambda t, j: boxes(t, j, 0),
           "branch and bound": lambda t, j: summed_tree_bound(
               robot, base, region, t, dropped & (link >= j)[:, None], zero),
           "decomposition": lambda t, j: decomposed_tree_bound(robot, base, region, dropped,
                                                               t[0], t[1], zero)}
    for m, j in methods.items():
        for tree in () if m == "none" else decomposed if m == "decomposition" else trees:
            try:
                out[m] = np.minimum(out[m], how[m](tree, j))
            except ValueError:          # not a tiling of the region: it proves nothing
                continue
    return out


def _intersect(lo, hi, p_lo, p_hi, in_place=False):
    """Intervals intersected with their parents' (each holds on the sub-box); an empty
    intersection, by round-off, gives the hull. ``in_place`` writes into ``lo`` and ``hi``
    (the caller's own arrays, used up): the same values, two arrays fewer."""
    a = np.maximum(lo, p_lo, out=lo if in_place else None)
    b = np.minimum(hi, p_hi, out=hi if in_place else None)
    return np.minimum(a, b), np.maximum(a, b, out=b)


def prove_dropped(robot: Robot, base: BaseParameters, region: Region, dropped: np.ndarray,
                  limit: np.ndarray, max_boxes: int = 1024, zero: np.ndarray | None = None
                  ) -> bool:
    """Whether a set of dropped pairs changes no tau_i by more than ``limit_i`` over the region,
    proved by branch and bound on those pairs' enclosures only.

    Parameters
    ----------
    robot, base, region, dropped, max_boxes, zero
        As :func:`dropped_bound`: the arm (n joints), its b base parameters, the region, the
        pairs left out (b, 3), the boxes evaluated in all before giving up, and the pairs
        proved identically zero (left out of the joint sum).
    limit : ndarray, shape (n,)
        The bound to prove per joint [N m or N].

    Returns
    -------
    bool
        True when every box of a tiling of the region has, on every joint, the sum over the
        dropped pairs of their enclosures <= limit_i, or else (a second branch and bound,
        :func:`dropped_bound`) their joint sum (:meth:`JointSums.bound`) <= limit_i, so
        |tau_s - tau| <= limit_i at every state of the region; False when ``max_boxes`` did
        not suffice for either (nothing is then known: a full :func:`certify` decides).

    Notes
    -----
    Only the dropped parameters' columns are evaluated, so a model that drops a few parameters
    is checked at a fraction of a certification's cost; each box's enclosure of a pair is the
    least of its own and its ancestors' (each holds on it), as in :func:`certify` (Moore,
    Kearfott & Cloud 2009, Ch. 6).
    """
    limit = np.asarray(limit, float)
    return _prove_pairs(robot, base, region, dropped, limit, max_boxes) or bool(
        np.all(dropped_bound(robot, base, region, dropped, limit, max_boxes, zero) <= limit))


def _prove_pairs(robot, base, region, dropped, limit, max_boxes):
    """:func:`prove_dropped` by the sum of the pairs' own enclosures on each box (each the
    least of its own and its ancestors')."""
    n = robot.n
    dropped = np.asarray(dropped, bool)
    used = np.flatnonzero(dropped.any(axis=1))
    if used.size == 0:
        return bool(np.all(limit >= 0))
    cols = np.flatnonzero(base.independent.reshape(-1))[used]
    absb = np.abs(np.asarray(base.beta, float)[used])
    weight = dropped[used].T.astype(float)                              # (3, k)
    zero = zero_parts(robot, cols)
    lo, hi = region.q_min[None, :].copy(), region.q_max[None, :].copy()
    rel = _relevant(robot)
    inherited = np.full((1, 3, n, used.size), np.inf)
    evaluated = 0
    while True:
        U = np.minimum(_enclose(robot, lo, hi, cols, region, absb, zero), inherited)
        evaluated += lo.shape[0]
        total = np.einsum("bpnk,pk->bn", U, weight)
        open_ = ~np.all(total <= limit[None, :], axis=1)                # NaN stays open
        if not open_.any():
            return True
        if evaluated + 2 * int(open_.sum()) > max_boxes:
            return False
        above = (U[open_] * weight[None, :, None, :]) > 0                  # (B, 3, n, k)
        lo, hi = _bisect(lo[open_], hi[open_], rel, _demand(above, cols))[:2]
        inherited = np.concatenate([U[open_], U[open_]])
