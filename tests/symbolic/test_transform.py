"""Transformations of straight-line programs (symbolic/transform.py).

Oracles: the programs' own formulas evaluated by hand (numpy) with the substituted values, and
the derivatives of those formulas written out analytically."""

import numpy as np
import symengine as se

from gd_analyze.symbolic.codegen import Program
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.transform import finish_program, jacobian, substitute

q0, q1, qd0, qd1, qdd0, qdd1 = se.symbols("q0 q1 qd0 qd1 qdd0 qdd1")
t, u, x0 = se.symbols("t u x0")


def _program():
    """tau_0 = cos(q1) qdd0 + sin(q0) qd1^2 + 0.5 sign(qd0) + 9.81 cos(q0),
    tau_1 = (q0 + 1) qdd1 + qd0 qd1 sin(q1) q0."""
    return Program(2, [(t, se.cos(q1) * qdd0), (u, se.sin(q1) * q0), (x0, qd1 * qd1)],
                   [t + se.sin(q0) * x0 + 0.5 * se.sign(qd0) + 9.81 * se.cos(q0),
                    (q0 + 1) * qdd1 + qd0 * qd1 * u])


def _states():
    rng = np.random.default_rng(1)
    return rng.uniform(-2, 2, (3, 20, 2))


def test_substitute_folds_zero_velocities():
    prog = substitute(_program(), {qd0: 0, qd1: 0, qdd0: 0, qdd1: 0})
    q, _, _ = _states()
    got = python_function(prog)(q, np.zeros_like(q), np.zeros_like(q))
    want = np.stack([9.81 * np.cos(q[:, 0]), np.zeros(len(q))], axis=1)
    assert np.abs(got - want).max() < 1e-13
    assert all("qd" not in str(e) for _, e in prog.assignments) and prog.outputs[1] == 0
    assert prog.cost()["multiplications"] == 1 and prog.cost()["cos"] == 1


def test_jacobian_is_the_derivative():
    """d tau_0/d qdd0 = cos q1, d tau_1/d qdd1 = q0 + 1, d tau_0/d qd1 = 2 sin(q0) qd1,
    d tau_1/d qdd0 = 0."""
    assign, out = jacobian(_program(), [qdd0, qdd1, qd1], [(0, 0), (1, 1), (0, 2), (1, 0)])
    prog = finish_program(assign, out, 2)
    q, qd, _ = _states()
    got = np.array([_evaluate(prog, *x) for x in np.concatenate([q, qd], axis=1)])
    want = np.stack([np.cos(q[:, 1]), q[:, 0] + 1, 2 * np.sin(q[:, 0]) * qd[:, 1],
                     np.zeros(len(q))], axis=1)
    assert np.abs(got - want).max() < 1e-13
    assert out[3] == 0


def _evaluate(prog, a, b, c, d):
    env = {q0: a, q1: b, qd0: c, qd1: d}
    for s, e in prog.assignments:
        env[s] = float(e.subs(env))
    return [float(e.subs(env)) for e in prog.outputs]


def test_tidying_twice_keeps_names_apart():
    """A program tidied a second time (its cse temporaries x0, x1 ...) meets no name twice."""
    once = finish_program(*[[], [se.cos(q0) * se.sin(q1) * qd0, se.cos(q0) * se.sin(q1) * qd1]],
                          2)
    assert once.assignments and once.assignments[0][0].name == "x0"
    twice = substitute(Program(2, once.assignments, [o * se.cos(q0) for o in once.outputs]),
                       {qdd0: 0})
    names = [s.name for s, _ in twice.assignments]
    assert len(names) == len(set(names))
    q, qd, qdd = _states()
    want = (np.cos(q[:, 0]) ** 2 * np.sin(q[:, 1]))[:, None] * qd
    assert np.abs(python_function(twice)(q, qd, qdd) - want).max() < 1e-13


