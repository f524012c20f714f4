"""Straight-line program of an explicit G-D model: its kept terms assembled in the AKB style.

The program (:func:`build_program`) is assembled with symengine from the kept terms of an
explicit model (:mod:`gd_analyze.symbolic.explicit`) in the AKB style (Armstrong, Khatib & Burdick,
ICRA 1986), keeping the structure instead of expanding it:

- angles: theta_i = q_i + offset_i (only where the offset is not 0) and their cos and sin;
  cos and sin of the compound angles k . theta of the harmonics (theta_2 + theta_3 on the
  PUMA) by the angle-addition formulas, each once, from products of two cos/sin formed once;
- velocity products qd_j qd_k, each once;
- groups: every element D_ij (used by tau_i with qdd_j and by tau_j with qdd_i), every
  Christoffel coefficient of qd_j qd_k in h_i and every c_i is one sum of coefficient x
  cos/sin; a group proportional to an earlier one is that one times a constant; the pairs
  cos(A +- B), sin(A +- B) of a sum are written in their shared products and common factors
  are taken out (:mod:`gd_analyze.symbolic.factoring`);
- tau_i = sum_j D_ij qdd_j + sum_{j<=k} C_ijk (qd_j qd_k) + c_i, Eq. (3.4-24), factored;
- unused assignments are dropped, common subexpressions eliminated
  (:mod:`gd_analyze.symbolic.subexpressions`).

A :class:`Program` is printed as C99 or numpy Python by :mod:`gd_analyze.symbolic.emit`;
its :meth:`Program.cost` is :func:`gd_analyze.symbolic.operation_count.count_operations` of
the very expressions that are printed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
import symengine as se
from numpy.typing import ArrayLike

from .emit import emit_python, emit_state_python
from .factoring import expand_pairs, factor_sum, private_products, prune_dead, sum_to_product
from .operation_count import count_operations
from .subexpressions import eliminate

if TYPE_CHECKING:
    from .explicit import Term

__all__ = ["Program", "build_program", "ExplicitProgram"]


@dataclass(frozen=True, eq=False)
class Program:
    """A straight-line program computing tau from q, qd, qdd.

    Attributes
    ----------
    n : int
        Number of joints.
    assignments : list of (symengine.Symbol, symengine.Basic)
        Temporaries, in order.
    outputs : list of symengine.Basic, length n
        tau_i [N m].
    forms : tuple of str
        For a program of the customized recursive model (:mod:`.recursive`): the form of each
        link's inertial moment (:data:`.newton_euler.FORMS`) it was built with, length n; empty
        otherwise. Given back to :func:`.recursive.recursive_program` or
        :func:`.recursive.parts_program` it builds the same program without the search.
    """

    n: int
    assignments: list
    outputs: list
    forms: tuple = ()

    def cost(self) -> dict:
        """Operation counts: dict with ``multiplications``, ``additions``, ``sin``, ``cos``."""
        return dict(self._cost)

    @cached_property
    def _cost(self):
        return count_operations(self.assignments, self.outputs)

    @cached_property
    def _tau_function(self):
        ns = {}
        exec(compile(emit_python(self, {}), "<simplified_model.py>", "exec"), ns)
        return _blocked(ns["tau"])

    @cached_property
    def _state_function(self):
        ns = {}
        exec(compile(emit_state_python(self), "<simplified_model_state.py>", "exec"), ns)
        return ns["tau"]


#: Set points a program's numpy ``tau`` evaluates at once (:func:`_blocked`): each of its few
#: hundred temporaries is then 64 KiB, and they stay in the processor's cache.
TAU_BLOCK = 8192


def _blocked(tau):
    """``tau`` of an emitted numpy program, evaluated :data:`TAU_BLOCK` set points at a time on
    copies whose columns are contiguous.

    The program reads one joint's column at a time (``q[:, j]``); on a row-major array, or a
    column slice of a trajectory file's table, those are strided, and each of its element-wise
    operations is about twice as slow. The values are the same floats: every operation is
    element-wise. Inputs that do not share one (N, n) shape go to ``tau`` whole, which
    broadcasts them or raises ``ValueError``.
    """

    def blocked(q, qd, qdd):
        q, qd, qdd = (np.asarray(x, dtype=float) for x in (q, qd, qdd))
        if q.ndim != 2 or q.shape != qd.shape or q.shape != qdd.shape:
            return tau(q, qd, qdd)
        out = np.empty(q.shape)
        for a in range(0, max(q.shape[0], 1), TAU_BLOCK):    # no set point: tau checks n
            rows = slice(a, a + TAU_BLOCK)
            out[rows] = tau(np.asfortranarray(q[rows]), np.asfortranarray(qd[rows]),
                            np.asfortranarray(qdd[rows]))
        return out
    return blocked


def _key(K, S):
    return (bool(S),) + tuple(int(v) for v in K)


#: Above this many terms the sums are factored after cse: cse on the nested sums of a large
#: factored program is slow (Panda's full model: 12 s instead of 6 s, 85,770 not 97,231 ops).
LATE_FACTORING = 50_000


def build_program(terms: Term, n: int, offset: ArrayLike, trig_mode: str = "products",
                  prismatic: ArrayLike | None = None) -> Program:
    """Assemble the straight-line program of the kept terms.

    Parameters
    ----------
    terms : gd_analyze.symbolic.explicit.Term
        The kept terms (tran and rot of one element and harmonic are added together).
    n : int
        Number of joints.
    offset : array_like, shape (n,)
        Joint offsets [rad]: theta = q + offset.
    trig_mode : {"products", "calls"}, optional
        ``"products"``: cos and sin of the n angles are the only calls, compound angles come
        from the angle-addition formulas (counted); ``"calls"``: one cos/sin call per compound
        angle (fewer counted operations, more calls).
    prismatic : array_like of bool, shape (n,), optional
        The prismatic joints: their columns of the terms' K are powers of q_i [m], formed as
        products of q_i (each power once) and factored out per harmonic; default none.

    Returns
    -------
    Program
        tau [N m or N] of q, qd, qdd (:meth:`ExplicitProgram.tau`).

    Notes
    -----
    tau = D qdd + h + c, Eq. (3.4-24) of Fu, Gonzalez & Lee (1987), with D, h, c in the explicit
    forms of :mod:`gd_analyze.symbolic.explicit`.
    """
    return ExplicitProgram(terms, n, offset, trig_mode, prismatic).tau()


class ExplicitProgram:
    """The explicit model's program, built in stages (one method each).

    1. :meth:`__init__` merges the kept terms per group and harmonic;
    2. :meth:`trig_values` forms the angles, their cos and sin (and products of two);
    3. :meth:`group_value` writes one group (D_ij, C_ijk or c_i) as a sum of coefficient x
       cos/sin, factored;
    4. :meth:`assemble_tau` adds up tau_i = sum_j D_ij qdd_j + sum_{j<=k} C_ijk qd_j qd_k + c_i,
       Eq. (3.4-24);
    5. :meth:`finish` drops unused assignments and eliminates common subexpressions.

    :meth:`tau` runs them in order. One instance builds one program (its caches fill the
    assignments in the order of use).

    Parameters
    ----------
    terms, n, offset, trig_mode, prismatic
        As :func:`build_program`.
    """

    def __init__(self, terms: Term, n: int, offset: ArrayLike, trig_mode: str = "products",
                 prismatic: ArrayLike | None = None) -> None:
        self.n, self.trig_mode = n, trig_mode
        self.q = [se.Symbol(f"q{i}") for i in range(n)]
        self.qd = [se.Symbol(f"qd{i}") for i in range(n)]
        self.qdd = [se.Symbol(f"qdd{i}") for i in range(n)]
        self.assignments: list = []
        groups: dict = {}                           # merge the kept terms per group, harmonic
        for kind, i, j, k, K, S, C in zip(terms.kind, terms.i, terms.j, terms.k, terms.K,
                                          terms.S, terms.C):
            g = groups.setdefault((str(kind), int(i), int(j), int(k)), {})
            key = _key(K, S)
            g[key] = g.get(key, 0.0) + float(C)
        groups = {gk: {h: c for h, c in g.items() if c != 0.0} for gk, g in groups.items()}
        self.groups = {gk: g for gk, g in groups.items() if g}
        self.lin = np.zeros(n, bool) if prismatic is None else np.asarray(prismatic, bool)
        self.late = len(terms) > LATE_FACTORING
        self.has_lin = bool(self.lin.any())
        self.theta: list = []
        offsets = np.asarray(offset)
        for i in range(n):
            off = float(offsets[i])
            if off:
                t = se.Symbol(f"th{i}")
                self.assignments.append((t, self.q[i] + off))
                self.theta.append(t)
            else:
                self.theta.append(self.q[i])
        self.angle_cache: dict = {}
        self.trig_cache: dict = {}
        self.prod_cache: dict = {}
        self.recipe: dict = {}
        self.by_sym: dict = {}
        self.factors: dict = {}
        self.mono_cache: dict = {}
        self.vel_cache: dict = {}
        self.shared: dict = {}
        self.expanded: Any = None                   # dicts, set by trig_values
        self.private: Any = None

    # --- stage 2: trig values --------------------------------------------------------------
    def _split(self, key):
        """(trig key with the polynomial columns zeroed, powers of the prismatic q)."""
        if not self.has_lin:
            return key, None
        kv, lin = key[1:], self.lin
        return ((key[0],) + tuple(0 if lin[m] else v for m, v in enumerate(kv)),
                tuple(v if lin[m] else 0 for m, v in enumerate(kv)))

    def _prod(self, a, b):
        """The product a b of two trig values, each formed once."""
        pk = (a, b) if a.name <= b.name else (b, a)
        if pk not in self.prod_cache:
            sym = se.Symbol(f"p{len(self.prod_cache)}")
            self.assignments.append((sym, a * a if a == b else a * b))
            self.prod_cache[pk] = sym
            self.factors[sym] = pk
        return self.prod_cache[pk]

    def _angle(self, kvec):
        """The compound angle k . theta, each formed once (by its last joint's term)."""
        kvec = tuple(kvec)
        if kvec in self.angle_cache:
            return self.angle_cache[kvec]
        g = 0
        for v in kvec:
            g = math.gcd(g, abs(v))
        if g > 1:
            expr = g * self._angle(tuple(v // g for v in kvec))
        else:
            nz = [m for m, v in enumerate(kvec) if v]
            if len(nz) == 1:
                self.angle_cache[kvec] = self.theta[nz[0]]
                return self.theta[nz[0]]
            # split off the last joint: k . theta = (k without m) . theta + k_m theta_m
            m = nz[-1]
            head = list(kvec)
            head[m] = 0
            expr = self._angle(tuple(head)) + kvec[m] * self.theta[m]
        sym = se.Symbol(f"a{len(self.angle_cache)}")
        self.assignments.append((sym, expr))
        self.angle_cache[kvec] = sym
        return sym

    def _trig(self, key):
        """cos or sin of a harmonic key (is_sin, k...): a call, or the angle-addition formula
        from products of two trig values formed once."""
        if key in self.trig_cache:
            return self.trig_cache[key]
        is_sin, kvec = key[0], tuple(key[1:])
        if not any(kvec):
            return se.Integer(1)
        nz = [m for m, v in enumerate(kvec) if v]
        if self.trig_mode == "calls" or (len(nz) == 1 and kvec[nz[0]] == 1):
            a = self._angle(kvec)
            expr = se.sin(a) if is_sin else se.cos(a)
        else:
            expr = se.Add(*[_coef(sg) * p for sg, p in self._addition(key, kvec, nz)])
        sym = se.Symbol(f"{'s' if is_sin else 'c'}{len(self.trig_cache)}")
        self.assignments.append((sym, expr))
        self.trig_cache[key] = sym
        if key in self.recipe:
            self.by_sym[sym] = self.recipe[key]
        return sym

    def _addition(self, key, kvec, nz):
        """The recipe of cos/sin(a + b) = ca cb -+ sa sb, sa cb +- ca sb for k = a + b."""
        is_sin, trig, prod = key[0], self._trig, self._prod
        g = 0
        for v in kvec:
            g = math.gcd(g, abs(v))
        if g > 1:
            unit = tuple(v // g for v in kvec)
            ka, kb = unit, tuple(v * (g - 1) for v in unit)
            sign_b = 1
        else:
            m = nz[-1]
            ka = tuple(0 if i == m else v for i, v in enumerate(kvec))
            sign_b = 1 if kvec[m] > 0 else -1
            kb = tuple(abs(kvec[m]) if i == m else 0 for i in range(len(kvec)))
        ca, sa = trig((False,) + ka), trig((True,) + ka)
        cb, sb = trig((False,) + kb), trig((True,) + kb)
        if ka == kb and not is_sin:
            self.recipe[key] = ((1, prod(ca, ca)), (-1, prod(sa, sa)))
        elif ka == kb:
            self.recipe[key] = ((2, prod(sa, ca)),)
        elif not is_sin:
            self.recipe[key] = ((1, prod(ca, cb)), (-sign_b, prod(sa, sb)))
        else:
            self.recipe[key] = ((1, prod(sa, cb)), (sign_b, prod(ca, sb)))
        return self.recipe[key]

    def trig_values(self) -> None:
        """Stage 2: every group's trig values (in a stable order), then each group's items
        expanded into products of pairs (:mod:`.factoring`) and the private products found."""
        for g in self.groups.values():
            for key in sorted(g):
                self._trig(self._split(key)[0])
        self.expanded = {gk: self._expand(g) for gk, g in self.groups.items()}
        self.private = private_products([[a if a[0] == "p" else self._trig(a) for a, _, _ in ex]
                                         for ex in self.expanded.values()], self.by_sym,
                                        self.factors)

    def _pairs(self, items):
        rest, prods = sum_to_product(items, self.trig_cache.__contains__)
        rest += [(("p", self._prod(self._trig(ka), self._trig(kb))), c) for c, ka, kb in prods]
        return expand_pairs(rest, self.recipe)

    def _expand(self, g):
        """[(trig value or product key, powers of the prismatic q, coef)]: pairs in products."""
        if not self.has_lin:
            return [(a, None, c) for a, c in self._pairs(sorted(g.items()))]
        by_pw = {}
        for key, c in sorted(g.items()):
            th, pw = self._split(key)
            by_pw.setdefault(pw, []).append((th, c))
        return [(a, pw, c) for pw, items in by_pw.items() for a, c in self._pairs(items)]

    def _atom(self, h):
        """A term's trig value: a harmonic, a product, or a private product's two factors."""
        if h[0] != "p":
            return self._trig(h)
        return se.Mul(*self.factors[h[1]]) if h[1] in self.private else h[1]

    def _mono(self, pvec):
        """prod q_m^p_m over the prismatic joints, each power formed once."""
        if pvec is None or not any(pvec):
            return se.Integer(1)
        if pvec in self.mono_cache:
            return self.mono_cache[pvec]
        nz = [m for m, v in enumerate(pvec) if v]
        if len(nz) == 1 and pvec[nz[0]] == 1:
            return self.q[nz[0]]
        m = nz[-1]
        head = tuple(v - 1 if i == m else v for i, v in enumerate(pvec))
        sym = se.Symbol(f"m{len(self.mono_cache)}")
        self.mono_cache[pvec] = sym                 # reserve the name before the recursion
        self.assignments.append((sym, self._mono(head) * self.q[m]))
        return sym

    def _vel(self, j, k):
        """The velocity product qd_j qd_k, formed once."""
        if (j, k) not in self.vel_cache:
            sym = se.Symbol(f"v{j}{k}" if self.n < 10 else f"v{j}_{k}")
            self.assignments.append((sym, self.qd[j] * self.qd[k]))
            self.vel_cache[(j, k)] = sym
        return self.vel_cache[(j, k)]

    # --- stage 3: groups ------------------------------------------------------------------
    def group_value(self, gk: tuple, name: str) -> se.Basic:
        """A symbol (or constant) for sum coef x trig, reusing a proportional earlier group.

        Parameters
        ----------
        gk : tuple
            The group's key (kind ``"D"``, ``"h"`` or ``"c"``, i, j, k).
        name : str
            The name of its temporary, e.g. ``D01``.

        Returns
        -------
        symengine.Basic
            The temporary, a constant, or a multiple of an earlier proportional group's.
        """
        g = self.groups[gk]
        items = sorted(g.items())
        if len(items) == 1 and not any(items[0][0][1:]):
            return se.RealDouble(items[0][1])            # a constant group
        ref = max(items, key=lambda t: abs(t[1]))[1]
        norm = tuple((h, round(c / ref, 12)) for h, c in items)
        if norm in self.shared:
            sym, ref0 = self.shared[norm]
            factor = ref / ref0
            return sym if factor == 1.0 else (-sym if factor == -1.0 else
                                               se.RealDouble(factor) * sym)
        by_atom: dict = {}                          # per trig value: a polynomial in q
        for a, pw, c in self.expanded[gk]:
            by_atom.setdefault(a, []).append((pw, c))
        expr = [se.Add(*[_coef(c) * self._mono(pw) for pw, c in poly]) * self._atom(a)
                for a, poly in by_atom.items()]
        expr = se.Add(*expr) if self.late else factor_sum(expr, self.by_sym)
        sym = se.Symbol(name)
        self.assignments.append((sym, expr))
        self.shared[norm] = (sym, ref)
        return sym

    def _name(self, kind, i, j, k):
        n = self.n
        if kind == "D":
            return f"D{i}{j}" if n < 10 else f"D{i}_{j}"
        if kind == "h":
            return f"C{i}{j}{k}" if n < 10 else f"C{i}_{j}_{k}"
        return f"g{i}"

    # --- stage 4: tau assembly -----------------------------------------------------------------
    def assemble_tau(self) -> list[list[se.Basic]]:
        """Stage 4: the terms of each tau_i, Eq. (3.4-24): D groups first, then h and c.

        Returns
        -------
        list of list of symengine.Basic, length n
        """
        tau: list[list] = [[] for _ in range(self.n)]
        for (kind, i, j, k) in sorted(self.groups):
            if kind == "D":
                val = self.group_value((kind, i, j, k), self._name(kind, i, j, k))
                tau[i].append(val * self.qdd[j])
                if i != j:
                    tau[j].append(val * self.qdd[i])
        for (kind, i, j, k) in sorted(self.groups):
            if kind == "h":
                val = self.group_value((kind, i, j, k), self._name(kind, i, j, k))
                tau[i].append(val * self._vel(j, k))
            elif kind == "c":
                tau[i].append(self.group_value((kind, i, j, k), self._name(kind, i, j, k)))
        return tau

    # --- stage 5: cse ---------------------------------------------------------------------------
    def finish(self, outputs: list[se.Basic]) -> Program:
        """Stage 5: unused assignments dropped, common subexpressions eliminated.

        Parameters
        ----------
        outputs : list of symengine.Basic

        Returns
        -------
        Program
        """
        assignments, outputs = eliminate(prune_dead(self.assignments, outputs), outputs)
        if self.late:
            assignments = [(s, factor_sum(list(e.args), self.by_sym) if e.is_Add else e)
                           for s, e in assignments]
        return Program(n=self.n, assignments=assignments, outputs=outputs)

    def tau(self) -> Program:
        """The program of tau [N m or N] of q, qd, qdd: the stages in order.

        Returns
        -------
        Program
        """
        self.trig_values()
        tau = self.assemble_tau()
        return self.finish([factor_sum(t) if t else se.Integer(0) for t in tau])

    def inertia(self) -> Program:
        """The program of D(q) from the D groups: outputs D_ij row-major (n x n) [kg m^2].

        Returns
        -------
        Program
            D_ij = D_ji, each group written once (Eq. (3.4-25) in the explicit form); the other
            kinds of terms are ignored.
        """
        self.trig_values()
        out = [se.Integer(0)] * (self.n * self.n)
        for (kind, i, j, k) in sorted(self.groups):
            if kind == "D":
                val = self.group_value((kind, i, j, k), self._name(kind, i, j, k))
                out[i * self.n + j] = out[j * self.n + i] = val
        return self.finish(out)

    def regressor(self) -> tuple[Program, list[str], np.ndarray]:
        """The model as tau = Y beta with one parameter per kept coefficient.

        Returns
        -------
        program : Program
            Outputs Y[i, m] row-major (n x M): column m is the kept term's function (its cos or
            sin, times the powers of prismatic q) times qdd_j (D_ij, in rows i and j), qd_j
            qd_k (C_ijk) or 1 (c_i).
        names : list of str, length M
            E.g. ``"D12 cos(q2+q3)"`` (joints from 1).
        values : ndarray, shape (M,)
            The coefficients [kg m^2 for D and h, N m for c]: tau = Y values.

        Notes
        -----
        The explicit form keeps coefficients, not inertial parameters, so its parameters are
        these coefficients (merged over the tran and rot parts, as :meth:`tau` adds them): Y
        values is the model's tau, Eq. (3.4-24) term by term. They are not a minimal set:
        Khalil & Kleinfinger's base parameters (1987) are those of the recursive form.
        """
        self.trig_values()
        rows: list[list] = [[] for _ in range(self.n)]
        names: list[str] = []
        values: list[float] = []
        for (kind, i, j, k), g in sorted(self.groups.items()):
            for key, c in sorted(g.items()):
                th, pw = self._split(key)
                f = self._trig(th) * self._mono(pw)
                m = len(values)
                if kind == "D":
                    rows[i].append((m, f * self.qdd[j]))
                    if i != j:
                        rows[j].append((m, f * self.qdd[i]))
                elif kind == "h":
                    rows[i].append((m, f * self._vel(j, k)))
                else:
                    rows[i].append((m, f))
                label = self._name(kind, i + 1, j + 1, k + 1).replace("g", "c")
                powers = "".join(f" q{m + 1}^{v}" for m, v in enumerate(pw or ()) if v)
                names.append(f"{label} {_harmonic_text(th)}{powers}")
                values.append(c)
        out = [se.Integer(0)] * (self.n * len(values))
        for i, row in enumerate(rows):
            for m, e in row:
                out[i * len(values) + m] = e
        return self.finish(out), names, np.array(values, float)


def _harmonic_text(key):
    """``cos(q2+q3)``, ``sin(2q1)``, ``1``: a harmonic key (is_sin, k...) as text."""
    parts = []
    for m, v in enumerate(key[1:]):
        if v:
            sign = "-" if v < 0 else ("+" if parts else "")
            parts.append(f"{sign}{abs(v) if abs(v) != 1 else ''}q{m + 1}")
    if not parts:
        return "1"
    return f"{'sin' if key[0] else 'cos'}({''.join(parts)})"


def _coef(c):
    if c == 1.0:
        return se.Integer(1)
    return se.Integer(-1) if c == -1.0 else se.RealDouble(c)
