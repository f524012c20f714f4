"""The simplified models of an arm with drives: the explicit and the recursive
forms keep the armature and the friction whole; oracle Pinocchio rnea with ``model.armature``
plus the hand-written friction viscous qd + coulomb sign(qd)."""

import json

import numpy as np
from conftest import SHIPPED, random_states
from model.test_drives import _friction
from symbolic.test_explicit import _c_operator_count, natural_error, python_tau, rnea
from symbolic.test_explicit_prismatic import _compile

from gd_analyze import load_robot
from gd_analyze.simplify.deploy import build_recursive
from gd_analyze.store.model_file import load_model
from gd_analyze.symbolic.codegen import build_program
from gd_analyze.symbolic.drive_regressor import with_drives
from gd_analyze.symbolic.emit import emit_c
from gd_analyze.symbolic.explicit import derive, model_terms
from gd_analyze.trajectory.trajectory import read_trajectory

TOL = 1e-10


def _reference(robot, q, qd, qdd):
    return rnea(robot, q, qd, qdd) + _friction(robot, qd)


def test_full_explicit_model_with_drives_equals_rnea_in_python_and_c(tmp_path):
    robot = load_robot("puma560-drives")
    rigid = build_program(model_terms(derive(robot)), robot.n, np.zeros(robot.n))
    program = with_drives(rigid, robot)
    q, qd, qdd = random_states(robot, 150, 31)
    qd[0] = 0.0
    ref = _reference(robot, q, qd, qdd)
    assert natural_error(python_tau(program)(q, qd, qdd), ref).max() < TOL
    assert natural_error(_compile(tmp_path, program, robot.n)(q, qd, qdd), ref).max() < TOL
    # the drives cost at most 3 multiplications and 3 additions per joint (fewer where the
    # armature folds into a constant coefficient of qdd_i already there), read off the C text
    more, base = program.cost(), rigid.cost()
    for op in ("multiplications", "additions"):
        assert 0 < more[op] - base[op] <= 3 * robot.n
    assert "(qd[0] > 0 ? 1.0 : qd[0] < 0 ? -1.0 : 0.0)" in emit_c(program, {})
    assert _c_operator_count(emit_c(program, {})) == (
        more["multiplications"], more["additions"], more["sin"] + more["cos"])


def test_recursive_model_with_drives_equals_rnea():
    robot = load_robot("puma560-drives")
    q, qd, qdd = random_states(robot, 120, 32)
    model, _ = build_recursive(robot, q, qd, qdd, tolerance=0.0)
    ref = _reference(robot, q, qd, qdd)
    assert natural_error(model.torque(q, qd, qdd), ref).max() < TOL


def test_main_job_on_the_puma_with_drives_keeps_them_in_the_model(shared_main):
    eps = 0.01                  # the main job's default --tolerance
    folder = shared_main("puma560-drives", SHIPPED)      # the default run, read only
    robot = load_robot("puma560-drives")
    traj = read_trajectory(SHIPPED, 6)
    ref = _reference(robot, traj.q, traj.qd, traj.qdd)
    scale = np.abs(ref).max(axis=0)
    ns = {}
    exec((folder / "simplified_model.py").read_text(), ns)
    loaded = load_model(folder / "simplified_model.json")
    assert loaded.robot.armature.tolist() == robot.armature.tolist()
    for tau in (ns["tau"](traj.q, traj.qd, traj.qdd), loaded.torque(traj.q, traj.qd, traj.qdd)):
        assert (np.abs(tau - ref).max(axis=0) <= eps * scale * (1 + 1e-9)).all()
    spec = json.loads((folder / "simplified_model.json").read_text())
    assert spec["robot"]["parameters"]["link"][1]["armature"] == robot.armature[1]


def test_stored_dataset_carries_the_armature_part_and_the_friction(shared_main):
    import xarray as xr

    folder = shared_main("puma560-drives", SHIPPED)      # the default run, read only
    robot = load_robot("puma560-drives")
    with xr.open_dataset(folder / "results.h5", engine="h5netcdf") as ds:
        np.testing.assert_array_equal(ds["D_arm"].values, robot.armature)
        D = ds["D_tran"].values + ds["D_rot"].values + np.diag(ds["D_arm"].values)
        np.testing.assert_allclose(ds["D"].values, D, rtol=0, atol=1e-15 * np.abs(D).max())
        qd, qdd = ds["qd"].values, ds["qdd"].values
        np.testing.assert_array_equal(ds["tau_f"].values, _friction(robot, qd))
        tau = (np.einsum("kij,kj->ki", ds["D"].values, qdd) + ds["h"].values + ds["c"].values
               + ds["tau_f"].values)
        scale = np.abs(tau).max(axis=0)
        assert (np.abs(ds["tau"].values - tau).max(axis=0) <= 1e-12 * scale).all()
        # the rigid links are ranked too, for the comparison with the chapter
        assert set(ds["dominance_rigid_links"].values) <= {"translational", "rotational",
                                                           "both", "negligible"}
        diag = [list(ds["element"].values).index(f"D{i}{i}") for i in range(1, 7)]
        assert (ds["share_arm"].values[diag] > 0).all()
        # the report's chapter comparison states both agreements, counted here afresh
        from gd_analyze.ranking.ranking import CHAPTER_DOMINANCE
        from gd_analyze.report.main_context import report_context

        labels = [str(v) for v in ds["element"].values]
        ours = dict(zip(labels, (str(v) for v in ds["dominance"].values)))
        rigid = dict(zip(labels, (str(v) for v in ds["dominance_rigid_links"].values)))
        n_drives = sum(ours[k] == v for k, v in CHAPTER_DOMINANCE.items())
        n_rigid = sum(rigid[k] == v for k, v in CHAPTER_DOMINANCE.items())
        note = report_context(ds)["compare"]["note"]
        assert (f"{n_drives} of {len(CHAPTER_DOMINANCE)} classes agree" in note
                and f"alone (drives left out, the chapter's model) {n_rigid} of "
                    f"{len(CHAPTER_DOMINANCE)}" in note), note


def test_report_of_the_puma_with_drives_draws_the_armature(shared_main):
    """The whole main job, report included, on the built-in arm with drives (the armature is
    a fourth part on the diagonal D panels)."""
    out = shared_main("puma560-drives", SHIPPED)         # the default run, read only
    svg = (out / "figures" / "fig_3_10_D.svg").read_text()
    assert "armature" in svg            # the legend's text, kept as a comment beside its glyphs
    assert (out / "report.pdf").stat().st_size > 0
