"""Which form of the simplified model is deployed, and the exact explicit model.

Oracles: Pinocchio's rnea (the exact explicit model's torques at random states of the region)
and the operation counts given to the decision.
"""

import json

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.simplify.deploy import region_model, robot_region
from gd_analyze.simplify.explicit_model import build_model, collect_peaks
from gd_analyze.simplify.form_choice import choose_form, exact_explicit_model
from gd_analyze.store.explicit_cache import explicit_terms
from gd_analyze.trajectory.planning import default_motion, plan_quintic


def _rnea(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, *x).copy() for x in zip(q, qd, qdd)])


def test_the_exact_explicit_model_keeps_terms_idle_on_its_trajectory():
    """Under a region guarantee the exact explicit model keeps every term, also those whose
    peak is 0 on the trajectory it was built on (joint 6 at rest there, which EPS = 0 on its
    peaks may drop), and equals rnea at random states of the region."""

    puma = load_robot("puma560")
    tr = plan_quintic(puma, *default_motion(puma))
    q, qd, qdd = tr.q.copy(), tr.qd.copy(), tr.qdd.copy()
    q[:, 5], qd[:, 5], qdd[:, 5] = 0.3, 0.0, 0.0
    terms, _ = explicit_terms(puma)
    full, _ = build_model(puma, terms, collect_peaks(puma, terms, q, qd, qdd), tolerance=0.0)
    region, _ = robot_region(puma)
    _, guarantee = region_model(puma, base_parameters(puma), region, 0.01)
    model = exact_explicit_model(full, terms, guarantee, 0.01)
    rng = np.random.default_rng(4)
    states = (rng.uniform(region.q_min, region.q_max, (200, 6)),
              rng.uniform(-1, 1, (200, 6)) * region.qd_max,
              rng.uniform(-1, 1, (200, 6)) * region.qdd_max)
    ref = _rnea(puma, *states)
    scale = np.asarray(guarantee.scale)
    assert len(full.terms) < len(terms) and len(model.terms) == len(terms)
    assert np.all(np.abs(model.torque(*states) - ref).max(axis=0) <= 1e-9 * scale)
    assert model.bound == [0.0] * 6 and set(model.choices.values()) == {"both"}


def _cost(total):
    return {"multiplications": total, "additions": 0}


@pytest.mark.parametrize("rule, form, proved, rec, ex, full, expected", [
    ("chapter", "cheapest", False, 100, 900, 900, "explicit"),
    ("budget", "explicit", True, 100, 900, 900, "explicit"),        # pruned, on the trajectory
    ("budget", "explicit", True, 100, None, 900, "exact explicit"),  # a sweep over the region
    ("budget", "cheapest", False, 100, 99, 50, "explicit"),
    ("budget", "cheapest", False, 100, 100, 50, "recursive"),        # a tie: the recursive one
    ("budget", "cheapest", True, 100, 10, 99, "exact explicit"),
    ("budget", "cheapest", True, 100, 10, 100, "recursive"),
    ("budget", "recursive", False, 100, 10, 10, "recursive"),
    ("budget", "cheapest", False, 100, None, None, "recursive"),
])
def test_one_decision_chooses_the_form(rule, form, proved, rec, ex, full, expected):
    """The form deployed by operation counts, rule, --form and where the bound is proved."""
    choice = choose_form(rule, form, proved, _cost(rec), None if ex is None else _cost(ex),
                         None if full is None else _cost(full))
    assert choice.form == expected
    if expected == "recursive" and ex is not None:     # it says why the explicit one is not
        assert f"{rec:,} operations against the pruned explicit one's {ex:,}" in choice.why
        assert ("--form recursive" in choice.why) == (form == "recursive")
        assert ("proved over the joint-limit region" in choice.why) == (proved and ex < rec)


