"""The explicit (closed-form) G-D model of a robot, and its pruning term by term.

Derivation (:func:`derive`), from the robot's joint model (placements P_i, t_i; revolute and
prismatic joints) and link inertial parameters, in the canonical Fourier form of
:class:`~gd_analyze.symbolic.trigpoly.TrigPoly` (sums of numeric coefficients times cos or sin of
integer combinations of the revolute joint angles, times powers of the prismatic joint
variables, which enter the kinematics polynomially):

- D_tran, Eq. (3.4-25) 2nd term: D_tran(i, j) = sum_{s >= j} m_s Jv_s[:, i] . Jv_s[:, j]
  (i <= j). The Jacobian columns are taken in body frame i (joint i turns about its z axis
  through its origin; the dot product does not depend on the frame), so D(i, j) never carries
  q_1 .. q_i and no cancellation is left to chance.
- D_rot, Eq. (3.4-25) 1st term: D_rot(i, j) = sum_{s >= j} u_si^T I_s u_sj with u_si the axis
  of joint i expressed in body frame s.
- h_tran, h_rot, Eqs. (3.4-26), (3.4-27): each part is the inertial force of its own kinetic
  energy (1/2 qd^T D_tran qd, resp. 1/2 qd^T D_rot qd), so it is given by the Christoffel
  symbols of that part: h_i = sum_{j <= k} C_ijk qd_j qd_k with
  C_ijk = Gamma_ijk + Gamma_ikj (j < k), C_ijj = Gamma_ijj,
  Gamma_ijk = d D_ij / d theta_k - 1/2 d D_jk / d theta_i.
- c, Eq. (3.4-28): c = dV/dq with V = -sum_s m_s g . rbar_s.

Pruning (:func:`prune`): every term (a coefficient times a cos or sin, times qdd_j, qd_j qd_k or
nothing) contributes to the joint torques along a trajectory. Terms are pruned by atoms
(:func:`atoms`: one harmonic of a class of proportional groups, so shared structure survives);
with the error budget rule the dropped atoms' peak contributions sum to at most
EPS x scale_i for every joint i, so by the triangle inequality the pruned model's error on that
trajectory is within EPS x scale_i.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from .trigpoly import TrigPoly

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["ExplicitModel", "derive", "Term", "model_terms", "merge_parts", "atoms",
           "term_peaks", "budget_drop", "prune", "PART_KINDS"]

#: The parts of a model's terms: the two G-D parts of D and h, and gravity.
PART_KINDS = ("tran", "rot", "grav")


def _snap(x):
    """cos/sin of a DH twist: exact 0 and +-1 where rounding left 6e-17 and 0.9999999999999999."""
    for v in (0.0, 1.0, -1.0):
        if abs(x - v) < 1e-12:
            return v
    return float(x)


@dataclass(frozen=True, eq=False)
class ExplicitModel:
    """The closed-form G-D terms of a robot, Eqs. (3.4-24) to (3.4-28).

    Attributes
    ----------
    n : int
        Number of joints.
    offset : ndarray, shape (n,)
        Joint offsets; the polynomials are in theta = q + offset [rad].
    D_tran, D_rot : dict
        (i, j) with i <= j (0-based) -> TrigPoly [kg m^2].
    h_tran, h_rot : dict
        (i, j, k) with j <= k -> TrigPoly: the coefficient of qd_j qd_k in h_i [kg m^2].
    c : dict
        i -> TrigPoly [N m].

    Notes
    -----
    Source: Fu, Gonzalez & Lee (1987), Eqs. (3.4-24) to (3.4-28), in Jacobian and Christoffel
    form (module docstring).
    """

    n: int
    offset: np.ndarray
    D_tran: dict
    D_rot: dict
    h_tran: dict
    h_rot: dict
    c: dict

    def theta(self, q: ArrayLike) -> np.ndarray:
        """The angles of the polynomials.

        Parameters
        ----------
        q : array_like, shape (N, n)
            Joint positions [rad].

        Returns
        -------
        ndarray, shape (N, n)
            theta = q + offset [rad].
        """
        return np.atleast_2d(np.asarray(q, float)) + self.offset

    def terms(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, ...]:
        """Evaluate D_tran, D_rot (N, n, n), h_tran, h_rot, c (N, n) at set points.

        Parameters
        ----------
        q, qd : ndarray, shape (N, n)
            Joint positions [rad] and velocities [rad/s].

        Returns
        -------
        tuple of ndarray
            D_tran, D_rot [kg m^2], h_tran, h_rot, c [N m].
        """
        th = self.theta(q)
        qd = np.atleast_2d(np.asarray(qd, float))
        N, n = th.shape
        out: list[np.ndarray] = []
        for Dp in (self.D_tran, self.D_rot):
            D = np.zeros((N, n, n))
            for (i, j), p in Dp.items():
                D[:, i, j] = D[:, j, i] = p(th)
            out.append(D)
        for hp in (self.h_tran, self.h_rot):
            h = np.zeros((N, n))
            for (i, j, k), p in hp.items():
                h[:, i] += p(th) * qd[:, j] * qd[:, k]
            out.append(h)
        c = np.zeros((N, n))
        for i, p in self.c.items():
            c[:, i] = p(th)
        out.append(c)
        return tuple(out)


def _vec(n, values, lin=None):
    return [v if isinstance(v, TrigPoly) else TrigPoly.const(n, v, lin) for v in values]


def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _matvec(M, v):
    """M (3x3 list of TrigPoly or float) times v (3 TrigPoly)."""
    return [sum((M[r][c] * v[c] for c in range(3) if not (isinstance(M[r][c], float)
                                                          and M[r][c] == 0.0)),
                TrigPoly.zero(v[0].n, v[0].lin)) for r in range(3)]


def derive(robot: Robot) -> ExplicitModel:
    """Derive the explicit G-D model of a robot.

    Parameters
    ----------
    robot : Robot
        The arm, revolute and prismatic joints: placements (``rotation`` P_i, ``translation``
        t_i) of the joint model, ``prismatic``, link masses, centres of mass and inertia
        tensors in the body frames (``body_com``, ``body_inertia``), gravity. For a DH robot
        the placements carry d, a, alpha and the offsets.

    Returns
    -------
    ExplicitModel
        In the joint variables q (the offsets are part of the placements): harmonics of the
        revolute q_i [rad] times powers of the prismatic q_i [m].

    Notes
    -----
    Source: the joint model of :mod:`gd_analyze.model.robot` (^{i-1}T_i = [P_i t_i; 0 1]
    Rot(z, q_i) for a revolute joint, [P_i t_i; 0 1] Trans(0, 0, q_i) for a prismatic one) and
    Eqs. (3.4-24) to (3.4-28) of Fu, Gonzalez & Lee (1987), in the forms given in the module
    docstring: joint i turns about (slides along) the z axis of body frame i, so in body frame i
    the Jacobian column of a point r is e_z x r (e_z for a prismatic joint, whose rotational
    column is 0) and the columns of the later joints are the derivatives of r.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> model = derive(load_robot("two-link"))
    >>> round(model.D_rot[(1, 1)].constant(), 6)      # m2 l^2 / 12
    0.083333
    """
    n = robot.n
    lin = np.asarray(getattr(robot, "prismatic", np.zeros(n, bool)), bool).copy()
    C: list[Any] = [None if lin[i] else TrigPoly.cos(n, i, lin) for i in range(n)]
    S: list[Any] = [None if lin[i] else TrigPoly.sin(n, i, lin) for i in range(n)]
    P = np.vectorize(_snap)(np.asarray(robot.rotation, float))
    t = np.where(np.abs(np.asarray(robot.translation, float)) < 1e-15, 0.0,
                 np.asarray(robot.translation, float))
    zero = TrigPoly.zero(n, lin)
    # R_i = P_i Rot(z, q_i) (revolute) or P_i (prismatic): entries as TrigPoly
    R: list[list[list[Any]]] = []
    for i in range(n):
        if lin[i]:
            R.append([[float(P[i][a][c]) for c in range(3)] for a in range(3)])
            continue
        rz = [[C[i], -S[i], 0.0], [S[i], C[i], 0.0], [0.0, 0.0, 1.0]]
        R.append([[sum((P[i][a][b] * rz[b][c] for b in range(3)
                        if P[i][a][b] != 0 and not (isinstance(rz[b][c], float)
                                                    and rz[b][c] == 0.0)),
                       zero) for c in range(3)] for a in range(3)])

    def apply(i, v):                     # point v of body frame i in body frame i-1
        out = [sum((R[i][a][b] * v[b] for b in range(3)
                    if not (isinstance(R[i][a][b], float) and R[i][a][b] == 0.0)), zero)
               + float(t[i][a]) for a in range(3)]
        if lin[i]:                       # P_i (v + q_i e_z) + t_i
            d = TrigPoly.var(n, i, lin)
            out = [o + float(P[i][a][2]) * d if P[i][a][2] != 0 else o
                   for a, o in enumerate(out)]
        return out

    com, inertia = np.asarray(robot.body_com, float), np.asarray(robot.body_inertia, float)
    # rounding residue of the link-frame rotations (cos 90 deg = 6e-17) is not a parameter
    com = np.where(np.abs(com) < 1e-15, 0.0, com)
    inertia = np.where(np.abs(inertia) < 1e-15 * max(np.abs(inertia).max(), 1e-300), 0.0,
                       inertia)
    pos = {}                             # pos[(i, s)]: centre of mass of link s in frame i
    for s in range(n):
        v = _vec(n, [float(x) for x in com[s]], lin)
        pos[(s, s)] = v
        for i in range(s, -1, -1):
            v = apply(i, v)
            pos[(i - 1, s)] = v
    ez = _vec(n, [0.0, 0.0, 1.0], lin)
    D_tran, D_rot = {}, {}
    for i in range(n):
        for j in range(i, n):
            acc = zero
            for s in range(j, n):
                if robot.mass[s] == 0:
                    continue
                r = pos[(i, s)]
                Ji = ez if lin[i] else [-r[1], r[0], zero]     # in body frame i
                Jj = Ji if j == i else [x.diff(j) for x in r]
                acc = acc + float(robot.mass[s]) * _dot(Ji, Jj)
            D_tran[(i, j)] = acc
    u = {}                               # u[(s, i)]: axis of joint i in body frame s
    for i in range(n):
        if lin[i]:                       # no rotational Jacobian column
            continue
        v = ez
        u[(i, i)] = v
        for s in range(i + 1, n):
            v = _matvec([[R[s][c][r] for c in range(3)] for r in range(3)], v)    # R_s^T v
            u[(s, i)] = v
    for i in range(n):
        for j in range(i, n):
            acc = zero
            if lin[i] or lin[j]:
                D_rot[(i, j)] = acc
                continue
            for s in range(j, n):
                I = inertia[s]
                Iu = [sum((u[(s, j)][b] * float(I[a, b]) for b in range(3) if I[a, b] != 0),
                          zero) for a in range(3)]
                acc = acc + _dot(u[(s, i)], Iu)
            D_rot[(i, j)] = acc

    def christoffel(D):
        def Dij(i, j):
            return D[(min(i, j), max(i, j))]

        h = {}
        for i in range(n):
            for j in range(n):
                for k in range(j, n):
                    g = Dij(i, j).diff(k) - 0.5 * Dij(j, k).diff(i)
                    if k != j:
                        g = g + Dij(i, k).diff(j) - 0.5 * Dij(k, j).diff(i)
                    if len(g):
                        h[(i, j, k)] = g
        return h

    g = [float(x) for x in robot.gravity]
    V = zero
    for s in range(n):
        if robot.mass[s]:
            V = V - float(robot.mass[s]) * _dot(_vec(n, g, lin), pos[(-1, s)])
    c = {i: V.diff(i) for i in range(n)}
    return ExplicitModel(n=n, offset=np.zeros(n), D_tran=D_tran, D_rot=D_rot,
                         h_tran=christoffel(D_tran), h_rot=christoffel(D_rot), c=c)


@dataclass(frozen=True, eq=False)
class Term:
    """The terms of an explicit model as flat arrays (one row per term).

    Attributes
    ----------
    kind : ndarray of str, shape (U,)
        ``"D"`` (a term of D_ij, i <= j), ``"h"`` (of the coefficient of qd_j qd_k in h_i) or
        ``"c"`` (of c_i).
    part : ndarray of str, shape (U,)
        ``"tran"``, ``"rot"`` or ``"grav"``.
    i, j, k : ndarray of int, shape (U,)
        Indices (0-based; -1 where unused).
    K : ndarray of int, shape (U, n)
        Harmonic vectors; in the column of a prismatic joint, the power of q_i [m]
        (:mod:`gd_analyze.symbolic.trigpoly`).
    S : ndarray of bool, shape (U,)
        sin (True) or cos (False).
    C : ndarray, shape (U,)
        Coefficients [kg m^2] for D and h, [N m] for c.
    """

    kind: np.ndarray
    part: np.ndarray
    i: np.ndarray
    j: np.ndarray
    k: np.ndarray
    K: np.ndarray
    S: np.ndarray
    C: np.ndarray

    def __len__(self):
        return int(self.C.size)

    def subset(self, mask: ArrayLike) -> Term:
        """The terms where ``mask`` is True.

        Parameters
        ----------
        mask : array_like of bool, shape (U,)

        Returns
        -------
        Term
        """
        mask = np.asarray(mask, bool)
        return Term(*(getattr(self, f)[mask] for f in
                      ("kind", "part", "i", "j", "k", "K", "S", "C")))

    @cached_property
    def _atoms(self):
        """:func:`atoms` of these terms, computed once (the terms never change)."""
        return _atoms(self)

    @cached_property
    def programs(self) -> dict:
        """A memo of the straight-line programs built from subsets of these terms.

        A dict owned by this value (the terms never change), keyed by the caller with the
        SHA-256 of the subset (:func:`gd_analyze.simplify.explicit_model.full_program`).
        """
        return {}


def model_terms(model: ExplicitModel) -> Term:
    """Flatten an :class:`ExplicitModel` into :class:`Term` rows.

    Parameters
    ----------
    model : ExplicitModel

    Returns
    -------
    Term
        D terms (tran then rot), h terms (tran then rot), then c terms.
    """
    rows = []
    part: Any                           # a label in the loops, then the column of labels
    for part, Dp in (("tran", model.D_tran), ("rot", model.D_rot)):
        for (i, j), p in Dp.items():
            rows += [("D", part, i, j, -1, kv, s, cf) for kv, s, cf in p.rows()]
    for part, hp in (("tran", model.h_tran), ("rot", model.h_rot)):
        for (i, j, k), p in hp.items():
            rows += [("h", part, i, j, k, kv, s, cf) for kv, s, cf in p.rows()]
    for i, p in model.c.items():
        rows += [("c", "grav", i, -1, -1, kv, s, cf) for kv, s, cf in p.rows()]
    n = model.n
    if not rows:
        return Term(np.zeros(0, "<U1"), np.zeros(0, "<U4"), *(np.zeros(0, int),) * 3,
                    np.zeros((0, n), int), np.zeros(0, bool), np.zeros(0))
    kind, part, i, j, k, K, S, C = zip(*rows)
    return Term(np.array(kind), np.array(part), np.array(i), np.array(j), np.array(k),
                np.array(K, dtype=np.int64).reshape(-1, n), np.array(S, bool),
                np.array(C, float))


def merge_parts(terms: Term) -> Term:
    """Add the tran and rot terms of one element and harmonic together (part ``"both"``).

    Parameters
    ----------
    terms : Term

    Returns
    -------
    Term
        One row per (kind, i, j, k, harmonic), sorted; gravity rows keep part ``"grav"``.
    """
    acc: dict = {}
    for kind, i, j, k, K, S, C in zip(terms.kind, terms.i, terms.j, terms.k, terms.K,
                                      terms.S, terms.C):
        key = (str(kind), int(i), int(j), int(k), bool(S)) + tuple(int(v) for v in K)
        acc[key] = acc.get(key, 0.0) + float(C)
    keys = sorted(k for k, c in acc.items() if c != 0.0)
    n = terms.K.shape[1]
    if not keys:
        return terms.subset(np.zeros(len(terms), bool))
    return Term(np.array([k[0] for k in keys]),
                np.array(["grav" if k[0] == "c" else "both" for k in keys]),
                np.array([k[1] for k in keys]), np.array([k[2] for k in keys]),
                np.array([k[3] for k in keys]),
                np.array([k[5:] for k in keys], dtype=np.int64).reshape(-1, n),
                np.array([k[4] for k in keys], bool), np.array([acc[k] for k in keys]))


def atoms(terms: Term) -> tuple[Term, np.ndarray]:
    """Group the merged terms into atoms, the units of pruning that keep shared structure.

    A group is the sum of coefficient x cos/sin of one D_ij, one Christoffel coefficient of
    qd_j qd_k in h_i, or one c_i. Groups that are proportional (many Christoffel symbols are
    multiples of one derivative of a D element) form a class, computed once in the emitted
    code; an atom is one harmonic of one class, and pruning drops it from every group of the
    class together, so the groups stay proportional.

    Parameters
    ----------
    terms : Term
        Terms of any parts (tran and rot are merged first, :func:`merge_parts`).

    Returns
    -------
    merged : Term
        The merged terms.
    atom : ndarray of int, shape (M,)
        The atom of each merged term, 0 .. A-1.
    """
    return terms._atoms


def _atoms(terms):
    merged = merge_parts(terms)
    groups = {}
    for r, (kind, i, j, k) in enumerate(zip(merged.kind, merged.i, merged.j, merged.k)):
        groups.setdefault((str(kind), int(i), int(j), int(k)), []).append(r)
    atom = np.zeros(len(merged), np.int64)
    classes, next_id = {}, 0
    for _, rows in sorted(groups.items()):
        ref = merged.C[rows][np.argmax(np.abs(merged.C[rows]))]
        norm = tuple((bool(merged.S[r]),) + tuple(int(v) for v in merged.K[r])
                     + (round(merged.C[r] / ref, 12),) for r in rows)
        if norm not in classes:
            classes[norm] = list(range(next_id, next_id + len(rows)))
            next_id += len(rows)
        atom[rows] = classes[norm]
    return merged, atom


def _entries(terms, atom, n):
    """Where each merged term's contribution goes: (term, joint, velocity column) by atom."""
    isD, ish = terms.kind == "D", terms.kind == "h"
    U = np.arange(len(terms))
    i, j, k = terms.i, np.maximum(terms.j, 0), np.maximum(terms.k, 0)
    # velocity columns of [qdd (n), qd_a qd_b (n*n), 1]
    vcol = np.where(isD, j, np.where(ish, n + j * n + k, n + n * n))
    off = isD & (terms.i != terms.j)
    e_term = np.concatenate([U, U[off]])
    e_joint = np.concatenate([i, j[off]])
    e_vcol = np.concatenate([vcol, i[off]])                  # D_ij qdd_i -> tau_j
    key = atom[e_term] * n + e_joint
    order = np.argsort(key, kind="stable")
    key = key[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    return e_term[order], e_vcol[order], starts, key[starts] // n, key[starts] % n


def term_peaks(terms: Term, offset: np.ndarray, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
               chunk: int = 65536, prismatic: ArrayLike | None = None) -> np.ndarray:
    """Peak |contribution| of every atom of the terms to every joint torque on a trajectory.

    Parameters
    ----------
    terms : Term
        The terms (:func:`model_terms`); their atoms are those of :func:`atoms`.
    offset : ndarray, shape (n,)
        Joint offsets [rad] (0 for a prismatic joint).
    q, qd, qdd : ndarray, shape (N, n)
        Joint positions [rad], velocities [rad/s] and accelerations [rad/s^2] (m, m/s and
        m/s^2 for a prismatic joint).
    chunk : int, optional
        Set points per call of the kernel; memory is O(terms) whatever N is.
    prismatic : array_like of bool, shape (n,), optional
        The prismatic joints (their columns of K are powers of q_i [m]); default none.

    Returns
    -------
    ndarray, shape (A, n)
        Peaks [N m] of |sum of the atom's terms' contributions| (D_ij qdd_j to tau_i and
        D_ij qdd_i to tau_j, the h and c terms to tau_i); they combine over trajectories and
        chunks by taking the maximum; a NaN contribution is never a peak.

    Notes
    -----
    The reduction runs in the compiled kernel
    :func:`gd_analyze.symbolic.term_kernels.atom_peaks_kernel`.
    """
    from .term_kernels import atom_peaks_kernel  # numba: imported by the first call

    merged, atom = atoms(terms)
    q, qd, qdd = (np.atleast_2d(np.asarray(x, float)) for x in (q, qd, qdd))
    n = q.shape[1]
    A = int(atom.max()) + 1 if atom.size else 0
    peaks = np.zeros((A, n))
    if not A:
        return peaks
    key = np.concatenate([merged.S[:, None].astype(np.int64), merged.K], axis=1)
    uniq, hidx = np.unique(key, axis=0, return_inverse=True)
    hidx = hidx.reshape(-1)
    Su, Ku = uniq[:, 0].astype(bool), uniq[:, 1:]
    e_term, e_vcol, starts, g_atom, g_joint = _entries(merged, atom, n)
    lin = np.zeros(n, bool) if prismatic is None else np.asarray(prismatic, bool)
    group_peak = np.zeros(starts.size)
    c = np.ascontiguousarray
    for a in range(0, q.shape[0], max(1, int(chunk))):
        sl = slice(a, a + max(1, int(chunk)))
        atom_peaks_kernel(c(q[sl] + offset), c(qd[sl]), c(qdd[sl]), c(Ku, np.int64), c(Su),
                          lin, c(hidx, np.int64), c(merged.C, float), c(e_term, np.int64),
                          c(e_vcol, np.int64), c(starts, np.int64), group_peak)
    np.maximum.at(peaks, (g_atom, g_joint), group_peak)
    return peaks


def budget_drop(peaks: np.ndarray, budget: np.ndarray,
                fixed: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Greedy selection under the error budget: which units to drop.

    Units are visited in order of increasing peak contribution (relative to the budget of the
    joints they touch); a unit is dropped if, for every joint i, the peaks already dropped plus
    its own stay within ``budget[i]``, and kept otherwise (the walk goes on).

    Parameters
    ----------
    peaks : ndarray, shape (U, n)
        Peak |contribution| of each unit to each joint torque [N m].
    budget : ndarray, shape (n,)
        EPS x scale_i [N m], >= 0.
    fixed : ndarray of bool, shape (U,), optional
        Units that may not be dropped.

    Returns
    -------
    drop : ndarray of bool, shape (U,)
    used : ndarray, shape (n,)
        Sum of the dropped units' peaks per joint; used <= budget, so by the triangle
        inequality the error of the model without them is at most ``used`` at every set point
        where the peaks were taken.
    """
    peaks = np.asarray(peaks, float)
    budget = np.asarray(budget, float)
    U, n = peaks.shape
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(peaks > 0, peaks / np.where(budget > 0, budget, 0.0)[None, :], 0.0)
    rel = np.nan_to_num(rel, nan=np.inf, posinf=np.inf)
    key = rel.max(axis=1) if n else np.zeros(U)
    drop = np.zeros(U, bool)
    used = np.zeros(n)
    for u in np.argsort(key, kind="stable"):
        if fixed is not None and fixed[u]:
            continue
        if not np.isfinite(key[u]):
            break
        new = used + peaks[u]
        if np.all(new <= budget):
            drop[u], used = True, new
    return drop, used


def prune(terms: Term, peaks: np.ndarray,
          budget: np.ndarray | None) -> tuple[Term, np.ndarray, np.ndarray]:
    """Prune the atoms of an explicit model within the budget.

    Parameters
    ----------
    terms : Term
        The terms of the model (any parts).
    peaks : ndarray, shape (A, n)
        Peak contributions of their atoms (:func:`term_peaks`) [N m].
    budget : ndarray, shape (n,) or None
        EPS x scale_i [N m]; None prunes nothing (the terms come back merged).

    Returns
    -------
    kept : Term
        The merged terms of the kept atoms.
    used : ndarray, shape (n,)
        The budget the dropped atoms used [N m].
    dropped : ndarray of bool, shape (A,)
        Which atoms were dropped.
    """
    merged, atom = atoms(terms)
    if budget is None:
        return merged, np.zeros(peaks.shape[1]), np.zeros(peaks.shape[0], bool)
    drop, used = budget_drop(peaks, np.maximum(budget, 0.0))
    return merged.subset(~drop[atom]), used, drop
