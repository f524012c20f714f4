"""A model file records the mounting it was built with: ``evaluate`` and ``control``
with the same ``--base-rpy`` or ``--gravity`` apply it once (with a note), another mounting
replaces it (never a turn on top of it).

Oracle: Pinocchio's ``rnea`` of the upright two-link arm with its gravity set to R^T g_world
(the URDF rpy convention), and the closed loop's exact tracking (computed-torque control with
the plant's own model tracks to round-off)."""

import json

import numpy as np
import pinocchio as pin
import pytest
from urdf_oracle import TOY_URDF

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.mounting import rpy_matrix, with_mounting
from gd_analyze.store.model_file import load_model
from gd_analyze.trajectory.trajectory import read_trajectory

TURN = (0.0, 0.0, 180.0)


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def turned(tmp_path_factory):
    """The two-link arm's model built with --base-rpy 0,0,180 on its default plan."""
    folder = tmp_path_factory.mktemp("turned")
    csv = folder / "plan.csv"
    assert main(["plan", "two-link", "-o", str(csv)]) == 0
    assert main(["two-link", str(csv), "-o", str(folder / "out"), "--no-report", "-q",
                 "--base-rpy", "0,0,180"]) == 0
    return folder / "out" / "simplified_model.json", csv


def _oracle_tau(csv, rpy):
    """Pinocchio's rnea of the upright arm with gravity turned into its base by rpy."""
    robot = load_robot("two-link")
    model = pinocchio_model(robot)
    model.gravity.linear = rpy_matrix(*rpy, degrees=True).T @ np.asarray(robot.gravity)
    data = model.createData()
    traj = read_trajectory(csv, n_joints=2)
    return np.array([pin.rnea(model, data, q, qd, qdd).copy()
                     for q, qd, qdd in zip(traj.q, traj.qd, traj.qdd)]), traj


def _error(model_path, csv, rpy):
    tau, traj = _oracle_tau(csv, rpy)
    return np.abs(load_model(model_path).torque(traj.q, traj.qd, traj.qdd) - tau).max(axis=0)


def test_the_model_file_records_its_mounting(turned):
    model_path, _ = turned
    said = json.loads(model_path.read_text())["mounting"]
    assert said["base_rpy_deg"] == list(TURN)
    assert said["gravity_world"] == list(load_robot("two-link").gravity)


def test_evaluate_with_the_same_flag_applies_it_once(turned, capsys):
    model_path, csv = turned
    code, out, err = _run(capsys, "evaluate", model_path, csv, "--base-rpy", "0,0,180",
                          "--json")
    said = json.loads(out)
    assert code == 0 and said["guarantee"]["covered"]
    assert "applied once" in err and len(err.strip().splitlines()) == 1
    # the reference is the turned arm, once: the model's error against it is round-off
    assert np.all(_error(model_path, csv, TURN) <= 1e-9)
    assert max(said["peak_abs_error"]) <= 1e-9


def test_evaluate_with_another_mounting_replaces_the_models(turned, capsys):
    """--base-rpy 0,0,0 is the upright arm: the error is the model's against upright rnea,
    not against a turn of 180 deg on top of the model's own."""
    model_path, csv = turned
    code, out, _ = _run(capsys, "evaluate", model_path, csv, "--base-rpy", "0,0,0", "--json")
    said = json.loads(out)
    expected = _error(model_path, csv, (0.0, 0.0, 0.0))
    assert code == 3 and not said["guarantee"]["covered"]
    np.testing.assert_allclose(said["peak_abs_error"], expected, rtol=1e-9)


def test_a_file_without_the_key_reads_its_mounting_from_the_provenance(turned, tmp_path,
                                                                        capsys):
    model_path, csv = turned
    spec = json.loads(model_path.read_text())
    del spec["mounting"]
    older = tmp_path / "older.json"
    older.write_text(json.dumps(spec))
    code, out, _ = _run(capsys, "evaluate", older, csv, "--base-rpy", "0,0,180", "--json")
    assert code == 0 and max(json.loads(out)["peak_abs_error"]) <= 1e-9


