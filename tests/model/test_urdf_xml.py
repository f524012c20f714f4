"""Broken URDF inertials and <mimic> joints are refused, naming the link or joint and the
attribute; urdfdom would drop such an <inertial> and Pinocchio would agree
with the massless link. The good files still load, and the inertias read from the XML are the
ones Pinocchio loaded."""

import glob
import importlib.metadata
import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest
from urdf_oracle import (
    BAD_UR5,
    PANDA,
    STATES,
    TOL,
    UR5,
    UrdfOracle,
    chain_model,
    random_chain_states,
    worst_relative,
)

from gd_analyze.errors import InputError
from gd_analyze.model import urdf as urdf_mod
from gd_analyze.model.limits import LIMITS
from gd_analyze.model.urdf import builtin_urdf_path, read_urdf_chain
from gd_analyze.model.urdf_xml import check_inertias, read_urdf_xml


def _write(tmp_path, text, old, new, name="bad.urdf"):
    assert text.count(old) >= 1, old
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize("case, old, new, column", BAD_UR5, ids=[c[0] for c in BAD_UR5])
def test_broken_ur5_refused_naming_link_and_attribute(tmp_path, case, old, new, column):
    path = _write(tmp_path, UR5, old, new)
    with pytest.raises(InputError) as err:
        read_urdf_chain(path)
    assert err.value.column == column
    assert str(err.value).startswith(f"{path}: {column}: ")        # an attribute, not a "key"


def test_missing_inertia_element_refused(tmp_path):
    text = UR5.replace('<inertia ixx="0.22689067591" ixy="0.0" ixz="0.0" iyy="0.22689067591" '
                       'iyz="0.0" izz="0.0151074"/>', "", 1)
    assert text != UR5
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    with pytest.raises(InputError, match="no <inertia> element") as err:
        read_urdf_chain(path)
    assert err.value.column == "link 'upper_arm_link' <inertia>"


@pytest.mark.parametrize("old, new, column", [
    # the hand is merged into link 7 through fixed joints: its inertial counts too
    ('<mass value="0.73"/>', '<mass value="0,73"/>', "link 'panda_hand' <mass value>"),
    # the fingers are locked: a mimic that follows a chain joint would move with the chain
    ('<mimic joint="panda_finger_joint1"/>', '<mimic joint="panda_joint7"/>',
     "joint 'panda_finger_joint2' <mimic>"),
])
def test_broken_panda_refused(tmp_path, old, new, column):
    path = _write(tmp_path, PANDA, old, new)
    with pytest.raises(InputError) as err:
        read_urdf_chain(path, "panda_link0", "panda_hand")
    assert err.value.column == column


def test_a_locked_mimic_joint_is_locked_at_its_offset(tmp_path):
    """A finger that mimics the other with an offset (example-robot-data's alex_psyonic hands
    have one of 0.72) is locked where its <mimic> puts it: offset + multiplier x the other
    finger, locked at 0. Before, every chain of such a file was refused. Oracle: Pinocchio's
    rnea on the whole URDF, the fingers at (0, 0.03) m and at rest, against the chain's."""
    from gd_analyze import load_robot
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    path = _write(tmp_path, PANDA, '<mimic joint="panda_finger_joint1"/>',
                  '<mimic joint="panda_finger_joint1" multiplier="-2" offset="0.03"/>')
    robot = load_robot(str(path), base="panda_link0", tip="panda_hand")
    assert "(panda_finger_joint2 at 0.03, its <mimic> offset)" in robot.description
    full = pin.buildModelFromUrdf(str(path))
    chain = pinocchio_model(robot)
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(20):
        q, qd, qdd = (rng.uniform(-1.5, 1.5, 7) for _ in range(3))
        tau = pin.rnea(full, full.createData(), np.r_[q, 0.0, 0.03], np.r_[qd, 0, 0],
                       np.r_[qdd, 0, 0])[:7]
        at_zero = pin.rnea(full, full.createData(), np.r_[q, 0.0, 0.0], np.r_[qd, 0, 0],
                           np.r_[qdd, 0, 0])[:7]
        assert np.abs(at_zero - tau).max() > 1e-6 * np.abs(tau).max()   # the offset matters
        worst = max(worst, np.abs(pin.rnea(chain, chain.createData(), q, qd, qdd) - tau).max()
                    / np.abs(tau).max())
    assert worst <= 1e-12


