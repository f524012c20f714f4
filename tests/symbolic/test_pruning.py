"""Pruning with a guarantee: on the shipped trajectories the pruned program's error against
Pinocchio's rnea stays within its per-joint bound, and the bound within EPS of the scale."""

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from symbolic_helpers import count_c, rnea, robot, states

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.dynamics.regressor_kernels import part_regressor
from gd_analyze.symbolic import pruning as pruning_module
from gd_analyze.symbolic.emit import emit_c, python_function
from gd_analyze.symbolic.pruning import part_contributions, prune, pruned_program, zero_parts
from gd_analyze.symbolic.recursive import recursive_program
from gd_analyze.trajectory.trajectory import read_trajectory

DATA = Path(__file__).resolve().parents[2] / "data"
TRAJECTORIES = {"puma560": "puma560_trajectory.csv", "stanford": "stanford_trajectory.csv",
                "ur5": "ur5_trajectory.csv"}


@cache
def case(name):
    arm = robot(name)
    if name in TRAJECTORIES:
        traj = read_trajectory(DATA / TRAJECTORIES[name], arm.n)
        q, qd, qdd = traj.q, traj.qd, traj.qdd
    else:
        q, qd, qdd = states(arm, 150, 9)
    base = base_parameters(arm)
    return arm, base, (q, qd, qdd), rnea(arm, q, qd, qdd), recursive_program(arm).cost()


def _total(cost):
    return cost["multiplications"] + cost["additions"]


def test_parts_add_up_to_rnea_and_each_part_is_its_own_rnea():
    arm, base, (q, qd, qdd), tau, _ = case("stanford")
    C = part_contributions(arm, base, q, qd, qdd)
    scale = np.abs(tau).max()
    assert np.abs(C.sum(axis=(0, 3)) - tau).max() <= 1e-10 * scale
    zero = np.zeros_like(q)
    inertial = rnea(arm, q, zero, qdd, gravity=False)
    velocity = rnea(arm, q, qd, zero, gravity=False)
    assert np.abs(C[0].sum(axis=-1) - inertial).max() <= 1e-10 * scale
    assert np.abs(C[1].sum(axis=-1) - velocity).max() <= 1e-10 * scale


CASES = [(name, eps, "peaks") for name in ("puma560", "stanford", "ur5", "mixed-chain")
         for eps in (0.001, 0.01, 0.05)]
CASES += [(name, 0.05, "error") for name in ("puma560", "ur5", "mixed-chain")]


@pytest.mark.parametrize("name, eps, criterion", CASES)
def test_pruned_error_within_bound_within_eps(name, eps, criterion):
    arm, base, (q, qd, qdd), tau, exact = case(name)
    pr = prune(arm, base, q, qd, qdd, eps, criterion=criterion)
    assert pr.criterion == criterion
    scale = np.abs(tau).max(axis=0)
    np.testing.assert_allclose(pr.scale, scale, rtol=1e-9)
    assert np.all(pr.bound <= eps * pr.scale)
    prog = pruned_program(arm, base, pr.dropped)
    err = np.abs(python_function(prog)(q, qd, qdd) - tau).max(axis=0)
    assert np.isfinite(err).all()
    assert np.all(err <= pr.bound + 1e-10 * scale), (err, pr.bound)
    assert _total(prog.cost()) <= _total(exact)


@pytest.mark.parametrize("strategy", ["peak", "cost"])
def test_every_dropped_unit_counts_in_the_bound(strategy):
    arm, base, (q, qd, qdd), _, _ = case("puma560")
    pr = prune(arm, base, q, qd, qdd, 0.05, strategy=strategy)
    assert pr.dropped.any()
    single = pr.dropped & ~pr.whole[:, None]
    want = (pr.peak * single[:, :, None]).sum(axis=(0, 1)) + pr.whole_peak[pr.whole].sum(0)
    np.testing.assert_allclose(pr.bound, want, rtol=1e-12, atol=0)
    assert np.all(pr.dropped[pr.whole] | (pr.peak[pr.whole].max(axis=2) == 0))
    assert np.all(pr.whole_peak <= pr.peak.sum(axis=1) * (1 + 1e-12))
    if strategy == "peak":
        assert not pr.whole.any()


def test_pruning_lowers_the_count_and_eps_zero_is_exact():
    arm, base, (q, qd, qdd), tau, exact = case("puma560")
    pr = prune(arm, base, q, qd, qdd, 0.0)
    assert not pr.bound.any()
    prog = pruned_program(arm, base, pr.dropped)
    assert _total(prog.cost()) == _total(exact)
    pr = prune(arm, base, q, qd, qdd, 0.05)
    pruned = pruned_program(arm, base, pr.dropped)
    assert _total(pruned.cost()) < _total(exact)
    assert count_c(emit_c(pruned, {"robot": "test"})) == pruned.cost()


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf")])
def test_bad_eps_is_refused(bad):
    arm, base, (q, qd, qdd), _, _ = case("stanford")
    with pytest.raises(ValueError, match="eps"):
        prune(arm, base, q, qd, qdd, bad)
    with pytest.raises(ValueError, match="criterion"):
        prune(arm, base, q, qd, qdd, 0.01, criterion="max")


