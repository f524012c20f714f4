"""The customized recursive Newton-Euler model as straight-line code.

The link-frame recursive Newton-Euler algorithm (Fu, Gonzalez & Lee 1987, Algorithm 3.1 and
Table 3.3) in the customized form of Khalil & Kleinfinger (1987) (parameters J_j, MS_j, M_j
about the body-frame origin, :mod:`.base_parameters`), built symbolically with symengine for
one arm, every intermediate scalar a temporary, the numbers (placements, base parameters,
gravity) as constants:

- forward, in body frame j (R_j = P_j Rot(z, q_j) from frame j-1, p_j the origin of frame j
  in frame j-1; vd_0 = -g, Eq. (3.3-46))::

      w_j  = R_j^T w_{j-1} + qd_j z                                  (revolute)
      wd_j = R_j^T wd_{j-1} + qdd_j z + (R_j^T w_{j-1}) x qd_j z
      vd_j = R_j^T (vd_{j-1} + U_{j-1} p_j)  [+ qdd_j z + 2 w_j x qd_j z, prismatic]
      U_j  = skew(wd_j) + skew(w_j)^2

- link wrench: F_j = M_j vd_j + U_j MS_j, N_j = J_j wd_j + w_j x (J_j w_j) + MS_j x vd_j;
- backward: f_j = F_j + R_{j+1} f_{j+1}, n_j = N_j + R_{j+1} n_{j+1} + p_{j+1} x (R_{j+1}
  f_{j+1}); tau_j = n_j . z (revolute) or f_j . z (prismatic).

The parameters are the base parameters (0 in the dependent slots), so whatever multiplies a
zero folds away; rotations are applied as Rot(z, q)^T (P^T x) with P's near-0/+-1 entries
snapped, identical expressions are built once (hash-consing) and only what tau needs is kept.
The quantities can be split into parts (inertial: qdd, velocity: qd, gravity) for the pruned
models of :mod:`.pruning`.
"""

from __future__ import annotations

import symengine as se
import numpy as np

from ..codegen import Program, _cse
from ..factoring import factor_sum, prune_dead
from .base_parameters import base_parameters

__all__ = ["recursive_program", "exact_program", "parts_program", "PARTS"]

#: The parts of a torque: inertial (qdd), velocity (Coriolis and centrifugal, qd) and gravity.
PARTS = ("a", "v", "g")
ALL = frozenset(PARTS)

#: Entries of placements and parameters within this of 0 or +-1 are exactly 0 or +-1.
_SNAP = 1e-12


def _const(x, scale=1.0):
    """A numeric constant, exactly 0 or +-1 where within _SNAP (relative to scale)."""
    x = float(x)
    if abs(x) <= _SNAP * scale:
        return se.Integer(0)
    if abs(abs(x) - 1.0) <= _SNAP:
        return se.Integer(1 if x > 0 else -1)
    return se.RealDouble(x)


def _is_num(e):
    return isinstance(e, se.Number)


def _atomic(e):
    """Free to use as it is: a number, a symbol or its negation."""
    if _is_num(e) or e.is_Symbol:
        return True
    if e.is_Mul and len(e.args) == 2:
        a, b = e.args
        return (_is_num(a) and float(a) == -1.0 and b.is_Symbol) or \
            (_is_num(b) and float(b) == -1.0 and a.is_Symbol)
    return False


class _Builder:
    """SSA temporaries with hash-consing: identical expressions (or their negations) once."""

    def __init__(self):
        self.assignments = []
        self.table = {}

    def __call__(self, e):
        if _atomic(e):
            return e
        sym = self.table.get(e)
        if sym is not None:
            return sym
        sym = self.table.get(-e)
        if sym is not None:
            return -sym
        sym = se.Symbol(f"t{len(self.assignments)}")
        self.assignments.append((sym, e))
        self.table[e] = sym
        return sym


ZERO3 = (se.Integer(0),) * 3


