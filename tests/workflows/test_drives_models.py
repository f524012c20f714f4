"""The simplified models of an arm with drives (issue 20, item 1): the explicit and the recursive
forms keep the armature and the friction whole; oracle Pinocchio rnea with ``model.armature``
plus the hand-written friction viscous qd + coulomb sign(qd)."""

import json

import numpy as np

from conftest import SHIPPED, random_states
from core.test_drives import _friction
from core.test_explicit import _c_operator_count, natural_error, python_tau, rnea
from core.test_explicit_prismatic import _compile
from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.core.codegen import build_program, emit_c, with_drives
from gd_analyze.core.explicit import derive, model_terms
from gd_analyze.core.simplified import SimplifiedModel
from gd_analyze.io.trajectory import read_trajectory
from gd_analyze.workflows.deploy import build_recursive

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


def test_main_job_on_the_puma_with_drives_keeps_them_in_the_model(tmp_path, capsys):
    eps = 0.01
    code = main(["puma560-drives", str(SHIPPED), "-o", str(tmp_path), "--no-report",
                 "--tolerance", str(eps)])
    assert code == 0, capsys.readouterr().err
    robot = load_robot("puma560-drives")
    traj = read_trajectory(SHIPPED, 6)
    ref = _reference(robot, traj.q, traj.qd, traj.qdd)
    scale = np.abs(ref).max(axis=0)
    ns = {}
    exec((tmp_path / "simplified_model.py").read_text(), ns)
    loaded = SimplifiedModel.load(tmp_path / "simplified_model.json")
    assert loaded.robot.armature.tolist() == robot.armature.tolist()
    for tau in (ns["tau"](traj.q, traj.qd, traj.qdd), loaded.torque(traj.q, traj.qd, traj.qdd)):
        assert (np.abs(tau - ref).max(axis=0) <= eps * scale * (1 + 1e-9)).all()
    spec = json.loads((tmp_path / "simplified_model.json").read_text())
    assert spec["robot"]["parameters"]["link"][1]["armature"] == robot.armature[1]
