"""Pruning the recursive model with a guaranteed error bound on a trajectory.

The torques are linear in the base parameters, tau = Y_b(q, qd, qdd) beta (:mod:`gd_analyze.dynamics.base_parameters`),
and every column splits into an inertial part (linear in qdd), a velocity part (Coriolis and
centrifugal, quadratic in qd) and a gravity part::

    Y_b(q, qd, qdd) = Y_b(q, 0, qdd; g = 0) + Y_b(q, qd, 0; g = 0) + Y_b(q, 0, 0; g)

The contribution of (base parameter k, part p) to tau_i along a trajectory is
Y_p[:, i, k] beta_k; dropping a set of pairs changes tau_i by at most the sum of their peak
|contributions| on the trajectory (triangle inequality). :func:`prune` drops pairs in
increasing order of their peak contribution (relative to the joint scales) while every
joint's sum of dropped peaks stays within EPS scale_i, and :func:`pruned_program` generates the
recursive program without them (:mod:`.recursive`). :func:`prune_on_peaks` makes the same
choice for many trajectories at once (a sweep), from each trajectory's peaks and scales, so that
the budget holds on every one of them; :func:`stacked_peaks` gives those peaks for trajectories
stacked in one array.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..dynamics.regressor_kernels import (
    contribution_peaks,
    part_contributions,
    stacked_contribution_peaks,
)
from ..model.kinematics import as_states
from .explicit import _snap
from .recursive import PARTS, exact_program, parts_count, parts_program
from .trigpoly import TrigPoly

if TYPE_CHECKING:                       # for the type hints only
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot
    from .codegen import Program

#: part_contributions and contribution_peaks are the compiled ones of :mod:`gd_analyze.dynamics.regressor_kernels`.
__all__ = ["part_contributions", "contribution_peaks", "stacked_peaks", "Pruning", "prune",
           "prune_on_peaks", "prune_bounds", "dropped_peaks", "pruned_program", "pruned_choice",
           "part_values", "STRATEGIES", "zero_parts",
           "CRITERIA"]


def _peaks_of(C):
    """(tau_peak (n,), peak (b, 3, n), whole_peak (b, n)) of contributions C (3, N, n, b)."""
    return (np.abs(C.sum(axis=(0, 3))).max(axis=0), np.abs(C).max(axis=1).transpose(2, 0, 1),
            np.abs(C.sum(axis=0)).max(axis=0).T)


def stacked_peaks(robot: Robot, base: BaseParameters, q: ArrayLike, qd: ArrayLike,
                  qdd: ArrayLike, lengths: Sequence[int]
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`contribution_peaks` of each of K trajectories stacked in one array.

    Short trajectories evaluated together (:func:`gd_analyze.dynamics.regressor_kernels.stacked_contribution_peaks`).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    q, qd, qdd : array_like, shape (N, n)
        The K trajectories one after the other, N = sum(lengths) [rad, rad/s, rad/s^2; m,
        m/s, m/s^2].
    lengths : sequence of int
        The set points of each trajectory, each >= 1.

    Returns
    -------
    tau_peak : ndarray, shape (K, n)
        Peak |tau_i| on each trajectory [N m or N].
    peak : ndarray, shape (K, b, 3, n)
        Peak |contribution| of each (base parameter, part) on each trajectory [N m or N].
    whole_peak : ndarray, shape (K, b, n)
        The same for each base parameter, all parts together [N m or N].

    Raises
    ------
    ValueError
        If the arrays are not (N, n) or the lengths do not add up to N.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.dynamics.base_parameters import base_parameters
    >>> robot = load_robot("two-link")
    >>> base = base_parameters(robot)
    >>> q = np.linspace(0, 1, 10)[:, None] * [1.0, -1.0]
    >>> tau, peak, whole = stacked_peaks(robot, base, q, q, q, [4, 6])
    >>> one = contribution_peaks(robot, base, q[4:], q[4:], q[4:])
    >>> all(np.allclose(x[1], y) for x, y in zip((tau, peak, whole), one))
    True
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    lengths = [int(k) for k in lengths]
    if min(lengths, default=1) < 1 or sum(lengths) != q.shape[0]:
        raise ValueError(f"the lengths {lengths[:5]}... do not split {q.shape[0]} set points")
    return stacked_contribution_peaks(robot, base, q, qd, qdd, lengths)


@dataclass(frozen=True, eq=False)
class Pruning:
    """Which (base parameter, part) pairs are dropped, and the error bound that gives.

    Attributes
    ----------
    eps : float
        The tolerance EPS (fraction of scale_i).
    dropped : ndarray of bool, shape (b, 3)
        ``dropped[m, p]``: the part p (:data:`PARTS`: inertial, velocity, gravity) of base
        parameter m is left out.
    peak : ndarray, shape (b, 3, n)
        Peak |contribution| of each pair to each joint torque on the trajectory [N m or N].
    whole_peak : ndarray, shape (b, n)
        Peak |contribution| of each base parameter (all parts together) [N m or N].
    whole : ndarray of bool, shape (b,)
        The parameters dropped as a unit (all their parts), counted by ``whole_peak``.
    bound : ndarray, shape (n,)
        Per joint, criterion "peaks": the sum of the dropped units' peaks (``whole_peak`` of
        the parameters in ``whole``, ``peak`` of the other dropped pairs); criterion "error":
        the largest |sum of the dropped contributions| on the trajectory. The pruned model's
        error on the trajectory is at most this [N m or N], and bound <= eps * scale.
    criterion : str
        ``"peaks"`` or ``"error"`` (:func:`prune`).
    scale : ndarray, shape (n,)
        max(peak |tau_i| on the trajectory, torque_floor) [N m or N].
    """

    eps: float
    dropped: np.ndarray
    peak: np.ndarray
    whole_peak: np.ndarray
    whole: np.ndarray
    bound: np.ndarray
    scale: np.ndarray
    criterion: str = "peaks"


#: Selection strategies of :func:`prune`.
STRATEGIES = ("cost", "peak")
#: How :func:`prune` bounds the error of a dropped set on the trajectory.
CRITERIA = ("peaks", "error")


def prune(robot: Robot, base: BaseParameters, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike,
          eps: float, torque_floor: float = 0.0, strategy: str = "cost",
          criterion: str = "peaks", peaks: tuple[np.ndarray, ...] | None = None) -> Pruning:
    """Choose the (base parameter, part) pairs to drop within the error budget EPS.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters.
    q, qd, qdd : array_like, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    eps : float
        Tolerance, >= 0: every joint's bound stays within eps * scale_i.
    torque_floor : float, optional
        Least scale of a joint [N m or N] (for joints whose torque is near 0 on the
        trajectory); default 0.
    strategy : {"cost", "peak"}, optional
        ``"peak"``: pairs in increasing order of their largest peak relative to the joint
        scales, max_i peak_i / scale_i, each dropped when the budget allows. ``"cost"``
        (default): first whole parameters (all their parts) in increasing order of their
        relative whole peak or in decreasing order of operations saved per budget share
        (the cheaper result of the two), then single pairs in increasing order of peak,
        each kept dropped only when it lowers the operation count of the program (single
        parts need split kinematic quantities, which may cost more than they save).
    criterion : {"peaks", "error"}, optional
        ``"peaks"`` (default): the bound of joint i is the sum of the dropped units' peaks
        (a unit is a pair, or with the "cost" strategy a whole parameter, counted by the
        peak of its whole contribution). ``"error"``: the bound is the largest |sum of the
        dropped contributions| on the trajectory itself, i.e. the pruned model's error
        there (tighter: contributions peak at different set points or cancel).
    peaks : tuple of ndarray, optional
        For criterion "peaks": :func:`contribution_peaks` of these base parameters on this
        trajectory, when the caller has computed them (e.g. while doing something else);
        computed here otherwise.

    Returns
    -------
    Pruning

    Raises
    ------
    ValueError
        If eps or torque_floor is negative or not finite, the strategy or criterion
        unknown, or the arrays not (N, n).

    Notes
    -----
    A unit is dropped only when every joint's bound stays within eps * scale_i. With
    "peaks", by the triangle inequality the pruned torque differs from the exact one on the
    trajectory by at most the bound. Pairs whose peak is 0 on the trajectory are dropped with
    their parameter when all its other parts are, and kept otherwise.
    """
    if not (np.isfinite(eps) and eps >= 0):
        raise ValueError(f"eps must be a finite number >= 0, got {eps!r}")
    if not (np.isfinite(torque_floor) and torque_floor >= 0):
        raise ValueError(f"torque_floor must be a finite number >= 0, got {torque_floor!r}")
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
    if criterion not in CRITERIA:
        raise ValueError(f"criterion must be one of {CRITERIA}, got {criterion!r}")
    if criterion == "error":             # the dropped set's own error: every contribution kept
        C = part_contributions(robot, base, q, qd, qdd)      # (3, N, n, b)
        tau_peak, peak, whole_peak = _peaks_of(C)
    else:                                # peaks only, accumulated chunk by chunk
        C = None
        tau_peak, peak, whole_peak = contribution_peaks(robot, base, q, qd, qdd) \
            if peaks is None else peaks
    scale = np.maximum(tau_peak, torque_floor)
    sel = _Selection(robot, base, C, peak, whole_peak, eps * scale, criterion)
    dropped, whole = sel.by_peak() if strategy == "peak" else sel.by_cost()
    return Pruning(eps=float(eps), dropped=_normalize(dropped, sel.live), peak=peak,
                   whole_peak=whole_peak, whole=whole, bound=sel.bound(dropped, whole),
                   scale=scale, criterion=criterion)


def prune_on_peaks(robot: Robot, base: BaseParameters, scale: ArrayLike, peak: ArrayLike,
                   whole_peak: ArrayLike, eps: float, strategy: str = "cost") -> Pruning:
    """Choose the pairs to drop within EPS on each of K trajectories at once (a sweep).

    Each pair's peak on trajectory t is divided by that trajectory's scale_{t,i}, and the
    largest ratio over the trajectories is what the budget weighs (scale 1, budget EPS): for
    every t and joint i the dropped pairs' peaks on t sum to at most
    scale_{t,i} x sum of their largest ratios <= EPS x scale_{t,i}.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    scale : array_like, shape (K, n)
        scale_{t,i} = max(peak |tau_i| on t, torque floor) [N m or N].
    peak : array_like, shape (K, b, 3, n)
        A bound on |contribution| of each (base parameter, part) to each joint torque on
        each trajectory [N m or N]: its peak there (:func:`stacked_peaks`), or any larger
        bound, e.g. one proved on a region of states, which the guarantee then carries over.
    whole_peak : array_like, shape (K, b, n)
        The same for each base parameter, all parts together [N m or N].
    eps : float
        EPS >= 0.
    strategy : {"cost", "peak"}, optional
        As :func:`prune`.

    Returns
    -------
    Pruning
        In units of the scales: ``peak`` (b, 3, n) and ``whole_peak`` (b, n) are the largest
        ratios over the trajectories [1], ``scale`` is ones, ``bound`` (n,) the sum of the
        dropped units' ratios (<= eps); criterion "peaks". The bound on each trajectory in
        N m is :func:`dropped_peaks` of the given peaks, summed over the parts.

    Raises
    ------
    ValueError
        If eps is negative or not finite, the strategy unknown, a scale negative or NaN, or
        the shapes disagree.

    Notes
    -----
    A ratio with scale 0 and a positive peak is infinite: that unit is never dropped. Source:
    the budget of :mod:`gd_analyze.simplify.budget` over several trajectories, applied
    to the base-parameter contributions of the recursive model (Khalil & Kleinfinger 1987;
    Gautier 1990).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> from gd_analyze.dynamics.base_parameters import base_parameters, random_states
    >>> arm = load_robot("puma560")
    >>> b = base_parameters(arm)
    >>> tau, peak, whole = stacked_peaks(arm, b, *random_states(arm, 20, 1), [5, 15])
    >>> pr = prune_on_peaks(arm, b, tau, peak, whole, 0.05)
    >>> each = dropped_peaks(peak, whole, pr.dropped, pr.whole).sum(axis=-2)   # (2, n)
    >>> bool(pr.dropped.any() and np.all(each <= 0.05 * tau))
    True
    """
    if not (np.isfinite(eps) and eps >= 0):
        raise ValueError(f"eps must be a finite number >= 0, got {eps!r}")
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
    scale, peak = np.asarray(scale, float), np.asarray(peak, float)
    whole_peak = np.asarray(whole_peak, float)
    K, n, b = scale.shape[0] if scale.ndim == 2 else -1, robot.n, base.rank
    if (scale.shape != (K, n) or peak.shape != (K, b, len(PARTS), n)
            or whole_peak.shape != (K, b, n)):
        raise ValueError(f"expected scale (K, {n}), peak (K, {b}, 3, {n}) and whole_peak "
                         f"(K, {b}, {n}), got {scale.shape}, {peak.shape}, {whole_peak.shape}")
    if not np.all(scale >= 0):
        raise ValueError("every scale must be >= 0")
    with np.errstate(divide="ignore", invalid="ignore"):
        def ratio(x, s):
            r = np.where(x > 0, x / np.where(s > 0, s, 0.0), 0.0)
            return np.where(np.isnan(r), np.inf, r).max(axis=0, initial=0.0)

        rel = ratio(peak, scale[:, None, None, :])
        rel_whole = ratio(whole_peak, scale[:, None, :])
    sel = _Selection(robot, base, None, rel, rel_whole, np.full(n, float(eps)), "peaks")
    dropped, whole = sel.by_peak() if strategy == "peak" else sel.by_cost()
    return Pruning(eps=float(eps), dropped=_normalize(dropped, sel.live), peak=rel,
                   whole_peak=rel_whole, whole=whole, bound=sel.bound(dropped, whole),
                   scale=np.ones(n), criterion="peaks")


def dropped_peaks(peak: ArrayLike, whole_peak: ArrayLike, dropped: ArrayLike,
                  whole: ArrayLike) -> np.ndarray:
    """The bound of a dropped set, split by part: the dropped units' peaks per joint.

    Parameters
    ----------
    peak : array_like, shape (..., b, 3, n)
        Peak |contribution| of each (base parameter, part) [N m or N], on one trajectory or
        on each of several (leading dimensions).
    whole_peak : array_like, shape (..., b, n)
        The same for each base parameter, all parts together.
    dropped : array_like of bool, shape (b, 3)
        The pairs left out.
    whole : array_like of bool, shape (b,)
        The parameters dropped as a unit, counted by ``whole_peak``.

    Returns
    -------
    ndarray, shape (..., 4, n)
        The dropped single pairs' peaks summed per part (inertial, velocity, gravity), then the
        parameters dropped whole; summed over this axis, the bound (triangle inequality).

    Examples
    --------
    >>> peak = np.ones((2, 3, 1))
    >>> dropped_peaks(peak, np.full((2, 1), 2.0), np.array([[1, 0, 1], [1, 1, 1]], bool),
    ...               np.array([False, True]))[:, 0].tolist()
    [1.0, 0.0, 1.0, 2.0]
    """
    peak, whole_peak = np.asarray(peak, float), np.asarray(whole_peak, float)
    whole = np.asarray(whole, bool)
    single = np.asarray(dropped, bool) & ~whole[:, None]
    parts = np.where(single[:, :, None], peak, 0.0).sum(axis=-3)            # (..., 3, n)
    wholes = np.where(whole[:, None], whole_peak, 0.0).sum(axis=-2)         # (..., n)
    return np.concatenate([parts, wholes[..., None, :]], axis=-2)


class _Selection:
    """The state of a selection: contributions, peaks, budget and the bound of a set."""

    def __init__(self, robot, base, C, peak, whole_peak, budget, criterion, free=None,
                 joint=None):
        self.robot, self.base = robot, base
        self.joint = joint       # (dropped, enough) -> (n,) with .quick, or None
        self.free = None if free is None else np.asarray(free, bool)   # (b, 3): proved 0
        # (b, 3, N, n), C-ordered: a set's sums gather its pairs' rows
        self.C = None if C is None else np.ascontiguousarray(C.transpose(3, 0, 1, 2))
        self.peak, self.whole_peak, self.budget = peak, whole_peak, budget
        self.criterion = criterion
        safe = np.where(budget > 0, budget, 1.0)
        self.rel = np.where(budget > 0, peak / safe, np.where(peak > 0, np.inf, 0.0))
        self.use = np.where(budget > 0, whole_peak / safe,
                            np.where(whole_peak > 0, np.inf, 0.0)).max(axis=1)
        self.live = self.rel.max(axis=2) > 0                   # (b, 3): contributes

    def _sums(self, dropped):
        """(n,): the pieces' sums, the largest |sum of the dropped pairs' contributions|
        over the set points."""
        return np.abs(self.C[np.asarray(dropped, bool)].sum(axis=0)).max(axis=0)

    def bound(self, dropped, whole, enough=None):
        """(n,): the bound of a dropped set (whole: parameters dropped as a unit); with
        ``enough`` (n,), the pieces' sums alone when they are within it."""
        if self.criterion == "error":
            if not dropped.any():
                return np.zeros(self.budget.shape)
            err = self._sums(dropped)
            if self.joint is not None and not (enough is not None and np.all(err <= enough)):
                err = np.minimum(err, self.joint(dropped, enough))
            return err
        return dropped_peaks(self.peak, self.whole_peak, dropped, whole).sum(axis=-2)

    def fits(self, dropped, whole):
        return bool(np.all(self.bound(dropped, whole, self.budget) <= self.budget))

    def quick_fits(self, dropped, whole):
        """:meth:`fits` where cheap bounds decide it, else None (only the whole bound can):
        the pieces' sums, then the joint bound's ``quick`` answer where it has one."""
        quick = getattr(self.joint, "quick", None)
        if self.criterion != "error" or quick is None or not dropped.any():
            return self.fits(dropped, whole)
        err = self._sums(dropped)
        if np.all(err <= self.budget):
            return True
        first = quick(dropped, self.budget)
        return None if first is None else bool(np.all(np.minimum(err, first) <= self.budget))

    def count(self, dropped):
        return _count(self.robot, self.base, _normalize(dropped, self.live, self.free))

    def by_peak(self):
        dropped = np.zeros(self.live.shape, bool)
        whole = np.zeros(self.live.shape[0], bool)
        for flat in np.argsort(self.rel.max(axis=2), axis=None, kind="stable"):
            m, p = np.unravel_index(flat, self.live.shape)
            if self.live[m, p]:
                dropped[m, p] = True
                if not self.fits(dropped, whole):
                    dropped[m, p] = False
        return dropped, whole

    def _savings(self, none):
        """(b,): the quick count saved by dropping each parameter's live pairs alone (0 where
        its whole bound alone is over the budget)."""
        live, b = self.live, self.live.shape[0]
        full = self.count(none)
        saving = np.zeros(b)
        for m in range(b):
            if live[m].any() and np.isfinite(self.use[m]) and self.use[m] <= 1.0:
                one = none.copy()
                one[m] = live[m]
                saving[m] = full - self.count(one)
        return saving

    def by_cost(self, stop_at=None):
        """The greedy search (two starting orders); with ``stop_at``, the first set found
        whose quick count is at most it."""
        live, b = self.live, self.live.shape[0]
        none = np.zeros(live.shape, bool)
        best = None
        for start in ("use", "saving"):
            order = np.argsort(self.use, kind="stable") if start == "use" else np.argsort(
                -self._savings(none) / np.maximum(self.use, 1e-300), kind="stable")
            dropped, whole = none.copy(), np.zeros(b, bool)
            for m in order:
                if live[m].any():
                    trial, twhole = dropped.copy(), whole.copy()
                    trial[m], twhole[m] = live[m], True
                    if self.fits(trial, twhole):
                        dropped, whole = trial, twhole
            cost = self.count(dropped)
            if stop_at is not None and cost <= stop_at:
                return dropped, whole
            for flat in np.argsort(self.rel.max(axis=2), axis=None, kind="stable"):
                m, p = np.unravel_index(flat, live.shape)
                if not live[m, p] or dropped[m, p]:
                    continue
                trial = dropped.copy()
                trial[m, p] = True
                fits = self.quick_fits(trial, whole)   # None: only the whole bound decides
                if fits is False:
                    continue
                c = self.count(trial)
                if c < cost and (fits or self.fits(trial, whole)):
                    cost, dropped = c, trial
                    if stop_at is not None and cost <= stop_at:
                        return dropped, whole
            if best is None or cost < best[0]:
                best = (cost, dropped, whole)
        return best[1:]