class _Recursion:
    """Memoized symbolic quantities of the recursion for one arm."""

    def __init__(self, robot, lock_last=False, direct=None):
        self.robot = robot
        self.direct = dict(direct or {})
        self.n = n = robot.n
        self.b = _Builder()
        self.q = [se.Symbol(f"q{i}") for i in range(n)]
        self.qd = [se.Symbol(f"qd{i}") for i in range(n)]
        self.qdd = [se.Symbol(f"qdd{i}") for i in range(n)]
        self.P = [[[_const(v) for v in row] for row in robot.rotation[j]] for j in range(n)]
        tscale = max(float(np.abs(robot.translation).max(initial=0.0)), 1.0)
        self.t = [[_const(v, tscale) for v in robot.translation[j]] for j in range(n)]
        g = np.asarray(robot.gravity, float)
        gs = max(float(np.abs(g).max(initial=0.0)), 1.0)
        self.minus_g = tuple(_const(-v, gs) for v in g)
        self.prismatic = [bool(p) for p in robot.prismatic]
        # joints whose angle is replaced by 0 (the torques do not depend on it)
        self.locked = [False] * n
        if lock_last and not self.prismatic[n - 1]:
            self.locked[n - 1] = True
        self._memo = {}

    # --- helpers -----------------------------------------------------------------------
    def memo(self, key, fn):
        if key not in self._memo:
            self._memo[key] = fn()
        return self._memo[key]

    def vec(self, exprs):
        return tuple(self.b(e) for e in exprs)

    def trig(self, j):
        if self.locked[j]:
            return se.Integer(1), se.Integer(0)
        return self.memo(("cs", j), lambda: (self.b(se.cos(self.q[j])),
                                             self.b(se.sin(self.q[j]))))

    def rot_t(self, j, x):
        """R_j^T x = Rot(z, q_j)^T (P_j^T x) (x in frame j-1, result in frame j)."""
        if all(e == 0 for e in x):
            return ZERO3
        P = self.P[j]
        y = self.vec([P[0][k] * x[0] + P[1][k] * x[1] + P[2][k] * x[2] for k in range(3)])
        if self.prismatic[j]:
            return y
        c, s = self.trig(j)
        return self.vec([c * y[0] + s * y[1], c * y[1] - s * y[0], y[2]])

    def rot(self, j, x):
        """R_j x = P_j (Rot(z, q_j) x) (x in frame j, result in frame j-1)."""
        if all(e == 0 for e in x):
            return ZERO3
        if self.prismatic[j]:
            y = x
        else:
            c, s = self.trig(j)
            y = self.vec([c * x[0] - s * x[1], s * x[0] + c * x[1], x[2]])
        P = self.P[j]
        return self.vec([P[k][0] * y[0] + P[k][1] * y[1] + P[k][2] * y[2] for k in range(3)])

    def p(self, j):
        """Origin of frame j in frame j-1: t_j (+ q_j P_j z, prismatic)."""
        t = self.t[j]
        if not self.prismatic[j]:
            return tuple(t)
        return self.vec([t[k] + self.q[j] * self.P[j][k][2] for k in range(3)])

    def cross(self, a, b):
        return self.vec([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                         a[0] * b[1] - a[1] * b[0]])

    # --- forward recursion ----------------------------------------------------------------
    def w_parent(self, j):
        """R_j^T w_{j-1}: the angular velocity of frame j-1 in frame j."""
        return self.memo(("wp", j), lambda: ZERO3 if j == 0 else self.rot_t(j, self.w(j - 1)))

    def w(self, j):
        def make():
            wp = self.w_parent(j)
            if self.prismatic[j]:
                return wp
            return (wp[0], wp[1], self.b(wp[2] + self.qd[j]))
        return self.memo(("w", j), make)

    def ww(self, j):
        """Products w_a w_b of frame j, keyed (a, b) with a <= b."""
        def make():
            w = self.w(j)
            return {(a, b): self.b(w[a] * w[b]) for a in range(3) for b in range(a, 3)}
        return self.memo(("ww", j), make)

    # A quantity of a set of parts: the whole recursion for all parts; the inertial (a) and
    # gravity (g) parts by their own recursions; any other set from these by sums or
    # differences (the velocity part never has its own recursion).
    def _parts(self, parts, relevant):
        return frozenset(parts) & relevant

    def _combine(self, whole, chain, S, relevant):
        """The quantity of parts S from whole(), chain(part) for part in ('a', 'g')."""
        if not S:
            return None
        if S == relevant:
            return whole()
        if "v" in S:
            terms, sign = [whole()] + [chain(p) for p in sorted(relevant - S)], -1
        else:
            terms, sign = [chain(p) for p in sorted(S)], 1
        out = terms[0]
        for t in terms[1:]:
            out = self.vec_sum(out, t, sign)
        return out

    def vec_sum(self, x, y, sign=1):
        if isinstance(x[0], (list, tuple)):          # a matrix, by rows
            return [self.vec_sum(a, b, sign) for a, b in zip(x, y)]
        return self.vec([a + sign * b for a, b in zip(x, y)])

    def wd(self, j, parts):
        """wd_j of the given parts (a: qdd, v: qd)."""
        relevant = frozenset("av")
        S = self._parts(parts, relevant)
        if j < 0 or not S:
            return ZERO3
        return self.memo(("wd", j, S), lambda: self._combine(
            lambda: self._wd_rec(j, relevant), lambda p: self._wd_rec(j, {p}), S, relevant))

    def _wd_rec(self, j, S):
        S = frozenset(S)

        def make():
            prev = ZERO3 if j == 0 else self._wd_rec(j - 1, S)
            x = self.rot_t(j, prev)
            if self.prismatic[j]:
                return x
            x = list(x)
            if "a" in S:
                x[2] = x[2] + self.qdd[j]
            if "v" in S:
                wp, qd = self.w_parent(j), self.qd[j]
                x[0] = x[0] + wp[1] * qd
                x[1] = x[1] - wp[0] * qd
            return self.vec(x)
        return self.memo(("wd_rec", j, S), make)

    def U(self, j, parts):
        """U_j = skew(wd_j) + skew(w_j)^2 (the second term in the velocity part), by entry."""
        relevant = frozenset("av")
        S = self._parts(parts, relevant)
        if not S:
            return [list(ZERO3) for _ in range(3)]
        return self.memo(("U", j, S), lambda: self._combine(
            lambda: self._U_rec(j, relevant), lambda p: self._U_rec(j, {p}), S, relevant))

    def _U_rec(self, j, S):
        def make():
            wd = self._wd_rec(j, S)
            out = [[se.Integer(0)] * 3 for _ in range(3)]
            if "v" in S:
                p = self.ww(j)
                out[0][0] = -(p[1, 1] + p[2, 2])
                out[1][1] = -(p[0, 0] + p[2, 2])
                out[2][2] = -(p[0, 0] + p[1, 1])
                out[0][1] = out[1][0] = p[0, 1]
                out[0][2] = out[2][0] = p[0, 2]
                out[1][2] = out[2][1] = p[1, 2]
            out[0][1] = out[0][1] - wd[2]
            out[1][0] = out[1][0] + wd[2]
            out[0][2] = out[0][2] + wd[1]
            out[2][0] = out[2][0] - wd[1]
            out[1][2] = out[1][2] - wd[0]
            out[2][1] = out[2][1] + wd[0]
            return [[self.b(e) for e in row] for row in out]
        return self.memo(("U_rec", j, frozenset(S)), make)

    def vd(self, j, parts):
        """vd_j of the given parts (a: qdd, v: qd, g: gravity)."""
        S = self._parts(parts, ALL)
        if not S:
            return ZERO3
        return self.memo(("vd", j, S), lambda: self._combine(
            lambda: self._vd_rec(j, ALL), lambda p: self._vd_rec(j, {p}), S, ALL))

    def _vd_rec(self, j, S):
        S = frozenset(S)
        if j < 0:
            return self.minus_g if "g" in S else ZERO3

        def make():
            prev = self._vd_rec(j - 1, S)
            if j > 0 and S & {"a", "v"}:
                U, p = self._U_rec(j - 1, S & {"a", "v"}), self.p(j)
                prev = self.vec([prev[a] + sum((U[a][k] * p[k] for k in range(3)),
                                               se.Integer(0)) for a in range(3)])
            x = self.rot_t(j, prev)
            if not self.prismatic[j]:
                return x
            x = list(x)
            if "a" in S:
                x[2] = x[2] + self.qdd[j]
            if "v" in S:        # 2 w_j x (qd_j z) = 2 qd_j (w_y, -w_x, 0)
                w, qd2 = self.w(j), self.b(2 * self.qd[j])
                x[0] = x[0] + w[1] * qd2
                x[1] = x[1] - w[0] * qd2
            return self.vec(x)
        return self.memo(("vd_rec", j, S), make)

    # --- link wrench ------------------------------------------------------------------------
    def wrench(self, j, phi, parts):
        """(F_j, N_j) of the link parameters phi (10 constants) over the given parts."""
        XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M = phi
        MS = (MX, MY, MZ)
        F, N = [se.Integer(0)] * 3, [se.Integer(0)] * 3
        if any(v != 0 for v in (M, MX, MY, MZ)) and parts:
            vd = self.vd(j, parts)
            for a in range(3):
                F[a] = F[a] + M * vd[a]
            if any(v != 0 for v in MS):
                U = self.U(j, parts)
                for a in range(3):
                    F[a] = F[a] + U[a][0] * MX + U[a][1] * MY + U[a][2] * MZ
                N = [MS[1] * vd[2] - MS[2] * vd[1], MS[2] * vd[0] - MS[0] * vd[2],
                     MS[0] * vd[1] - MS[1] * vd[0]]
        J = ((XX, XY, XZ), (XY, YY, YZ), (XZ, YZ, ZZ))
        if any(v != 0 for v in (XX, XY, XZ, YY, YZ, ZZ)) and self.direct.get(j) == "second":
            # N = vee(U K - (U K)^T), K = tr(J)/2 1 - J the second moment about the origin
            Jf = np.array([[float(v) for v in row] for row in J])
            K = np.trace(Jf) / 2 * np.eye(3) - Jf
            K = [[_const(v, np.abs(Jf).max()) for v in row] for row in K]
            U = self.U(j, parts)

            def UK(a, b):
                return U[a][0] * K[0][b] + U[a][1] * K[1][b] + U[a][2] * K[2][b]
            N = [N[0] + UK(2, 1) - UK(1, 2), N[1] + UK(0, 2) - UK(2, 0),
                 N[2] + UK(1, 0) - UK(0, 1)]
        elif any(v != 0 for v in (XX, XY, XZ, YY, YZ, ZZ)):
            wd = self.wd(j, parts)
            for a in range(3):
                N[a] = N[a] + J[a][0] * wd[0] + J[a][1] * wd[1] + J[a][2] * wd[2]
            if "v" in parts and self.direct.get(j) == "direct":    # w x (J w) as it stands
                w = self.w(j)
                Jw = self.vec([J[a][0] * w[0] + J[a][1] * w[1] + J[a][2] * w[2]
                               for a in range(3)])
                gyro = self.cross(w, Jw)
                N = [a + c for a, c in zip(N, gyro)]
            elif "v" in parts:        # w x (J w) from the products of w
                p = self.ww(j)
                N[0] = N[0] + (XZ * p[0, 1] - XY * p[0, 2] + (ZZ - YY) * p[1, 2]
                               + YZ * self.b(p[1, 1] - p[2, 2]))
                N[1] = N[1] + (XY * p[1, 2] - YZ * p[0, 1] + (XX - ZZ) * p[0, 2]
                               + XZ * self.b(p[2, 2] - p[0, 0]))
                N[2] = N[2] + (YZ * p[0, 2] - XZ * p[1, 2] + (YY - XX) * p[0, 1]
                               + XY * self.b(p[0, 0] - p[1, 1]))
        return F, N