def test_error_criterion_bound_is_the_error_and_no_looser():
    """criterion "error": the bound is the dropped set's own peak error on the trajectory
    (<= the sum of its peaks), and it allows at least the drops of "peaks" at no more cost."""
    arm, base, (q, qd, qdd), tau, _ = case("puma560")
    by_error = prune(arm, base, q, qd, qdd, 0.01, criterion="error")
    C = part_contributions(arm, base, q, qd, qdd)
    lost = (C * by_error.dropped.T[:, None, None, :]).sum(axis=(0, 3))
    np.testing.assert_allclose(by_error.bound, np.abs(lost).max(axis=0), rtol=1e-12,
                               atol=1e-15 * np.abs(tau).max())
    by_peaks = prune(arm, base, q, qd, qdd, 0.01)
    costs = [_total(pruned_program(arm, base, p.dropped).cost()) for p in (by_error, by_peaks)]
    assert costs[0] <= costs[1]


@pytest.mark.parametrize("name", ["stanford", "panda", "mixed-chain"])
def test_parts_program_computes_exactly_the_kept_pairs(name):
    """Each part alone is its rnea; random dropped sets equal the regressor's sum of the kept
    (parameter, part) contributions to 1e-10 (the split recursions are exact)."""
    from gd_analyze.symbolic.pruning import part_values
    from gd_analyze.symbolic.recursive import parts_program

    arm = robot(name)
    base = base_parameters(arm)
    q, qd, qdd = states(arm, 60, 4)
    C = part_contributions(arm, base, q, qd, qdd)
    scale = np.abs(C.sum(axis=(0, 3))).max(axis=0)
    rng = np.random.default_rng(3)
    sets = [np.tile(np.arange(3) != p, (base.rank, 1)) for p in range(3)]
    sets += [rng.random((base.rank, 3)) < 0.3 for _ in range(3)]
    for dropped in sets:
        prog = parts_program(arm, part_values(base, dropped), search=False)
        want = (C * ~dropped.T[:, None, None, :]).sum(axis=(0, 3))
        got = python_function(prog)(q, qd, qdd)
        assert (np.abs(got - want).max(axis=0) <= 1e-10 * scale).all()


def test_pruned_counts_at_one_percent_within_the_targets():
    """On the shipped trajectories at EPS = 0.01 the pruned PUMA counts <= 305
    operations; the PUMA and the Panda prune below their exact counts and far below the
    chapter's Newton-Euler (Table 3.3, counted by dynamics.opcount)."""
    from gd_analyze.dynamics.opcount import count_operations

    for name, target in (("puma560", 305), ("panda", None)):
        arm = robot(name)
        traj = read_trajectory(DATA / f"{name}_trajectory.csv", arm.n)
        base = base_parameters(arm)
        pr = prune(arm, base, traj.q, traj.qd, traj.qdd, 0.01)
        pruned = _total(pruned_program(arm, base, pr.dropped).cost())
        exact = _total(recursive_program(arm).cost())
        ne = count_operations(arm, "newton-euler")
        assert pruned < exact < ne.multiplications + ne.additions
        assert target is None or pruned <= target


def _sweep_case(name):
    """Three random states sets and one slow, small move: joint scales that differ by orders
    of magnitude between the 'trajectories'."""
    arm = robot(name)
    sets = [states(arm, 40, seed) for seed in (1, 2, 3)]
    q, qd, qdd = states(arm, 30, 4)
    sets.append((q, qd * 1e-3, qdd * 1e-3))
    return arm, base_parameters(arm), sets


@pytest.mark.parametrize("name, eps", [("puma560", 0.01), ("puma560", 0.05),
                                       ("mixed-chain", 0.02), ("panda", 0.01)])
def test_pruning_on_several_trajectories_holds_on_each(name, eps):
    """prune_on_peaks: on every trajectory t the pruned program's error against Pinocchio's
    rnea is within EPS x that trajectory's own scale (not the largest one), and within the
    bound dropped_peaks gives on t; the program costs no more than the exact one."""
    from gd_analyze.symbolic.pruning import dropped_peaks, prune_on_peaks, stacked_peaks

    arm, base, sets = _sweep_case(name)
    cat = [np.concatenate([s[k] for s in sets]) for k in range(3)]
    tau_peak, peak, whole = stacked_peaks(arm, base, *cat, [len(s[0]) for s in sets])
    pr = prune_on_peaks(arm, base, tau_peak, peak, whole, eps)
    assert pr.dropped.any() and np.all(pr.bound <= eps)
    each = dropped_peaks(peak, whole, pr.dropped, pr.whole).sum(axis=1)     # (K, n)
    prog = pruned_program(arm, base, pr.dropped)
    f = python_function(prog)
    for k, (q, qd, qdd) in enumerate(sets):
        ref = rnea(arm, q, qd, qdd)                                        # the oracle
        scale = np.abs(ref).max(axis=0)
        err = np.abs(f(q, qd, qdd) - ref).max(axis=0)
        assert np.all(err <= each[k] + 1e-10 * scale.max()), (k, err, each[k])
        assert np.all(err <= eps * scale * (1 + 1e-9) + 1e-10 * scale.max()), (k, err / scale)
    assert _total(prog.cost()) <= _total(recursive_program(arm).cost())


