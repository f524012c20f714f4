"""The sampled pre-screen of the region model: where no region model could save enough
operations, the exact recursive model is deployed without certification, and its guarantee
and D_s proof still hold.

Oracles: Pinocchio's rnea and crba at random states of the region, the operation counts of
the programs, and the sampled magnitudes of the pairs (each a lower bound of its enclosure).
"""

import json

import numpy as np
import pytest
from conftest import SHIPPED
from robot_files import random_chain

from gd_analyze.certify import regressor_bounds
from gd_analyze.certify.screen import MIN_SAVING
from gd_analyze.cli import main
from gd_analyze.simplify.deploy import robot_region
from gd_analyze.store.model_file import load_model

TWO_LINK_CSV = "t,q1,q2\n0,0,0\n0.1,0.1,0.05\n0.2,0.2,0.1\n0.3,0.3,0.2\n0.4,0.35,0.25\n"


def _pinocchio(robot):
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model

    model = pinocchio_model(robot)
    return pin, model, model.createData()


def _region_states(region, count, seed=1):
    rng = np.random.default_rng(seed)
    q = rng.uniform(region.q_min, region.q_max, (count, region.q_min.size))
    qd = rng.uniform(-1, 1, q.shape) * region.qd_max
    qdd = rng.uniform(-1, 1, q.shape) * region.qdd_max
    return q, qd, qdd


def test_no_saving_takes_the_early_exit_with_a_proved_exact_model(tmp_path, monkeypatch,
                                                                   capsys):
    """The two-link arm: no region model can save an operation, so the region is not
    certified; the exact recursive model is deployed with bound 0 under the region guarantee,
    its torque is rnea's at random states of the region, its D_s proof holds under crba's
    eigenvalues, and every output says why, with the numbers."""
    import gd_analyze.certify.certify as certify_module

    def refused(*args, **kwargs):
        raise AssertionError("the region was certified")
    monkeypatch.setattr(certify_module, "certify", refused)
    # a derivation cache of its own: a search another test stored for the two-link arm (a
    # sweep's) is read instead of screening, and says nothing of the screen
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    csv = tmp_path / "t.csv"
    csv.write_text(TWO_LINK_CSV)
    out = tmp_path / "out"
    assert main(["two-link", str(csv), "-o", str(out), "--no-report"]) == 0
    said = capsys.readouterr().out
    assert "region certification skipped: a region model could save at most about 0 %" in said
    assert "threshold of 2 %" in said
    spec = json.loads((out / "simplified_model.json").read_text())
    screen = spec["provenance"]["region_screen"]
    assert screen["skipped"] and screen["possible_saving"] < screen["threshold"] == MIN_SAVING
    assert spec["form"] == "recursive"
    assert spec["cost"] == spec["costs"]["exact recursive"]
    g = spec["guarantee"]
    assert g["kind"] == "region" and "(proved" in g["statement"]
    assert np.all(np.array(g["bound"]) == 0) and "proved identically zero" in g["method"]

    import xarray as xr
    with xr.open_dataset(out / "results.h5", engine="h5netcdf") as ds:
        assert float(ds.attrs["simplified_region_possible_saving"]) < \
            float(ds.attrs["simplified_region_saving_threshold"]) == MIN_SAVING
        assert "certification and search were skipped" in ds.attrs["simplified_region_screen"]
        assert "not certified" in ds.attrs["simplified_ladder_skipped"]

    model = load_model(out / "simplified_model.json")        # its claim checked on reading
    robot = model.robot
    region, _ = robot_region(robot)
    q, qd, qdd = _region_states(region, 200)
    pin, pm, data = _pinocchio(robot)
    ref = np.array([pin.rnea(pm, data, *x).copy() for x in zip(q, qd, qdd)])
    scale = np.asarray(model.guarantee.scale)
    assert np.all(np.abs(model.torque(q, qd, qdd) - ref) <= 1e-9 * scale)
    check = spec["inertia_check"]
    assert check["proved"] and check["where"] == "region" and check["lower_bound"] > 0
    lam = min(np.linalg.eigvalsh(pin.crba(pm, data, x).copy()).min() for x in q)
    assert check["lower_bound"] <= lam


def test_the_puma_main_job_is_searched(shared_main):
    """The PUMA 560's default run (its region model counts 308 operations against the exact
    320) is certified and searched: no screen in its provenance, pairs dropped."""
    out = shared_main("puma560", SHIPPED)      # the default run, read only
    spec = json.loads((out / "simplified_model.json").read_text())
    assert "region_screen" not in spec["provenance"]
    assert spec["guarantee"]["kind"] == "region"
    assert np.any(spec["recursive"]["dropped"])