def _normalize(dropped, live, free=None):
    """Zero-peak pairs dropped with their parameter when all its live parts are, else kept;
    the pairs ``free`` (proved identically zero) always dropped."""
    gone = np.all(dropped | ~live, axis=1) & dropped.any(axis=1)
    out = np.where(live, dropped, gone[:, None])
    return out if free is None else out | free


def part_values(base: BaseParameters, dropped: np.ndarray) -> np.ndarray:
    """Per part, the base parameters' values without the dropped ones.

    Parameters
    ----------
    base : BaseParameters
        The b base parameters.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out.

    Returns
    -------
    ndarray, shape (3, n, 10)
        Per part (inertial, velocity, gravity), per link, beta in the independent slots of the
        kept pairs, 0 elsewhere [kg m^2, kg m, kg].
    """
    values = np.zeros((len(PARTS),) + base.standard.shape)
    for p in range(len(PARTS)):
        flat = np.zeros(base.standard.size)
        flat[base.independent.reshape(-1)] = np.where(dropped[:, p], 0.0, base.beta)
        values[p] = flat.reshape(base.standard.shape)
    return values


def _count(robot, base, dropped):
    """Multiplications + additions of the pruned program (quick: no cse, one form)."""
    return parts_count(robot, part_values(base, dropped))


