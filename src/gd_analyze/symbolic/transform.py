"""Transformations of straight-line programs: tidying, substitution and differentiation.

The deployed model's functions are derived from straight-line programs
(:class:`~gd_analyze.symbolic.codegen.Program`) without leaving them:

- :func:`finish_program` tidies a program: dead code dropped, sums used once merged into their
  user, common factors taken out, common subexpressions eliminated (symengine's cse);
- :func:`substitute` replaces inputs by numbers and lets them propagate (0 q = 0, sin 0 = 0,
  sign 0 = 0), dropping what folds to a constant;
- :func:`jacobian` differentiates in forward mode (each temporary's derivative from those of the
  temporaries it uses, the chain rule of a straight-line program; Griewank & Walther,
  *Evaluating Derivatives*, 2nd ed. 2008, Sec. 3.1): tau is linear in qdd and in the inertial
  parameters, so the derivatives are the inertia matrix D(q) of Eq. (3.4-24) of Fu, Gonzalez &
  Lee (1987) and the regressor Y(q, qd, qdd) of tau = Y beta (Khalil & Kleinfinger 1987).
"""

from __future__ import annotations

import itertools
import re

import symengine as se

from .codegen import Program
from .factoring import factor_sum, prune_dead
from .newton_euler import is_num
from .subexpressions import eliminate

__all__ = ["finish_program", "substitute", "jacobian"]


def finish_program(assignments: list[tuple[se.Symbol, se.Basic]], outputs: list[se.Basic], n: int,
                   cse: bool = True) -> Program:
    """A straight-line program tidied: dead code dropped, sums used once merged into their
    user, common factors taken out, common subexpressions eliminated.

    Parameters
    ----------
    assignments : list of (symengine.Symbol, symengine.Basic)
        Temporaries, each using only earlier ones.
    outputs : list of symengine.Basic
    n : int
        Number of joints.
    cse : bool, optional
        Run symengine's common-subexpression elimination (default True).

    Returns
    -------
    gd_analyze.symbolic.codegen.Program
    """
    outputs = list(outputs)
    assignments, outputs = _fresh_names(assignments, outputs)
    assignments, outputs = _inline_sums(prune_dead(assignments, outputs), outputs)
    if cse:
        assignments = [(sym, _factored(e)) for sym, e in assignments]
        assignments, outputs = eliminate(assignments, outputs)
        assignments = [(sym, _factored(e)) for sym, e in assignments]
    else:           # both tidyings of each temporary, kept together
        assignments = [(sym, _factored_twice(e)) for sym, e in assignments]
    outputs = [_factored(e) for e in outputs]
    return Program(n=n, assignments=assignments, outputs=outputs)


def _inline_sums(assignments, outputs):
    """Sums used once, as a term of another sum, merged into it (one flat sum to factor)."""
    uses: dict = {}
    for e in [e for _, e in assignments] + list(outputs):
        for sym, k in _uses(e):
            uses[sym] = uses.get(sym, 0) + k
    defs = dict(assignments)
    merged = set()

    def expand(e):
        out = []
        for t in _terms(e):
            coef, sym = (se.Integer(1), t)
            if t.is_Mul and len(t.args) == 2 and is_num(t.args[0]) and t.args[1].is_Symbol:
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


#: Most expressions kept by :func:`_factored` (then forgotten all at once): the tidied
#: form of an expression is a pure function of it, and the programs a search compares share
#: most of their expressions.
FACTORED_KEPT = 50_000
_FACTORED: dict = {}
_USES: dict = {}


def _factored(e, key=None):
    """A sum with its common factors (symbols, equal coefficients) taken out (kept by
    expression: the programs the form search and the pruning compare differ in a few links);
    ``key``: the expression's own (:func:`_order`), where the caller has it."""
    if not e.is_Add:
        return e
    key = (e, _order(e)) if key is None else key
    out = _FACTORED.get(key)
    if out is None:
        if len(_FACTORED) >= FACTORED_KEPT:
            _FACTORED.clear()
        out = _FACTORED[key] = factor_sum(_terms(e))
    return out


#: ``_factored(_factored(e))`` by ``e``'s key (:func:`_factored_twice`).
_TWICE: dict = {}


def _factored_twice(e):
    """``_factored(_factored(e))``, kept by ``e``'s key: a program finished without common
    subexpressions tidies each temporary twice, and the quick counts of a pruning's candidates
    (hundreds of programs sharing most of their temporaries) would otherwise work out the
    key of each first tidying again."""
    if not e.is_Add:
        return e
    key = (e, _order(e))
    out = _TWICE.get(key)
    if out is None:
        if len(_TWICE) >= FACTORED_KEPT:
            _TWICE.clear()
        out = _TWICE[key] = _factored(_factored(e, key))
    return out


def _terms(e):
    """The terms of a sum, nested sums (also negated ones, as cse leaves them) flattened."""
    if e.is_Add:
        return [t for a in e.args for t in _terms(a)]
    if e.is_Mul and len(e.args) == 2:
        a, b = e.args
        if is_num(a) and b.is_Add:
            return [a * t for t in _terms(b)]
        if is_num(b) and a.is_Add:
            return [b * t for t in _terms(a)]
    return [e]


