"""The sampled pre-screen of the region model: where no region model could save enough
operations, the exact recursive model is deployed without certification, and its guarantee
and D_s proof still hold.

Oracles: Pinocchio's rnea and crba at random states of the region, the operation counts of
the programs, and the sampled magnitudes of the pairs (each a lower bound of its enclosure).
"""

import json

import numpy as np
from conftest import SHIPPED

from gd_analyze.certify.screen import MIN_SAVING
from gd_analyze.cli import main
from gd_analyze.jobs.deploy import robot_region
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
    from gd_analyze.jobs.deploy import build_recursive
    from gd_analyze.model.robots import load_robot
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
