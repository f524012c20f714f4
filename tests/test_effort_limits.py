"""Each joint's peak |tau| against the robot's effort limit, in the summary
and the report; the oracle is Pinocchio's rnea on the URDF's own model and the URDF's text."""

import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import xarray as xr
from conftest import built_once, printed_by
from urdf_oracle import UrdfOracle

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.model.urdf import builtin_urdf_path
from gd_analyze.report.main import write_report
from gd_analyze.trajectory.trajectory import read_trajectory

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
UR5_CSV = ROOT / "data" / "ur5_trajectory.csv"


def _efforts(urdf_text, names):
    doc = ET.fromstring(urdf_text)
    limits = {j.get("name"): float(j.find("limit").get("effort"))
              for j in doc.iter("joint") if j.find("limit") is not None}
    return np.array([limits[n] for n in names])


def _summary_rows(out):
    block = out.split("effort limits")[1].split("\n\n")[0].splitlines()[2:]
    return [line.split() for line in block if re.match(r"\d", line)]


@pytest.fixture(scope="module")
def weak_ur5():
    """ur5.urdf with the wrist's limits (28 N m) cut to 0.5 N m: joints 4 and 5 exceed them;
    written once a session (:func:`conftest.built_once`), so that its runs are shared."""
    def build(folder):
        text = builtin_urdf_path("ur5").read_text().replace('effort="28.0"', 'effort="0.5"')
        assert text.count('effort="0.5"') == 3
        (folder / "weak_ur5.urdf").write_text(text)
    return built_once("weak-ur5", build) / "weak_ur5.urdf"


@pytest.fixture(scope="module")
def weak_run(weak_ur5, shared_main):
    """The main job on the weak UR5 without report, shared (read only): its output folder."""
    return shared_main(weak_ur5, UR5_CSV, "--no-report")


def test_summary_and_dataset_give_peak_tau_against_the_urdf_effort(weak_ur5, weak_run):
    out_dir, out = weak_run, printed_by(weak_run)
    names = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
             "wrist_2_joint", "wrist_3_joint"]
    limit = _efforts(weak_ur5.read_text(), names)
    oracle = UrdfOracle(weak_ur5, names)
    traj = read_trajectory(UR5_CSV, n_joints=6)
    tau = np.array([oracle.rnea(traj.q[k], traj.qd[k], traj.qdd[k])
                    for k in range(traj.n_setpoints)])
    peak = np.abs(tau).max(axis=0)
    rows = _summary_rows(out)
    assert [int(r[0]) for r in rows] == [1, 2, 3, 4, 5, 6]
    for j, r in enumerate(rows):
        assert float(r[1]) == pytest.approx(peak[j], rel=1e-3)       # printed to 4 digits
        assert float(r[2]) == pytest.approx(limit[j], rel=1e-12)
        assert r[3:5] == ["N", "m"]
        assert r[-1] == ("EXCEEDED" if peak[j] > limit[j] else "within")
    assert {int(r[0]) for r in rows if r[-1] == "EXCEEDED"} == set(
        np.flatnonzero(peak > limit) + 1) and (peak > limit).any()
    assert "exceed" in out.split("effort limits")[1].split("\n\n")[0].splitlines()[-1]
    with xr.open_dataset(out_dir / "results.h5") as ds:
        assert np.array_equal(ds["tau_max"].values, limit)


@pytest.mark.slow
def test_report_has_the_effort_table(tmp_path, weak_run):
    # the main job's report is written from its results (never recomputed): the HTML alone,
    # from the shared run's results.h5
    write_report(weak_run / "results.h5", tmp_path / "out", formats=("html",))
    html = (tmp_path / "out" / "report.html").read_text()
    assert "effort limit" in html and html.count("EXCEEDED") >= 1
    assert "exceeds" in html or "exceed their" in html


def test_robot_file_tau_max_and_robots_without_limits(tmp_path, capsys):
    from importlib import resources

    text = resources.files("gd_analyze").joinpath("data", "two-link.toml").read_text()
    text = text.replace("qdd_max_deg = 360.0", "qdd_max_deg = 360.0\ntau_max = 1.0", 1)
    path = tmp_path / "limited.toml"
    path.write_text(text)
    robot = load_robot(str(path))
    assert robot.tau_max[0] == 1.0 and np.isnan(robot.tau_max[1])
    assert load_robot(str(path)).to_dict()["link"][0]["tau_max"] == 1.0
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("tau_max = 1.0", "tau_max = -1.0"))
    code = main([str(bad), str(ROOT / "data" / "puma560_trajectory.csv")])
    err = capsys.readouterr().err
    assert code == 2 and "link[1].tau_max" in err and "positive" in err
    # no limit given: no table, no line
    t = np.linspace(0, 1, 21)
    csv = tmp_path / "tl.csv"
    np.savetxt(csv, np.column_stack([t, np.sin(t), np.cos(t)]), delimiter=",",
               header="t,q1,q2", comments="")
    code = main(["two-link", str(csv), "-o", str(tmp_path / "plain"), "--no-report"])
    assert code == 0 and "effort limits" not in capsys.readouterr().out
    code = main([str(path), str(csv), "-o", str(tmp_path / "one"), "--no-report"])
    out = capsys.readouterr().out
    rows = _summary_rows(out)
    assert code == 0 and len(rows) == 1 and rows[0][0] == "1" and rows[0][2] == "1"
