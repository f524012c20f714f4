"""Fewer operations in the straight-line program of an explicit model, same values.

Three rewrites that :func:`gd_analyze.symbolic.codegen.build_program` applies (none changes which
terms are kept, each is an algebraic identity):

- pairs of harmonics (:func:`expand_pairs`): cos(A + B) = cA cB - sA sB and
  cos(A - B) = cA cB + sA sB are formed from the same two products, and so are sin(A + B) and
  sin(A - B); where one sum holds both members of such a pair, it is written in the two
  products, a cos(A + B) + b cos(A - B) = (a + b) cA cB + (b - a) sA sB: never more terms,
  one less where a = +-b (the physics makes that frequent: on the PUMA 560 D_26 =
  2e-5 cos(q4 - q5) - 2e-5 cos(q4 + q5) = 4e-5 s4 s5), and the pair's own values are not
  formed at all where no sum uses them any more. This is the product form of Armstrong,
  Khatib & Burdick (ICRA 1986), taken where it is not dearer than the harmonic form;
- common factors (:func:`factor_sum`): a x y + b x z -> x (a y + b z), greedily over the
  factor shared by the most terms (a nested, Horner-like form), e.g. C_013 qd_1 qd_3 +
  C_013 qd_2 qd_3 -> C_013 (qd_1 qd_3 + qd_2 qd_3); numeric coefficients equal in magnitude
  count as a common factor too (a x - a y + a z -> a (x - y + z));
- dead code (:func:`prune_dead`): assignments no output needs are dropped.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from typing import Any

import symengine as se

__all__ = ["expand_pairs", "sum_to_product", "private_products", "factor_sum", "prune_dead"]


def expand_pairs(items: list[tuple[Any, float]], recipe: dict) -> list[tuple[Any, float]]:
    """Write the pairs of harmonics of a sum in their shared products.

    Parameters
    ----------
    items : list of (key, float)
        The sum: harmonic key and its coefficient.
    recipe : dict
        For a harmonic formed by angle addition, ``key -> ((sign, product), ...)``: the
        harmonic equals sum sign x product (products are symbols). Harmonics without a recipe
        are kept as they are.

    Returns
    -------
    list of (key or ("p", product), float)
        The same sum: the harmonics whose pair partner is also in the sum replaced by the
        products (``("p", product)``), coefficients merged, exact zeros dropped; the order
        is deterministic (that of ``items``, products after).

    Examples
    --------
    >>> x, y = se.symbols("x y")
    >>> rec = {"c+": ((1, x), (-1, y)), "c-": ((1, x), (1, y))}
    >>> expand_pairs([("c+", -2.0), ("c-", 2.0), ("c0", 1.0)], rec)
    [('c0', 1.0), (('p', y), 4.0)]
    """
    family: dict = {}
    for key, _ in items:
        r = recipe.get(key)
        if r is not None and len(r) == 2:
            fam = frozenset(p for _, p in r)
            family.setdefault(fam, []).append(key)
    expand = {k for keys in family.values() if len(keys) >= 2 for k in keys}
    if not expand:
        return list(items)
    out: list = []
    acc: dict = {}
    for key, c in items:
        if key in expand:
            for sign, p in recipe[key]:
                acc[p] = acc.get(p, 0.0) + sign * c
        else:
            out.append((key, c))
    out.extend((("p", p), c) for p, c in acc.items() if c != 0.0)
    return out


def _canon(v):
    """(canonical vector: first non-zero entry positive, sign of sin) of an integer vector."""
    for x in v:
        if x:
            return (v, 1) if x > 0 else (tuple(-y for y in v), -1)
    return v, 0


def sum_to_product(items: list[tuple[Any, float]], exists: Callable[..., bool]
                   ) -> tuple[list[tuple[Any, float]], list[tuple[float, Any, Any]]]:
    """Pairs a cos K1 +- a cos K2 (or sines) of equal magnitude as one product of two cos/sin.

    With K1 = A + B, K2 = A - B: cos K1 + cos K2 = 2 cA cB, cos K1 - cos K2 = -2 sA sB,
    sin K1 + sin K2 = 2 sA cB, sin K1 - sin K2 = 2 cA sB. Used where cos/sin of A and B are
    formed anyway; on the PUMA 560, cos(q3) + cos(2 q2 + q3) = 2 c2 c23.

    Parameters
    ----------
    items : list of (key, float)
        The sum: harmonic keys ``(is_sin, k_1, ..., k_n)`` with the first non-zero k positive,
        and coefficients.
    exists : callable
        ``exists(key) -> bool``: whether that cos/sin is formed anyway.

    Returns
    -------
    rest : list of (key, float)
        The terms not paired, in their order.
    products : list of (float, key, key)
        ``(coef, key_a, key_b)``: each a term coef x trig(key_a) x trig(key_b).

    Examples
    --------
    >>> items = [((False, 0, 1), 0.5), ((False, 2, 1), 0.5), ((True, 1, 0), 3.0)]
    >>> sum_to_product(items, lambda key: True)
    ([((True, 1, 0), 3.0)], [(1.0, (False, 1, 1), (False, 1, 0))])
    """
    by_mag: dict = {}
    for idx, (key, c) in enumerate(items):
        by_mag.setdefault((key[0], abs(c)), []).append(idx)
    used, products = set(), []
    for idx, (k1, c1) in enumerate(items):
        if idx in used or len(by_mag[(k1[0], abs(c1))]) < 2:
            continue
        for jdx in by_mag[(k1[0], abs(c1))]:
            if jdx <= idx or jdx in used:
                continue
            k2, c2 = items[jdx]
            v1, v2 = k1[1:], k2[1:]
            if any((x + y) % 2 for x, y in zip(v1, v2)):
                continue
            (a, sa), (b, sb) = _canon(tuple((x + y) // 2 for x, y in zip(v1, v2))), \
                _canon(tuple((x - y) // 2 for x, y in zip(v1, v2)))
            if not sa or not sb:
                continue
            same = (c1 == c2)
            if not k1[0]:                           # cosines
                ka, kb = ((False,) + a, (False,) + b) if same else ((True,) + a, (True,) + b)
                coef = 2 * c1 if same else -2 * c1 * sa * sb
            else:                                   # sines
                ka, kb = ((True,) + a, (False,) + b) if same else ((False,) + a, (True,) + b)
                coef = 2 * c1 * sa if same else 2 * c1 * sb
            if not (exists(ka) and exists(kb)):
                continue
            used |= {idx, jdx}
            products.append((coef, ka, kb))
            break
    return [it for idx, it in enumerate(items) if idx not in used], products


def private_products(sums: list[list], recipe: dict, factors: dict) -> set:
    """The products that exactly one sum uses and nothing else needs.

    Parameters
    ----------
    sums : list of list
        Per sum, its terms' atoms: ``("p", product)`` or a trig value (symbol).
    recipe : dict
        ``trig symbol -> ((sign, product), ...)`` for the values formed by angle addition.
    factors : dict
        ``product -> (factor, factor)``: the two trig values of each product.

    Returns
    -------
    set
        Products used by one sum and by no needed trig value: written inline in their sum
        (``a x y`` instead of ``a p`` with ``p = x y``, the same count), they can share a
        factor with the sum's other terms (:func:`factor_sum`).

    Examples
    --------
    >>> x, y, p, h = se.symbols("x y p h")
    >>> sorted(map(str, private_products([[("p", p)]], {}, {p: (x, y)})))
    ['p']
    >>> private_products([[("p", p)], [h]], {h: ((1, p),)}, {p: (x, y)})
    set()
    """
    uses: dict = {}
    needed: set = set()
    stack: list = []
    seen: set = set()
    for atoms in sums:
        for a in atoms:
            if isinstance(a, tuple):
                uses[a[1]] = uses.get(a[1], 0) + 1
                stack.extend(factors[a[1]])
            else:
                stack.append(a)
    while stack:                                    # the trig values needed, and their products
        t = stack.pop()
        if t in seen:
            continue
        seen.add(t)
        for _, p in recipe.get(t, ()):
            needed.add(p)
            stack.extend(factors[p])
    return {p for p, k in uses.items() if k == 1 and p not in needed}


def _num(x):
    return isinstance(x, se.Number) or getattr(x, "is_Number", False)


def _split(term):
    """(float coefficient, [symbol factors], [other factors]) of a product."""
    if term.is_Symbol:
        return 1.0, [term], []
    if _num(term):
        return float(term), [], []
    if not term.is_Mul:
        return 1.0, [], [term]
    coef, syms, other = 1.0, [], []
    for a in term.args:
        if a.is_Symbol:
            syms.append(a)
        elif _num(a):
            coef *= float(a)
        else:
            other.append(a)
    return coef, syms, other


def factor_sum(terms: list[se.Basic], recipe: dict[str, Any] | None = None) -> se.Basic:
    """A sum with its common factors taken out, greedily and nested.

    Parameters
    ----------
    terms : list of symengine.Basic
        The terms of the sum (products of a number, symbols and other expressions).
    recipe : dict, optional
        ``symbol -> ((sign, product), (sign, product))`` of the harmonics formed by angle
        addition: inside every bracket, the pairs of such harmonics are written in their
        products as :func:`expand_pairs` does (a bracket ``s12 (c19 + c29)`` holds a pair
        the whole sum did not show).

    Returns
    -------
    symengine.Basic
        The same sum: the factor that divides the most terms (at least two) is taken out of
        them, then the same on the bracket and on the rest. A factor is a symbol or the
        magnitude of a numeric coefficient (terms whose coefficients are exactly +-a become
        a (+-x +-y ...)); ties go to the symbol, then by name or value. Taking a factor out
        of k terms saves k - 1 multiplications and adds no operation.

    Examples
    --------
    >>> a, b, x, y, z = se.symbols("a b x y z")
    >>> factor_sum([2.0 * a * x, 3.0 * a * y, b * z])
    a*(2.0*x + 3.0*y) + b*z
    >>> factor_sum([0.25 * x, -0.25 * y, 0.5 * z])
    0.5*z + 0.25*(x - y)
    """
    return _factor(_combine([_split(t) for t in terms]), recipe or {})


def _combine(parts):
    """Like terms (the same factors) added into one, exact zeros dropped, order kept."""
    acc = {}
    for coef, syms, other in parts:
        key = (tuple(sorted(s.name for s in syms)), tuple(other))
        if key in acc:
            acc[key][0] += coef
        else:
            acc[key] = [coef, syms, other]
    return [(c, syms, other) for c, syms, other in acc.values() if c != 0.0]


def _merge_pairs(parts, recipe):
    """expand_pairs on the terms that are a coefficient times one harmonic of a recipe."""
    family = {}
    for coef, syms, other in parts:
        if len(syms) == 1 and not other and len(recipe.get(syms[0], ())) == 2:
            family.setdefault(frozenset(p for _, p in recipe[syms[0]]), []).append(syms[0])
    expand = {h for hs in family.values() if len(hs) >= 2 for h in hs}
    if not expand:
        return parts
    out, acc = [], {}
    for coef, syms, other in parts:
        if len(syms) == 1 and not other and syms[0] in expand:
            for sign, p in recipe[syms[0]]:
                acc[p] = acc.get(p, 0.0) + sign * coef
        else:
            out.append((coef, syms, other))
    out.extend((c, [p], []) for p, c in acc.items() if c != 0.0)
    return _combine(out)


def _rebuild(part):
    coef, syms, other = part
    body = syms + other
    if coef == 0.0:
        return se.Integer(0)
    if not body:
        return se.RealDouble(coef)
    c = se.Integer(1) if coef == 1.0 else (se.Integer(-1) if coef == -1.0 else
                                           se.RealDouble(coef))
    return se.Mul(c, *body)


def _factor(parts, recipe):
    """Greedy: the factor of the most remaining terms first (a heap, counts updated lazily)."""
    if recipe and len(parts) >= 2:
        parts = _merge_pairs(parts, recipe)
    if len(parts) < 2:
        return se.Add(*[_rebuild(p) for p in parts])
    index = {}
    for i, (coef, syms, other) in enumerate(parts):
        for s in set(syms):
            index.setdefault(("s", s.name, s), []).append(i)
        m = abs(coef)
        if m != 1.0 and m != 0.0 and (syms or other):     # constants are added, not factored
            index.setdefault(("c", m, None), []).append(i)
    heap = [((-len(v), k[0] == "c", k[1]), k) for k, v in index.items() if len(v) >= 2]
    heapq.heapify(heap)
    taken = [False] * len(parts)
    out = []
    while heap:
        rank, k = heapq.heappop(heap)
        live = [i for i in index[k] if not taken[i]]
        if len(live) < 2:
            continue
        if len(live) < -rank[0]:                    # some terms went to another factor
            heapq.heappush(heap, ((-len(live),) + rank[1:], k))
            continue
        inner = []
        for i in live:
            taken[i] = True
            coef, syms, other = parts[i]
            if k[0] == "s":
                syms = list(syms)
                syms.remove(k[2])
            else:
                coef = 1.0 if coef > 0 else -1.0
            inner.append((coef, syms, other))
        head = k[2] if k[0] == "s" else se.RealDouble(k[1])
        out.append(se.Mul(head, _factor(inner, recipe)))
    out.extend(_rebuild(p) for i, p in enumerate(parts) if not taken[i])
    return se.Add(*out)


def prune_dead(assignments: list[tuple[se.Symbol, se.Basic]],
               outputs: list[se.Basic]) -> list[tuple[se.Symbol, se.Basic]]:
    """The assignments some output needs, in their order.

    Parameters
    ----------
    assignments : list of (Symbol, expression)
        Each assignment uses only earlier ones.
    outputs : list of expression

    Returns
    -------
    list of (Symbol, expression)

    Examples
    --------
    >>> x, y, z = se.symbols("x y z")
    >>> prune_dead([(y, x * x), (z, y + 1)], [2 * y])
    [(y, x**2)]
    """
    live = set().union(*(e.free_symbols for e in outputs))
    kept = []
    for sym, e in reversed(assignments):
        if sym in live:
            live |= e.free_symbols
            kept.append((sym, e))
    return kept[::-1]
