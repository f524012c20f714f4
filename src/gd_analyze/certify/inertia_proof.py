"""A proof that a pruned model's inertia matrix D_s is positive definite over a box of q.

Two parts, both rounded outward:

1. A floor under the exact D, the same at every q: D(q) >= diag(f) in the Loewner order
   (:func:`inertia_floor`). Joint k's velocity x_k moves link k by x_k s_k = V_k - X_k V_(k-1)
   (V_k: the link's spatial velocity, s_k: the joint's axis, X_k: the transform from link k-1,
   Fu, Gonzalez & Lee 1987, Eq. 3.2-27 for the kinetic energy); with N_k = g_k s_k s_k^T,
   N_k <= M_k and X_k^T N_k X_k <= M_(k-1) (M_k: link k's spatial inertia), so that
   x_k^2 g_k <= 2 V_k^T M_k V_k + 2 V_(k-1)^T M_(k-1) V_(k-1), and summing over the links,
   x^T D x >= sum_k (g_k / 4 + Ia_k) x_k^2 (or, with Young's inequality weighted along the
   chain, x^T D x >= sum_k (t + Ia_k) x_k^2 for the largest t that keeps every link's energy
   counted at most once). Both conditions read g_k u^T M^-1 u <= 1 for a
   vector u that depends on no joint position (X_k^T s_k is P_k z, or (t_k x P_k z, P_k z)
   for a prismatic joint), so f is a constant per joint; each g_k is checked by a
   preconditioned Gershgorin test of M - g_k u u^T (Horn & Johnson, *Matrix Analysis*, 2nd ed.
   2013, Thm. 6.1.1 and 4.5.8) with the rounding of every product bounded.
2. The dropped part, D - D_s = Delta D(q), enclosed over boxes of positions by the
   Newton-Euler recursion in interval arithmetic
   (:func:`gd_analyze.certify.regressor_bounds.inertia_enclosure`), split where the
   bound is not yet good (branch and bound, Moore, Kearfott & Cloud 2009, Ch. 6; only the
   joints D depends on: never joint 1). On each box, D_s = D - Delta D >= diag(f) - Delta D,
   whose smallest eigenvalue is bounded from below by Gershgorin's discs (weighted by
   sqrt(f)).

So lambda_min(D_s(q)) >= L at every q of the box (kg m^2 on revolute joints; for prismatic
joints the matrix mixes kg m^2, kg m and kg, q in rad and m). The margin is stated against an
upper bound of min over the box of lambda_min(D): the Rayleigh quotient v^T D(q*) v / v^T v,
enclosed, at the sampled position q* where D's smallest eigenvalue is least, v its
eigenvector. Samples never prove; they only find a counterexample quickly.
Pure: no files.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..dynamics.base_parameters import standard_parameters
from ..symbolic.pruning import part_values
from . import intervals as iv
from .regressor_bounds import inertia_enclosure, inertia_form_enclosure

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot

__all__ = ["SAMPLES", "MAX_BOXES", "InertiaProof", "inertia_floor", "gershgorin_lower",
           "prove_inertia", "inertia_context", "dropped_inertia_values"]

#: Positions sampled for a counterexample and for the upper bound of min lambda_min(D).
SAMPLES = 2000
#: Boxes the branch and bound may evaluate.
MAX_BOXES = 1024
_U = iv.ROUNDING


@dataclass(frozen=True, eq=False)
class InertiaProof:
    """The outcome of :func:`prove_inertia`.

    Attributes
    ----------
    proved : bool
        lambda_min(D_s(q)) >= ``lower`` > 0 at every q of the box [q_min, q_max].
    lower : float
        The proved lower bound of lambda_min(D_s) over the box [kg m^2] (-inf when not proved).
    floor : ndarray, shape (n,)
        f: D(q) >= diag(f) at every q [kg m^2; kg].
    dropped_norm : float
        Upper bound of the spectral norm of the scaled Delta D over the box (0 when nothing
        inertial is dropped) [1].
    d_upper : float
        Upper bound of min over the box of lambda_min(D) [kg m^2] (the Rayleigh quotient at
        ``witness``).
    witness : ndarray, shape (n,)
        Where [rad or m].
    sampled_min : float
        The least lambda_min(D_s) found at the sampled positions [kg m^2] (a counterexample
        when <= 0).
    boxes : int
        Boxes evaluated.
    samples : int
        Positions sampled.
    seconds : float
        Wall time [s].
    why : str
        Why it is not proved ("" when proved).
    """

    proved: bool
    lower: float
    floor: np.ndarray
    dropped_norm: float
    d_upper: float
    witness: np.ndarray
    sampled_min: float
    boxes: int
    samples: int
    seconds: float
    why: str = ""

    @property
    def ratio(self) -> float:
        """float: ``lower / d_upper``: min lambda_min(D_s) >= ratio x min lambda_min(D) over
        the box (NaN when not proved)."""
        if not self.proved or not self.d_upper > 0:
            return float("nan")
        return float(np.nextafter(self.lower / self.d_upper, -np.inf))


def gershgorin_lower(lo: np.ndarray, hi: np.ndarray, weights: np.ndarray | None = None
                     ) -> np.ndarray:
    """A lower bound of lambda_min over symmetric interval matrices, by Gershgorin's discs.

    Parameters
    ----------
    lo, hi : ndarray, shape (B, n, n)
        Element-wise enclosures; every symmetric matrix within them counts.
    weights : ndarray, shape (B, n) or (n,), optional
        Positive weights w of the discs of W^-1 A W (W = diag(w)); default 1.

    Returns
    -------
    ndarray, shape (B,)
        min_i (lo_ii - sum_(j != i) max(|lo_ij|, |hi_ij|) w_j / w_i), rounded down.

    Notes
    -----
    Every eigenvalue of A lies in a disc of W^-1 A W (a similarity), and a symmetric A's are
    real (Horn & Johnson 2013, Thm. 6.1.1).

    Examples
    --------
    >>> A = np.array([[[2.0, 1.0], [1.0, 2.0]]])
    >>> v = float(gershgorin_lower(A, A)[0])
    >>> 0.99999 < v < 1.0
    True
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    B, n, _ = lo.shape
    idx = np.arange(n)
    F = np.maximum(np.abs(lo), np.abs(hi))
    F[:, idx, idx] = 0.0
    w = np.ones((B, n)) if weights is None else np.broadcast_to(
        np.asarray(weights, float), (B, n))
    rad = np.einsum("bij,bj->bi", F, w) / w * (1 + 4 * (n + 2) * _U)
    return np.nextafter(np.nextafter(lo[:, idx, idx] - rad, -np.inf), -np.inf).min(axis=1)


