"""Test helpers for the URDF import: a Pinocchio model built from a chain's joint dicts, and
the URDF's own Pinocchio model evaluated at the chain's joints (the others at q = 0)."""

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze.model.urdf import builtin_urdf_path

#: Tolerance and number of random states of the comparisons with the URDF's own model.
TOL = 1e-10
STATES = 200

TOY_URDF = """<?xml version="1.0"?>
<robot name="toy">
  <link name="world"/>
  <joint name="fix0" type="fixed"><parent link="world"/><child link="base"/>
    <origin xyz="0.1 0 0.2" rpy="0.3 0 0"/></joint>
  <link name="base"><inertial><mass value="2"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3" rpy="0 0.2 0"/><axis xyz="1 1 0"/>
    <limit velocity="2.0" effort="5"/></joint>
  <link name="l1"><inertial><origin xyz="0.1 0.02 0.03" rpy="0.1 0.2 0.3"/><mass value="1.5"/>
    <inertia ixx="0.02" iyy="0.03" izz="0.04" ixy="0.001" ixz="0.002" iyz="0.003"/></inertial></link>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.2 0 0" rpy="0 0 0.5"/><axis xyz="0 0 -1"/>
    <limit lower="-0.1" upper="0.3" velocity="0.5" effort="10"/></joint>
  <link name="l2"><inertial><origin xyz="0.0 0.05 0.1"/><mass value="0.8"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.015" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0.1 0.1" rpy="0.4 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" velocity="1.5" effort="10"/></joint>
  <link name="l3"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/>
    <inertia ixx="0.003" iyy="0.002" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="fix3" type="fixed"><parent link="l3"/><child link="tool"/>
    <origin xyz="0.2 0 0"/></joint>
  <link name="tool"><inertial><origin xyz="0.01 0 0"/><mass value="0.3"/>
    <inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="jb" type="revolute"><parent link="l2"/><child link="side"/>
    <origin xyz="0 -0.1 0" rpy="0 0.7 0"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <link name="side"><inertial><origin xyz="0 -0.05 0.02"/><mass value="0.4"/>
    <inertia ixx="0.001" iyy="0.002" izz="0.003" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>
"""


UR5 = builtin_urdf_path("ur5").read_text()
PANDA = builtin_urdf_path("panda").read_text()
# the upper arm's <inertial> in the shipped UR5 file
UR5_MASS = '<mass value="8.393"/>'
UR5_COM = '<origin rpy="0 0 0" xyz="0.0 0.0 0.28"/>'
UR5_IXX = 'ixx="0.22689067591"'
UR5_IZZ = 'izz="0.0151074"'

#: Broken copies of ur5.urdf: (name, text to replace in ur5.urdf, replacement, column the message names)
BAD_UR5 = [
    ("mass decimal comma", UR5_MASS, '<mass value="2,5"/>', "link 'upper_arm_link' <mass value>"),
    ("mass with unit", UR5_MASS, '<mass value="2.5kg"/>', "link 'upper_arm_link' <mass value>"),
    ("mass nan", UR5_MASS, '<mass value="nan"/>', "link 'upper_arm_link' <mass value>"),
    ("mass overflows", UR5_MASS, '<mass value="1e400"/>', "link 'upper_arm_link' <mass value>"),
    ("mass negative", UR5_MASS, '<mass value="-1"/>', "link 'upper_arm_link' <mass value>"),
    ("mass trailing blank", UR5_MASS, '<mass value="8.393 "/>',
     "link 'upper_arm_link' <mass value>"),
    ("mass missing", UR5_MASS, "", "link 'upper_arm_link' <mass>"),
    ("mass without value", UR5_MASS, "<mass/>", "link 'upper_arm_link' <mass value>"),
    ("com nan", UR5_COM, '<origin rpy="0 0 0" xyz="0.0 nan 0.28"/>',
     "link 'upper_arm_link' <inertial> <origin xyz>"),
    ("com two numbers", UR5_COM, '<origin rpy="0 0 0" xyz="0.0 0.28"/>',
     "link 'upper_arm_link' <inertial> <origin xyz>"),
    ("inertial rpy inf", UR5_COM, '<origin rpy="0 0 inf" xyz="0.0 0.0 0.28"/>',
     "link 'upper_arm_link' <inertial> <origin rpy>"),
    ("ixx inf", UR5_IXX, 'ixx="inf"', "link 'upper_arm_link' <inertia ixx>"),
    ("ixx overflows", UR5_IXX, 'ixx="1e400"', "link 'upper_arm_link' <inertia ixx>"),
    ("izz missing", UR5_IZZ, "", "link 'upper_arm_link' <inertia izz>"),
    ("two inertials", UR5_MASS, UR5_MASS + '</inertial><inertial><mass value="1"/>',
     "link 'upper_arm_link' <inertial>"),
    ("mimic on the chain", '<child link="forearm_link"/>',
     '<child link="forearm_link"/><mimic joint="shoulder_lift_joint"/>',
     "joint 'elbow_joint' <mimic>"),
    ("revolute joint without limit", '<limit effort="150.0" lower="-3.14159265359" '
     'upper="3.14159265359" velocity="3.15"/>', "", "joint 'elbow_joint' <limit>"),
]


