"""``gd-analyze identify``: its files, its JSON, bad input and a file size limit below its
store (one line, exit 2)."""

import json
import sys

import numpy as np
import pytest
from identify_recordings import fourier, irregular_clock, truth_for, write_recording
from staging_checks import refused_by_the_limit, run_limited

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.store.stored_identification import read_identification


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
