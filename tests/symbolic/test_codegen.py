"""The straight-line program of an explicit model (symbolic/codegen.py).

Oracles: the program's own symbolic expression (the assignments substituted into the outputs
by symengine and evaluated numerically); Pinocchio's rnea for what the program computes; the
chapter's two-link closed forms. The printers and the operation count have their own tests
(test_emit.py, test_operation_count.py)."""

import chapter_two_link
import numpy as np
import pytest
from scales import joint_relative_error
from symbolic_helpers import TWO_LINK, explicit_program, rnea, states, symbolic_tau, two_link

from gd_analyze.symbolic.codegen import build_program
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.explicit import derive, model_terms

TOL = 1e-10
OFFSET_DEG = (30.0, -45.0)


@pytest.mark.parametrize("name", ["two-link", "mixed"])
def test_python_equals_the_symbolic_expression_and_rnea(name):
    arm, prog = explicit_program(name)
    q, qd, qdd = states(arm, 40, 3)
    tau = python_function(prog)(q, qd, qdd)
    assert joint_relative_error(tau[:8], symbolic_tau(prog, q[:8], qd[:8], qdd[:8])) < 1e-13
    assert joint_relative_error(tau, rnea(arm, q, qd, qdd)) < TOL


def test_two_link_program_is_the_chapters_closed_form_and_offsets_shift_the_angles():
    """theta = q + offset: the program built with offsets from the terms of the arm without
    them is the chapter's closed form at theta, and rnea of the arm with those offsets."""
    _, prog = explicit_program("two-link")
    arm = two_link()
    offset = np.radians(OFFSET_DEG)
    shifted = build_program(model_terms(derive(arm)), 2, offset)
    rng = np.random.default_rng(4)
    q, qd, qdd = rng.uniform(-3, 3, (3, 30, 2))
    for p, theta in ((prog, q), (shifted, q + offset)):
        D_tran, D_rot, h_tran, h_rot, c = chapter_two_link.terms(theta, qd, *TWO_LINK)
        want = np.einsum("kij,kj->ki", D_tran + D_rot, qdd) + h_tran + h_rot + c
        assert joint_relative_error(python_function(p)(q, qd, qdd), want) < 1e-12
    assert joint_relative_error(python_function(shifted)(q, qd, qdd), rnea(two_link(OFFSET_DEG), q, qd, qdd)) \
        < TOL
    assert joint_relative_error(python_function(shifted)(q[:4], qd[:4], qdd[:4]),
                symbolic_tau(shifted, q[:4], qd[:4], qdd[:4])) < 1e-13


def test_trig_modes_compute_the_same_torques():
    """"products": cos and sin of the joint angles are the only calls (at most n each);
    "calls": one call per compound angle, no fewer calls."""
    arm, prod = explicit_program("mixed", "products")
    _, calls = explicit_program("mixed", "calls")
    q, qd, qdd = states(arm, 30, 6)
    assert joint_relative_error(python_function(calls)(q, qd, qdd), python_function(prod)(q, qd, qdd)) < 1e-12
    n_rev = int((~np.asarray(arm.prismatic)).sum())
    assert prod.cost()["sin"] <= n_rev and prod.cost()["cos"] <= n_rev
    assert calls.cost()["sin"] + calls.cost()["cos"] >= prod.cost()["sin"] + prod.cost()["cos"]


def test_blocked_tau_is_the_emitted_program_on_any_layout(monkeypatch):
    """python_function evaluates TAU_BLOCK set points at a time on column-contiguous copies:
    every value is bit for bit the emitted module's tau on the whole arrays, for row-major,
    column-major and strided inputs, across uneven blocks; one state and no state keep their
    shapes, and a joint-count mismatch still raises ValueError."""
    import gd_analyze.symbolic.codegen as codegen
    from gd_analyze.symbolic.emit import emit_python

    arm, prog = explicit_program("mixed")
    ns = {}
    exec(compile(emit_python(prog, {}), "<emitted>", "exec"), ns)
    q, qd, qdd = states(arm, 23, 8)
    whole = ns["tau"](q, qd, qdd)
    monkeypatch.setattr(codegen, "TAU_BLOCK", 5)
    tau = python_function(prog)
    table = np.hstack([np.zeros((23, 1)), q, qd, qdd])      # a trajectory file's columns
    n = arm.n
    for args in ((q, qd, qdd), tuple(np.asfortranarray(x) for x in (q, qd, qdd)),
                 (table[:, 1:n + 1], table[:, n + 1:2 * n + 1], table[:, 2 * n + 1:])):
        got = tau(*args)
        assert got.shape == (23, n) and np.array_equal(got, whole)
    assert np.array_equal(tau(q[3], qd[3], qdd[3]), whole[3:4])
    assert np.array_equal(tau(q[2:5], qd[3], qdd[3]), ns["tau"](q[2:5], qd[3], qdd[3]))
    assert tau(q[:0], qd[:0], qdd[:0]).shape == (0, n)
    with pytest.raises(ValueError):
        tau(q[:, :-1], qd[:, :-1], qdd[:, :-1])
