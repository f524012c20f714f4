"""The commands: the main job's region (its options, the summary lines, results.h5 and the
model JSON read back, a trajectory outside the region flagged); ``control`` and ``plan`` under a
file size limit; ``identify`` (its files, its JSON, bad input and a file size limit below its
store: one line, exit 2); and ``sweep``'s merged model (of the recursive form where that is the
cheaper, its file evaluated by ``gd-analyze evaluate`` and checked against Pinocchio's rnea,
every figure it prints and stores counted on the model written; the sweep under a file size
limit)."""

import contextlib
import io
import json
import math
import re
import sys
from pathlib import Path

import h5py
import numpy as np
import pinocchio as pin
import pytest
import xarray as xr
from conftest import SHIPPED
from identify_recordings import fourier, irregular_clock, truth_for, write_recording
from robot_files import toml_without_limits
from staging_checks import refused_by_the_limit, run_limited

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.estimation.estimate import RANK_TOL
from gd_analyze.report.identify import identify_context
from gd_analyze.store.model_file import load_model
from gd_analyze.store.stored_identification import read_identification
from gd_analyze.store.sweep_view import sweep_size
from gd_analyze.symbolic.recursive import recursive_program
from gd_analyze.trajectory.planning import default_motion, random_trajectories
from gd_analyze.trajectory.trajectory import read_trajectory, write_trajectory


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
def test_a_payload_sweep_with_a_shape_and_no_mass_sweeps_that_shape(tmp_path, capsys):
    """--payload-sweep with --payload-com and --payload-inertia but no --payload: each swept
    load of that shape moves peak |tau_i| as Pinocchio's rnea of the PUMA with the load's
    body appended to joint 6 says, and the main analysis is the unloaded arm's (the command
    refused the shape without --payload before)."""
    com, inertia = np.array([0.02, -0.01, 0.05]), np.array([0.002, 0.003, 0.001])
    code, _, err = _run(capsys, "puma560", SHIPPED, "-o", tmp_path / "out", "--no-report",
                        "-q", "--payload-sweep", "0:2.5:2.5", "--payload-com",
                        ",".join(map(str, com)), "--payload-inertia",
                        ",".join(map(str, inertia)), "--explicit", "never",
                        "--guarantee", "trajectory")
    assert code == 0, err
    robot = load_robot("puma560")
    traj = read_trajectory(SHIPPED, n_joints=robot.n)
    # the load's centre of mass and inertia from link frame 6 to the body frame of joint 6
    R, t = np.asarray(robot.link_rotation[-1]), np.asarray(robot.link_translation[-1])

    def peaks(mass):
        model = pinocchio_model(robot)
        if mass is not None:
            model.appendBodyToJoint(robot.n, pin.Inertia(mass, R @ com + t,
                                                         R @ np.diag(inertia) @ R.T),
                                    pin.SE3.Identity())
        data = model.createData()
        tau = [pin.rnea(model, data, *s) for s in zip(traj.q, traj.qd, traj.qdd)]
        return np.abs(tau).max(axis=0)

    with xr.open_dataset(tmp_path / "out" / "results.h5", engine="h5netcdf") as ds:
        np.testing.assert_array_equal(ds["payload"].values, [0.0, 2.5])
        for k, mass in enumerate((0.0, 2.5)):
            np.testing.assert_allclose(ds["payload_tau_peak"].values[k], peaks(mass),
                                       rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(ds["tau_peak"].values, peaks(None), rtol=1e-9, atol=1e-12)
        assert float(ds.attrs["payload_mass"]) == 0.0
        np.testing.assert_allclose(ds.attrs["payload_com"], com)


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
    assert "This trajectory leaves the region: joint 1 q\u0307 reaches 2x its limit" in text
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
    from gd_analyze.cli.parsing import analyze_parser

    text = " ".join(analyze_parser().format_help().split())
    assert "by default the largest |tau_i| found over the region" in text
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


def test_an_empty_output_folder_name_is_refused(tmp_path, monkeypatch, capsys):
    """-o "" (a shell variable left empty) wrote to the default reports/ROBOT-STEM, a folder
    the user did not name, where plan's -o "" is refused: one line naming the option."""
    monkeypatch.chdir(tmp_path)
    csv = _fast_csv(tmp_path / "t.csv", speed=0.5)
    code, _, err = _run(capsys, "two-link", csv, "-o", "", "-q", "--no-report")
    assert (code, err) == (2, "gd-analyze: error: --outdir: an empty name is no folder\n")
    assert not (tmp_path / "reports").exists()


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
    # an excitation and a random sweep take no --ignore-limits: their refusals offer none
    capsys.readouterr()
    for args in (["plan", urdf, "--excitation", "-o", str(plan)],
                 ["sweep", urdf, "--random", "1", "-o", str(tmp_path / "s")]):
        assert main(args) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.rstrip().endswith("(<limit velocity> in a URDF)")


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


@pytest.mark.parametrize("step", [1e-101, 1e-63])
def test_control_on_time_steps_whose_fifth_power_underflows_is_one_line(two_link_model, tmp_path,
                                                                         capsys, step):
    """The desired motion's quintics divide by each step's fifth power: 0 in doubles below
    about 1e-62 s. Such a step printed numpy's warnings, then a line without file or row; it
    is now refused where the file is read, naming its row and column, and nothing is written."""
    model, _ = two_link_model
    csv = tmp_path / "tiny.csv"
    csv.write_text("t,q1,q2,qd1,qd2,qdd1,qdd2\n" + "".join(
        f"{k * step!r},0.1,0.2,0.3,0.1,0,0\n" for k in range(5)))
    assert main(["control", str(model), str(csv), "-o", str(tmp_path / "out"), "-q"]) == 2
    err = capsys.readouterr().err
    assert err == (f"gd-analyze: error: {csv}: row 3, column t: time not strictly increasing, "
                   f"by 1e-60 s or more ({step!r} after 0.0)\n")
    assert not (tmp_path / "out").exists()


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


@pytest.fixture(scope="module")
def recordings(tmp_path_factory):
    """Two-link recordings of a true arm (Pinocchio), irregular clocks, no derivatives."""
    folder = tmp_path_factory.mktemp("rec")
    robot = load_robot("two-link")
    truth = truth_for(robot, seed=4)
    out = []
    for name, seed, seconds in (("fit", 2, 20), ("held out", 5, 8)):
        t = irregular_clock(seconds, seed)
        q, qd, qdd = fourier(robot.n, t, seed=seed, harmonics=3, base_hz=0.2)
        out.append(write_recording(folder / f"{name}.csv", t, q, truth.torque(q, qd, qdd)))
    return out


def test_the_summary_says_the_robot_file_holds_consistent_links_where_the_fit_has_none(
        recordings, tmp_path, capsys):
    """The least-squares standard parameters of this true arm (perturbed from the robot file)
    are not physically consistent, those of identified_robot.toml are (oracle: each link's
    pseudo-inertia from Pinocchio's inertias). The summary said only 'link(s) 1, 2 not
    physically consistent', of the robot the user takes away."""
    out = tmp_path / "out"
    code = main(["identify", "two-link", str(recordings[0]), "-o", str(out), "--no-report"])
    said = capsys.readouterr().out
    assert code == 0
    model = pinocchio_model(load_robot(str(out / "identified_robot.toml")))
    for inertia in model.inertias[1:]:
        m, c = inertia.mass, inertia.lever
        about = inertia.inertia + m * (c @ c * np.eye(3) - np.outer(c, c))   # at the joint
        J = np.block([[0.5 * np.trace(about) * np.eye(3) - about, m * c[:, None]],
                      [m * c[None, :], np.array([[m]])]])
        assert np.linalg.eigvalsh(J).min() >= -1e-9 * np.abs(J).max()
    assert "standard parameters: link(s) 1, 2 not physically consistent" in said
    assert "identified_robot.toml holds the physically consistent parameters" in said
    # the report's lead, which gives the least-squares fit's errors, says so too (it did not)
    tree = read_identification(out / "identification.h5")
    lead = identify_context(tree["/"], {k: v for k, v in tree.items() if k != "/"})["lead"]
    assert "identified_robot.toml holds physically consistent parameters instead" in lead


def test_json_and_files(recordings, tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["identify", "two-link", str(recordings[0]), "--validate", str(recordings[1]),
                 "-o", str(out), "--json"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    doc = json.loads(captured.out)
    assert set(doc) >= {"recordings", "condition_number"}
    assert [r["role"] for r in doc["recordings"]] == ["train", "validate"]
    assert [r["file"] for r in doc["recordings"]] == [str(p) for p in recordings]
    tree = read_identification(out / "identification.h5")
    assert set(tree) == {"/", "fit", "held_out"}
    for rec, name in zip(doc["recordings"], ("fit", "held_out")):
        ds = tree[name]
        E = ds.tau_measured.values - ds.tau_predicted.values
        T = ds.tau_measured.values
        assert rec["total_relative_error"] == pytest.approx(np.linalg.norm(E) / np.linalg.norm(T))
        assert rec["relative_error"] == pytest.approx(
            (np.linalg.norm(E, axis=0) / np.linalg.norm(T, axis=0)).tolist())
        assert ds.attrs["role"] == rec["role"]
        # the file's own times, not shifted
        assert ds.t.values[0] >= 0 and ds.t.values[-1] <= 20
    # filtered, differentiated data of a noise-free arm: far better than the robot file
    held = doc["recordings"][1]
    assert held["total_relative_error"] < 0.2 * held["prior_total_relative_error"]
    root = tree["/"]
    assert root.attrs["condition_number"] == pytest.approx(doc["condition_number"])
    assert json.loads(root.attrs["inputs"])[str(recordings[0])]
    assert (out / "identified_robot.toml").is_file()
    assert load_robot(str(out / "identified_robot.toml")).n == 2
    # the report, with the held-out recording's figures, unless --no-report
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "held out" in html or "held_out" in html
    assert (out / "report.pdf").read_bytes().startswith(b"%PDF")
    assert sorted(p.name for p in (out / "figures").iterdir())



def test_a_clipped_torque_is_one_warning_line(recordings, tmp_path, capsys):
    """The fit recording with joint 1's torque clipped at 80 % of its peak: one warning line
    naming the file, the column, the joint, the value and the share; exit 0."""
    data = np.genfromtxt(recordings[0], delimiter=",", names=True)
    limit = 0.8 * np.abs(data["tau1"]).max()
    data["tau1"] = np.clip(data["tau1"], -limit, limit)
    path = tmp_path / "clipped.csv"
    np.savetxt(path, np.column_stack([data[k] for k in data.dtype.names]), delimiter=",",
               header=",".join(data.dtype.names), comments="", fmt="%.17g")
    code = main(["identify", "two-link", str(path), "-o", str(tmp_path / "out"), "--no-report"])
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if "clipped" in line]
    share = np.mean(np.abs(data["tau1"]) == limit)
    assert code == 0 and lines == [
        f"gd-analyze: warning: {path}: column tau1: joint 1's torque is clipped at "
        f"{np.sign(data['tau1'][np.abs(data['tau1']) == limit][0]) * limit:.6g} N m (flat at "
        f"its extreme, a drive's limit or a sensor's range?) on {share:.1%} of the samples: "
        f"left out of the fit"], err

def test_no_report(recordings, tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["identify", "two-link", str(recordings[0]), "-o", str(out), "--no-report",
                 "-q"])
    assert code == 0, capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "identification.h5", "identified_robot.toml"]


def _bad(tmp_path, text, name="bad.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


GOOD_ROWS = "".join(f"{k * 0.01},{0.1 * k},{0.2 * k},{k},{k}\n" for k in range(30))

BAD = [
    ("a word in a cell", "t,q1,q2,tau1,tau2\n" + GOOD_ROWS + "0.5,1,x,2,3\n", "row 32, column q2"),
    ("nan", "t,q1,q2,tau1,tau2\n0,nan,0,0,0\n" + GOOD_ROWS, "row 2, column q1"),
    ("no torque", "t,q1,q2\n" + "".join(f"{k * 0.01},{k},{k}\n" for k in range(30)),
     "row 1, column tau1"),
    ("unknown column", "t,q1,q2,tau1,tau2,foo\n", "row 1, column foo"),
    ("ragged", "t,q1,q2,tau1,tau2\n" + GOOD_ROWS + "0.5,1,2\n", "row 32"),
    ("too few", "t,q1,q2,tau1,tau2\n0,0,0,0,0\n0.1,0,0,0,0\n", "at least 10"),
    ("three joints", "t,q1,q2,q3,tau1,tau2,tau3\n0,0,0,0,0,0,0\n", "row 1, column q"),
]


@pytest.mark.parametrize("what, text, where", BAD, ids=[b[0] for b in BAD])
def test_bad_recordings_exit_2_naming_file_row_and_column(tmp_path, capsys, what, text, where):
    path = _bad(tmp_path, text)
    code = main(["identify", "two-link", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert str(path) in err and where in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("args, where", [
    (["--current"], "--current"),
    (["--drive-gains", "1,2"], "--drive-gains"),
    (["--drives", "stiction"], "stiction"),
    (["--cutoff", "-3"], "cutoff"),
    (["--decimate", "0"], "--decimate"),
])
def test_bad_options_exit_2(recordings, tmp_path, capsys, args, where):
    code = main(["identify", "two-link", str(recordings[0]), "-o", str(tmp_path / "o"), *args])
    err = capsys.readouterr().err
    assert code == 2 and where in err and len(err.strip().splitlines()) == 1


def test_currents_times_gains_are_torques(recordings, tmp_path, capsys):
    """A recording of currents i = tau / K with --current --drive-gains K gives the same fit."""
    text = recordings[0].read_text().splitlines()
    header = text[0].split(",")
    K = np.array([2.0, 0.5])
    rows = np.array([[float(v) for v in line.split(",")] for line in text[1:]])
    rows[:, 3:5] /= K
    cur = tmp_path / "current.csv"
    cur.write_text(",".join(header[:3] + ["i1", "i2"]) + "\n"
                   + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n")
    outs = []
    for path, extra in ((recordings[0], []), (cur, ["--current", "--drive-gains", "2,0.5"])):
        code = main(["identify", "two-link", str(path), "-o", str(tmp_path / path.stem),
                     "--json", *extra])
        assert code == 0
        outs.append(json.loads(capsys.readouterr().out)["recordings"][0])
    assert outs[1]["total_relative_error"] == pytest.approx(outs[0]["total_relative_error"],
                                                            rel=1e-6)


@pytest.mark.slow
def test_urdf_input_writes_a_urdf_that_reproduces_the_identified_model(tmp_path, capsys):
    import pinocchio as pin
    from identify_recordings import builtin_urdf

    robot = load_robot("panda")
    truth = truth_for(robot, urdf=builtin_urdf("panda"))
    files = []
    for name, seed, seconds in (("fit", 2, 20), ("held", 5, 5)):
        t = irregular_clock(seconds, seed)
        q, qd, qdd = fourier(robot.n, t, seed=seed)
        files.append(write_recording(tmp_path / f"{name}.csv", t, q, truth.torque(q, qd, qdd),
                                     qd, qdd))
    out = tmp_path / "out"
    code = main(["identify", "panda", str(files[0]), "--validate", str(files[1]), "-o", str(out),
                 "--cutoff", "none", "-q"])
    assert code == 0, capsys.readouterr().err
    tree = read_identification(out / "identification.h5")
    held = tree["held"]
    model = pin.buildModelFromUrdf(str(out / "identified_robot.urdf"))
    data = model.createData()
    drives = load_robot(str(out / "identified_robot.toml"))
    q, qd, qdd = (held[k].values for k in ("q", "qd", "qdd"))
    tau = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    tau += drives.armature * qdd + drives.viscous * qd + drives.coulomb * np.sign(qd)
    # the offsets are in the robot file, as identification.h5 has them
    assert np.array_equal(drives.torque_offset, tree["/"]["offset"].values)
    assert np.abs(drives.torque_offset).max() > 0
    tau += drives.torque_offset
    pred = held.tau_predicted.values
    assert np.abs(tau - pred).max() <= 1e-9 * np.abs(pred).max()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE")
@pytest.mark.parametrize("limit", [40_000, 200_000])
def test_a_file_size_limit_below_identification_h5_is_refused(recordings, tmp_path, limit):
    """Under ``ulimit -f`` below identification.h5's estimate and the margin: one line naming
    the limit, exit 2, nothing left, before the identification. HDF5 cut short by the limit
    failed with "file too large" or crashed the process (SIGSEGV, exit 139, its lock and
    staging folder left)."""
    runs = tmp_path / "runs"
    runs.mkdir()
    run = run_limited(["identify", "two-link", recordings[0], "--validate", recordings[1],
                       "-o", runs / "out", "-q", "--no-report"], tmp_path, limit)
    refused_by_the_limit(run, runs)


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """A PUMA 560 sweep of 3 random trajectories by the command, merged on the trajectories,
    and what it printed."""
    out = tmp_path_factory.mktemp("sweep")
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["sweep", "puma560", "--random", "3", "--seed", "4", "--workers", "1",
                     "--held-out", "0", "--no-report", "-o", str(out),
                     "--guarantee", "trajectory"]) == 0
    return out, buf.getvalue()


def test_provenance_says_what_cluster_ran(swept):
    """A plain command-line sweep said "client given by the caller". It says what
    ran: here the local cluster the command started, with its one worker (--workers 1)."""
    import xarray as xr

    from gd_analyze.report.sweep import sweep_context

    out, printed = swept
    with xr.open_dataset(out / "sweep.h5") as ds:
        ds = ds.load()
    said = "a LocalCluster of 1 worker process started by gd-analyze on this machine"
    assert ds.attrs["cluster"] == said and int(ds.attrs["n_workers"]) == 1
    rows = dict(sweep_context(ds, None)["settings"]["rows"])
    assert rows["computed on"].startswith(f"dask, {said} (1 worker joined; scheduler at "), rows
    assert "caller" not in rows["computed on"]


def test_the_printed_line_counts_one_worker_in_the_singular(swept):
    """--workers 1 printed "on 1 dask workers": the line counts the worker that ran."""
    _, printed = swept
    line = next(x for x in printed.splitlines() if " trajectories in " in x)
    assert re.search(r"^puma560: 3 trajectories in [0-9.]+ s on 1 dask worker \(", line), line


def test_the_merged_model_is_recursive_and_said_so(swept):
    out, printed = swept
    model = load_model(out / "merged_model.json")
    assert model.form == "recursive"
    exact = recursive_program(model.robot).cost()
    mine = model.program().cost()                              # counted on the file's model
    assert mine["multiplications"] + mine["additions"] <= (exact["multiplications"]
                                                          + exact["additions"])
    line = next(x for x in printed.splitlines() if x.startswith("merged model (budget"))
    assert "recursive form" in line
    assert f"{mine['multiplications'] + mine['additions']:,} operations" in line
    assert f"exact recursive: {exact['multiplications'] + exact['additions']:,}" in line
    with xr.open_dataset(out / "sweep.h5") as ds:
        assert ds.attrs["merged_form"] == "recursive" and "pair_peak" not in ds.variables
        bound = ds["merged_bound"].values
        scale = ds["merged_scale"].values
        err = ds["merged_tau_error_peak"].values
    assert np.all(err <= bound + 1e-9 * scale.max()) and np.all(bound <= 0.01 * scale)
    for name in ("merged_model.c", "merged_model.py"):     # the emitted files say it too
        text = (out / name).read_text()
        assert (f"exact recursive model: {exact['multiplications']} multiplications, "
                f"{exact['additions']} additions") in text
        said = re.search(r"bound on each swept trajectory: .*?, b = ([0-9e., +-]+)\n", text)
        b = np.array([float(v) for v in said.group(1).split(",")])
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.where(bound > 0, bound / scale, 0.0).max(axis=0)
        assert np.all(b >= rel) and np.all(b <= rel * 1.01)          # 3 digits, rounded up
        assert np.all(b <= 0.01 * (1 + 1e-9))


def test_evaluate_reads_the_merged_model_and_pinocchio_agrees(swept, tmp_path, capsys):
    out, _ = swept
    model = load_model(out / "merged_model.json")
    robot = model.robot
    tr = random_trajectories(robot, 1, seed=99)[0]            # not swept: no guarantee
    csv = tmp_path / "t.csv"
    write_trajectory(tr, csv)
    capsys.readouterr()
    assert main(["evaluate", str(out / "merged_model.json"), str(csv), "--json"]) == 0
    said = json.loads(capsys.readouterr().out)
    pm = pinocchio_model(robot)
    data = pm.createData()
    ref = np.array([pin.rnea(pm, data, *s) for s in zip(tr.q, tr.qd, tr.qdd)])
    err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - ref).max(axis=0)
    got = np.array(said["peak_abs_error"], float)
    np.testing.assert_allclose(got, err, rtol=1e-6, atol=1e-9 * np.abs(ref).max())


def test_the_main_job_s_report_runs_without_the_kept_certifications(tmp_path, capsys,
                                                                     monkeypatch):
    """The command line's main job builds one model, so what its process keeps for a later
    model of the arm (the region's certification with its samples' channel values: about
    300 MB for 12 joints) is released before its report, on a trajectory held in memory too
    (``run_analysis`` called as a library keeps them then). Oracle: no PairBounds alive in
    the process when the report starts."""
    import gc

    from gd_analyze.certify.certify import PairBounds
    from gd_analyze.cli import commands

    alive = []

    def report(results, folder, **options):
        gc.collect()
        alive.append(sum(isinstance(o, PairBounds) for o in gc.get_objects()))
        return []
    monkeypatch.setattr(commands, "write_report", report)
    code, out, err = _run(capsys, "puma560", SHIPPED, "-o", tmp_path / "out", "-q")
    assert code == 0, err
    assert alive == [0]


def _sweep(args, capsys):
    """Run the command; (exit status, stdout and stderr together)."""
    capsys.readouterr()
    code = main(["sweep", *map(str, args)])
    out = capsys.readouterr()
    return code, out.out + out.err


def test_an_element_round_off_on_every_trajectory_prints_no_share(tmp_path, capsys):
    """The two-link arm with massless rods keeps only their inertias about z: D is constant
    (closed form: D = [[I1 + I2, I2], [I2, I2]]), so h is identically 0 and has no share. The
    printed table said "nan" for its min, median and max share; the report says "\u2261 0"."""
    from importlib import resources

    text = resources.files("gd_analyze").joinpath("data", "two-link.toml").read_text()
    assert text.count("mass = 1.0") == 2
    (tmp_path / "massless.toml").write_text(text.replace("mass = 1.0", "mass = 0.0"))
    code, printed = _sweep([tmp_path / "massless.toml", "--random", "2", "--held-out", "0",
                            "--no-report", "-o", tmp_path / "out"], capsys)
    assert code == 0, printed
    rows = {line.split()[0]: line.split() for line in printed.splitlines()
            if line.startswith(("D1", "D2", "h"))}
    for h in ("h1", "h2"):
        assert rows[h][5:] == ["\u2261", "0"] * 3 + [rows[h][-1]], printed
    assert "nan" not in printed and rows["D11"][5:8] == ["0.000"] * 3     # rotational only


@pytest.mark.slow
def test_guarantee_region_the_files_say_it_and_it_holds(tmp_path, capsys):
    """--guarantee region: the merged model file, sweep.h5, the emitted code, the printed
    lines and the report state the region guarantee in the model's one sentence; its error on
    each swept trajectory (inside the region) is within its proved bound against rnea."""
    import xarray as xr
    from html_checks import html_text

    out = tmp_path / "region"
    code, printed = _sweep(["puma560", "--random", "3", "--seed", "4",
                            "--held-out", "2", "--guarantee", "region", "-o", out], capsys)
    assert code == 0, printed
    spec = json.loads((out / "merged_model.json").read_text())
    g = spec["guarantee"]
    assert g["kind"] == "region" and "at every state of the region (proved" in g["statement"]
    assert f"guarantee: {g['statement']}\n" in printed
    line = next(x for x in printed.splitlines() if x.startswith("merged model (budget"))
    assert "of s_i over the joint-limit region (guaranteed <= 0.01)" in line
    assert "2 of them inside the region" in line and "not covered" not in printed
    for name in ("merged_model.c", "merged_model.py"):
        text = (out / name).read_text()
        assert f"guarantee: {g['statement']}" in text
        assert "bound on each swept trajectory" not in text
    with xr.open_dataset(out / "sweep.h5") as ds:
        assert ds.attrs["merged_guarantee_kind"] == "region"
        assert ds.attrs["merged_guarantee_statement"] == g["statement"]
        assert ds["merged_covered"].values.tolist() == [1, 1, 1]
    text = html_text((out / "sweep_report.html").read_text(encoding="utf-8"))
    assert "on every swept trajectory" not in text
    assert "at every state of the region (proved" in text
    model = load_model(out / "merged_model.json")
    bound, scale = np.array(g["bound"]), np.array(g["scale"])
    assert np.all(bound <= 0.01 * scale * (1 + 1e-12))
    pm = pinocchio_model(model.robot)
    data = pm.createData()
    for tr in random_trajectories(model.robot, 3, seed=4):      # the swept ones, planned again
        ref = np.array([pin.rnea(pm, data, *s) for s in zip(tr.q, tr.qd, tr.qdd)])
        err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - ref).max(axis=0)
        assert np.all(err <= bound + 1e-9 * scale)


@pytest.mark.slow
def test_default_guarantee_region_with_limits_trajectory_without(tmp_path, capsys):
    """The default (auto): region on the PUMA 560 (it gives every limit); on an arm without
    limits the trajectory guarantee, and the missing limit said in one line, once."""
    from gd_analyze import load_robot
    from gd_analyze.certify.region import missing_limits

    code, printed = _sweep(["puma560", "--random", "2", "--held-out", "0",
                            "--no-report", "-o", tmp_path / "puma"], capsys)
    assert code == 0, printed
    spec = json.loads((tmp_path / "puma" / "merged_model.json").read_text())
    assert spec["guarantee"]["kind"] == "region"
    free = toml_without_limits(tmp_path)
    assert missing_limits(load_robot(str(free))) == "joint 1 has no velocity limit"
    csvs = []
    for k, tr in enumerate(random_trajectories(load_robot("two-link"), 2, seed=3)):
        csvs.append(tmp_path / f"t{k}.csv")
        write_trajectory(tr, csvs[-1])
    for extra in ([], ["--guarantee", "region"]):    # no region to prove over: trajectory
        out = tmp_path / f"free{len(extra)}"
        code, printed = _sweep([free, *csvs, "--held-out", "0",
                                "--no-report", "-o", out, *extra], capsys)
        assert code == 0, printed
        spec = json.loads((out / "merged_model.json").read_text())
        assert spec["guarantee"]["kind"] == "trajectory"
        assert spec["guarantee"]["region_missing"] == "joint 1 has no velocity limit"
        assert printed.count("no velocity limit") == 1, printed
        line = next(x for x in printed.splitlines() if "no velocity limit" in x)
        assert line == f"guarantee: {spec['guarantee']['statement']}"
        assert "on the 2 swept trajectories only" in line


def test_a_sweep_of_an_arm_without_limits_skips_the_held_out_plans_in_one_line(tmp_path,
                                                                             capsys):
    """The default --held-out plans random trajectories, which an arm without velocity limits
    cannot have: the sweep of its files still writes the trajectory merge (exit 0), and one
    warning line says why no held-out trajectory was measured."""
    free = toml_without_limits(tmp_path)
    csvs = []
    for k, tr in enumerate(random_trajectories(load_robot("two-link"), 2, seed=3)):
        csvs.append(tmp_path / f"t{k}.csv")
        write_trajectory(tr, csvs[-1])
    code, printed = _sweep([free, *csvs, "--no-report", "-o", tmp_path / "out"], capsys)
    assert code == 0, printed
    spec = json.loads((tmp_path / "out" / "merged_model.json").read_text())
    assert spec["guarantee"]["kind"] == "trajectory"
    said = [x for x in printed.splitlines() if "held-out" in x]
    assert len(said) == 1 and "no held-out trajectories" in said[0], printed
    assert "neither an acceleration nor a finite velocity limit" in said[0]


def test_a_swept_trajectory_outside_the_region_is_reported(tmp_path, capsys):
    """A plan run twice as fast (qd x 2, qdd x 4: beyond the PUMA's limits) is swept with two
    plans: the command names it as not covered by the region guarantee, the others not."""
    import dataclasses

    from gd_analyze import load_robot

    robot = load_robot("puma560")
    plans = random_trajectories(robot, 2, seed=5)
    fast = dataclasses.replace(plans[0], t=plans[0].t / 2, qd=2 * plans[0].qd,
                               qdd=4 * plans[0].qdd)
    assert (np.abs(fast.qd) > robot.qd_max).any()                # the oracle: outside
    csvs = []
    for name, tr in (("a", plans[0]), ("b", plans[1]), ("fast", fast)):
        csvs.append(tmp_path / f"{name}.csv")
        write_trajectory(tr, csvs[-1])
    code, printed = _sweep(["puma560", *csvs, "--held-out", "0",
                            "--no-report", "-o", tmp_path / "out"], capsys)
    assert code == 0, printed
    line = next(x for x in printed.splitlines() if x.startswith("not covered by the region"))
    assert "(1 swept trajectory outside the region)" in line
    assert "fast.csv: outside the model's region" in line
    assert "a.csv" not in line and "b.csv" not in line
    merged = next(x for x in printed.splitlines() if x.startswith("merged model (budget"))
    assert "on the 2 of 3 swept trajectories inside the region" in merged


def test_the_merged_model_emits_every_file_with_its_own_prefix(swept):
    """merged_model.h, .c, .py and _casadi.py, prefix puma560_merged_; the
    numpy functions keep D_s qdd + h_s + c_s = tau_s = Y_s beta_s; D_s checked on the sweep."""
    from scales import identity_errors

    from gd_analyze.symbolic.emit_model import artefact_names

    out, _ = swept
    assert set(artefact_names("merged_model")) <= {p.name for p in out.iterdir()}
    assert "void puma560_merged_tau(const double *q" in (out / "merged_model.h").read_text()
    ns = {}
    exec((out / "merged_model.py").read_text(), ns)
    model = load_model(out / "merged_model.json")
    q, qd, qdd = (np.random.default_rng(2).uniform(-2, 2, (3, 20, 6)))
    assert max(identity_errors(ns, q, qd, qdd)) < 1e-12
    tau = ns["tau"](q, qd, qdd)
    assert np.abs(model.torque(q, qd, qdd) - tau).max() <= 1e-12 * np.abs(tau).max()
    check = json.loads((out / "merged_model.json").read_text())["inertia_check"]
    assert check["proved"] and check["where"] == "trajectory" and check["lower_bound"] > 0


@pytest.mark.slow
def test_users_region_is_printed_and_stored_by_the_sweep(tmp_path, capsys):
    """--qd-max and --qdd-max: the sweep proves the merged model over the user's
    region, prints it one line per limit kind before the guarantee line, and sweep.h5 and
    merged_model.json store it; the robot's random trajectories that leave it are not
    covered."""
    out = tmp_path / "user"
    code, printed = _sweep(["two-link", "--random", "3", "--seed", "4",
                            "--held-out", "0", "--no-report", "-o", out, "--qd-max", "30",
                            "--qdd-max", "60"], capsys)
    assert code == 0, printed
    lines = printed.splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("guarantee: "))
    assert lines[k - 3:k] == ["region: q [deg] 1 any angle (full turn), 2 any angle (full turn)",
                              "qd max [deg/s] 1 30, 2 30", "qdd max [deg/s^2] 1 60, 2 60"]
    with xr.open_dataset(out / "sweep.h5") as ds:
        np.testing.assert_allclose(ds["region_qd_max"].values, np.radians([30, 30]))
        np.testing.assert_allclose(ds["region_qdd_max"].values, np.radians([60, 60]))
        assert ds.attrs["merged_guarantee_kind"] == "region"
    spec = json.loads((out / "merged_model.json").read_text())
    np.testing.assert_allclose(spec["guarantee"]["region"]["qd_max"], np.radians([30, 30]))
    np.testing.assert_allclose(spec["guarantee"]["qd_max"], np.radians([30, 30]))


@pytest.mark.slow
def test_a_small_sweep_without_workers_runs_in_the_command_process(tmp_path, capsys,
                                                                    monkeypatch):
    """Without --workers or --scheduler, a sweep of at most IN_PROCESS_SETPOINTS_MAX set points
    is ranked, and its merged model built and checked, in the command's own process, and the
    provenance and the printed line say so; above that limit the command starts a
    LocalCluster. Both give the same files: the ranking and the model to the last bit, the
    measured errors up to round-off (their set points are grouped otherwise)."""
    from gd_analyze.jobs import sweep as sweep_job
    from gd_analyze.report.sweep import sweep_context

    args = ["puma560", "--random", "3", "--seed", "4", "--held-out", "2", "--no-report"]
    code, printed = _sweep([*args, "-o", tmp_path / "here"], capsys)
    assert code == 0, printed
    assert "puma560: 3 trajectories in " in printed
    assert " s in this process (no dask cluster)" in printed and "dask workers" not in printed
    monkeypatch.setattr(sweep_job, "IN_PROCESS_SETPOINTS_MAX", 3 * 31 - 1)
    code, printed = _sweep([*args, "-o", tmp_path / "cluster"], capsys)
    assert code == 0, printed
    assert re.search(r"in [0-9.]+ s on \d+ dask workers \(tcp://", printed), printed
    with xr.open_dataset(tmp_path / "here" / "sweep.h5") as here, \
            xr.open_dataset(tmp_path / "cluster" / "sweep.h5") as there:
        here, there = here.load(), there.load()
    assert here.attrs["cluster"] == sweep_job.IN_PROCESS and int(here.attrs["n_workers"]) == 0
    assert there.attrs["cluster"].startswith("a LocalCluster of ")
    assert int(there.attrs["n_workers"]) >= 1 and int(there.attrs["n_tasks"]) >= 2
    rows = dict(sweep_context(here, None)["settings"]["rows"])
    assert rows["computed on"].startswith(f"{sweep_job.IN_PROCESS} (the 3 trajectories in 1 "
                                          "batch: ranked, and the merged model built and "
                                          "checked on every trajectory, in the process"), rows
    assert set(here.variables) == set(there.variables)
    for name in here.variables:
        a, b = here[name].values, there[name].values
        if a.dtype.kind == "f" and "error" in name:
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12, err_msg=name)
        else:
            np.testing.assert_array_equal(a, b, err_msg=name)
    for name in ("merged_model.json", "merged_model.c", "merged_model.py"):
        a, b = ((tmp_path / side / name).read_text() for side in ("here", "cluster"))
        if name.endswith(".json"):
            a, b = json.loads(a), json.loads(b)
            for spec in (a, b):         # measured on the trajectories: up to round-off
                spec.pop("validation", None)
                spec.get("provenance", {}).pop("command", None)
        assert a == b, name


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE")
@pytest.mark.parametrize("limit", [40_000, 200_000])
def test_a_file_size_limit_below_sweep_h5_is_refused_before_the_sweep(tmp_path, limit):
    """Under ``ulimit -f`` below sweep.h5's estimate and the margin: one line naming the limit,
    exit 2, nothing left, before the sweep. At 40 kB the write failed ("file too large"), or,
    with numba's cache not yet written, the cache's write did (exit 4, an internal error); at
    200 kB this sweep's 0.1 MB sweep.h5 fitted, where a larger one meets the limit inside
    HDF5."""
    runs = tmp_path / "runs"
    runs.mkdir()
    run = run_limited(["sweep", "two-link", "--random", "2", "-o", runs / "out", "-q",
                       "--no-report"], tmp_path, limit)
    refused_by_the_limit(run, runs)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE")
