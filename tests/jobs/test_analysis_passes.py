"""Many trajectories ranked in one pass (jobs/analyze.py ``analysis_passes``, the ranking of a
sweep's task): each trajectory's result is, bit for bit, its own analysis (``analyze_one``,
the main job's per-trajectory pass on it alone), and its shares and classes are the chapter's
definitions (Sec. 3.4.1) computed from the G-D terms with numpy; the segmented accumulators
and the segmented simplified torque against the same taken one trajectory at a time and
against their definitions."""

import dataclasses

import numpy as np
import pytest
from numpy_engines import element_series

from gd_analyze import gd_terms, load_robot
from gd_analyze.jobs.analyze import analysis_pass, analysis_passes
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.jobs.sweep import _analyze_batch, _error_batch, analyze_one
from gd_analyze.ranking.ranking import RankingAccumulator, element_labels
from gd_analyze.simplify.choices import choice_masks, simplified_torque
from gd_analyze.simplify.torque_error import TorqueErrorAccumulator
from gd_analyze.trajectory.planning import plan_quintic, random_trajectories

S, E = 0.9, 0.01
RANK_ONLY = AnalysisOptions(dominance=S, negligible=E, verify=False, formulations=False,
                            simplify=None)  # type: ignore[arg-type]  (a sweep's: no model)


