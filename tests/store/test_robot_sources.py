"""load_robot from URDF text and from a pinocchio.Model: the same dynamics as
the URDF file, checked against Pinocchio's own model of the file (crba, rnea); bad input is one
InputError, also at the command line."""

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from urdf_oracle import TOY_URDF, UrdfOracle, random_chain_states, worst_relative

from gd_analyze import gd_terms, load_robot
from gd_analyze.errors import InputError
from gd_analyze.model.urdf import builtin_urdf_path

PANDA = builtin_urdf_path("panda")


def _states(robot, seed, count=50):
    joints = [{"q_min": lo, "q_max": hi} for lo, hi in zip(robot.q_min, robot.q_max)]
    return random_chain_states(joints, count, seed)


def _check_against(robot, crba, rnea, seed):
    """G-D D and tau of the robot against an oracle's crba and rnea at random states."""
    q, qd, qdd = _states(robot, seed)
    terms = gd_terms(robot, q, qd)
    D_ref = np.array([crba(qk) for qk in q])
    tau_ref = np.array([rnea(*s) for s in zip(q, qd, qdd)])
    assert worst_relative(terms.D, D_ref, "D") < 1e-10
    assert worst_relative(terms.tau(qdd), tau_ref, "tau") < 1e-10


@pytest.mark.parametrize("which", ["panda", "toy"])
def test_urdf_text_is_the_file(which, tmp_path):
    text = PANDA.read_text() if which == "panda" else TOY_URDF
    path = PANDA if which == "panda" else tmp_path / "toy.urdf"
    if which == "toy":
        path.write_text(text)
    tip = "panda_hand" if which == "panda" else "tool"
    from_text, from_file = load_robot(text, tip=tip), load_robot(str(path), tip=tip)
    assert from_text.source == "URDF text" and from_text.name == from_file.name
    assert from_text.joint_names() == from_file.joint_names()
    oracle = UrdfOracle(path, from_text.metadata["urdf_joints"])
    _check_against(from_text, oracle.crba, oracle.rnea, seed=1)
    q, qd, _ = _states(from_text, seed=2, count=5)
    assert np.array_equal(gd_terms(from_text, q, qd).D, gd_terms(from_file, q, qd).D)


def test_urdf_text_with_declaration_and_comment_loads():
    text = '\n  <?xml version="1.0"?>\n<!-- a comment -->\n' + TOY_URDF.split("?>", 1)[1]
    assert load_robot(text, tip="tool").n == 3


def test_pinocchio_model_of_the_panda_urdf():
    model = pin.buildModelFromUrdf(str(PANDA))
    robot = load_robot(model, tip="panda_hand")
    assert robot.source == "pinocchio.Model" and robot.n == 7
    assert robot.joint_names() == [f"panda_joint{i}" for i in range(1, 8)]
    assert model.nframes == pin.buildModelFromUrdf(str(PANDA)).nframes     # not changed
    oracle = UrdfOracle(PANDA, robot.metadata["urdf_joints"])
    _check_against(robot, oracle.crba, oracle.rnea, seed=3)
    # and the same dynamics as the URDF path
    q, qd, qdd = _states(robot, seed=4, count=20)
    file_robot = load_robot(str(PANDA), tip="panda_hand")
    assert worst_relative(gd_terms(robot, q, qd).tau(qdd),
                          gd_terms(file_robot, q, qd).tau(qdd), "tau") < 1e-12


def test_pinocchio_model_without_frames_or_limits():
    """A model a notebook builds by hand: no frames, Pinocchio's default (unbounded) limits,
    a revolute joint about x and a prismatic joint along y."""
    rng = np.random.default_rng(0)
    model = pin.Model()
    model.name = "hand made"
    parent = 0
    for name, joint in (("shoulder", pin.JointModelRX()), ("slide", pin.JointModelPY()),
                        ("wrist", pin.JointModelRZ())):
        placement = pin.SE3(pin.utils.rpyToMatrix(*rng.uniform(-1, 1, 3)), rng.uniform(-.3, .3, 3))
        parent = model.addJoint(parent, joint, placement, name)
        A = rng.normal(size=(3, 3))
        model.appendBodyToJoint(parent, pin.Inertia(float(rng.uniform(0.5, 2)),
                                                    rng.uniform(-.1, .1, 3),
                                                    A @ A.T / 10 + 0.01 * np.eye(3)),
                                pin.SE3.Identity())
    robot = load_robot(model)
    assert robot.name == "hand made" and robot.joint_names() == ["shoulder", "slide", "wrist"]
    assert robot.joint_types == ("revolute", "prismatic", "revolute")
    assert np.isinf(robot.q_min).all() and np.isnan(robot.qd_max).all()
    data = model.createData()

    def crba(q):
        M = pin.crba(model, data, q)
        return np.triu(M) + np.triu(M, 1).T

    _check_against(robot, crba, lambda q, v, a: pin.rnea(model, data, q, v, a), seed=5)


@pytest.mark.parametrize("bad, match", [
    ("<robot", "not well-formed"),
    ('<robot name="x"><link name="a"/></robot>', "no moving joint"),
    ("<?xml version='1.0'?><!DOCTYPE r [<!ENTITY a 'b'>]><robot/>", "not URDF text"),
    ("<urdf/>", "not URDF text"),
    ("<robot><joint name='j' type='revolute'></robot>", "not well-formed"),
    (42, "not a int"),
    ("x" * 5000, "unknown robot"),
])
def test_bad_robot_input_is_one_input_error(bad, match):
    with pytest.raises(InputError, match=match) as err:
        load_robot(bad)
    assert len(str(err.value)) < 300 and "\n" not in str(err.value)


def test_bad_urdf_text_at_the_command_line(tmp_path, capsys):
    """In the test's process (the console script's own path is tests/test_one_code_path.py's
    and test_cli's real-process test's): a warning, which a child would print as a line of its
    own, counts as a line."""
    import warnings

    from gd_analyze.cli import main

    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        code = main(['<robot name="x"><link name="a"/>',
                     str(Path(__file__).resolve().parents[2] / "data" / "puma560_trajectory.csv"),
                     "-o", str(tmp_path / "out"), "--no-report"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and "URDF text" in err
    assert len(err.strip().splitlines() + [str(w.message) for w in seen]) == 1