def _certified_pd(A):
    """Whether the point symmetric matrices A (B, m, m) are positive definite: Gershgorin's
    discs of X A X^T with X = Lambda^-1/2 V^T of A's computed eigenvectors (a congruence),
    every rounding of the products bounded (Higham 2002, Sec. 3.5: |fl(XY) - XY| <=
    gamma_m |X| |Y|)."""
    A = np.asarray(A, float)
    m = A.shape[-1]
    lam, V = np.linalg.eigh(A)
    ok = lam[:, 0] > 0
    X = np.swapaxes(V, 1, 2) / np.sqrt(np.where(lam > 0, lam, 1.0))[:, :, None]
    P = X @ A @ np.swapaxes(X, 1, 2)
    aX = np.abs(X)
    err = 4 * (m + 2) * _U * (aX @ np.abs(A) @ np.swapaxes(aX, 1, 2)) * (1 + 1e-6)
    return ok & (gershgorin_lower(P - err, P + err) > 0)


def _skew(c):
    return np.array([[0.0, -c[2], c[1]], [c[2], 0.0, -c[0]], [-c[1], c[0], 0.0]])


def _spatial(p):
    """The spatial inertia about the link frame's origin, (omega, v) ordered."""
    I = np.array([[p[0], p[1], p[2]], [p[1], p[3], p[4]], [p[2], p[4], p[5]]])
    M = np.zeros((6, 6))
    M[:3, :3], M[:3, 3:], M[3:, :3] = I, _skew(p[6:9]), _skew(p[6:9]).T
    M[3:, 3:] = p[9] * np.eye(3)
    return M


def _largest_g(M, u):
    """A certified g >= 0 with M - g u u^T positive semidefinite (0 when none is found); rows
    and columns of M that are exactly 0 (a thin rod about its own axis) are left out, where u
    is 0 too."""
    keep = np.any(M != 0, axis=1)
    if np.any(u[~keep] != 0):
        return 0.0
    M, u = M[np.ix_(keep, keep)], u[keep]
    if u.size == 0:
        return 0.0
    Mp = np.linalg.pinv(M)
    a = float(u @ Mp @ u)
    if not (np.isfinite(a) and a > 0):
        return 0.0
    g = 1.0 / a
    for shrink in (1e-3, 1e-2, 0.1, 0.5):
        trial = g * (1 - shrink)
        if _certified_pd((M - trial * np.outer(u, u))[None])[0]:
            return float(np.nextafter(trial, 0.0))
    return 0.0