def chain_model(joints, gravity):
    """A Pinocchio model of the joint dicts: JointModelRZ / JointModelPZ at SE3 placements."""
    model = pin.Model()
    parent = 0
    for k, j in enumerate(joints, start=1):
        jm = pin.JointModelRZ() if j["type"] == "revolute" else pin.JointModelPZ()
        placement = pin.SE3(np.asarray(j["rotation"], float), np.asarray(j["translation"], float))
        parent = model.addJoint(parent, jm, placement, f"joint{k}")
        model.appendBodyToJoint(parent, pin.Inertia(float(j["mass"]), np.asarray(j["com"], float),
                                                    np.asarray(j["inertia"], float)),
                                pin.SE3.Identity())
    model.gravity = pin.Motion(np.asarray(gravity, float), np.zeros(3))
    return model


class UrdfOracle:
    """The URDF loaded directly with pin.buildModelFromUrdf, driven by the chain's coordinates."""

    def __init__(self, path, joint_names):
        self.model = pin.buildModelFromUrdf(str(path))
        self.data = self.model.createData()
        self.ids = [self.model.getJointId(name) for name in joint_names]
        self.v = [self.model.idx_vs[j] for j in self.ids]

    def q(self, q):
        full = pin.neutral(self.model)
        for j, qj in zip(self.ids, q):
            iq = self.model.idx_qs[j]
            if self.model.nqs[j] == 2:
                full[iq:iq + 2] = np.cos(qj), np.sin(qj)
            else:
                full[iq] = qj
        return full

    def v_full(self, v):
        full = np.zeros(self.model.nv)
        full[self.v] = v
        return full

    def crba(self, q):
        M = pin.crba(self.model, self.data, self.q(q))
        M = np.triu(M) + np.triu(M, 1).T
        return M[np.ix_(self.v, self.v)]

    def rnea(self, q, qd, qdd):
        return pin.rnea(self.model, self.data, self.q(q), self.v_full(qd), self.v_full(qdd))[self.v]

    def nle(self, q, qd):
        return pin.nonLinearEffects(self.model, self.data, self.q(q), self.v_full(qd))[self.v]

    def gravity(self, q):
        return pin.computeGeneralizedGravity(self.model, self.data, self.q(q))[self.v]


def random_chain_states(joints, count, seed):
    """q uniform in the limits (+-pi where unbounded), qd and qdd uniform in +-2."""
    rng = np.random.default_rng(seed)
    lo = np.array([max(j["q_min"], -np.pi) for j in joints])
    hi = np.array([min(j["q_max"], np.pi) for j in joints])
    n = len(joints)
    return (rng.uniform(lo, hi, (count, n)), rng.uniform(-2, 2, (count, n)),
            rng.uniform(-2, 2, (count, n)))


def worst_relative(values, refs, kind, scale=None):
    """Largest error on the natural scale: peak |ref_i| per joint, or sqrt(D_ii D_jj) per element.

    values, refs : shape (N, n) or (N, n, n). NaN or inf anywhere gives inf.
    scale : the per-joint torque scale to use instead (e.g. the peak |tau_i| of the full
    torques, for gravity, which is exactly zero on a vertical first joint).
    """
    values, refs = np.asarray(values, float), np.asarray(refs, float)
    if not (np.isfinite(values).all() and np.isfinite(refs).all()):
        return np.inf
    if scale is not None:
        scale = np.asarray(scale, float)
    elif kind == "D":
        diag = np.einsum("kii->ki", refs)
        scale = np.sqrt(np.abs(diag[:, :, None] * diag[:, None, :])).max(axis=0)
    else:
        scale = np.abs(refs).max(axis=0)
    assert (scale > 0).all(), "a zero scale: the test states do not excite every element"
    return float((np.abs(values - refs) / scale).max())


@pytest.fixture(scope="module")
def toy(tmp_path_factory):
    """TOY_URDF written to a file: a continuous, a prismatic (-z) and a revolute (y) joint on
    the chain to 'tool', and a side branch 'side'."""
    path = tmp_path_factory.mktemp("urdf") / "toy.urdf"
    path.write_text(TOY_URDF)
    return path
