"""URDF import against the URDF's own Pinocchio model (pin.buildModelFromUrdf), not the chain."""

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from urdf_oracle import (
    STATES,
    TOL,
    TOY_URDF,
    UR5,
    UrdfOracle,
    chain_model,
    random_chain_states,  # noqa: F401 (a fixture)
    toy,  # noqa: F401 (a fixture)
    worst_relative,
)

from gd_analyze.errors import InputError
from gd_analyze.model.urdf import (
    RIGHT_ANGLE_TOL,
    URDF_BUILTIN,
    axis_rotation,
    builtin_urdf_path,
    read_urdf_chain,
    right_angle_rotation,
)


def _check_against_urdf(path, chain, seed):
    model = chain_model(chain.joints, chain.gravity)
    data = model.createData()
    oracle = UrdfOracle(path, chain.joint_names)
    q, qd, qdd = random_chain_states(chain.joints, STATES, seed)
    D, Dr, tau, taur, c, cr = [], [], [], [], [], []
    for k in range(STATES):
        M = pin.crba(model, data, q[k])
        D.append(np.triu(M) + np.triu(M, 1).T)
        Dr.append(oracle.crba(q[k]))
        tau.append(pin.rnea(model, data, q[k], qd[k], qdd[k]))
        taur.append(oracle.rnea(q[k], qd[k], qdd[k]))
        c.append(pin.computeGeneralizedGravity(model, data, q[k]))
        cr.append(oracle.gravity(q[k]))
    assert worst_relative(D, Dr, "D") < TOL
    assert worst_relative(tau, taur, "tau") < TOL
    # gravity on the peak |tau_i| of the full torques: c_1 is exactly 0 about a vertical axis
    tau_scale = np.maximum(np.abs(taur).max(axis=0), np.abs(cr).max(axis=0))
    assert worst_relative(c, cr, "tau", scale=tau_scale) < TOL


@pytest.mark.parametrize("name", sorted(URDF_BUILTIN))
def test_builtin_chain_matches_urdf_model(name):
    spec = URDF_BUILTIN[name]
    path = builtin_urdf_path(name)
    chain = read_urdf_chain(path, spec["base"], spec["tip"])
    assert chain.n == {"panda": 7, "ur5": 6}[name]
    assert all(j["type"] == "revolute" for j in chain.joints)
    _check_against_urdf(path, chain, seed=11)


def test_panda_fingers_and_hand_merged_into_link7():
    chain = read_urdf_chain(builtin_urdf_path("panda"), "panda_link0", "panda_hand")
    assert chain.locked == ("panda_finger_joint1", "panda_finger_joint2")
    # link 7 + hand 0.73 kg + two fingers of 0.015 kg (panda_link8 is massless)
    model = pin.buildModelFromUrdf(str(builtin_urdf_path("panda")))
    m7 = model.inertias[model.getJointId("panda_joint7")].mass
    assert chain.joints[6]["mass"] == pytest.approx(m7 + 0.03, rel=1e-12)
    assert np.abs(chain.joints[6]["inertia"] - np.diag(np.diag(chain.joints[6]["inertia"]))
                  ).max() > 1e-4      # full tensors, not diagonal


def test_panda_needs_a_tip_and_names_the_candidates():
    with pytest.raises(InputError, match="panda_leftfinger, panda_rightfinger"):
        read_urdf_chain(builtin_urdf_path("panda"))


def test_ur5_default_chain_and_axes_turned_onto_z():
    chain = read_urdf_chain(builtin_urdf_path("ur5"))
    assert chain.tip == "wrist_3_link" and chain.n == 6 and chain.locked == ()
    # joints 2, 3, 4 and 6 turn about URDF y: their com stays on the link's axis
    # (URDF y becomes local z, URDF z becomes local -y)
    assert chain.base == "world"
    assert chain.joints[1]["com"] == pytest.approx([0.0, -0.28, 0.0], abs=1e-12)
    assert chain.joints[2]["com"] == pytest.approx([0.0, -0.25, 0.0], abs=1e-12)
    assert chain.gravity == pytest.approx([0.0, 0.0, -9.81])


