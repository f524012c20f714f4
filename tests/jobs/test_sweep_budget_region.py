"""The sweep's merged model under a region guarantee: the main job's region
model, whatever the swept trajectories, checked on each of them and each said to lie inside the
robot's joint-limit region or not.

Oracles: Pinocchio's rnea (the torques), the main job's own model on the shipped trajectory
(its dropped pairs), and the robot's limits read directly (which trajectory leaves the region).
"""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions, SimplifyOptions
from gd_analyze.jobs.sweep import ERRORS_SETPOINTS_MAX, WorkerErrors, run_sweep
from gd_analyze.jobs.sweep_merged import budget_region_model, budget_sweep_model, with_budget_model
from gd_analyze.model.limits import acceleration_limits
from gd_analyze.simplify.sweep_model import per_trajectory_errors, sweep_validation
from gd_analyze.store.sweep_view import merged_guarantee
from gd_analyze.trajectory.planning import random_trajectories


@pytest.fixture(scope="module")
def client(cluster):
    return cluster[1]


@pytest.fixture(scope="module")
def planned(puma):
    """Three random PUMA 560 plans (shortest duration within its limits: inside its region)."""
    return random_trajectories(puma, 3, seed=21)


@pytest.fixture(scope="module")
def fast(planned):
    """The first plan run twice as fast: the same path, qd x 2 and qdd x 4."""
    tr = planned[0]
    return dataclasses.replace(tr, t=tr.t / 2, qd=2 * tr.qd, qdd=4 * tr.qdd,
                               source="twice-as-fast")


@pytest.fixture(scope="module")
def swept(puma, planned, fast, client):
    """The sweep (ranking only: a region merge needs no per-trajectory peaks) of the plans and
    the fast one."""
    return run_sweep(puma, [*planned, fast], client=client, batch=2)


def _rnea(robot, tr):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, *s).copy() for s in zip(tr.q, tr.qd, tr.qdd)])


def _outside(robot, tr):
    """Whether a trajectory leaves the robot's limits (read from the robot, not the model)."""
    qdd_max, _ = acceleration_limits(robot)
    slack = 1e-12
    return bool((tr.q < robot.q_min - slack).any() or (tr.q > robot.q_max + slack).any()
                or (np.abs(tr.qd) > robot.qd_max * (1 + slack)).any()
                or (np.abs(tr.qdd) > np.asarray(qdd_max) * (1 + slack)).any())


@pytest.mark.parametrize("eps", [0.01, 0.05])
def test_region_merge_is_the_main_jobs_region_model_and_holds_on_each(puma, planned, fast,
                                                                       swept, shipped, eps):
    trajectories = [*planned, fast]
    model = budget_sweep_model(puma, trajectories, swept, tolerance=eps, guarantee="region",
                               explicit="never")
    g = model.guarantee
    assert g.kind == "region" and model.form == "recursive"
    # the main job's model on the shipped trajectory drops the same pairs: the region does
    # not depend on the trajectories
    main = analyze(puma, shipped, AnalysisOptions(verify=False, formulations=False,
                                                  simplify=SimplifyOptions(tolerance=eps,
                                                                           explicit="never")))
    assert main.model.guarantee.kind == "region"
    np.testing.assert_array_equal(model.recursive.dropped, main.model.recursive.dropped)
    assert model.recursive.dropped.any()
    bound, scale = np.asarray(g.bound), np.asarray(g.scale)
    assert np.all(bound <= eps * scale * (1 + 1e-12))
    np.testing.assert_allclose(bound, main.model.guarantee.bound, rtol=1e-12, atol=0)
    per = model.validation["per_trajectory"]
    for k, tr in enumerate(trajectories):
        if _outside(puma, tr):
            continue                                   # not covered: reported, not checked
        err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - _rnea(puma, tr)).max(axis=0)
        assert np.all(err <= bound + 1e-9 * scale), (tr.source, err, bound)
        np.testing.assert_allclose(per["bound"][k], bound, rtol=0, atol=0)
        np.testing.assert_allclose(per["scale"][k], scale, rtol=0, atol=0)
    c_source = model.sources()["simplified_model.c"]
    assert "bound on each swept trajectory" not in c_source
    assert f"guarantee: {g.statement()}" in c_source


