"""Any number of joints. The main job, evaluate, control and sweep run end to
end on a 10- and a 12-joint chain (two-digit element labels, "D1,10"), and the model they write
matches Pinocchio's rnea within its error budget.

The chains are planar but for one twisted joint, so that their explicit model derives in
seconds (a chain twisted at every joint has too many harmonics for that at n = 10). The 10-joint
chain has joint limits, so the model's error is also sampled over its joint-limit region; the
12-joint one has no region: the region's velocity vertices grow as 2^(n-1), and that
certification alone takes minutes at 12 joints (the 10-joint run covers the path). A revolute
joint without position limits is continuous (its region covers the full circle), so the
12-joint arm's last joint has no velocity limit instead; its trajectory is planned on the same
arm with that limit."""

import json

import numpy as np
import pinocchio as pin
import pytest
from robot_files import chain_toml

from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.ranking.ranking import element_labels
from gd_analyze.store.model_file import load_model
from gd_analyze.trajectory.trajectory import read_trajectory

EPS = 0.01          # the main job's default --tolerance


def _run(args, capsys):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.slow
@pytest.mark.parametrize("n", [10, 12])
def test_every_command_on_a_chain_of_n_joints(n, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    robot_file = tmp_path / "chain.toml"
    robot_file.write_text(chain_toml(n, limits=n == 10, last_qd_max=n == 10))
    planned = robot_file
    if n == 12:                 # planning needs every velocity limit: the arm with joint 12's
        planned = tmp_path / "planned.toml"
        planned.write_text(chain_toml(n, limits=False))
    start = ",".join(str(10 * (-1) ** k) for k in range(n))
    goal = ",".join(str(-20 * (-1) ** k) for k in range(n))
    code, _, err = _run(["plan", planned, "-o", "t.csv", "--setpoints", "5",
                         f"--start={start}", f"--goal={goal}"], capsys)
    assert code == 0, err
    if n == 12:                 # its provenance names that arm: the commands would warn
        (tmp_path / "t.provenance.json").unlink()

    # the reports (their figures and tables are keyed by the labels) on 10 joints only: they
    # take as long as the rest
    reports = [] if n == 10 else ["--no-report"]
    code, _, err = _run([robot_file, "t.csv", "-o", "main", "-q", "--guarantee", "trajectory",
                         *reports], capsys)
    assert code == 0, err
    for name in ("results.h5", "simplified_model.json") + \
            ("report.html", "report.pdf") * (n == 10):
        assert (tmp_path / "main" / name).is_file(), name
    model = load_model(tmp_path / "main" / "simplified_model.json")
    assert list(model.choices) == element_labels(n) and "D1,10" in model.choices

    # the model's torque against Pinocchio's rnea, within EPS x peak |tau| per joint
    traj = read_trajectory(tmp_path / "t.csv", n_joints=n)
    pm = pinocchio_model(model.robot)
    data = pm.createData()
    tau_ref = np.array([pin.rnea(pm, data, *x) for x in zip(traj.q, traj.qd, traj.qdd)])
    err_tau = np.abs(model.torque(traj.q, traj.qd, traj.qdd) - tau_ref).max(axis=0)
    scale = np.abs(tau_ref).max(axis=0)
    assert np.all(err_tau <= EPS * scale * (1 + 1e-6)), (err_tau / scale).max()

    code, out, err = _run(["evaluate", "main/simplified_model.json", "t.csv", "--json"], capsys)
    assert code == 0, err
    report = json.loads(out)
    assert report["max_relative_peak_error"] <= EPS * (1 + 1e-6)
    assert ("joint 12 has no velocity limit" in report["guarantee"]["statement"]) == (n == 12)

    code, _, err = _run(["control", "main/simplified_model.json", "t.csv", "-o", "control",
                         "-q", *reports], capsys)
    assert code == 0, err
    for name in ("control.h5",) + ("control_report.html", "control_report.pdf") * (n == 10):
        assert (tmp_path / "control" / name).is_file(), name

    # ranked in the command's own process (no --workers: a sweep this small starts no dask
    # cluster); the cluster's path is tests/jobs/test_sweep.py's and test_dask_cluster.py's
    code, _, err = _run(["sweep", robot_file, "t.csv", "-o", "sweep", "--tolerance", str(EPS),
                         "--held-out", "0", "-q", *reports], capsys)
    assert code == 0, err
    for name in ("sweep.h5", "merged_model.json", "merged_model.h", "merged_model.c",
                 "merged_model.py", "merged_model_casadi.py") + \
            ("sweep_report.html",) * (n == 10):
        assert (tmp_path / "sweep" / name).is_file(), name
    merged = load_model(tmp_path / "sweep" / "merged_model.json")
    assert list(merged.choices) == element_labels(n)
