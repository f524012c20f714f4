"""Check explicit terms against the G-D engine at a few fixed states (a cache's self-check).

The terms of the explicit model (:class:`~gd_analyze.symbolic.explicit.Term`) are evaluated at a
few pseudo-random states of a seeded generator and compared with the G-D engine
(:func:`gd_analyze.dynamics.dalembert.gd_terms`), part by part (D_tran, D_rot, h_tran, h_rot, c),
each relative to its own scale. Terms that were derived for the robot agree to round-off; the
terms of another robot, or coefficients scaled, do not.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..dynamics.dalembert import gd_terms
from .trigpoly import evaluate_rows

if TYPE_CHECKING:
    from ..model.robot import Robot
    from .explicit import Term

__all__ = ["term_values", "terms_disagreement", "CHECK_STATES", "CHECK_SEED"]

#: States of the check and the seed of their generator.
CHECK_STATES = 3
CHECK_SEED = 20250916
#: Floor of an element's scale, as a fraction of the largest scale of its quantity (an
#: element that is zero at every state is compared with its quantity's scale). The engine's
#: round-off is that of the arm's largest torques (up to about 1e-14 of them): an element
#: far smaller, such as the gravity torque of an axis a URDF's rounded angles tilt from the
#: vertical (1e-6 of the arm's, the SO-101's first joint), is measured against 1e-3 of them,
#: so that round-off stays about 1e-11 of its scale.
_FLOOR = 1e-3


def term_values(terms: Term, q: np.ndarray, qd: np.ndarray,
                prismatic: ArrayLike | None = None) -> tuple[np.ndarray, ...]:
    """Evaluate explicit terms: D_tran, D_rot, h_tran, h_rot and c at set points.

    Parameters
    ----------
    terms : Term
        Rows of an explicit model (:func:`gd_analyze.symbolic.explicit.model_terms`), in q (no
        offsets).
    q, qd : ndarray, shape (N, n)
        Joint positions [rad] and velocities [rad/s] (m, m/s for a prismatic joint).
    prismatic : array_like of bool, shape (n,), optional
        The prismatic joints (their columns of K are powers of q_i [m]); default none.

    Returns
    -------
    tuple of ndarray
        D_tran, D_rot (N, n, n) [kg m^2], mirrored from the rows i <= j; h_tran, h_rot, c
        (N, n) [N m].

    Raises
    ------
    IndexError
        If a row's joint index is outside 0 .. n-1.
    ValueError
        If a row's kind is not ``"D"``, ``"h"`` or ``"c"``, or its part does not fit it.

    Notes
    -----
    Source: Eqs. (3.4-25) to (3.4-28) of Fu, Gonzalez & Lee (1987) in the term form of
    :mod:`gd_analyze.symbolic.explicit`: D_ij = sum of its rows, h_i = sum over rows of
    C cos/sin(k . q) qd_j qd_k, c_i = sum of its rows.

    Examples
    --------
    >>> from gd_analyze.symbolic.explicit import derive, model_terms
    >>> from gd_analyze import load_robot
    >>> D_tran, D_rot, h_tran, h_rot, c = term_values(model_terms(derive(load_robot(
    ...     "two-link"))), np.zeros((1, 2)), np.zeros((1, 2)))
    >>> round(float(D_rot[0, 1, 1]), 6)
    0.083333
    """
    q, qd = np.atleast_2d(np.asarray(q, float)), np.atleast_2d(np.asarray(qd, float))
    N, n = q.shape
    kind, part = np.asarray(terms.kind).astype(str), np.asarray(terms.part).astype(str)
    i, j, k = (np.asarray(x, np.int64) for x in (terms.i, terms.j, terms.k))
    isD, ish, isc = kind == "D", kind == "h", kind == "c"
    tran = part == "tran"
    if not np.all(np.where(isc, part == "grav", (isD | ish) & (tran | (part == "rot")))):
        raise ValueError("a term's kind and part do not go together")
    inside = (i >= 0) & (i < n) & np.where(isc, True, (j >= 0) & (j < n)) \
        & np.where(ish, (k >= 0) & (k < n), True)
    if not inside.all():
        raise IndexError(f"a term's joint index is outside 0 .. {n - 1}")
    val = evaluate_rows(np.asarray(terms.K), np.asarray(terms.S, bool), q, prismatic) \
        * np.asarray(terms.C, float)                                     # (N, U)
    j0, k0 = np.maximum(j, 0), np.maximum(k, 0)
    val = np.where(ish, val * qd[:, j0] * qd[:, k0], val)

    def gather(rows, index, size):
        return np.stack([np.bincount(index[rows], val[s, rows], size) for s in range(N)])

    out = []
    for p in (tran, ~tran):
        rows = isD & p
        upper = gather(rows, i * n + j0, n * n).reshape(N, n, n)
        lower = gather(rows & (i != j), j0 * n + i, n * n).reshape(N, n, n)
        out.append(upper + lower)
    out += [gather(ish & p, i, n) for p in (tran, ~tran)]
    out.append(gather(isc, i, n))
    return tuple(out)


def _check_states(robot):
    """The fixed states of the check: q in [-pi, pi] (prismatic: [-0.5, 0.5] m), qd in +-1."""
    rng = np.random.default_rng(CHECK_SEED)
    n = robot.n
    pris = np.asarray(robot.prismatic, bool)
    q = rng.uniform(-np.pi, np.pi, (CHECK_STATES, n))
    q[:, pris] /= 2 * np.pi
    return q, rng.uniform(-1.0, 1.0, (CHECK_STATES, n))


def terms_disagreement(robot: Robot, terms: Term) -> float:
    """Largest relative difference between explicit terms and the G-D engine, at fixed states.

    Parameters
    ----------
    robot : Robot
        The arm the terms claim to describe.
    terms : Term
        Its explicit terms (:func:`gd_analyze.symbolic.explicit.model_terms`).

    Returns
    -------
    float
        max over the :data:`CHECK_STATES` states, the parts and the elements of
        |terms - engine| / scale: sqrt(D_ii D_jj) for D_ij (of the whole D), and for h_i and
        c_i the largest |h_i| (|c_i|) over the states (tran and rot added in magnitude), with
        a floor of 1e-3 of the arm's torque scale there (the largest of D's scale times
        max(1, qd^2), |h| and |c|: a one-joint arm's h or a massless link's parts are zero up
        to round-off, never measured against that round-off). ``inf`` if a value is not
        finite, a row's index is out of range or the terms' shape does not fit the robot.
        Terms derived for the robot give round-off (about 1e-15).

    Notes
    -----
    Source: the engine is the Jacobian form of Eqs. (3.4-25) to (3.4-28) of Fu, Gonzalez &
    Lee (1987) (:func:`gd_analyze.dynamics.dalembert.gd_terms`).

    Examples
    --------
    >>> from gd_analyze.symbolic.explicit import derive, model_terms
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("two-link")
    >>> terms_disagreement(robot, model_terms(derive(robot))) < 1e-12
    True
    """
    n = robot.n
    try:
        if np.asarray(terms.K).shape[1:] != (n,):
            return float("inf")
        q, qd = _check_states(robot)
        got = term_values(terms, q, qd, robot.prismatic)
    except (IndexError, ValueError, TypeError, KeyError):
        return float("inf")
    ref = gd_terms(robot, q, qd)
    want = (ref.D_tran, ref.D_rot, ref.h_tran, ref.h_rot, ref.c)
    if not all(np.isfinite(x).all() for x in got + want):
        return float("inf")
    diag = np.abs(np.diagonal(ref.D_tran + ref.D_rot, axis1=1, axis2=2))     # (N, n)
    d_scale = np.sqrt(diag[:, :, None] * diag[:, None, :])
    d_scale = np.maximum(d_scale, _FLOOR * d_scale.max(initial=0.0))
    worst = 0.0
    for g, w in zip(got[:2], want[:2]):
        worst = max(worst, _ratio(np.abs(g - w), d_scale))
    # the arm's torque at the check states: D times 1 rad/s^2 or its largest qd^2, h, c; a
    # quantity that is zero up to round-off (h of a one-joint arm, c along a joint axis, a
    # massless link's parts) is measured against it, not against its own round-off
    parts = [sum(np.abs(w) for w in group).max(axis=0) for group in (want[2:4], want[4:])]
    arm = max(float(d_scale.max(initial=0.0)) * max(1.0, float(np.abs(qd).max()) ** 2),
              *(float(p.max(initial=0.0)) for p in parts))
    for parts_got, parts_want, scale in ((got[2:4], want[2:4], parts[0]),
                                         (got[4:], want[4:], parts[1])):
        scale = np.maximum(scale, _FLOOR * arm)
        for g, w in zip(parts_got, parts_want):
            worst = max(worst, _ratio(np.abs(g - w), scale))
    return worst


def _ratio(err, scale):
    """max err / scale; an exact 0 where the scale is 0 and the error too; inf otherwise."""
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(err == 0.0, 0.0, err / scale)
    r = np.nan_to_num(r, nan=np.inf, posinf=np.inf)
    return float(r.max(initial=0.0))