def _link_capacities(robot):
    """(A, B): A_k the largest certified g with g (s_k^T V)^2 <= V^T M_k V for every V
    (A_1 = s_1^T M_1 s_1: the first link moves about its axis only), B_k the same for
    (u_k^T V)^2 and M_(k-1), u_k = X_k^T s_k (B_1 on the line of s_1; inf where u_k is
    orthogonal to it); the index k (int) of the first link whose spatial inertia is not
    certified semidefinite along its joint (the argument needs every link's energy to be
    non-negative)."""
    phi = standard_parameters(robot)
    n = robot.n
    A, B = np.zeros(n), np.full(n, np.inf)
    S = np.zeros((n, 6))        # each joint's axis, (omega, v) ordered
    S[np.arange(n), np.where(np.asarray(robot.prismatic, bool), 5, 2)] = 1.0
    for k, s in enumerate(S):
        M = _spatial(phi[k])
        A[k] = float(np.nextafter(s @ M @ s * (1 - 4 * _U), 0.0)) if k == 0 else \
            _largest_g(M, s)
        if not A[k] > 0:
            return k
        if k == 0:
            continue
        P, t = np.asarray(robot.rotation[k], float), np.asarray(robot.translation[k], float)
        z = P[:, 2]
        u = np.concatenate([np.cross(t, z), z]) if robot.prismatic[k] else \
            np.concatenate([z, np.zeros(3)])
        prev = _spatial(phi[k - 1])
        if k == 1:          # V_0 moves about s_0 only: the condition on that line
            e = float(S[0] @ prev @ S[0]) * (1 - 4 * _U)
            c = float(u @ S[0]) ** 2 * (1 + 4 * _U)
            B[k] = np.inf if c == 0 else (e / c if e > 0 else 0.0)
        else:
            B[k] = _largest_g(prev, u)
    return A, B


def _chain_feasible(t, A, B):
    """Whether x_k^2 t summed over k stays below the links' energies: Young's inequality
    x_k^2 <= (1 + a_k) (s_k^T V_k)^2 + (1 + 1/a_k) (u_k^T V_(k-1))^2 with the least a_k each
    link's remaining capacity allows, in chain order; every coefficient of a link's energy
    at most 1 (rounded up)."""
    up = 1 + 16 * _U
    left = 1 - t / A[0] * up
    for k in range(1, A.size):
        if left < 0:
            return False
        if np.isinf(B[k]):
            a = 1e-12
        else:
            room = left * B[k] / t / up
            if room <= 1:
                return False
            a = 1 / (room - 1) * up
        left = 1 - t * (1 + a) / A[k] * up
    return left >= 0


def inertia_floor(robot: Robot, kind: str = "chain") -> np.ndarray:
    """f with D(q) >= diag(f) at every q (Loewner order), from the links' own inertias.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    kind : {"chain", "pairs"}, optional
        ``"pairs"``: f_k = min(A_k, B_k) / 4 + Ia_k, each link's energy counted twice with
        equal weights; ``"chain"`` (default): one f = t + Ia_k with the largest t for which
        Young's inequality with weights chosen along the chain holds (bisection).

    Returns
    -------
    ndarray, shape (n,)
        [kg m^2; kg], rounded down: A_k the largest certified g with g (s_k^T V)^2 <= V^T M_k
        V for every V, B_k the same for (u_k^T V)^2 <= V^T M_(k-1) V, u_k = X_k^T s_k (the
        first link moves about its axis only: A_1 = s_1^T M_1 s_1); all 0 (no floor) when a
        link's spatial inertia is not certified positive semidefinite in the direction of its
        joint (a singular inertia, e.g. a point mass).

    Raises
    ------
    ValueError
        If ``kind`` is unknown.

    Notes
    -----
    x^T D x = sum_k V_k^T M_k V_k + sum_k Ia_k x_k^2 (Fu, Gonzalez & Lee 1987, Eq. 3.2-27
    with the drives' armature), and x_k = s_k^T V_k - u_k^T V_(k-1) (s_k a unit vector) gives
    x_k^2 <= (1 + a) (s_k^T V_k)^2 + (1 + 1/a) (u_k^T V_(k-1))^2 <= (1 + a) V_k^T M_k V_k /
    A_k + (1 + 1/a) V_(k-1)^T M_(k-1) V_(k-1) / B_k; summed with weights w_k, x^T D x >=
    sum_k w_k x_k^2 wherever each link's energy gets a total coefficient of at most 1.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> bool((inertia_floor(load_robot("puma560")) > 0).all())
    True
    """
    if kind not in ("chain", "pairs"):
        raise ValueError(f"kind must be 'chain' or 'pairs', got {kind!r}")
    n = robot.n
    arm = np.asarray(robot.armature, float)
    caps = _link_capacities(robot)
    if isinstance(caps, int):
        return np.zeros(n)
    A, B = caps
    if kind == "pairs":
        g = np.minimum(A, B) / 4
    else:
        lo, hi = 0.0, float(A.min())
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if _chain_feasible(mid, A, B) else (lo, mid)
        g = np.full(n, lo if lo > 0 and _chain_feasible(lo, A, B) else 0.0)
    f = g * (1 - 4 * _U) + arm
    return np.nextafter(f, -np.inf).clip(min=0.0)


