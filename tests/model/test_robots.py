"""Loading robots by name, TOML or URDF; the G-D terms of URDF robots against the URDF's own
Pinocchio model (pin.buildModelFromUrdf), not against the converted chain."""

import numpy as np
import pinocchio as pin
import pytest
from urdf_oracle import STATES, TOL, UrdfOracle, random_chain_states, toy, worst_relative  # noqa: F401  (toy, random_chain_states: fixtures)

from gd_analyze import gd_terms
from gd_analyze.errors import InputError, InputNote
from gd_analyze.model.robots import builtin_robots, is_urdf, load_robot
from gd_analyze.model.urdf import URDF_BUILTIN, builtin_urdf_path


def test_builtins_and_dispatch():
    names = builtin_robots()
    assert {"puma560", "two-link", "panda", "ur5"} <= set(names)
    assert is_urdf("panda") and is_urdf("x/arm.URDF") and not is_urdf("puma560")
    assert load_robot("puma560").n == 6
    with pytest.raises(InputError, match="--base and --tip apply to a URDF robot only"):
        load_robot("puma560", tip="link3")


def test_builtin_urdf_robots():
    panda, ur5 = load_robot("panda"), load_robot("ur5")
    assert (panda.n, ur5.n) == (7, 6)
    assert panda.metadata["tip_link"] == "panda_hand"
    assert panda.metadata["locked_joints"] == ["panda_finger_joint1", "panda_finger_joint2"]
    assert "Simplified inertials" in ur5.description
    assert np.isnan(panda.qdd_max).all() and np.isfinite(panda.qd_max).all()
    assert panda.source == "panda" and len(panda.sha256) == 64


def _half(model, part):
    """The URDF model with every body's rotational inertia (tran) or mass (rot) set to zero."""
    model = model.copy()
    for j in range(1, model.njoints):
        I = model.inertias[j]
        model.inertias[j] = (pin.Inertia(I.mass, I.lever, np.zeros((3, 3))) if part == "tran"
                             else pin.Inertia(0.0, I.lever, I.inertia))
    return model


def _terms_vs_urdf(robot, path, halves, seed):
    oracle = UrdfOracle(path, robot.metadata["urdf_joints"])
    joints = [{"q_min": lo, "q_max": hi} for lo, hi in zip(robot.q_min, robot.q_max)]
    q, qd, qdd = random_chain_states(joints, STATES, seed)
    terms = gd_terms(robot, q, qd)
    tau_ref = np.array([oracle.rnea(*s) for s in zip(q, qd, qdd)])
    D_ref = np.array([oracle.crba(qk) for qk in q])
    c_ref = np.array([oracle.gravity(qk) for qk in q])
    h_ref = np.array([oracle.nle(qk, qdk) for qk, qdk in zip(q, qd)]) - c_ref
    scale = np.maximum(np.abs(tau_ref).max(axis=0), np.abs(c_ref).max(axis=0))
    assert worst_relative(terms.D, D_ref, "D") < TOL
    assert worst_relative(terms.h, h_ref, "tau", scale=scale) < TOL
    assert worst_relative(terms.c, c_ref, "tau", scale=scale) < TOL
    assert worst_relative(terms.tau(qdd), tau_ref, "tau", scale=scale) < TOL
    if halves:   # the split: half-models of the URDF's own model (one body per chain joint)
        full = oracle.model
        for part, D_part, h_part in (("tran", terms.D_tran, terms.h_tran),
                                     ("rot", terms.D_rot, terms.h_rot)):
            oracle.model = _half(full, part)
            oracle.model.gravity = pin.Motion.Zero()
            oracle.data = oracle.model.createData()
            Dh = np.array([oracle.crba(qk) for qk in q])
            hh = np.array([oracle.nle(qk, qdk) for qk, qdk in zip(q, qd)])
            assert worst_relative(D_part, Dh, "D", scale=_d_scale(D_ref)) < TOL
            assert worst_relative(h_part, hh, "tau", scale=scale) < TOL
        oracle.model = full


def _d_scale(D):
    diag = np.einsum("kii->ki", D)
    return np.sqrt(np.abs(diag[:, :, None] * diag[:, None, :])).max(axis=0)


@pytest.mark.parametrize("name", sorted(URDF_BUILTIN))
def test_gd_terms_of_builtin_against_urdf_model(name):
    # the panda's fingers are separate bodies in the URDF model: only D, h, c compare there
    _terms_vs_urdf(load_robot(name), builtin_urdf_path(name), halves=name == "ur5", seed=7)


