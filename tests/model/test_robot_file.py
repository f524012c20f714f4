"""The robot-file writer: the built-ins read back unchanged; hostile text stays text."""

import dataclasses
import json

import numpy as np
import pytest
from urdf_oracle import TOY_URDF

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import standard_parameters
from gd_analyze.errors import InputError
from gd_analyze.model.robot_file import robot_toml
from gd_analyze.trajectory.trajectory import read_recording


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
    assert back.joint_names() == robot.joint_names()


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


def test_a_urdf_robot_s_file_keeps_its_joint_names_for_recordings_that_name_them(tmp_path):
    """The UR5's URDF names its joints; the robot file written from it (as identify writes
    identified_robot.toml) names them too, so a recording whose columns name the joints
    ("shoulder_pan_joint_position", ...) is read with it as with the URDF. Before, the file
    named them joint1.. and refused such a recording."""
    robot = load_robot("ur5")
    path = tmp_path / "r.toml"
    path.write_text(robot_toml(robot))
    back = load_robot(str(path))
    names = robot.joint_names()
    csv = tmp_path / "rec.csv"
    cols = [f"{j}_position" for j in names] + [f"{j}_effort" for j in names]
    csv.write_text("t," + ",".join(reversed(cols)) + "\n" + "".join(
        f"{0.01 * k!r}," + ",".join(repr(0.1 * i + 0.001 * k) for i in range(12)) + "\n"
        for k in range(50)))
    by_urdf, by_file = (read_recording(csv, 6, joint_names=r.joint_names()) for r in (robot, back))
    assert np.array_equal(by_file.q, by_urdf.q) and np.array_equal(by_file.tau, by_urdf.tau)
    assert np.array_equal(by_file.q[:, 0], 0.1 * 11 + 0.001 * np.arange(50))   # reversed order


@pytest.mark.parametrize("change, column, message", [
    ({2: None}, "link[2].joint_name", "give it on every link or none"),
    ({2: "a"}, "link[2].joint_name", "is that of link[1]"),
    ({1: "a" * 201}, "link[1].joint_name", "expected at most 200 characters"),
    ({1: "a\x00b"}, "link[1].joint_name", "no NUL"),
    ({1: 3}, "link[1].joint_name", "expected a non-empty string"),
])
def test_joint_names_in_a_robot_file_are_checked(tmp_path, change, column, message):
    """joint_name on every link or none, at most 200 characters without NUL, no two alike;
    hostile text read back as the same string."""
    names = {1: "a", 2: "b"} | change
    text = robot_toml(load_robot("two-link"))
    plain, parts = text.split("[[link]]"), text.split("[[link]]")
    for i, name in names.items():
        if name is not None:
            parts[i] = "\njoint_name = " + (repr(name) if isinstance(name, int) else
                                             '"' + name.replace("\x00", "\\u0000") + '"') + parts[i]
    path = tmp_path / "r.toml"
    path.write_text("[[link]]".join(parts))
    with pytest.raises(InputError) as err:
        load_robot(str(path))
    assert err.value.column == column and message in str(err.value)
    evil = 'x" [[link]] mass = 1 # \\'
    path.write_text("[[link]]".join([plain[0]] + [f"\njoint_name = {json.dumps(evil + str(i))}"
                                                  + p for i, p in enumerate(plain[1:])]))
    assert load_robot(str(path)).joint_names() == [evil + "0", evil + "1"]


def test_a_urdf_s_joint_names_read_back_from_its_robot_file_or_are_refused_by_both(tmp_path):
    """A URDF may name a joint with a tab, a newline or a carriage return (XML writes them as
    character references); identify writes such a robot's identified_robot.toml with
    robot_toml. The robot file reads those names back as they were. A name of over 200
    characters is refused on reading the URDF, as the robot file refuses it, in one line that
    names the joint; before, the URDF was read and the file it wrote was refused."""
    names = ["j1\tα", "j2\nnext line", "j3\r" + "x" * 197]
    text = TOY_URDF
    for k, name in enumerate(names, start=1):
        attr = "".join(c if c.isprintable() else f"&#{ord(c)};" for c in name)
        text = text.replace(f'name="j{k}"', f'name="{attr}"')
    robot = load_robot(text, tip="tool")
    assert robot.joint_names() == names and len(names[2]) == 200
    path = tmp_path / "r.toml"
    path.write_text(robot_toml(robot))
    back = load_robot(str(path))
    assert back.joint_names() == names
    assert np.array_equal(standard_parameters(back), standard_parameters(robot))
    long = "j" * 201
    with pytest.raises(InputError) as err:
        load_robot(text.replace('name="j1&#9;α"', f'name="{long}"'), tip="tool")
    assert err.value.column == f"joint[1].name (joint {long!r})"
    assert "expected at most 200 characters" in str(err.value) and "\n" not in str(err.value)