def test_stacked_peaks_are_each_trajectorys_own():
    from gd_analyze.symbolic.pruning import contribution_peaks, stacked_peaks

    arm, base, sets = _sweep_case("stanford")
    cat = [np.concatenate([s[k] for s in sets]) for k in range(3)]
    got = stacked_peaks(arm, base, *cat, [len(s[0]) for s in sets])
    for k, (q, qd, qdd) in enumerate(sets):
        for a, b in zip(got, contribution_peaks(arm, base, q, qd, qdd)):
            np.testing.assert_allclose(a[k], b, rtol=1e-13, atol=0)
    with pytest.raises(ValueError, match="lengths"):
        stacked_peaks(arm, base, *cat, [10, 10])


def test_a_joint_without_torque_on_a_trajectory_keeps_what_moves_it():
    """A trajectory where a joint's scale is 0 (torque floor 0): any pair with a positive
    peak on that joint there has an infinite ratio and is kept, whatever EPS; a region bound
    (larger peaks) is taken as given."""
    from gd_analyze.symbolic.pruning import prune_on_peaks

    arm, base, sets = _sweep_case("puma560")
    from gd_analyze.symbolic.pruning import contribution_peaks

    peaks = [contribution_peaks(arm, base, *s) for s in sets[:2]]
    scale = np.array([p[0] for p in peaks])
    peak = np.array([p[1] for p in peaks])
    whole = np.array([p[2] for p in peaks])
    scale[1, 2] = 0.0
    pr = prune_on_peaks(arm, base, scale, peak, whole, 0.5)
    moves = peak[1, :, :, 2] > 0
    assert pr.dropped.any() and not (pr.dropped & moves).any()
    with pytest.raises(ValueError, match="expected scale"):
        prune_on_peaks(arm, base, scale[0], peak, whole, 0.01)
    with pytest.raises(ValueError, match="eps"):
        prune_on_peaks(arm, base, scale, peak, whole, float("nan"))


def test_settled_restore_is_a_subset_and_never_dearer():
    """After a restore of inertial parts, the pairs kept dropped are a subset of those asked
    for, and their program counts no more than the one asked for, nor than the exact one."""
    from gd_analyze.symbolic.pruning import pruned_choice, settle_restored

    arm, base, (q, qd, qdd), _, exact_cost = case("puma560")
    before = prune(arm, base, q, qd, qdd, 0.05).dropped
    rows = np.nonzero(before[:, 0])[0]
    assert rows.size                                       # something inertial to restore
    asked = before.copy()
    asked[rows[:2], 0] = False                             # restore two inertial parts
    settled = settle_restored(arm, base, before, asked)
    assert not (settled & ~asked).any()                    # a subset of the pairs asked for
    total = _total(pruned_choice(arm, base, settled)[0].cost())
    assert total <= _total(pruned_choice(arm, base, asked)[0].cost())
    assert total <= _total(exact_cost)
    with pytest.raises(ValueError):
        settle_restored(arm, base, before, asked[:-1])


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_zero_parts_decides_each_column_once_whatever_columns_it_is_asked_with(name,
                                                                             monkeypatch):
    """A column's decision is its own: any set of columns gives the rows a fresh decision on
    that set gives, each declared zero part is zero at random states (the regressor's part
    columns, an independent numeric computation), and columns asked again are not decided
    again."""
    arm = load_robot(name)
    n = arm.n
    every = np.arange(10 * n)
    monkeypatch.setattr(pruning_module, "_ZERO_MEMO", {})
    rng = np.random.default_rng(1)
    subsets = [np.sort(rng.choice(every, size=k, replace=False)) for k in (3, 17, 10 * n)]
    for cols in subsets:
        np.testing.assert_array_equal(zero_parts(arm, cols), pruning_module._zero_parts(arm, cols))
    q, qd, qdd = (rng.uniform(-2, 2, (20, n)) for _ in range(3))
    parts = part_regressor(arm, every, q, qd, qdd)                        # (K, 3, n, m)
    declared = zero_parts(arm, every)                                     # (m, 3, n)
    assert declared.any()
    assert np.all(np.abs(parts.transpose(3, 1, 2, 0)[declared]) <= 1e-9)

    def refuse(*args):
        raise AssertionError("decided again")
    monkeypatch.setattr(pruning_module, "_zero_parts", refuse)
    out = zero_parts(arm, every[::-1])
    np.testing.assert_array_equal(out, declared[::-1])
    out[:] = True                                   # the caller's copy, not the memo
    np.testing.assert_array_equal(zero_parts(arm, every), declared)
