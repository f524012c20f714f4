"""The ``sweep`` command's merged model (issue 29 item 2): of the recursive form where that is
the cheaper, its file evaluated by ``gd-analyze evaluate`` and checked against Pinocchio's
rnea, and every figure it prints and stores counted on the model written."""

import contextlib
import io
import json
import re

import numpy as np
import pinocchio as pin
import pytest
import xarray as xr

from gd_analyze.cli import main
from gd_analyze.core.symbolic.recursive import recursive_program
from gd_analyze.formulations.pinocchio import pinocchio_model
from gd_analyze.io.model_file import load_model
from gd_analyze.io.planning import random_trajectories
from gd_analyze.io.trajectory import write_trajectory


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """A PUMA 560 sweep of 3 random trajectories by the command, and what it printed."""
    out = tmp_path_factory.mktemp("sweep")
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["sweep", "puma560", "--random", "3", "--seed", "4", "--workers", "1",
                     "--held-out", "0", "--no-report", "-o", str(out)]) == 0
    return out, buf.getvalue()


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


def test_the_merged_model_emits_every_file_with_its_own_prefix(swept):
    """Issue 30 item 7: merged_model.h, .c, .py and _casadi.py, prefix puma560_merged_; the
    numpy functions keep D_s qdd + h_s + c_s = tau_s = Y_s beta_s; D_s checked on the sweep."""
    from scales import identity_errors

    from gd_analyze.core.symbolic.emit_model import artefact_names

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
    assert check["positive_definite"] and check["where"] == "trajectory"