def test_a_trajectory_outside_the_region_is_reported_not_covered(puma, planned, fast, swept,
                                                                 tmp_path):
    trajectories = [*planned, fast]
    outside = [_outside(puma, tr) for tr in trajectories]
    assert outside == [False, False, False, True]                 # the oracle's verdict
    model = budget_sweep_model(puma, trajectories, swept, tolerance=0.01, guarantee="region",
                               explicit="never", held_out=[fast, planned[1]])
    per = model.validation["per_trajectory"]
    assert per["covered"] == [not o for o in outside]
    assert "outside the model's region" in per["coverage"][3]
    assert model.validation["held_out_inside_region"] == 1
    ds = with_budget_model(swept, model)
    np.testing.assert_array_equal(ds["merged_covered"].values, [1, 1, 1, 0])
    said = merged_guarantee(ds)
    assert [src for src, _, _ in said["outside"]] == ["twice-as-fast"]
    assert said["statement"] == model.guarantee.statement()
    # the guaranteed figure is over the three inside the region only
    rel = ds["merged_tau_error_relative_peak"].values
    assert said["worst"] == pytest.approx(rel[:3].max(), rel=1e-12)
    # the report says which is not covered, and never that the bound holds on every swept one
    from gd_analyze.report.sweep import sweep_context
    from gd_analyze.store.schema import write_dataset

    ctx = sweep_context(ds)
    assert "twice-as-fast" in ctx["summary"] and "not covered by the proof" in ctx["summary"]
    assert "3 of the 4 swept trajectories lie in the region" in ctx["summary"]
    for text in (ctx["summary"], ctx["merged_text"], ctx["error_text"], *ctx["captions"].values()):
        assert "on every swept trajectory" not in text
    write_dataset(ds, tmp_path / "sweep.h5")                       # stores and reads back
    import xarray as xr

    with xr.open_dataset(tmp_path / "sweep.h5") as back:
        assert merged_guarantee(back)["outside"] == said["outside"]


def test_default_is_region_where_the_robot_gives_limits(puma, planned, fast, swept):
    model = budget_sweep_model(puma, [*planned, fast], swept, tolerance=0.01, explicit="never")
    assert model.guarantee.kind == "region"
    # --guarantee trajectory keeps the merge on the trajectories (it needs their peaks)
    from gd_analyze.errors import InputError

    with pytest.raises(InputError, match="recursive_peaks"):
        budget_sweep_model(puma, [*planned, fast], swept, guarantee="trajectory")
    with pytest.raises(ValueError, match="guarantee"):
        budget_sweep_model(puma, [*planned, fast], swept, guarantee="everywhere")


def test_form_explicit_over_the_region_is_the_exact_model(puma, planned, swept, fast):
    """Never a pruned explicit model under a region guarantee: --form explicit gives the
    exact one, bound 0, equal to rnea to round-off."""
    trajectories = [*planned, fast]
    model = budget_sweep_model(puma, trajectories, swept, tolerance=0.05, form="explicit",
                               guarantee="region")
    assert model.form == "explicit" and model.guarantee.kind == "region"
    assert np.all(np.asarray(model.guarantee.bound) == 0) and model.bound == [0.0] * puma.n
    scale = np.asarray(model.guarantee.scale)
    for tr in trajectories[:3]:
        err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - _rnea(puma, tr)).max(axis=0)
        assert np.all(err <= 1e-9 * scale)


