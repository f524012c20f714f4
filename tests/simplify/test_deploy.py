"""The deployed simplified model: the cheaper of the pruned recursive and explicit
models, its file, and the guarantee it states.

Oracles: Pinocchio's rnea (the torques), the operation counts of the models compared (each
counted from its own program), and the model file itself (hand edits are refused).
"""

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, SHIPPED

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.dynamics.base_parameters import base_parameters, random_states
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions, SimplifyOptions
from gd_analyze.store.model_file import load_model
from gd_analyze.trajectory.trajectory import read_trajectory


def _rnea(robot, q, qd, qdd):
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model

    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, *x).copy() for x in zip(q, qd, qdd)])


def _ops(c):
    return int(c["multiplications"]) + int(c["additions"])


@pytest.fixture(scope="module")
def puma_run(shared_main):
    # shared, read only (tests/store/test_model_trust.py reads the same run)
    out = shared_main("puma560", SHIPPED, "--guarantee", "trajectory")
    return out, json.loads((out / "simplified_model.json").read_text())


def test_region_model_by_default_bound_within_the_region_budget(shared_main):
    """The default PUMA model carries the region guarantee: its bound is within EPS of the
    region's scale, holds on the shipped trajectory (inside the region) against rnea, and it
    is cheaper than the exact recursive model."""
    out = shared_main("puma560", SHIPPED)      # the default run, read only
    spec = json.loads((out / "simplified_model.json").read_text())
    g = spec["guarantee"]
    assert g["kind"] == "region" and "(proved" in g["statement"]
    assert spec["form"] == "recursive"
    assert _ops(spec["cost"]) < _ops(spec["costs"]["exact recursive"])
    scale, bound = np.array(g["scale"]), np.array(g["bound"])
    assert np.all(bound <= 0.01 * scale * (1 + 1e-12))
    robot = load_robot("puma560")
    traj = read_trajectory(SHIPPED, 6)
    ref = _rnea(robot, traj.q, traj.qd, traj.qdd)
    assert np.all(np.abs(ref).max(axis=0) <= scale * (1 + 1e-9))   # the trajectory is inside
    model = load_model(out / "simplified_model.json")
    err = np.abs(model.torque(traj.q, traj.qd, traj.qdd) - ref).max(axis=0)
    assert np.all(err <= bound + 64 * np.finfo(float).eps * scale.max())


def test_deployed_model_is_the_cheapest_within_budget(puma_run):
    out, spec = puma_run
    costs = spec["costs"]
    deployed = _ops(spec["cost"])
    assert deployed == min(_ops(costs["recursive, budget"]), _ops(costs["explicit, budget"]))
    assert deployed <= _ops(costs["exact recursive"]) < _ops(costs["newton-euler"])
    assert _ops(costs["exact recursive"]) <= 338           # the published customized N-E
    robot = load_robot("puma560")
    traj = read_trajectory(SHIPPED, 6)
    ref = _rnea(robot, traj.q, traj.qd, traj.qdd)
    scale = np.abs(ref).max(axis=0)
    model = load_model(out / "simplified_model.json")
    err = np.abs(model.torque(traj.q, traj.qd, traj.qdd) - ref).max(axis=0)
    assert np.all(err <= np.array(spec["bound"]) + 1e-9 * scale)
    assert np.all(np.array(spec["bound"]) <= 0.01 * scale * (1 + 1e-9))


