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
