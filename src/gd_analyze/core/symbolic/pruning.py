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

from ..kinematics import as_states
from .base_parameters import regressor
from .recursive import PARTS, exact_program, parts_program

__all__ = ["part_contributions", "Pruning", "prune", "pruned_program", "STRATEGIES"]


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
        Per joint, the sum of the dropped units' peaks (``whole_peak`` of the parameters in
        ``whole``, ``peak`` of the other dropped pairs): the pruned model's error on the
        trajectory is at most this [N m or N], and bound <= eps * scale.
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


#: Selection strategies of :func:`prune`.
STRATEGIES = ("cost", "peak")


def prune(robot, base, q, qd, qdd, eps, torque_floor=0.0, strategy="cost"):
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
        Tolerance, >= 0: every joint's dropped peaks add up to at most eps * scale_i.
    torque_floor : float, optional
        Least scale of a joint [N m or N] (for joints whose torque is near 0 on the
        trajectory); default 0.
    strategy : {"cost", "peak"}, optional
        ``"peak"``: pairs in increasing order of their largest peak relative to the joint
        scales, max_i peak_i / scale_i, each dropped when the budget allows. ``"cost"``
        (default): first whole parameters (all their parts, bounded by the peak of their
        whole contribution) in increasing order of their relative peak or in decreasing
        order of operations saved per budget share (the cheaper result of the two), then
        single pairs in increasing order of peak, each kept
        dropped only when it lowers the operation count of the program (single parts need
        split kinematic quantities, which may cost more than they save).

    Returns
    -------
    Pruning

    Raises
    ------
    ValueError
        If eps or torque_floor is negative or not finite, the strategy unknown, or the
        arrays not (N, n).

    Notes
    -----
    A unit (a pair, or a whole parameter with the peak of its whole contribution) is dropped
    only when every joint's sum of dropped peaks stays within eps * scale_i; by the triangle
    inequality the pruned torque then differs from the exact
    one on the trajectory by at most that sum. Pairs whose peak is 0 on the trajectory are
    dropped with their parameter when all its other parts are, and kept otherwise.
    """
    if not (np.isfinite(eps) and eps >= 0):
        raise ValueError(f"eps must be a finite number >= 0, got {eps!r}")
    if not (np.isfinite(torque_floor) and torque_floor >= 0):
        raise ValueError(f"torque_floor must be a finite number >= 0, got {torque_floor!r}")
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
    C = part_contributions(robot, base, q, qd, qdd)          # (3, N, n, b)
    tau = C.sum(axis=(0, 3))
    scale = np.maximum(np.abs(tau).max(axis=0), torque_floor)
    peak = np.abs(C).max(axis=1).transpose(2, 0, 1)         # (b, 3, n)
    whole_peak = np.abs(C.sum(axis=0)).max(axis=0).T         # (b, n)
    budget = eps * scale
    safe = np.where(scale > 0, scale, 1.0)
    rel = np.where(scale > 0, peak / safe, np.where(peak > 0, np.inf, 0.0)).max(axis=2)
    live = rel > 0                                            # (b, 3): contributes
    dropped = np.zeros(peak.shape[:2], bool)
    whole = np.zeros(peak.shape[0], bool)
    bound = np.zeros(robot.n)

    def fits(extra):
        return np.all(bound + extra <= budget)

    if strategy == "peak":
        for flat in np.argsort(rel, axis=None, kind="stable"):
            m, p = np.unravel_index(flat, rel.shape)
            if live[m, p] and fits(peak[m, p]):
                dropped[m, p] = True
                bound = bound + peak[m, p]
    else:
        dropped, whole, bound = _by_cost(robot, base, peak, whole_peak, live, budget)
    return Pruning(eps=float(eps), dropped=_normalize(dropped, live), peak=peak,
                   whole_peak=whole_peak, whole=whole, bound=bound, scale=scale)


def _by_cost(robot, base, peak, whole_peak, live, budget):
    """The "cost" strategy: whole parameters, then single pairs (see :func:`prune`)."""
    b = peak.shape[0]
    safe = np.where(budget > 0, budget, 1.0)
    rel = np.where(budget > 0, peak / safe, np.where(peak > 0, np.inf, 0.0))
    use = np.where(budget > 0, whole_peak / safe,
                   np.where(whole_peak > 0, np.inf, 0.0)).max(axis=1)    # budget share
    none = np.zeros(peak.shape[:2], bool)
    full = _count(robot, base, none)
    saving = np.zeros(b)
    for m in range(b):
        if live[m].any() and np.isfinite(use[m]) and use[m] <= 1.0:
            one = none.copy()
            one[m] = live[m]
            saving[m] = full - _count(robot, base, _normalize(one, live))
    best = None
    for order in (np.argsort(use, kind="stable"),
                  np.argsort(-saving / np.maximum(use, 1e-300), kind="stable")):
        dropped, bound = none.copy(), np.zeros(peak.shape[2])
        whole = np.zeros(b, bool)
        for m in order:
            if live[m].any() and np.all(bound + whole_peak[m] <= budget):
                dropped[m], whole[m] = live[m], True
                bound = bound + whole_peak[m]
        cost = _count(robot, base, _normalize(dropped, live))
        for flat in np.argsort(rel.max(axis=2), axis=None, kind="stable"):
            m, p = np.unravel_index(flat, rel.shape[:2])
            if not live[m, p] or dropped[m, p] or not np.all(bound + peak[m, p] <= budget):
                continue
            dropped[m, p] = True
            trial = _count(robot, base, _normalize(dropped, live))
            if trial < cost:
                cost, bound = trial, bound + peak[m, p]
            else:
                dropped[m, p] = False
        if best is None or cost < best[0]:
            best = (cost, dropped, whole, bound)
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


def pruned_program(robot, base, dropped, cse=True):
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

    Returns
    -------
    gd_analyze.core.codegen.Program
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
    exact = exact_program(robot, base.values, cse=cse)
    if not dropped.any():
        return exact
    pruned = parts_program(robot, _part_values(base, dropped), cse=cse)
    return pruned if _total(pruned) <= _total(exact) else exact


def _total(program):
    c = program.cost()
    return c["multiplications"] + c["additions"]