def test_toy_chain_continuous_prismatic_unaligned_axes_side_branch(toy):
    chain = read_urdf_chain(toy, tip="tool")
    assert [j["type"] for j in chain.joints] == ["revolute", "prismatic", "revolute"]
    assert chain.joint_names == ("j1", "j2", "j3") and chain.locked == ("jb",)
    assert chain.joints[0]["q_min"] == -math.inf and chain.joints[0]["q_max"] == math.inf
    assert (chain.joints[1]["q_min"], chain.joints[1]["q_max"]) == (-0.1, 0.3)
    assert chain.joints[1]["qd_max"] == 0.5 and chain.joints[0]["qd_max"] == 2.0
    assert all(j["qdd_max"] is None for j in chain.joints)
    assert chain.joints[2]["mass"] == pytest.approx(0.8)       # l3 with the fixed tool
    _check_against_urdf(toy, chain, seed=3)


def test_toy_base_below_a_moving_joint(toy):
    """A base link below j1: j1 is held at q = 0, gravity is turned into l1's frame."""
    chain = read_urdf_chain(toy, base="l1", tip="l3")
    assert chain.joint_names == ("j2", "j3") and chain.locked == ("jb",)
    _check_against_urdf(toy, chain, seed=5)


def test_toy_several_chains(toy):
    with pytest.raises(InputError, match=r"2 chains below .world.: give --tip LINK \(candidate tips: l3, side\)"):
        read_urdf_chain(toy)


@pytest.mark.parametrize("kwargs, match", [
    ({"tip": "nope"}, "no link 'nope'"),
    ({"base": "nope", "tip": "l3"}, "no link 'nope'"),
    ({"base": "l3", "tip": "l1"}, "no moving joint between"),
    ({"base": "l3", "tip": "tool"}, "no moving joint between"),
])
def test_bad_links(toy, kwargs, match):
    with pytest.raises(InputError, match=match):
        read_urdf_chain(toy, **kwargs)


def test_not_a_urdf(tmp_path):
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'>")
    with pytest.raises(InputError, match="not a valid URDF"):
        read_urdf_chain(bad)
    with pytest.raises(InputError, match="no such file"):
        read_urdf_chain(tmp_path / "missing.urdf")


@pytest.mark.parametrize("old, new, reason", [
    ('<child link="forearm_link"/>', '<child link="fore_arm_link"/>',
     "Failed to build tree: child link [fore_arm_link] of joint [elbow_joint] not found"),
    ('name="shoulder_pan_joint" type="revolute"', 'name="shoulder_pan_joint" type="hinge"',
     "Joint [shoulder_pan_joint] has no known type [hinge]"),
    ('lower="-3.14159265359"', 'lower="-180deg"',
     "joint [elbow_joint]: lower value (-180deg) is not a valid float"),
    ('<robot name="ur5" ', "<robot ", "No name given for the robot."),
])
def test_a_urdf_urdfdom_refuses_is_one_line_with_its_reason(tmp_path, capfd, old, new, reason):
    """urdfdom printed its reason (and the C source line) on the C stderr, and the error said
    only 'The XML stream does not contain a valid URDF model.': now its reason is the error's,
    and nothing else is printed. Oracle: urdfdom's own words for the file."""
    assert UR5.count(old) == 1
    path = tmp_path / "bad.urdf"
    path.write_text(UR5.replace(old, new))
    with pytest.raises(InputError) as err:
        read_urdf_chain(path)
    assert str(err.value) == f"{path}: not a valid URDF file: {reason}"
    assert capfd.readouterr().err == ""