def pruned_program(robot: Robot, base: BaseParameters, dropped: np.ndarray, cse: bool = True,
                   exact: Program | None = None) -> Program:
    """The recursive program without the dropped (base parameter, part) pairs.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out (:attr:`Pruning.dropped`).
    cse : bool, optional
        Run symengine's common-subexpression elimination (default True).
    exact : Program, optional
        The exact program (:func:`.recursive.exact_program` of ``base.values`` with the same
        ``cse``) when the caller has built it already; built here otherwise.

    Returns
    -------
    gd_analyze.symbolic.codegen.Program
        The pruned program, or the exact one (:func:`.recursive.exact_program`) when the
        pruned one would count more operations (multiplications + additions).

    Notes
    -----
    Per link, parameters whose kept parts differ are grouped, each group's wrench formed
    from the kinematic quantities of its kept parts (inertial and gravity parts by their own
    recursions, the others as the whole minus those; :mod:`.recursive`).
    """
    return pruned_choice(robot, base, dropped, cse, exact)[0]


def pruned_choice(robot: Robot, base: BaseParameters, dropped: np.ndarray, cse: bool = True,
                  exact: Program | None = None, forms: Sequence[str] | None = None
                  ) -> tuple[Program, np.ndarray]:
    """:func:`pruned_program` and the pairs its program actually leaves out.

    Parameters
    ----------
    robot, base, dropped, cse, exact
        As :func:`pruned_program`.
    forms : sequence of str, optional
        The pruned program's forms of the links' inertial moments
        (:attr:`~gd_analyze.symbolic.codegen.Program.forms` of an earlier build): built
        with these, without the search.

    Returns
    -------
    program : gd_analyze.symbolic.codegen.Program
        :func:`pruned_program`'s.
    left_out : ndarray of bool, shape (b, 3)
        ``dropped``, or all False where the exact program was the cheaper one.

    Raises
    ------
    ValueError
        If ``dropped`` is not of shape (b, 3).
    """
    dropped = np.asarray(dropped, bool)
    if dropped.shape != (base.rank, len(PARTS)):
        raise ValueError(f"dropped must have shape ({base.rank}, 3), got {dropped.shape}")
    if exact is None:
        exact = exact_program(robot, base.values, cse=cse)
    if not dropped.any():
        return exact, dropped
    pruned = parts_program(robot, part_values(base, dropped), cse=cse, forms=forms)
    if _total(pruned) <= _total(exact):
        return pruned, dropped
    return exact, np.zeros_like(dropped)


