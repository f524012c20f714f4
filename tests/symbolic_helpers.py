"""Helpers of the symbolic-model tests: the arms, Pinocchio's rnea of them, the explicit
programs of two small arms, their symbolic evaluation, their compiled C, and an independent
count of the operations of emitted C."""

import ctypes
import re
import shutil
import subprocess
from functools import cache

import chapter_two_link
import numpy as np
import pinocchio as pin
import symengine as se
from scipy.spatial.transform import Rotation

from gd_analyze.dynamics.opcount import random_chain
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.robot_spec import robot_from_chain, robot_from_dict
from gd_analyze.model.robots import load_robot
from gd_analyze.symbolic.codegen import build_program
from gd_analyze.symbolic.emit import emit_c
from gd_analyze.symbolic.explicit import derive, model_terms

#: Built-in arms: DH (PUMA), DH with a prismatic joint (Stanford), URDF (UR5, Panda).
BUILTIN = ("puma560", "stanford", "ur5", "panda")
ROBOTS = BUILTIN + ("modified-dh", "mixed-chain")


def mixed_chain(n=6, seed=5):
    """A random general chain: random placements, revolute and prismatic joints, full
    inertia tensors, gravity off the axes."""
    rng = np.random.default_rng(seed)
    joints = []
    for i in range(n):
        B = rng.normal(size=(3, 3)) * 0.1
        S = B @ B.T
        joints.append({
            "type": "prismatic" if i in (1, 4) else "revolute",
            "rotation": Rotation.random(random_state=seed * 100 + i).as_matrix(),
            "translation": rng.uniform(-0.3, 0.3, 3), "mass": rng.uniform(0.3, 4.0),
            "com": rng.uniform(-0.2, 0.2, 3), "inertia": np.trace(S) * np.eye(3) - S,
            "q_min": -np.inf, "q_max": np.inf, "qd_max": 2.0, "qdd_max": None})
    return robot_from_chain("mixed", joints, [0.5, -1.0, -9.5], source="<test>")


def modified_dh():
    """A random 6R arm in Craig's modified DH convention."""
    spec = random_chain(6, seed=11).to_dict()
    spec["convention"] = "modified"
    spec["name"] = "random-mdh"
    return robot_from_dict(spec)


def robot(name):
    if name == "modified-dh":
        out = modified_dh()
        assert out.convention == "modified"
        return out
    if name == "mixed-chain":
        return mixed_chain()
    return load_robot(name)


def states(robot, count, seed):
    """Random (q, qd, qdd) of shape (count, n): q within +-pi, qd and qdd within +-3."""
    rng = np.random.default_rng(seed)
    n = robot.n
    return (rng.uniform(-np.pi, np.pi, (count, n)), rng.uniform(-3, 3, (count, n)),
            rng.uniform(-3, 3, (count, n)))


def rnea(robot, q, qd, qdd, gravity=True):
    """Pinocchio's inverse dynamics at every set point [N m or N], shape (N, n)."""
    model = pinocchio_model(robot)
    if not gravity:
        model.gravity = pin.Motion.Zero()
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


_TOKEN = re.compile(r"\s*(?:(\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?)|([A-Za-z_]\w*)"
                    r"|(.))")


def count_c(src):
    """Operations of the emitted C by its tokens: binary * + - (a - after an operand is a
    subtraction, else a free negation), calls of sin and cos; no division allowed."""
    tally = {"multiplications": 0, "additions": 0, "sin": 0, "cos": 0}
    body = [ln for ln in src.splitlines()
            if ln.strip().startswith(("const double", "tau["))]
    for line in body:
        rhs = line.split("=", 1)[1].rstrip().rstrip(";")
        prev = None
        for num, name, op in _TOKEN.findall(rhs):
            if num:
                kind = "operand"
            elif name:
                kind = "name"
                if name in ("sin", "cos"):
                    tally[name] += 1
            else:
                op = op.strip()
                if not op:
                    continue
                assert op != "/", line
                binary = prev in ("operand", "name", ")", "]")
                if op == "*":
                    assert binary, line
                    tally["multiplications"] += 1
                elif op in "+-" and binary:
                    tally["additions"] += 1
                kind = op
            prev = kind
    return tally


#: The chapter's two-link arm of the explicit-program tests: m1, m2 [kg], l [m], g [m/s^2].
TWO_LINK = (1.1, 0.7, 0.9, 9.81)


def two_link(offsets=(0.0, 0.0)):
    """The chapter's two-link arm (:data:`TWO_LINK`), with joint offsets [deg]."""
    spec = chapter_two_link.spec(*TWO_LINK)
    for link, off in zip(spec["link"], offsets):
        link["offset_deg"] = off
    return robot_from_dict(spec)


@cache
def explicit_program(name, trig_mode="products"):
    """The arm ("two-link" or "mixed") and the program of its whole explicit model."""
    arm = {"two-link": two_link, "mixed": lambda: mixed_chain(3, seed=2)}[name]()
    prog = build_program(model_terms(derive(arm)), arm.n, np.zeros(arm.n), trig_mode=trig_mode,
                         prismatic=arm.prismatic)
    return arm, prog


def symbolic_tau(prog, q, qd, qdd):
    """Evaluate a program's expression: every assignment substituted in order, then the
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


def compile_c(tmp_path, prog, name="m", optimise="-O1"):
    """The program's emitted C compiled by the machine's cc (-std=c99 -pedantic -Wall -Wextra
    -Werror, ``optimise``) and loaded: tau(q, qd, qdd) on arrays of shape (N, n)."""
    cc = shutil.which("cc")
    assert cc, "the machine's C compiler (cc) is required"
    src = tmp_path / f"{name}.c"
    src.write_text(emit_c(prog, {"robot": "test"}))
    lib = tmp_path / f"lib{name}.so"
    subprocess.run([cc, optimise, "-shared", "-fPIC", "-std=c99", "-pedantic", "-Wall", "-Wextra",
                    "-Werror", "-o", str(lib), str(src), "-lm"], check=True)
    fn = ctypes.CDLL(str(lib)).gd_tau
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