def test_recursive_file_round_trip_and_hand_edits(puma_run, tmp_path):
    out, spec = puma_run
    assert spec["form"] == "recursive"
    model = load_model(out / "simplified_model.json")
    robot = model.robot
    q, qd, qdd = random_states(robot, 20, 3)
    exact = _rnea(robot, q, qd, qdd)
    # the deployed program is the one the file describes: rebuild it from the pairs
    dropped = {tuple(p) for key in ("dropped", "dropped_round_off")   # named, and round-off
               for p in spec["recursive"].get(key, [])}
    assert len(dropped) == int(model.recursive.dropped.sum())
    np.testing.assert_allclose(model.torque(q, qd, qdd),
                               load_model(out / "simplified_model.json")
                               .torque(q, qd, qdd), rtol=0, atol=0)
    # with nothing dropped the file's model is exact
    spec0 = json.loads(json.dumps(spec))
    spec0["recursive"]["dropped"] = []
    del spec0["cost"]                   # the stored count is the pruned program's
    p0 = tmp_path / "exact.json"
    p0.write_text(json.dumps(spec0))
    tau0 = load_model(p0).torque(q, qd, qdd)
    assert np.all(np.abs(tau0 - exact).max(axis=0) <= 1e-10 * np.abs(exact).max(axis=0))
    # a base parameter value edited by 1.5 is refused, as is an unknown pair
    for edit, column in ((lambda s: s["recursive"]["beta"].__setitem__(
            0, 1.5 * s["recursive"]["beta"][0]), "recursive.beta"),
            (lambda s: s["recursive"]["dropped"].append(["XX9", "inertial"]),
             "recursive.dropped")):
        bad = json.loads(json.dumps(spec))
        edit(bad)
        path = tmp_path / "bad.json"
        path.write_text(json.dumps(bad))
        with pytest.raises(Exception) as exc:
            load_model(path)
        assert column in str(exc.value)


@pytest.mark.parametrize("explicit", ["never", "always"])
def test_explicit_option(explicit, tmp_path):
    out = tmp_path / explicit
    assert main(["puma560", str(SHIPPED), "-o", str(out), "--no-report", "-q",
                 "--explicit", explicit]) == 0
    spec = json.loads((out / "simplified_model.json").read_text())
    assert ("explicit, full" in spec["costs"]) == (explicit == "always")
    if explicit == "never":
        assert spec["form"] == "recursive"


@pytest.mark.slow
def test_seven_joints_skip_the_expansion_and_stay_exact_at_eps_0(tmp_path, monkeypatch):
    """The Panda: no explicit expansion by default (its estimate is expensive), and at
    --tolerance 0 the deployed model is exact off the trajectory too."""
    import gd_analyze.store.explicit_cache as cache

    def refuse(*a, **k):
        raise AssertionError("the explicit model was derived")

    monkeypatch.setattr(cache, "explicit_terms", refuse)
    csv = ROOT / "data" / "panda_trajectory.csv"
    out = tmp_path / "panda"
    assert main(["panda", str(csv), "-o", str(out), "--no-report", "-q",
                 "--tolerance", "0"]) == 0
    spec = json.loads((out / "simplified_model.json").read_text())
    assert spec["form"] == "recursive" and spec["recursive"]["dropped"] == []
    assert _ops(spec["cost"]) <= 648
    model = load_model(out / "simplified_model.json")
    q, qd, qdd = random_states(model.robot, 200, 7)
    ref = _rnea(model.robot, q, qd, qdd)
    err = np.abs(model.torque(q, qd, qdd) - ref).max(axis=0)
    assert np.all(err <= 1e-10 * np.abs(ref).max(axis=0))


def test_report_text_follows_the_model(tmp_path):
    """The summary and Sec. 5.3 name the form and count what the built model drops."""
    from gd_analyze.report.main_context import report_context

    traj = read_trajectory(SHIPPED, 6)
    robot = load_robot("puma560")
    for eps in (0.0, 0.05):
        a = analyze(robot, traj, AnalysisOptions(verify=False, formulations=False, simplify=SimplifyOptions(tolerance=eps, explicit="never")))
        ctx = report_context(a.dataset)
        rec = a.model.recursive
        live = rec.relative_peak >= 1e-12
        dropped, pairs = int((rec.dropped & live).sum()), int(live.sum())
        b = base_parameters(robot).rank
        assert f"recursive Newton-Euler model on {b} base parameters" in ctx["summary"]
        if dropped:
            assert f"of the {pairs} inertial, velocity and gravity parts" in ctx["summary"]
            assert f"it drops {dropped}," in ctx["summary"]      # then what it does with c
            where = "over the joint-limit region" if a.model.guarantee.kind == "region" \
                else "on this trajectory"
            assert f"Of the {pairs} (parameter, part) pairs that contribute {where}, " \
                f"{dropped} are dropped" in ctx["simplified_model"]["text"]
        else:
            assert f"of the {pairs} inertial, velocity and gravity parts" in ctx["summary"]
            assert "it drops none: it is exact." in ctx["summary"]
            assert f"of the {pairs} (parameter, part) pairs that contribute, none is " \
                "dropped; the model is exact" in ctx["simplified_model"]["text"]
        assert ctx["choices_heading"].endswith("Base parameters and the parts kept")


