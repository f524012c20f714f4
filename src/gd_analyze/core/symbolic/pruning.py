"""Pruning the recursive model with a guaranteed error bound on a trajectory.

The torques are linear in the base parameters, tau = Y_b(q, qd, qdd) beta (:mod:`.base_parameters`),
and every column splits into an inertial part (linear in qdd), a velocity part (Coriolis and
centrifugal, quadratic in qd) and a gravity part::

    Y_b(q, qd, qdd) = Y_b(q, 0, qdd; g = 0) + Y_b(q, qd, 0; g = 0) + Y_b(q, 0, 0; g)

The contribution of (base parameter k, part p) to tau_i along a trajectory is
Y_p[:, i, k] beta_k; dropping a set of pairs changes tau_i by at most the sum of their peak
|contributions| on the trajectory (triangle inequality). :func:`prune` drops pairs in
increasing order of their peak contribution (relative to the joint scales) while every
joint's sum of dropped peaks stays within EPS scale_i, and :func:`pruned_program` generates the
recursive program without them (:mod:`.recursive`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.kinematics import as_states
from .base_parameters import regressor
from .recursive import PARTS, exact_program, parts_program

__all__ = ["part_contributions", "contribution_peaks", "Pruning", "prune", "pruned_program",
           "STRATEGIES", "CRITERIA", "PEAK_CHUNK", "prune_bounds"]


def part_contributions(robot, base, q, qd, qdd):
    """Contribution of every (part, base parameter) to every joint torque along a trajectory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters (:func:`.base_parameters.base_parameters`).
    q, qd, qdd : array_like, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2].

    Returns
    -------
    ndarray, shape (3, N, n, b)
        ``C[p, k, i, m]`` = Y_p[k, i, m] beta_m [N m or N] for the parts p of :data:`PARTS`
        (inertial ``a``: Y_b(q, 0, qdd) with g = 0; velocity ``v``: Y_b(q, qd, 0) with g = 0;
        gravity ``g``: Y_b(q, 0, 0)); summed over p and m it is tau.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n).
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    zero = np.zeros_like(q)
    B = base.independent.reshape(-1)
    out = []
    for a, b, c, g in ((q, zero, qdd, np.zeros(3)), (q, qd, zero, np.zeros(3)),
                       (q, zero, zero, None)):
        out.append(regressor(robot, a, b, c, gravity=g)[:, :, B] * base.beta)
    return np.stack(out)


#: Set points per chunk of :func:`contribution_peaks` (about 3 x 8 MB of regressor for 7 joints).
PEAK_CHUNK = 2048


