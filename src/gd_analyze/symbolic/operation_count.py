"""Operation count of a straight-line program: multiplications, additions, sin and cos calls.

Counting rule (that of :mod:`gd_analyze.dynamics.opcount`): operations between numeric
constants are free, multiplying by +-1 and adding 0 are free, a negation is free, a
subtraction is an addition, a square is one multiplication; the calls to cos and sin are listed
separately. :func:`count_operations` is applied to the very expressions that
:mod:`gd_analyze.symbolic.emit` prints, so the count is that of the emitted code.
"""

from __future__ import annotations

from typing import Any

import symengine as se

__all__ = ["count_operations", "is_number"]


def is_number(x: se.Basic) -> bool:
    """Whether a symengine expression is a numeric constant (free in the count).

    Parameters
    ----------
    x : symengine.Basic

    Returns
    -------
    bool
    """
    return isinstance(x, se.Number) or getattr(x, "is_Number", False)


def _count(e, tally):
    if e.is_Symbol or is_number(e):
        return
    args = e.args
    if e.is_Add:
        tally["additions"] += len(args) - 1
    elif e.is_Mul:
        coeff = [a for a in args if is_number(a)]
        rest = len(args) - len(coeff)
        tally["multiplications"] += max(rest - 1, 0)
        if coeff and abs(float(coeff[0])) != 1.0:
            tally["multiplications"] += 1
    elif e.is_Pow:
        base, ex = args
        if not (is_number(ex) and float(ex) == int(float(ex)) and int(float(ex)) >= 2):
            raise ValueError(f"unexpected power {e}")
        tally["multiplications"] += int(float(ex)) - 1
        _count(base, tally)
        return
    elif isinstance(e, se.cos):
        tally["cos"] += 1
    elif isinstance(e, se.sin):
        tally["sin"] += 1
    elif isinstance(e, se.sign):        # friction's sign(qd): two comparisons, no arithmetic
        pass
    else:
        raise ValueError(f"unexpected expression {e}")
    for a in args:
        _count(a, tally)


def count_operations(assignments: list[tuple[se.Symbol, se.Basic]],
                     outputs: list[se.Basic]) -> dict[str, Any]:
    """Count the operations of a straight-line program (rule in the module docstring).

    Parameters
    ----------
    assignments : list of (Symbol, expression)
    outputs : list of expression

    Returns
    -------
    dict
        ``multiplications``, ``additions``, ``sin``, ``cos`` (ints).

    Examples
    --------
    >>> x, y = se.symbols("x y")
    >>> count_operations([], [2.0 * x * y + x**2 - y])
    {'multiplications': 3, 'additions': 2, 'sin': 0, 'cos': 0}
    """
    tally = dict.fromkeys(_KINDS, 0)
    for e in [e for _, e in assignments] + list(outputs):
        for kind, k in zip(_KINDS, _counted(e)):
            tally[kind] += k
    return tally


_KINDS = ("multiplications", "additions", "sin", "cos")
#: Most expressions whose counts :func:`_counted` keeps (then all forgotten at once).
COUNTED_KEPT = 50_000
_COUNTED: dict = {}


def _counted(e):
    """The counts of one expression, in the order of _KINDS (kept by expression: the programs
    a search compares share most of their expressions)."""
    if e.is_Symbol or is_number(e):
        return (0, 0, 0, 0)
    out = _COUNTED.get(e)
    if out is None:
        tally = dict.fromkeys(_KINDS, 0)
        _count(e, tally)
        out = tuple(tally[k] for k in _KINDS)
        if len(_COUNTED) >= COUNTED_KEPT:
            _COUNTED.clear()
        _COUNTED[e] = out
    return out