def test_a_file_size_limit_above_the_estimate_lets_the_sweep_run(tmp_path):
    """64 MiB holds the estimate and the margin: the sweep runs, and the sweep.h5 it wrote is
    within the estimate."""
    run = run_limited(["sweep", "two-link", "--random", "2", "-o", tmp_path / "out", "-q",
                       "--no-report"], tmp_path, 64 << 20)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stderr == ""
    assert (tmp_path / "out" / "sweep.h5").stat().st_size <= sweep_size(2, 2)


def test_identify_names_its_folder_after_the_first_of_files_joined_on_one_clock(tmp_path,
                                                                              monkeypatch):
    """Without -o, identify's folder is named after the recording's first file, as its report
    names the recording: ``P.csv+V.csv+E.csv`` (one recording from files on one clock) gave
    the last file's name, since a path splits at the slashes after the "+"."""
    robot = load_robot("puma560")
    t = irregular_clock(6, seed=1)
    q, qd, qdd = fourier(robot.n, t, seed=1)
    tau = truth_for(robot).torque(q, qd, qdd)
    files = []
    for field, values in (("position", q), ("velocity", qd), ("effort", tau)):
        path = tmp_path / "rec" / f"arm_{field}.csv"
        path.parent.mkdir(exist_ok=True)
        path.write_text("t," + ",".join(f"{j}_{field}" for j in robot.joint_names()) + "\n"
                        + "".join(",".join(repr(float(v)) for v in (s, *row)) + "\n"
                                  for s, row in zip(t, values)))
        files.append(str(path))
    monkeypatch.chdir(tmp_path)
    assert main(["identify", "puma560", "+".join(files), "--no-report"]) == 0
    assert [p.name for p in (tmp_path / "reports").iterdir()] == ["puma560-arm_position-identify"]