def _link_constants(values):
    """(n, 10) parameter values as symengine constants, rounding noise snapped to 0."""
    values = np.asarray(values, float)
    out = []
    for row in values:
        out.append([_const(v, 0.0) if v != 0.0 else se.Integer(0) for v in row])
    return out


def _torques(rec, groups):
    """tau from the link wrenches of groups[j] = [(parts, phi constants), ...]."""
    n, b = rec.n, rec.b
    f_next = n_next = None
    tau = [None] * n
    for j in range(n - 1, -1, -1):
        F, N = [se.Integer(0)] * 3, [se.Integer(0)] * 3
        for parts, phi in groups[j]:
            Fg, Ng = rec.wrench(j, phi, parts)
            F = [a + c for a, c in zip(F, Fg)]
            N = [a + c for a, c in zip(N, Ng)]
        if f_next is not None:
            Rf = rec.rot(j + 1, f_next)
            Rn = rec.rot(j + 1, n_next)
            pf = rec.cross(rec.p(j + 1), Rf)
            F = [a + c for a, c in zip(F, Rf)]
            N = [a + c + e for a, c, e in zip(N, Rn, pf)]
        f_next, n_next = rec.vec(F), rec.vec(N)
        tau[j] = f_next[2] if rec.prismatic[j] else n_next[2]
    return tau