def settle_restored(robot: Robot, base: BaseParameters, before: np.ndarray, dropped: np.ndarray,
                    exact: Program | None = None) -> np.ndarray:
    """The pairs to drop once some parameters' inertial parts are restored: none dearer.

    Restoring a parameter's inertial part, and keeping its other parts dropped, can make the
    program cost more than keeping the whole parameter, or more than the exact program. The
    pairs returned are a subset of ``dropped`` (so the bound of ``dropped`` still bounds them)
    whose program costs no more than that of ``dropped``.

    Parameters
    ----------
    robot : Robot
    base : BaseParameters
        Its base parameters (b of them).
    before : array_like of bool, shape (b, 3)
        The pairs dropped before the restore.
    dropped : array_like of bool, shape (b, 3)
        The pairs dropped after it (a subset of ``before``).
    exact : Program, optional
        The exact recursive program, when built already.

    Returns
    -------
    ndarray of bool, shape (b, 3)
        ``dropped`` with the restored parameters' other parts kept too where that costs no
        more; all False where the exact program costs no more than the pruned one.

    Raises
    ------
    ValueError
        If the shapes are not (b, 3).
    """
    before, dropped = np.asarray(before, bool), np.array(dropped, bool)
    if before.shape != dropped.shape:
        raise ValueError(f"before and dropped differ in shape: {before.shape}, {dropped.shape}")
    if exact is None:
        exact = exact_program(robot, base.values)
    restored = before[:, 0] & ~dropped[:, 0]
    program, left = pruned_choice(robot, base, dropped, exact=exact)
    if not left.any():
        return left
    if restored.any():
        whole = dropped.copy()
        whole[restored] = False
        other, other_left = pruned_choice(robot, base, whole, exact=exact)
        if _total(other) <= _total(program):
            return other_left
    return left