def test_gd_terms_of_toy_against_urdf_model(toy):
    """Continuous, prismatic and unaligned joints; with and without a locked side branch."""
    _terms_vs_urdf(load_robot(toy, tip="tool"), toy, halves=False, seed=8)
    _terms_vs_urdf(load_robot(toy, base="l1", tip="l3"), toy, halves=False, seed=9)


def test_a_robot_file_with_a_byte_order_mark_is_read_with_a_note(tmp_path):
    """A TOML robot file saved with a UTF-8 byte-order mark (as Windows editors write it) is
    the same robot, with a note; it was refused as invalid TOML at line 1, column 1."""
    import warnings
    from importlib import resources

    text = resources.files("gd_analyze").joinpath("data", "two-link.toml").read_text()
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = load_robot(str(path))
    assert [w.category for w in caught] == [InputNote]
    plain = load_robot("two-link")
    np.testing.assert_array_equal(robot.mass, plain.mass)
    np.testing.assert_array_equal(robot.inertia, plain.inertia)
    assert robot.name == plain.name


@pytest.mark.parametrize("name", ["ur5.xml", "ur5.urdf.xacro"])
def test_a_urdf_not_named_urdf_is_said_to_be_xml(tmp_path, name):
    """A robot file whose name does not end in .urdf is read as TOML: a URDF saved as .xml,
    or a ROS package's .urdf.xacro, was refused with TOML's 'Invalid statement (at line 1,
    column 1)'. Oracle: the file is the shipped UR5 URDF."""
    path = tmp_path / name
    path.write_bytes(builtin_urdf_path("ur5").read_bytes())
    with pytest.raises(InputError, match=r"not a valid TOML robot file: XML, not TOML \(a URDF "
                       r"file's name ends in \.urdf; a xacro file needs xacro first\)"):
        load_robot(path)
    (tmp_path / "ur5.urdf").write_bytes(path.read_bytes())
    assert load_robot(tmp_path / "ur5.urdf").n == 6


@pytest.mark.parametrize("name", ["arm.urdf", "arm.toml"])
def test_a_robot_that_is_a_folder_or_a_fifo_is_said_to_be_so(tmp_path, name):
    """A folder named arm.urdf was "no such file", a FIFO or device given as the robot
    "unknown robot ... and no such file": both exist, so the line says what they are, as the
    CSV reader says it. Oracle: the file system (os.mkdir, os.mkfifo, os.devnull)."""
    import os

    folder, fifo = tmp_path / name, tmp_path / f"fifo-{name}"
    folder.mkdir()
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r": is a folder, not a robot file$"):
        load_robot(folder)
    for path in (fifo, os.devnull):
        with pytest.raises(InputError, match=r": not a regular file \(a device, FIFO or socket"
                                             r"\?\): give a robot file$"):
            load_robot(path)


def test_an_empty_robot_name_is_no_folder():
    """load_robot("") said ": is a folder, not a robot file" (Path("") is "."): an empty name
    is an unknown robot and no file."""
    with pytest.raises(InputError, match=r"^'': unknown robot \(built-in: .*\) and no such file$"):
        load_robot("")


def test_a_robot_file_not_in_utf8_names_the_byte(tmp_path):
    """A TOML robot file saved as Latin-1 said Python's "'utf-8' codec can't decode byte 0xe9
    in position 21: invalid continuation byte"; now, as the CSV and URDF readers say it, the
    byte counted from 1 (oracle: where the file's own bytes hold it)."""
    from importlib import resources

    text = resources.files("gd_analyze").joinpath("data", "two-link.toml").read_text()
    raw = text.replace('name = "two-link"', 'name = "two-link \xe9"').encode("latin-1")
    path = tmp_path / "latin1.toml"
    path.write_bytes(raw)
    at = raw.index(b"\xe9") + 1
    with pytest.raises(InputError) as err:
        load_robot(path)
    assert str(err.value) == f"{path}: not a valid TOML robot file: not UTF-8 text (byte {at})"


@pytest.mark.parametrize("name", ["a\x00b.toml", "x" * 5000 + ".toml"])
def test_a_name_no_file_system_can_hold_is_an_unknown_robot(name):
    with pytest.raises(InputError, match=r"^unknown robot '.*' \(no such file; built-in: "):
        load_robot(name)
