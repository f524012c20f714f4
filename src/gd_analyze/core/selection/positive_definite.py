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

from ..dynamics.dalembert import compiled_engine

__all__ = ["SAMPLES", "CHECK_BLOCK", "sample_positions", "check_inertia",
           "with_inertia_check"]

#: Positions sampled over a region.
SAMPLES = 2000
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


def check_inertia(inertia, q, block=CHECK_BLOCK, engine="auto"):
    """Whether D(q) is positive definite at each position, block by block.

    Parameters
    ----------
    inertia : callable
        ``inertia(q)`` of shape (M, n) -> D of shape (M, n, n) [kg m^2; kg].
    q : ndarray, shape (M, n)
        Positions [rad; m].
    block : int, optional
        Positions evaluated at once (:data:`CHECK_BLOCK`): memory stays a few blocks of
        (block, n, n) whatever M is; the figures do not depend on it.
    engine : {"auto", "numpy", "compiled"}, optional
        The pass over each block as array code or compiled (numba; ``"auto"``: compiled from
        :data:`gd_analyze.core.dynamics.dalembert.COMPILED_MIN_SETPOINTS` positions on,
        :func:`~gd_analyze.core.dynamics.dalembert.compiled_engine`): the same figures.

    Returns
    -------
    dict
        ``samples`` (M), ``positive_definite`` (bool: at every position),
        ``gershgorin_proved`` (positions where the scaled discs prove it),
        ``min_eigenvalue`` (smallest eigenvalue over the positions [kg m^2]) and
        ``min_relative_eigenvalue`` (smallest lambda_min / lambda_max over them [1]).

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
    >>> check_inertia(D, np.array([[0.5]]))["gershgorin_proved"]
    1
    >>> check_inertia(D, np.array([[2.0]]))["positive_definite"]
    False
    """
    q = np.asarray(q, float)
    M = q.shape[0]
    if M == 0:
        raise ValueError("no positions to check")
    compiled = compiled_engine(engine, M)
    block = max(1, int(block))
    positive, proved = True, 0
    lo_min, ratio_min = np.inf, np.inf
    nan = False
    for a in range(0, M, block):
        D = np.asarray(inertia(q[a:a + block]), float)
        pos, disc, D, norm = (_block_compiled if compiled else _block)(D)
        proved += int((pos & disc).sum())
        positive = positive and bool(pos.all())
        lo, ratio = _screened_eigenvalues(D, norm, lo_min, ratio_min, compiled)
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
    Gershgorin discs prove positive definite, and ||D||_F (array code)."""
    D = 0.5 * (D + np.swapaxes(D, 1, 2))
    diag = np.diagonal(D, axis1=1, axis2=2)
    pos = (diag > 0).all(axis=1)
    s = 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0))
    A = np.abs(D * s[:, :, None] * s[:, None, :])
    off = A.sum(axis=2) - np.diagonal(A, axis1=1, axis2=2)
    return pos, pos & (off < 1.0).all(axis=1), D, np.sqrt((D ** 2).sum(axis=(1, 2)))


def _block_compiled(D):
    """:func:`_block` in one compiled pass (:func:`.kernels.inertia_block_kernel`)."""
    from .kernels import inertia_block_kernel

    D = np.ascontiguousarray(D)
    S, M = np.empty_like(D), D.shape[0]
    pos, disc, norm = np.empty(M, bool), np.empty(M, bool), np.empty(M)
    inertia_block_kernel(D, S, pos, disc, norm)
    return pos, disc, S, norm


def _screened_eigenvalues(D, norm, lo_min, ratio_min, compiled=False):
    """lambda_min and lambda_min / max |lambda| of the positions of a block that may hold the
    minima: the anchors, and the positions a shifted definiteness test does not rule out
    (:func:`check_inertia`).

    Parameters
    ----------
    D : ndarray, shape (M, n, n)
        Symmetric matrices [kg m^2; kg].
    norm : ndarray, shape (M,)
        Their ||D||_F.
    lo_min, ratio_min : float
        The smallest lambda_min and ratio found so far (inf: none yet).
    compiled : bool, optional
        Test in one compiled pass (:func:`.kernels.inertia_screen_kernel`) instead of
        array code.

    Returns
    -------
    lo, ratio : ndarray, shape (K,)
        Of the K positions computed (every one whose values might be below the minima).
    """
    M, n = D.shape[0], D.shape[1]
    anchors = np.arange(0, M, ANCHOR_STEP)
    eig = _eigenvalues(D[anchors])
    lo = [eig[:, 0]]
    hi_a = np.abs(eig).max(axis=1)
    ratio = [eig[:, 0] / np.where(hi_a > 0, hi_a, 1.0)]
    best_lo = float(np.fmin.reduce(lo[0], initial=lo_min))          # NaN left aside here
    best_ratio = float(np.fmin.reduce(ratio[0], initial=ratio_min))
    if compiled:
        from .kernels import inertia_screen_kernel

        maybe = np.empty(M, bool)
        inertia_screen_kernel(D, norm, hi_a, ANCHOR_STEP, best_lo, best_ratio, ROUND_OFF,
                              maybe)
        rows = np.flatnonzero(maybe)
    else:
        which = np.arange(M) // ANCHOR_STEP              # the anchor before each position
        weyl = hi_a[which] + np.sqrt(((D - D[anchors][which]) ** 2).sum(axis=(1, 2)))
        margin = ROUND_OFF * norm
        eye = np.eye(n)
        # lambda_min(D_p) > best_lo + margin: D_p - (best_lo + margin) I is positive definite
        out = _definite(D - (best_lo + margin)[:, None, None] * eye)
        # lambda_min / max|lambda| > best_ratio: lambda_min > r B with B >= max|lambda| for
        # r > 0 (||D||_F, Weyl's bound from the anchor) and B <= max|lambda| for r <= 0
        # (max |D_ii|)
        r = best_ratio + ROUND_OFF
        bound = np.minimum(norm, weyl) if r > 0 else \
            np.abs(np.diagonal(D, axis1=1, axis2=2)).max(1)
        out &= _definite(D - (r * bound + margin)[:, None, None] * eye)
        out[anchors] = True
        rows = np.flatnonzero(~out)
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


def _definite(A):
    """Whether each symmetric matrix is positive definite: every pivot of its L D L^T
    factorisation (Gaussian elimination without pivoting) is positive (Golub & Van Loan,
    *Matrix Computations*, 4th ed. 2013, Sec. 4.2). NaN is not.

    Parameters
    ----------
    A : ndarray, shape (M, n, n)

    Returns
    -------
    ndarray of bool, shape (M,)
    """
    A = np.ascontiguousarray(np.moveaxis(np.asarray(A, float), 0, -1))    # (n, n, M)
    ok = np.ones(A.shape[2], bool)
    for k in range(A.shape[0]):
        d = A[k, k]
        ok &= d > 0
        col = A[k + 1:, k] / np.where(d > 0, d, 1.0)
        A[k + 1:, k + 1:] -= col[:, None, :] * A[k, None, k + 1:]
    return ok


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