@pytest.mark.parametrize("axis", ["0 0 0", "0.0 -0 0e5"])
def test_an_axis_of_zero_length_is_named(tmp_path, axis):
    """urdfdom keeps an axis of zero length (and normalises any other): the error said the
    joint was "neither a pure rotation nor a pure translation", not what is wrong."""
    first = UR5.index('<axis xyz="0 0 1"/>')        # the shoulder_pan_joint's, the first joint
    assert UR5.rindex('<joint name=', 0, first) == UR5.index('<joint name="shoulder_pan_joint"')
    path = tmp_path / "axis.urdf"
    path.write_text(UR5.replace('<axis xyz="0 0 1"/>', f'<axis xyz="{axis}"/>', 1))
    with pytest.raises(InputError) as err:
        read_urdf_chain(path)
    assert str(err.value) == (f"{path}: joint 'shoulder_pan_joint' <axis xyz>: an axis of zero "
                              "length")


def test_floating_joint_refused(tmp_path):
    path = tmp_path / "float.urdf"
    path.write_text(TOY_URDF.replace('name="j1" type="continuous"', 'name="j1" type="floating"'))
    with pytest.raises(InputError, match="'j1'.*not a revolute, continuous or prismatic"):
        read_urdf_chain(path, tip="tool")


@pytest.mark.parametrize("axis", [(0, 0, 1), (0, 0, -1), (1, 0, 0), (0, -1, 0), (0.6, 0, 0.8),
                                  (1, 1, 1), (-1e-3, 2e-3, -1)])
def test_axis_rotation(axis):
    A = axis_rotation(axis)
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    assert A @ [0, 0, 1] == pytest.approx(a, abs=1e-15)
    assert A.T @ A == pytest.approx(np.eye(3), abs=1e-15)
    assert np.linalg.det(A) == pytest.approx(1.0, abs=1e-15)


def _rpy(r, p, y):
    """Rz(y) Ry(p) Rx(r), URDF's convention, by Pinocchio (an independent construction)."""
    return np.array(pin.rpy.rpyToMatrix(r, p, y))


@pytest.mark.parametrize("rpy", [(0, 3.14159265359, 0), (-1.57079632679, 0, 3.14159265359),
                                 (0, -1.5707963268, 0), (0, 0, -3.1415926536)])
def test_a_turn_by_pi_written_with_few_digits_is_taken_as_exact(rpy):
    # the same turn with pi and pi/2 to full precision is the oracle: a signed permutation
    exact = _rpy(*[round(2 * v / math.pi) * math.pi / 2 for v in rpy])
    written = _rpy(*rpy)
    assert 1e-14 < np.abs(written - np.round(written)).max() <= RIGHT_ANGLE_TOL   # the file's
    got = right_angle_rotation(written)
    assert np.array_equal(got, np.round(exact)) and not np.signbit(got[got == 0]).any()


@pytest.mark.parametrize("rpy", [(0.3, 0, 0), (0, 3.14159, 0), (0.1, 0.2, 0.3),
                                 (0, 0, 1.570796325)])
def test_a_turn_off_a_right_angle_is_kept(rpy):
    # 3.14159 is 2.7e-6 off pi and 1.570796325 is 1.8e-9 off pi/2: kept as written, so that
    # the arm stays within 1e-10 of the file's
    R = _rpy(*rpy)
    assert np.array_equal(right_angle_rotation(R), R)


def test_the_urdfs_placements_are_exact_right_angle_turns_where_written_so(tmp_path):
    # the UR5's file writes pi/2 as 1.57079632679: every placement of its chain is a signed
    # permutation or a turn about z by a non-right angle, with exact 0 and +-1 entries; the
    # chain still matches Pinocchio's own model of the file (the file's decimals are 1e-12)
    chain = read_urdf_chain(builtin_urdf_path("ur5"))
    for joint in chain.joints:
        R = joint["rotation"]
        near = np.abs(R - np.round(R)) <= RIGHT_ANGLE_TOL
        assert not near.all() or np.array_equal(R, np.round(R))
    _check_against_urdf(builtin_urdf_path("ur5"), chain, seed=12)


