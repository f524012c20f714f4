"""Helpers of the symbolic-model tests: the arms, Pinocchio's rnea of them, and an
independent count of the operations of emitted C."""

import re

import numpy as np
import pinocchio as pin
from scipy.spatial.transform import Rotation

from gd_analyze.core.model.robot_spec import robot_from_chain, robot_from_dict
from gd_analyze.formulations.opcount import random_chain
from gd_analyze.formulations.pinocchio import pinocchio_model
from gd_analyze.io.robots import load_robot

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
