"""The error budget (simplify/budget.py): its peaks and its guarantee.

Oracles: Pinocchio's half-models for the parts' contributions (D_ij^p qdd_j, h_i^p) and its
rnea for the full torque; the guarantee itself, checked against rnea: the torque error of the
simplified model (element level and explicit, pruned) never exceeds the bound, and the bound
never exceeds EPS x scale_i, on one trajectory and on each trajectory of a sweep."""

from functools import cache

import numpy as np
import pytest
from conftest import random_states

from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.dynamics.pinocchio import pinocchio_model, reference_terms
from gd_analyze.model.robots import load_robot
from gd_analyze.ranking.labels import element_labels
from gd_analyze.simplify.budget import (
    PartPeaks,
    budget_choices,
    chosen_terms,
    part_index,
    relative_peaks,
    select_terms,
)
from gd_analyze.simplify.choices import full_choices, simplified_torque
from gd_analyze.symbolic.codegen import build_program
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.explicit import derive, model_terms, term_peaks

ROUND = 1e-12          # round-off allowance, relative to the largest joint scale (engine vs rnea)


@cache
def puma_terms():
    robot = load_robot("puma560")
    return robot, model_terms(derive(robot))


def rnea(robot, q, qd, qdd):
    import pinocchio as pin

    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def _states(robot, N, seed, speed=1.0):
    q, qd, qdd = random_states(robot, N, seed)
    return q, qd * speed, qdd * speed ** 2


def _peaks(robot, q, qd, qdd):
    parts = PartPeaks(robot.n)
    t = gd_terms(robot, q, qd)
    parts.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, qdd, t.tau(qdd))
    return parts


