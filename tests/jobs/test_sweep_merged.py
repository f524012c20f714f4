"""The merged model of a sweep (gd_analyze.jobs.sweep_merged).

The chapter rule's (:func:`merged_model`), read from a sweep dataset written by hand: its
choices and validation as stored, and a dataset without one of them refused in one line naming
it. The budget rule's: pruned in the recursive form on the peaks the dask workers computed per
trajectory, never dearer than the exact recursive model, and within EPS x that trajectory's own
scale on every swept trajectory, checked against Pinocchio's rnea (the URDF arms against the
URDF's own Pinocchio model)."""

import numpy as np
import pytest
import xarray as xr
from urdf_oracle import UrdfOracle

from gd_analyze import load_robot
from gd_analyze.errors import InputError
from gd_analyze.jobs.sweep import run_sweep
from gd_analyze.jobs.sweep_merged import (
    budget_sweep_model,
    merged_model,
    pair_peaks,
    with_budget_model,
)
from gd_analyze.model.urdf import builtin_urdf_path
from gd_analyze.ranking.labels import element_labels
from gd_analyze.store.model_file import load_model, save_model
from gd_analyze.symbolic.drive_regressor import with_drives
from gd_analyze.symbolic.recursive import recursive_program
from gd_analyze.trajectory.planning import random_trajectories


def _sweep(robot):
    labels = element_labels(robot.n)
    joint = ("joint",)
    return xr.Dataset({
        "merged_choice": ("element", ["both"] * len(labels)),
        "merged_error_peak": (joint, [0.1, 0.2]),
        "merged_error_rms": (joint, [0.01, 0.02]),
        "merged_error_tau_peak": (joint, [10.0, 20.0]),
        "merged_error_relative_peak": (joint, [0.01, 0.01]),
        "merged_error_relative_rms": (joint, [0.001, 0.001]),
    }, coords={"element": labels, "trajectory": [0, 1, 2]}, attrs={"setpoints_total": 93})


def test_the_validation_is_the_stored_error_over_all_trajectories(two_link):
    model = merged_model(two_link, _sweep(two_link))
    assert model.validation == {
        "peak_abs_error": [0.1, 0.2], "rms_error": [0.01, 0.02], "peak_tau": [10.0, 20.0],
        "relative_peak_error": [0.01, 0.01], "relative_rms_error": [0.001, 0.001],
        "trajectories": 3, "setpoints": 93}
    assert set(model.choices.values()) == {"both"}


@pytest.mark.parametrize("name", ["merged_choice", "merged_error_rms",
                                  "merged_error_relative_rms"])
def test_a_dataset_without_a_merged_variable_is_refused_naming_it(two_link, name):
    with pytest.raises(InputError) as err:
        merged_model(two_link, _sweep(two_link).drop_vars(name))
    assert str(err.value) == f"not a gd-analyze sweep dataset: missing variable(s) {name}"


@pytest.fixture(scope="module")
def client(cluster):
    return cluster[1]


def oracle(robot, name):
    """tau(q, qd, qdd) of Pinocchio: the URDF's own model for a URDF arm, else the chain."""
    import pinocchio as pin

    if robot.metadata.get("urdf_joints"):
        own = UrdfOracle(builtin_urdf_path(name), robot.metadata["urdf_joints"])
        return lambda q, qd, qdd: np.array([own.rnea(*s) for s in zip(q, qd, qdd)])
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    model = pinocchio_model(robot)
    data = model.createData()
    return lambda q, qd, qdd: np.array([pin.rnea(model, data, *s) for s in zip(q, qd, qdd)])


def check_on_each(model, trajectories, tau, eps, floor):
    """Per trajectory and joint: the model's error against the oracle within EPS x scale_i
    (scale_i = max(peak |tau_i| on it, floor)) and within the stored bound on it; returns
    the worst error / scale_i."""
    per = model.validation["per_trajectory"]
    worst = 0.0
    for k, tr in enumerate(trajectories):
        ref = tau(tr.q, tr.qd, tr.qdd)
        scale = np.maximum(np.abs(ref).max(axis=0), floor)
        err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - ref).max(axis=0)
        slack = 1e-10 * np.abs(ref).max()                 # the oracle's own round-off
        assert np.isfinite(err).all()
        assert np.all(err <= eps * scale * (1 + 1e-9) + slack), (tr.source, err / scale)
        assert np.all(err <= np.asarray(per["bound"][k]) + slack), (tr.source, err)
        assert np.all(np.asarray(per["bound"][k]) <= eps * scale * (1 + 1e-9) + slack)
        worst = max(worst, float((err / scale).max()))
    return worst


def exact_count(robot):
    c = with_drives(recursive_program(robot), robot).cost()
    return c["multiplications"] + c["additions"]


def ops(cost):
    return cost["multiplications"] + cost["additions"]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "ur5", "panda"])
