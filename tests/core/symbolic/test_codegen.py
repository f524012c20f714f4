"""Straight-line code of an explicit model (core/symbolic/codegen.py).

Oracles: the program's own symbolic expression (the assignments substituted into the outputs
by symengine and evaluated numerically) for the emitted Python and the compiled C; Pinocchio's
rnea for what the program computes; the chapter's two-link closed forms; an independent
token count of the emitted C for the operation count; hand counts of small expressions."""

import ast
import ctypes
import shutil
import subprocess
from functools import cache

import chapter_two_link
import numpy as np
import pytest
import symengine as se
from symbolic_helpers import count_c, mixed_chain, rnea, states

from gd_analyze.core.model.robot_spec import robot_from_dict
from gd_analyze.core.symbolic.codegen import (
    C_FUNCTION,
    build_program,
    count_operations,
    emit_c,
    emit_python,
    python_function,
)
from gd_analyze.core.symbolic.explicit import derive, model_terms

TOL = 1e-10
M1, M2, L, G = 1.1, 0.7, 0.9, 9.81


OFFSET_DEG = (30.0, -45.0)


def _two_link(offsets=(0.0, 0.0)):
    spec = chapter_two_link.spec(M1, M2, L, G)
    for link, off in zip(spec["link"], offsets):
        link["offset_deg"] = off
    return robot_from_dict(spec)


@cache
def program(name, trig_mode="products"):
    """The arm and the program of its whole explicit model (terms in q: offsets inside)."""
    arm = {"two-link": _two_link, "mixed": lambda: mixed_chain(3, seed=2)}[name]()
    prog = build_program(model_terms(derive(arm)), arm.n, np.zeros(arm.n), trig_mode=trig_mode,
                         prismatic=arm.prismatic)
    return arm, prog


def symbolic_tau(prog, q, qd, qdd):
    """Evaluate the program's expression: every assignment substituted in order, then the
    outputs at each state (symengine's own arithmetic, no printer involved)."""
    n = prog.n
    out = np.empty(q.shape)
    for k in range(q.shape[0]):
        env = {}
        for i in range(n):
            env[se.Symbol(f"q{i}")] = q[k, i]
            env[se.Symbol(f"qd{i}")] = qd[k, i]
            env[se.Symbol(f"qdd{i}")] = qdd[k, i]
        for sym, expr in prog.assignments:
            env[sym] = float(expr.subs(env))
        out[k] = [float(e.subs(env)) for e in prog.outputs]
    return out


def _rel(a, b):
    scale = np.abs(b).max(axis=0)
    assert (scale > 0).all()
    err = np.abs(a - b).max(axis=0) / scale
    assert np.isfinite(err).all()
    return float(err.max())


@pytest.mark.parametrize("name", ["two-link", "mixed"])
def test_python_equals_the_symbolic_expression_and_rnea(name):
    arm, prog = program(name)
    q, qd, qdd = states(arm, 40, 3)
    tau = python_function(prog)(q, qd, qdd)
    assert _rel(tau[:8], symbolic_tau(prog, q[:8], qd[:8], qdd[:8])) < 1e-13
    assert _rel(tau, rnea(arm, q, qd, qdd)) < TOL


def test_two_link_program_is_the_chapters_closed_form_and_offsets_shift_the_angles():
    """theta = q + offset: the program built with offsets from the terms of the arm without
    them is the chapter's closed form at theta, and rnea of the arm with those offsets."""
    _, prog = program("two-link")
    arm = _two_link()
    offset = np.radians(OFFSET_DEG)
    shifted = build_program(model_terms(derive(arm)), 2, offset)
    rng = np.random.default_rng(4)
    q, qd, qdd = rng.uniform(-3, 3, (3, 30, 2))
    for p, theta in ((prog, q), (shifted, q + offset)):
        D_tran, D_rot, h_tran, h_rot, c = chapter_two_link.terms(theta, qd, M1, M2, L, G)
        want = np.einsum("kij,kj->ki", D_tran + D_rot, qdd) + h_tran + h_rot + c
        assert _rel(python_function(p)(q, qd, qdd), want) < 1e-12
    assert _rel(python_function(shifted)(q, qd, qdd), rnea(_two_link(OFFSET_DEG), q, qd, qdd)) \
        < TOL
    assert _rel(python_function(shifted)(q[:4], qd[:4], qdd[:4]),
                symbolic_tau(shifted, q[:4], qd[:4], qdd[:4])) < 1e-13


