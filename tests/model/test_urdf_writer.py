"""The URDF writer: Pinocchio's own URDF parser gives the robot's rigid-body torque back."""

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import standard_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.urdf_writer import robot_urdf


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_pinocchio_reads_the_same_arm(tmp_path, name):
    robot = load_robot(name)
    path = tmp_path / "r.urdf"
    path.write_text(robot_urdf(robot, ["a comment -- with dashes"]))
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    ref = pinocchio_model(robot)
    ref.armature = np.zeros(robot.n)
    ref_data = ref.createData()
    for x in np.random.default_rng(0).uniform(-1.5, 1.5, (10, robot.n)):
        want = pin.rnea(ref, ref_data, x, x, x)
        got = pin.rnea(model, data, x, x, x)
        assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()
    back = load_robot(str(path))
    assert np.allclose(standard_parameters(back), standard_parameters(robot), rtol=0,
                       atol=1e-12 * np.abs(standard_parameters(robot)).max())
    assert back.joint_names() == robot.joint_names()


def test_hostile_names_are_escaped():
    import dataclasses

    robot = dataclasses.replace(load_robot("two-link"), name='a"><evil/>&')
    import xml.etree.ElementTree as ET

    root = ET.fromstring(robot_urdf(robot, ["--> <evil/>"]).split("\n", 1)[1])
    assert root.get("name") == robot.name
    assert root.find(".//evil") is None and root.tag == "robot"


@pytest.mark.parametrize("comment", ["rec---a.csv", "a -", "ctl\x01\x1b.csv", "bad\udcff.csv",
                                     "line\nbreak\rreturn"])
def test_a_comment_of_any_text_keeps_the_urdf_well_formed(tmp_path, comment):
    """A recording's file name in the comments (three dashes, a control character, a byte
    that is not UTF-8): XML 1.0 allows no ``--`` and none of those characters in a comment."""
    import xml.etree.ElementTree as ET

    robot = load_robot("two-link")
    path = tmp_path / "r.urdf"
    path.write_text(robot_urdf(robot, [comment]), encoding="utf-8")
    ET.parse(path)
    assert load_robot(str(path)).joint_names() == robot.joint_names()
