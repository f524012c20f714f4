"""No guarantee believed from a file. Forged model files, built from the main
job's real PUMA 560 models, are refused by ``evaluate``, ``control`` and the API with exit 2
and one line naming the key; the honest files are read. Oracle: Pinocchio's ``rnea`` on the
robot's own model for the torques a claim rests on."""

import json
import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import SHIPPED, golden_run

import gd_analyze
from gd_analyze.certify.region import Region
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.errors import InputError
from gd_analyze.store.model_trust import reproved_bound
from gd_analyze.trajectory.trajectory import read_trajectory

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def models(tmp_path_factory, shared_main):
    """The main job's region model and trajectory model of the PUMA 560 on its shipped
    trajectory; the runs (with their reports) are shared (read only), linked into the
    module's folder, where the tests write their forged files."""
    folder = tmp_path_factory.mktemp("trust")
    for name, extra in (("region", ()), ("trajectory", ("--guarantee", "trajectory"))):
        (folder / name).symlink_to(shared_main("puma560", SHIPPED, *extra),
                                   target_is_directory=True)
    region = json.loads((folder / "region" / "simplified_model.json").read_text())
    trajectory = json.loads((folder / "trajectory" / "simplified_model.json").read_text())
    assert region["guarantee"]["kind"] == "region"
    assert trajectory["guarantee"]["kind"] == "trajectory"
    assert trajectory["recursive"]["dropped"] != region["recursive"]["dropped"]
    return folder, region, trajectory


def _write(folder, name, doc):
    path = folder / f"{name}.json"
    path.write_text(json.dumps(doc))
    return path


def _copy(doc):
    return json.loads(json.dumps(doc))


def _region_as_limits(g):
    """The guarantee's ``region`` made to agree with its edited limits, as a forger would (so
    that the check of the claim, not the region's consistency, must refuse it)."""
    region = g.get("region")
    if region is not None:
        region["q"] = [q if isinstance(q, str) else [lo, hi]
                       for q, lo, hi in zip(region["q"], g["q_min"], g["q_max"])]
        region["qd_max"], region["qdd_max"] = list(g["qd_max"]), list(g["qdd_max"])
    return g


def _refused(capsys, args, key):
    """Exit 2 and one error line on stderr naming ``key``, no traceback; the stdout."""
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    lines = [ln for ln in err.splitlines() if ": warning: " not in ln and ": note: " not in ln]
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("gd-analyze: error: "), err
    assert f"key {key}:" in lines[0], lines[0]
    assert "Traceback" not in err
    return out, lines[0]