def test_deployed_model_never_costs_more_than_a_model_within_budget(tmp_path):
    """finger_edu (example-robot-data): pruning its explicit model raised the count (105
    against the full model's 101); the deployed model is the cheapest one within the budget."""
    import importlib.metadata

    root = importlib.metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots")
    urdf = root / "finger_edu_description" / "robots" / "finger_edu.urdf"
    csv = tmp_path / "f.csv"
    assert main(["plan", str(urdf), "-o", str(csv)]) == 0
    assert main([str(urdf), str(csv), "-o", str(tmp_path / "o"), "--no-report", "-q",
                 "--guarantee", "trajectory"]) == 0
    spec = json.loads((tmp_path / "o" / "simplified_model.json").read_text())
    assert spec["form"] in ("explicit", "recursive")
    within = [c for key, c in spec["costs"].items() if key != "newton-euler"]
    assert _ops(spec["cost"]) == min(_ops(c) for c in within)
    # by default the model must hold over the region: the cheapest of the proved models
    # (the recursive one pruned over the region, the exact explicit and recursive ones)
    assert main([str(urdf), str(csv), "-o", str(tmp_path / "r"), "--no-report", "-q"]) == 0
    spec = json.loads((tmp_path / "r" / "simplified_model.json").read_text())
    assert spec["guarantee"]["kind"] == "region"
    proved = [spec["costs"][k] for k in ("recursive, budget", "explicit, full", "exact recursive")]
    assert _ops(spec["cost"]) == min(_ops(c) for c in proved)
    model = load_model(tmp_path / "r" / "simplified_model.json")
    q, qd, qdd = random_states(model.robot, 50, 4)
    assert np.abs(model.torque(q, qd, qdd) - _rnea(model.robot, q, qd, qdd)).max() <= (
        np.array(spec["guarantee"]["bound"]).max() + 1e-9)


def test_a_cheaper_explicit_model_not_deployed_is_explained(shared_main):
    """The drives arm's pruned explicit model counts fewer operations than the
    deployed recursive one; the stored sentence says why it is not deployed (its bound holds
    on the trajectory only; the recursive model's is proved over the region), as the model
    file's guarantee (oracle) says."""
    import re

    import xarray as xr

    out = shared_main("puma560-drives", SHIPPED)     # the default run, read only
    with xr.open_dataset(out / "results.h5") as ds:
        said = str(ds.attrs["simplified_form_note"])
    spec = json.loads((out / "simplified_model.json").read_text())
    assert spec["form"] == "recursive" and spec["guarantee"]["kind"] == "region"
    rec, ex = (int(v.replace(",", "")) for v in re.search(
        r"recursive one \(([\d,]+) operations against the pruned explicit one's ([\d,]+)",
        said).groups())
    assert ex < rec                     # the case: a cheaper model left out
    assert "holds on this trajectory only" in said and "proved over the joint-limit region" \
        in said, said