def test_part_index_lists_every_element_twice_in_label_order():
    for n in (1, 3, 6):
        index = part_index(n)
        assert len(index) == 2 * (n * (n + 1) // 2 + n)
        assert [label for label, *_ in index[::2]] == element_labels(n)
        assert [p for _, p, *_ in index] == ["tran", "rot"] * (len(index) // 2)
        for label, _, kind, i, j in index:
            assert label[0] == kind and (j == -1) == (kind == "h") and (kind == "h" or i <= j)


def test_part_peaks_are_the_peaks_of_pinocchios_half_model_contributions(puma):
    q, qd, qdd = random_states(puma, 90, 51)
    ref = reference_terms(puma, q, qd)
    tau = rnea(puma, q, qd, qdd)
    want = np.zeros((len(part_index(puma.n)), puma.n))
    for r, (_, p, kind, i, j) in enumerate(part_index(puma.n)):
        if kind == "D":
            D = getattr(ref, f"D_{p}")
            want[r, i] = np.abs(D[:, i, j] * qdd[:, j]).max()
            if i != j:
                want[r, j] = np.abs(D[:, i, j] * qdd[:, i]).max()
        else:
            want[r, i] = np.abs(getattr(ref, f"h_{p}")[:, i]).max()
    # chunks and merged halves give the peaks of the whole
    a, b = PartPeaks(puma.n), PartPeaks(puma.n)
    t = gd_terms(puma, q, qd)
    for part, sl in ((a, slice(0, 30)), (a, slice(30, 31)), (b, slice(31, 90)), (b, slice(0, 0))):
        part.update(t.D_tran[sl], t.D_rot[sl], t.h_tran[sl], t.h_rot[sl], qdd[sl], tau[sl])
    merged = a.merge(b)
    scale = np.abs(tau).max(axis=0)
    assert np.all(np.abs(merged.peaks - want) <= 1e-10 * scale)
    np.testing.assert_allclose(merged.tau_peak, scale, rtol=1e-10)


@pytest.mark.parametrize("tolerance", [0.0, 0.01, 0.1, 0.5])
def test_element_level_error_within_the_bound_within_the_budget(puma, tolerance):
    q, qd, qdd = random_states(puma, 200, 52)
    parts = _peaks(puma, q, qd, qdd)
    floor = 5.0
    scale = np.maximum(parts.tau_peak, floor)
    choices, used = budget_choices(parts.peaks, scale, tolerance)
    assert set(choices) == set(element_labels(puma.n))
    error = np.abs(simplified_torque(gd_terms(puma, q, qd), choices, qdd)
                   - rnea(puma, q, qd, qdd)).max(axis=0)
    assert np.all(error <= used + ROUND * scale.max())
    assert np.all(used <= tolerance * scale)
    # used is the sum of the dropped parts' peaks, as the choices name them
    keep = {"tran": ("tran", "both"), "rot": ("rot", "both")}
    dropped = [r for r, (label, p, *_) in enumerate(part_index(puma.n))
               if choices[label] not in keep[p]]
    np.testing.assert_allclose(used, parts.peaks[dropped].sum(axis=0), rtol=1e-12, atol=0)
    if tolerance == 0:
        assert choices == {lab: "both" for lab in choices} or np.all(used == 0)
    if tolerance >= 0.1:
        assert dropped                                   # the budget is used


def test_explicit_model_error_within_the_bound_within_the_budget():
    robot, terms = puma_terms()
    q, qd, qdd = random_states(robot, 150, 53)
    parts = _peaks(robot, q, qd, qdd)
    peaks = term_peaks(terms, np.zeros(robot.n), q, qd, qdd)
    eps = 0.05
    sel = select_terms(terms, peaks, parts.peaks, parts.tau_peak, tolerance=eps, torque_floor=1.0)
    np.testing.assert_array_equal(sel.scale, np.maximum(parts.tau_peak, 1.0))
    tau_s = python_function(build_program(sel.kept, robot.n, np.zeros(robot.n)))(q, qd, qdd)
    error = np.abs(tau_s - rnea(robot, q, qd, qdd)).max(axis=0)
    assert np.all(error <= sel.bound + ROUND * sel.scale.max())
    assert np.all(sel.bound <= eps * sel.scale)
    assert np.all(sel.element_bound <= eps * sel.scale)
    np.testing.assert_allclose(sum(sel.bound_by_kind.values()), sel.bound, rtol=1e-12, atol=0)
    assert len(sel.kept) < len(terms) and np.all(sel.bound > 0)


def test_a_sweep_keeps_each_trajectory_within_its_own_scale(puma):
    """Relative peaks: a slow and a fast trajectory (scales far apart); the model chosen on
    the largest ratios is within EPS x scale_t on each, against rnea."""
    trajectories = [_states(puma, 120, 54, 0.2), _states(puma, 120, 55, 3.0)]
    eps = 0.05
    rel, scales = None, []
    for q, qd, qdd in trajectories:
        parts = _peaks(puma, q, qd, qdd)
        scales.append(parts.tau_peak)
        r = relative_peaks(parts.peaks, parts.tau_peak)
        rel = r if rel is None else np.maximum(rel, r)
    choices, used = budget_choices(rel, np.ones(puma.n), eps)
    assert choices != full_choices(puma.n)
    for (q, qd, qdd), scale in zip(trajectories, scales):
        error = np.abs(simplified_torque(gd_terms(puma, q, qd), choices, qdd)
                       - rnea(puma, q, qd, qdd)).max(axis=0)
        assert np.all(error <= used * scale + ROUND * scale.max())
        assert np.all(error <= eps * scale + ROUND * scale.max())


def test_relative_peaks_divide_by_the_trajectorys_scale():
    peaks = np.array([[1.0, 0.0, 2.0], [3.0, 5.0, 0.0]])
    scale = np.array([2.0, 0.0, 4.0])
    np.testing.assert_array_equal(relative_peaks(peaks, scale),
                                  [[0.5, 0.0, 0.5], [1.5, np.inf, 0.0]])
    # a part that acts on a joint of scale 0 can never be dropped
    choices, used = budget_choices(np.array([[0.0, 1e-9]] * 2 + [[0.0, 0.0]] * 4),
                                   np.array([1.0, 0.0]), 0.5)
    assert choices["D11"] == "both" and np.all(used == 0)


def test_chapter_rule_keeps_the_chosen_parts_and_has_no_bound():
    robot, terms = puma_terms()
    rng = np.random.default_rng(56)
    labels = element_labels(robot.n)
    choices = dict(zip(labels, rng.choice(["tran", "rot", "both", "none"], len(labels))))
    keep = chosen_terms(terms, choices)
    for kind, part, i, j, kept in zip(terms.kind, terms.part, terms.i, terms.j, keep):
        if kind == "c":
            assert kept
        else:
            label = f"D{i + 1}{j + 1}" if kind == "D" else f"h{i + 1}"
            assert kept == (choices[label] in (part, "both"))
    sel = select_terms(terms, None, None, np.ones(robot.n), rule="chapter",
                       chapter_choices=choices)
    assert np.isnan(sel.bound).all() and np.isnan(sel.element_bound).all()
    q, qd, qdd = random_states(robot, 20, 57)
    t = gd_terms(robot, q, qd)
    tau_s = python_function(build_program(sel.kept, robot.n, np.zeros(robot.n)))(q, qd, qdd)
    want = simplified_torque(t, choices, qdd)
    assert np.abs(tau_s - want).max() <= 1e-10 * np.abs(want).max()


def test_bad_arguments_are_refused(puma):
    _, terms = puma_terms()
    parts = PartPeaks(puma.n)
    with pytest.raises(ValueError, match="tolerance"):
        budget_choices(parts.peaks, np.ones(puma.n), -0.1)
    with pytest.raises(ValueError, match="tolerance"):
        budget_choices(parts.peaks, np.ones(puma.n), float("nan"))
    with pytest.raises(ValueError, match="rule"):
        select_terms(terms, None, parts.peaks, np.ones(puma.n), rule="greedy")
    with pytest.raises(ValueError, match="torque floor"):
        select_terms(terms, None, parts.peaks, np.ones(puma.n), torque_floor=-1.0)
    with pytest.raises(ValueError, match="chapter rule needs"):
        select_terms(terms, None, parts.peaks, np.ones(puma.n), rule="chapter")
