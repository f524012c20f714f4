"""Straight-line program of an explicit G-D model: its kept terms assembled in the AKB style.

The program (:func:`build_program`) is assembled with symengine from the kept terms of an
explicit model (:mod:`gd_analyze.core.symbolic.explicit`) in the AKB style (Armstrong, Khatib & Burdick,
ICRA 1986), keeping the structure instead of expanding it:

- angles: theta_i = q_i + offset_i (only where the offset is not 0) and their cos and sin;
  cos and sin of the compound angles k . theta of the harmonics (theta_2 + theta_3 on the
  PUMA) by the angle-addition formulas, each once, from products of two cos/sin formed once;
- velocity products qd_j qd_k, each once;
- groups: every element D_ij (used by tau_i with qdd_j and by tau_j with qdd_i), every
  Christoffel coefficient of qd_j qd_k in h_i and every c_i is one sum of coefficient x
  cos/sin; a group proportional to an earlier one is that one times a constant; the pairs
  cos(A +- B), sin(A +- B) of a sum are written in their shared products and common factors
  are taken out (:mod:`gd_analyze.core.symbolic.factoring`);
- tau_i = sum_j D_ij qdd_j + sum_{j<=k} C_ijk (qd_j qd_k) + c_i, Eq. (3.4-24), factored;
- unused assignments are dropped, common subexpressions eliminated
  (:mod:`gd_analyze.core.symbolic.subexpressions`).

A :class:`Program` is printed as C99 or numpy Python by :mod:`gd_analyze.core.symbolic.emit`;
its :meth:`Program.cost` is :func:`gd_analyze.core.symbolic.operation_count.count_operations` of
the very expressions that are printed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import symengine as se

from .emit import emit_python
from .factoring import expand_pairs, factor_sum, private_products, prune_dead, sum_to_product
from .operation_count import count_operations
from .subexpressions import eliminate

__all__ = ["Program", "build_program"]


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
    """

    n: int
    assignments: list
    outputs: list

    def cost(self):
        """Operation counts: dict with ``multiplications``, ``additions``, ``sin``, ``cos``."""
        return dict(self._cost)

    @cached_property
    def _cost(self):
        return count_operations(self.assignments, self.outputs)

    @cached_property
    def _tau_function(self):
        ns = {}
        exec(compile(emit_python(self, {}), "<simplified_model.py>", "exec"), ns)
        return ns["tau"]


def _key(K, S):
    return (bool(S),) + tuple(int(v) for v in K)


#: How cos and sin of compound angles are formed: "products" (angle-addition formulas from the
#: n joint angles' cos and sin: only 2n calls) or "calls" (one call per compound angle).
TRIG_MODES = ("products", "calls")


#: Above this many terms the sums are factored after cse: cse on the nested sums of a large
#: factored program is slow (Panda's full model: 12 s instead of 6 s, 85,770 not 97,231 ops).
LATE_FACTORING = 50_000


