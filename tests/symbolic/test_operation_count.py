"""Operation count of a straight-line program (symbolic/operation_count.py).

Oracles: hand counts of small expressions; an independent count of the emitted C by its tokens
(binary * + -, calls of sin and cos: symbolic_helpers.count_c) for the explicit and recursive
programs of several arms and for random programs."""

import numpy as np
import pytest
import symengine as se
from symbolic_helpers import count_c, explicit_program, robot

from gd_analyze.symbolic.codegen import Program
from gd_analyze.symbolic.emit import emit_c
from gd_analyze.symbolic.operation_count import count_operations, is_number
from gd_analyze.symbolic.recursive import recursive_program

x, y, z = se.symbols("x y z")


def _tally(mul, add, sin, cos):
    return {"multiplications": mul, "additions": add, "sin": sin, "cos": cos}


@pytest.mark.parametrize("assignments, outputs, expected", [
    ([], [x * y * z], (2, 0, 0, 0)),
    ([], [x - y + 1.0], (0, 2, 0, 0)),                  # a subtraction is an addition
    ([], [-x], (0, 0, 0, 0)),                           # a negation is free
    ([], [1.0 * x + 0 * y], (0, 0, 0, 0)),              # times 1, plus 0: free
    ([], [x ** 3], (2, 0, 0, 0)),                       # a cube is two multiplications
    ([], [3.0 * x], (1, 0, 0, 0)),
    ([], [-2.0 * x * y], (2, 0, 0, 0)),                 # the sign is free, the 2 is not
    ([], [se.Integer(2) * 3.5], (0, 0, 0, 0)),          # between constants: free
    ([], [se.sign(x) * y], (1, 0, 0, 0)),               # sign: comparisons, not counted
    ([(z, se.sin(x) * se.cos(y))], [z + 2.0 * z * x], (3, 1, 1, 1)),
])
def test_counting_rule_by_hand(assignments, outputs, expected):
    assert count_operations(assignments, outputs) == _tally(*expected)


@pytest.mark.parametrize("expr", [se.exp(x), x ** -1, x ** se.Rational(1, 2), se.tan(x)])
def test_what_the_printers_cannot_write_is_refused(expr):
    with pytest.raises(ValueError, match="unexpected"):
        count_operations([], [expr])


def test_numbers_are_symengine_constants():
    assert all(is_number(v) for v in (se.Integer(3), se.RealDouble(-0.5), se.Rational(1, 3)))
    assert not any(is_number(v) for v in (x, x + 1, se.sin(se.Integer(1)) * x))


@pytest.mark.parametrize("name", ["two-link", "mixed"])
def test_count_of_explicit_programs_is_that_of_the_emitted_c(name):
    _, prog = explicit_program(name)
    assert all(_as_programs_are(e) for e in [e for _, e in prog.assignments] + prog.outputs)
    assert count_c(emit_c(prog, {})) == prog.cost()
    assert prog.cost() == count_operations(prog.assignments, prog.outputs)


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_count_of_recursive_programs_is_that_of_the_emitted_c(name):
    prog = recursive_program(robot(name))
    assert all(_as_programs_are(e) for e in [e for _, e in prog.assignments] + prog.outputs)
    assert count_c(emit_c(prog, {})) == count_operations(prog.assignments, prog.outputs)


def _random_expr(rng, atoms, depth):
    """A random expression of sums, products, squares and cubes of symbols, sin and cos, with
    coefficients of either sign (some +-1, written as integers as the programs write them)."""
    if depth == 0 or rng.random() < 0.2:
        return atoms[rng.integers(len(atoms))]
    kind = rng.integers(5)
    parts = [_random_expr(rng, atoms, depth - 1) for _ in range(rng.integers(2, 5))]
    if kind == 0:
        return se.Add(*parts) + se.RealDouble(rng.uniform(-2, 2))
    if kind == 1:
        coef = [se.Integer(1), se.Integer(-1), se.RealDouble(rng.uniform(-3, 3))]
        return coef[rng.integers(3)] * se.Mul(*parts)
    if kind == 2:
        return atoms[rng.integers(len(atoms))] ** int(rng.integers(2, 4))
    if kind == 3:
        return (se.sin if rng.random() < 0.5 else se.cos)(parts[0])
    return parts[0] - se.RealDouble(rng.uniform(-2, 2)) * parts[1]


def _as_programs_are(e):
    """Whether an expression is of the form the programs' expressions take, for which the
    count is that of the printed code: every power's base a symbol (a power is printed as a
    product of copies of its base) and no product's coefficient a floating +1.0 (printed)."""
    if e.is_Pow and not e.args[0].is_Symbol:
        return False
    if e.is_Mul and any(is_number(a) and float(a) == 1.0 for a in e.args):
        return False
    return all(_as_programs_are(a) for a in e.args)


def test_count_of_random_programs_is_that_of_the_emitted_c():
    rng = np.random.default_rng(8)
    checked = 0
    while checked < 40:
        atoms = list(se.symbols("q0 q1 qd0 qd1 qdd0"))
        assignments = []
        for k in range(int(rng.integers(1, 6))):
            sym = se.Symbol(f"t{k}")
            assignments.append((sym, _random_expr(rng, atoms, 3)))
            atoms.append(sym)
        outputs = [_random_expr(rng, atoms, 3) for _ in range(2)]
        if not all(_as_programs_are(e) for e in [e for _, e in assignments] + outputs):
            continue
        prog = Program(n=2, assignments=assignments, outputs=outputs)
        assert count_c(emit_c(prog, {})) == count_operations(assignments, outputs), checked
        checked += 1