def _finish(rec, tau, cse):
    assignments, outputs = _inline_sums(prune_dead(rec.b.assignments, tau), list(tau))
    assignments = [(sym, _factored(e)) for sym, e in assignments]
    if cse:
        assignments, outputs = _cse(assignments, outputs)
    assignments = [(sym, _factored(e)) for sym, e in assignments]
    outputs = [_factored(e) for e in outputs]
    return Program(n=rec.n, assignments=assignments, outputs=outputs)


def _inline_sums(assignments, outputs):
    """Sums used once, as a term of another sum, merged into it (one flat sum to factor)."""
    uses = {}

    def count(e):
        if e.is_Symbol:
            uses[e] = uses.get(e, 0) + 1
        for a in e.args:
            count(a)
    for e in [e for _, e in assignments] + list(outputs):
        count(e)
    defs = dict(assignments)
    merged = set()

    def expand(e):
        out = []
        for t in _terms(e):
            coef, sym = (se.Integer(1), t)
            if t.is_Mul and len(t.args) == 2 and _is_num(t.args[0]) and t.args[1].is_Symbol:
                coef, sym = t.args
            if sym.is_Symbol and uses.get(sym) == 1 and sym in defs and defs[sym].is_Add:
                merged.add(sym)
                out += [coef * u for u in expand(defs[sym])]
            else:
                out.append(t)
        return out

    def flat(e):
        return se.Add(*expand(e)) if e.is_Add else e
    new = [(sym, flat(e)) for sym, e in assignments]
    outs = [flat(e) for e in outputs]
    return [(sym, e) for sym, e in new if sym not in merged], outs


