"""The symbolic recursive Newton-Euler quantities (symbolic/newton_euler.py), run through
the module's own recursion and wrench assembly (no pruning, no base parameters).

Oracles: Pinocchio. Each part of the torque has its own: inertial (a) = crba(q) qdd,
gravity (g) = computeGeneralizedGravity(q), velocity (v) = nonLinearEffects(q, qd) - g; any
set of parts is the sum of its members' oracles, whichever form of the inertial moment
(:data:`FORMS`) each link takes."""

import itertools
from functools import cache

import numpy as np
import pinocchio as pin
import pytest
import symengine as se
from symbolic_helpers import robot, states

from gd_analyze.dynamics.base_parameters import standard_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.symbolic.codegen import Program
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.newton_euler import (
    FORMS,
    PARTS,
    Recursion,
    _Builder,
    _const,
    link_constants,
    link_torques,
)

TOL = 1e-10
ARMS = ("puma560", "stanford", "mixed-chain")
SETS = [frozenset(s) for r in (1, 2, 3) for s in itertools.combinations(PARTS, r)]


@cache
def arm(name):
    return robot(name)


def program(robot, parts, forms=None, lock_last=False):
    """tau of the given parts with the standard parameters, every link in one group."""
    rec = Recursion(robot, lock_last=lock_last, direct=forms)
    consts = link_constants(standard_parameters(robot))
    tau = link_torques(rec, [[(frozenset(parts), consts[j])] for j in range(robot.n)])
    return Program(n=robot.n, assignments=list(rec.b.assignments), outputs=list(tau))


@cache
def oracles(name):
    """Per part, Pinocchio's torque at 25 random states; and the states."""
    robot = arm(name)
    q, qd, qdd = states(robot, 25, 61)
    model = pinocchio_model(robot)
    data = model.createData()
    a, v, g = [], [], []
    for qk, qdk, qddk in zip(q, qd, qdd):
        M = pin.crba(model, data, qk)
        M = np.triu(M) + np.triu(M, 1).T
        grav = pin.computeGeneralizedGravity(model, data, qk)
        a.append(M @ qddk)
        g.append(grav)
        v.append(pin.nonLinearEffects(model, data, qk, qdk) - grav)
    return (q, qd, qdd), {"a": np.array(a), "v": np.array(v), "g": np.array(g)}


def _rel(a, b):
    scale = np.abs(b).max()
    assert scale > 0 and np.isfinite(a).all()
    return float(np.abs(a - b).max() / scale)


@pytest.mark.parametrize("name", ARMS)
@pytest.mark.parametrize("parts", SETS, ids=lambda s: "".join(sorted(s)))
def test_each_set_of_parts_is_the_sum_of_its_pinocchio_parts(name, parts):
    (q, qd, qdd), ref = oracles(name)
    tau = python_function(program(arm(name), parts))(q, qd, qdd)
    assert _rel(tau, sum(ref[p] for p in parts)) < TOL


@pytest.mark.parametrize("form", FORMS)
def test_every_form_of_the_inertial_moment_gives_the_same_torque(form):
    name = "mixed-chain"                   # full inertia tensors: every term of J w matters
    robot = arm(name)
    (q, qd, qdd), ref = oracles(name)
    forms = {j: form for j in range(robot.n)}
    tau = python_function(program(robot, PARTS, forms))(q, qd, qdd)
    assert _rel(tau, ref["a"] + ref["v"] + ref["g"]) < TOL


def test_a_last_link_symmetric_about_its_axis_lets_its_angle_be_locked():
    """PUMA link 6: XX = YY, no products, centre of mass on the axis; then tau does not depend
    on q_6, and the locked program (q_6 taken as 0) equals rnea at any q_6."""
    robot = arm("puma560")
    XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M = standard_parameters(robot)[-1]
    assert XX == YY and XY == XZ == YZ == MX == MY == 0
    (q, qd, qdd), ref = oracles("puma560")
    prog = program(robot, PARTS, lock_last=True)
    assert not any(s.name == "q5" for _, e in prog.assignments for s in e.free_symbols)
    tau = python_function(prog)(q, qd, qdd)
    assert _rel(tau, ref["a"] + ref["v"] + ref["g"]) < TOL


def test_builder_keeps_identical_expressions_and_negations_once():
    b = _Builder()
    x, y = se.symbols("x y")
    t = b(x * y + 1)
    assert b(x * y + 1) == t and b(-(x * y + 1)) == -t and len(b.assignments) == 1
    assert b(x) == x and b(3 * y) == 3 * y and len(b.assignments) == 1     # atomic: no temp


def test_constants_snap_near_zero_and_unit_values():
    assert _const(1e-13) == 0 and _const(1 - 1e-13) == 1 and _const(-1 + 1e-13) == -1
    assert float(_const(0.5)) == 0.5 and _const(1e-13, scale=1e-20) != 0