def test_merged_choices_say_which_elements_the_dropped_parts_change(puma, planned, fast, swept):
    """The recursive merged model's choices read "both" everywhere although its
    dropped pairs change some elements. Oracle: its D_s and h_s against Pinocchio's crba and
    nonLinearEffects (minus gravity) at every set point of the swept trajectories: "pruned"
    exactly where some set point differs beyond round-off of the element's scale there."""
    from gd_analyze.ranking.ranking import element_labels

    trajectories = [*planned, fast]
    model = budget_sweep_model(puma, trajectories, swept, tolerance=0.05, guarantee="region",
                               explicit="never")
    assert model.form == "recursive" and model.recursive.dropped.any()
    pm = pinocchio_model(puma)
    data = pm.createData()
    fns = model.functions().numpy()
    n = puma.n
    iu = np.triu_indices(n)
    diff, scale = 0.0, 0.0
    for tr in trajectories:
        D = np.array([pin.crba(pm, data, q).copy() for q in tr.q])
        D = np.triu(D) + np.triu(D, 1).transpose(0, 2, 1)
        g = np.array([pin.computeGeneralizedGravity(pm, data, q).copy() for q in tr.q])
        h = np.array([pin.nonLinearEffects(pm, data, q, v).copy()
                      for q, v in zip(tr.q, tr.qd)]) - g
        tau = _rnea(puma, tr)
        D_s = np.asarray(fns["inertia"](tr.q), float).reshape(-1, n, n)
        h_s = np.asarray(fns["velocity_terms"](tr.q, tr.qd), float).reshape(-1, n)
        diff = np.maximum(diff, np.concatenate([np.abs(D_s - D).max(axis=0)[iu],
                                                np.abs(h_s - h).max(axis=0)]))
        d = np.sqrt(np.einsum("kii->ki", D))
        scale = np.maximum(scale, np.concatenate([(d[:, iu[0]] * d[:, iu[1]]).max(axis=0),
                                                  np.abs(tau).max(axis=0)]))
    changed = diff > 1e-9 * scale
    choices = [model.choices[lab] for lab in element_labels(n)]
    assert set(choices) == {"both", "pruned"}
    assert [c == "pruned" for c in choices] == changed.tolist(), (choices, diff / scale)
    # the stored dataset and its report sentence say the same
    ds = with_budget_model(swept, model)
    assert [str(v) for v in ds["merged_choice"].values] == choices