def test_identify_names_its_folder_as_the_recording_joined_from_one_folders_files(tmp_path,
                                                                                  monkeypatch):
    """Without -o, a recording joined from files of one folder whose names share nothing
    (``log/q.csv+log/tau.csv``) names identify's folder as it names the recording in the
    results: after the folder (``log``), not its first file (``q``)."""
    robot = load_robot("two-link")
    t = irregular_clock(6, seed=2)
    q, qd, qdd = fourier(robot.n, t, seed=2)
    tau = truth_for(robot).torque(q, qd, qdd)
    (tmp_path / "log").mkdir()
    for kind, values in (("q", q), ("tau", tau)):
        np.savetxt(tmp_path / "log" / f"{kind}.csv", np.column_stack([t, values]),
                   delimiter=",", header=f"t,{kind}1,{kind}2", comments="")
    monkeypatch.chdir(tmp_path)
    assert main(["identify", "two-link", "log/q.csv+log/tau.csv", "--no-report"]) == 0
    assert [p.name for p in (tmp_path / "reports").iterdir()] == ["two-link-log-identify"]
    with h5py.File(tmp_path / "reports" / "two-link-log-identify" / "identification.h5") as f:
        assert "log" in f


def test_a_sweep_at_tolerance_zero_is_within_its_guarantee_up_to_round_off(capsys, tmp_path):
    """EPS = 0 keeps the exact model: its error against Pinocchio's rnea is round-off, within
    the guarantee's round-off allowance (64 eps of the largest s_i), so the sweep says the
    guarantee holds; an error raised above the bound in the stored file is said to breach it."""
    from gd_analyze.simplify.guarantee import ROUND_OFF_EPS
    from gd_analyze.store.sweep_view import merged_guarantee

    out = tmp_path / "sweep"
    code, printed, err = _run(capsys, "sweep", "two-link", "--random", "2", "--tolerance", "0",
                              "--held-out", "0", "-o", out, "--no-report")
    assert code == 0, err
    line = next(x for x in printed.splitlines() if x.startswith("merged model (budget"))
    model = load_model(out / "merged_model.json")
    robot = model.robot
    worst = 0.0
    with xr.open_dataset(out / "sweep.h5", engine="h5netcdf") as ds:
        ds = ds.load()
    scale = ds["merged_scale"].values
    pm = pinocchio_model(robot)
    data = pm.createData()
    rng = np.random.default_rng(3)
    for _ in range(200):            # the exact model equals Pinocchio up to round-off
        q, qd, qdd = (rng.uniform(-1, 1, robot.n) for _ in range(3))
        ref = pin.rnea(pm, data, q, qd, qdd)
        err = np.abs(np.asarray(model.torque(q[None], qd[None], qdd[None]))[0] - ref)
        worst = max(worst, float(err.max()))
    assert worst <= ROUND_OFF_EPS * np.finfo(float).eps * scale.max()
    assert "(guaranteed <= 0)" in line and "ABOVE" not in line, line
    said = merged_guarantee(ds)
    assert said["within"] and said["worst"] > 0       # round-off, not an exact zero
    ds["merged_tau_error_peak"][0, 0] = 1e-6 * scale.max()     # far above round-off
    assert not merged_guarantee(ds)["within"]