def _same(a, b):
    """Equal bit for bit up to NaN payloads (NaN where the other has NaN)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a.shape == b.shape and bool(np.all((a == b) & (np.signbit(a) == np.signbit(b))
                                              | (np.isnan(a) & np.isnan(b))))


def _motions(robot, seed):
    """Random 31-set-point trajectories, with a long one and a two-set-point one among them."""
    trs = random_trajectories(robot, 7, seed=seed)
    long = plan_quintic(robot, trs[0].q[0], trs[0].q[-1], n_setpoints=300)
    short = plan_quintic(robot, trs[1].q[0], trs[1].q[-1], n_setpoints=2)
    return trs[:3] + [long] + trs[3:5] + [short] + trs[5:]


def _same_error(a, b):
    """Torque error dicts equal bit for bit (NaN where the other has NaN)."""
    assert a.keys() == b.keys()
    for key, value in b.items():
        assert (a[key] == value if key == "round_off" else _same(a[key], value)), key
    return True


def _same_ranking(a, b):
    for field in dataclasses.fields(a):
        x, y = getattr(a, field.name), getattr(b, field.name)
        if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
            assert _same(x, y), field.name
        else:
            assert x == y, field.name


@pytest.mark.parametrize("name", ["puma560", "puma560-drives", "stanford", "ur5"])
def test_one_pass_over_many_is_each_trajectory_s_own_analysis(name):
    robot = load_robot(name)
    trs = _motions(robot, 3)
    batch = _analyze_batch(robot, trs, S, E)          # the sweep's task, groups and all
    passes = analysis_passes(robot, trs, RANK_ONLY)   # the terms computed in the pass
    for tr, got, each in zip(trs, batch, passes):
        one = analyze_one(robot, tr, S, E)
        assert _same(got["share_tran"], one["share_tran"])
        assert got["classes"] == one["classes"] and got["choices"] == one["choices"]
        for key in ("peak_tran", "peak_rot", "peak_total", "scale"):
            assert _same(got["peaks"][key], one["peaks"][key]), key
        assert _same(got["summary"]["tau_peak"], one["summary"]["tau_peak"])
        assert _same_error(got["summary"]["error"], one["summary"]["error"])
        alone = analysis_pass(robot, tr, RANK_ONLY, chunk=tr.q.shape[0])
        _same_ranking(each.ranking, alone.ranking)      # the drives' rigid classes too
        assert _same_error(each.error, alone.error) and each.choices == alone.choices
        assert _same(each.tau, alone.tau) and _same(each.tau_simplified, alone.tau_simplified)
    assert (passes[0].ranking.rigid_dominance is not None) == (name == "puma560-drives")


@pytest.mark.parametrize("name", ["puma560", "stanford", "ur5"])
def test_shares_and_classes_are_the_chapter_s_definitions(name):
    """share_tran = sum |tran| / (sum |tran| + sum |rot|); negligible where peak |tran + rot|
    < e x scale (peak sqrt(D_ii D_jj) for D_ij, peak |tau_i| for h_i), translational where
    share >= s, rotational where share <= 1 - s, else both (ranking.py's module docstring)."""
    robot = load_robot(name)
    trs = _motions(robot, 8)
    n, T = robot.n, robot.n * (robot.n + 1) // 2
    iu = np.triu_indices(n)
    checked = 0
    for tr, got in zip(trs, analysis_passes(robot, trs, RANK_ONLY)):
        terms = gd_terms(robot, tr.q, tr.qd)
        tran, rot = element_series(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot)
        with np.errstate(invalid="ignore"):         # 0 / 0 where an element vanishes
            share = np.abs(tran).sum(axis=0) / (np.abs(tran).sum(axis=0)
                                                + np.abs(rot).sum(axis=0))
        diag = np.diagonal(terms.D_tran + terms.D_rot, axis1=1, axis2=2)
        scale = np.concatenate([np.sqrt(diag[:, iu[0]] * diag[:, iu[1]]).max(axis=0),
                                np.abs(terms.tau(tr.qdd)).max(axis=0)])
        peak = np.abs(tran + rot).max(axis=0)
        kind_max = np.concatenate([np.full(T, scale[:T].max()), np.full(n, scale[T:].max())])
        clear = (peak > 1e-9 * kind_max) & (np.abs(peak - E * scale) > 1e-9 * scale) & \
            (np.abs(share - S) > 1e-9) & (np.abs(share - (1 - S)) > 1e-9)
        expected = np.where(peak < E * scale, "negligible",
                            np.where(share >= S, "translational",
                                     np.where(share <= 1 - S, "rotational", "both")))
        finite = clear & np.isfinite(share)
        np.testing.assert_allclose(got.ranking.share_tran[finite], share[finite], rtol=1e-12)
        assert list(np.array(got.ranking.dominance)[clear]) == list(expected[clear])
        checked += int(clear.sum())
    assert checked > 0.8 * len(trs) * len(element_labels(n))


def test_segmented_accumulators_are_each_segment_alone_and_the_definitions():
    """Two chunks cut into segments, the first trajectory across both, against one
    accumulator per trajectory (the one-trajectory path) and numpy's peak and rms."""
    robot = load_robot("puma560-drives")
    rng = np.random.default_rng(4)
    N = 40
    q, qd, qdd = (rng.uniform(-1.0, 1.0, (N, robot.n)) for _ in range(3))
    terms = gd_terms(robot, q, qd)
    tau = terms.tau(qdd)
    tau_s = tau + rng.normal(scale=0.01, size=tau.shape)
    ends = [5, 17, 18, 40]                  # trajectories 0 .. 3; the chunks cut at 9
    K = len(ends)
    many = RankingAccumulator(robot.n, trajectories=K)
    errors = TorqueErrorAccumulator(robot.n, trajectories=K)
    for a, b in ((0, 9), (9, N)):
        t = terms.rows(slice(a, b))
        many.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, tau[a:b], armature=terms.armature,
                    ends=ends, at=a)
        errors.update(tau_s[a:b], tau[a:b], ends=ends, at=a)
    assert many.count.tolist() == np.diff([0] + ends).tolist()
    for k, (a, b) in enumerate(zip([0] + ends, ends)):
        alone = RankingAccumulator(robot.n)
        err = TorqueErrorAccumulator(robot.n)
        for lo, hi in ((a, min(b, 9)), (max(a, 9), b)):   # the chunks as the pass cut them
            if hi > lo:
                t = terms.rows(slice(lo, hi))
                alone.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, tau[lo:hi],
                             armature=terms.armature)
                err.update(tau_s[lo:hi], tau[lo:hi])
        _same_ranking(many.results()[k], alone.result())
        assert _same_error(errors.results()[k], err.result())
        d = np.abs(tau_s[a:b] - tau[a:b])
        np.testing.assert_allclose(errors.results()[k]["peak_abs_error"], d.max(axis=0),
                                   rtol=0)
        np.testing.assert_allclose(errors.results()[k]["rms_error"],
                                   np.sqrt((d**2).mean(axis=0)), rtol=1e-13)