def build_program(terms, n, offset, trig_mode="products", prismatic=None):
    """Assemble the straight-line program of the kept terms.

    Parameters
    ----------
    terms : gd_analyze.core.symbolic.explicit.Term
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

    Notes
    -----
    tau = D qdd + h + c, Eq. (3.4-24) of Fu, Gonzalez & Lee (1987), with D, h, c in the explicit
    forms of :mod:`gd_analyze.core.symbolic.explicit`.
    """
    q = [se.Symbol(f"q{i}") for i in range(n)]
    qd = [se.Symbol(f"qd{i}") for i in range(n)]
    qdd = [se.Symbol(f"qdd{i}") for i in range(n)]
    assignments = []
    # merge the kept terms per group and harmonic
    groups = {}
    for kind, i, j, k, K, S, C in zip(terms.kind, terms.i, terms.j, terms.k, terms.K,
                                      terms.S, terms.C):
        g = groups.setdefault((str(kind), int(i), int(j), int(k)), {})
        key = _key(K, S)
        g[key] = g.get(key, 0.0) + float(C)
    groups = {gk: {h: c for h, c in g.items() if c != 0.0} for gk, g in groups.items()}
    groups = {gk: g for gk, g in groups.items() if g}
    lin = np.zeros(n, bool) if prismatic is None else np.asarray(prismatic, bool)
    late = len(terms) > LATE_FACTORING
    has_lin = bool(lin.any())

    def split(key):
        """(trig key with the polynomial columns zeroed, powers of the prismatic q)."""
        if not has_lin:
            return key, None
        kv = key[1:]
        return ((key[0],) + tuple(0 if lin[m] else v for m, v in enumerate(kv)),
                tuple(v if lin[m] else 0 for m, v in enumerate(kv)))
    # angles, compound angles and their cos/sin
    theta = []
    for i in range(n):
        off = float(offset[i])
        if off:
            t = se.Symbol(f"th{i}")
            assignments.append((t, q[i] + off))
            theta.append(t)
        else:
            theta.append(q[i])
    angle_cache, trig_cache, prod_cache, recipe, by_sym, factors = {}, {}, {}, {}, {}, {}

    def prod(a, b):
        """The product a b of two trig values, each formed once."""
        pk = (a, b) if a.name <= b.name else (b, a)
        if pk not in prod_cache:
            sym = se.Symbol(f"p{len(prod_cache)}")
            assignments.append((sym, a * a if a == b else a * b))
            prod_cache[pk] = sym
            factors[sym] = pk
        return prod_cache[pk]

    def angle(kvec):
        kvec = tuple(kvec)
        if kvec in angle_cache:
            return angle_cache[kvec]
        g = 0
        for v in kvec:
            g = math.gcd(g, abs(v))
        if g > 1:
            base = angle(tuple(v // g for v in kvec))
            expr = g * base
        else:
            nz = [m for m, v in enumerate(kvec) if v]
            if len(nz) == 1:
                angle_cache[kvec] = theta[nz[0]]
                return theta[nz[0]]
            # split off the last joint: k . theta = (k without m) . theta + k_m theta_m
            m = nz[-1]
            head = list(kvec)
            head[m] = 0
            expr = angle(tuple(head)) + kvec[m] * theta[m]
        sym = se.Symbol(f"a{len(angle_cache)}")
        assignments.append((sym, expr))
        angle_cache[kvec] = sym
        return sym

    def trig(key):
        if key in trig_cache:
            return trig_cache[key]
        is_sin, kvec = key[0], tuple(key[1:])
        if not any(kvec):
            return se.Integer(1)
        nz = [m for m, v in enumerate(kvec) if v]
        if trig_mode == "calls" or (len(nz) == 1 and kvec[nz[0]] == 1):
            a = angle(kvec)
            expr = se.sin(a) if is_sin else se.cos(a)
        else:
            # angle addition: k = a + b, cos(a+b) = ca cb - sa sb, sin(a+b) = sa cb + ca sb
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
                recipe[key] = ((1, prod(ca, ca)), (-1, prod(sa, sa)))
            elif ka == kb:
                recipe[key] = ((2, prod(sa, ca)),)
            elif not is_sin:
                recipe[key] = ((1, prod(ca, cb)), (-sign_b, prod(sa, sb)))
            else:
                recipe[key] = ((1, prod(sa, cb)), (sign_b, prod(ca, sb)))
            expr = se.Add(*[_coef(sg) * p for sg, p in recipe[key]])
        sym = se.Symbol(f"{'s' if is_sin else 'c'}{len(trig_cache)}")
        assignments.append((sym, expr))
        trig_cache[key] = sym
        if key in recipe:
            by_sym[sym] = recipe[key]
        return sym

    for g in groups.values():                       # trig values first, in a stable order
        for key in sorted(g):
            trig(split(key)[0])
    def pairs(items):
        rest, prods = sum_to_product(items, trig_cache.__contains__)
        rest += [(("p", prod(trig(ka), trig(kb))), c) for c, ka, kb in prods]
        return expand_pairs(rest, recipe)

    def expand(g):
        """[(trig value or product key, powers of the prismatic q, coef)]: pairs in products."""
        if not has_lin:
            return [(a, None, c) for a, c in pairs(sorted(g.items()))]
        by_pw = {}
        for key, c in sorted(g.items()):
            th, pw = split(key)
            by_pw.setdefault(pw, []).append((th, c))
        return [(a, pw, c) for pw, items in by_pw.items() for a, c in pairs(items)]
    expanded = {gk: expand(g) for gk, g in groups.items()}
    private = private_products([[a if a[0] == "p" else trig(a) for a, _, _ in ex]
                                for ex in expanded.values()], by_sym, factors)

    def atom(h):
        """A term's trig value: a harmonic, a product, or a private product's two factors."""
        if h[0] != "p":
            return trig(h)
        return se.Mul(*factors[h[1]]) if h[1] in private else h[1]
    mono_cache = {}

    def mono(pvec):
        """prod q_m^p_m over the prismatic joints, each power formed once."""
        if pvec is None or not any(pvec):
            return se.Integer(1)
        if pvec in mono_cache:
            return mono_cache[pvec]
        nz = [m for m, v in enumerate(pvec) if v]
        if len(nz) == 1 and pvec[nz[0]] == 1:
            return q[nz[0]]
        m = nz[-1]
        head = tuple(v - 1 if i == m else v for i, v in enumerate(pvec))
        sym = se.Symbol(f"m{len(mono_cache)}")
        mono_cache[pvec] = sym                      # reserve the name before the recursion
        assignments.append((sym, mono(head) * q[m]))
        return sym
    vel_cache = {}

    def vel(j, k):
        if (j, k) not in vel_cache:
            sym = se.Symbol(f"v{j}{k}" if n < 10 else f"v{j}_{k}")
            assignments.append((sym, qd[j] * qd[k]))
            vel_cache[(j, k)] = sym
        return vel_cache[(j, k)]

    shared = {}

    def group_value(gk, name):
        """A symbol (or constant) for sum coef x trig, reusing a proportional earlier group."""
        g = groups[gk]
        items = sorted(g.items())
        if len(items) == 1 and not any(items[0][0][1:]):
            return se.RealDouble(items[0][1])            # a constant group
        ref = max(items, key=lambda t: abs(t[1]))[1]
        norm = tuple((h, round(c / ref, 12)) for h, c in items)
        if norm in shared:
            sym, ref0 = shared[norm]
            factor = ref / ref0
            return sym if factor == 1.0 else (-sym if factor == -1.0 else
                                               se.RealDouble(factor) * sym)
        by_atom = {}                                # per trig value: a polynomial in q
        for a, pw, c in expanded[gk]:
            by_atom.setdefault(a, []).append((pw, c))
        expr = [se.Add(*[_coef(c) * mono(pw) for pw, c in poly]) * atom(a)
                for a, poly in by_atom.items()]
        expr = se.Add(*expr) if late else factor_sum(expr, by_sym)
        sym = se.Symbol(name)
        assignments.append((sym, expr))
        shared[norm] = (sym, ref)
        return sym

    tau = [[] for _ in range(n)]
    for (kind, i, j, k), g in sorted(groups.items()):
        if kind == "D":
            val = group_value((kind, i, j, k), f"D{i}{j}" if n < 10 else f"D{i}_{j}")
            tau[i].append(val * qdd[j])
            if i != j:
                tau[j].append(val * qdd[i])
    for (kind, i, j, k), g in sorted(groups.items()):
        if kind == "h":
            val = group_value((kind, i, j, k), f"C{i}{j}{k}" if n < 10 else f"C{i}_{j}_{k}")
            tau[i].append(val * vel(j, k))
        elif kind == "c":
            tau[i].append(group_value((kind, i, j, k), f"g{i}"))
    outputs = [factor_sum(t) if t else se.Integer(0) for t in tau]
    assignments, outputs = eliminate(prune_dead(assignments, outputs), outputs)
    if late:
        assignments = [(s, factor_sum(list(e.args), by_sym) if e.is_Add else e)
                       for s, e in assignments]
    return Program(n=n, assignments=assignments, outputs=outputs)


def _coef(c):
    if c == 1.0:
        return se.Integer(1)
    if c == -1.0:
        return se.Integer(-1)
    return se.RealDouble(c)
