"""The simplified model's inertia matrix D_s, proved positive definite where its bound holds.

Pruning drops inertial contributions, and a D_s that is not positive definite breaks forward
dynamics (qdd = D_s^-1 (tau - h_s - c_s)) and every controller that inverts it. The proof
(:mod:`.inertia_proof`) runs over the model's region (guarantee kind ``"region"``) or over the
bounding box of its trajectories' positions (kind ``"trajectory"``).

Where the proof fails for a model of the recursive form, the parameters whose inertial part
was dropped are restored, whole and largest inertial contribution first, until it holds (or,
for an arm whose D has no floor to prove D_s on, until D_s is positive definite at the sampled
positions, which is said and not called proved), and those not needed are then dropped again:
restoring a parameter whole removes whole units from the dropped set, so a bound computed
again for the pairs still dropped holds. The caller
builds the restored model (``rebuild``) so that its bound and sampled error are those of the
model deployed. An explicit model that drops terms is checked at sampled positions only, and
says so. Samples never prove.
Pure: no files.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from ..dynamics.base_parameters import base_parameters
from ..symbolic.pruning import settle_restored
from .inertia_proof import (
    MAX_BOXES,
    SAMPLES,
    InertiaProof,
    dropped_inertia_values,
    gershgorin_lower,
    inertia_context,
    inertia_floor,
    prove_inertia,
)

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot

#: Boxes of a restore's trial proof (the model finally deployed is proved with the full
#: budget).
CANDIDATE_BOXES = 256

__all__ = ["CANDIDATE_BOXES", "CHECK_BLOCK", "SAMPLES", "MAX_BOXES", "InertiaProof", "inertia_floor",
           "gershgorin_lower", "prove_inertia", "inertia_context", "check_inertia",
           "sample_positions", "with_inertia_check", "inertia_statement",
           "dropped_inertia_values", "inertia_restored"]

#: Positions whose D_s is evaluated at once by :func:`check_inertia` (each (block, n, n)
#: temporary of a 6-joint arm is 2.3 MiB).
CHECK_BLOCK = 8192
#: Every ANCHOR_STEP-th position of a block has its eigenvalues computed; the others only
#: where a shifted definiteness test cannot rule them out of the minima.
ANCHOR_STEP = 16
#: Relative round-off margin of that ruling out (eigvalsh's error is a few eps of the norm).
ROUND_OFF = 1e-10


def sample_positions(model, q=None, count=SAMPLES, seed=0):
    """Where D_s is checked: the model's region, else the given trajectory positions.

    Parameters
    ----------
    model : SimplifiedModel
    q : array_like, shape (N, n), optional
        The positions of the trajectories the model was built on [rad; m].
    count : int, optional
        Samples over a region.
    seed : int, optional

    Returns
    -------
    where : str
        ``"region"`` or ``"trajectory"``.
    q : ndarray, shape (M, n)
        The positions [rad; m]: uniform in [q_min, q_max] over a region (with the given
        trajectory's positions added), else the trajectory's.

    Raises
    ------
    ValueError
        If the model has no region and no positions are given.
    """
    g = model.guarantee
    extra = np.zeros((0, model.robot.n)) if q is None else np.atleast_2d(np.asarray(q, float))
    if g is not None and g.kind == "region":
        rng = np.random.default_rng(seed)
        lo, hi = np.asarray(g.q_min, float), np.asarray(g.q_max, float)
        return "region", np.concatenate([rng.uniform(lo, hi, (count, lo.size)), extra])
    if extra.shape[0] == 0:
        raise ValueError("the model has no region: give the trajectory's positions")
    return "trajectory", extra


def check_inertia(inertia, q, block=CHECK_BLOCK):
    """Whether D(q) is positive definite at each given position, block by block (sampled: no
    proof).

    Parameters
    ----------
    inertia : callable
        ``inertia(q)`` of shape (M, n) -> D of shape (M, n, n) [kg m^2; kg].
    q : ndarray, shape (M, n)
        Positions [rad; m].
    block : int, optional
        Positions evaluated at once (:data:`CHECK_BLOCK`): memory stays a few blocks of
        (block, n, n) whatever M is; the figures do not depend on it.

    Returns
    -------
    dict
        ``samples`` (M), ``positive_definite`` (bool: at every position) and
        ``min_eigenvalue`` (smallest eigenvalue over the positions [kg m^2]).

    Notes
    -----
    The eigenvalues are computed (``numpy.linalg.eigvalsh``) at every :data:`ANCHOR_STEP`-th
    position of a block (the anchors) and wherever a shifted definiteness test cannot rule the
    position out of the minima: lambda_min(D) > t exactly when D - t I is positive definite
    (every pivot of its L D L^T factorisation positive), tested with t the smallest
    lambda_min found plus a round-off margin of :data:`ROUND_OFF` ||D||_F, and with t = r B for
    the ratio r found, B an upper bound on max |lambda| (||D||_F, or Weyl's inequality from
    the anchor before: max |lambda(D)| <= max |lambda(D_a)| + ||D - D_a||_F; Horn & Johnson,
    *Matrix Analysis*, 2nd ed. 2013, Cor. 4.3.15). The minima are those of the eigenvalues of
    every position.

    Examples
    --------
    >>> D = lambda q: np.array([[[2.0, q[0, 0]], [q[0, 0], 1.0]]])
    >>> check_inertia(D, np.array([[0.5]]))["positive_definite"]
    True
    >>> check_inertia(D, np.array([[2.0]]))["positive_definite"]
    False
    """
    q = np.asarray(q, float)
    M = q.shape[0]
    if M == 0:
        raise ValueError("no positions to check")
    block = max(1, int(block))
    positive, proved = True, 0
    lo_min, ratio_min = np.inf, np.inf
    nan = False
    for a in range(0, M, block):
        D = np.asarray(inertia(q[a:a + block]), float)
        pos, disc, D, norm = _block(D)
        proved += int((pos & disc).sum())
        positive = positive and bool(pos.all())
        lo, ratio = _screened_eigenvalues(D, norm, lo_min, ratio_min)
        nan = nan or bool(np.isnan(lo).any() or np.isnan(ratio).any())
        if lo.size:
            lo_min = min(lo_min, float(lo.min()))
            ratio_min = min(ratio_min, float(ratio.min()))
    if nan:                                   # NaN never passes (as numpy's min gives it)
        lo_min = ratio_min = float("nan")
    return {"samples": int(M), "positive_definite": bool(lo_min > 0 and positive),
            "gershgorin_proved": int(proved), "min_eigenvalue": float(lo_min),
            "min_relative_eigenvalue": float(ratio_min)}


def _block(D):
    """A block's D symmetrized, which positions have a positive diagonal and which the scaled
    Gershgorin discs prove positive definite, and ||D||_F, in one compiled pass
    (:func:`gd_analyze.ranking.kernels.inertia_block_kernel`)."""
    from ..ranking.kernels import inertia_block_kernel

    D = np.ascontiguousarray(D)
    S, M = np.empty_like(D), D.shape[0]
    pos, disc, norm = np.empty(M, bool), np.empty(M, bool), np.empty(M)
    inertia_block_kernel(D, S, pos, disc, norm)
    return pos, disc, S, norm


def _screened_eigenvalues(D, norm, lo_min, ratio_min):
    """lambda_min and lambda_min / max |lambda| of the positions of a block that may hold the
    minima: the anchors, and the positions a shifted definiteness test does not rule out
    (:func:`check_inertia`), tested in one compiled pass (:func:`gd_analyze.ranking.kernels.inertia_screen_kernel`).

    Parameters
    ----------
    D : ndarray, shape (M, n, n)
        Symmetric matrices [kg m^2; kg].
    norm : ndarray, shape (M,)
        Their ||D||_F.
    lo_min, ratio_min : float
        The smallest lambda_min and ratio found so far (inf: none yet).

    Returns
    -------
    lo, ratio : ndarray, shape (K,)
        Of the K positions computed (every one whose values might be below the minima).
    """
    M = D.shape[0]
    anchors = np.arange(0, M, ANCHOR_STEP)
    eig = _eigenvalues(D[anchors])
    lo = [eig[:, 0]]
    hi_a = np.abs(eig).max(axis=1)
    ratio = [eig[:, 0] / np.where(hi_a > 0, hi_a, 1.0)]
    best_lo = float(np.fmin.reduce(lo[0], initial=lo_min))          # NaN left aside here
    best_ratio = float(np.fmin.reduce(ratio[0], initial=ratio_min))
    from ..ranking.kernels import inertia_screen_kernel

    maybe = np.empty(M, bool)
    inertia_screen_kernel(D, norm, hi_a, ANCHOR_STEP, best_lo, best_ratio, ROUND_OFF, maybe)
    rows = np.flatnonzero(maybe)
    if rows.size:
        eig = _eigenvalues(D[rows])
        hi = np.abs(eig).max(axis=1)
        lo.append(eig[:, 0])
        ratio.append(eig[:, 0] / np.where(hi > 0, hi, 1.0))
    return np.concatenate(lo), np.concatenate(ratio)


def _eigenvalues(D):
    """numpy's eigvalsh of each matrix, NaN for one that holds a NaN or an infinity.

    Parameters
    ----------
    D : ndarray, shape (M, n, n)

    Returns
    -------
    ndarray, shape (M, n)
        Ascending.
    """
    out = np.full(D.shape[:2], np.nan)
    finite = np.isfinite(D).all(axis=(1, 2))
    if finite.any():
        out[finite] = np.linalg.eigvalsh(D[finite])
    return out


def _box(model, q):
    """The box D_s is proved over: the region's, else the trajectory's bounding box."""
    g = model.guarantee
    if g is not None and g.kind == "region":
        return "region", np.asarray(g.q_min, float), np.asarray(g.q_max, float)
    if q is None or np.size(q) == 0:
        return None, None, None
    q = np.atleast_2d(np.asarray(q, float))
    return "trajectory", q.min(axis=0), q.max(axis=0)


def inertia_statement(check):
    """The sentence a model's outputs state about D_s, from its ``inertia_check``.

    Parameters
    ----------
    check : dict or None
        :attr:`SimplifiedModel.inertia_check
        <gd_analyze.simplify.simplified.SimplifiedModel.inertia_check>`.

    Returns
    -------
    str
        e.g. "proved positive definite over the region: lambda_min(D_s) >= 0.00012 kg m^2
        (0.21 of min lambda_min(D))"; "" for None.

    Examples
    --------
    >>> inertia_statement({"proved": False, "where": "trajectory", "samples": 40,
    ...                    "sampled_min_eigenvalue": 0.5, "why": "explicit form"})
    'not proved (explicit form); positive definite at the 40 sampled positions of the trajectory'
    """
    if not check:
        return ""
    where = {"region": "the region",
             "trajectory": "the bounding box of the trajectory positions"}.get(
        check.get("where"), str(check.get("where")))
    if check.get("proved"):
        return (f"proved positive definite over {where}: lambda_min(D_s) >= "
                f"{check['lower_bound']:.3g} {check.get('unit', 'kg m^2')} "
                f"({check['ratio']:.3g} of min lambda_min(D))")
    sampled = check.get("sampled_min_eigenvalue")
    tail = "" if sampled is None else (
        f"; {'positive definite' if sampled > 0 else 'NOT positive definite'} at the "
        f"{check.get('samples', 0)} sampled positions of the "
        f"{'trajectory' if check.get('where') == 'trajectory' else 'region'}")
    return f"not proved ({check.get('why', '')}){tail}"


def _unit(robot):
    prismatic = np.asarray(robot.prismatic, bool)
    return ("kg m^2" if not prismatic.any() else "kg" if prismatic.all() else
            "SI units (kg m^2, kg m and kg mixed: q in rad and m)")


def with_inertia_check(model, q=None, max_boxes=MAX_BOXES, samples=SAMPLES, seed=0,
                       rebuild=None):
    """The model with D_s proved positive definite where its bound holds, restored if needed.

    Parameters
    ----------
    model : SimplifiedModel
    q : array_like, shape (N, n), optional
        The positions of the trajectories the model was built on [rad; m]: a model without a
        region guarantee is proved over their bounding box.
    max_boxes, samples, seed
        As :func:`prove_inertia`.
    rebuild : callable, optional
        ``rebuild(model, dropped)`` -> the model with exactly these pairs dropped, its bound,
        guarantee and cost derived again for them; default: the recursive model with
        ``dropped`` and its cost counted again (its bound is then that of the pairs dropped
        before, which still bounds: fewer pairs are dropped).

    Returns
    -------
    SimplifiedModel
        With ``inertia_check``: ``where`` (``"region"`` or ``"trajectory"``), ``proved``,
        ``lower_bound`` [kg m^2], ``ratio``, ``d_upper``, ``floor``, ``boxes``,
        ``samples``, ``sampled_min_eigenvalue``, ``restored`` (base parameters whose inertial
        part, the only one in D_s, is restored for the proof, or, with no floor under D, until
        D_s is positive definite at the sampled positions), ``why``, ``unit``, ``method``
        and ``statement``. An explicit model
        that drops terms is not proved (its dropped terms are not parameters): it is
        checked at the trajectory's positions only, and says so. A model with no region and
        no positions is returned as it is.
    """
    where, q_min, q_max = _box(model, q)
    if where is None:
        return model
    robot = model.robot
    rec = model.recursive
    if rec is None and _drops_terms(model):
        qs = np.atleast_2d(np.asarray(q, float)) if q is not None else \
            sample_positions(model, None, samples, seed)[1]
        check = check_inertia(model.functions().numpy()["inertia"], qs)
        return model.with_inertia_check(_record(
            model, where, None, [], samples=check["samples"],
            sampled=check["min_eigenvalue"],
            why="an explicit model that drops terms: its D_s is not proved",
            method=("sampled: the smallest eigenvalue of D_s (numpy.linalg.eigvalsh) at the "
                    f"{check['samples']} given positions; not a proof between them")))
    base = base_parameters(robot) if rec is None else rec.base(robot)
    left = np.zeros((len(base.beta), 3), bool) if rec is None else \
        np.asarray(model.left_out(), bool)

    context = inertia_context(robot, base, q_min, q_max, samples, seed)

    def prove(left_out, boxes=max_boxes):
        return prove_inertia(robot, base, left_out, q_min, q_max, boxes, samples, seed,
                             context=context)

    def candidate(left_out):        # a restore's trial: a smaller budget of boxes
        return prove(left_out, min(max_boxes, CANDIDATE_BOXES)).proved

    def positive_at_samples(left_out):  # where D has no floor to prove D_s on: samples
        return prove(left_out).sampled_min > 0

    proof = prove(left)
    restored = []
    # restore where it can help: to a proof when D itself has a floor; else, where D_s is not
    # positive definite at a sampled position, until it is there (said: not a proof)
    if not proof.proved and rec is not None and (
            (proof.floor > 0).all() or proof.sampled_min <= 0):
        trial, restored = _restore(np.array(rec.dropped, bool), rec.relative_peak,
                                   candidate if (proof.floor > 0).all() else positive_at_samples)
        if restored:
            model = (rebuild or _default_rebuild)(model, trial)
            rec = model.recursive
            proof = prove(np.asarray(model.left_out(), bool))
    return model.with_inertia_check(_record(model, where, proof,
                                            [rec.names[k] for k in restored]))


def _restore(dropped, relative_peak, candidate):
    """The dropped pairs with inertial parts restored until ``candidate`` proves D_s, the
    largest first, then those not needed dropped again; and the parameters restored."""
    inertial = np.where(dropped[:, 0], 1.0, -1.0) * (
        np.ones(dropped.shape[0]) if relative_peak is None
        else np.asarray(relative_peak, float)[:, 0] + 1e-300)
    trial, restored = dropped.copy(), []
    for k in np.argsort(-inertial, kind="stable"):
        if inertial[k] < 0:
            break
        trial[k, 0] = False             # its inertial part: the only one in D_s
        restored.append(int(k))
        if candidate(trial):
            break
    for k in list(restored[:-1]):               # then drop again what is not needed
        again = trial.copy()
        again[k, 0] = dropped[k, 0]
        if candidate(again):
            trial, restored = again, [j for j in restored if j != k]
    return trial, restored


def inertia_restored(robot: Robot, base: BaseParameters, dropped: np.ndarray,
                     relative_peak: np.ndarray | None, q_min: np.ndarray, q_max: np.ndarray,
                     max_boxes: int = MAX_BOXES, samples: int = SAMPLES, seed: int = 0
                     ) -> np.ndarray:
    """The pairs a recursive model dropping ``dropped`` keeps dropped once
    :func:`with_inertia_check` has restored what its proof of D_s needs.

    Parameters
    ----------
    robot, base : Robot, BaseParameters
        The arm (n joints) and its b base parameters.
    dropped : ndarray of bool, shape (b, 3)
        The pairs left out (the program leaves them out).
    relative_peak : ndarray, shape (b, 3), or None
        The pairs' peaks relative to s_i
        (:attr:`gd_analyze.symbolic.recursive_model.RecursiveModel.relative_peak`) [1]: the
        order of the restore.
    q_min, q_max : ndarray, shape (n,)
        The box D_s is proved over [rad or m].
    max_boxes, samples, seed
        As :func:`with_inertia_check`.

    Returns
    -------
    ndarray of bool, shape (b, 3)
        ``dropped`` where D_s is proved with it, or where no restore can help (D itself not
        proved); else ``dropped`` with the inertial parts restored by the same trials
        :func:`with_inertia_check` makes (it proves nothing itself: what to build is decided
        by it, the proof is the deployed model's).
    """
    dropped = np.asarray(dropped, bool)
    context = inertia_context(robot, base, q_min, q_max, samples, seed)
    proof = prove_inertia(robot, base, dropped, q_min, q_max, max_boxes, samples, seed,
                          context=context)
    if proof.proved or not (proof.floor > 0).all():
        return dropped.copy()
    return _restore(dropped, relative_peak, lambda left: prove_inertia(
        robot, base, left, q_min, q_max, min(max_boxes, CANDIDATE_BOXES), samples, seed,
        context=context).proved)[0]


def _default_rebuild(model, dropped):
    robot, rec = model.robot, model.recursive
    dropped = settle_restored(robot, rec.base(robot), rec.dropped, dropped)
    rec = dataclasses.replace(rec, dropped=dropped)
    model = dataclasses.replace(model, recursive=rec, program_cache=None, functions_cache=None,
                                choice_cache=None, cost={})
    cost = dict(model.program().cost())
    costs = {k: (cost if k == "recursive, budget" else v) for k, v in model.costs.items()}
    return dataclasses.replace(model, cost=cost, costs=costs)


def _drops_terms(model):
    """Whether an explicit model leaves out terms of D (the exact explicit one does not)."""
    return set(model.choices.values()) != {"both"}


def _record(model, where, proof, restored, samples=None, sampled=None, why="", method=""):
    unit = _unit(model.robot)
    if proof is not None:
        check = {"where": where, "proved": bool(proof.proved),
                 "lower_bound": float(proof.lower) if proof.proved else None,
                 "ratio": proof.ratio if proof.proved else None,
                 "d_upper": float(proof.d_upper), "witness": [float(v) for v in proof.witness],
                 "floor": [float(v) for v in proof.floor], "boxes": int(proof.boxes),
                 "samples": int(proof.samples),
                 "sampled_min_eigenvalue": float(proof.sampled_min),
                 "why": proof.why, "restored": list(restored),
                 "unit": unit,
                 "method": (
                     "proved: D(q) >= diag(f) at every q (f from each link's spatial inertia "
                     "and its parent's, certified; x^T D x as the links' kinetic energies), and "
                     "D - D_s (the dropped inertial parameters) enclosed over boxes of q by the "
                     "Newton-Euler recursion in interval arithmetic rounded outward, split by "
                     "branch and bound; lambda_min(diag(f) - (D - D_s)) bounded below by "
                     "Gershgorin's discs weighted by sqrt(f); min lambda_min(D) bounded above by "
                     "the Rayleigh quotient at the sampled position where it is least")}
    else:
        check = {"where": where, "proved": False, "lower_bound": None, "ratio": None,
                 "samples": int(samples), "sampled_min_eigenvalue": float(sampled),
                 "why": why, "restored": list(restored), "unit": unit, "method": method}
    check["statement"] = inertia_statement(check)
    return check