def test_the_main_job_on_a_continuous_joint_s_wrapped_log_analyses_the_motion(tmp_path, capsys):
    """The main job on a continuous joint's positions wrapped at +-pi (positions only, a robot
    file without limits): results.h5's D qdd + h + c is Pinocchio's rnea on the motion and its
    own not-a-knot spline's qd and qdd (the oracle), not the spline's spikes at each wrap, and
    stderr has one warning line naming the file, the row and the column."""
    free = toml_without_limits(tmp_path)
    t = np.linspace(0.0, 2.0, 61)
    q = np.column_stack([np.pi + np.sin(np.pi * t), 0.3 * t])
    wrapped = q.copy()
    wrapped[:, 0] = (q[:, 0] + np.pi) % (2 * np.pi) - np.pi
    path = tmp_path / "wrapped.csv"
    path.write_text("t,q1,q2\n" + "".join(f"{s!r},{a!r},{b!r}\n" for s, (a, b) in
                                          zip(t.tolist(), wrapped.tolist())))
    code, _, err = _run(capsys, free, path, "-o", tmp_path / "out", "--no-report",
                        "--explicit", "never")
    assert code == 0, err
    said = [x for x in err.splitlines() if "wrapped at +-pi" in x]
    k = int(np.flatnonzero(np.abs(np.diff(wrapped[:, 0])) > np.pi)[0])
    assert len(said) == 1 and said[0].startswith(
        f"gd-analyze: warning: {path}: row {k + 3}, column q1: joint 1's positions step by "), err
    _check_rnea_on_spline(load_robot(str(free)), t, q, tmp_path / "out" / "results.h5")