def _factored(e):
    """A sum with its common factors (symbols, equal coefficients) taken out."""
    return factor_sum(_terms(e)) if e.is_Add else e


def _terms(e):
    """The terms of a sum, nested sums (also negated ones, as cse leaves them) flattened."""
    if e.is_Add:
        return [t for a in e.args for t in _terms(a)]
    if e.is_Mul and len(e.args) == 2:
        a, b = e.args
        if _is_num(a) and b.is_Add:
            return [a * t for t in _terms(b)]
        if _is_num(b) and a.is_Add:
            return [b * t for t in _terms(a)]
    return [e]


def _last_joint_free(robot, values):
    """Whether tau does not depend on the last joint's angle: its link's base parameters are
    symmetric about the joint axis (XX - YY, XY, XZ, YZ, MX, MY all 0)."""
    if robot.prismatic[-1]:
        return False
    XX, XY, XZ, YY, YZ, _, MX, MY, _, _ = np.asarray(values, float)[-1]
    return bool(XX == YY and XY == XZ == YZ == MX == MY == 0.0)


def recursive_program(robot, values=None, cse=True):
    """The exact customized recursive Newton-Euler model of an arm as a straight-line program.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    values : array_like, shape (n, 10), optional
        Inertial parameters per link (:data:`.base_parameters.PARAMETER_NAMES`, body frame,
        about its origin); default the base parameters with zeros in the dependent slots
        (:attr:`.base_parameters.BaseParameters.values`), which give the same torques.
    cse : bool, optional
        Run symengine's common-subexpression elimination on the result (default True).

    Returns
    -------
    gd_analyze.core.codegen.Program
        tau [N m or N] from the symbols ``q0, qd0, qdd0, ...``; ``Program.cost()`` counts it.

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 and Table 3.3, with gravity as the base
    acceleration (Eq. (3.3-46)); customized form of Khalil & Kleinfinger (1987). When the last
    link's base parameters are symmetric about its (revolute) axis, the torques do not depend
    on the last angle and it is taken as 0 (no cos/sin of it). Per link, w x (J w) is formed
    either from the six products w_a w_b (shared with U) or as it stands, whichever gives the
    smaller count (a greedy pass over the links).

    Examples
    --------
    >>> from gd_analyze.core.robot import load_robot
    >>> prog = recursive_program(load_robot("two-link"))
    >>> sorted(prog.cost())
    ['additions', 'cos', 'multiplications', 'sin']
    """
    if values is None:
        values = base_parameters(robot).values
    consts = _link_constants(values)
    return _choose(robot, [[(ALL, consts[j])] for j in range(robot.n)],
                   _last_joint_free(robot, values), cse)


