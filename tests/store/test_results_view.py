"""The typed results view (gd_analyze.store.results_view): read once, checked as read, the
round-off marks and joint units stored at analysis checked against Pinocchio and the joint
types."""

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.errors import InputError
from gd_analyze.store.names import RANKING_COLUMNS, Attr, Var
from gd_analyze.store.results_view import ZERO_MARK, Results
from gd_analyze.trajectory.trajectory import read_trajectory

ROOT = Path(__file__).resolve().parents[2]


def _pinocchio_terms(name):
    """D (N, n, n) and the velocity terms h (N, n) of the robot along its shipped trajectory,
    by Pinocchio (crba, rnea with qdd = 0 and no gravity), and tau (N, n) by rnea."""
    robot = load_robot(name)
    traj = read_trajectory(ROOT / "data" / f"{name}_trajectory.csv", robot.n)
    model = pinocchio_model(robot)
    data = model.createData()
    D = np.array([pin.crba(model, data, q).copy() for q in traj.q])
    tau = np.array([pin.rnea(model, data, q, qd, qdd).copy()
                    for q, qd, qdd in zip(traj.q, traj.qd, traj.qdd)])
    model.gravity = pin.Motion.Zero()
    h = np.array([pin.rnea(model, data, q, qd, 0 * qd).copy() for q, qd in zip(traj.q, traj.qd)])
    return robot, D, h, tau


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_element_round_off_marks_are_zero_by_pinocchio(shipped_dataset, name):
    # an element marked zero in every part is zero by Pinocchio's D and h, to 1e-9 of its
    # scale (peak sqrt(D_ii D_jj) or peak |tau_i|); and the marks are not all False/True
    results = Results.from_dataset(shipped_dataset(name))
    robot, D, h, tau = _pinocchio_terms(name)
    n = robot.n
    marked = [r.label for r in results.ranking.rows if r.round_off]
    assert 0 < len(marked) < len(results.ranking.rows) or name == "stanford"
    diag = np.einsum("tii->ti", D)
    for row in results.ranking.rows:
        kind, idx = row.label[0], row.label[1:]
        if kind == "D":
            i, j = int(idx[0]) - 1, int(idx[1]) - 1
            peak = np.max(np.abs(D[:, i, j]))
            scale = np.max(np.sqrt(np.abs(diag[:, i] * diag[:, j])))
        else:
            i = int(idx) - 1
            peak, scale = np.max(np.abs(h[:, i])), np.max(np.abs(tau[:, i]))
        assert np.isfinite(peak) and np.isfinite(scale) and scale > 0
        if row.round_off:
            assert peak <= 1e-9 * scale, (row.label, peak, scale)
        else:                                    # a share or a peak is data: finite
            assert np.isfinite(row.peak_total)
    assert n == len(results.prismatic)


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_joint_units_are_those_of_the_joint_types(shipped_dataset, name):
    results = Results.from_dataset(shipped_dataset(name))
    prismatic = load_robot(name).prismatic
    assert results.prismatic == tuple(bool(p) for p in prismatic)
    assert results.joint_units["tau"] == tuple("N" if p else "N m" for p in prismatic)
    assert results.joint_units["q"] == tuple("m" if p else "rad" for p in prismatic)
    assert [r.units for r in results.torque_error.rows] == list(results.joint_units["tau"])


@pytest.mark.slow
def test_torque_error_round_off_is_within_round_off_of_pinocchio(shipped_dataset):
    # a joint whose error is marked round-off: the stored tau_s agrees with Pinocchio's rnea
    # to round-off of the arm's torques; the others carry a real error
    ds = shipped_dataset("puma560")
    results = Results.from_dataset(ds)
    _, _, _, tau = _pinocchio_terms("puma560")
    tau_s = np.asarray(ds[Var.TAU_SIMPLIFIED].values)
    arm = np.max(np.abs(tau))
    for row in results.torque_error.rows:
        diff = np.max(np.abs(tau_s[:, row.joint - 1] - tau[:, row.joint - 1]))
        assert np.isfinite(diff)
        if row.round_off:
            assert diff <= 1e-12 * arm, (row.joint, diff, arm)
            assert ZERO_MARK in results.torque_error.text()[row.joint]
        else:
            assert diff > 1e-12 * arm


def test_open_reads_what_the_memory_view_reads(shipped_dataset, tmp_path):
    ds = shipped_dataset("stanford")
    path = tmp_path / "results.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    opened, memory = Results.open(path), Results.from_dataset(ds)
    assert opened.source == str(path)
    assert opened.ranking.text() == memory.ranking.text()
    assert opened.torque_error.text() == memory.torque_error.text()
    np.testing.assert_array_equal(opened.ranking.column("round_off"),
                                  memory.ranking.column("round_off"))
    assert opened.region["lines"] == memory.region["lines"]


@pytest.mark.parametrize("missing", [Var.SHARE_TRAN, Var.TAU_ERROR_PEAK, Var.LINK_MASS,
                                     Var.DH_ALPHA])