@pytest.mark.parametrize("form", ["cheapest", "explicit"])
def test_deploy_builds_the_model_within_its_bound_and_leaves_no_cache(form, puma, shipped,
                                                                        tmp_path, monkeypatch):
    """The main job's decision called directly, with nothing kept between runs: the deployed
    model's error against Pinocchio's rnea on the trajectory is within its bound and EPS s_i;
    the form asked for is deployed; its ladder's rungs are cheaper as EPS grows; and the
    derivation cache folder stays empty."""
    from concurrent.futures import ThreadPoolExecutor

    from gd_analyze.dynamics.dalembert import gd_terms
    from gd_analyze.ranking.ranking import rank_dominance
    from gd_analyze.simplify.budget import PartPeaks
    from gd_analyze.simplify.form_choice import deploy
    from gd_analyze.simplify.options import SimplifyOptions
    from gd_analyze.symbolic.explicit import derive, model_terms, term_peaks
    from gd_analyze.symbolic.pruning import contribution_peaks

    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    q, qd, qdd = shipped.q, shipped.qd, shipped.qdd
    t = gd_terms(puma, q, qd)
    tau = t.tau(qdd)
    ranking = rank_dominance(t.D_tran, t.D_rot, t.h_tran, t.h_rot, tau)
    parts = PartPeaks(puma.n)
    parts.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, qdd, tau)
    base = base_parameters(puma)
    terms = model_terms(derive(puma))
    with ThreadPoolExecutor(2) as pool:
        rec = pool.submit(lambda: (base, contribution_peaks(puma, base, q, qd, qdd)))
        ex = pool.submit(lambda: (terms, term_peaks(terms, np.zeros(puma.n), q, qd, qdd,
                                                     prismatic=puma.prismatic)))
        d = deploy(puma, shipped, ranking, parts, SimplifyOptions(form=form), {}, rec, ex)
        rows = d.ladder_rows()
    assert d.model.form == ("explicit" if form == "explicit" else "recursive")
    ref = _rnea(puma, q, qd, qdd)
    err = np.abs(d.model.torque(q, qd, qdd) - ref).max(axis=0)
    g = d.model.guarantee
    assert np.all(err <= np.asarray(g.bound) * (1 + 1e-9) + 1e-12)
    assert np.all(np.asarray(g.bound) <= 0.01 * np.asarray(g.scale) * (1 + 1e-12))
    rows = sorted(rows, key=lambda r: r["tolerance"])
    costs = [r["multiplications"] + r["additions"] for r in rows]
    assert rows and costs == sorted(costs, reverse=True)
    assert all(r["worst_relative_error"] <= r["tolerance"] * (1 + 1e-9) + 1e-12 for r in rows)
    assert not (tmp_path / "cache").exists() or not any((tmp_path / "cache").rglob("*"))


def test_the_form_note_gives_the_deployed_model_s_own_cost():
    """The UR5's region model is chosen over the explicit one at 280 operations, then its
    proof that D_s is positive definite restores a parameter (YZ4): the note that says why it
    is deployed gives the count of the model deployed, the sum of its own multiplications and
    additions (it said 280 beside Table 5.5's 290)."""
    from conftest import ROOT

    from gd_analyze import load_robot
    from gd_analyze.jobs.analyze import analyze
    from gd_analyze.jobs.options import AnalysisOptions
    from gd_analyze.trajectory.trajectory import read_trajectory

    robot = load_robot("ur5")
    traj = read_trajectory(ROOT / "data" / "ur5_trajectory.csv", robot.n)
    a = analyze(robot, traj, AnalysisOptions(verify=False, formulations=False))
    assert a.model.inertia_check["restored"]            # the case: a parameter restored
    total = a.model.cost["multiplications"] + a.model.cost["additions"]
    note = a.dataset.attrs["simplified_form_note"]
    assert f"({total:,} operations, with the parameters restored for the proof that its " \
        "inertia matrix is positive definite," in note, note


def test_the_recursive_note_says_why_where_the_recursive_model_is_not_cheaper():
    """Oracle: the counts given. Fewer operations need no reason; a tie says the recursive
    model wins it (a one-joint arm read "3 operations against the pruned explicit one's 3"
    with no reason); a cheaper explicit model is passed over for its proof or --form."""
    from gd_analyze.simplify.form_choice import recursive_note

    assert recursive_note(290, 498, "cheapest", True).endswith("one's 498).")
    assert recursive_note(3, 3, "cheapest", True).endswith(
        "one's 3: a tie, which the recursive one wins).")
    assert "whose bound holds on this trajectory only" in recursive_note(500, 498, "cheapest", True)
    assert recursive_note(500, 498, "recursive", False).endswith("498, --form recursive).")


def test_a_model_that_drops_nothing_is_called_exact_not_pruned(one_joint_urdf, tmp_path):
    """Oracle: the deployed model's own bound. On this one-joint arm the model drops only
    pairs proved zero (its bound is 0 at every joint), yet Sec. 5.4's note read "the pruned
    recursive one (3 operations against the pruned explicit one's 3 ...)"."""
    import xarray as xr

    from gd_analyze.cli import main
    from gd_analyze.store.names import Attr

    traj = tmp_path / "one.csv"
    assert main(["plan", str(one_joint_urdf), "-o", str(traj)]) == 0
    out = tmp_path / "out"
    assert main([str(one_joint_urdf), str(traj), "-o", str(out), "--no-report", "-q",
                 "--explicit", "always"]) == 0
    model = json.loads((out / "simplified_model.json").read_text())
    with xr.open_dataset(out / "results.h5", engine="h5netcdf") as ds:
        note = str(ds.attrs.get(Attr.SIMPLIFIED_FORM_NOTE, ""))
    assert "recursive one (" in note, note
    assert not np.any(model["bound"]), model["bound"]     # it drops nothing that is not 0
    assert "the exact recursive one" in note and "pruned recursive" not in note
    assert "the exact explicit one's" in note and "pruned explicit" not in note


def test_the_recursive_note_names_each_model_exact_or_pruned():
    """Oracle: the flags given."""
    from gd_analyze.simplify.form_choice import recursive_note

    assert recursive_note(3, 3, "cheapest", True, exact=(True, True)).startswith(
        "The deployed model is the exact recursive one (3 operations against the exact "
        "explicit one's 3")
    assert "the pruned recursive one (5 operations against the exact explicit one's 9" in \
        recursive_note(5, 9, "cheapest", True, exact=(False, True))
