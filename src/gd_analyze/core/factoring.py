"""Fewer operations in the straight-line program of an explicit model, same values.

Three rewrites that :func:`gd_analyze.core.codegen.build_program` applies (none changes which
terms are kept, each is an algebraic identity):

- pairs of harmonics (:func:`expand_pairs`): cos(A + B) = cA cB - sA sB and
  cos(A - B) = cA cB + sA sB are formed from the same two products, and so are sin(A + B) and
  sin(A - B); where one sum holds both members of such a pair, it is written in the two
  products, a cos(A + B) + b cos(A - B) = (a + b) cA cB + (b - a) sA sB: never more terms,
  one less where a = +-b (the physics makes that frequent: on the PUMA 560 D_15 =
  2e-5 cos(t4 - t5) - 2e-5 cos(t4 + t5) = 4e-5 s4 s5), and the pair's own values are not
  formed at all where no sum uses them any more. This is the product form of Armstrong,
  Khatib & Burdick (ICRA 1986), taken where it is not dearer than the harmonic form;
- common factors (:func:`factor_sum`): a x y + b x z -> x (a y + b z), greedily over the
  symbol shared by the most terms (a nested, Horner-like form), e.g. C_013 qd_1 qd_3 +
  C_013 qd_2 qd_3 -> C_013 (qd_1 qd_3 + qd_2 qd_3);
- dead code (:func:`prune_dead`): assignments no output needs are dropped.
"""

from __future__ import annotations

import symengine as se

__all__ = ["expand_pairs", "factor_sum", "prune_dead"]


def expand_pairs(items, recipe):
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
    family = {}
    for key, _ in items:
        r = recipe.get(key)
        if r is not None and len(r) == 2:
            fam = frozenset(p for _, p in r)
            family.setdefault(fam, []).append(key)
    expand = {k for keys in family.values() if len(keys) >= 2 for k in keys}
    if not expand:
        return list(items)
    out, acc = [], {}
    for key, c in items:
        if key in expand:
            for sign, p in recipe[key]:
                acc[p] = acc.get(p, 0.0) + sign * c
        else:
            out.append((key, c))
    out.extend((("p", p), c) for p, c in acc.items() if c != 0.0)
    return out


def _split(term):
    """(coefficient expression or None, [symbol factors], [other factors]) of a product."""
    if term.is_Symbol:
        return None, [term], []
    if not term.is_Mul:
        return term, [], []
    coef, syms, other = [], [], []
    for a in term.args:
        if a.is_Symbol:
            syms.append(a)
        elif isinstance(a, se.Number) or getattr(a, "is_Number", False):
            coef.append(a)
        else:
            other.append(a)
    return (se.Mul(*coef) if coef else None), syms, other


def factor_sum(terms):
    """A sum with its common symbol factors taken out, greedily and nested.

    Parameters
    ----------
    terms : list of symengine.Basic
        The terms of the sum (products of numbers, symbols and other expressions).

    Returns
    -------
    symengine.Basic
        The same sum: the symbol that divides the most terms (at least two; ties by name) is
        factored out of them, then the same on the bracket and on the rest. Each factoring of
        a symbol out of k terms saves k - 1 multiplications and adds none.

    Examples
    --------
    >>> a, b, x, y, z = se.symbols("a b x y z")
    >>> factor_sum([2.0 * a * x, 3.0 * a * y, b * z])
    a*(2.0*x + 3.0*y) + b*z
    """
    parts = [_split(t) for t in terms]
    return _factor(parts)


def _rebuild(part):
    coef, syms, other = part
    args = ([coef] if coef is not None else []) + syms + other
    return se.Mul(*args) if args else se.Integer(1)


def _factor(parts):
    if len(parts) < 2:
        return se.Add(*[_rebuild(p) for p in parts])
    freq = {}
    for _, syms, _ in parts:
        for s in set(syms):
            freq[s] = freq.get(s, 0) + 1
    best, n_best = None, 1
    for s, k in freq.items():
        if k > n_best or (k == n_best and best is not None and k > 1 and s.name < best.name):
            best, n_best = s, k
    if best is None:
        return se.Add(*[_rebuild(p) for p in parts])
    inner, rest = [], []
    for coef, syms, other in parts:
        if best in syms:
            syms = list(syms)
            syms.remove(best)
            inner.append((coef, syms, other))
        else:
            rest.append((coef, syms, other))
    return se.Add(best * _factor(inner), _factor(rest)) if rest else best * _factor(inner)


def prune_dead(assignments, outputs):
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
    live = set()
    for e in outputs:
        live |= e.free_symbols
    kept = []
    for sym, e in reversed(assignments):
        if sym in live:
            live |= e.free_symbols
            kept.append((sym, e))
    return kept[::-1]
