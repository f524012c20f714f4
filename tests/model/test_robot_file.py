"""The robot-file writer: the built-ins read back unchanged; hostile text stays text."""

import dataclasses

import numpy as np
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import standard_parameters
from gd_analyze.model.robot_file import robot_toml


@pytest.mark.parametrize("name", ["puma560", "puma560-drives", "stanford", "panda", "ur5"])
def test_built_ins_read_back_unchanged(tmp_path, name):
    robot = load_robot(name)
    path = tmp_path / "r.toml"
    path.write_text(robot_toml(robot))
    back = load_robot(str(path))
    assert np.array_equal(standard_parameters(back), standard_parameters(robot))
    for key in ("rotation", "translation", "armature", "viscous", "coulomb", "gravity",
                "prismatic", "q_min", "q_max"):
        assert np.array_equal(getattr(back, key), getattr(robot, key)), key


def test_hostile_names_and_comments_stay_in_their_strings(tmp_path):
    robot = dataclasses.replace(load_robot("two-link"), name='x" [[link]] mass = 1 # \\',
                                description="\x1b[31m")
    text = robot_toml(robot, ["line one\nname = 'evil'"])
    path = tmp_path / "r.toml"
    path.write_text(text)
    back = load_robot(str(path))
    assert back.name == robot.name and back.description == robot.description
    assert back.n == 2
    assert text.splitlines()[0].startswith("# line one\\n")
