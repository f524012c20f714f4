"""Recordings the identification tests make themselves: a true arm (the robot file with its
inertial parameters changed, plus friction and offsets) driven along a finite Fourier series,
its torque computed by Pinocchio (``rnea``) plus the drives, with noise and irregular clocks."""

import importlib.metadata
from pathlib import Path

import numpy as np
import pinocchio as pin

from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.urdf import builtin_urdf_path

ERD = importlib.metadata.distribution("example-robot-data").locate_file(
    "cmeel.prefix/share/example-robot-data/robots")
#: A 7-joint URDF chain of example-robot-data.
XARM7 = ERD / "xarm_description/urdf/xarm7.urdf"


def fourier(n, t, seed, harmonics=5, base_hz=0.1, amplitude=0.8, centre=None):
    """q, qd, qdd of a finite Fourier series (Swevers et al. 1997) per joint, exact derivatives."""
    rng = np.random.default_rng(seed)
    w = 2 * np.pi * base_hz * np.arange(1, harmonics + 1)
    a = rng.normal(size=(harmonics, n)) * amplitude / np.arange(1, harmonics + 1)[:, None]
    b = rng.normal(size=(harmonics, n)) * amplitude / np.arange(1, harmonics + 1)[:, None]
    s, c = np.sin(np.outer(t, w)), np.cos(np.outer(t, w))
    q0 = np.zeros(n) if centre is None else np.asarray(centre, float)
    q = q0 + (s @ (a / w[:, None]) - c @ (b / w[:, None]))
    qd = c @ a + s @ b
    qdd = -s @ (a * w[:, None]) + c @ (b * w[:, None])
    return q, qd, qdd


def perturbed(model, seed, spread=0.2):
    """A copy of a Pinocchio model with every moving body's mass, centre of mass and inertia
    changed (physically consistent: scaled principal moments, rotated, mass scaled)."""
    rng = np.random.default_rng(seed)
    model = model.copy()
    for j in range(1, model.njoints):
        I = model.inertias[j]
        m = I.mass * (1 + spread * rng.uniform(-1, 1)) + 0.1
        c = I.lever + spread * 0.05 * rng.normal(size=3)
        Ic = I.inertia + np.diag(rng.uniform(0.001, 0.01, 3)) * (1 + I.mass)
        model.inertias[j] = pin.Inertia(m, c, 0.5 * (Ic + Ic.T))
    return model


class Truth:
    """The true arm: a Pinocchio model of the chain's joints, drives and offsets."""

    def __init__(self, model, ids, viscous, coulomb, offset, armature=None):
        self.model, self.data = model, model.createData()
        self.ids = ids
        self.v = [model.idx_vs[j] for j in ids]
        self.viscous, self.coulomb, self.offset = (np.asarray(x, float) for x in
                                                   (viscous, coulomb, offset))
        self.armature = np.zeros(len(ids)) if armature is None else np.asarray(armature, float)

    def _q(self, q):
        full = pin.neutral(self.model)
        for j, qj in zip(self.ids, q):
            iq = self.model.idx_qs[j]
            if self.model.nqs[j] == 2:
                full[iq:iq + 2] = np.cos(qj), np.sin(qj)
            else:
                full[iq] = qj
        return full

    def _v(self, v):
        full = np.zeros(self.model.nv)
        full[self.v] = v
        return full

    def torque(self, q, qd, qdd):
        """Pinocchio's rnea of the chain's joints plus Ia qdd + F_v qd + F_c sign(qd) + offset."""
        rigid = np.array([pin.rnea(self.model, self.data, self._q(a), self._v(b), self._v(c))[self.v]
                          for a, b, c in zip(q, qd, qdd)])
        return (rigid + self.armature * qdd + self.viscous * qd + self.coulomb * np.sign(qd)
                + self.offset)


def truth_for(robot, seed=1, urdf=None):
    """The true arm of a robot: its Pinocchio model (the URDF's own for a URDF robot) with changed
    inertial parameters, and friction and offsets of a few percent of its torque scale."""
    n = robot.n
    if urdf is not None:
        model = pin.buildModelFromUrdf(str(urdf))
        ids = [model.getJointId(name) for name in robot.joint_names()]
    else:
        model = pinocchio_model(robot)
        model.armature = np.zeros(n)
        ids = list(range(1, n + 1))
    rng = np.random.default_rng(seed + 100)
    return Truth(perturbed(model, seed), ids, viscous=rng.uniform(0.5, 2.0, n),
                 coulomb=rng.uniform(0.5, 2.0, n), offset=rng.uniform(-1, 1, n))


def write_recording(path, t, q, tau, qd=None, qdd=None):
    """Write t,q1..qn,tau1..taun[,qd..,qdd..] with repr floats."""
    n = q.shape[1]
    cols = ["t"] + [f"q{i + 1}" for i in range(n)] + [f"tau{i + 1}" for i in range(n)]
    blocks = [t[:, None], q, tau]
    if qd is not None:
        cols += [f"qd{i + 1}" for i in range(n)]
        blocks.append(qd)
    if qdd is not None:
        cols += [f"qdd{i + 1}" for i in range(n)]
        blocks.append(qdd)
    values = np.hstack(blocks)
    with open(path, "w") as fh:
        fh.write(",".join(cols) + "\n")
        for row in values:
            fh.write(",".join(repr(float(v)) for v in row) + "\n")
    return path


def irregular_clock(duration, seed, lo=0.7e-3, hi=8.8e-3):
    """Time stamps with steps uniform in [lo, hi] [s]."""
    rng = np.random.default_rng(seed)
    steps = rng.uniform(lo, hi, int(2 * duration / lo))
    t = np.concatenate([[0.0], np.cumsum(steps)])
    return t[t <= duration]


def builtin_urdf(name):
    """The path of a URDF built-in."""
    return builtin_urdf_path(name)


def write_echo_log(path, t, fields, joints, other_rows=()):
    """``rostopic echo -p`` of a sensor_msgs/JointState topic as ROS 1 writes it: ``%time``
    (received, 3 us after the stamp) and ``field.header.stamp`` in ns, the names then each
    array by index (``field.position0``...), the joints in another order in every other row,
    a gripper joint beside the chain's; ``other_rows``: the rows after which another publisher's
    message (the gripper's alone, fewer cells) stands. Returns the stamps [ns] / 1e9: t [s]."""
    stamp = 1_700_000_000_000_000_000 + np.round(t * 1e9).astype(np.int64)
    names = [*joints, "gripper"]
    kinds = [k for k in ("position", "velocity", "effort") if k in fields]
    lines = ["%time,field.header.seq,field.header.stamp,field.header.frame_id," + ",".join(
        f"field.{kind}{k}" for kind in ["name", *kinds] for k in range(len(names)))]
    for r, ns in enumerate(stamp):
        order = np.roll(np.arange(len(names)), r % 2)
        cells = [str(ns + 3000), str(r), str(ns), ""] + [names[k] for k in order] + [
            repr(float(fields[kind][r, k])) if k < len(joints) else "0.5"
            for kind in kinds for k in order]
        lines.append(",".join(cells))
        if r in other_rows:
            lines.append(",".join([str(ns + 5000), "9", str(ns + 4000), "", "gripper",
                                   *["0.5"] * len(kinds)]))
    Path(path).write_text("\n".join(lines) + "\n")
    return (stamp / 1e9).astype(float)