def dropped_inertia_values(base: BaseParameters, left_out: np.ndarray) -> np.ndarray:
    """The inertial values a model leaves out, per link.

    Parameters
    ----------
    base : BaseParameters
        The b base parameters.
    left_out : ndarray of bool, shape (b, 3)
        The pairs left out.

    Returns
    -------
    ndarray, shape (n, 10)
        beta in the independent slots of the parameters whose inertial part is left out, 0
        elsewhere (:func:`gd_analyze.symbolic.pruning.part_values`): D - D_s is the D of
        these values.
    """
    left = np.asarray(left_out, bool)
    keep_only = np.ones_like(left)
    keep_only[:, 0] = ~left[:, 0]
    return part_values(base, keep_only)[0]


def _relevant(robot):
    """Joints D depends on: all but the first (D is invariant when the whole arm moves
    about or along joint 1)."""
    rel = np.ones(robot.n, bool)
    rel[0] = False
    return rel


def _d_upper(robot, values, q):
    """Upper bound of min_q lambda_min(D) over the given positions, and where."""
    lo, hi = inertia_enclosure(robot, q, q, values)
    D = 0.5 * (lo + hi)
    lam, V = np.linalg.eigh(D)
    k = int(np.argmin(lam[:, 0]))
    v = V[k][:, 0]
    _, top = inertia_form_enclosure(robot, q[k:k + 1], q[k:k + 1], values, v[None, None, :])
    norm = float(v @ v) * (1 - 2 * (robot.n + 2) * _U)
    return float(np.nextafter(top[0, 0, 0] / norm, np.inf)), q[k].copy()


def inertia_context(robot: Robot, base: BaseParameters, q_min: ArrayLike, q_max: ArrayLike,
                    samples: int = SAMPLES, seed: int = 0) -> dict:
    """What :func:`prove_inertia` computes once for a box, whatever is dropped.

    Parameters
    ----------
    robot : Robot
    base : BaseParameters
    q_min, q_max : array_like, shape (n,)
        The box [rad or m].
    samples : int, optional
    seed : int, optional

    Returns
    -------
    dict
        ``floor`` (:func:`inertia_floor`), ``floors`` (it, the ``"pairs"`` floor and their
        mean: each holds, so the proof takes the best on each box), ``d_upper`` and
        ``witness`` (the Rayleigh bound of
        min lambda_min(D) and where), ``q`` (the sampled positions, with the box's corners
        q_min, q_max and its centre) and ``D`` (D at them, shape (M, n, n)); its arrays
        read-only. Made once per process for the same arm (the same object), parameter
        values, box, ``samples`` and ``seed`` (the last two of :data:`_CONTEXTS_MAX` kept).
    """
    n = robot.n
    q_min, q_max = np.asarray(q_min, float), np.asarray(q_max, float)
    full = part_values(base, np.zeros((len(base.beta), 3), bool))[0]
    key = b"".join(np.ascontiguousarray(a, float).tobytes() for a in (
        full, q_min, q_max, np.array([samples, seed], float)))
    for kept_robot, kept_key, context in _CONTEXTS:
        if kept_robot is robot and kept_key == key:
            return context
    rng = np.random.default_rng(seed)
    qs = np.vstack([rng.uniform(q_min, q_max, (samples, n)), q_min, q_max,
                    0.5 * (q_min + q_max)])
    d_upper, witness = _d_upper(robot, full, qs)
    lo, hi = inertia_enclosure(robot, qs, qs, full)
    chain, pairs = inertia_floor(robot), inertia_floor(robot, "pairs")
    context = {"floor": chain, "floors": np.stack([chain, pairs, 0.5 * (chain + pairs)]),
               "d_upper": d_upper, "witness": witness, "q": qs, "D": 0.5 * (lo + hi)}
    for value in context.values():
        if isinstance(value, np.ndarray):
            value.setflags(write=False)     # one object for every caller
    _CONTEXTS[:] = [(robot, key, context)] + _CONTEXTS[:_CONTEXTS_MAX - 1]
    return context


