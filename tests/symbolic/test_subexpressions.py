"""Common subexpressions of a straight-line program (symbolic/subexpressions.py).

Oracles: the given assignments and outputs evaluated in order by symengine's own arithmetic
(values must not change); the emitted Python's text (a repeated call appears once); for the
order, the definition itself (every assignment after each one whose symbol it uses)."""

import numpy as np
import pytest
import symengine as se

from gd_analyze.symbolic.codegen import Program
from gd_analyze.symbolic.emit import emit_python
from gd_analyze.symbolic.subexpressions import dependency_order, eliminate

q0, q1, qd0 = se.symbols("q0 q1 qd0")
INPUTS = (q0, q1, qd0)


def _evaluate(assignments, outputs, point):
    """Values of the outputs, the assignments substituted one after the other."""
    env = dict(zip(INPUTS, point))
    for sym, expr in assignments:
        env[sym] = float(expr.subs(env))
    return np.array([float(e.subs(env)) for e in outputs])


def _used_before_defined(assignments):
    """The assignments that use a symbol assigned only later (or never, if assigned)."""
    defined, assigned = set(), {s for s, _ in assignments}
    late = []
    for sym, expr in assignments:
        if any(x in assigned and x not in defined for x in expr.free_symbols):
            late.append(sym)
        defined.add(sym)
    return late


def _program():
    a, b = se.symbols("a b")
    assignments = [(a, q0 + q1), (b, se.sin(a) * qd0 + se.cos(q0 - q1) * se.sin(a) * q1)]
    outputs = [b * se.cos(q0 - q1) + se.sin(a) * qd0 ** 2,
               se.sin(a) * se.cos(q0 - q1) * qd0 - 2.0 * b]
    return assignments, outputs


def test_values_are_kept_and_each_assignment_follows_what_it_uses():
    assignments, outputs = _program()
    body, outs = eliminate(assignments, outputs)
    assert not _used_before_defined(body)
    rng = np.random.default_rng(5)
    for point in rng.uniform(-2, 2, (10, 3)):
        assert np.allclose(_evaluate(body, outs, point), _evaluate(assignments, outputs, point),
                           rtol=1e-14, atol=1e-14)


def test_repeated_calls_are_computed_once():
    assignments, outputs = _program()
    before = emit_python(Program(n=2, assignments=assignments, outputs=outputs), {})
    body, outs = eliminate(assignments, outputs)
    after = emit_python(Program(n=2, assignments=body, outputs=outs), {})
    assert before.count("np.sin(") == 4 and before.count("np.cos(") == 3
    assert after.count("np.sin(") == 1 and after.count("np.cos(") == 1


def test_new_temporaries_are_numbered_and_the_given_ones_keep_their_order():
    assignments, outputs = _program()
    body, _ = eliminate(assignments, outputs)
    given = {s for s, _ in assignments}
    new = sorted(s.name for s, _ in body if s not in given)
    assert new and new == sorted(f"x{k}" for k in range(len(new)))
    assert [s for s, _ in body if s in given] == [s for s, _ in assignments]


def test_random_programs_keep_their_values():
    rng = np.random.default_rng(2)
    for trial in range(20):
        atoms, assignments = list(INPUTS), []
        pieces = [se.sin(q0), se.cos(q1), q0 * qd0, se.sin(q0 + q1)]
        for k in range(5):
            sym = se.Symbol(f"t{k}")
            pick = [pieces[i] for i in rng.integers(len(pieces), size=3)]
            other = atoms[rng.integers(len(atoms))]
            expr = pick[0] * pick[1] + rng.uniform(-2, 2) * pick[2] * other
            assignments.append((sym, expr))
            atoms.append(sym)
            pieces.append(pick[0] * other)
        outputs = [atoms[-1] + pieces[-1], atoms[-2] * pieces[-2]]
        body, outs = eliminate(assignments, outputs)
        assert not _used_before_defined(body), trial
        point = rng.uniform(-1, 1, 3)
        assert np.allclose(_evaluate(body, outs, point), _evaluate(assignments, outputs, point),
                           rtol=1e-12, atol=1e-12), trial


def test_dependency_order_puts_each_assignment_after_what_it_uses():
    """A shuffled chain t0 <- t1 <- ... <- t9 comes back in chain order; independent
    assignments keep the given order, the first list before the second within a round."""
    t = se.symbols("t0:10")
    chain = [(t[0], q0 + 1)] + [(t[k], t[k - 1] * q1) for k in range(1, 10)]
    order = np.random.default_rng(1).permutation(10)
    shuffled = [chain[k] for k in order]
    got = dependency_order(shuffled[:4], shuffled[4:])
    assert [s for s, _ in got] == list(t)
    a, b, c = se.symbols("a b c")
    free = [(c, q0 * 2), (a, q1 * 3)], [(b, qd0 + 1)]
    assert [s for s, _ in dependency_order(*free)] == [c, a, b]


def test_dependency_order_rejects_a_cycle():
    a, b = se.symbols("a b")
    with pytest.raises(RuntimeError, match="cyclic"):
        dependency_order([], [(a, b + q0), (b, a * q1)])
