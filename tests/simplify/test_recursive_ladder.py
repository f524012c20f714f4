"""The tolerance ladder of the pruned recursive model (``fig_cost_ladder`` had no
ladder where the recursive model is deployed, the default).

Oracles: Pinocchio's rnea (each rung's error, rebuilt independently from the pruning it
states), and the budget (the measured error is within the bound, the bound within EPS s_i).
"""

import json

import numpy as np
import pytest
from conftest import SHIPPED

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.simplify.deploy import region_model, robot_region
from gd_analyze.simplify.explicit_model import LADDER
from gd_analyze.simplify.recursive_ladder import recursive_ladder
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.recursive_model import recursive_model
from gd_analyze.trajectory.trajectory import read_trajectory


def _rnea(robot, q, qd, qdd):
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model

    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, *x).copy() for x in zip(q, qd, qdd)])


@pytest.fixture(scope="module")
def puma():
    robot = load_robot("puma560")
    traj = read_trajectory(SHIPPED, 6)
    states = (traj.q, traj.qd, traj.qdd)
    return robot, base_parameters(robot), states, _rnea(robot, *states)


@pytest.mark.parametrize("proved", [True, False], ids=["region", "trajectory"])
def test_each_rung_s_error_is_that_of_its_model_against_rnea(puma, proved):
    """Each rung's stored worst error is its own model's, rebuilt here from the pruning it
    states (region or trajectory) and measured against Pinocchio's rnea, relative to that
    model's s_i; its bound is within EPS s_i and holds the error; a larger EPS never costs
    more operations on the PUMA 560."""
    robot, base, states, ref = puma
    region, _ = robot_region(robot)
    rows = recursive_ladder(robot, base, states, LADDER, region=region if proved else None)
    assert [r["tolerance"] for r in rows] == list(LADDER)
    for r in rows:
        eps = r["tolerance"]
        rec = region_model(robot, base, region, eps)[0] if proved else \
            recursive_model(robot, *states, eps, base=base)
        program = rec.choice(robot)[0]
        tau = python_function(program)(*states)
        scale = np.asarray(rec.scale, float)
        worst = float(np.max(np.abs(tau - ref).max(axis=0) / scale))
        np.testing.assert_allclose(r["worst_relative_error"], worst, rtol=1e-6, atol=1e-12)
        assert r["worst_relative_error"] <= r["worst_relative_bound"] + 1e-12
        assert r["worst_relative_bound"] <= eps * (1 + 1e-12)
    ops = [r["multiplications"] + r["additions"] for r in rows]
    assert ops == sorted(ops, reverse=True) and ops[-1] < ops[0], ops


def test_the_default_run_stores_and_draws_the_recursive_ladder(shared_puma):
    """The default PUMA run deploys the recursive model pruned over the region; results.h5
    holds its ladder (one rung per EPS, the deployed model's counts at its EPS, the exact
    recursive model's at 0), the cost table lists the other rungs, and the report's Sec. 5.5
    and Fig. 7's key name them."""
    import xarray as xr

    from gd_analyze.report.simplified_section import cost_points

    out = shared_puma["puma"][0]                  # the default run, with its report
    spec = json.loads((out / "simplified_model.json").read_text())
    assert spec["form"] == "recursive" and spec["guarantee"]["kind"] == "region"
    with xr.open_dataset(out / "results.h5", engine="h5netcdf") as ds:
        ds = ds.load()
    assert ds.attrs["simplified_ladder_form"] == "recursive"
    assert "simplified_ladder_skipped" not in ds.attrs
    ops = dict(zip(ds["ladder_tolerance"].values.tolist(), ds["ladder_operations"].values))
    assert list(ops) == list(LADDER)
    cost = spec["cost"]["multiplications"] + spec["cost"]["additions"]
    exact = spec["costs"]["exact recursive"]
    # EPS 0 drops only the pairs proved identically zero over the region (bound 0): never
    # dearer than the exact recursive model
    total = exact["multiplications"] + exact["additions"]
    assert ops[0.01] == cost and ops[0.0] <= total
    labels = [str(v) for v in ds["cost_model"].values]
    assert "recursive N-E, budget EPS=0.05" in labels
    keyed = [p[0] for p in cost_points(ds) if p[3] == "ladder"]
    assert "recursive N-E, budget \u03b5 = 0.05" in keyed
    assert not any("\u03b5 = 0.01" in k for k in keyed)     # the model built: said once
    err = dict(zip(ds["ladder_tolerance"].values.tolist(), ds["ladder_worst_error"].values))
    named = [p[0] for p in cost_points(ds)]
    rung = "recursive N-E, budget \u03b5 = 0.001"
    if ops[0.001] == total and err[0.001] == 0:         # the same model as the exact one
        assert "recursive N-E, exact (= " + rung + ")" in named and rung not in named
    elif ops[0.001] == ops[0.0] and err[0.001] == err[0.0]:     # the same as the EPS 0 rung
        assert "recursive N-E, budget \u03b5 = 0 (= " + rung + ")" in named and rung not in named
    else:
        assert rung in named
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Tolerance ladder of the recursive form" in html
    assert "proved over the joint-limit region (\u2264 \u03b5)" in html


