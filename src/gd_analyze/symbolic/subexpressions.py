"""Common subexpressions of a straight-line program: eliminated by symengine, then ordered by use.

:func:`eliminate` runs symengine's ``cse`` over all the assignments and outputs together and
names the new temporaries ``x0``, ``x1``, ...; :func:`dependency_order` then places every
assignment after the temporaries it uses (a new temporary may use an earlier assignment), in
linear time. Used by :func:`gd_analyze.symbolic.codegen.build_program` and the recursive
programs of :mod:`gd_analyze.symbolic.recursive`.
"""

from __future__ import annotations

import symengine as se

__all__ = ["eliminate", "dependency_order"]


def eliminate(assignments: list[tuple[se.Symbol, se.Basic]], outputs: list[se.Basic]
              ) -> tuple[list[tuple[se.Symbol, se.Basic]], list[se.Basic]]:
    """Eliminate what common subexpressions remain (symengine cse), keeping the order.

    Parameters
    ----------
    assignments : list of (symengine.Symbol, symengine.Basic)
        Temporaries, in order.
    outputs : list of symengine.Basic

    Returns
    -------
    (list of (symengine.Symbol, symengine.Basic), list of symengine.Basic)
        The new temporaries ``x0``, ``x1``, ... and the given ones rewritten in them, each
        after the temporaries it uses (:func:`dependency_order`); the outputs rewritten.

    Examples
    --------
    >>> a, b = se.symbols("a b")
    >>> body, outs = eliminate([], [se.sin(a + b) * a, se.sin(a + b) * b])
    >>> body
    [(x0, sin(a + b))]
    >>> outs
    [a*x0, b*x0]
    """
    exprs = [e for _, e in assignments] + list(outputs)
    reps, reduced = se.cse(exprs)
    out = [(se.Symbol(f"x{i}"), e) for i, (_, e) in enumerate(reps)]
    rename = {s: se.Symbol(f"x{i}") for i, (s, _) in enumerate(reps) if s.name != f"x{i}"}
    body = [(s, e.xreplace(rename) if rename else e) for (s, _), e in
            zip(assignments, reduced[:len(assignments)])]
    outs = [e.xreplace(rename) if rename else e for e in reduced[len(assignments):]]
    # cse temporaries may depend on earlier assignments: place each before first use
    return dependency_order(out, body), outs


def dependency_order(cse_defs: list[tuple[se.Symbol, se.Basic]],
                     body: list[tuple[se.Symbol, se.Basic]]) -> list[tuple[se.Symbol, se.Basic]]:
    """Topological order of the assignments (each after the temporaries it uses).

    The order is that of rounds: round 0 holds the assignments that use no temporary, round r
    those whose temporaries are all in earlier rounds; within a round the given order is kept.
    An assignment's round is therefore 1 + the largest round of the temporaries it uses, which
    is computed once per assignment (linear time) instead of by repeated scans.

    Parameters
    ----------
    cse_defs : list of (symengine.Symbol, symengine.Basic)
        Assignments placed first within their round.
    body : list of (symengine.Symbol, symengine.Basic)
        The other assignments.

    Returns
    -------
    list of (symengine.Symbol, symengine.Basic)
        All of them, each after every assignment whose symbol it uses.

    Raises
    ------
    RuntimeError
        If the assignments use each other in a cycle.
    """
    pending = list(cse_defs) + list(body)
    index = {s: k for k, (s, _) in enumerate(pending)}
    deps = [[index[x] for x in e.free_symbols if x in index] for _, e in pending]
    level = [-1] * len(pending)
    for start in range(len(pending)):
        if level[start] >= 0:
            continue
        stack, open_ = [start], set()
        while stack:
            v = stack[-1]
            if level[v] >= 0:
                stack.pop()
                continue
            todo = [d for d in deps[v] if level[d] < 0]
            if not todo:
                level[v] = 1 + max((level[d] for d in deps[v]), default=-1)
                open_.discard(v)
                stack.pop()
            elif v in open_:
                raise RuntimeError("cyclic program")
            else:
                open_.add(v)
                stack.extend(todo)
    return [pending[k] for k in sorted(range(len(pending)), key=lambda k: (level[k], k))]