def test_the_check_on_the_workers_of_a_model_built_ahead_is_each_trajectorys(
        puma, planned, fast, swept, client):
    """The region model built before the ranking is known (as the command line builds it
    while the workers rank), then measured by the workers one trajectory per task: each
    swept and held-out trajectory's peak error is that against Pinocchio's rnea, and the
    model, its errors and verdicts are those measured in this process."""
    trajectories = [*planned, fast]
    settings = {"tolerance": 0.01, "guarantee": "region", "explicit": "never"}
    prepared = budget_region_model(puma, trajectories, **settings)
    errors = WorkerErrors(client, 1)
    model = budget_sweep_model(puma, trajectories, swept, held_out=[planned[2]],
                               prepared=prepared, errors=errors, **settings)
    assert errors.tasks == 5                              # 4 swept + 1 held out
    here = budget_sweep_model(puma, trajectories, swept, held_out=[planned[2]], **settings)
    np.testing.assert_array_equal(model.recursive.dropped, here.recursive.dropped)
    per, per_here = model.validation["per_trajectory"], here.validation["per_trajectory"]
    assert per["covered"] == per_here["covered"] and per["coverage"] == per_here["coverage"]
    for k, tr in enumerate(trajectories):
        ref = _rnea(puma, tr)
        err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - ref).max(axis=0)
        np.testing.assert_allclose(per["peak_abs_error"][k], err, rtol=0,
                                   atol=1e-9 * np.abs(ref).max())
        np.testing.assert_allclose(per["peak_abs_error"][k], per_here["peak_abs_error"][k],
                                   rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    held = model.validation["held_out"]
    ref = _rnea(puma, planned[2])
    err = np.abs(model.torque(planned[2].q, planned[2].qd, planned[2].qdd) - ref).max(axis=0)
    np.testing.assert_allclose(held["peak_abs_error"], err, rtol=0,
                               atol=1e-9 * np.abs(ref).max())
    assert model.validation["held_out_inside_region"] == 1
    assert budget_region_model(puma, trajectories, tolerance=0.01,
                               guarantee="trajectory") is None


def test_a_model_that_cannot_travel_is_measured_here(puma, planned, client):
    """A reference (or model) holding an object that cannot be serialized (here a lock, as a
    compiled function of this process) is measured in this process, with the same errors as
    per_trajectory_errors and no task submitted."""
    import threading

    from gd_analyze.simplify.sweep_model import per_trajectory_errors

    settings = {"tolerance": 0.01, "guarantee": "region", "explicit": "never"}
    model = budget_region_model(puma, planned, **settings)[0]
    pin_model = pinocchio_model(puma)
    lock = threading.Lock()

    def reference(q, qd, qdd):
        with lock:
            data = pin_model.createData()
            return np.array([pin.rnea(pin_model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])

    errors = WorkerErrors(client, 1)
    got = errors(model, planned, reference)
    want = per_trajectory_errors(model, planned, reference)
    assert errors.tasks == 0
    for a, b in zip(got, want):
        np.testing.assert_array_equal(a, b)


def test_the_workers_check_in_one_task_each_finds_a_trajectory_above_the_budget(
        puma, planned, fast, client):
    """By default the workers measure a merged model in one task per worker, each on all its
    trajectories' set points at once, with the errors measured in this process (to
    round-off); planted: a
    model that drops every pair (its torque 0) under the region model's bound, which the
    check must find above EPS on the swept trajectories inside the region, each error that
    against Pinocchio's rnea."""
    trajectories = [*planned, fast]
    settings = {"tolerance": 0.01, "guarantee": "region", "explicit": "never"}
    model, reference = budget_region_model(puma, trajectories, **settings)
    workers = len(client.scheduler_info()["workers"])
    errors = WorkerErrors(client)
    got = errors(model, [*trajectories, planned[2]], reference)
    assert errors.tasks == min(workers, len(trajectories) + 1)
    want = per_trajectory_errors(model, [*trajectories, planned[2]], reference)
    for a, b in zip(got, want):         # the model's arithmetic on other batches: round-off
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * want[2].max())
    # planted: the first plan ten times as fast, far outside the region, where the dropped
    # velocity pairs grow 100-fold past the bound proved inside it
    tr = planned[0]
    flung = dataclasses.replace(tr, t=tr.t / 10, qd=10 * tr.qd, qdd=100 * tr.qdd,
                                source="ten-times-as-fast")
    g = model.guarantee
    scale, bound = np.asarray(g.scale, float), np.asarray(g.bound, float)
    errors = WorkerErrors(client)
    checked = sweep_validation(model, [*planned, flung], np.broadcast_to(scale, (4, puma.n)),
                               bound / scale, reference=reference, errors=errors)
    assert errors.tasks == min(workers, 4)
    per = np.asarray(checked["per_trajectory"]["peak_abs_error"])
    for k, t in enumerate([*planned, flung]):
        ref = _rnea(puma, t)
        err = np.abs(model.torque(t.q, t.qd, t.qdd) - ref).max(axis=0)
        np.testing.assert_allclose(per[k], err, rtol=0, atol=1e-9 * np.abs(ref).max())
    assert (per[:3] / scale).max() <= (bound / scale).max() <= 0.01
    assert (per[3] / scale).max() > 0.01
    assert checked["worst_scaled_error"] == (per[3] / scale).max()


def test_worker_errors_cut_by_set_points(client):
    """Without a batch, as many tasks as workers, more where a task would exceed
    ERRORS_SETPOINTS_MAX set points; consecutive, every trajectory once."""
    workers = len(client.scheduler_info()["workers"])
    trs = [SimpleNamespace(q=np.zeros((n, 2))) for n in (5, 1, 7, 3, 9, 2)]
    batches = WorkerErrors(client)._batches(trs)
    assert len(batches) == min(workers, len(trs))
    assert [t for b in batches for t in b] == trs
    big = [SimpleNamespace(q=np.zeros((ERRORS_SETPOINTS_MAX // 2 + 1, 1)))
           for _ in range(4)]
    batches = WorkerErrors(client)._batches(big)
    assert len(batches) >= 3 and [t for b in batches for t in b] == big
    assert all(sum(t.q.shape[0] for t in b) <= ERRORS_SETPOINTS_MAX * 1.5 for b in batches)