def test_a_mounting_that_does_not_give_the_robots_gravity_is_refused(turned, tmp_path,
                                                                     capsys):
    model_path, csv = turned
    spec = json.loads(model_path.read_text())
    spec["mounting"]["base_rpy_deg"] = [0.0, 0.0, 90.0]
    edited = tmp_path / "edited.json"
    edited.write_text(json.dumps(spec))
    code, _, err = _run(capsys, "evaluate", edited, csv)
    assert code == 2 and "mounting" in err and len(err.strip().splitlines()) == 1


def test_control_with_the_same_flag_tracks_exactly(turned, tmp_path, capsys):
    """The full-model controller on its own plant tracks to round-off; with the mounting
    applied twice it tracked at 0.10 rad."""
    model_path, csv = turned
    code, out, err = _run(capsys, "control", model_path, csv, "--base-rpy", "0,0,180",
                          "--no-report", "--json", "-o", tmp_path / "control")
    assert code == 0 and "applied once" in err
    tracking = json.loads(out)["tracking"]
    assert max(tracking["full"]["peak_grid"]) < 1e-6
    assert max(tracking["simplified"]["peak_grid"]) < 1e-6


@pytest.mark.slow
def test_a_turned_base_link_records_the_worlds_gravity(tmp_path, capsys):
    """``--base`` on a link turned in the URDF's root frame (Rx(0.3)): the model file stores
    gravity in the world (the root's, as Pinocchio reads the URDF), not in the base link's
    frame, and the base's turn; ``evaluate --gravity`` with the world's gravity is the model's
    own robot, its error at round-off against Pinocchio's model of the whole URDF."""
    urdf = tmp_path / "toy.urdf"
    urdf.write_text(TOY_URDF.replace('name="j1" type="continuous"', 'name="j1" type="revolute"')
                    .replace('<limit velocity="2.0" effort="5"/>',
                             '<limit lower="-2" upper="2" velocity="2.0" effort="5"/>'))
    chain = ["--base", "base", "--tip", "tool"]
    csv, out = tmp_path / "toy.csv", tmp_path / "out"
    assert main(["plan", str(urdf), "-o", str(csv), *chain]) == 0
    assert _run(capsys, urdf, csv, *chain, "-o", out, "--no-report", "-q")[0] == 0
    whole = pin.buildModelFromUrdf(str(urdf))
    saved = json.loads((out / "simplified_model.json").read_text())["mounting"]
    assert saved["gravity_world"] == list(whole.gravity.linear)
    np.testing.assert_allclose(rpy_matrix(*saved["base_rpy_deg"], degrees=True),
                               whole.frames[whole.getFrameId("base")].placement.rotation,
                               rtol=0, atol=1e-15)
    model = load_model(out / "simplified_model.json")
    g = ",".join(f"{v:g}" for v in whole.gravity.linear)
    code, text, err = _run(capsys, "evaluate", out / "simplified_model.json", csv, "--gravity", g)
    assert code == 0, err
    assert "covers this trajectory: yes" in text and "not the model's robot" not in text
    # the oracle: the URDF's own model (its side joint jb locked at 0) and the model's robot
    # mounted with the world's gravity give the same torques
    mounted = with_mounting(model.robot, gravity=whole.gravity.linear)
    np.testing.assert_allclose(mounted.gravity, model.robot.gravity, rtol=0, atol=1e-14)
    traj = read_trajectory(csv, 3)
    reduced = pin.buildReducedModel(whole, [whole.getJointId("jb")], pin.neutral(whole))
    ours = pinocchio_model(mounted)
    for x in zip(traj.q, traj.qd, traj.qdd):
        want = pin.rnea(reduced, reduced.createData(), *x)
        assert np.abs(pin.rnea(ours, ours.createData(), *x) - want).max() <= \
            1e-10 * max(1.0, np.abs(want).max())