def test_missing_velocity_limit_is_not_given(tmp_path):
    """A joint without <limit velocity> is read (only planning needs the limit): NaN."""
    path = tmp_path / "nolimit.urdf"
    path.write_text(TOY_URDF.replace('<limit velocity="2.0" effort="5"/>', ""))
    chain = read_urdf_chain(path, tip="tool")
    assert math.isnan(chain.joints[0]["qd_max"]) and math.isnan(chain.joints[0]["tau_max"])


@pytest.mark.parametrize("joint, link", [("fix0", "base"), ("j2", "l2"), ("jb", "side"), ("jb", "l2")])
def test_a_joint_named_as_a_link_is_read(tmp_path, toy, joint, link):
    """A URDF may give a joint a link's name (example-robot-data's b1-z1: the fixed joint
    "gripperStator" into the link "gripperStator"; its anymal_c names every joint as its child
    link, so a leg's chain locks joints so named); Pinocchio's buildReducedModel, which locks
    the side branch, looked the frames up by name and refused one that two frames hold, or
    that the locked joint's frame takes (an internal error, exit 4). A joint's name changes no
    dynamics: the chain is the toy's, and it matches the URDF's own Pinocchio model."""
    text = TOY_URDF.replace(f'<joint name="{joint}"', f'<joint name="{link}"')
    assert text != TOY_URDF
    same = tmp_path / "same_name.urdf"
    same.write_text(text)
    chain = read_urdf_chain(same, tip="tool")
    assert chain.locked == ((link,) if joint == "jb" else ("jb",))
    ref = read_urdf_chain(toy, tip="tool")
    for a, b in zip(chain.joints, ref.joints):
        for key in ("rotation", "translation", "mass", "com", "inertia"):
            np.testing.assert_array_equal(a[key], b[key])
    _check_against_urdf(same, chain, seed=5)


def test_example_robot_datas_b1_z1_arm_whose_joint_has_its_links_name():
    """The Z1 arm on the B1 quadruped (example-robot-data's b1-z1.urdf): its fixed joint
    "gripperStator" leads into the link "gripperStator", and the legs are locked; read up to
    the gripper, the chain matches the URDF's own Pinocchio model."""
    from robot_files import erd_path

    path = erd_path("b1_description/urdf/b1-z1.urdf")
    chain = read_urdf_chain(path, tip="gripperMover")
    assert chain.n == 7 and '<joint name="gripperStator"' in Path(path).read_text()
    _check_against_urdf(path, chain, seed=7)


@pytest.mark.parametrize("lower, upper, expected", [
    ("-1e+16", "1e+16", (-math.inf, math.inf)),     # SDF's default, in Gazebo's URDF export
    ("-1e4", "1e4", (-1e4, 1e4)),                    # the largest travel taken as a limit
])
def test_a_position_limit_beyond_any_travel_is_no_limit(tmp_path, lower, upper, expected):
    """A URDF exported from Gazebo writes a joint without limits as lower -1e16, upper 1e16;
    it was refused ("-1e+16 is beyond the supported magnitude 10000"). Now it is read as no
    limit, as Pinocchio's largest float is; a limit within 1e4 rad is kept."""
    old = '<limit lower="-2" upper="2" velocity="1.5" effort="10"/>'
    assert TOY_URDF.count(old) == 1
    path = tmp_path / "sdf.urdf"
    path.write_text(TOY_URDF.replace(old, f'<limit lower="{lower}" upper="{upper}" '
                                          'velocity="1.5" effort="10"/>'))
    chain = read_urdf_chain(path, tip="tool")
    assert (chain.joints[2]["q_min"], chain.joints[2]["q_max"]) == expected
    _check_against_urdf(path, chain, seed=7)