def test_a_link_with_two_parent_joints_is_refused_naming_the_second():
    """urdfdom keeps one of a link's two parent joints: Pinocchio then loaded another body
    than the file gives, and the error blamed the parser's reading of a link's <inertial>.
    Oracle: the joint added to the file."""
    text = UR5.replace("</robot>", '<joint name="again" type="fixed"><parent link="base_link"/>'
                       '<child link="forearm_link"/></joint></robot>')
    with pytest.raises(InputError, match="link 'forearm_link' is the child of two joints") as err:
        read_urdf_xml(text.encode(), "two.urdf")
    assert err.value.column == "joint 'again'"


def test_doctype_refused_before_any_entity_is_expanded(tmp_path):
    """Billion laughs: urdfdom ignores the declaration, ElementTree would expand it."""
    lol = ['<!ENTITY lol0 "lol">'] + [
        f'<!ENTITY lol{k} "{f"&lol{k - 1};" * 10}">' for k in range(1, 10)]
    text = UR5.replace("<robot ", f"<!DOCTYPE robot [{''.join(lol)}]>\n<robot ", 1)
    path = tmp_path / "lol.urdf"
    path.write_text(text.replace('name="ur5"', 'name="&lol9;"', 1))
    with pytest.raises(InputError, match="document type declaration"):
        read_urdf_chain(path)
    path.write_text(text)    # declared, not used
    with pytest.raises(InputError, match="document type declaration"):
        read_urdf_chain(path)


def test_massless_link_without_inertial_accepted(tmp_path):
    """A link without <inertial> is massless in URDF (a frame link): still read."""
    start = UR5.index("<inertial>", UR5.index('<link name="upper_arm_link">'))
    end = UR5.index("</inertial>", start) + len("</inertial>")
    path = tmp_path / "massless.urdf"
    path.write_text(UR5[:start] + UR5[end:])
    chain = read_urdf_chain(path)
    assert chain.joints[1]["mass"] == 0.0 and not chain.joints[1]["inertia"].any()


def test_inertia_pinocchio_did_not_load_is_refused(monkeypatch):
    """The safety net: if Pinocchio's parser read an <inertial> differently from the file,
    the link is named (here a model whose link 3 lost its inertia tensor)."""
    real = pin.buildModelFromXML

    def dropped(text, *args):
        model = real(text, *args)
        j = model.getJointId("elbow_joint")
        model.inertias[j] = pin.Inertia(model.inertias[j].mass, model.inertias[j].lever,
                                        np.zeros((3, 3)))
        return model

    monkeypatch.setattr(urdf_mod._pin(), "buildModelFromXML", dropped)
    with pytest.raises(InputError, match="Pinocchio loaded mass") as err:
        read_urdf_chain(builtin_urdf_path("ur5"))
    assert err.value.column == "link 'forearm_link' <inertial>"


def _erd_robots():
    """The robots folder of example-robot-data (a wheel with data, no Python module)."""
    root = importlib.metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots")
    assert root.is_dir(), f"example-robot-data has no {root}"
    return root


ERD_ARMS = [
    ("ur_description/urdf/ur5_robot.urdf", None, None, 6),
    ("ur_description/urdf/ur5_gripper.urdf", None, None, 6),
    ("panda_description/urdf/panda.urdf", None, "panda_hand", 7),
    ("kinova_description/robots/kinova.urdf", None, None, 6),
    ("z1_description/urdf/z1.urdf", None, None, 7),
    # indefinite inertia tensors on the antennas (merged into the base) and a locked hand
    ("tiago_description/robots/tiago.urdf", "torso_lift_link", "arm_7_link", 7),
]


