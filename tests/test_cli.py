import hashlib
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from conftest import ROOT, SHIPPED, golden_run

import gd_analyze
from gd_analyze.cli import main, parse_range
from gd_analyze.errors import InputError

SRC = pathlib.Path(gd_analyze.__file__).resolve().parent
GOOD_HEADER = "t," + ",".join(f"q{i}" for i in range(1, 7))


def _run(args, capsys):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def test_main_job_without_report():
    # the run of golden case puma560 (gd-analyze puma560 <shipped> --no-report), read only
    (folder, *_), out = golden_run("puma560")
    out_dir = folder / "puma560"
    assert sorted(p.name for p in out_dir.iterdir()) == [".gd-analyze-manifest-analyze.json",
                                                         "results.h5", "simplified_model.c",
                                                         "simplified_model.h",
                                                         "simplified_model.json",
                                                         "simplified_model.py",
                                                         "simplified_model_casadi.py"]
    assert "D11" in out and "h6" in out and "torque error" in out
    with xr.open_dataset(out_dir / "results.h5", engine="h5netcdf") as ds:
        assert ds.attrs["dominance_threshold"] == 0.9
        # the printed table is the stored ranking
        for lab, cls in zip(ds.element.values, ds.dominance.values):
            assert any(line.split()[:1] == [lab] and cls in line for line in out.splitlines())


def test_thresholds_reach_the_outputs(tmp_path, capsys):
    out_dir = tmp_path / "o"
    code, _, err = _run(["puma560", SHIPPED, "-o", out_dir, "--no-report", "--dominance",
                         "0.8", "--negligible", "0.001", "--quiet"], capsys)
    assert code == 0, err
    spec = json.loads((out_dir / "simplified_model.json").read_text())
    assert spec["dominance_threshold"] == 0.8 and spec["negligible_threshold"] == 0.001


def test_default_outdir(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = _run(["two-link", _two_link_csv(tmp_path), "--no-report", "-q"], capsys)
    assert code == 0, err
    assert (tmp_path / "reports" / "two-link-arm" / "results.h5").is_file()


def _two_link_csv(tmp_path):
    t = np.linspace(0, 1, 11)
    path = tmp_path / "arm.csv"
    rows = ["t,q1,q2"] + [f"{v},{np.sin(v)},{np.cos(v)}" for v in t]
    path.write_text("\n".join(rows) + "\n")
    return path


BAD = {
    "empty": "",
    "no_header": "0,1,2,3,4,5,6\n1,1,2,3,4,5,6\n",
    "missing_column": "t,q1,q2,q3,q4,q5,qd1\n0,1,2,3,4,5,6\n1,1,2,3,4,5,6\n",
    "extra_column": GOOD_HEADER + ",q7x\n0,1,2,3,4,5,6,7\n1,1,2,3,4,5,6,7\n",
    "ragged": GOOD_HEADER + "\n0,1,2,3,4,5,6\n1,1,2,3,4,5\n",
    "not_a_number": GOOD_HEADER + "\n0,1,2,3,4,5,6\n1,1,2,x,4,5,6\n",
    "nan": GOOD_HEADER + "\n0,1,2,3,4,5,6\n1,1,2,NaN,4,5,6\n",
    "inf": GOOD_HEADER + "\n0,1,2,3,4,5,6\n1,1,2,3,-inf,5,6\n",
    "time_not_increasing": GOOD_HEADER + "\n0,1,2,3,4,5,6\n0,1,2,3,4,5,6\n",
    "one_setpoint": GOOD_HEADER + "\n0,1,2,3,4,5,6\n",
    "joint_count": "t,q1,q2\n0,1,2\n1,2,3\n",
}
WHERE = {"ragged": "row 3", "not_a_number": "row 3, column q3", "nan": "row 3, column q3",
         "inf": "row 3, column q4", "time_not_increasing": "row 3, column t",
         "missing_column": "row 1", "extra_column": "row 1", "no_header": "row 1",
         "joint_count": "row 1"}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_trajectory_exits_2_with_one_line_and_no_output(tmp_path, capsys, case):
    path = tmp_path / f"{case}.csv"
    path.write_text(BAD[case])
    out_dir = tmp_path / "out"
    code, out, err = _run(["puma560", path, "-o", out_dir], capsys)
    assert code == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert str(path) in err
    if case in WHERE:
        assert WHERE[case] in err
    assert not out_dir.exists()


@pytest.mark.parametrize("args, expect", [
    (["no-such-robot", SHIPPED], "unknown robot"),
    (["puma560", "missing.csv"], "missing.csv: no such file"),
    (["puma560", SHIPPED, "--dominance", "0.3"], "--dominance"),
    (["puma560", SHIPPED, "--negligible", "abc"], "--negligible"),
    (["puma560"], "required"),
])
def test_bad_arguments_exit_2(tmp_path, capsys, args, expect):
    code, _, err = _run(args + ["-o", tmp_path / "o"], capsys)
    assert code == 2 and expect in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_positions_outside_limits_warn_but_run(tmp_path, capsys):
    path = tmp_path / "wide.csv"
    path.write_text(GOOD_HEADER + "\n0,0,0,0,0,0,0\n1,3.0,0,0,0,0,0\n2,0,0,0,0,0,0\n")
    code, _, err = _run(["puma560", path, "-o", tmp_path / "o", "--no-report", "-q"], capsys)
    assert code == 0
    assert "warning" in err and "column q1" in err and "outside its limits" in err


def test_plan_writes_the_shipped_trajectory(tmp_path, capsys):
    out = tmp_path / "plan.csv"
    code, _, err = _run(["plan", "puma560", "-o", out], capsys)
    assert code == 0, err
    a = np.loadtxt(out, delimiter=",", skiprows=1)
    b = np.loadtxt(SHIPPED, delimiter=",", skiprows=1)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-14)
    code, _, err = _run(["plan", "two-link", "-o", out, "--start", "0,10,20"], capsys)
    assert code == 2 and "--start" in err