def test_segmented_simplified_torque_is_each_model_on_its_rows():
    """Each segment's rows under its own model: as the model alone on them, and as
    D_s qdd + h_s + c with the masks (Eq. (3.4-24)) row by row."""
    robot = load_robot("stanford")
    rng = np.random.default_rng(6)
    N = 30
    q, qd, qdd = (rng.uniform(-1.0, 1.0, (N, robot.n)) for _ in range(3))
    terms = gd_terms(robot, q, qd)
    options = ("tran", "rot", "both", "none")
    labels = element_labels(robot.n)
    models = [{lab: options[rng.integers(4)] for lab in labels} for _ in range(3)]
    ends = [4, 11, 30]
    got = np.concatenate([simplified_torque(terms.rows(slice(a, b)), models, qdd[a:b],
                                            ends=ends, at=a) for a, b in ((0, 6), (6, 30))])
    for (a, b), choices in zip(zip([0] + ends, ends), models):
        assert _same(got[a:b], simplified_torque(terms.rows(slice(a, b)), choices, qdd[a:b]))
        Mt, Mr, mt, mr = choice_masks(choices, robot.n)
        for k in range(a, b):
            D_s = Mt * terms.D_tran[k] + Mr * terms.D_rot[k]
            h_s = mt * terms.h_tran[k] + mr * terms.h_rot[k]
            np.testing.assert_allclose(got[k], D_s @ qdd[k] + h_s + terms.c[k], rtol=1e-12,
                                       atol=1e-12)


def test_the_chapter_merge_s_errors_are_each_trajectory_s():
    """The chapter merge's per-trajectory error (a sweep's second pass) in groups: as the
    model measured along each trajectory alone."""
    robot = load_robot("puma560")
    trs = _motions(robot, 5)
    choices = {lab: ("both", "tran", "rot", "none")[k % 4]
               for k, lab in enumerate(element_labels(robot.n))}
    for tr, got in zip(trs, _error_batch(robot, trs, choices)):
        terms = gd_terms(robot, tr.q, tr.qd)
        d = np.abs(simplified_torque(terms, choices, tr.qdd) - terms.tau(tr.qdd))
        assert _same(got["peak"], d.max(axis=0)) and got["count"] == tr.q.shape[0]
        assert _same(got["sum_sq"], (d**2).sum(axis=0))
        assert _same(got["peak_tau"], np.abs(terms.tau(tr.qdd)).max(axis=0))


def test_segments_are_checked():
    acc = RankingAccumulator(2, trajectories=2)
    z3, z2 = np.zeros((3, 2, 2)), np.zeros((3, 2))
    with pytest.raises(ValueError, match="for 2 trajectories"):
        acc.update(z3, z3, z2, z2, z2, ends=[1, 2, 3])
    with pytest.raises(ValueError, match="are not in"):
        acc.update(z3, z3, z2, z2, z2, ends=[1, 3], at=1)
    acc.update(z3, z3, z2, z2, z2, ends=[1, 3])
    with pytest.raises(ValueError, match="results"):
        acc.result()
    with pytest.raises(ValueError, match="trajectories must be"):
        TorqueErrorAccumulator(2, trajectories=0)
    robot = load_robot("two-link")
    tr = random_trajectories(robot, 1)[0]
    with pytest.raises(ValueError, match="ranks only"):
        analysis_passes(robot, [tr], AnalysisOptions())
    with pytest.raises(ValueError, match="for 1 trajectories"):
        simplified_torque(gd_terms(robot, tr.q, tr.qd), [dict.fromkeys(
            element_labels(robot.n), "both")], tr.qdd, ends=[5, 31])