def _total(program):
    c = program.cost()
    return c["multiplications"] + c["additions"]


def prune_bounds(robot: Robot, base: BaseParameters, scale: np.ndarray, peak: np.ndarray,
                 whole_peak: np.ndarray, eps: float, strategy: str = "cost",
                 pieces: np.ndarray | None = None,
                 chosen: tuple[np.ndarray, np.ndarray] | None = None,
                 zero: np.ndarray | None = None, joint: Callable[..., Any] | None = None,
                 stop_at: int | None = None) -> Pruning:
    """Choose the pairs to drop from given upper bounds of their contributions.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (b of them).
    scale : ndarray, shape (n,)
        s_i [N m or N].
    peak : ndarray, shape (b, 3, n)
        Upper bound of each pair's |contribution| to each tau_i where the model must hold
        (e.g. proved over the joint-limit region by
        :func:`gd_analyze.certify.certify.certify`) [N m or N].
    whole_peak : ndarray, shape (b, n)
        Upper bound of each parameter's whole |contribution|.
    eps : float
        Tolerance >= 0.
    strategy : {"cost", "peak"}, optional
        As :func:`prune`.
    pieces : ndarray, shape (b, 3, L, n), optional
        Bounds of each pair on L pieces that cover where the model must hold (the boxes of
        a branch and bound): a dropped set's bound is then the largest over the pieces of
        the sum of its pairs' bounds there (criterion "error"), never above the sum of their
        overall bounds.
    chosen : (ndarray of bool, ndarray of bool), optional
        The dropped pairs, shape (b, 3), and the parameters dropped whole, shape (b,), of an
        earlier search with the same inputs (the derivation cache): taken as they are, without
        the search, if their bound (the one the model states, without the quick rejections
        of a search's candidates) is within the budget.
    zero : ndarray of bool, shape (b, 3), optional
        Pairs proved identically zero where the model must hold
        (:attr:`gd_analyze.certify.certify.PairBounds.zero`): dropped at no cost to
        the bound (their pieces must be 0).
    joint : callable, optional
        With ``pieces``: ``joint(dropped, enough)`` -> ndarray (n,), an upper bound of |the
        sum of the dropped pairs' contributions| per joint where the model must hold (e.g.
        by :func:`gd_analyze.certify.certify.dropped_bound`, which lets them cancel);
        ``enough`` (n,) is the budget when only whether the set fits matters (the callable
        may then return a cheaper bound that decides it), None for the set's bound itself.
        A set's bound is the least of it and the pieces' (taken only where the pieces'
        alone do not fit the budget). Its optional method ``quick(dropped, enough)`` returns
        the bound the call would return with ``enough`` when that is cheap to find, else
        None: the search then asks it before counting a candidate's operations.
    stop_at : int, optional
        Strategy "cost": end the search at the first set found whose quick count
        (multiplications + additions of the pruned program without common-subexpression
        elimination, product forms) is at most this, instead of searching on for the least
        (for a question that needs only whether such a set exists).

    Returns
    -------
    Pruning
        Every joint's bound is within eps scale_i, so by the triangle inequality |tau_s -
        tau| <= bound_i wherever the bounds hold.

    Raises
    ------
    ValueError
        If eps is negative or not finite, or the strategy unknown.
    """
    if not (np.isfinite(eps) and eps >= 0):
        raise ValueError(f"eps must be a finite number >= 0, got {eps!r}")
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
    scale = np.asarray(scale, float)
    criterion = "peaks" if pieces is None else "error"
    C = None if pieces is None else np.asarray(pieces, float).transpose(1, 2, 3, 0)
    free = None if zero is None else np.asarray(zero, bool)
    if free is not None and pieces is not None and np.any(np.asarray(pieces, float)[free] != 0):
        raise ValueError("a pair declared zero has a nonzero piece")
    sel = _Selection(robot, base, C, peak, whole_peak, eps * scale, criterion, free,
                     None if pieces is None else joint)
    if chosen is not None:
        dropped, whole = (np.asarray(a) for a in chosen)
        if dropped.shape != sel.live.shape or whole.shape != sel.live.shape[:1] \
                or dropped.dtype != bool or whole.dtype != bool \
                or not np.all(sel.bound(dropped, whole) <= sel.budget):
            raise ValueError("chosen pairs of another shape, or over the budget")
    else:
        dropped, whole = sel.by_peak() if strategy == "peak" else sel.by_cost(stop_at)
    dropped = _normalize(dropped, sel.live, free)
    return Pruning(eps=float(eps), dropped=dropped, peak=peak, whole_peak=whole_peak,
                   whole=whole, bound=sel.bound(dropped, whole), scale=scale,
                   criterion=criterion)


