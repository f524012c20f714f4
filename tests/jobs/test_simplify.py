"""The simplified explicit model in the main job, the CLI, the sweep and the report."""

import json

import numpy as np
import pinocchio as pin
import pytest
from conftest import SHIPPED, golden_run

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.store.model_file import load_model
from gd_analyze.trajectory.trajectory import read_trajectory


def _rnea(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("eps", ["0.01", "0.05"])
def test_main_job_model_within_tolerance_and_cheaper_than_newton_euler(capsys, eps,
                                                                       shared_main):
    from gd_analyze.dynamics.opcount import operation_counts

    # shared runs, read only: 0.01 is the default --tolerance (the default run)
    folder = shared_main("puma560", SHIPPED,
                         *(() if eps == "0.01" else ("--no-report", "--tolerance", eps)))
    spec = json.loads((folder / "simplified_model.json").read_text())
    assert spec["rule"] == "budget" and spec["tolerance"] == float(eps)
    ne = operation_counts(6)["newton-euler"]
    cost = spec["cost"]
    assert cost["multiplications"] + cost["additions"] < ne["multiplications"] + ne["additions"]
    full = spec["full_cost"]
    assert cost["multiplications"] + cost["additions"] < full["multiplications"] + \
        full["additions"]
    traj = read_trajectory(SHIPPED, 6)
    robot = load_robot("puma560")
    ref = _rnea(robot, traj.q, traj.qd, traj.qdd)
    scale = np.abs(ref).max(axis=0)
    ns = {}
    exec((folder / "simplified_model.py").read_text(), ns)     # numpy only, no gd_analyze
    for tau in (ns["tau"](traj.q, traj.qd, traj.qdd),
                load_model(folder / "simplified_model.json").torque(
                    traj.q, traj.qd, traj.qdd)):
        assert (np.abs(tau - ref).max(axis=0) <= float(eps) * scale * (1 + 1e-9)).all()
    for name in ("simplified_model.c", "simplified_model.h"):
        header = (folder / name).read_text().split("*/")[0]
        for needle in (robot.sha256, traj.sha256, f"tolerance: {float(eps):g}",
                       f"{cost['multiplications']} multiplications", "gd-analyze version"):
            assert needle in header
    # evaluate uses the explicit model: within EPS on its own trajectory, exit 0
    code, out, err = _run(["evaluate", folder / "simplified_model.json", SHIPPED,
                           "--max-error", eps, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["max_relative_peak_error"] <= float(eps)


def test_stanford_main_job_emits_the_simplified_model():
    """A prismatic joint: the main job writes simplified_model.h, .c, .py and _casadi.py like
    every robot,
    verification passes, and the emitted model is within EPS of rnea on the trajectory."""
    from conftest import ROOT

    csv = ROOT / "data" / "stanford_trajectory.csv"
    # golden case stanford's run (gd-analyze stanford <its trajectory> --no-report), read only
    (root, *_), _ = golden_run("stanford")
    out = root / "stanford"
    assert sorted(p.name for p in out.iterdir()) == [
        ".gd-analyze-manifest-analyze.json", "results.h5", "simplified_model.c",
        "simplified_model.h", "simplified_model.json", "simplified_model.py",
        "simplified_model_casadi.py"]
    robot = load_robot("stanford")
    traj = read_trajectory(csv, robot.n)
    ref = _rnea(robot, traj.q, traj.qd, traj.qdd)
    scale = np.abs(ref).max(axis=0)
    ns = {}
    exec((out / "simplified_model.py").read_text(), ns)
    tau = ns["tau"](traj.q, traj.qd, traj.qdd)
    assert (np.abs(tau - ref).max(axis=0) <= 0.01 * scale * (1 + 1e-9)).all()
    spec = json.loads((out / "simplified_model.json").read_text())
    assert spec["cost"]["multiplications"] > 0
    assert bool(spec.get("explicit_terms")) == (spec.get("form", "explicit") == "explicit")
    loaded = load_model(out / "simplified_model.json")
    np.testing.assert_allclose(loaded.torque(traj.q, traj.qd, traj.qdd), tau, rtol=0,
                               atol=1e-12 * scale.max())
    assert "prismatic joint 3: q [m]" in (out / "simplified_model.c").read_text()


def test_rule_chapter_and_bad_tolerance(tmp_path, capsys, shared_main):
    chapter = shared_main("puma560", SHIPPED, "--rule", "chapter")      # shared, read only
    spec = json.loads((chapter / "simplified_model.json").read_text())
    assert spec["rule"] == "chapter"
    code, _, err = _run(["puma560", SHIPPED, "-o", tmp_path / "x", "--tolerance", "-1"], capsys)
    assert code == 2 and "--tolerance" in err and "Traceback" not in err
    code, _, err = _run(["puma560", SHIPPED, "-o", tmp_path / "y", "--torque-floor", "nan"],
                        capsys)
    assert code == 2 and "Traceback" not in err


@pytest.mark.slow
def test_torque_floor_lowers_the_cost(tmp_path, capsys, shared_main):
    """A floor drops at least the pairs dropped without it, unless what it would drop makes
    D_s singular (the PUMA's ZZ6 at 1 N m, restored for the proof that D_s is positive
    definite), and never costs more (each s_i only grows, so the pairs dropped without a floor
    fit its budget)."""
    costs, checks, dropped = [], [], []
    for floor in ("0", "1"):
        if floor == "0":        # the default --torque-floor: the default run, shared, read only
            out = shared_main("puma560", SHIPPED)
        else:
            out = tmp_path / floor
            code, _, err = _run(["puma560", SHIPPED, "-o", out, "--no-report", "--torque-floor",
                                 floor], capsys)
            assert code == 0, err
        spec = json.loads((out / "simplified_model.json").read_text())
        costs.append(spec["cost"]["multiplications"] + spec["cost"]["additions"])
        checks.append(spec["inertia_check"])
        dropped.append({tuple(p) for p in spec["recursive"]["dropped"]})
    assert costs[1] <= costs[0] and all(c["proved"] and c["lower_bound"] > 0 for c in checks)
    assert dropped[0] and (dropped[0] <= dropped[1] or checks[1]["restored"])


def test_report_section_reads_the_stored_dataset(shared_main):
    import xarray as xr

    from gd_analyze.report.simplified_section import error_figure, simplified_context

    folder = shared_main("puma560", SHIPPED)          # the default run, shared, read only
    with xr.open_dataset(folder / "results.h5", engine="h5netcdf") as ds:
        ds = ds.load()
    ctx = simplified_context(ds)
    assert ctx["rule"] == "budget" and ctx["tolerance"] == 0.01
    assert ctx["files"] == ["simplified_model.h", "simplified_model.c", "simplified_model.py",
                            "simplified_model_casadi.py"]
    labels = [row[0] for row in ctx["costs"]["rows"]]
    assert "AKB 1986 simplified (1 %)" in labels and "project N-E as implemented" in labels
    # the recursive form is deployed (cheaper): the ladder is of that form, and the note
    # beside the cost table says the explicit one is dearer
    assert ctx["ladder"] is not None and not ctx["ladder_note"]
    assert ctx["ladder_heading"] == "5.5 Tolerance ladder of the recursive form"
    assert len(ctx["ladder"]["rows"]) == ds.sizes["ladder_tolerance"] == 4
    total = dict(zip(ds["cost_model"].values, ds["cost_total"].values))
    rec = total["recursive N-E, budget EPS=0.01 (this model)"]
    ex = total["explicit, budget EPS=0.01"]
    assert rec < ex
    assert ctx["form_note"].startswith("The deployed model is the pruned recursive one")
    assert f"{int(rec):,} operations" in ctx["form_note"] and f"{int(ex):,}" in ctx["form_note"]
    # the stored bound holds the measured error
    assert (ds["tau_error_peak"].values <= ds["simplified_bound"].values + 1e-12).all()
    assert (ds["simplified_bound"].values <= 0.01 * ds["simplified_scale"].values).all()
    fig = error_figure(ds)              # a panel per joint with dropped terms
    assert len(fig.axes) == int((ds["simplified_bound"].values > 0).sum()) > 0


@pytest.mark.slow
def test_ladder_is_skipped_when_the_explicit_model_cannot_pay(tmp_path, monkeypatch, capsys,
                                                              shared_main):
    """The explicit form deployed (--form explicit): with the limit below the PUMA's full/N-E
    ratio (the full explicit model costs more than half of Newton-Euler's 1,212) the ladder is
    not built: no ladder_* variables, the reason stored and shown in both reports; the model
    itself, its bound and its cost table are still there. With the default limit it is
    built."""
    import xarray as xr

    import gd_analyze.simplify.explicit_model as simplify

    monkeypatch.setattr(simplify, "LADDER_COST_LIMIT", 0.5)
    assert main(["puma560", str(SHIPPED), "-o", str(tmp_path / "skip"), "-q",
                 "--form", "explicit"]) == 0
    full = json.loads((tmp_path / "skip" / "simplified_model.json").read_text())["full_cost"]
    with xr.open_dataset(tmp_path / "skip" / "results.h5", engine="h5netcdf") as ds:
        assert "ladder_operations" not in ds and "cost_total" in ds
        note = ds.attrs["simplified_ladder_skipped"]
        assert f"{full['multiplications'] + full['additions']:,}" in note and "1,212" in note
    html = (tmp_path / "skip" / "report.html").read_text(encoding="utf-8")
    assert "Tolerance ladder not built" in html
    monkeypatch.undo()
    assert simplify.LADDER_COST_LIMIT == 4.0
    # the default limit: the shared run of the explicit form (--rule budget is the default),
    # read only
    built = shared_main("puma560", SHIPPED, "--rule", "budget", "--form", "explicit")
    with xr.open_dataset(built / "results.h5", engine="h5netcdf") as ds:
        assert ds.sizes["ladder_tolerance"] == 4
        assert "simplified_ladder_skipped" not in ds.attrs


@pytest.mark.slow
def test_form_recursive_derives_no_explicit_model_and_says_so(tmp_path, capsys, shared_main):
    """Under --form recursive the explicit model cannot be deployed: --explicit auto does not
    derive it (no explicit costs), the report says it was not derived instead of showing a
    count, and the ladder is of the recursive form; the deployed model is the one of the
    default form (the recursive one is the cheaper on the shipped trajectory). --explicit
    always still derives it."""
    import xarray as xr

    # the shared run of the recursive form (--rule budget is the default), read only
    rec_run = shared_main("puma560", SHIPPED, "--rule", "budget", "--form", "recursive")
    default_run = shared_main("puma560", SHIPPED)     # shared, read only
    rec = json.loads((rec_run / "simplified_model.json").read_text())
    default = json.loads((default_run / "simplified_model.json").read_text())
    assert rec["form"] == default["form"] == "recursive"
    assert rec["recursive"]["dropped"] == default["recursive"]["dropped"]
    assert not any(k.startswith("explicit") for k in rec["costs"])
    assert any(k.startswith("explicit") for k in default["costs"])
    with xr.open_dataset(rec_run / "results.h5", engine="h5netcdf") as ds:
        assert ds.attrs["simplified_ladder_form"] == "recursive"
        assert "simplified_ladder_skipped" not in ds.attrs
        assert not any(str(m).startswith("explicit") for m in ds["cost_model"].values)
    html = (rec_run / "report.html").read_text(encoding="utf-8")
    assert "the full explicit model was not derived" in html
    assert "Tolerance ladder of the recursive form" in html
    assert main(["puma560", str(SHIPPED), "-o", str(tmp_path / "always"), "-q", "--no-report",
                 "--form", "recursive", "--explicit", "always"]) == 0
    always = json.loads((tmp_path / "always" / "simplified_model.json").read_text())
    assert "explicit, full" in always["costs"]


def test_akb_anchors_only_for_the_puma():
    """Armstrong, Khatib & Burdick's counts are the PUMA 560's: another six-joint arm's cost
    table does not list them."""
    import xarray as xr

    (root, *_), _ = golden_run("stanford")    # golden case stanford's run, read only
    out = root / "stanford"
    with xr.open_dataset(out / "results.h5", engine="h5netcdf") as ds:
        labels = [str(v) for v in ds["cost_model"].values]
    assert ds.sizes["joint"] == 6 and "project N-E as implemented" in labels
    assert not any(lab.startswith("AKB") for lab in labels)


def test_coefficient_structure_counts_harmonics_and_equal_magnitudes():
    """Hand count: D_11 = 2 (tran) + 1 (rot) cos q1 + 3 sin q1 and D_12 = -3 cos q2 give
    three harmonic terms (the two parts of D_11's constant add to one) with the
    magnitudes 3, 3 and 3 (one distinct); keeping only D_11's tran part leaves 2 and 3:
    two distinct."""
    from gd_analyze.jobs.simplified_dataset import coefficient_structure
    from gd_analyze.symbolic.explicit import Term

    def terms(rows):
        kind, part, i, j, K, S, C = zip(*rows)
        return Term(np.array(kind), np.array(part), np.array(i), np.array(j),
                    np.full(len(rows), -1), np.array(K).reshape(-1, 2), np.array(S, bool),
                    np.array(C, float))

    full = terms([("D", "tran", 0, 0, (0, 0), False, 2.0),
                  ("D", "rot", 0, 0, (0, 0), False, 1.0),
                  ("D", "tran", 0, 0, (1, 0), True, 3.0),
                  ("D", "tran", 0, 1, (0, 1), False, -3.0)])
    assert coefficient_structure(full) == (3, 1)
    assert coefficient_structure(full.subset(np.array([True, False, True, True]))) == (3, 2)