def _compile(tmp_path, prog):
    cc = shutil.which("cc")
    assert cc, "the machine's C compiler (cc) is required"
    src = tmp_path / "m.c"
    src.write_text(emit_c(prog, {"robot": "test"}))
    lib = tmp_path / "libm_codegen.so"
    subprocess.run([cc, "-O1", "-shared", "-fPIC", "-std=c99", "-pedantic", "-Wall", "-Wextra",
                    "-Werror", "-o", str(lib), str(src), "-lm"], check=True)
    fn = getattr(ctypes.CDLL(str(lib)), C_FUNCTION)
    dp = ctypes.POINTER(ctypes.c_double)
    fn.argtypes, fn.restype = [dp, dp, dp, dp], None

    def tau(q, qd, qdd):
        res = np.empty_like(q)
        for k in range(q.shape[0]):
            args = [np.ascontiguousarray(x[k]) for x in (q, qd, qdd)] + [np.empty(prog.n)]
            fn(*(a.ctypes.data_as(dp) for a in args))
            res[k] = args[-1]
        return res
    return tau


@pytest.mark.parametrize("name", ["two-link", "mixed"])
def test_compiled_c_equals_the_symbolic_expression(tmp_path, name):
    arm, prog = program(name)
    q, qd, qdd = states(arm, 8, 5)
    tau_c = _compile(tmp_path, prog)(q, qd, qdd)
    assert _rel(tau_c, symbolic_tau(prog, q, qd, qdd)) < 1e-13
    assert _rel(tau_c, rnea(arm, q, qd, qdd)) < TOL


@pytest.mark.parametrize("name", ["two-link", "mixed"])
def test_count_is_that_of_the_emitted_c(name):
    _, prog = program(name)
    assert count_c(emit_c(prog, {})) == prog.cost()
    assert prog.cost() == count_operations(prog.assignments, prog.outputs)


def test_trig_modes_compute_the_same_torques():
    """"products": cos and sin of the joint angles are the only calls (at most n each);
    "calls": one call per compound angle, no fewer calls."""
    arm, prod = program("mixed", "products")
    _, calls = program("mixed", "calls")
    q, qd, qdd = states(arm, 30, 6)
    assert _rel(python_function(calls)(q, qd, qdd), python_function(prod)(q, qd, qdd)) < 1e-12
    n_rev = int((~np.asarray(arm.prismatic)).sum())
    assert prod.cost()["sin"] <= n_rev and prod.cost()["cos"] <= n_rev
    assert calls.cost()["sin"] + calls.cost()["cos"] >= prod.cost()["sin"] + prod.cost()["cos"]


def test_counting_rule_by_hand():
    x, y, z = se.symbols("x y z")
    cases = [
        ([], [x * y * z], (2, 0, 0, 0)),
        ([], [x - y + 1.0], (0, 2, 0, 0)),                  # a subtraction is an addition
        ([], [-x], (0, 0, 0, 0)),                           # a negation is free
        ([], [1.0 * x + 0 * y], (0, 0, 0, 0)),              # times 1, plus 0: free
        ([], [x ** 3], (2, 0, 0, 0)),                       # a cube is two multiplications
        ([], [3.0 * x], (1, 0, 0, 0)),
        ([(z, se.sin(x) * se.cos(y))], [z + 2.0 * z * x], (3, 1, 1, 1)),
    ]
    for assignments, outputs, (mul, add, sin, cos) in cases:
        assert count_operations(assignments, outputs) == {
            "multiplications": mul, "additions": add, "sin": sin, "cos": cos}, outputs
    with pytest.raises(ValueError, match="unexpected"):
        count_operations([], [se.exp(x)])


def test_emitted_python_imports_only_numpy_and_checks_its_input():
    arm, prog = program("two-link")
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