def test_a_missing_variable_is_one_line_naming_file_and_variable(shipped_dataset, tmp_path,
                                                                 missing):
    path = tmp_path / "results.h5"
    shipped_dataset("puma560").drop_vars(missing).to_netcdf(path, engine="h5netcdf")
    with pytest.raises(InputError) as err:
        Results.open(path)
    text = str(err.value)
    assert "\n" not in text and str(path) in text and repr(missing) in text


def test_stored_marks_are_read_not_decided_again(shipped_dataset):
    # the view shows what results.h5 stores: flip a stored mark and the CLI text follows
    # (every number the command line shows of that element, the share and the peak, is "≡ 0")
    ds = shipped_dataset("puma560").copy(deep=True)
    k = next(i for i, r in enumerate(Results.from_dataset(ds).ranking.rows) if not r.round_off)
    assert ZERO_MARK not in Results.from_dataset(ds).ranking.text()[k + 1]
    ds[Var.ELEMENT_ROUND_OFF].values[k] = 1
    line = Results.from_dataset(ds).ranking.text()[k + 1]
    numbers = [c for c in RANKING_COLUMNS if c.cli is not None and c.cli.number]
    assert len(numbers) >= 2 and line.count(ZERO_MARK) == len(numbers), line


@pytest.mark.parametrize("name", ["stanford", "ur5"])
def test_the_stored_robot_is_the_robot_analysed(shipped_dataset, name):
    # the robot's view against the robot loaded again: links, geometry, joint types, limits
    robot, stored = load_robot(name), Results.from_dataset(shipped_dataset(name)).robot_record
    np.testing.assert_array_equal(stored.link_mass, robot.mass)
    np.testing.assert_array_equal(stored.link_com, robot.com)
    np.testing.assert_array_equal(stored.dh[1], robot.a)
    np.testing.assert_array_equal(stored.dh[2], robot.alpha)
    assert stored.joint_type == tuple("prismatic" if p else "revolute" for p in robot.prismatic)
    np.testing.assert_array_equal(stored.effort_limit, robot.tau_max)
    assert stored.drives is None or not stored.has_drives      # the shipped arms: no drives


def test_the_trajectory_is_read_on_demand_from_the_dataset(shipped_dataset):
    ds = shipped_dataset("puma560")
    traj = Results.from_dataset(ds).trajectory
    got = read_trajectory(ROOT / "data" / "puma560_trajectory.csv", 6)
    np.testing.assert_allclose(traj.t, got.t, rtol=0, atol=0)
    for stored, read in zip(next(traj.motion_blocks(len(got.t))), (got.q, got.qd, got.qdd)):
        np.testing.assert_allclose(stored, read, rtol=0, atol=0)
    assert traj.tau_f is None                                   # no drives, no friction


def test_other_attributes_are_kept_with_the_setting_they_record(shipped_dataset):
    # an attribute this version does not name is among the others, with the setting it
    # records beside it (simplified_x beside x); a named one is a field, not an other
    ds = shipped_dataset("puma560").copy()
    ds.attrs = {**ds.attrs, "zz_new": "a", "simplified_zz_new": "b", "robot_tip": "link6"}
    others = {k: (v, twin) for k, v, twin in Results.from_dataset(ds).provenance.others}
    assert others["zz_new"] == ("a", None) and others["simplified_zz_new"] == ("b", "a")
    assert others["robot_tip"] == ("link6", None)
    assert not any(k.startswith("verification_") or k == "rule" for k in others)
    assert list(others) == sorted(others)


def test_what_section_5_says_is_not_repeated_raw_among_the_others(shipped_dataset):
    # the screen's kind is said in words in Sec. 5 ("pruned region model not built"); its raw
    # attribute gave a provenance row "simplified region screen proved | 1"
    ds = shipped_dataset("puma560").copy()
    ds.attrs = {**ds.attrs, Attr.SIMPLIFIED_REGION_SCREEN: "proved",
                Attr.SIMPLIFIED_REGION_SCREEN_PROVED: 1}
    others = [k for k, _, _ in Results.from_dataset(ds).provenance.others]
    assert Attr.SIMPLIFIED_REGION_SCREEN_PROVED not in others
    assert Attr.SIMPLIFIED_REGION_SCREEN not in others


def test_motion_blocks_are_the_motion_in_order(shipped_dataset):
    """Read block by block (the report's tables of a long trajectory), the motion is the whole
    motion, in order, in blocks of at most the rows asked for."""
    traj = Results.from_dataset(shipped_dataset("puma560")).trajectory
    whole = [traj.dataset[v].values for v in ("q", "qd", "qdd")]
    for rows in (1, 7, 31, 1000):
        blocks = list(traj.motion_blocks(rows))
        assert [b[0].shape[0] for b in blocks] == [min(rows, 31 - a) for a in range(0, 31, rows)]
        for k in range(3):
            np.testing.assert_array_equal(np.concatenate([b[k] for b in blocks]), whole[k])