#: The contexts :func:`inertia_context` made in this process, newest first: the arm (by
#: identity), the key of its parameters' values, the box, ``samples`` and ``seed``, and the
#: context. A main job asks for the same one twice (the region search's
#: :func:`gd_analyze.certify.positive_definite.inertia_restored` and the deployed model's
#: :func:`gd_analyze.certify.positive_definite.with_inertia_check`).
_CONTEXTS: list[tuple[Robot, bytes, dict]] = []
_CONTEXTS_MAX = 2
#: The proofs :func:`prove_inertia` made in this process on a context of :data:`_CONTEXTS`:
#: by the context's identity, the dropped inertial values, the box and the settings, each
#: with its context (so that the identity stays its own while the entry is kept).
_PROOFS: dict[tuple, tuple[dict, Robot, InertiaProof]] = {}
_PROOFS_MAX = 64


def prove_inertia(robot: Robot, base: BaseParameters, left_out: np.ndarray, q_min: ArrayLike,
                  q_max: ArrayLike, max_boxes: int = MAX_BOXES, samples: int = SAMPLES,
                  seed: int = 0, rtol: float = 0.5, context: dict | None = None
                  ) -> InertiaProof:
    """Prove lambda_min(D_s(q)) >= L > 0 at every q of a box of positions.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    left_out : ndarray of bool, shape (b, 3)
        The pairs the model leaves out (only the inertial column is read); all False for a
        model that keeps every inertial part (the exact explicit one: D_s = D).
    q_min, q_max : array_like, shape (n,)
        The box [rad or m].
    max_boxes : int, optional
        Boxes the branch and bound may evaluate.
    samples : int, optional
        Positions sampled for a counterexample and for the upper bound of lambda_min(D).
    seed : int, optional
    rtol : float, optional
        A box is split while its bound is below (1 - rtol) times the least bound found at
        a box's centre.
    context : dict, optional
        :func:`inertia_context` of the same box, samples and seed, if already computed.

    Returns
    -------
    InertiaProof

    Notes
    -----
    D_s = D - Delta D >= diag(f) - Delta D on each box, f each of the floors of
    :func:`inertia_context` (the best bound of the three on each box),
    Delta D enclosed by :func:`gd_analyze.certify.regressor_bounds.inertia_enclosure`;
    the smallest eigenvalue of diag(f) - Delta D is bounded by :func:`gershgorin_lower`
    with weights sqrt(f). The bound is the least over the final boxes, which tile the box.

    A proof is made once per process for the same arm, context of :func:`inertia_context`
    (which makes each context once), dropped inertial values, box and settings: the main
    job's region search decides what its model restores by the very proofs the deployed
    model's check then makes (:mod:`gd_analyze.certify.positive_definite`).
    """
    t0 = time.perf_counter()
    q_min, q_max = np.asarray(q_min, float), np.asarray(q_max, float)
    drop = dropped_inertia_values(base, left_out)
    ctx = context if context is not None else inertia_context(robot, base, q_min, q_max,
                                                               samples, seed)
    key = (id(ctx), id(robot), drop.tobytes(), q_min.tobytes(), q_max.tobytes(),
           int(max_boxes), int(samples), int(seed), float(rtol))
    kept = _PROOFS.get(key)
    if kept is not None and kept[0] is ctx and kept[1] is robot:
        return kept[2]
    proof = _prove(robot, drop, q_min, q_max, max_boxes, rtol, ctx, t0)
    if any(r is robot and c is ctx for r, _, c in _CONTEXTS):   # this process's: kept
        for old in list(_PROOFS)[:max(len(_PROOFS) - _PROOFS_MAX + 1, 0)]:
            _PROOFS.pop(old, None)          # the oldest (a snapshot: another thread may add)
        _PROOFS[key] = (ctx, robot, proof)
    return proof


