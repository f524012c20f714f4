"""C99 and numpy Python source of a straight-line program (symbolic/emit.py).

Oracles: the program's own symbolic expression (symengine's arithmetic, no printer) and
Pinocchio's rnea for the explicit programs of two arms; for a program written by hand, the same
formulas written directly in numpy (negative coefficients, powers, sign(0) = 0, a sum longer
than one printed run); the emitted C compiled by the machine's cc under -Wall -Wextra -Werror."""

import ast

import numpy as np
import pytest
import symengine as se
from scales import joint_relative_error
from symbolic_helpers import compile_c, explicit_program, rnea, states, symbolic_tau

from gd_analyze.symbolic.codegen import Program
from gd_analyze.symbolic.emit import (
    emit_c,
    emit_python,
    emit_state_python,
    python_function,
    state_function,
)

TOL = 1e-10

q0, q1, qd0, qd1, qdd0, qdd1 = se.symbols("q0 q1 qd0 qd1 qdd0 qdd1")
#: Coefficients of the long sum of the hand-written program: alternating signs.
COEF = [(-1.0) ** k * (0.5 + 0.01 * k) for k in range(1, 41)]


def _hand_program():
    """tau_0 = sum_k c_k cos(k q1) qdd0 - 2.5 (sin(q0 + 0.25) qd1)^2 + 0.3 sign(qd0) - qdd1,
    tau_1 = -(q0 + 0.25) qd0^3 + 1.5 cos(q0 - q1) - 0.75."""
    t, s, p, w = se.symbols("t s p w")
    assignments = [
        (t, q0 + 0.25),
        (s, se.sin(t) * qd1),
        (p, s ** 2),
        (w, se.Add(*[se.RealDouble(c) * se.cos(k * q1) * qdd0 for k, c in enumerate(COEF, 1)])),
    ]
    outputs = [w - 2.5 * p + se.sign(qd0) * 0.3 - qdd1,
               -t * qd0 ** 3 + 1.5 * se.cos(q0 - q1) - 0.75]
    return Program(n=2, assignments=assignments, outputs=outputs)


def _hand_numpy(q, qd, qdd):
    """The same formulas, written in numpy."""
    t = q[:, 0] + 0.25
    p = (np.sin(t) * qd[:, 1]) ** 2
    k = np.arange(1, 41)
    w = (np.asarray(COEF) * np.cos(np.outer(q[:, 1], k))).sum(axis=1) * qdd[:, 0]
    return np.stack([w - 2.5 * p + 0.3 * np.sign(qd[:, 0]) - qdd[:, 1],
                     -t * qd[:, 0] ** 3 + 1.5 * np.cos(q[:, 0] - q[:, 1]) - 0.75], axis=1)


def _hand_states():
    rng = np.random.default_rng(12)
    q, qd, qdd = rng.uniform(-3, 3, (3, 25, 2))
    qd[:5, 0] = 0.0                                   # sign(0) = 0, as numpy's
    return q, qd, qdd


def test_hand_program_python_equals_numpy():
    prog = _hand_program()
    q, qd, qdd = _hand_states()
    got = python_function(prog)(q, qd, qdd)
    assert np.abs(got - _hand_numpy(q, qd, qdd)).max() < 1e-12
    assert np.abs(got - symbolic_tau(prog, q, qd, qdd)).max() < 1e-12


def _one_by_one(prog, q, qd, qdd):
    one = state_function(prog)
    return np.array([one(*(x.tolist() for x in s)) for s in zip(q, qd, qdd)])


def test_hand_program_at_one_state_equals_numpy():
    """The one-state function in floats: the hand-written numpy formulas (sign(0) = 0 among
    them) and the symbolic expression, at each of 25 states."""
    prog = _hand_program()
    q, qd, qdd = _hand_states()
    got = _one_by_one(prog, q, qd, qdd)
    assert got.shape == (25, 2)
    assert np.abs(got - _hand_numpy(q, qd, qdd)).max() < 1e-12
    assert np.abs(got - symbolic_tau(prog, q, qd, qdd)).max() < 1e-12