def test_a_skipped_search_still_leaves_out_the_pairs_that_are_identically_zero(tmp_path,
                                                                             monkeypatch):
    """The PUMA 560 at EPS = 0: the screen finds that no region model saves 2 % and skips the
    search; the model deployed leaves out the (base parameter, part) pairs that are
    identically zero, so it counts fewer operations than the exact program, and its torque is
    still rnea's at random states of the region."""
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.model.robots import load_robot
    from gd_analyze.simplify.deploy import build_recursive
    from gd_analyze.symbolic.recursive import recursive_program

    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    robot = load_robot("puma560")
    region, _ = robot_region(robot)
    q, qd, qdd = _region_states(region, 300)
    model, _ = build_recursive(robot, q[:5], qd[:5], qdd[:5], tolerance=0.0, region=region)
    assert model.provenance["region_screen"]["skipped"]
    assert np.any(model.recursive.dropped)
    exact = recursive_program(robot, base_parameters(robot).values).cost()
    ops = model.cost["multiplications"] + model.cost["additions"]
    assert ops < exact["multiplications"] + exact["additions"]
    pin, pm, data = _pinocchio(robot)
    ref = np.array([pin.rnea(pm, data, *x).copy() for x in zip(q, qd, qdd)])
    scale = np.asarray(model.guarantee.scale)
    assert np.all(np.abs(model.torque(q, qd, qdd) - ref) <= 1e-9 * scale)
    assert np.all(np.asarray(model.guarantee.bound) == 0)


@pytest.mark.slow
def test_a_proved_saving_below_the_threshold_deploys_the_exact_model_unbuilt(
        tmp_path, monkeypatch, capsys):
    """A random 5-joint chain at EPS = 0.01: the sampled pre-screen finds that a region model
    could save more than 2 %, so the region is certified and searched; the pairs the search
    drops under the proved bounds save less than 2 % by the quick counts (counted here on the
    programs themselves). The pruned model's program is then never built; the exact recursive
    model is deployed with bound 0 under the region guarantee, its torque is rnea's at random
    states of the region, the ladder is built (the region is certified), and every output says
    why with the numbers, without claiming that the certification was skipped."""
    import xarray as xr

    import gd_analyze.symbolic.pruning as pruning_module
    import gd_analyze.symbolic.recursive_model as recursive_model_module
    from gd_analyze.certify.screen import screen_region
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.model.robot_file import robot_toml
    from gd_analyze.simplify.deploy import region_search
    from gd_analyze.simplify.region_memo import region_magnitudes, region_values
    from gd_analyze.store.derivations import DERIVATIONS
    from gd_analyze.symbolic.pruning import part_values
    from gd_analyze.symbolic.recursive import parts_program

    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    # the joint sums in balls alone, as on chains of more than BOX_MAX_JOINTS joints: with the
    # balls intersected with interval boxes the search on this chain saves 2.2 %
    monkeypatch.setattr(regressor_bounds, "BOX_MAX_JOINTS", 0)
    robot = random_chain(5)
    base = base_parameters(robot)
    region, _ = robot_region(robot)
    sampled = screen_region(robot, base, region, region_values(robot, base, region), 0.01,
                            magnitudes=region_magnitudes(robot, base, region))
    assert not sampled.skip                              # the old exit does not apply
    searched = region_search(robot, base, region, 0.01, screen=False).rec.dropped
    assert searched.any()

    def quick(dropped):
        c = parts_program(robot, part_values(base, dropped), cse=False, search=False).cost()
        return c["multiplications"] + c["additions"]
    exact_quick = quick(np.zeros(searched.shape, bool))
    assert quick(searched) > (1 - MIN_SAVING) * exact_quick         # saves less than 2 %

    built = []
    original = pruning_module.pruned_choice

    def spy(robot_, base_, dropped, *args, **kwargs):
        built.append(np.array(dropped, bool))
        return original(robot_, base_, dropped, *args, **kwargs)
    monkeypatch.setattr(pruning_module, "pruned_choice", spy)
    monkeypatch.setattr(recursive_model_module, "pruned_choice", spy)

    toml = tmp_path / "chain.toml"
    toml.write_text(robot_toml(robot, ["random chain of 5 joints"]))
    t = np.linspace(0.0, 3.0, 31)
    arg = 0.7 * t[:, None] + np.arange(5)
    amp = np.where(np.asarray(robot.prismatic, bool), 0.1, 0.8)
    q, qd, qdd = amp * np.sin(arg), 0.7 * amp * np.cos(arg), -0.49 * amp * np.sin(arg)
    csv = tmp_path / "t.csv"
    header = ["t"] + [f"{k}{j + 1}" for k in ("q", "qd", "qdd") for j in range(5)]
    np.savetxt(csv, np.column_stack([t, q, qd, qdd]), delimiter=",", header=",".join(header),
               comments="")
    out = tmp_path / "out"
    capsys.readouterr()
    assert main([str(toml), str(csv), "-o", str(out), "--no-report"]) == 0
    said = capsys.readouterr().out
    assert built and not any(np.array_equal(d, searched) for d in built)

    line = next(x for x in said.splitlines() if x.startswith("pruned region model not built: "))
    assert "bounds proved over the region" in line and "below the threshold of 2 %" in line
    assert "certification skipped" not in said and "certification and search were" not in said
    spec = json.loads((out / "simplified_model.json").read_text())
    screen = spec["provenance"]["region_screen"]
    assert screen["proved"] and screen["skipped"]
    assert screen["possible_saving"] < screen["threshold"] == MIN_SAVING
    assert screen["exact_operations"] == exact_quick
    assert screen["best_operations"] == quick(searched)
    assert spec["form"] == "recursive"
    exact = spec["costs"]["exact recursive"]
    assert spec["cost"]["multiplications"] + spec["cost"]["additions"] <= \
        exact["multiplications"] + exact["additions"]
    g = spec["guarantee"]
    assert g["kind"] == "region" and "(proved" in g["statement"]
    assert np.all(np.array(g["bound"]) == 0) and "proved identically zero" in g["method"]
    assert "bounds proved over the region" in g["method"]
    with xr.open_dataset(out / "results.h5", engine="h5netcdf") as ds:
        assert int(ds.attrs["simplified_region_screen_proved"]) == 1
        assert float(ds.attrs["simplified_region_possible_saving"]) < MIN_SAVING
        assert "simplified_ladder_skipped" not in ds.attrs         # certified: built

    model = load_model(out / "simplified_model.json")        # its claim checked on reading
    qs, qds, qdds = _region_states(region, 200)
    pin, pm, data = _pinocchio(robot)
    ref = np.array([pin.rnea(pm, data, *x).copy() for x in zip(qs, qds, qdds)])
    scale = np.asarray(model.guarantee.scale)
    assert np.all(np.abs(model.torque(qs, qds, qdds) - ref) <= 1e-9 * scale)
    assert spec["inertia_check"]["proved"]
    ran = model.robot                          # as the job read it: its search, read back
    again = region_search(ran, base_parameters(ran), robot_region(ran)[0], 0.01,
                          derive=DERIVATIONS)
    assert again.forms is not None and again.screen.proved and again.screen.skip
    np.testing.assert_array_equal(again.rec.dropped, model.recursive.dropped)