#: The symmetric unit matrices of the six inertia parameters XX, XY, XZ, YY, YZ, ZZ.
_INERTIA_PAIRS = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
#: Links decided by :func:`zero_parts`: those with at most this many joints up to them (the
#: trigonometric polynomials grow with the joints; later links are never declared zero).
ZERO_JOINTS = 7


def zero_parts(robot: Robot, columns: np.ndarray) -> np.ndarray:
    """The parts of regressor columns that are identically zero at a joint, decided
    symbolically.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    columns : array_like of int, shape (m,)
        Flat standard-parameter indices 10 k + c (link k, parameter c).

    Returns
    -------
    ndarray of bool, shape (m, 3, n)
        ``[m, p, i]`` True where part p (0 inertial, 1 velocity) of column m is identically
        zero at joint i, for the inertia parameters (c < 6: XX .. ZZ); False for every other
        column and for the gravity part (first moments and masses are not decided here:
        never declared zero), and for links beyond :data:`ZERO_JOINTS` joints.

    Notes
    -----
    Column m of the regressor is the torque of a link whose only parameter is m, so it is
    D_m(q) qdd + h_m(q, qd) + c_m(q) with h_m given by the Christoffel symbols of D_m (Fu,
    Gonzalez & Lee 1987, Eqs. (3.4-25), (3.4-27)): h_m,i = sum_{j <= l} C_ijl qd_j qd_l with
    C_ijl = dD_ij/dq_l + dD_il/dq_j - dD_jl/dq_i (j < l), C_ijj = dD_ij/dq_j - dD_jj/dq_i / 2.
    For the inertia parameter (a, b) of link k, D_m(i, j) = u_ki^T E_ab u_kj, with u_ki the
    axis of joint i in body frame k (zero for a prismatic joint) and E_ab the symmetric unit
    matrix. Each entry is a trigonometric polynomial (:class:`.trigpoly.TrigPoly`, in
    canonical form) in the placements of the explicit model (:func:`.explicit.derive`:
    rotation entries within 1e-12 of 0 or +-1 taken as those); a part is declared zero only
    where every coefficient cancels exactly (a polynomial with no rows). A column's decision
    depends on the arm's rotations and joint kinds and on that column alone, so each is made
    once per process, whichever columns it is asked with.
    """
    columns = np.asarray(columns, int).reshape(-1)
    key = (np.asarray(robot.rotation, float).tobytes(),
           np.asarray(robot.prismatic, bool).tobytes())
    if key not in _ZERO_MEMO:           # the decisions depend on these alone
        if len(_ZERO_MEMO) >= 16:
            _ZERO_MEMO.pop(next(iter(_ZERO_MEMO)))
        _ZERO_MEMO[key] = {}
    rows = _ZERO_MEMO[key]
    missing = sorted({int(c) for c in columns} - rows.keys())
    if missing:
        rows.update(zip(missing, _zero_parts(robot, np.asarray(missing, int))))
    out = np.zeros((columns.size, 3, robot.n), bool)
    for m, col in enumerate(columns):
        out[m] = rows[int(col)]
    return out


