"""A one-joint arm with limits, from a robot file and from a URDF: the main job with a region
guarantee, evaluate and plan, each against Pinocchio."""

import json

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze.cli import main

ONE_TOML = """name = "one"
gravity = [0.0, -9.81, 0.0]
[[link]]
d = 0.0
a = 0.5
alpha_deg = 0.0
mass = 2.0
com = [-0.25, 0.0, 0.0]
inertia = [0.01, 0.05, 0.05]
q_limits_deg = [-160.0, 160.0]
qd_max_deg = 100.0
qdd_max_deg = 200.0
"""

ONE_URDF = """<?xml version="1.0"?>
<robot name="one">
  <link name="base"/>
  <link name="arm">
    <inertial><origin xyz="0.25 0 0"/><mass value="2.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.05"/></inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" velocity="2.0" effort="50"/>
  </joint>
</robot>
"""


def _urdf_oracle(path):
    return pin.buildModelFromUrdf(str(path))


def _toml_oracle():
    """The robot file's pendulum built in Pinocchio by hand: a revolute joint about z, the
    link's centre of mass at x = 0.5 - 0.25 m, gravity along -y."""
    model = pin.Model()
    joint = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "j1")
    inertia = pin.Inertia(2.0, np.array([0.25, 0.0, 0.0]), np.diag([0.01, 0.05, 0.05]))
    model.appendBodyToJoint(joint, inertia, pin.SE3.Identity())
    model.gravity.linear = np.array([0.0, -9.81, 0.0])
    return model


def _region_max(model, q_min, q_max, qdd_max):
    """max |tau| over a fine grid of the position range at qd = 0 and qdd = +-qdd_max (one
    joint: h = 0, so the velocity does not enter) [N m]."""
    data = model.createData()
    best = 0.0
    for q in np.linspace(q_min, q_max, 20001):
        for a in (-qdd_max, qdd_max):
            best = max(best, abs(pin.rnea(model, data, np.array([q]), np.zeros(1),
                                          np.array([a]))[0]))
    return best


@pytest.mark.slow
@pytest.mark.parametrize("kind", ("toml", "urdf"))
def test_one_joint_main_job_evaluate_and_plan(kind, tmp_path, capsys):
    robot = tmp_path / f"one.{kind}"
    robot.write_text(ONE_TOML if kind == "toml" else ONE_URDF)
    traj = tmp_path / "one.csv"
    assert main(["plan", str(robot), "-o", str(traj)]) == 0
    rows = np.loadtxt(traj, delimiter=",", skiprows=1)
    assert rows.shape == (31, 4)
    out = tmp_path / "out"
    code = main([str(robot), str(traj), "-o", str(out), "--no-report", "-q"])
    assert code == 0, capsys.readouterr().err
    model_json = json.loads((out / "simplified_model.json").read_text())
    guarantee = model_json["guarantee"]
    assert guarantee["kind"] == "region" and "proved" in guarantee["statement"]
    oracle = _urdf_oracle(robot) if kind == "urdf" else _toml_oracle()
    # s_1 is the largest |tau_1| found over the region: a lower bound by search, reached at
    # its scale_state (Pinocchio's torque there)
    q, qd, qdd = guarantee["scale_state"][0]
    at_state = abs(pin.rnea(oracle, oracle.createData(), np.array([q]), np.array([qd]),
                            np.array([qdd]))[0])
    assert at_state == pytest.approx(guarantee["scale"][0], rel=1e-9)
    grid = _region_max(oracle, guarantee["q_min"][0], guarantee["q_max"][0],
                       guarantee["qdd_max"][0])
    assert guarantee["scale"][0] == pytest.approx(grid, rel=1e-6)
    # the model is exact on one joint: evaluate passes its gate
    assert main(["evaluate", str(out / "simplified_model.json"), str(traj)]) == 0
    printed = capsys.readouterr().out
    assert "covers this trajectory: yes" in printed
