"""The ``sweep`` command's merged model: of the recursive form where that is
the cheaper, its file evaluated by ``gd-analyze evaluate`` and checked against Pinocchio's
rnea, and every figure it prints and stores counted on the model written; the sweep under a
file size limit."""

import contextlib
import io
import json
import re
import sys

import numpy as np
import pinocchio as pin
import pytest
import xarray as xr
from robot_files import toml_without_limits
from staging_checks import refused_by_the_limit, run_limited

from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.store.model_file import load_model
from gd_analyze.store.sweep_view import sweep_size
from gd_analyze.symbolic.recursive import recursive_program
from gd_analyze.trajectory.planning import random_trajectories
from gd_analyze.trajectory.trajectory import write_trajectory


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