def _reference_finish(assignments, outputs, n, cse=True):
    """finish_program as it stands without keeping anything between calls: every sum tidied,
    every symbol's uses counted and every operation counted from scratch (the oracle of the
    kept results)."""
    import gd_analyze.symbolic.transform as T
    from gd_analyze.symbolic.factoring import factor_sum, prune_dead
    from gd_analyze.symbolic.subexpressions import eliminate

    def terms(e):
        if e.is_Add:
            return [s for a in e.args for s in terms(a)]
        if e.is_Mul and len(e.args) == 2:
            a, b = e.args
            if isinstance(a, se.Number) and b.is_Add:
                return [a * s for s in terms(b)]
            if isinstance(b, se.Number) and a.is_Add:
                return [b * s for s in terms(a)]
        return [e]

    def factored(e):
        return factor_sum(terms(e)) if e.is_Add else e

    def uses_of(e, uses):
        if e.is_Symbol:
            uses[e] = uses.get(e, 0) + 1
        for a in e.args:
            uses_of(a, uses)

    assignments, outputs = T._fresh_names(assignments, list(outputs))
    assignments = prune_dead(assignments, outputs)
    uses: dict = {}
    for e in [e for _, e in assignments] + outputs:
        uses_of(e, uses)
    defs, merged = dict(assignments), set()

    def expand(e):
        out = []
        for s in terms(e):
            coef, sym = se.Integer(1), s
            if s.is_Mul and len(s.args) == 2 and isinstance(s.args[0], se.Number) \
                    and s.args[1].is_Symbol:
                coef, sym = s.args
            if sym.is_Symbol and uses.get(sym) == 1 and sym in defs and defs[sym].is_Add:
                merged.add(sym)
                out += [coef * u for u in expand(defs[sym])]
            else:
                out.append(s)
        return out

    def flat(e):
        return se.Add(*expand(e)) if e.is_Add else e
    new = [(s, flat(e)) for s, e in assignments]
    outputs = [flat(e) for e in outputs]
    assignments = [(s, factored(e)) for s, e in new if s not in merged]
    if cse:
        assignments, outputs = eliminate(assignments, outputs)
    return ([(s, factored(e)) for s, e in assignments], [factored(e) for e in outputs])


def _tree(e):
    """An expression as nested tuples in the order its arguments are stored (and printed by
    the emitters): expressions equal as values can differ in it."""
    return (type(e).__name__, str(e)) if not e.args else (type(e).__name__,
                                                            tuple(_tree(a) for a in e.args))


def _ordered(assignments, outputs):
    return [(s.name, _tree(e)) for s, e in assignments], [_tree(e) for e in outputs]


def _random_program(rng, names, width=12, length=40):
    """A random straight-line program over a few symbols: sums of products with repeated
    coefficients and factors, some sums used once (merged) and some used often."""
    leaves = list(se.symbols(" ".join(names)))
    coefs = [se.RealDouble(v) for v in (0.5, -0.5, 2.0, 1.25)] + [se.Integer(1), se.Integer(-1)]
    assignments = []
    for k in range(length):
        terms = []
        for _ in range(int(rng.integers(1, 5))):
            factors = [leaves[int(i)] for i in rng.integers(0, len(leaves), rng.integers(1, 3))]
            terms.append(coefs[int(rng.integers(len(coefs)))] * se.Mul(*factors))
        sym = se.Symbol(f"t{k}")
        assignments.append((sym, se.Add(*terms)))
        leaves.append(sym)
    outputs = [se.Add(*[leaves[int(i)] for i in rng.integers(len(names), len(leaves), 3)])
               for _ in range(width)]
    return assignments, outputs


def test_tidying_with_kept_results_equals_tidying_from_scratch():
    """Programs that share expressions (as the form search's and the pruning's candidates do)
    are tidied and counted, with the results kept between calls, exactly as from scratch:
    the same assignments, outputs (their terms in the same order) and operation counts, over
    40 random programs (half of them variants of earlier ones with one assignment changed)."""
    import gd_analyze.symbolic.operation_count as C
    import gd_analyze.symbolic.transform as T

    rng = np.random.default_rng(7)
    names = ["a", "b", "c", "d", "qd0", "qd1"]
    made = []
    for k in range(40):
        if made and k % 2:
            assignments, outputs = made[int(rng.integers(len(made)))]
            assignments = list(assignments)
            i = int(rng.integers(len(assignments)))
            extra, _ = _random_program(rng, names, 1, 1)
            assignments[i] = (assignments[i][0], assignments[i][1] + extra[0][1])
        else:
            assignments, outputs = _random_program(rng, names)
        made.append((assignments, outputs))
        for cse in (True, False):
            got = finish_program(assignments, outputs, 2, cse)
            want = _reference_finish(assignments, outputs, 2, cse)
            assert _ordered(got.assignments, got.outputs) == _ordered(*want)
            assert got.cost() == C.count_operations(*want)
            scratch = dict.fromkeys(("multiplications", "additions", "sin", "cos"), 0)
            for e in [e for _, e in want[0]] + list(want[1]):
                C._count(e, scratch)
            assert got.cost() == scratch
    assert T._FACTORED and T._TWICE and C._COUNTED      # kept (the test's premise)


def test_kept_results_are_bounded(monkeypatch):
    """At most FACTORED_KEPT tidied sums (once and twice) and COUNTED_KEPT counts are
    kept."""
    import gd_analyze.symbolic.operation_count as C
    import gd_analyze.symbolic.transform as T

    monkeypatch.setattr(T, "FACTORED_KEPT", 5)
    monkeypatch.setattr(C, "COUNTED_KEPT", 5)
    assignments, outputs = _random_program(np.random.default_rng(3), ["a", "b", "c"])
    finish_program(assignments, outputs, 2).cost()
    finish_program(assignments, outputs, 2, cse=False).cost()
    assert len(T._FACTORED) <= 5 and len(T._USES) <= 5 and 0 < len(T._TWICE) <= 5
    assert len(C._COUNTED) <= 5