#: zero_parts's decisions in this process: by rotations and joint kinds, then by column, its
#: (3, n) row.
_ZERO_MEMO: dict = {}


def _zero_parts(robot, columns):
    """:func:`zero_parts` itself."""
    n = robot.n
    lin = np.asarray(robot.prismatic, bool).copy()
    P = np.vectorize(_snap)(np.asarray(robot.rotation, float))
    zero = TrigPoly.zero(n, lin)
    ez = [zero, zero, TrigPoly.const(n, 1.0, lin)]
    u = {}                               # u[(k, i)]: axis of joint i in body frame k
    top = min(int(columns.max()) // 10 + 1 if columns.size else 0, ZERO_JOINTS)
    for k in range(top):
        if lin[k]:
            rz = np.eye(3).tolist()
        else:
            c, s = TrigPoly.cos(n, k, lin), TrigPoly.sin(n, k, lin)
            rz = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        for i in range(k + 1):           # R_k^T v = Rz(q_k)^T P_k^T v
            if lin[i]:
                continue
            v = ez if i == k else u[(k - 1, i)]
            if i < k:
                w = [sum((float(P[k][b][a]) * v[b] for b in range(3) if P[k][b][a] != 0), zero)
                     for a in range(3)]
                v = [sum((rz[b][a] * w[b] for b in range(3)
                          if not (isinstance(rz[b][a], float) and rz[b][a] == 0.0)), zero)
                     for a in range(3)]
            u[(k, i)] = v
    out = np.zeros((columns.size, 3, n), bool)
    for m, col in enumerate(columns):
        k, c = divmod(int(col), 10)
        if c >= 6 or k >= top:
            continue
        a, b = _INERTIA_PAIRS[c]
        D = {}
        for x in range(k + 1):
            for y in range(x, k + 1):
                if (k, x) not in u or (k, y) not in u:
                    e = zero
                else:
                    e = u[(k, x)][a] * u[(k, y)][b]
                    if a != b:
                        e = e + u[(k, x)][b] * u[(k, y)][a]
                D[(x, y)] = D[(y, x)] = e
        out[m, :2, k + 1:] = True        # link k moves no joint after k
        dD = {}

        def d(x, y, v, D=D, dD=dD):      # dD_xy / dq_v, each derivative taken once
            key = (min(x, y), max(x, y), v)
            if key not in dD:
                dD[key] = D[(x, y)].diff(v)
            return dD[key]
        constant = all(not np.any(D[(x, y)].K != 0) for x in range(k + 1) for y in range(x, k + 1))
        for i in range(k + 1):
            out[m, 0, i] = all(len(D[(i, j)]) == 0 for j in range(k + 1))
            velocity = constant
            for j in range(k + 1 if not constant else 0):
                for l in range(j, k + 1):
                    g = d(i, j, l) - 0.5 * d(j, l, i)
                    if l != j:
                        g = g + d(i, l, j) - 0.5 * d(l, j, i)
                    if len(g):
                        break
                else:
                    continue
                break
            else:
                velocity = True
            out[m, 1, i] = velocity
    return out