def test_the_proved_screen_counts_the_pairs_left_after_the_inertia_restore(monkeypatch):
    """The screen of the pairs searched under the proved bounds, for a model to deploy, counts
    the pairs its proof of D_s would leave dropped: on the PUMA 560 at EPS 0.01 (its searched
    set saves more than MIN_SAVING by the quick counts), with the bar after the restore
    between the saving of its searched set and that of the set with every dropped inertial
    part restored (as a proof that needs them all would leave it; the restored parameters'
    other parts kept too where that counts fewer), the exact model is deployed and the screen
    says how many parameters were restored; for a ladder's rung (no proof of D_s: ``restore``
    False) the same set is built."""
    import gd_analyze.simplify.deploy as deploy
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.model.robots import load_robot
    from gd_analyze.symbolic.pruning import part_values
    from gd_analyze.symbolic.recursive import parts_program

    robot = load_robot("puma560")
    base = base_parameters(robot)
    region, _ = robot_region(robot)
    pb = deploy.certified(robot, base, region)
    rec, _ = deploy.region_model(robot, base, region, 0.01)
    dropped = np.asarray(rec.dropped, bool)
    inertial = dropped[:, 0] & ~pb.zero[:, 0]
    assert inertial.any()
    calls = []

    def restored(robot, base, dropped, rel, q_min, q_max):
        calls.append(1)
        out = np.array(dropped, bool)
        out[:, 0] &= pb.zero[:, 0]              # every inertial part restored
        return out
    monkeypatch.setattr(deploy, "inertia_restored", restored)

    def quick(d):
        c = parts_program(robot, part_values(base, d), cse=False, search=False).cost()
        return c["multiplications"] + c["additions"]
    left = dropped.copy()
    left[:, 0] &= pb.zero[:, 0]
    whole = left.copy()
    whole[inertial] = False
    exact = quick(np.zeros_like(dropped))
    best = min(quick(left), quick(whole))
    high, low = ((exact - c) / exact for c in (quick(dropped), best))
    assert high >= MIN_SAVING and high > low
    monkeypatch.setattr(deploy, "RESTORED_MIN_SAVING", 0.5 * (high + low))
    got = deploy._proved_exact(robot, base, region, 0.01, pb, dropped)
    assert got is not None and calls
    screen = got[2]
    assert screen.skip and screen.restored == int(inertial.sum())
    assert screen.best_operations == best and screen.exact_operations == exact
    assert f"inertial parts of {int(inertial.sum())} parameters restored" in screen.text()
    assert screen.to_dict()["restored"] == int(inertial.sum())
    assert np.all(got[0].bound == 0)
    calls.clear()
    assert deploy._proved_exact(robot, base, region, 0.01, pb, dropped, False) is None
    assert not calls