def _order(e):
    """The expression tree's arguments in their stored order, as nested tuples of hashes:
    expressions equal as values can store their terms in different orders (by how they were
    built), and the tidied form and the printed code follow that order."""
    return tuple(_order(a) if a.args else hash(a) for a in e.args)


def _uses(e):
    """(symbol, how often it occurs in the expression tree) pairs of an expression (kept by
    expression)."""
    if e.is_Symbol:
        return ((e, 1),)
    out = _USES.get(e)
    if out is None:
        tally: dict = {}
        for a in e.args:
            for sym, k in _uses(a):
                tally[sym] = tally.get(sym, 0) + k
        out = _USES[e] = tuple(tally.items())
        if len(_USES) >= FACTORED_KEPT:
            _USES.clear()
    return out


def _fresh_names(assignments, outputs):
    """Temporaries named like cse's own (``x0``, ``x1``, ...) renamed ``w0``, ``w1``, ... (a
    program tidied a second time would otherwise meet its earlier cse's names)."""
    taken = {s.name for s, _ in assignments}
    old = [s for s, _ in assignments if re.fullmatch(r"x\d+", s.name)]
    if not old:
        return assignments, outputs
    fresh = (f"w{k}" for k in itertools.count() if f"w{k}" not in taken)
    rename = {s: se.Symbol(next(fresh)) for s in old}
    return ([(rename.get(s, s), e.xreplace(rename)) for s, e in assignments],
            [e.xreplace(rename) for e in outputs])


def substitute(program: Program, values: dict[se.Symbol, float], cse: bool = True) -> Program:
    """The program with some symbols replaced by numbers, the constants propagated.

    Parameters
    ----------
    program : Program
    values : dict of symengine.Symbol to float
        E.g. ``{qd0: 0, qdd0: 0, ...}`` for tau(q, 0, 0) = c(q).
    cse : bool, optional
        Tidy the result with :func:`finish_program` (default True).

    Returns
    -------
    Program
        What the program computes with those values; an assignment that folds to a number or a
        symbol is replaced by it where it is used.

    Examples
    --------
    >>> q0, qd0, t = se.symbols("q0 qd0 t")
    >>> p = substitute(Program(1, [(t, qd0 * se.cos(q0))], [t + se.sin(q0)]), {qd0: 0})
    >>> p.assignments, p.outputs
    ([], [sin(q0)])
    """
    env = {se.Symbol(str(k)) if not isinstance(k, se.Basic) else k: se.sympify(v)
           for k, v in values.items()}
    kept = []

    def put(e):
        used = {s: env[s] for s in e.free_symbols if s in env}
        return e.subs(used) if used else e
    for sym, e in program.assignments:
        e = put(e)
        if e.is_Number or e.is_Symbol:
            env[sym] = e
        else:
            kept.append((sym, e))
    outputs = [put(e) for e in program.outputs]
    if not cse:
        return Program(program.n, prune_dead(kept, outputs), outputs)
    return finish_program(kept, outputs, program.n)


def jacobian(program: Program, variables: list[se.Symbol],
             entries: list[tuple[int, int]]) -> tuple[list[tuple[se.Symbol, se.Basic]], list[se.Basic]]:
    """Derivatives of a program's outputs by forward-mode differentiation.

    Parameters
    ----------
    program : Program
    variables : list of symengine.Symbol
        The symbols x_j to differentiate by (inputs of the program).
    entries : list of (int, int)
        The pairs (i, j) wanted: d output_i / d x_j.

    Returns
    -------
    assignments : list of (symengine.Symbol, symengine.Basic)
        The program's assignments and, after each, its derivatives (named ``d<j>_<name>``)
        by the variables it depends on.
    outputs : list of symengine.Basic
        d output_i / d x_j per entry, in the order of ``entries``.

    Notes
    -----
    Forward mode on a straight-line program: dt/dx_j = sum over the symbols s of t's
    expression of (d expr / d s) (ds/dx_j) (Griewank & Walther 2008, Sec. 3.1). A derivative
    that is a number or a symbol is not given a temporary. The result is not tidied (see
    :func:`finish_program`).

    Examples
    --------
    >>> q0, a0, t = se.symbols("q0 qdd0 t")
    >>> body, out = jacobian(Program(1, [(t, se.cos(q0) * a0)], [2 * t + q0]), [a0], [(0, 0)])
    >>> body, out
    ([(t, cos(q0)*qdd0), (d0_t, cos(q0))], [2*d0_t])
    """
    deriv = [{x: se.Integer(1)} for x in variables]

    def diff(e, d):
        used = [s for s in e.free_symbols if s in d]
        return se.Add(*[e.diff(s) * d[s] for s in used]) if used else se.Integer(0)
    out = []
    for sym, e in program.assignments:
        out.append((sym, e))
        for j, d in enumerate(deriv):
            de = diff(e, d)
            if de == 0:
                continue
            if de.is_Number or de.is_Symbol:
                d[sym] = de
            else:
                ds = se.Symbol(f"d{j}_{sym.name}")
                out.append((ds, de))
                d[sym] = ds
    return out, [diff(program.outputs[i], deriv[j]) for i, j in entries]