def test_the_ladder_s_errors_are_measured_block_by_block(puma):
    """The meter gives each rung's peak |tau_s - tau| per joint, fed in uneven blocks, as the
    whole trajectory at once does, with the deployed rung's torques given or evaluated; and
    the ladder measured here holds no more for 10^5 set points than for 10^4 (less than
    twice: every rung's (N, n) torques are never held at once)."""
    import tracemalloc

    from gd_analyze.dynamics.base_parameters import random_states
    from gd_analyze.simplify.recursive_ladder import LadderMeter
    from gd_analyze.symbolic.drive_regressor import with_drives
    from gd_analyze.symbolic.recursive import recursive_program

    robot, base, states, _ = puma
    exact = with_drives(recursive_program(robot, base.values), robot)
    rungs = [(eps, rec, with_drives(rec.choice(robot)[0], robot)) for eps, rec in
             ((eps, recursive_model(robot, *states, eps, base=base)) for eps in (0.0, 0.01, 0.1))]
    q, qd, qdd = random_states(robot, 3000, 5)
    ref = python_function(exact)(q, qd, qdd)
    want = np.array([np.abs(python_function(p)(q, qd, qdd) - ref).max(axis=0)
                     for _, _, p in rungs])
    for deployed, given in ((None, False), (1, False), (1, True)):
        meter = LadderMeter(robot.n, rungs, deployed)
        for a in range(0, 3000, 700):
            rows = slice(a, a + 700)
            mine = python_function(rungs[1][2])(q[rows], qd[rows], qdd[rows]) if given else None
            meter.update(q[rows], qd[rows], qdd[rows], ref[rows], mine)
        np.testing.assert_array_equal(meter.peaks(), want)
    assert want[0].max() < 1e-9 * np.abs(ref).max() and want[2].max() > want[1].max() > 0
    peaks = []
    for N in (10_000, 100_000):
        q, qd, qdd = random_states(robot, N, 6)
        tracemalloc.start()
        recursive_ladder(robot, base, (q, qd, qdd), (0.01, 0.1), contributions=None)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    assert peaks[1] < 2 * peaks[0], peaks


def test_rungs_with_the_same_code_share_one_evaluation(puma, monkeypatch):
    """Rungs whose programs are separately built but the same code get the errors each
    would get alone, from one evaluation per distinct program."""
    import dataclasses

    import gd_analyze.simplify.recursive_ladder as ladder
    from gd_analyze.dynamics.base_parameters import random_states
    from gd_analyze.symbolic.recursive import recursive_program

    robot, base, states, _ = puma
    exact = recursive_program(robot, base.values)

    def rung(eps):
        rec = recursive_model(robot, *states, eps, base=base)
        return eps, rec, rec.choice(robot)[0]
    # new objects of the same code (programs are memoised: built again, they are the same one)
    rungs = [rung(0.01), rung(0.0), rung(0.1), rung(0.01)]
    rungs[3] = (*rungs[3][:2], dataclasses.replace(rungs[3][2]))
    assert rungs[0][2] is not rungs[3][2]
    q, qd, qdd = random_states(robot, 500, 7)
    ref = python_function(exact)(q, qd, qdd)
    want = np.array([np.abs(python_function(p)(q, qd, qdd) - ref).max(axis=0)
                     for _, _, p in rungs])
    evaluated = []

    def spy(program):
        evaluated.append(program)
        return python_function(program)
    monkeypatch.setattr(ladder, "python_function", spy)
    meter = ladder.LadderMeter(robot.n, rungs)
    evaluated.clear()
    meter.update(q, qd, qdd, ref)
    np.testing.assert_array_equal(meter.peaks(), want)
    assert want[2].max() > want[0].max() > 0
    assert {id(p) for p in evaluated} == {id(rungs[k][2]) for k in (0, 1, 2)}
    assert len(evaluated) == 3
