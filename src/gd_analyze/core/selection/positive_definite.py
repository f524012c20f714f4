"""The simplified model's inertia matrix D_s stays positive definite (issue 30, item 3).

Pruning drops inertial contributions, and a D_s that is not positive definite breaks forward
dynamics (qdd = D_s^-1 (tau - h_s - c_s)) and every controller that inverts it. The check runs
where the model's bound holds: over its joint-limit region (guarantee kind ``"region"``: q
sampled uniformly in [q_min, q_max]) or on its trajectories (kind ``"trajectory"``: their
positions). At each sampled q, D_s scaled to a unit diagonal, S D_s S with S = diag(D_ii^-1/2),
is positive definite if every Gershgorin disc lies right of 0 (sum_j!=i |D_ij| / sqrt(D_ii
D_jj) < 1; Horn & Johnson, *Matrix Analysis*, 2nd ed. 2013, Thm. 6.1.1 and 6.1.10); where the
discs do not prove it, the smallest eigenvalue decides. It is a sampled check, not a proof over
the region: the JSON says so, with the number of samples and of those Gershgorin proved.

Where the check fails for a model of the recursive form, the parameters whose inertial part
was dropped are restored, whole and largest inertial contribution first, until D_s is positive
definite at every sample, and those not needed for it are then dropped again: restoring a
parameter whole removes whole units from the dropped set, so the model's bound (the sum of the
dropped units' peaks, :mod:`.budget`) still holds.
Pure: no files.
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["SAMPLES", "sample_positions", "check_inertia", "with_inertia_check"]

#: Positions sampled over a region.
SAMPLES = 2000


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


def check_inertia(inertia, q):
    """Whether D(q) is positive definite at each position.

    Parameters
    ----------
    inertia : callable
        ``inertia(q)`` of shape (M, n) -> D of shape (M, n, n) [kg m^2; kg].
    q : ndarray, shape (M, n)
        Positions [rad; m].

    Returns
    -------
    dict
        ``samples`` (M), ``positive_definite`` (bool: at every position),
        ``gershgorin_proved`` (positions where the scaled discs prove it),
        ``min_eigenvalue`` (smallest eigenvalue over the positions [kg m^2]) and
        ``min_relative_eigenvalue`` (smallest lambda_min / lambda_max over them [1]).

    Examples
    --------
    >>> D = lambda q: np.array([[[2.0, q[0, 0]], [q[0, 0], 1.0]]])
    >>> check_inertia(D, np.array([[0.5]]))["gershgorin_proved"]
    1
    >>> check_inertia(D, np.array([[2.0]]))["positive_definite"]
    False
    """
    D = np.asarray(inertia(q), float)
    D = 0.5 * (D + np.swapaxes(D, 1, 2))
    diag = np.diagonal(D, axis1=1, axis2=2)
    positive = (diag > 0).all(axis=1)
    s = 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0))
    A = np.abs(D * s[:, :, None] * s[:, None, :])
    off = A.sum(axis=2) - np.diagonal(A, axis1=1, axis2=2)
    proved = positive & (off < 1.0).all(axis=1)
    eig = np.linalg.eigvalsh(D)
    lo, hi = eig[:, 0], np.abs(eig).max(axis=1)
    return {"samples": int(q.shape[0]), "positive_definite": bool((lo > 0).all() and
                                                                  positive.all()),
            "gershgorin_proved": int(proved.sum()), "min_eigenvalue": float(lo.min()),
            "min_relative_eigenvalue": float((lo / np.where(hi > 0, hi, 1.0)).min())}


def _restore(model, k):
    """The recursive model with base parameter k kept, all its parts."""
    rec = model.recursive
    dropped = np.array(rec.dropped, bool)
    dropped[k] = False
    rec = dataclasses.replace(rec, dropped=dropped)
    return dataclasses.replace(model, recursive=rec, program_cache=None, functions_cache=None,
                               choice_cache=None, cost={})


def with_inertia_check(model, q=None, count=SAMPLES, seed=0):
    """The model with D_s checked (and kept) positive definite where its bound holds.

    Parameters
    ----------
    model : SimplifiedModel
    q : array_like, shape (N, n), optional
        The positions of the trajectories the model was built on [rad; m] (needed for a model
        without a region guarantee; added to the samples otherwise).
    count : int, optional
        Samples over a region (:data:`SAMPLES`).
    seed : int, optional

    Returns
    -------
    SimplifiedModel
        With ``inertia_check``: :func:`check_inertia`'s figures, ``where`` (``"region"`` or
        ``"trajectory"``), ``restored`` (the base parameters restored with all their parts for
        positive definiteness, a recursive model only) and ``method``; a recursive model whose D_s
        was not positive definite has those parameters kept (its program, cost and functions built
        again; bound unchanged). A model with no region and no positions is returned as it is.

    Notes
    -----
    A sampled check (Gershgorin discs, Horn & Johnson 2013, Thm. 6.1.1; eigenvalues where the
    discs do not prove it), not a proof over the region.
    """
    try:
        where, qs = sample_positions(model, q, count, seed)
    except ValueError:
        return model
    restored = []
    check = check_inertia(model.functions().numpy()["inertia"], qs)
    rec = model.recursive
    if not check["positive_definite"] and rec is not None:
        from ..symbolic.emit_model import numpy_function
        from ..symbolic.model_functions import FUNCTIONS, recursive_inertia, with_armature

        base, dropped, n = rec.base(model.robot), np.array(rec.dropped, bool), model.robot.n
        inertial = np.where(dropped[:, 0], 1.0, -1.0) * (
            np.ones(len(rec.names)) if rec.relative_peak is None
            else np.asarray(rec.relative_peak, float)[:, 0] + 1e-300)
        def definite(left_out):                     # a quick D_s of a candidate
            D = with_armature(recursive_inertia(model.robot, base, left_out, search=False),
                              model.robot)
            return check_inertia(numpy_function(FUNCTIONS[1], D, (n, n)), qs)[
                "positive_definite"]
        for k in np.argsort(-inertial, kind="stable"):
            if inertial[k] < 0:
                break
            dropped[k] = False
            restored.append(k)
            if definite(dropped):
                break
        for k in list(restored[:-1]):               # then drop again what is not needed
            trial = dropped.copy()
            trial[k] = rec.dropped[k]
            if definite(trial):
                dropped, restored = trial, [j for j in restored if j != k]
        restored = [rec.names[k] for k in restored]
        for name in restored:
            model = _restore(model, rec.names.index(name))
        if restored:
            check = check_inertia(model.functions().numpy()["inertia"], qs)
            cost = dict(model.program().cost())
            costs = {k: (cost if k == "recursive, budget" else v) for k, v in model.costs.items()}
            model = dataclasses.replace(model, cost=cost, costs=costs)
    method = ("sampled: D_s at each position scaled to a unit diagonal, positive definite where "
              "every Gershgorin disc lies right of 0, else by its smallest eigenvalue; "
              + ("uniform over the region [q_min, q_max]" if where == "region" else
                 "the positions of the trajectories the model was built on")
              + "; not a proof between the samples")
    return model.with_inertia_check({"where": where, **check, "restored": restored,
                                     "method": method})