def _prove(robot, drop, q_min, q_max, max_boxes, rtol, ctx, t0):
    """:func:`prove_inertia`'s proof of the dropped inertial values ``drop`` (n, 10) on the
    context ``ctx`` (:func:`inertia_context`)."""
    n = robot.n
    floor, d_upper, witness, qs = ctx["floor"], ctx["d_upper"], ctx["witness"], ctx["q"]
    floors = ctx["floors"]
    Ds = ctx["D"]
    if np.any(drop):
        lo, hi = inertia_enclosure(robot, qs, qs, drop, armature=np.zeros(n))
        Ds = Ds - 0.5 * (lo + hi)
    sampled = float(np.linalg.eigvalsh(Ds)[:, 0].min())

    def result(proved, lower, norm, boxes, why=""):
        return InertiaProof(proved=proved, lower=lower, floor=floor, dropped_norm=norm,
                            d_upper=d_upper, witness=witness, sampled_min=sampled,
                            boxes=boxes, samples=qs.shape[0],
                            seconds=time.perf_counter() - t0, why=why)
    if not (floor > 0).all():
        k = _link_capacities(robot)
        return result(False, -np.inf, np.nan, 0, "no floor under D: " + (
            f"link {k + 1}'s spatial inertia gives none" if isinstance(k, int) else
            "the links' inertias give none along the chain"))
    if sampled <= 0:
        return result(False, -np.inf, np.nan, 0,
                      f"D_s has eigenvalue {sampled:.3g} at a sampled position")
    idx = np.arange(n)

    def bounds(a, b):
        """Lower bounds of lambda_min(diag(f) - Delta D) over boxes (the best of the floors,
        each of which holds), and the magnitudes of Delta D."""
        dl, dh = inertia_enclosure(robot, a, b, drop, armature=np.zeros(n))
        best = np.full(a.shape[0], -np.inf)
        for f in floors:
            if not (f > 0).all():
                continue
            Alo, Ahi = -dh, -dl
            Alo[:, idx, idx] = np.nextafter(Alo[:, idx, idx] + f, -np.inf)
            Ahi[:, idx, idx] = np.nextafter(Ahi[:, idx, idx] + f, np.inf)
            best = np.maximum(best, gershgorin_lower(Alo, Ahi, np.sqrt(f)))
        return best, np.maximum(np.abs(dl), np.abs(dh))

    if not np.any(drop):
        lower = float(np.nextafter(floor.min(), -np.inf))
        return result(lower > 0, lower, 0.0, 0)
    rel = _relevant(robot)
    span = np.where(rel & (q_max > q_min), q_max - q_min, 1.0)
    lo, hi = q_min[None, :].copy(), q_max[None, :].copy()
    lo[:, ~rel] = hi[:, ~rel] = q_min[~rel]
    leaves, evaluated, best, norm = [], 0, np.inf, 0.0
    while lo.shape[0]:
        ell, mag = bounds(lo, hi)
        c = 0.5 * (lo + hi)
        centre, _ = bounds(c, c)
        evaluated += lo.shape[0]
        best = min(best, float(centre.min()))
        if best <= 0:
            return result(False, -np.inf, np.nan, evaluated,
                          "diag(f) - Delta D is not Gershgorin-definite at a box centre: the "
                          "dropped inertia exceeds the floor under D")
        split = ell < (1 - rtol) * best
        if not split.any() or evaluated + 2 * int(split.sum()) > max_boxes:
            leaves.append(ell)
            norm = max(norm, float((mag / np.sqrt(np.outer(floor, floor))).sum(2).max()))
            break
        leaves.append(ell[~split])
        norm = max(norm, float((mag[~split] / np.sqrt(np.outer(floor, floor))).sum(2).max())
                   if (~split).any() else 0.0)
        lo, hi = lo[split], hi[split]
        width = np.where(rel[None, :], (hi - lo) / span, -1.0)
        d = width.argmax(axis=1)
        rows = np.arange(lo.shape[0])
        mid = 0.5 * (lo[rows, d] + hi[rows, d])
        lo2, hi2 = lo.copy(), hi.copy()
        hi[rows, d] = mid
        lo2[rows, d] = mid
        lo, hi = np.vstack([lo, lo2]), np.vstack([hi, hi2])
    lower = float(np.concatenate(leaves).min())
    if lower > 0:
        return result(True, lower, norm, evaluated)
    return result(False, lower, norm, evaluated,
                  f"the dropped inertia is not bounded below the floor under D in "
                  f"{evaluated} boxes")