def test_the_model_file_s_choices_are_those_of_results_h5(puma_run, tmp_path):
    """simplified_model.json said "both" for every element of the recursive model
    while results.h5 said "pruned" where its dropped pairs change the element. Oracle: D_s
    of the model against Pinocchio's crba, element by element, on the trajectory."""
    import pinocchio as pin
    import xarray as xr

    from gd_analyze.dynamics.pinocchio import pinocchio_model

    out, spec = puma_run
    with xr.open_dataset(out / "results.h5") as ds:
        stored = dict(zip((str(v) for v in ds["element"].values),
                          (str(v) for v in ds["choice"].values)))
    assert spec["form"] == "recursive" and spec["choices"] == stored
    assert "pruned" in stored.values() and "both" in stored.values()
    robot = load_robot("puma560")
    model = load_model(out / "simplified_model.json")
    traj = read_trajectory(SHIPPED, 6)
    D_s = np.asarray(model.functions().numpy()["inertia"](traj.q), float).reshape(-1, 6, 6)
    pm = pinocchio_model(robot)
    data = pm.createData()
    D = np.array([pin.crba(pm, data, q) for q in traj.q])
    D = np.triu(D) + np.triu(D, 1).transpose(0, 2, 1)
    scale = np.sqrt(np.einsum("kii,kjj->ij", D, D) / len(D))        # sqrt(D_ii D_jj)
    for i in range(6):
        for j in range(i, 6):
            changed = np.abs(D_s[:, i, j] - D[:, i, j]).max() > 1e-9 * scale[i, j]
            assert changed == (stored[f"D{i + 1}{j + 1}"] == "pruned"), (i, j)
    spec["form"] = "explicit"
    spec.pop("recursive")
    bad = tmp_path / "explicit.json"
    bad.write_text(json.dumps(spec))
    with pytest.raises(Exception, match="pruned"):
        load_model(bad)


def test_a_trajectory_model_s_sampled_error_is_pinocchios_over_the_samples():
    """The stored ``region_sampled_error`` of a model pruned on a trajectory, found
    by sampling only (no certification), is the largest error of the model against
    Pinocchio's rnea over the sampled positions of the region, every vertex of the velocity
    box and the worst acceleration in its box, relative to s_i there; s_i is |rnea_i| at the
    state where it was found."""
    import itertools

    from gd_analyze.simplify.deploy import build_recursive, robot_region
    from gd_analyze.simplify.region_memo import region_values

    puma = load_robot("puma560")
    traj = read_trajectory(SHIPPED, 6)
    region, _ = robot_region(puma)
    model, _ = build_recursive(puma, traj.q, traj.qd, traj.qdd, tolerance=0.05,
                               sample_region=region)
    stored = np.asarray(model.guarantee.region_sampled_error)
    q, _, scale, where = region_values(puma, base_parameters(puma), region)
    n, B = 6, q.shape[0]
    verts = np.array(list(itertools.product([-1.0, 1.0], repeat=n))) * region.qd_max
    zero, eye = np.zeros((B, n)), np.eye(n)

    def err(qq, qd, qdd):
        return model.torque(qq, qd, qdd) - _rnea(puma, qq, qd, qdd)

    at_rest = err(q, zero, zero)                                   # gravity's error
    inertial = sum(np.abs(err(q, zero, np.tile(eye[j], (B, 1))) - at_rest) * region.qdd_max[j]
                   for j in range(n))                              # sum_j |M_ij| qdd_max_j
    quad = np.max([np.abs(err(q, np.tile(v, (B, 1)), zero)) for v in verts], axis=0)
    expected = (quad + inertial).max(axis=0) / scale
    assert stored.max() > 1e-3                                     # pairs were dropped
    np.testing.assert_allclose(stored, expected, rtol=1e-6, atol=1e-9)
    ref = _rnea(puma, where[:, :n], where[:, n:2 * n], where[:, 2 * n:])
    np.testing.assert_allclose(np.abs(ref[np.arange(n), np.arange(n)]), scale, rtol=1e-9)