def test_merged_model_costs_no_more_than_the_exact_recursive_and_holds_on_each(name, client):
    robot = load_robot(name)
    trajectories = random_trajectories(robot, 3, seed=7)
    ds = run_sweep(robot, trajectories, client=client, batch=2, recursive_peaks=True)
    model = budget_sweep_model(robot, trajectories, ds, tolerance=0.01,
                               guarantee="trajectory")
    assert ops(model.cost) <= exact_count(robot)                       # counted afresh
    assert ops(model.program().cost()) == ops(model.cost)
    if name == "panda":                 # the explicit expansion is not started for it
        assert model.form == "recursive" and "explicit, full" not in model.costs
    else:
        assert ops(model.costs["explicit, budget"]) >= ops(model.cost)   # the cheaper one
    check_on_each(model, trajectories, oracle(robot, name), 0.01, 0.0)
    if model.form == "recursive":       # something was pruned, unless restored for D_s
        assert model.recursive.dropped.any() or model.inertia_check["restored"]


@pytest.fixture(scope="module")
def mixed_sweep(puma, mixed, client):
    return run_sweep(puma, mixed, client=client, batch=3, recursive_peaks=True)


@pytest.mark.slow
@pytest.mark.parametrize("eps, floor", [(0.002, 0.0), (0.05, 0.0), (0.01, 1.0)])
def test_each_trajectory_is_held_to_its_own_scale(puma, mixed, mixed_sweep, eps, floor):
    """The slow move's torques are far below the fast ones': a merge on the largest scale
    would break the budget on it."""
    model = budget_sweep_model(puma, mixed, mixed_sweep, tolerance=eps, torque_floor=floor,
                               guarantee="trajectory")
    worst = check_on_each(model, mixed, oracle(puma, "puma560"), eps, floor)
    # the stored figure (against the G-D terms) is the oracle's, to round-off of small scales
    assert model.validation["worst_scaled_error"] == pytest.approx(worst, rel=1e-6, abs=1e-9)
    assert max(model.validation["relative_bound"]) <= eps * (1 + 1e-12)


def test_peaks_computed_by_the_workers_are_each_trajectorys(puma, mixed, mixed_sweep):
    """pair_tau_peak is each trajectory's peak |tau_i| by Pinocchio; the pair peaks add up
    to at least it (triangle inequality)."""
    tau_peak, peak, whole = pair_peaks(mixed_sweep)
    tau = oracle(puma, "puma560")
    for k, tr in enumerate(mixed):
        ref = np.abs(tau(tr.q, tr.qd, tr.qdd)).max(axis=0)
        np.testing.assert_allclose(tau_peak[k], ref, rtol=1e-9, atol=1e-12 * ref.max())
        assert np.all(peak[k].sum(axis=(0, 1)) >= ref * (1 - 1e-9))
        assert np.all(whole[k] <= peak[k].sum(axis=1) * (1 + 1e-12) + 1e-15)


@pytest.mark.slow
def test_forms_and_the_file(puma, mixed, mixed_sweep, tmp_path):
    """form="explicit" deploys the explicit model, "recursive" the recursive one, the default
    the cheaper; the recursive model's file reads back with the same torques, and the dataset
    says what was built, with the bound on each trajectory."""
    on = dict(tolerance=0.01, guarantee="trajectory")        # the merge on the trajectories
    rec = budget_sweep_model(puma, mixed, mixed_sweep, form="recursive", **on)
    ex = budget_sweep_model(puma, mixed, mixed_sweep, form="explicit", **on)
    cheap = budget_sweep_model(puma, mixed, mixed_sweep, **on)
    assert (rec.form, ex.form) == ("recursive", "explicit")
    assert ops(cheap.cost) == min(ops(rec.cost), ops(ex.cost))
    check_on_each(ex, mixed, oracle(puma, "puma560"), 0.01, 0.0)
    path = tmp_path / "merged_model.json"
    save_model(rec, path)
    back = load_model(path)
    assert back.form == "recursive"
    tr = mixed[0]
    np.testing.assert_allclose(back.torque(tr.q, tr.qd, tr.qdd), rec.torque(tr.q, tr.qd, tr.qdd),
                               rtol=0, atol=1e-12 * np.abs(rec.torque(tr.q, tr.qd, tr.qdd)).max())
    ds = with_budget_model(mixed_sweep, rec)
    assert "pair_peak" not in ds.variables and ds.attrs["merged_form"] == "recursive"
    np.testing.assert_array_equal(ds["merged_bound"].values, rec.validation["per_trajectory"]
                                  ["bound"])
    assert int(ds.attrs["merged_pairs_dropped"]) == rec.recursive.stated_facts()["dropped"] > 0
    assert "recursive Newton-Euler" in ds.attrs["merge_rule"]
    with pytest.raises(ValueError, match="form"):
        budget_sweep_model(puma, mixed, mixed_sweep, form="fastest", guarantee="trajectory")
    with pytest.raises(ValueError, match="trajectories"):
        budget_sweep_model(puma, mixed[:2], mixed_sweep, guarantee="trajectory")
