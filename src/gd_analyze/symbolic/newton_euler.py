"""The symbolic quantities of the link-frame recursive Newton-Euler algorithm.

Fu, Gonzalez & Lee (1987), Algorithm 3.1 and Table 3.3, in the customized form of Khalil &
Kleinfinger (1987), built with symengine for one arm as SSA temporaries (:class:`_Builder`:
identical expressions, or their negations, once):

- forward, in body frame j (R_j = P_j Rot(z, q_j) from frame j-1, p_j the origin of frame j
  in frame j-1; vd_0 = -g, Eq. (3.3-46))::

      w_j  = R_j^T w_{j-1} + qd_j z                                  (revolute)
      wd_j = R_j^T wd_{j-1} + qdd_j z + (R_j^T w_{j-1}) x qd_j z
      vd_j = R_j^T (vd_{j-1} + U_{j-1} p_j)  [+ qdd_j z + 2 w_j x qd_j z, prismatic]
      U_j  = skew(wd_j) + skew(w_j)^2

- link wrench: F_j = M_j vd_j + U_j MS_j, N_j = J_j wd_j + w_j x (J_j w_j) + MS_j x vd_j;
- backward: f_j = F_j + R_{j+1} f_{j+1}, n_j = N_j + R_{j+1} n_{j+1} + p_{j+1} x (R_{j+1}
  f_{j+1}); tau_j = n_j . z (revolute) or f_j . z (prismatic).

Rotations are applied as Rot(z, q)^T (P^T x) with P's near-0/+-1 entries snapped. Every
quantity can be taken for a set of parts of the torque (inertial: qdd, velocity: qd,
gravity): the inertial and gravity parts have their own recursions, the others are the
whole minus those. The programs are assembled in :mod:`.recursive`.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import symengine as se
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["PARTS", "FORMS"]

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


def is_num(e: se.Basic) -> bool:
    """Whether a symengine expression is a number (a constant folded at generation time).

    Parameters
    ----------
    e : symengine.Basic

    Returns
    -------
    bool

    Examples
    --------
    >>> import symengine as se
    >>> is_num(se.Integer(2)), is_num(se.Symbol("q1"))
    (True, False)
    """
    return isinstance(e, se.Number)


def _atomic(e):
    """Left as it is (no temporary): a number, a symbol or a number times a symbol (its
    multiplication, when not by +-1, is counted where it is used, or merges with others)."""
    if is_num(e) or e.is_Symbol:
        return True
    if e.is_Mul and len(e.args) == 2:
        a, b = e.args
        return (is_num(a) and b.is_Symbol) or (is_num(b) and a.is_Symbol)
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


class Recursion:
    """Memoized symbolic quantities of the recursion for one arm."""

    def __init__(self, robot: Robot, lock_last: bool = False, direct: dict | None = None
                 ) -> None:
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
        self._memo: dict = {}

    # --- helpers -----------------------------------------------------------------------
    def memo(self, key: Hashable, fn: Callable[[], Any]) -> Any:
        if key not in self._memo:
            self._memo[key] = fn()
        return self._memo[key]

    def vec(self, exprs: Iterable[Any]) -> tuple:
        return tuple(self.b(e) for e in exprs)

    def trig(self, j: int) -> tuple:
        if self.locked[j]:
            return se.Integer(1), se.Integer(0)
        return self.memo(("cs", j), lambda: (self.b(se.cos(self.q[j])),
                                             self.b(se.sin(self.q[j]))))

    def rot_t(self, j: int, x: Sequence[Any]) -> tuple:
        """R_j^T x = Rot(z, q_j)^T (P_j^T x) (x in frame j-1, result in frame j)."""
        if all(e == 0 for e in x):
            return ZERO3
        P = self.P[j]
        y = self.vec([P[0][k] * x[0] + P[1][k] * x[1] + P[2][k] * x[2] for k in range(3)])
        if self.prismatic[j]:
            return y
        c, s = self.trig(j)
        return self.vec([c * y[0] + s * y[1], c * y[1] - s * y[0], y[2]])

    def rot(self, j: int, x: Sequence[Any]) -> tuple:
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

    def p(self, j: int) -> tuple:
        """Origin of frame j in frame j-1: t_j (+ q_j P_j z, prismatic)."""
        t = self.t[j]
        if not self.prismatic[j]:
            return tuple(t)
        return self.vec([t[k] + self.q[j] * self.P[j][k][2] for k in range(3)])

    def cross(self, a: Sequence[Any], b: Sequence[Any]) -> tuple:
        return self.vec([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                         a[0] * b[1] - a[1] * b[0]])

    # --- forward recursion ----------------------------------------------------------------
    def w_parent(self, j: int) -> tuple:
        """R_j^T w_{j-1}: the angular velocity of frame j-1 in frame j."""
        return self.memo(("wp", j), lambda: ZERO3 if j == 0 else self.rot_t(j, self.w(j - 1)))

    def w(self, j: int) -> tuple:
        def make():
            wp = self.w_parent(j)
            if self.prismatic[j]:
                return wp
            return (wp[0], wp[1], self.b(wp[2] + self.qd[j]))
        return self.memo(("w", j), make)

    def ww(self, j: int) -> dict:
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

    def vec_sum(self, x: Sequence[Any], y: Sequence[Any], sign: int = 1) -> Any:
        if isinstance(x[0], (list, tuple)):          # a matrix, by rows
            return [self.vec_sum(a, b, sign) for a, b in zip(x, y)]
        return self.vec([a + sign * b for a, b in zip(x, y)])

    def wd(self, j: int, parts: Iterable[str]) -> tuple:
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

    def U(self, j: int, parts: Iterable[str]) -> list:
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

    def vd(self, j: int, parts: Iterable[str]) -> tuple:
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
    def wrench(self, j: int, phi: Sequence[Any], parts: Iterable[str]) -> tuple:
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


def link_constants(values: ArrayLike) -> list:
    """(n, 10) parameter values as symengine constants, rounding noise snapped to 0."""
    return [[_const(v, 0.0) if v != 0.0 else se.Integer(0) for v in row]
            for row in np.asarray(values, float)]


def link_torques(rec: Recursion, groups: Sequence[Sequence[tuple]]) -> list:
    """tau from the link wrenches of groups[j] = [(parts, phi constants), ...]."""
    n = rec.n
    f_next: tuple | None = None
    n_next: Any = None
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


#: Forms of a link's inertial moment J wd + w x (J w): "products" (w x (J w) from the six
#: products w_a w_b shared with U), "direct" (w x (J w) as it stands), "second" (the whole
#: moment as vee(U K - (U K)^T) from U and the second moment K = tr(J)/2 1 - J).
FORMS = ("products", "direct", "second")