def _rnea(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def test_honest_files_are_read_and_their_claims_hold(models, capsys):
    folder, region_doc, trajectory_doc = models
    model = gd_analyze.load_model(folder / "region" / "simplified_model.json")
    g = model.guarantee
    n = model.robot.n
    state = np.asarray(g.scale_state)
    tau = _rnea(model.robot, state[:, :n], state[:, n:2 * n], state[:, 2 * n:])
    np.testing.assert_allclose(np.abs(tau[np.arange(n), np.arange(n)]), g.scale, rtol=1e-9)
    region = Region(g.q_min, g.q_max, g.qd_max, g.qdd_max)
    reproved = reproved_bound(model, region)
    assert np.all(reproved <= np.asarray(g.bound) * (1 + 1e-12)) and reproved.max() > 0
    for name in ("region", "trajectory"):
        code = main(["evaluate", str(folder / name / "simplified_model.json"), str(SHIPPED)])
        out, err = capsys.readouterr()
        assert code == 0, err
        assert "covers this trajectory: yes" in out


def test_issue_trajectory_model_with_a_region_guarantee_pasted_in_x100(models, capsys):
    """The issue's reproduction: evaluate printed "(proved)" and "covers this trajectory: yes"
    while joint 1 erred 12.6 x its true budget; control --json repeated "proved"."""
    folder, region_doc, trajectory_doc = models
    forged = _copy(trajectory_doc)
    forged["guarantee"] = _copy(region_doc["guarantee"])
    forged["guarantee"]["scale"] = [100 * v for v in trajectory_doc["guarantee"]["scale"]]
    forged["guarantee"]["bound"] = [100 * v for v in trajectory_doc["guarantee"]["bound"]]
    path = _write(folder, "pasted_x100", forged)
    out, line = _refused(capsys, ["evaluate", path, SHIPPED], "guarantee.scale")
    assert "(proved" not in out and "covers this trajectory" not in out
    out, line = _refused(capsys, ["control", path, SHIPPED, "-o", folder / "control_x100",
                                  "--no-report", "--json"], "guarantee.scale")
    assert "proved" not in out
    assert not (folder / "control_x100").exists()
    with pytest.raises(InputError, match="guarantee.scale"):
        gd_analyze.load_model(path)
    # the oracle: |tau_1| at the pasted scale state is the region model's s_1, not 100 x
    n = 6
    state = np.asarray(forged["guarantee"]["scale_state"])
    tau = _rnea(gd_analyze.load_model(folder / "trajectory" / "simplified_model.json").robot,
                state[:, :n], state[:, n:2 * n], state[:, 2 * n:])
    assert abs(abs(tau[0, 0]) - forged["guarantee"]["scale"][0]) > 0.5 * abs(tau[0, 0])


def test_region_guarantee_pasted_onto_other_dropped_pairs_is_refused(models, capsys):
    """The region model's guarantee on the trajectory model's dropped pairs is judged for
    those pairs: its bound re-proved for them, and refused where it is below that (here the
    trajectory model's pairs are among the region model's, so the pasted bound itself holds
    for them; halved at the joint where their re-proved bound is largest, below the error
    that sampling finds there, it is refused)."""
    folder, region_doc, trajectory_doc = models
    forged = _copy(trajectory_doc)
    forged["guarantee"] = _copy(region_doc["guarantee"])
    forged["bound"] = forged["recursive"]["bound"] = forged["guarantee"]["bound"]
    path = _write(folder, "pasted", forged)
    model = gd_analyze.load_model(path)
    g = model.guarantee
    reproved = reproved_bound(model, Region(g.q_min, g.q_max, g.qd_max, g.qdd_max))
    j = int(np.argmax(reproved / np.asarray(g.scale)))
    assert reproved[j] > 0
    forged["guarantee"]["bound"][j] = 0.5 * reproved[j]     # the model's bounds with it
    path = _write(folder, "pasted_lowered", forged)
    out, line = _refused(capsys, ["evaluate", path, SHIPPED], "guarantee.bound")
    assert f"joint {j + 1}" in line


def test_bound_lowered_to_the_sampled_error_is_refused(models, capsys):
    """A bound lowered to just above the largest sampled error holds at every sampled state,
    so no sample can tell; the bound re-proved for the dropped pairs is above it."""
    folder, region_doc, _ = models
    g = region_doc["guarantee"]
    j = int(np.argmax(np.asarray(g["bound"]) - np.asarray(g["sampled_error"])))
    assert g["sampled_error"][j] < 0.99 * g["bound"][j]
    forged = _copy(region_doc)
    forged["guarantee"]["bound"][j] = g["sampled_error"][j] * 1.001
    forged["recursive"]["bound"][j] = forged["bound"][j] = forged["guarantee"]["bound"][j]
    path = _write(folder, "lowered", forged)
    out, line = _refused(capsys, ["evaluate", path, SHIPPED], "guarantee.bound")
    assert "re-proved" in line and f"joint {j + 1}:" in line


def test_issue_region_widened_to_a_full_turn_is_refused(models, capsys):
    """The issue's reproduction: a region widened to [-pi, pi] "covered" a trajectory 40 deg
    outside the robot's limit."""
    folder, region_doc, _ = models
    robot = gd_analyze.load_model(folder / "region" / "simplified_model.json").robot
    j = 1                                                   # joint 2: [-45, 225] deg
    forged = _copy(region_doc)
    forged["guarantee"]["q_min"][j], forged["guarantee"]["q_max"][j] = -math.pi, math.pi
    _region_as_limits(forged["guarantee"])
    path = _write(folder, "wide", forged)
    traj = read_trajectory(SHIPPED, n_joints=6)
    q = traj.q.copy()
    q[:, j] += robot.q_min[j] - math.radians(40) - q[:, j].min()
    assert q[:, j].min() == pytest.approx(robot.q_min[j] - math.radians(40))
    csv = folder / "outside.csv"
    header = ["t"] + [f"{k}{i + 1}" for k in ("q", "qd", "qdd") for i in range(6)]
    rows = np.column_stack([traj.t, q, traj.qd, traj.qdd])
    csv.write_text(",".join(header) + "\n" + "\n".join(",".join(repr(float(v)) for v in r)
                                                       for r in rows) + "\n")
    out, line = _refused(capsys, ["evaluate", path, csv], "guarantee.q_min")
    assert "joint 2" in line and "robot's limit" in line
    assert "covers this trajectory" not in out


@pytest.mark.parametrize("edit, key", [
    (lambda g: g["qd_max"].__setitem__(0, 2 * g["qd_max"][0]), "guarantee.qd_max"),
    (lambda g: g["scale_state"][2].__setitem__(0, 10.0), "guarantee.scale_state"),
    (lambda g: g.update(scale=[3 * v for v in g["scale"]],
                        bound=[3 * v for v in g["bound"]]), "guarantee.scale"),
])
def test_region_claims_checked_against_the_robot(models, capsys, edit, key):
    folder, region_doc, _ = models
    forged = _copy(region_doc)
    edit(forged["guarantee"])
    _region_as_limits(forged["guarantee"])
    path = _write(folder, key.replace(".", "_"), forged)
    _refused(capsys, ["evaluate", path, SHIPPED], key)
    with pytest.raises(InputError, match=key):
        gd_analyze.load_model(path)


def test_trajectory_bound_below_its_measured_error_is_refused(models, capsys):
    """On its own file (by SHA-256) a trajectory model's bound is measured again: half the
    error Pinocchio's torques give is refused; on another file it is not stated as covering."""
    folder, _, trajectory_doc = models
    model = gd_analyze.load_model(folder / "trajectory" / "simplified_model.json")
    traj = read_trajectory(SHIPPED, n_joints=6)
    err = np.abs(model.torque(traj.q, traj.qd, traj.qdd)
                 - _rnea(model.robot, traj.q, traj.qd, traj.qdd)).max(axis=0)
    j = int(np.argmax(err / np.asarray(model.guarantee.scale)))
    forged = _copy(trajectory_doc)
    forged["guarantee"]["bound"][j] = 0.5 * err[j]
    forged["recursive"]["bound"][j] = forged["bound"][j] = 0.5 * err[j]
    path = _write(folder, "low_trajectory", forged)
    out, line = _refused(capsys, ["evaluate", path, SHIPPED], "guarantee.bound")
    assert f"joint {j + 1}:" in line


def test_the_bound_is_re_proved_with_the_main_jobs_samples():
    """The re-proof reads the main job's certification from the cache: the same samples."""
    from gd_analyze.simplify.region_memo import REGION_SAMPLES
    from gd_analyze.store.model_trust import CERTIFICATION_SAMPLES

    assert CERTIFICATION_SAMPLES == REGION_SAMPLES


def test_exact_explicit_region_model_is_read_and_its_terms_checked(models, tmp_path):
    """The exact explicit model deployed under a region guarantee (bound 0) is read; with a
    coefficient edited it no longer is the full explicit model, and its bound 0 is refused."""
    from gd_analyze import load_robot
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.simplify.deploy import region_model, robot_region
    from gd_analyze.simplify.explicit_model import build_model, collect_peaks
    from gd_analyze.simplify.form_choice import exact_explicit_model
    from gd_analyze.store.explicit_cache import explicit_terms
    from gd_analyze.store.model_file import save_model

    puma = load_robot("puma560")
    traj = read_trajectory(SHIPPED, n_joints=6)
    terms, _ = explicit_terms(puma)
    full, _ = build_model(puma, terms, collect_peaks(puma, terms, traj.q, traj.qd, traj.qdd),
                          tolerance=0.0)
    region, _ = robot_region(puma)
    _, guarantee = region_model(puma, base_parameters(puma), region, 0.01)
    save_model(exact_explicit_model(full, terms, guarantee, 0.01), tmp_path / "exact.json")
    model = gd_analyze.load_model(tmp_path / "exact.json")
    assert model.guarantee.kind == "region" and model.bound == [0.0] * 6
    doc = json.loads((tmp_path / "exact.json").read_text())
    k = int(np.argmax(np.abs(doc["explicit_terms"]["coef"])))
    doc["explicit_terms"]["coef"][k] *= 1 + 1e-6
    with pytest.raises(InputError, match="guarantee.bound"):
        gd_analyze.load_model(_write(tmp_path, "edited", doc))


def test_a_guarantee_built_in_memory_is_checked_before_it_is_stated(models):
    """The API's coverage (which ``evaluate`` and ``control`` print) checks a region guarantee
    of a model that never went through a file: its scale multiplied by 100 is refused."""
    import dataclasses

    from gd_analyze.jobs.evaluate import coverage

    folder, _, _ = models
    model = gd_analyze.load_model(folder / "region" / "simplified_model.json")
    traj = read_trajectory(SHIPPED, n_joints=6)
    assert coverage(model, traj)["covered"]
    g = model.guarantee
    bound = 100 * np.asarray(g.bound)
    forged = dataclasses.replace(
        model, guarantee=dataclasses.replace(g, scale=100 * np.asarray(g.scale), bound=bound),
        bound=list(bound), recursive=dataclasses.replace(model.recursive, bound=bound))
    with pytest.raises(InputError, match="guarantee.scale"):
        coverage(forged, traj)


def _spied(monkeypatch):
    """The module's memo of checked claims emptied, and the calls of the re-derivation
    counted."""
    from gd_analyze.store import model_trust

    monkeypatch.setattr(model_trust, "_PROVED_CLAIMS", set())
    calls = []
    real = model_trust.reproved_bound

    def reproved(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)
    monkeypatch.setattr(model_trust, "reproved_bound", reproved)
    return calls


def test_the_stored_trees_prove_the_bound_without_search(models, monkeypatch):
    """The PUMA 560's region model (its bound from the joint sum's branch and bound, which
    the quick proof does not reach) is read on the trees stored with it: neither the quick
    proof nor the re-derivation runs."""
    from gd_analyze.store import model_trust

    folder, region_doc, _ = models
    assert region_doc["guarantee"]["tilings"]
    _spied(monkeypatch)

    def searched(*args, **kwargs):
        raise AssertionError("searched again")
    monkeypatch.setattr(model_trust, "prove_dropped", searched)
    monkeypatch.setattr(model_trust, "reproved_bound", searched)
    model = gd_analyze.load_model(folder / "region" / "simplified_model.json")
    assert len(model.guarantee.tilings) == len(region_doc["guarantee"]["tilings"])


@pytest.mark.parametrize("forge", [
    "missing_leaf", "extra_leaf", "joint_not_the_arms", "whole_region", "none_stored"])
def test_forged_or_missing_trees_are_never_believed(models, monkeypatch, forge):
    """Trees that do not tile the region (a final box missing, one more, a cut along a
    joint the arm does not have), a tiling on which the bound is not reached (the region as
    one box), or no trees at all (a file written before them): the bound is derived again
    (the honest bound then holds, so the file is read)."""
    folder, region_doc, _ = models
    forged = _copy(region_doc)
    g = forged["guarantee"]
    code = g["tilings"][0]
    if forge == "missing_leaf":
        g["tilings"] = [code[:-1]]
    elif forge == "extra_leaf":
        g["tilings"] = [code + "."]
    elif forge == "joint_not_the_arms":
        g["tilings"] = [code.replace("1", "9")]
    elif forge == "whole_region":
        g["tilings"] = ["."]
    else:
        del g["tilings"]
    calls = _spied(monkeypatch)
    model = gd_analyze.load_model(_write(folder, f"trees_{forge}", forged))
    assert calls == [1], "the bound was believed without being derived again"
    assert model.guarantee.bound == pytest.approx(region_doc["guarantee"]["bound"])


def test_trees_of_another_form_are_refused_by_the_schema(models):
    folder, region_doc, _ = models
    forged = _copy(region_doc)
    forged["guarantee"]["tilings"] = ["1.0X"]
    with pytest.raises(InputError, match="guarantee.tilings"):
        gd_analyze.load_model(_write(folder, "trees_bad_text", forged))


def test_honest_trees_do_not_save_a_lowered_bound(models, monkeypatch):
    """The stored trees evaluated on a bound lowered to just above the error sampling finds
    (so that no sample tells): they do not reach it, the re-derivation runs and refuses it;
    lowered below that error, it is refused too."""
    from gd_analyze.certify.certify import tilings_bound
    from gd_analyze.dynamics.base_parameters import base_parameters

    folder, region_doc, _ = models
    honest = gd_analyze.load_model(folder / "region" / "simplified_model.json")
    g = honest.guarantee
    region = Region(g.q_min, g.q_max, g.qd_max, g.qdd_max)
    tiled = tilings_bound(honest.robot, base_parameters(honest.robot), region,
                          honest.recursive.dropped, g.tilings)
    j = int(np.argmax(np.asarray(g.bound) - np.asarray(g.sampled_error)))
    for share, calls_expected in ((1.001, [1]), (0.9, None)):
        forged = _copy(region_doc)
        low = g.sampled_error[j] * share
        forged["guarantee"]["bound"][j] = forged["recursive"]["bound"][j] = low
        forged["bound"][j] = low
        assert tiled[j] > low
        calls = _spied(monkeypatch)
        with pytest.raises(InputError, match="guarantee.bound"):
            gd_analyze.load_model(_write(folder, f"trees_lowered_{share}", forged))
        if calls_expected is not None:
            assert calls == calls_expected


@pytest.fixture(scope="module")
def panda_doc():
    """The Panda's region model at EPS 0.01 (its bound from the decomposition: the branch and
    bound on the first links' pairs plus the final boxes' bound of the rest), as its file's
    dict, with its robot: the model file of the Panda's main job on its shipped trajectory
    without report, its golden case (tests/golden/freeze.py), run once a session and shared
    with tests/test_golden.py and tests/report/test_region_bound_ways.py (read only). Its
    region and so its bound's proof do not depend on the trajectory."""
    from gd_analyze import load_robot

    doc = json.loads((golden_run("panda")[0][0] / "panda" / "simplified_model.json")
                     .read_text())
    g = doc["guarantee"]
    assert g["kind"] == "region" and any(doc["recursive"]["dropped"])
    assert g["decomposed_tilings"] and "decomposition" in g["bound_method"]
    return doc, load_robot("panda")


def _panda_model(doc, robot):
    from gd_analyze.simplify.simplified import SimplifiedModel

    return SimplifiedModel.from_dict(_copy(doc), robot)


def test_a_panda_model_bounded_by_the_decomposition_is_proved_on_its_stored_trees(
        panda_doc, monkeypatch):
    """The Panda's region model is read on the pair of trees stored with it
    (``guarantee.decomposed_tilings``: the first links' branch-and-bound tree and the
    certification's): neither the quick proof nor the re-derivation runs; its bound lowered
    to a half on the joint where the decomposition binds is refused."""
    import dataclasses

    from gd_analyze.store import model_trust
    from gd_analyze.store.model_trust import check_guarantee

    doc, robot = panda_doc
    assert doc["guarantee"]["decomposed_tilings"]
    _spied(monkeypatch)

    def searched(*args, **kwargs):
        raise AssertionError("searched again")
    monkeypatch.setattr(model_trust, "prove_dropped", searched)
    monkeypatch.setattr(model_trust, "reproved_bound", searched)
    model = _panda_model(doc, robot)
    assert len(model.guarantee.decomposed) == len(doc["guarantee"]["decomposed_tilings"])
    check_guarantee(model)
    monkeypatch.undo()
    _spied(monkeypatch)
    g = model.guarantee
    j = int(np.argmax(np.asarray(g.bound) / np.asarray(g.scale)))
    low = np.array(g.bound, float)
    low[j] *= 0.5
    forged = dataclasses.replace(model, guarantee=dataclasses.replace(g, bound=low))
    with pytest.raises(InputError, match="guarantee.bound"):
        check_guarantee(forged)


@pytest.mark.parametrize("forge", [
    "first_missing_leaf", "rest_extra_leaf", "first_joint_not_the_arms", "first_whole_region",
    "swapped", "none_stored"])
def test_a_forged_or_missing_pair_of_trees_is_never_believed(panda_doc, monkeypatch, forge):
    """A tree of the pair that does not tile the region (a final box missing, one more, a cut
    along a joint the arm does not have), a tiling on which the bound is not reached (the
    region as one box for the first links' pairs, the two trees swapped), or no pair at all
    (a file written before them): the bound is derived again (the honest bound then holds,
    so the model is read)."""
    from gd_analyze.store.model_trust import check_guarantee

    doc, robot = panda_doc
    forged = _copy(doc)
    g = forged["guarantee"]
    first, rest = g["decomposed_tilings"][0]
    if forge == "first_missing_leaf":
        g["decomposed_tilings"] = [[first[:-1], rest]]
    elif forge == "rest_extra_leaf":
        g["decomposed_tilings"] = [[first, rest + "."]]
    elif forge == "first_joint_not_the_arms":
        g["decomposed_tilings"] = [[first.replace("1", "9").replace("2", "9"), rest]]
    elif forge == "first_whole_region":
        g["decomposed_tilings"] = [[".", rest]]
    elif forge == "swapped":
        g["decomposed_tilings"] = [[rest, first]]
    else:
        del g["decomposed_tilings"]
    g.pop("tilings", None)
    calls = _spied(monkeypatch)
    model = _panda_model(forged, robot)
    check_guarantee(model)
    assert calls == [1], "the bound was believed without being derived again"


def test_a_pair_of_trees_of_another_form_is_refused_by_the_schema(models):
    folder, region_doc, _ = models
    for bad in ([["1.0X", "."]], [["1.."]], ["1.."], [["1..", ".", "."]]):
        forged = _copy(region_doc)
        forged["guarantee"]["decomposed_tilings"] = bad
        with pytest.raises(InputError, match="guarantee.decomposed_tilings"):
            gd_analyze.load_model(_write(folder, "pair_bad_text", forged))


def test_a_forged_pair_of_trees_does_not_save_a_lowered_bound(panda_doc, monkeypatch):
    """The Panda's bound lowered to just above the error sampling finds on the joint where
    the decomposition binds, with its first tree cut to the last level's first half (not a
    tiling: a bound on fewer boxes would be lower) or the honest pair: the pair does not
    prove it, the re-derivation runs and refuses it."""
    from gd_analyze.store.model_trust import check_guarantee

    doc, robot = panda_doc
    g = doc["guarantee"]
    first, rest = g["decomposed_tilings"][0]
    bound, scale = np.asarray(g["bound"], float), np.asarray(g["scale"], float)
    j = int(np.argmax(bound / scale))
    for pair in ([first[: len(first) - (len(first) - first.rfind("1")) // 2], rest],
                 [first, rest]):
        forged = _copy(doc)
        low = float(g["sampled_error"][j]) * 1.001
        forged["guarantee"]["bound"][j] = forged["recursive"]["bound"][j] = low
        forged["bound"][j] = low
        forged["guarantee"]["decomposed_tilings"] = [pair]
        calls = _spied(monkeypatch)
        with pytest.raises(InputError, match="guarantee.bound"):
            check_guarantee(_panda_model(forged, robot))
        assert calls == [1]


@pytest.mark.parametrize("forge", [
    ("puma", 0, "pairs"), ("puma", 0, "decomposition"), ("puma", 1, "none"),
    ("puma", 1, "decomposition"), ("panda", 0, "branch and bound"), ("panda", 4, "pairs"),
    ("panda", 6, "joint sum")])
def test_a_forged_way_of_a_joints_bound_is_refused(models, panda_doc, monkeypatch, forge):
    """A joint's way of proving its bound (``guarantee.bound_method``) changed to one that
    does not give it: the pairs' own bounds where the joint sum's branch and bound or the
    decomposition gave it, a decomposition the PUMA 560's dropped pairs do not have, a
    branch and bound the Panda's do not run, "none" where something dropped acts, a joint
    sum said of a joint with bound 0. The trees do not show it, the re-derivation runs and
    refuses the file, naming the key."""
    from gd_analyze.simplify.simplified import SimplifiedModel
    from gd_analyze.store.model_trust import check_guarantee

    arm, j, way = forge
    folder, region_doc, _ = models
    doc = region_doc if arm == "puma" else panda_doc[0]
    forged = _copy(doc)
    assert forged["guarantee"]["bound_method"][j] != way
    forged["guarantee"]["bound_method"][j] = way
    _spied(monkeypatch)
    with pytest.raises(InputError, match="guarantee.bound_method"):
        if arm == "puma":
            gd_analyze.load_model(_write(folder, f"way_{j}_{way}", forged))
        else:
            check_guarantee(SimplifiedModel.from_dict(forged, panda_doc[1]))


def test_the_ways_and_their_arithmetic_are_checked(models, monkeypatch):
    """The honest ways are the PUMA 560's (joint sum's branch and bound on joints 1 and 2,
    the pairs' own bounds on joint 3, nothing on 4-6) and are read on the stored trees; an
    arithmetic other than the arm's, a way that is not a name, or one per joint too few, is
    refused."""
    folder, region_doc, _ = models
    g = region_doc["guarantee"]
    assert g["bound_method"] == ["branch and bound"] * 2 + ["pairs"] + ["none"] * 3
    calls = _spied(monkeypatch)
    model = gd_analyze.load_model(folder / "region" / "simplified_model.json")
    assert calls == [] and model.guarantee.bound_method == tuple(g["bound_method"])
    for key, value in (("joint_sum_arithmetic", "ball"), ("joint_sum_arithmetic", "boxes"),
                       ("bound_method", ["pairs"] * 5),
                       ("bound_method", ["sum"] + g["bound_method"][1:])):
        forged = _copy(region_doc)
        forged["guarantee"][key] = value
        with pytest.raises(InputError, match=f"guarantee.{key}"):
            gd_analyze.load_model(_write(folder, f"way_{key}", forged))


def test_a_file_without_the_ways_is_read(models, panda_doc, monkeypatch):
    """A model file written before the ways were stored: read, its bound checked on its trees
    as before, and no way said."""
    from gd_analyze.simplify.simplified import SimplifiedModel
    from gd_analyze.store.model_trust import check_guarantee

    folder, region_doc, _ = models
    for doc in (region_doc, panda_doc[0]):
        older = _copy(doc)
        del older["guarantee"]["bound_method"], older["guarantee"]["joint_sum_arithmetic"]
        calls = _spied(monkeypatch)
        if doc is region_doc:
            model = gd_analyze.load_model(_write(folder, "no_ways", older))
        else:
            model = SimplifiedModel.from_dict(older, panda_doc[1])
            check_guarantee(model)
        assert calls == [] and model.guarantee.bound_method == ()
        assert "bound_method" not in model.guarantee.to_dict()


def test_a_full_turn_joints_range_beyond_180_deg_within_its_limits_is_read_back(tmp_path):
    """The PUMA 560's joint 6 turns over [-266, 266] deg, more than a full turn: the main job
    proves its bound on --q-limits 150:250 deg there, and the file it writes is read back
    (the check takes the robot's own limits, not [-180, 180] deg)."""
    limits = ",".join(["-1e9:1e9"] * 5 + ["150:250"])
    out = tmp_path / "out"
    assert main(["puma560", str(SHIPPED), "--q-limits", limits, "--no-report", "-q", "-o",
                 str(out)]) == 0
    model = gd_analyze.load_model(out / "simplified_model.json")
    assert model.guarantee.q_max[5] == pytest.approx(math.radians(250))


def test_a_trajectory_models_scale_x100_is_refused_on_any_trajectory(models, capsys, tmp_path):
    """A trajectory model's s_i multiplied by 100 was measured again on its own trajectory
    only: evaluated on another, it loosened the gate 100 times. Oracle: Pinocchio's |tau_i|
    at the stored states is the honest s_i, the peak of |tau_i| on the trajectory."""
    folder, _, trajectory_doc = models
    g, n = trajectory_doc["guarantee"], 6
    robot = gd_analyze.load_model(folder / "trajectory" / "simplified_model.json").robot
    state = np.asarray(g["scale_state"])
    tau = _rnea(robot, state[:, :n], state[:, n:2 * n], state[:, 2 * n:])
    traj = read_trajectory(SHIPPED, n_joints=n)
    peak = np.abs(_rnea(robot, traj.q, traj.qd, traj.qdd)).max(axis=0)
    np.testing.assert_allclose(np.abs(tau[np.arange(n), np.arange(n)]), g["scale"], rtol=1e-9)
    np.testing.assert_allclose(peak, g["scale"], rtol=1e-9)
    other = tmp_path / "other.csv"
    assert main(["plan", "puma560", "-o", str(other)]) == 0
    capsys.readouterr()
    forged = _copy(trajectory_doc)
    forged["guarantee"]["scale"] = [100 * v for v in g["scale"]]
    _, line = _refused(capsys, ["evaluate", _write(folder, "trajectory_x100", forged), other],
                       "guarantee.scale")
    assert "joint 1:" in line and "drives included" in line
    del forged["guarantee"]["scale_state"]
    _refused(capsys, ["evaluate", _write(folder, "trajectory_no_states", forged), other],
             "guarantee.scale_state")


@pytest.mark.parametrize("edit, key", [
    (lambda d: d.pop("guarantee"), "guarantee"),
    (lambda d: (d.pop("guarantee"), d.pop("rule")), "rule"),
    (lambda d: (d.pop("guarantee"), d.update(rule="chapter")), "(document)"),
    (lambda d: (d.pop("guarantee"), d.pop("rule"), d.update(schema_version=1)), "(document)")])
def test_a_model_without_its_guarantee_is_refused_not_read_as_an_older_file(
        models, capsys, tmp_path, edit, key):
    """A budget model whose guarantee was removed (and its rule, or relabelled the chapter's,
    or its version set to 1) was read as an older file: evaluate applied no gate, exit 0.
    Oracle: a file of this version with an error budget always states its guarantee."""
    folder, _, trajectory_doc = models
    forged = _copy(trajectory_doc)
    edit(forged)
    path = _write(folder, "no_guarantee_" + str(len(list(folder.iterdir()))), forged)
    _refused(capsys, ["evaluate", path, SHIPPED], key)
    with pytest.raises(InputError, match=key.replace("(", r"\(").replace(")", r"\)")):
        gd_analyze.load_model(path)


def test_a_budget_model_relabelled_the_chapters_is_refused(tmp_path):
    """An explicit model pruned within a budget, its guarantee removed and its rule set to
    "chapter", was read as the chapter's model, which evaluate does not gate. Oracle: the
    chapter's model keeps every term of the parts its choices name (Sec. 3.4.1)."""
    from gd_analyze import load_robot
    from gd_analyze.simplify.explicit_model import build_model, collect_peaks
    from gd_analyze.simplify.simplified import json_safe
    from gd_analyze.store.explicit_cache import explicit_terms

    puma = load_robot("puma560")
    traj = read_trajectory(SHIPPED, n_joints=6)
    terms, _ = explicit_terms(puma)
    peaks = collect_peaks(puma, terms, traj.q, traj.qd, traj.qdd)
    pruned, _ = build_model(puma, terms, peaks, tolerance=0.01)
    chapter, _ = build_model(puma, terms, peaks, rule="chapter", chapter_choices=pruned.choices)
    assert 0 < pruned.terms.C.size < chapter.terms.C.size
    for name, model in (("chapter", chapter), ("relabelled", pruned)):
        doc = json.loads(json.dumps(json_safe(model.to_dict())))
        doc["rule"] = "chapter"
        doc.pop("guarantee", None)
        path = _write(tmp_path, name, doc)
        if model is chapter:
            assert gd_analyze.load_model(path).terms.C.size == chapter.terms.C.size
            continue
        with pytest.raises(InputError, match="key explicit_terms: are not the chapter's model"):
            gd_analyze.load_model(path)


def test_a_trajectory_models_sampled_region_error_is_said_to_be_the_files(models, capsys):
    """A trajectory model's region_sampled_error set to 1e-6 was printed by evaluate as
    "sampled over the region: 0.0001 % of s_i", a figure nothing measured again. Oracle: the
    edited file's figure, 1e-6 of s_i, is 1e-4 %; it is printed only as the file's."""
    folder, _, trajectory_doc = models
    forged = _copy(trajectory_doc)
    forged["guarantee"]["region_sampled_error"] = [1e-6] * 6
    code = main(["evaluate", str(_write(folder, "sampled_1e-6", forged)), str(SHIPPED)])
    out, err = capsys.readouterr()
    assert code == 0, err
    said = [ln for ln in out.splitlines() if "sampled over the region" in ln]
    assert len(said) == 1 and "0.0001 % of s_i (as the model file states, not measured " \
        "again)" in said[0], out
    model = gd_analyze.load_model(folder / "trajectory" / "simplified_model.json")
    assert model.scope().endswith("(as the model file states, not measured again)")


@pytest.mark.parametrize("edit, key", [
    (lambda d: d.update(tolerance=0.5), "tolerance"),
    (lambda d: (d.update(torque_floor=1e4), d["guarantee"].update(scale=[1e4] * 6)),
     "torque_floor")])
def test_an_eps_or_torque_floor_edited_upward_is_refused(models, capsys, edit, key):
    """EPS edited from 0.01 to 0.5 loosened evaluate's gate (EPS s_i) 50 times; a torque floor
    of 1e4 N m with every s_i set to it passed every check of s_i. Oracle: the provenance's
    EPS and torque floor, the ones the main job was run with (its command line's defaults)."""
    folder, _, trajectory_doc = models
    assert trajectory_doc["provenance"]["tolerance"] == 0.01
    assert trajectory_doc["provenance"]["torque_floor"] == 0.0
    forged = _copy(trajectory_doc)
    edit(forged)
    path = _write(folder, f"edited_{key}", forged)
    _, line = _refused(capsys, ["evaluate", path, SHIPPED], key)
    assert "the model was built with" in line
    with pytest.raises(InputError, match=f"key {key}:"):
        gd_analyze.load_model(path)


def test_a_bound_beside_the_region_guarantee_that_is_not_its_bound_is_refused(models, capsys):
    """The model's ``bound`` and ``recursive.bound`` (``SimplifiedModel.bound``, "guaranteed
    bound on |tau_s - tau|") halved, the guarantee's bound left honest: the file was read and
    its model stated a bound that Pinocchio's torques break at states of the region. Refused,
    naming the key."""
    folder, region_doc, _ = models
    g = region_doc["guarantee"]
    robot = gd_analyze.load_model(folder / "region" / "simplified_model.json").robot
    rng = np.random.default_rng(0)
    lo, hi = np.asarray(g["q_min"]), np.asarray(g["q_max"])
    q = rng.uniform(lo, hi, (200, robot.n))
    qd, qdd = (np.asarray(g[k]) * rng.choice([-1.0, 1.0], (200, robot.n))
               for k in ("qd_max", "qdd_max"))
    model = gd_analyze.load_model(folder / "region" / "simplified_model.json")
    error = np.abs(model.torque(q, qd, qdd) - _rnea(robot, q, qd, qdd)).max(axis=0)
    halved = [b / 2 for b in g["bound"]]
    round_off = 1e-12 * max(g["scale"])
    assert (error > halved).any() and (error <= np.asarray(g["bound"]) + round_off).all()
    for key in ("bound", "recursive.bound"):
        forged = _copy(region_doc)
        if key == "bound":
            forged["bound"] = halved
        else:
            forged["recursive"]["bound"] = halved
        path = _write(folder, "bound_beside", forged)
        _refused(capsys, ["evaluate", path, SHIPPED], key)
        with pytest.raises(InputError, match="is not guarantee.bound"):
            gd_analyze.load_model(path)