@pytest.mark.parametrize("name", ["two-link", "mixed"])
def test_one_state_function_equals_rnea_and_imports_only_math(name):
    """Explicit programs of two arms at one state at a time against Pinocchio's rnea; the
    module imports only math and holds no header text."""
    arm, prog = explicit_program(name)
    q, qd, qdd = states(arm, 40, 5)
    assert joint_relative_error(_one_by_one(prog, q, qd, qdd), rnea(arm, q, qd, qdd)) < 1e-10
    tree = ast.parse(emit_state_python(prog))
    imports = [a.name for node in ast.walk(tree) if isinstance(node, ast.Import)
               for a in node.names]
    assert imports == ["math"]
    assert not any(isinstance(node, ast.ImportFrom) for node in ast.walk(tree))


def test_hand_program_c_equals_numpy(tmp_path):
    prog = _hand_program()
    q, qd, qdd = _hand_states()
    got = compile_c(tmp_path, prog, "hand")(q, qd, qdd)
    assert np.abs(got - _hand_numpy(q, qd, qdd)).max() < 1e-12


def test_a_very_long_sum_compiles_in_python_and_c(tmp_path):
    """3,000 terms in one output: printed in runs, so Python's compiler does not nest them all."""
    rng = np.random.default_rng(3)
    c = rng.uniform(-1, 1, 3000)
    a, v, acc = se.symbols("q0 qd0 qdd0")
    prog = Program(n=1, assignments=[], outputs=[
        se.Add(*[se.RealDouble(ck) * a ** 2 * se.cos(k * v) for k, ck in enumerate(c, 1)])
        + 0.5 * acc])
    q, qd, qdd = rng.uniform(-1, 1, (3, 6, 1))
    want = (c * np.cos(np.outer(qd[:, 0], np.arange(1, 3001)))).sum(axis=1)[:, None] * q ** 2 \
        + 0.5 * qdd
    assert joint_relative_error(python_function(prog)(q, qd, qdd), want) < 1e-12
    # -O0: the optimiser takes 8 s over the one 3,000-term expression, and is not under test
    assert joint_relative_error(compile_c(tmp_path, prog, "long", "-O0")(q, qd, qdd), want) \
        < 1e-12


@pytest.mark.parametrize("name", ["two-link", "mixed"])
def test_compiled_c_equals_the_symbolic_expression_and_rnea(tmp_path, name):
    arm, prog = explicit_program(name)
    q, qd, qdd = states(arm, 8, 5)
    tau_c = compile_c(tmp_path, prog)(q, qd, qdd)
    assert joint_relative_error(tau_c, symbolic_tau(prog, q, qd, qdd)) < 1e-13
    assert joint_relative_error(tau_c, rnea(arm, q, qd, qdd)) < TOL


def test_emitted_c_includes_only_math_h_and_defines_one_function():
    _, prog = explicit_program("two-link")
    src = emit_c(prog, {"robot": "two-link"})
    assert [ln for ln in src.splitlines() if ln.startswith("#")] == ["#include <math.h>"]
    assert " * robot: two-link" in src.splitlines()
    top = [ln for ln in src.splitlines() if ln and not ln[0].isspace()
           and not ln.startswith(("/*", " *", "#", "{", "}"))]
    assert top == ["void gd_tau(const double *q, const double *qd, const double *qdd, "
                   "double *tau)"]


def test_emitted_python_imports_only_numpy_and_checks_its_input():
    _, prog = explicit_program("two-link")
    src = emit_python(prog, {"robot": "two-link", "tolerance": 0.01})
    tree = ast.parse(src)
    imports = [a.name for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))
               for a in node.names]
    assert imports == ["numpy"]
    assert "# robot: two-link" in src.splitlines()
    tau = python_function(prog)
    one = tau(np.zeros(2), np.zeros(2), np.zeros(2))
    assert one.shape == (1, 2)
    with pytest.raises(ValueError, match="expected 2 joints"):
        tau(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros((1, 3)))


def test_emitted_python_module_is_the_compiled_function():
    """The source written to a file computes what python_function computes (compiled once)."""
    arm, prog = explicit_program("mixed")
    ns = {}
    exec(compile(emit_python(prog, {"robot": "mixed"}), "<test>", "exec"), ns)
    q, qd, qdd = states(arm, 10, 9)
    assert np.array_equal(ns["tau"](q, qd, qdd), python_function(prog)(q, qd, qdd))
    assert python_function(prog) is python_function(prog)
