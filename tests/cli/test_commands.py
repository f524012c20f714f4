"""The main job's region: its options, the summary lines, results.h5 and
the model JSON read back, and a trajectory outside the region flagged; ``control`` and ``plan``
under a file size limit."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from staging_checks import refused_by_the_limit, run_limited

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.estimation.estimate import RANK_TOL
from gd_analyze.trajectory.planning import default_motion


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def _fast_csv(path, speed=2.0):
    """A two-link trajectory whose joint 1 reaches ``speed`` x its velocity limit (pi rad/s)
    while its acceleration stays within its limit (2 pi rad/s^2): q1 = a sin(w t)."""
    robot = load_robot("two-link")
    qd_max, qdd_max = robot.qd_max[0], robot.qdd_max[0]
    w = 0.5 * qdd_max / (speed * qd_max)                 # a w^2 = qdd_max / 2
    a = speed * qd_max / w
    t = np.linspace(0.0, 2 * np.pi / w, 121)
    q1, qd1, qdd1 = a * np.sin(w * t), a * w * np.cos(w * t), -a * w * w * np.sin(w * t)
    z = np.zeros_like(t) + 0.3
    rows = np.column_stack([t, q1, z, qd1, 0 * t, qdd1, 0 * t])
    path.write_text("t,q1,q2,qd1,qd2,qdd1,qdd2\n"
                    + "\n".join(",".join(f"{v:.17g}" for v in r) for r in rows) + "\n")
    return path


@pytest.mark.slow
def test_trajectory_outside_the_region_is_flagged_stored_and_not_covered(tmp_path, capsys):
    """Twice the velocity limit: one warning naming joint, quantity and amount; results.h5
    stores coverage 0; the guarantee line says the trajectory is not covered (today's code
    printed the region guarantee without a word)."""
    csv = _fast_csv(tmp_path / "fast.csv")
    code, out, err = _run(capsys, "two-link", csv, "-o", tmp_path / "out")
    assert code == 0, err
    warn = [line for line in err.splitlines() if "leaves the region" in line]
    assert len(warn) == 1, err
    assert "joint 1 qd reaches 2x its limit (360 deg/s > 180 deg/s)" in warn[0]
    guarantee = next(line for line in out.splitlines() if line.startswith("guarantee:"))
    assert "at every state of the region (proved" in guarantee
    assert "this trajectory is not covered" in guarantee
    with xr.open_dataset(tmp_path / "out" / "results.h5") as ds:
        assert int(ds.attrs["region_covers_trajectory"]) == 0
        assert "joint 1 qd" in ds.attrs["region_coverage"]
        robot = load_robot("two-link")
        np.testing.assert_allclose(ds["region_qd_max"].values, robot.qd_max)
        assert ds["region_qd_max"].attrs["units"] == "rad s-1"
        assert ds["region_q_full_turn"].values.tolist() == [1, 1]
        assert np.isnan(ds["region_q_min"].values).all()        # not stored as [-pi, pi]
    model = json.loads((tmp_path / "out" / "simplified_model.json").read_text())
    region = model["guarantee"]["region"]
    assert region["q"] == ["any angle (full turn)"] * 2
    assert region["qdd_max_assumed"] == [False, False]
    from html_checks import html_text

    text = html_text((tmp_path / "out" / "report.html").read_text(), nbsp=True)
    assert "this trajectory is not covered: it leaves the region (joint 1 q\u0307 reaches 2x" in text
    assert "This trajectory leaves the region: joint 1 qd reaches 2x its limit" in text
    assert text.count("any angle (full turn)") >= 2


@pytest.mark.slow
def test_users_region_is_printed_stored_and_narrows_s_i(tmp_path, capsys):
    """--qd-max and --qdd-max in deg/s and deg/s^2: the summary prints the region one line per
    limit kind and s_i per joint in N m; results.h5 and the JSON hold the same limits; s_i is
    below the default region's, and above |tau_i| at every one of the trajectory's states
    that lies in the narrower region (Pinocchio's rnea, the oracle)."""
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model
    from gd_analyze.trajectory.trajectory import read_trajectory

    csv = _fast_csv(tmp_path / "slow.csv", speed=0.2)
    code, out, err = _run(capsys, "two-link", csv, "-o", tmp_path / "wide", "--no-report")
    assert code == 0 and "leaves the region" not in err, err
    code, narrow, err = _run(capsys, "two-link", csv, "-o", tmp_path / "narrow", "--no-report",
                             "--qd-max", "40", "--qdd-max", "70,80", "--q-limits", "-180:180")
    assert code == 0, err
    lines = narrow.splitlines()
    assert "region: q [deg] 1 any angle (full turn), 2 any angle (full turn)" in lines
    assert "qd max [deg/s] 1 40, 2 40" in lines
    assert "qdd max [deg/s^2] 1 70, 2 80" in lines
    # 36 deg/s < 40 deg/s, but the acceleration reaches 180 deg/s^2 > 70 deg/s^2
    assert "leaves the region: joint 1 qdd reaches 2.57x its limit (180 deg/s^2 > 70" in err
    scale = {}
    for name, text in (("wide", out), ("narrow", narrow)):
        row = next(line for line in text.splitlines() if line.startswith("s_i [N m]"))
        scale[name] = np.array([float(p.split()[1]) for p in
                                row.split(": ", 1)[1].split(";")[0].split(", ")])
    with xr.open_dataset(tmp_path / "narrow" / "results.h5") as ds:
        np.testing.assert_allclose(ds["region_qd_max"].values, [math.radians(40)] * 2)
        np.testing.assert_allclose(ds["region_qdd_max"].values,
                                   [math.radians(70), math.radians(80)])
        s = ds["simplified_guarantee_scale"].values
    np.testing.assert_allclose(scale["narrow"], s, rtol=1e-3)
    assert (scale["narrow"] < scale["wide"]).all()
    model = json.loads((tmp_path / "narrow" / "simplified_model.json").read_text())
    np.testing.assert_allclose(model["guarantee"]["region"]["qd_max"], [math.radians(40)] * 2)
    robot = load_robot("two-link")
    traj = read_trajectory(csv, n_joints=2)
    pm = pinocchio_model(robot)
    data = pm.createData()
    tau = np.array([pin.rnea(pm, data, *x) for x in zip(traj.q, traj.qd, traj.qdd)])
    inside = (np.abs(traj.qd) <= math.radians(40)).all(1) & \
        (np.abs(traj.qdd) <= [math.radians(70), math.radians(80)]).all(1)
    assert inside.any() and (np.abs(tau[inside]).max(0) <= s * (1 + 1e-9)).all()


@pytest.mark.parametrize("option, value", [
    ("--qd-max", "-1"), ("--qd-max", "nan"), ("--qdd-max", "inf"), ("--qdd-max", "0"),
    ("--q-limits", "10:5"), ("--q-limits", "-10:nan"), ("--qd-max", "1,2,3")])
def test_bad_region_options_exit_2_with_one_line_naming_the_option(tmp_path, capsys, option,
                                                                    value):
    csv = _fast_csv(tmp_path / "t.csv", speed=0.2)
    code, out, err = _run(capsys, "two-link", csv, "-o", tmp_path / "o", "--no-report",
                          option, value)
    assert code == 2 and not out
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and option in lines[0] and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_position_range_beyond_the_robots_is_clipped_with_a_warning(tmp_path, capsys):
    code, out, err = _run(capsys, "plan", "puma560", "-o", tmp_path / "p.csv",
                          "--q-limits", "-170:170", "--start", "0,0,0,0,0,0",
                          "--goal", "10,10,10,10,10,10")
    assert code == 0, err
    assert "joint 1's lower position limit -170 deg is beyond the robot's limit: clipped to " \
           "-160 deg" in err
    record = json.loads((tmp_path / "p.provenance.json").read_text())
    assert record["q_min"][0] == pytest.approx(math.radians(-160))


def test_tolerance_help_says_the_region_is_the_default(capsys):
    from gd_analyze.cli import analyze_parser

    text = " ".join(analyze_parser().format_help().split())
    assert "by default the largest |tau_i| over the region" in text
    assert "within EPS times its scale on the analysed trajectory" not in text


def test_the_output_folder_is_refused_where_a_file_stands(tmp_path):
    """-o naming a file: one InputError naming it, for every command that writes a folder;
    a folder, or none given (reports/ROBOT-STEM), is taken as it is."""
    from gd_analyze.cli.commands import output_folder
    from gd_analyze.errors import InputError

    afile = tmp_path / "out"
    afile.write_text("a file")
    with pytest.raises(InputError, match="exists and is not a folder") as err:
        output_folder(afile, "puma560", "control")
    assert str(afile) in str(err.value)
    assert output_folder(tmp_path) == tmp_path
    assert output_folder(None, "puma 560", "t") == Path("reports") / "puma_560-t"


def test_a_plan_without_velocity_limits_takes_the_duration_it_is_told(tmp_path, capsys):
    """example-robot-data's double pendulum gives no velocity limits: the refusal says to give
    --duration with --ignore-limits, and that plan is then written, with rest at both ends and
    t running to the duration given."""
    from robot_files import erd_path

    urdf = erd_path("double_pendulum_description/urdf/double_pendulum.urdf")
    plan = tmp_path / "plan.csv"
    assert main(["plan", urdf, "-o", str(plan)]) == 2
    assert "give --duration with --ignore-limits" in capsys.readouterr().err
    assert main(["plan", urdf, "-o", str(plan), "--duration", "2", "--ignore-limits"]) == 0
    data = np.loadtxt(plan, delimiter=",", skiprows=1)
    assert data[0, 0] == 0 and data[-1, 0] == 2
    assert np.all(data[[0, -1], 3:] == 0)                      # qd, qdd at rest at both ends


@pytest.mark.parametrize("options, limits, column, kind", [
    (["--qd-max", "1e-9"], (180.0, 360.0), "--qd-max: ", "velocity limits (--qd-max)"),
    ([], (1e-9, 360.0), "", "velocity limits (robot)"),
    ([], (180.0, 1e-30), "", "acceleration limits (robot)"),
])
def test_a_plan_too_slow_for_t_names_the_limit_that_makes_it_so(tmp_path, capsys, options,
                                                                 limits, column, kind):
    """A duration beyond the largest t accepted blames the limit that sets it, the option when
    the user gave it: --qd-max blamed the robot's limits. The duration said is the quintic's
    closed form, max_i of 15 |dq_i| / (8 qd_max_i) and sqrt(10 |dq_i| / (sqrt(3)
    qdd_max_i)). The robot is the two-link arm with the velocity and acceleration limits
    ``limits`` [deg/s, deg/s^2] in its own file."""
    robot = tmp_path / "slow.toml"
    shipped = Path(__file__).parents[2] / "src" / "gd_analyze" / "data" / "two-link.toml"
    robot.write_text(shipped.read_text().replace("qd_max_deg = 180.0", f"qd_max_deg = {limits[0]}")
                     .replace("qdd_max_deg = 360.0", f"qdd_max_deg = {limits[1]}"))
    dq = np.abs(np.subtract(*default_motion(load_robot(str(robot)))))
    qd_max = math.radians(float(options[1]) if options else limits[0])
    qdd_max = math.radians(limits[1])
    T = max((15 * dq / (8 * qd_max)).max(), np.sqrt(10 * dq / (math.sqrt(3) * qdd_max)).max())
    code, out, err = _run(capsys, "plan", robot, "-o", tmp_path / "plan.csv", *options)
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    said = err.removeprefix(f"gd-analyze: error: {column}the planned duration, ")
    assert said != err and f"the {kind} are too small" in said, err
    assert float(said.split(" s, ")[0]) == pytest.approx(T, rel=1e-12)
    assert not (tmp_path / "plan.csv").exists()


@pytest.fixture(scope="module")
def two_link_model(tmp_path_factory):
    """A two-link plan of 20 set points and the main job's model on it (no report)."""
    folder = tmp_path_factory.mktemp("model")
    csv = folder / "plan.csv"
    assert main(["plan", "two-link", "-o", str(csv), "--setpoints", "20"]) == 0
    assert main(["two-link", str(csv), "-o", str(folder / "main"), "-q", "--no-report"]) == 0
    return folder / "main" / "simplified_model.json", csv


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE")
@pytest.mark.parametrize("limit", [40_000, 200_000])
def test_control_refuses_a_file_size_limit_below_control_h5(two_link_model, tmp_path, limit):
    """Under ``ulimit -f`` below control.h5's estimate and the margin: one line naming the
    limit, exit 2, nothing left, before the closed-loop runs. HDF5 cut short by the limit
    crashed the process (SIGSEGV, exit 139, its lock and staging folder left) or failed with
    "file too large"."""
    model, csv = two_link_model
    runs = tmp_path / "runs"
    runs.mkdir()
    run = run_limited(["control", model, csv, "-o", runs / "out", "-q", "--no-report"],
                      tmp_path, limit)
    refused_by_the_limit(run, runs)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE")
@pytest.mark.parametrize("limit", [40_000, 200_000])
def test_plan_meeting_a_file_size_limit_is_one_line(tmp_path, limit):
    """``plan`` writes text, not HDF5: a CSV the limit cuts short is one line, exit 2, and its
    temporary file is removed (no estimate needed: a plan that fits is written)."""
    runs = tmp_path / "runs"
    runs.mkdir()
    run = run_limited(["plan", "two-link", "--setpoints", "5000", "-o", runs / "plan.csv"],
                      tmp_path, limit)
    assert run.returncode == 2, run.stderr[-2000:]
    assert run.stderr == f"gd-analyze: error: {runs / 'plan.csv'}: cannot write: File too " \
                         "large\n"
    assert list(runs.iterdir()) == []


@pytest.mark.parametrize("options", [(), ("--base-frequency", "1e4")])
def test_an_excitation_identification_cannot_use_is_warned_in_one_line(tmp_path, capsys,
                                                                       options):
    """At w_f = 1e4 rad/s the two-link excitation lasts 0.6 ms: its scaled condition number
    (stored in the provenance, the oracle) is far beyond 1 / the estimator's rank tolerance, so
    one warning line says so, exit 0; the default excitation (10 s) stays below it, unwarned."""
    csv = tmp_path / "x.csv"
    code, out, err = _run(capsys, "plan", "two-link", "--excitation", "-o", csv, *options)
    cond = json.loads(csv.with_suffix(".provenance.json").read_text())["excitation"][
        "scaled_condition_number"]
    warned = [line for line in err.splitlines() if "rank tolerance" in line]
    assert code == 0 and (cond > 1 / RANK_TOL) == bool(options)
    assert warned == ([f"gd-analyze: warning: scaled condition number {cond:.4g} above 1e+06 (1 / "
                       "the estimator's rank tolerance): identify may find parameters not "
                       "identifiable"] if options else [])