def test_a_search_is_made_once_per_process_for_the_same_inputs_and_entry(puma):
    """region_search's in-process memo: the same inputs and stored entry give the first
    search's result; it equals a search made afresh (the memo emptied); another region
    (its source alone differs) or EPS is searched on its own; a bad stored entry is warned
    of at every call, never kept."""
    import dataclasses
    import warnings

    from gd_analyze.cache import CacheWarning
    from gd_analyze.simplify import deploy
    from gd_analyze.simplify.region_memo import Derivations

    base = base_parameters(puma)
    region = deploy.robot_region(puma, None)[0]
    deploy._SEARCHED.clear()
    first = deploy.region_search(puma, base, region, 0.01, sampled=False)
    assert deploy.region_search(puma, base, region, 0.01, sampled=False) is first
    deploy._SEARCHED.clear()
    fresh = deploy.region_search(puma, base, region, 0.01, sampled=False)
    assert fresh is not first
    np.testing.assert_array_equal(fresh.rec.dropped, first.rec.dropped)
    other = dataclasses.replace(region, source="the user's --region")
    assert deploy.region_search(puma, base, other, 0.01, sampled=False) is not fresh
    assert deploy.region_search(puma, base, region, 0.05, sampled=False) is not fresh
    assert len(deploy._SEARCHED) <= deploy._SEARCHED_MAX

    # an entry whose pairs are all dropped cannot fit the budget: warned of each time
    bad = {"dropped": np.ones((base.rank, 3), bool), "whole": np.ones(base.rank, bool),
           "exact_forms": ("products",) * puma.n, "pruned_forms": None}
    store = Derivations(read_search=lambda *args: (bad, "an entry"))
    for _ in range(2):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            found = deploy.region_search(puma, base, region, 0.01, sampled=False,
                                         derive=store)
        assert any(issubclass(w.category, CacheWarning) for w in caught)
        np.testing.assert_array_equal(found.rec.dropped, fresh.rec.dropped)


def test_arms_above_the_decomposition_s_joint_limit_are_searched_without_it():
    """The region search of an arm with more joints than ``DECOMPOSED_MAX_JOINTS`` never runs
    the decomposed bound's branch and bound: the Panda (7 joints, whose search runs it at the
    shipped limit) under a limit of 6 searches without it, and finds the model the search
    without the decomposition finds (``DECOMPOSE`` False)."""
    from unittest import mock

    import gd_analyze.certify.certify as certify
    import gd_analyze.simplify.deploy as deploy

    robot = load_robot("panda")
    base = base_parameters(robot)
    region = deploy.robot_region(robot)[0]
    assert robot.n > 6 and deploy.DECOMPOSED_MAX_JOINTS >= robot.n

    def refused(*args, **kwargs):
        raise AssertionError("the decomposed bound was searched")

    with mock.patch.object(certify, "decomposed_search", refused), \
            mock.patch.object(deploy, "DECOMPOSED_MAX_JOINTS", 6):
        rec, guarantee = deploy.region_model(robot, base, region, 0.01)
    with mock.patch.object(deploy, "DECOMPOSE", False):
        plain, plain_guarantee = deploy.region_model(robot, base, region, 0.01)
    assert np.array_equal(rec.dropped, plain.dropped)
    assert np.array_equal(guarantee.bound, plain_guarantee.bound)
    assert not guarantee.decomposed


def test_a_second_eps_read_from_the_ladders_entry_writes_a_model_that_loads(tmp_path,
                                                                            monkeypatch):
    """A run at EPS 0.01 keeps its ladder's search at EPS 0.05; a run at 0.05 reads it, and
    where its proved screen then deploys the exact model (a random 6-joint chain of
    analysis/main_job_scaling.py --fuzz 6:2), the file it writes is the model load_model
    rebuilds (its cost is the program's, not one built with the entry's pruned forms)."""
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    urdf = Path(__file__).with_name("random_chain_6.urdf")
    csv = tmp_path / "plan.csv"
    assert main(["plan", str(urdf), "-o", str(csv)]) == 0
    for eps in ("0.01", "0.05"):
        out = tmp_path / eps
        assert main([str(urdf), str(csv), "--tolerance", eps, "--no-report", "-q",
                     "-o", str(out)]) == 0
        model = load_model(out / "simplified_model.json")      # the stored cost re-checked
        assert model.tolerance == float(eps)