def test_the_main_job_reads_a_recording_whose_columns_name_the_joints(tmp_path, capsys):
    """A ROS-style recording ("- joint1_position", "- joint1_effort", ..., shuffled), as
    identify reads it: the main job analyses its set points (it was refused: "the header must
    start with 't'"), its torques ignored with a note; results.h5's D qdd + h + c is
    Pinocchio's rnea on the positions and their own not-a-knot spline's qd and qdd."""
    t = np.linspace(0.0, 2.0, 41)
    q = np.column_stack([np.sin(t), 0.5 * np.cos(2 * t)])
    path = tmp_path / "joint_states.csv"
    path.write_text("- joint2_effort,t,- joint1_position,- joint2_position,- joint1_effort\n"
                    + "".join(f"1.0,{s!r},{a!r},{b!r},2.0\n" for s, (a, b) in
                              zip(t.tolist(), q.tolist())))
    code, _, err = _run(capsys, "two-link", path, "-o", tmp_path / "out", "--no-report",
                        "--explicit", "never")
    assert code == 0, err
    assert "its torques - joint1_effort..- joint2_effort are ignored" in err, err
    _check_rnea_on_spline(load_robot("two-link"), t, q, tmp_path / "out" / "results.h5")


def _check_rnea_on_spline(robot, t, q, results):
    """results.h5's D qdd + h + c against Pinocchio's rnea on q and its own not-a-knot cubic
    spline's qd and qdd (scipy), to 1e-9 of the largest torque."""
    from scipy.interpolate import CubicSpline

    spline = CubicSpline(t, q, axis=0, bc_type="not-a-knot")
    model = pinocchio_model(robot)
    data = model.createData()
    tau = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, spline(t, 1),
                                                                        spline(t, 2))])
    with xr.open_dataset(results, engine="h5netcdf") as ds:
        got = np.einsum("kij,kj->ki", ds.D.values, ds.qdd.values) + ds.h.values + ds.c.values
    np.testing.assert_allclose(got, tau, rtol=0, atol=1e-9 * np.abs(tau).max())