def contribution_peaks(robot, base, q, qd, qdd, chunk=PEAK_CHUNK):
    """Peaks of the joint torques and of every contribution along a trajectory, in chunks.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters.
    q, qd, qdd : array_like, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    chunk : int, optional
        Set points at once: memory stays O(chunk n^2) whatever N is.

    Returns
    -------
    tau_peak : ndarray, shape (n,)
        Peak |tau_i| [N m or N].
    peak : ndarray, shape (b, 3, n)
        Peak |contribution| of each (base parameter, part) to each joint torque.
    whole_peak : ndarray, shape (b, n)
        Peak |contribution| of each base parameter, all parts together.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n).
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    n, b = robot.n, base.rank
    tau_peak, peak, whole_peak = np.zeros(n), np.zeros((b, len(PARTS), n)), np.zeros((b, n))
    for a in range(0, q.shape[0], max(1, int(chunk))):
        sl = slice(a, a + max(1, int(chunk)))
        t, p, w = _peaks_of(part_contributions(robot, base, q[sl], qd[sl], qdd[sl]))
        np.maximum(tau_peak, t, out=tau_peak)
        np.maximum(peak, p, out=peak)
        np.maximum(whole_peak, w, out=whole_peak)
    return tau_peak, peak, whole_peak


def _peaks_of(C):
    """(tau_peak (n,), peak (b, 3, n), whole_peak (b, n)) of contributions C (3, N, n, b)."""
    return (np.abs(C.sum(axis=(0, 3))).max(axis=0), np.abs(C).max(axis=1).transpose(2, 0, 1),
            np.abs(C.sum(axis=0)).max(axis=0).T)


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


def prune(robot, base, q, qd, qdd, eps, torque_floor=0.0, strategy="cost",
          criterion="peaks"):
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
        tau_peak, peak, whole_peak = contribution_peaks(robot, base, q, qd, qdd)
    scale = np.maximum(tau_peak, torque_floor)
    sel = _Selection(robot, base, C, peak, whole_peak, eps * scale, criterion)
    if strategy == "peak":
        dropped, whole = sel.by_peak()
    else:
        dropped, whole = sel.by_cost()
    return Pruning(eps=float(eps), dropped=_normalize(dropped, sel.live), peak=peak,
                   whole_peak=whole_peak, whole=whole, bound=sel.bound(dropped, whole),
                   scale=scale, criterion=criterion)


class _Selection:
    """The state of a selection: contributions, peaks, budget and the bound of a set."""

    def __init__(self, robot, base, C, peak, whole_peak, budget, criterion):
        self.robot, self.base = robot, base
        self.C = None if C is None else C.transpose(3, 0, 1, 2)       # (b, 3, N, n)
        self.peak, self.whole_peak, self.budget = peak, whole_peak, budget
        self.criterion = criterion
        safe = np.where(budget > 0, budget, 1.0)
        self.rel = np.where(budget > 0, peak / safe, np.where(peak > 0, np.inf, 0.0))
        self.use = np.where(budget > 0, whole_peak / safe,
                            np.where(whole_peak > 0, np.inf, 0.0)).max(axis=1)
        self.live = self.rel.max(axis=2) > 0                   # (b, 3): contributes

    def bound(self, dropped, whole):
        """(n,): the bound of a dropped set (whole: parameters dropped as a unit)."""
        if self.criterion == "error":
            if not dropped.any():
                return np.zeros(self.budget.shape)
            err = np.einsum("bpkn,bp->kn", self.C, dropped.astype(float))
            return np.abs(err).max(axis=0)
        single = dropped & ~whole[:, None]
        return ((self.peak * single[:, :, None]).sum(axis=(0, 1))
                + self.whole_peak[whole].sum(axis=0))

    def fits(self, dropped, whole):
        return bool(np.all(self.bound(dropped, whole) <= self.budget))

    def count(self, dropped):
        return _count(self.robot, self.base, _normalize(dropped, self.live))

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

    def by_cost(self):
        live, b = self.live, self.live.shape[0]
        none = np.zeros(live.shape, bool)
        full = self.count(none)
        saving = np.zeros(b)
        for m in range(b):
            if live[m].any() and np.isfinite(self.use[m]) and self.use[m] <= 1.0:
                one = none.copy()
                one[m] = live[m]
                saving[m] = full - self.count(one)
        best = None
        for order in (np.argsort(self.use, kind="stable"),
                      np.argsort(-saving / np.maximum(self.use, 1e-300), kind="stable")):
            dropped, whole = none.copy(), np.zeros(b, bool)
            for m in order:
                if live[m].any():
                    trial, twhole = dropped.copy(), whole.copy()
                    trial[m], twhole[m] = live[m], True
                    if self.fits(trial, twhole):
                        dropped, whole = trial, twhole
            cost = self.count(dropped)
            for flat in np.argsort(self.rel.max(axis=2), axis=None, kind="stable"):
                m, p = np.unravel_index(flat, live.shape)
                if not live[m, p] or dropped[m, p]:
                    continue
                trial = dropped.copy()
                trial[m, p] = True
                if self.fits(trial, whole):
                    c = self.count(trial)
                    if c < cost:
                        cost, dropped = c, trial
            if best is None or cost < best[0]:
                best = (cost, dropped, whole)
        return best[1:]


def _normalize(dropped, live):
    """Zero-peak pairs dropped with their parameter when all its live parts are, else kept."""
    gone = np.all(dropped | ~live, axis=1) & dropped.any(axis=1)
    return np.where(live, dropped, gone[:, None])


def _part_values(base, dropped):
    """(3, n, 10): per part, the base parameters without the dropped ones."""
    values = np.zeros((len(PARTS),) + base.standard.shape)
    for p in range(len(PARTS)):
        flat = np.zeros(base.standard.size)
        flat[base.independent.reshape(-1)] = np.where(dropped[:, p], 0.0, base.beta)
        values[p] = flat.reshape(base.standard.shape)
    return values


def _count(robot, base, dropped):
    """Multiplications + additions of the pruned program (quick: no cse, one form)."""
    return _total(parts_program(robot, _part_values(base, dropped), cse=False, search=False))


def pruned_program(robot, base, dropped, cse=True, exact=None):
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
    gd_analyze.core.symbolic.codegen.Program
        The pruned program, or the exact one (:func:`.recursive.exact_program`) when the
        pruned one would count more operations (multiplications + additions).

    Notes
    -----
    Per link, parameters whose kept parts differ are grouped, each group's wrench formed
    from the kinematic quantities of its kept parts (inertial and gravity parts by their own
    recursions, the others as the whole minus those; :mod:`.recursive`).
    """
    dropped = np.asarray(dropped, bool)
    if dropped.shape != (base.rank, len(PARTS)):
        raise ValueError(f"dropped must have shape ({base.rank}, 3), got {dropped.shape}")
    if exact is None:
        exact = exact_program(robot, base.values, cse=cse)
    if not dropped.any():
        return exact
    pruned = parts_program(robot, _part_values(base, dropped), cse=cse)
    return pruned if _total(pruned) <= _total(exact) else exact


def _total(program):
    c = program.cost()
    return c["multiplications"] + c["additions"]


def prune_bounds(robot, base, scale, peak, whole_peak, eps, strategy="cost", pieces=None):
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
        (e.g. proved over the joint-limit region, :func:`gd_analyze.core.selection.certify.
        certify`) [N m or N].
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
    sel = _Selection(robot, base, C, peak, whole_peak, eps * scale, criterion)
    dropped, whole = sel.by_peak() if strategy == "peak" else sel.by_cost()
    dropped = _normalize(dropped, sel.live)
    return Pruning(eps=float(eps), dropped=dropped, peak=peak, whole_peak=whole_peak,
                   whole=whole, bound=sel.bound(dropped, whole), scale=scale,
                   criterion=criterion)