def test_plan_writes_the_shipped_stanford_trajectory(tmp_path, capsys):
    """Default motion between staggered fractions of every joint's range (joint 3, k = 2,
    moves up from 0.28 to 0.72 of its range); the prismatic joint 3 in metres."""
    out = tmp_path / "plan.csv"
    code, _, err = _run(["plan", "stanford", "-o", out], capsys)
    assert code == 0, err
    a = np.loadtxt(out, delimiter=",", skiprows=1)
    b = np.loadtxt(ROOT / "data" / "stanford_trajectory.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-14)
    np.testing.assert_allclose(a[[0, -1], 3], [0.3048 + 0.28 * 0.9652, 0.3048 + 0.72 * 0.9652])
    code, _, err = _run(["plan", "stanford", "-o", out, "--start", "0,0,0.5,0,0,0", "--goal",
                         "10,20,0.9,0,0,0"], capsys)
    assert code == 0, err
    a = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(a[[0, -1], 3], [0.5, 0.9])                     # [m]
    np.testing.assert_allclose(a[-1, 1:3], np.radians([10, 20]))               # [rad]


def test_evaluate_and_max_error_gate(tmp_path, capsys, shared_main):
    out_dir = shared_main("puma560", SHIPPED)        # shared, read only
    model = out_dir / "simplified_model.json"
    other = tmp_path / "other.csv"
    assert _run(["plan", "puma560", "-o", other, "--start", "0,45,-90,0,30,0", "--goal",
                 "90,100,-30,45,-30,90"], capsys)[0] == 0
    code, out, _ = _run(["evaluate", model, other, "--json"], capsys)
    assert code == 0
    report = json.loads(out)
    assert report["setpoints"] == 31 and len(report["peak_abs_error"]) == 6
    worst = report["max_relative_peak_error"]
    assert worst > 0
    assert _run(["evaluate", model, other, "--max-error", str(worst * 2)], capsys)[0] == 0
    assert _run(["evaluate", model, other, "--max-error", str(worst / 2)], capsys)[0] == 3


@pytest.mark.parametrize("module", ["gd_analyze.cli", "gd_analyze"])
def test_real_process_no_traceback(tmp_path, module):
    """A real process (``python -m gd_analyze.cli``, or ``python -m gd_analyze`` as a user
    types it): exit status 2 and one line, no traceback."""
    bad = tmp_path / "bad.csv"
    bad.write_text(BAD["nan"])
    here = os.pathsep.join([str(SRC.parent), os.environ.get("PYTHONPATH", "")])
    proc = subprocess.run([sys.executable, "-m", module, "puma560", str(bad)],
                          capture_output=True, text=True, cwd=tmp_path,
                          env={**os.environ, "PYTHONPATH": here})
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "Traceback" not in proc.stderr
    assert "row 3, column q3" in proc.stderr
    assert not (tmp_path / "reports").exists()


def test_compare_json(capsys):
    code, out, err = _run(["compare", "puma560", SHIPPED, "--json"], capsys)
    assert code == 0, err
    report = json.loads(out)
    assert report["n"] == 6 and report["set_points"] == 31
    assert report["max_disagreement"] < 1e-10
    for quantity in ("D", "h", "c", "tau"):
        assert len(report["agreement"][quantity]) == 6          # every pair of the four
    counts = report["operation_counts"]
    assert {"lagrange-euler", "newton-euler", "gd"} <= set(counts)
    # Table 3.5's N-E row at n = 6: 132 n multiplications, 111 n - 4 additions
    assert counts["newton-euler"]["multiplications_table_3_5"] == 132 * 6
    assert counts["newton-euler"]["additions_table_3_5"] == 111 * 6 - 4
    code, out, _ = _run(["compare", "puma560", SHIPPED], capsys)
    assert code == 0 and "gd vs pinocchio" in out


@pytest.mark.slow
def test_payload_changes_the_torques_and_is_recorded(tmp_path, capsys, shared_main):
    loaded = tmp_path / "loaded"
    plain = shared_main("puma560", SHIPPED)          # shared, read only
    # what is read (the payload's attributes, the link mass, the peak torques) comes before
    # any model: pruned on the trajectory, no explicit model, so that the loaded arm's region
    # certification and explicit derivation (no cache holds them) are not run
    code, _, err = _run(["puma560", SHIPPED, "-o", loaded, "--no-report", "-q", "--payload",
                         "2.5", "--payload-com", "0,0,0.05", "--payload-inertia",
                         "0.002,0.002,0.001", "--guarantee", "trajectory", "--explicit",
                         "never"], capsys)
    assert code == 0, err
    with xr.open_dataset(plain / "results.h5", engine="h5netcdf") as a, \
            xr.open_dataset(loaded / "results.h5", engine="h5netcdf") as b:
        assert b.attrs["payload_mass"] == 2.5
        assert b.link_mass.values[-1] == pytest.approx(0.09 + 2.5)
        # the load hangs from the wrist: it adds gravity torque at joint 2
        assert b.tau_peak.values[1] > a.tau_peak.values[1] + 1.0
    code, _, err = _run(["puma560", SHIPPED, "-o", tmp_path / "x", "--payload", "-1"], capsys)
    assert code == 2 and "--payload" in err
    code, _, err = _run(["puma560", SHIPPED, "-o", tmp_path / "x", "--payload-com", "1,2"],
                        capsys)
    assert code == 2 and "3 comma-separated" in err


@pytest.mark.slow
def test_control_command(tmp_path, capsys, shared_main):
    out_dir = shared_main("puma560", SHIPPED)        # shared, read only
    model = out_dir / "simplified_model.json"
    code, out, err = _run(["control", model, SHIPPED, "-o", tmp_path / "c", "--no-report",
                           "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    peak = {c: max(f["peak_grid"]) for c, f in summary["tracking"].items()}
    assert peak["full"] < 1e-6                      # exact model: integrator error only
    assert peak["full"] < peak["simplified"] < peak["pd_gravity"]
    with xr.open_dataset(tmp_path / "c" / "control.h5", engine="h5netcdf") as ds:
        assert ds.attrs["robot"] == "puma560"
        # provenance: the model's own path and the SHA-256 of its bytes
        assert ds.attrs["model_path"] == str(model)
        assert ds.attrs["model_file"] == "simplified_model.json"
        assert ds.attrs["model_sha256"] == hashlib.sha256(model.read_bytes()).hexdigest()
    code, _, err = _run(["control", model, SHIPPED, "--wn", "-3"], capsys)
    assert code == 2 and "--wn" in err
    code, _, err = _run(["control", tmp_path / "none.json", SHIPPED], capsys)
    assert code == 2 and "no such file" in err


def test_evaluate_under_a_payload(capsys, shared_main):
    out_dir = shared_main("puma560", SHIPPED)        # shared, read only
    model = out_dir / "simplified_model.json"
    code, out, _ = _run(["evaluate", model, SHIPPED, "--json"], capsys)
    bare = json.loads(out)
    code, out, _ = _run(["evaluate", model, SHIPPED, "--json", "--payload", "2.5"], capsys)
    loaded = json.loads(out)
    # the model's own promise (EPS s_i) is the default gate: an unknown load breaks it, and the
    # guarantee (for the model's own robot) does not cover the loaded arm
    assert code == 3 and loaded["payload_mass"] == 2.5 and loaded["exceeded"]
    assert bare["guarantee"]["covered"] and not loaded["guarantee"]["covered"]
    # the model knows nothing of the load: its error grows, most at the shoulder and elbow
    assert loaded["peak_abs_error"][1] > 50 * bare["peak_abs_error"][1]


@pytest.mark.slow
def test_sweep_command_on_csv_files(tmp_path, capsys, puma_analysis):
    other = tmp_path / "other.csv"
    assert _run(["plan", "puma560", "-o", other, "--start", "0,45,-90,0,30,0", "--goal",
                 "90,100,-30,45,-30,90"], capsys)[0] == 0
    out_dir = tmp_path / "sw"
    code, out, err = _run(["sweep", "puma560", SHIPPED, other, "-o", out_dir,
                           "--no-report", "--payload-sweep", "0:1:1"], capsys)
    assert code == 0, err
    assert "2 trajectories" in out
    with xr.open_dataset(out_dir / "sweep.h5", engine="h5netcdf") as ds:
        assert ds.sizes["trajectory"] == 2
        # the shipped trajectory's row is its own ranking, as the main job gives it (the
        # session's analysis of it, default options, read only)
        single = puma_analysis.dataset
        # (results.h5 stores no share for an element zero in every part: the sweep flags it)
        data = np.isfinite(single.share_tran.values)
        np.testing.assert_allclose(ds.share_tran.values[0][data],
                                   single.share_tran.values[data], rtol=1e-12)
        assert ds.round_off.values[0][~data].all() and (~data).any()
    with xr.open_dataset(out_dir / "payload_sweep.h5", engine="h5netcdf") as p:
        assert list(p.payload.values) == [0.0, 1.0]
        assert p.class_fraction.dims == ("payload", "element", "class")
    spec = json.loads((out_dir / "merged_model.json").read_text())
    assert set(spec["choices"]) == set(single.element.values)


@pytest.mark.parametrize("args, expect", [
    (["sweep", "puma560"], "either --random K or trajectory CSV files"),
    (["sweep", "puma560", "--random", "3", str(SHIPPED)], "either --random K"),
    (["sweep", "puma560", "--random", "0"], "--random must be in [1, 1000000]"),
    (["sweep", "puma560", "--random", "2", "--payload-sweep", "1:0:0.5"], "--payload-sweep"),
])
def test_sweep_bad_arguments(tmp_path, capsys, args, expect):
    code, _, err = _run(args + ["-o", tmp_path / "o"], capsys)
    assert code == 2 and expect in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_parse_range():
    assert parse_range("0:2.5:0.5") == [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]
    assert parse_range("0:0.3:0.1") == [0.0, 0.1, 0.2, 0.3]      # exact decimal grid
    assert parse_range(" 0.1 : 0.7 : 0.2 ") == [0.1, 0.3, 0.5, 0.7]
    assert parse_range("0:1:0.3") == [0.0, 0.3, 0.6, 0.9]         # stop off the grid
    assert parse_range("1.5:1.5:1") == [1.5]
    assert len(parse_range("0:10:0.01")) == 1001


@pytest.mark.parametrize("text, match", [
    ("0:2.5", "START:STOP:STEP"), ("0:1:2:3", "START:STOP:STEP"), ("a:1:0.5", "three numbers"),
    ("0:1:", "three numbers"), ("0:1:0", "STEP must be positive"),
    ("0:1:-0.5", "STEP must be positive"), ("2:1:0.5", "STOP must not be below"),
    ("0:inf:1", "finite"), ("0:1e9:1e-3", "at most"),
])
def test_parse_range_errors(text, match):
    with pytest.raises(InputError, match=match) as info:
        parse_range(text)
    assert "--payload-sweep" in str(info.value)


def test_summary_gives_the_model_cost_beside_newton_euler():
    """The printed cost line reads the stored cost table; N-E's figure is the counted one."""
    from gd_analyze import load_robot
    from gd_analyze.dynamics.opcount import count_operations

    # the run of golden case puma560 (gd-analyze puma560 <shipped> --no-report), read only
    (root, *_), out = golden_run("puma560")
    folder = root / "puma560"
    ne = count_operations(load_robot("puma560"), "newton-euler")
    line = next(x for x in out.splitlines() if x.startswith("simplified model ("))
    assert line.endswith(f"Newton-Euler as implemented: {ne[0] + ne[1]:,}")
    model = json.loads((folder / "simplified_model.json").read_text())
    total = model["cost"]["multiplications"] + model["cost"]["additions"]
    assert f": {total:,} operations per set point" in line
    exact = model["costs"]["exact recursive"]
    assert f"exact recursive model: {exact['multiplications'] + exact['additions']:,}" in line
    assert line.startswith(f"simplified model ({'recursive N-E' if model['form'] == 'recursive' else 'explicit'}, budget")
    assert "does not beat Newton-Euler" not in out        # 622 < 1,212 on the PUMA


def test_summary_warns_when_the_model_does_not_pay():
    from gd_analyze.cli.commands import _cost_lines
    from gd_analyze.store.stored_simplified import CostTable

    names = ["explicit, budget EPS=0.01 (this model)", "project N-E as implemented"]
    ds = xr.Dataset({"cost_multiplications": ("cost_model", [900, 600]),
                     "cost_additions": ("cost_model", [800, 500]),
                     "cost_total": ("cost_model", [1700, 1100])},
                    coords={"cost_model": names})
    lines = _cost_lines(CostTable.from_dataset(ds))
    assert "1,700 operations" in lines[1] and lines[1].endswith("1,100")
    assert "does not beat Newton-Euler" in lines[2]


# ------------------------------------------------------------------------------------------
# The program's exit: a normal one (atexit handlers run), with everything flushed; the main
# job runs as without dask
# ------------------------------------------------------------------------------------------

def test_program_exits_with_its_status_and_all_its_output(tmp_path):
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "gd_analyze.cli", "two-link",
                           str(tmp_path / "missing.csv")], capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
    assert "missing.csv: no such file" in proc.stderr
    # the trajectory planned in this process: the program's exit is the main job's below
    assert main(["plan", "two-link", "--start", "0,0", "--goal", "30,20", "-o",
                 str(tmp_path / "t.csv")]) == 0
    proc = subprocess.run([sys.executable, "-m", "gd_analyze.cli", "two-link",
                           str(tmp_path / "t.csv"), "-o", str(out), "--no-report"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    last = proc.stdout.rstrip("\n").splitlines()[-1]        # the last line made it out whole
    assert last == f"wrote 6 files to {out}"               # the count, not every path
    listed = subprocess.run([sys.executable, "-m", "gd_analyze.cli", "two-link",
                             str(tmp_path / "t.csv"), "-o", str(out), "--no-report", "-v"],
                            capture_output=True, text=True)
    last = listed.stdout.rstrip("\n").splitlines()[-1]      # -v: every file, whole
    assert last.startswith("wrote ") and last.endswith("simplified_model_casadi.py")
    assert last.count(str(out)) == 6


def test_a_plan_on_stdout_whose_reader_goes_away_exits_0_and_says_nothing():
    # `gd-analyze plan ... -o - | head -1`: the reader closes the pipe after one line
    proc = subprocess.Popen([sys.executable, "-m", "gd_analyze.cli", "plan", "two-link", "-o",
                             "-", "--setpoints", "100000"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    header = proc.stdout.readline()
    proc.stdout.close()
    assert proc.wait(timeout=300) == 0
    assert header == "t,q1,q2,qd1,qd2,qdd1,qdd2\n" and proc.stderr.read() == ""


_AT_EXIT = """
import atexit, sys
from gd_analyze.cli import run

def report():
    print("atexit ran; dask imported:", sys.modules.get("dask") is not None, file=sys.stderr)

atexit.register(report)
sys.argv = ["gd-analyze"] + sys.argv[1:]
run()
"""


@pytest.mark.slow
def test_main_job_exits_normally_without_importing_dask(tmp_path):
    """The console script returns through sys.exit: the interpreter's teardown and atexit
    handlers run (no os._exit), and the main job with its report never imports dask. On the
    two-link arm (11 set points): the same job and report code as on a larger arm, in a
    fraction of its time."""
    proc = subprocess.run([sys.executable, "-c", _AT_EXIT, "two-link", str(_two_link_csv(tmp_path)),
                           "-o", str(tmp_path / "out"), "-q"], capture_output=True, text=True,
                          env={**os.environ, "MPLBACKEND": "Agg"}, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "out" / "report.pdf").is_file()
    assert proc.stderr.splitlines()[-1] == "atexit ran; dask imported: False"


def test_a_command_that_runs_alone_exits_normally(tmp_path):
    """``plan`` starts no thread and no child: the old early exit (os._exit) skipped the
    atexit handlers exactly there."""
    proc = subprocess.run([sys.executable, "-c", _AT_EXIT, "plan", "two-link", "--start", "0,0",
                           "--goal", "30,20", "-o", str(tmp_path / "t.csv")],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "t.csv").is_file()
    assert proc.stderr.splitlines()[-1].startswith("atexit ran")


def test_a_sub_command_may_import_dask(tmp_path):
    """Only the main job is kept from dask: the sweep runs on it."""
    proc = subprocess.run([sys.executable, "-c", _AT_EXIT, "sweep", "two-link", "--random",
                           "2", "--workers", "1", "--no-report", "-o", str(tmp_path / "out"),
                           "-q"], capture_output=True, text=True,
                          env={**os.environ, "MPLBACKEND": "Agg"}, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.splitlines()[-1] == "atexit ran; dask imported: True"


def test_summary_says_how_many_set_points_were_verified(tmp_path, capsys):
    """On a 5,000-set-point run the printout says "on 2,000 of 5,000 set
    points" (thousands separators as the report's counts), not "on 2000 set points"; on a
    short run, where every set point is checked, the plain count. Oracle: the trajectory file's
    own row count and the stored attribute."""
    from gd_analyze.jobs.analyze import VERIFY_MAX_SETPOINTS

    N = 5000
    t = np.linspace(0, 5, N)
    path = tmp_path / "long.csv"
    path.write_text("t,q1,q2\n" + "".join(f"{v:.17g},{np.sin(v):.17g},{np.cos(v):.17g}\n" for v in t))
    assert main(["two-link", str(path), "-o", str(tmp_path / "o"), "--no-report"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("verified"))
    with xr.open_dataset(tmp_path / "o" / "results.h5") as ds:
        checked = int(ds.attrs["verification_setpoints"])
    assert checked == VERIFY_MAX_SETPOINTS < N
    assert line.startswith(f"verified against Pinocchio on {checked:,} of {N:,} set points:")
    short = _two_link_csv(tmp_path)
    assert main(["two-link", str(short), "-o", str(tmp_path / "s"), "--no-report"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("verified"))
    assert line.startswith("verified against Pinocchio on 11 set points:")


@pytest.mark.parametrize("command", [["sweep", "two-link", "--random", "2"], ["two-link", "T"]])
@pytest.mark.parametrize("option", [["--form", "recursive"], ["--explicit", "never"]])
def test_the_chapter_rule_refuses_the_options_it_would_ignore(tmp_path, capsys, option,
                                                              command):
    """The chapter rule's model (and a sweep's merge of it) is explicit, in the main job and
    the sweep alike (the budget rule takes --form and --explicit): one line, exit 2, nothing
    written."""
    out_dir = tmp_path / "out"
    command = [str(_two_link_csv(tmp_path)) if a == "T" else a for a in command]
    code, out, err = _run([*command, "-o", out_dir, "--rule", "chapter", *option], capsys)
    assert code == 2
    assert option[0] in err and len(err.strip().splitlines()) == 1, err
    assert not out_dir.exists()


@pytest.mark.parametrize("form", ["recursive", "explicit"])
def test_sweep_writes_the_form_asked_for(tmp_path, capsys, form):
    """--form of the budget rule's merge: the model file, sweep.h5 and the printout say the
    form written."""
    import json

    import xarray as xr

    out_dir = tmp_path / "sweep"
    code, out, _ = _run(["sweep", "two-link", "--random", "2", "--held-out",
                         "0", "--no-report", "-o", out_dir, "--form", form], capsys)
    assert code == 0 and f"{form} form" in out
    assert json.loads((out_dir / "merged_model.json").read_text())["form"] == form
    with xr.open_dataset(out_dir / "sweep.h5") as ds:
        assert ds.attrs["merged_form"] == form


@pytest.mark.slow
def test_control_printout_marks_integrator_noise_as_the_report_does():
    """The printed table gave the full-model controller's tracking error as digits
    (1.476e-11 rad), which the report and the verdict call integrator noise, ≡ 0: each printed
    cell is "≡ 0" exactly where the stored error is at or below the report's floor."""
    from gd_analyze.report.control import dataset_verdict
    from gd_analyze.store.schema import open_results

    # the run of golden case puma560-control (gd-analyze control <golden case puma560's
    # model> <shipped> --no-report) and what it printed, shared, read only
    (root, *_), out = golden_run("puma560-control")
    ds = open_results(root / "puma560-control" / "control.h5")
    q_floor = dataset_verdict(ds)["floors"][0]
    rows = {line.split()[0]: line for line in out.splitlines() if "peak |e|" in line}
    assert set(rows) == {"full", "simplified", "pd_gravity"}
    for c, line in rows.items():
        cells = line.split("peak |e|")[0].split()[1:]
        cells = [a for a in " ".join(cells).replace("\u2261 0", "\u22610").split()]
        stored = ds["error_peak_grid"].sel(controller=c).values
        assert len(cells) == len(stored)
        for text, v, f in zip(cells, stored, q_floor):
            assert (text == "\u22610") == bool(v <= f), (c, text, v, f)
    assert rows["full"].count("\u2261 0") == 6


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs Linux's /dev/full")
def test_a_full_disk_outside_the_output_folder_is_not_a_bug(monkeypatch, capsys):
    """A write outside the output folder that a full disk stops (numba's cache of compiled
    kernels beside the package, written while a command computes) is an operational failure:
    one line, exit 2, not "internal error" and exit 4. The write is real: /dev/full answers
    every write with ENOSPC; the command wraps it, as numba does, in another error."""
    import gd_analyze.cli as cli

    def fills_the_disk(args):
        try:
            with open("/dev/full", "wb") as cache:
                cache.write(b"x" * 100_000)
        except OSError as exc:
            raise RuntimeError("could not save the compiled kernel") from exc
        return 0

    monkeypatch.setattr(cli.commands, "cmd_plan", fills_the_disk)
    assert main(["plan", "two-link", "-o", "unused.csv"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "gd-analyze: error: cannot write: no space left on the device", err