@pytest.mark.parametrize("file, base, tip, n", ERD_ARMS, ids=[a[0].split("/")[-1] for a in ERD_ARMS])
def test_example_robot_data_arms_still_load(file, base, tip, n):
    path = _erd_robots() / file
    chain = read_urdf_chain(path, base, tip)
    assert chain.n == n
    model = chain_model(chain.joints, chain.gravity)
    data = model.createData()
    oracle = UrdfOracle(path, chain.joint_names)
    q, qd, qdd = random_chain_states(chain.joints, STATES // 4, seed=7)
    tau = [pin.rnea(model, data, q[k], qd[k], qdd[k]) for k in range(len(q))]
    taur = [oracle.rnea(q[k], qd[k], qdd[k]) for k in range(len(q))]
    assert worst_relative(tau, taur, "tau") < TOL


def test_every_example_robot_data_urdf_matches_pinocchio():
    """Every URDF of example-robot-data that Pinocchio can read passes the XML checks and
    gives, joint by joint, the spatial inertia Pinocchio loaded (talos and tiago_pro have
    mimic grippers, tiago indefinite antenna tensors)."""
    files = sorted(glob.glob(str(_erd_robots() / "**" / "*.urdf"), recursive=True))
    assert len(files) > 50
    checked = 0
    for file in files:
        raw = open(file, "rb").read()
        doc = read_urdf_xml(raw, file)
        try:
            model = pin.buildModelFromXML(raw.decode("utf-8"))
        except ValueError:      # ur3.urdf: not a URDF Pinocchio reads
            continue
        check_inertias(doc, model, file)
        checked += 1
    assert checked >= len(files) - 1


def _long_chain(count, fan=False):
    """A one-joint arm and ``count`` fixed links after its tip: in a chain (depth count + 1),
    or all on the tip (fan: depth 2)."""
    parts = ['<?xml version="1.0"?><robot name="long"><link name="base"/>'
             '<link name="arm"><inertial><origin xyz="0.25 0 0"/><mass value="2.0"/>'
             '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.05"/></inertial>'
             '</link><joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>'
             '<axis xyz="0 1 0"/><limit lower="-2.5" upper="2.5" velocity="2.0" effort="50"/>'
             '</joint>']
    parent = "arm"
    for i in range(count):
        parts.append(f'<link name="f{i}"/><joint name="fj{i}" type="fixed"><parent '
                     f'link="{parent}"/><child link="f{i}"/><origin xyz="0.001 0 0"/></joint>')
        parent = "arm" if fan else f"f{i}"
    return "".join(parts) + "</robot>"


def test_urdf_size_limits_refused_before_pinocchio(tmp_path):
    """4,000 fixed links after the tip crashed Pinocchio's parser (SIGSEGV, C stack overflow):
    the depth, link and joint counts are refused first, on one line, exit 2; the run is a
    child process so that a crash fails this test instead of ending the session."""
    deep = tmp_path / "deep.urdf"
    deep.write_text(_long_chain(4000))
    with pytest.raises(InputError, match="too deep: a chain of 4,001 joints"):
        read_urdf_xml(deep.read_bytes(), str(deep))
    wide = _long_chain(LIMITS["urdf_links"], fan=True)      # depth 2, one link too many
    with pytest.raises(InputError, match=f"too large: {LIMITS['urdf_links'] + 2:,} <link>"):
        read_urdf_xml(wide.encode(), "wide.urdf")
    joints = _long_chain(LIMITS["urdf_links"] - 2, fan=True).replace(
        "</robot>", '<joint name="extra" type="fixed"><parent link="arm"/><child link="f0"/>'
        '</joint><joint name="extra2" type="fixed"><parent link="arm"/><child link="f1"/>'
        '</joint></robot>')
    with pytest.raises(InputError, match="too large: 10,001 <joint>"):
        read_urdf_xml(joints.encode(), "joints.urdf")
    loop = _long_chain(2).replace("</robot>", '<joint name="back" type="fixed"><parent '
                                  'link="f1"/><child link="base"/></joint></robot>')
    with pytest.raises(InputError, match="loop"):
        read_urdf_xml(loop.encode(), "loop.urdf")
    # within the limits, Pinocchio's parser reads the file: the deepest accepted chain loads
    ok = _long_chain(LIMITS["urdf_depth"] - 1)
    assert pin.buildModelFromXML(ok).nq == 1
    read_urdf_xml(ok.encode(), "ok.urdf")
    done = subprocess.run([sys.executable, "-c", "import sys; from gd_analyze.cli import main; "
                           "sys.exit(main(sys.argv[1:]))", "plan", str(deep), "-o",
                           str(tmp_path / "t.csv")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "too deep" in done.stderr