#: The exact program: :func:`recursive_program` (the name the pruning module uses).
exact_program = recursive_program


def parts_program(robot, values, cse=True, search=True):
    """The recursive program with different parameter values per part of the torque.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    values : array_like, shape (3, n, 10)
        Per part of :data:`PARTS` (inertial, velocity, gravity) the parameter values per
        link; a parameter is either 0 or one common value in every part.
    cse : bool, optional
        Run symengine's common-subexpression elimination on the result (default True).
    search : bool, optional
        Choose each link's form of w x (J w) by the count (default True); False: the
        product form everywhere (quicker).

    Returns
    -------
    gd_analyze.core.codegen.Program
        tau = sum over the parts p of the part p of the torque of values[p] [N m or N].

    Raises
    ------
    ValueError
        If values is not of shape (3, n, 10).

    Notes
    -----
    Per link the parameters are grouped by the set of parts they are kept in; a group's
    wrench is formed from the kinematic quantities of those parts: the whole recursion,
    the inertial and gravity parts by their own recursions, the others by differences.
    """
    values = np.asarray(values, float)
    if values.shape != (len(PARTS), robot.n, 10):
        raise ValueError(f"values must have shape (3, {robot.n}, 10), got {values.shape}")
    groups = []
    for j in range(robot.n):
        by_set = {}
        for c in range(10):
            col = values[:, j, c]
            kept = [p for p, v in zip(PARTS, col) if v != 0.0]
            if not kept:
                continue
            if len({float(col[PARTS.index(p)]) for p in kept}) == 1:
                by_set.setdefault(frozenset(kept), np.zeros(10))[c] = col[PARTS.index(kept[0])]
            else:
                for p in kept:
                    by_set.setdefault(frozenset(p), np.zeros(10))[c] = col[PARTS.index(p)]
        groups.append([(S, _link_constants(phi[None, :])[0])
                       for S, phi in sorted(by_set.items(), key=lambda t: sorted(t[0]))])
    lock = all(_last_joint_free(robot, values[p]) for p in range(len(PARTS)))
    return _choose(robot, groups, lock, cse, search)


def _total(program):
    c = program.cost()
    return c["multiplications"] + c["additions"]


#: Forms of a link's inertial moment J wd + w x (J w): "products" (w x (J w) from the six
#: products w_a w_b shared with U), "direct" (w x (J w) as it stands), "second" (the whole
#: moment as vee(U K - (U K)^T) from U and the second moment K = tr(J)/2 1 - J).
FORMS = ("products", "direct", "second")


def _choose(robot, groups, lock, cse, search=True):
    """The cheapest program over the links' forms of :data:`FORMS`, by a greedy pass from
    the product form: each link switched to another form where that lowers the count."""
    def build(forms):
        rec = _Recursion(robot, lock_last=lock, direct=forms)
        return _finish(rec, _torques(rec, groups), cse)
    forms = {}
    best = build(forms)
    for j in range(robot.n if search else 0):
        for form in FORMS[1:]:
            trial = build({**forms, j: form})
            if _total(trial) < _total(best):
                best, forms = trial, {**forms, j: form}
    return best
