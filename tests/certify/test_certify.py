"""The region guarantee: the stored bound holds at every sampled state of the region,
against Pinocchio's rnea, on real arms and a mixed chain with prismatic joints."""
import copy
import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.certify.certify import dropped_bound, region_bound
from gd_analyze.certify.region import joint_region
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.limits import acceleration_limits
from gd_analyze.model.robot_spec import robot_from_chain
from gd_analyze.simplify.deploy import certified
from gd_analyze.simplify.deploy import region_model as _searched_model
from gd_analyze.simplify.region_memo import region_key
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.pruning import pruned_program

STATES = 100_000


def _chain(name, prismatic, rotation_seed):
    """A general chain with full inertia tensors and limits on every joint, prismatic at the
    joints ``prismatic`` (a tuple of flags), revolute elsewhere, each placement randomly
    rotated."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(5)
    joints = []
    for i, pris in enumerate(prismatic):
        B = rng.normal(size=(3, 3)) * 0.1
        S = B @ B.T
        joints.append({
            "type": "prismatic" if pris else "revolute",
            "rotation": Rotation.random(random_state=rotation_seed + i).as_matrix(),
            "translation": rng.uniform(-0.3, 0.3, 3), "mass": rng.uniform(0.3, 4.0),
            "com": rng.uniform(-0.2, 0.2, 3), "inertia": np.trace(S) * np.eye(3) - S,
            "q_min": -0.4 if pris else -2.5, "q_max": 0.4 if pris else 2.5,
            "qd_max": 0.5 if pris else 2.0, "qdd_max": 1.0 if pris else 3.0})
    return robot_from_chain(name, joints, [0.5, -1.0, -9.5], source="<test>")


def _mixed():
    """A general chain with two prismatic joints, full inertia tensors, limits on every joint."""
    return _chain("mixed", (False, True, False, True, False), 500)


def _prismatic_first():
    """A chain whose first joint is prismatic on an oblique axis, then two revolute joints:
    some columns' velocity terms involve one joint only (qd_2^2), with no pair of joints."""
    return _chain("prismatic-first", (True, False, False), 700)


def _robot(name):
    if name == "mixed":
        return _mixed()
    return _prismatic_first() if name == "prismatic-first" else load_robot(name)


def _states(region, count, seed):
    """Uniform states of the region, a quarter of them with qd, qdd at their limits and a
    few joints at their position limits."""
    rng = np.random.default_rng(seed)
    n = region.q_min.size
    q = rng.uniform(region.q_min, region.q_max, (count, n))
    qd = rng.uniform(-1, 1, (count, n)) * region.qd_max
    qdd = rng.uniform(-1, 1, (count, n)) * region.qdd_max
    k = count // 4
    qd[:k] = rng.choice([-1.0, 1.0], (k, n)) * region.qd_max
    qdd[:k] = rng.choice([-1.0, 1.0], (k, n)) * region.qdd_max
    at = rng.uniform(size=(k, n)) < 0.3
    q[:k] = np.where(at, np.where(rng.uniform(size=(k, n)) < 0.5, region.q_min,
                                  region.q_max), q[:k])
    return q, qd, qdd


def _rnea(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


#: :func:`region_model`'s results and :func:`_sampled`'s states and torques, by their inputs.
_SEARCHED: dict = {}
_SAMPLED: dict = {}


@pytest.fixture(autouse=True, scope="module")
def _memos_of_the_module():
    """:func:`region_model`'s and :func:`_sampled`'s memos, kept for this module's cases
    only (the sampled states and torques are some 90 MB)."""
    yield
    _SEARCHED.clear()
    _SAMPLED.clear()


def region_model(robot, base, region, eps):
    """``gd_analyze.simplify.deploy.region_model`` on an arm, its base parameters, region and
    EPS, searched once per process for the same inputs (a pure function of them): a copy of
    the first result each time, which a test may change."""
    key = (region_key(robot, region, 0.0), eps)
    if key not in _SEARCHED:
        _SEARCHED[key] = _searched_model(robot, base, region, eps)
    return copy.deepcopy(_SEARCHED[key])


def _sampled(robot, region, count, seed):
    """``(q, qd, qdd, tau)``: :func:`_states` and Pinocchio's rnea at them, made once per
    process for the same arm, region, count and seed; read only."""
    key = (region_key(robot, region, 0.0), count, seed)
    if key not in _SAMPLED:
        q, qd, qdd = _states(region, count, seed)
        _SAMPLED[key] = (q, qd, qdd, _rnea(robot, q, qd, qdd))
        for a in _SAMPLED[key]:
            a.setflags(write=False)
    return _SAMPLED[key]


@pytest.mark.parametrize("name,eps", [("puma560", 0.05), ("puma560", 0.01), ("panda", 0.02),
                                      ("ur5", 0.05), ("ur5", 0.01), ("mixed", 0.05),
                                      ("prismatic-first", 0.05)])
def test_the_region_bound_holds_at_every_sampled_state(name, eps):
    robot = _robot(name)
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    rec, guarantee = region_model(robot, base, region, eps)
    assert rec.dropped.any(), "nothing dropped: the test would prove nothing"
    assert np.all(guarantee.bound <= eps * guarantee.scale * (1 + 1e-12))
    tau_s = python_function(pruned_program(robot, base, rec.dropped))
    q, qd, qdd, ref = _sampled(robot, region, STATES, seed=7)
    err = np.abs(tau_s(q, qd, qdd) - ref).max(axis=0)
    round_off = 64 * np.finfo(float).eps * max(guarantee.scale.max(), np.abs(ref).max())
    assert np.all(np.isfinite(err))
    assert np.all(err <= guarantee.bound + round_off), (err, guarantee.bound)
    # the scale is attained where the model says
    n = robot.n
    st = guarantee.scale_state
    at = _rnea(robot, st[:, :n], st[:, n:2 * n], st[:, 2 * n:])
    assert np.allclose(np.abs(at[np.arange(n), np.arange(n)]), guarantee.scale, rtol=1e-9)
    assert np.all(np.abs(ref).max(axis=0) <= guarantee.scale * 1.05)   # a found maximum


def test_the_model_prunes_on_the_proved_bound_not_the_sampled_peak():
    robot = load_robot("puma560")
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    pb = certified(robot, base, region)
    looser = pb.bound > pb.sampled * 1.01
    assert looser.any()                     # a pair whose sampled peak is below its bound
    assert np.all(pb.bound >= pb.sampled)
    rec, guarantee = region_model(robot, base, region, 0.05)
    # the stored bound is, per joint, derived from the proved enclosures (the largest over the
    # branch and bound's final boxes of the dropped pairs' bounds there, or of their joint
    # sum), never from their sampled peaks
    by_bound = np.einsum("bpln,bp->ln", pb.leaves, rec.dropped.astype(float)).max(axis=0)
    by_sample = (pb.sampled * rec.dropped[:, :, None]).sum(axis=(0, 1))
    again = region_bound(robot, base, region, pb, rec.dropped, 0.05 * pb.scale)
    assert np.allclose(guarantee.bound, again, rtol=1e-12, atol=1e-12 * pb.scale.max())
    assert np.all(guarantee.bound <= by_bound * (1 + 1e-12))
    assert np.all(by_bound <= (pb.bound * rec.dropped[:, :, None]).sum(axis=(0, 1)) * (1 + 1e-12))
    assert np.any(by_bound > by_sample * 1.01)
    assert np.all(guarantee.sampled_error <= guarantee.bound * (1 + 1e-12))


def test_the_joint_sum_admits_pairs_the_pairs_bounds_do_not():
    """At EPS 0.01 (the main job's) the PUMA 560's model drops pairs whose bounds, added on
    each final box, exceed the budget: their joint sum, by branch and bound, fits it. The
    bound holds at 100,000 states against Pinocchio's rnea
    (:func:`test_the_region_bound_holds_at_every_sampled_state`)."""
    robot = load_robot("puma560")
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    pb = certified(robot, base, region)
    rec, guarantee = region_model(robot, base, region, 0.01)
    pieces = np.einsum("bpln,bp->ln", pb.leaves, rec.dropped.astype(float)).max(axis=0)
    budget = 0.01 * pb.scale
    assert np.any(pieces > budget) and np.all(guarantee.bound <= budget * (1 + 1e-12))
    assert np.all(guarantee.sampled_error <= guarantee.bound * (1 + 1e-12))
    # the branch and bound never proves less than the error found at sampled states
    low = guarantee.sampled_error * 0.99
    assert np.all(dropped_bound(robot, base, region, rec.dropped, low, 4096, pb.zero)
                  >= guarantee.sampled_error * (1 - 1e-12))


@pytest.mark.slow
def test_prove_dropped_proves_the_bound_and_never_a_false_one():
    """The quick proof on the dropped pairs alone: it proves the region model's own
    bound, and never a limit that Pinocchio's rnea shows is exceeded somewhere in the region
    (the error at sampled states, 1 % lowered)."""
    from gd_analyze.certify.certify import prove_dropped

    robot = load_robot("puma560")
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    rec, guarantee = region_model(robot, base, region, 0.05)
    assert rec.dropped.any()
    slack = 1e-9 * guarantee.scale
    pb = certified(robot, base, region)
    pieces = np.einsum("bpln,bp->ln", pb.leaves, rec.dropped.astype(float)).max(axis=0)
    assert prove_dropped(robot, base, region, rec.dropped, np.maximum(pieces, guarantee.bound)
                         + slack)
    tau_s = python_function(pruned_program(robot, base, rec.dropped))
    q, qd, qdd = _states(region, 20_000, seed=3)
    err = np.abs(tau_s(q, qd, qdd) - _rnea(robot, q, qd, qdd)).max(axis=0)
    j = int(np.argmax(err / guarantee.scale))
    assert err[j] > 1e-3 * guarantee.scale[j]
    false = guarantee.bound + slack
    false[j] = 0.99 * err[j]
    assert not prove_dropped(robot, base, region, rec.dropped, false)
    assert not prove_dropped(robot, base, region, rec.dropped, np.full(robot.n, np.nan))


def test_the_tree_tiles_the_region_and_gives_the_same_bounds_again():
    """The boxes rebuilt from a certification's tree cover the region once: random positions
    lie in exactly one box's interior (volume adds up to the region's), and the bounds derived
    on that tree without search equal the certification's."""
    from gd_analyze.certify.certify import certify, certify_tree, tiling
    from gd_analyze.certify.region import region_samples

    robot = _mixed()
    base = base_parameters(robot)
    region = joint_region(robot, np.asarray(robot.qdd_max, float))
    values = region_samples(robot, base, region, samples=100)
    pb = certify(robot, base, region, samples=100, max_boxes=64, values=values)
    levels = tiling(region, pb.split_joint, pb.split_at)
    lo = np.concatenate([a[~s] for a, _, s in levels])
    hi = np.concatenate([b[~s] for _, b, s in levels])
    np.testing.assert_array_equal(np.stack([lo, hi], axis=1), pb.leaf_boxes)
    q = np.random.default_rng(3).uniform(region.q_min, region.q_max, (20_000, robot.n))
    inside = ((q[:, None] > lo[None]) & (q[:, None] < hi[None])).all(axis=2)
    assert np.all(inside.sum(axis=1) == 1)
    volume = np.prod(hi - lo, axis=1).sum()
    assert abs(volume / np.prod(region.q_max - region.q_min) - 1) < 1e-12
    again = certify_tree(robot, base, region, pb.split_joint, pb.split_at, values)
    for f in ("bound", "leaves", "leaf_boxes", "sampled", "zero"):
        np.testing.assert_array_equal(getattr(again, f), getattr(pb, f), err_msg=f)


@pytest.mark.parametrize("name", ["mixed", "prismatic-first"])
def test_the_sampled_peaks_search_every_vertex_of_the_velocity_box(name):
    """Oracle: each pair's velocity peak at a position by brute force over all 2^n vertices
    of the velocity box; the peaks over the joints each column involves must equal it. The
    prismatic-first chain has columns whose velocity terms involve a single joint."""
    import itertools

    from gd_analyze.certify.certify import pair_magnitudes_at
    from gd_analyze.certify.region import channel_values, full_channels, sample_positions

    robot = _robot(name)
    base = base_parameters(robot)
    region = joint_region(robot, np.asarray(robot.qdd_max, float))
    cols = np.flatnonzero(base.independent.reshape(-1))
    V = channel_values(robot, sample_positions(region, 5), cols)
    beta = np.asarray(base.beta, float)
    got = pair_magnitudes_at(V, beta, region.qd_max, region.qdd_max)[:, :, 1]   # (B, b, n)
    n = robot.n
    verts = np.array(list(itertools.product([-1.0, 1.0], repeat=n))) * region.qd_max
    C = full_channels(V)[:, 1 + n:].reshape(V.positions, n, n, n, -1)     # (B, j, l, i, b)
    quad = np.einsum("kj,kl,Bjlib->Bkbi", verts, verts, C)
    want = np.abs(quad).max(axis=1) * np.abs(beta)[None, :, None]
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * want.max())


def test_pairs_proved_zero_are_zero_in_pinocchio_and_dropped_at_no_cost():
    """The PUMA's velocity pairs of ZZ2 and ZZ3 are proved identically zero: their enclosure
    is 0 on every final box, the same after a read-back of the tree; every inertial or
    velocity part declared zero at a joint is zero there in Pinocchio's regressor at random
    states (oracle), and an inertia column's part not zero in Pinocchio is never declared
    zero; the selection drops the zero pairs without adding to its bound."""
    from gd_analyze.certify.certify import certify, certify_tree
    from gd_analyze.certify.region import region_samples
    from gd_analyze.symbolic.pruning import prune_bounds, zero_parts

    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, acceleration_limits(robot)[0])
    values = region_samples(robot, base, region, samples=100)
    pb = certify(robot, base, region, samples=100, max_boxes=64, values=values)
    names = base.names()
    for zz in ("ZZ2", "ZZ3"):
        assert pb.zero[names.index(zz), 1], zz
    assert np.all(pb.leaves[pb.zero] == 0)
    again = certify_tree(robot, base, region, pb.split_joint, pb.split_at, values)
    np.testing.assert_array_equal(again.zero, pb.zero)
    # oracle: every part declared zero at a joint vanishes there in Pinocchio's regressor
    model = pinocchio_model(robot)
    data = model.createData()
    cols = np.flatnonzero(base.independent.reshape(-1))
    order = np.array([4, 5, 7, 6, 8, 9, 1, 2, 3, 0])        # ours (XX .. ZZ, MX .. M) in pin's
    pcols = 10 * (cols // 10) + order[cols % 10]
    rng = np.random.default_rng(11)
    part = np.zeros((2, robot.n, cols.size))                 # largest |part| per joint, column
    zero = np.zeros(robot.n)
    for _ in range(50):
        q = rng.uniform(region.q_min, region.q_max)
        qd = rng.uniform(-1, 1, robot.n) * region.qd_max
        qdd = rng.uniform(-1, 1, robot.n) * region.qdd_max
        G = pin.computeJointTorqueRegressor(model, data, q, zero, zero).copy()
        for p, (a, b) in enumerate(((zero, qdd), (qd, zero))):
            Y = pin.computeJointTorqueRegressor(model, data, q, a, b) - G
            part[p] = np.maximum(part[p], np.abs(Y[:, pcols]))
    part *= np.abs(base.beta)                                 # contributions
    scale = part.max()
    declared = zero_parts(robot, cols)[:, :2].transpose(1, 2, 0)      # (2, n, b)
    assert declared.any(axis=(1, 2)).all()                   # inertial and velocity zeros
    assert np.all(part[declared] <= 1e-12 * scale)
    assert np.all(part[1][:, pb.zero[:, 1]] <= 1e-12 * scale)
    # an inertia column's part declared zero only where Pinocchio's is: one not zero never is
    inertia = (cols % 10 < 6) & (np.abs(base.beta) > 0)
    np.testing.assert_array_equal(declared[:, :, inertia], part[:, :, inertia] <= 1e-12 * scale)
    # dropped at no cost: a budget of 0 still drops them, with a bound of 0
    pr = prune_bounds(robot, base, pb.scale, pb.bound, pb.leaves.sum(axis=1).max(axis=1), 0.0,
                      pieces=pb.leaves, zero=pb.zero)
    assert np.all(pr.dropped[pb.zero]) and np.all(pr.bound == 0)
    with pytest.raises(ValueError, match="declared zero"):
        wrong = pb.zero.copy()
        wrong[names.index("ZZ2"), 0] = True                  # the inertial part is not zero
        prune_bounds(robot, base, pb.scale, pb.bound, pb.leaves.sum(axis=1).max(axis=1), 0.0,
                     pieces=pb.leaves, zero=wrong)


def test_the_stored_trees_give_the_bound_again_and_it_holds_at_every_sampled_state():
    """The trees kept with the PUMA 560's region model (EPS 0.01, whose bound comes from the
    branch and bound on the joint sum) give its bound again without search, checked to tile
    the region; that bound is never below the error Pinocchio's rnea shows at 100,000
    sampled states, and a tree cut short, one with an extra box or a joint the arm does not
    have proves nothing."""
    from gd_analyze.certify.certify import proved_zero, tiling, tilings_bound, tree_bound

    robot = load_robot("puma560")
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    pb = certified(robot, base, region)
    rec, guarantee = region_model(robot, base, region, 0.01)
    assert guarantee.tilings, "no tree kept: the reader would search again"
    pieces = np.einsum("bpln,bp->ln", pb.leaves, rec.dropped.astype(float)).max(axis=0)
    assert np.any(guarantee.bound < 0.99 * pieces)       # the joint sum's search is needed
    slack = 1e-9 * guarantee.scale
    again = tilings_bound(robot, base, region, rec.dropped, guarantee.tilings)
    assert np.all(again <= guarantee.bound + slack), (again, guarantee.bound)
    # the pairs proved zero from the robot alone are the certification's
    np.testing.assert_array_equal(proved_zero(robot, base, region, rec.dropped),
                                  rec.dropped & pb.zero)
    # soundness against the oracle
    tau_s = python_function(pruned_program(robot, base, rec.dropped))
    q, qd, qdd, ref = _sampled(robot, region, STATES, seed=7)
    err = np.abs(tau_s(q, qd, qdd) - ref).max(axis=0)
    round_off = 64 * np.finfo(float).eps * max(guarantee.scale.max(), np.abs(ref).max())
    assert np.all(err <= again + round_off), (err, again)
    j = int(np.argmax(err / guarantee.scale))
    assert err[j] > 0.5 * again[j]                      # not vacuous: the bound is close
    # a coarser tree (the last box the search halved left whole) is a tiling: a sound bound
    tree = guarantee.tilings[0]
    last = int(np.flatnonzero(tree >= 0)[-1])               # a box of the level before last
    width = len(tiling(region, tree)[-1][0])                # the last level: halves only
    start = tree.size - width                               # lower halves, then upper ones
    coarse = np.delete(tree, [start + width // 2 - 1, tree.size - 1])
    coarse[last] = -1
    loose = tree_bound(robot, base, region, coarse, rec.dropped)
    assert np.all(loose >= again - slack) and np.all(err <= loose + round_off)
    # not trees of the region: no bound from them
    n = robot.n
    for forged in (tree[:-1], np.concatenate([tree, [-1]]), np.where(tree >= 0, n, tree),
                   np.where(tree == tree.max(), -2, tree)):
        assert np.all(tilings_bound(robot, base, region, rec.dropped, (forged,)) == np.inf)
        with pytest.raises(ValueError):
            tiling(region, forged)


def test_boxes_are_cut_along_the_joints_their_open_columns_depend_on():
    """A column of link k is a function of q_1..q_k alone (its torques come from link k's
    motion), checked here on Pinocchio's joint torque regressor; the cut of a box goes to the
    joint of the largest width times the number of its open columns that depend on it."""
    from gd_analyze.certify.certify import _bisect, _demand

    robot = load_robot("puma560")
    model = pinocchio_model(robot)
    data = model.createData()
    rng = np.random.default_rng(5)
    q, qd, qdd = (rng.uniform(-1, 1, robot.n) for _ in range(3))
    Y = pin.computeJointTorqueRegressor(model, data, q, qd, qdd).copy()
    for j in range(robot.n):                    # moving joint j changes no column below it
        q2 = q.copy()
        q2[j] += 0.7
        Y2 = pin.computeJointTorqueRegressor(model, data, q2, qd, qdd)
        assert np.allclose(Y2[:, :10 * j], Y[:, :10 * j], atol=1e-12)
        if j:                                   # (joint 1 turns about gravity: no change)
            assert not np.allclose(Y2[:, 10 * j:], Y[:, 10 * j:], atol=1e-9)
    cols = np.array([10 * 1 + 5, 10 * 4 + 2, 10 * 4 + 8])               # link 2, link 5 (two)
    above = np.zeros((3, 3, robot.n, cols.size), bool)
    above[0, 1, 2, 0] = True                                            # link 2's column
    above[1, 0, 0, 1] = above[1, 2, 3, 2] = True                        # link 5's columns
    above[2, :, :, 0] = True
    above[2, :, :, 1] = True
    demand = _demand(above, cols)
    assert np.allclose(demand, np.array([[1, 1, 0, 0, 0, 0], [2, 2, 2, 2, 2, 0],
                                         [2, 2, 1, 1, 1, 0]]) + 1e-3)
    lo = np.tile([-3.0, -1.0, -1.0, -1.0, -1.0, -3.0], (3, 1))
    hi = -lo
    rel = np.array([False, True, True, True, True, True])
    joints = _bisect(lo, hi, rel, demand)[2]
    # box 0: joint 2 (widths 2, demand 1 on joints 1-2 only); box 1: joints 2-5 tie, the
    # first; box 2: joint 2 (demand 2 against 1); joint 6 is the widest but wanted by none
    assert joints.tolist() == [1, 1, 1]
    assert _bisect(lo, hi, rel)[2].tolist() == [5, 5, 5]


def test_the_witnessed_enclosures_alone_give_the_bounds_and_wrong_ones_only_larger():
    """Oracle: the read-back evaluating every box of the tree. On the (box, link) pairs the
    certification's witnesses name alone, the bounds are the same bit for bit, with fewer
    enclosures evaluated; witnesses left out or added at random never give a bound below
    them (+inf where a final box has none), and random states' contributions stay within
    the bounds derived with them."""
    from gd_analyze.certify.certify import certify, certify_tree, pair_magnitudes_at
    from gd_analyze.certify.region import channel_values, region_samples

    robot = _mixed()
    base = base_parameters(robot)
    region = joint_region(robot, np.asarray(robot.qdd_max, float))
    values = region_samples(robot, base, region, samples=100)
    pb = certify(robot, base, region, samples=100, max_boxes=64, values=values)
    cols = np.flatnonzero(base.independent.reshape(-1))
    links = np.unique(cols // 10).size
    assert pb.witness.shape == (pb.boxes, robot.n) and pb.witness.sum() < pb.boxes * links
    full = certify_tree(robot, base, region, pb.split_joint, pb.split_at, values)
    named = certify_tree(robot, base, region, pb.split_joint, pb.split_at, values,
                         witness=pb.witness)
    for f in ("bound", "leaves", "zero"):
        np.testing.assert_array_equal(getattr(named, f), getattr(full, f), err_msg=f)
    rng = np.random.default_rng(8)
    q = rng.uniform(region.q_min, region.q_max, (300, robot.n))
    at = pair_magnitudes_at(channel_values(robot, q, cols), np.asarray(base.beta, float),
                            region.qd_max, region.qdd_max).max(axis=0)        # (b, 3, n)
    for trial in range(4):
        wrong = pb.witness ^ (rng.random(pb.witness.shape) < 0.3)
        other = certify_tree(robot, base, region, pb.split_joint, pb.split_at, values,
                             witness=wrong)
        assert np.all(other.leaves >= full.leaves) and np.all(other.bound >= full.bound)
        # the parts proved zero are 0; at the states, their round-off
        assert np.all(at <= other.bound + 1e-12 * pb.scale), (at - other.bound).max()
    with pytest.raises(ValueError, match="witness"):
        certify_tree(robot, base, region, pb.split_joint, pb.split_at, values,
                     witness=pb.witness[:-1])


def test_the_velocity_support_sees_a_value_past_the_first_position():
    """Oracle: (V != 0).any over positions and joints. A channel zero at the first position
    but not later is used; one zero everywhere is not."""
    from gd_analyze.certify.certify import _nonzero

    rng = np.random.default_rng(2)
    V = rng.standard_normal((6, 5, 3, 4))
    V[:, 1, :, 2] = 0.0
    V[0, 3, :, 0] = 0.0
    V[:, 4, :, 1] = 0.0
    V[4, 4, 2, 1] = -1e-300
    want = (V != 0).any(axis=(0, 2))
    np.testing.assert_array_equal(_nonzero(V), want)
    assert want[3, 0] and want[4, 1] and not want[1, 2]


@pytest.mark.parametrize("share", [1.0, 0.3])
def test_a_resumed_branch_and_bound_gives_the_fresh_ones_bound_and_tree(monkeypatch, share):
    """The branch and bound on a dropped set's joint sum, first with 256 boxes and then
    resumed up to 2,048 (as the pruning's search runs its scout and then the full one), gives
    the bound and tree of one fresh search of 2,048 boxes, bit for bit, and evaluates only
    the boxes beyond the first call's. With the PUMA 560's region model at EPS 0.01, its
    budget 0.01 s_i (share 1: the search ends with every box within it) and 0.3 of it (no
    tiling reaches it: the search runs out of boxes)."""
    import gd_analyze.certify.certify as certify_module
    from gd_analyze.certify.certify import dropped_search

    robot = load_robot("puma560")
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    pb = certified(robot, base, region)
    rec, _ = region_model(robot, base, region, 0.01)
    limit = share * 0.01 * np.asarray(pb.scale, float)
    seen = []
    summed = certify_module._summed

    def counted(robot, base, region, lo, *rest):
        seen.append(lo.shape[0])
        return summed(robot, base, region, lo, *rest)
    monkeypatch.setattr(certify_module, "_summed", counted)
    fresh = dropped_search(robot, base, region, rec.dropped, limit, 2048, pb.zero)
    boxes = sum(seen)
    kept: dict = {}
    seen.clear()
    first = dropped_search(robot, base, region, rec.dropped, limit, 256, pb.zero, kept)
    scout = sum(seen)
    assert 0 < scout <= 256 and kept
    seen.clear()
    again = dropped_search(robot, base, region, rec.dropped, limit, 2048, pb.zero, kept)
    assert scout + sum(seen) == boxes > 256
    np.testing.assert_array_equal(again[0], fresh[0])
    np.testing.assert_array_equal(again[1], fresh[1])
    assert np.all(first[0] >= fresh[0])
    assert np.all(fresh[0] <= limit) == (share == 1.0) == (boxes < 2048 - 256)


def test_the_trees_bound_reads_each_enclosure_as_it_was_evaluated(monkeypatch):
    """The bound of the PUMA 560's stored trees is the one found with every box's channel
    enclosures passed on intact (the joint sums given copies of them): the sums do not use up
    the enclosures that the box's own channel bound and its sub-boxes' intersections read
    afterwards."""
    from gd_analyze.certify import certify as cert

    robot = load_robot("puma560")
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    rec, guarantee = region_model(robot, base, region, 0.01)
    assert guarantee.tilings
    got = cert.tilings_bound(robot, base, region, rec.dropped, guarantee.tilings)
    sums = cert._joint_sums

    def on_copies(robot, base, region, used, pairs, zero, c_lo, c_hi):
        return sums(robot, base, region, used, pairs, zero, c_lo.copy(), c_hi.copy())

    monkeypatch.setattr(cert, "_joint_sums", on_copies)
    intact = cert.tilings_bound(robot, base, region, rec.dropped, guarantee.tilings)
    np.testing.assert_array_equal(got, intact)
    assert np.all(intact <= guarantee.bound + 1e-9 * guarantee.scale)


@pytest.mark.parametrize("boxes", [5, 300])
def test_channels_of_a_level_are_the_chunks_laid_end_to_end_and_hulled_with_the_parents(boxes):
    """The channel enclosures of a level of boxes (one chunk, or several) are each chunk's
    own, in order, intersected with their parents' (the hull where round-off leaves the
    intersection empty), as evaluated box block by box block here; the parents are left as
    they are."""
    from gd_analyze.certify import certify as cert
    from gd_analyze.certify.regressor_bounds import channel_enclosures

    robot = _mixed()
    base = base_parameters(robot)
    region = joint_region(robot, np.asarray(robot.qdd_max, float))
    cols = np.flatnonzero(base.independent.reshape(-1))[:5]
    rng = np.random.default_rng(3)
    a = rng.uniform(region.q_min, region.q_max, (boxes, robot.n))
    b = rng.uniform(region.q_min, region.q_max, (boxes, robot.n))
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    blocks = [channel_enclosures(robot, lo[k:k + cert._CHUNK], hi[k:k + cert._CHUNK], cols)
              for k in range(0, boxes, cert._CHUNK)]
    want_lo = np.concatenate([x[0] for x in blocks])
    want_hi = np.concatenate([x[1] for x in blocks])
    assert len(blocks) == (1 if boxes < cert._CHUNK else 3)
    got = cert._channels(robot, lo, hi, cols)
    np.testing.assert_array_equal(got[0], want_lo)
    np.testing.assert_array_equal(got[1], want_hi)
    # parents: some wider, some narrower, some disjoint (the hull of the crossed ends)
    width = want_hi - want_lo
    p_lo = want_lo + rng.uniform(-1.0, 1.0, want_lo.shape) * width
    p_hi = p_lo + rng.uniform(-0.5, 2.0, want_lo.shape) * width
    p_lo[..., 0], p_hi[..., 0] = want_hi[..., 0] + 1.0, want_hi[..., 0] + 2.0   # disjoint
    kept = (p_lo.copy(), p_hi.copy())
    got = cert._channels(robot, lo, hi, cols, (p_lo, p_hi))
    top, bottom = np.maximum(want_lo, p_lo), np.minimum(want_hi, p_hi)
    np.testing.assert_array_equal(got[0], np.minimum(top, bottom))
    np.testing.assert_array_equal(got[1], np.maximum(top, bottom))
    assert np.all(got[0] <= got[1])
    np.testing.assert_array_equal(p_lo, kept[0])
    np.testing.assert_array_equal(p_hi, kept[1])


def test_joint_sums_of_the_same_parameters_share_their_enclosures(monkeypatch):
    """Joint sums of two sets of pairs of the same parameters on one tree (two budgets of a
    tolerance ladder): the second evaluates no column, shares the first's enclosures, and
    gives the pairs, the sums and the bounds of joint sums evaluated afresh, channel by
    channel (the bound of every pair alone, of the set, of part of it); other parameter
    values or another arm are evaluated anew."""
    from gd_analyze.certify import certify as cert

    robot = _mixed()
    base = base_parameters(robot)
    region = joint_region(robot, np.asarray(robot.qdd_max, float))
    pb = cert.certify(robot, base, region, samples=100, max_boxes=64)
    live = np.flatnonzero((~pb.zero).any(axis=1))
    some = np.zeros(pb.zero.shape, bool)
    some[live] = ~pb.zero[live]
    fewer = some.copy()                     # the same parameters, one part of each fewer
    for m in live:
        if fewer[m].sum() > 1:
            fewer[m, np.flatnonzero(fewer[m])[0]] = False
    assert (fewer != some).any() and np.array_equal(fewer.any(axis=1), some.any(axis=1))
    asked = []
    evaluate = cert.channel_enclosures

    def counted(robot, lo, hi, columns, *a, **k):
        asked.append((robot, columns))
        return evaluate(robot, lo, hi, columns, *a, **k)

    monkeypatch.setattr(cert, "channel_enclosures", counted)

    def sums(arm, pairs, keep, b=base):
        if not keep:
            cert._LEAF_CHANNELS.clear()
            cert._JOINT_SUMS.clear()
        asked.clear()
        return cert.joint_sums(arm, b, region, pb.split_joint, pb.split_at, pairs, pb.zero)

    first = sums(robot, some, False)
    second = sums(robot, fewer, True)
    assert asked == [] and second.mid is first.mid and second.rad is first.rad
    assert not second.mid.flags.writeable and not second.rad.flags.writeable
    for got, pairs in ((first, some), (second, fewer)):
        fresh = sums(robot, pairs, False)
        assert asked
        np.testing.assert_array_equal(got.pairs, fresh.pairs)
        np.testing.assert_array_equal(got.columns, fresh.columns)
        np.testing.assert_array_equal(got.mid, fresh.mid)
        np.testing.assert_array_equal(got.rad, fresh.rad)
        for dropped in (pairs, fewer, *(np.eye(pairs.size, dtype=bool)[k].reshape(pairs.shape)
                                         for k in np.flatnonzero(pairs)[:4])):
            np.testing.assert_array_equal(got.bound(dropped), fresh.bound(dropped))
    assert np.isinf(second.bound(some)).all()           # a pair it does not hold
    before, after = np.zeros_like(some), np.zeros_like(some)    # as many parameters, one
    before[live[:-1]], after[live[1:]] = some[live[:-1]], some[live[1:]]   # other each
    cols = np.flatnonzero(base.independent.reshape(-1))
    sums(robot, before, False)
    cert._LEAF_CHANNELS.clear()                         # only the sums kept
    shifted = sums(robot, after, True)
    assert {c for a in asked for c in np.asarray(a[1]).tolist()} == {cols[live[-1]]}
    fresh = sums(robot, after, False)
    np.testing.assert_array_equal(shifted.columns, fresh.columns)
    np.testing.assert_array_equal(shifted.mid, fresh.mid)
    np.testing.assert_array_equal(shifted.rad, fresh.rad)
    np.testing.assert_array_equal(shifted.bound(after), fresh.bound(after))
    heavier = dataclasses.replace(base, beta=2.0 * np.asarray(base.beta, float))
    kept = sums(robot, some, False)
    other = sums(robot, some, True, heavier)            # the columns kept, the sums not
    assert other.mid is not kept.mid
    fresh = sums(robot, some, False, heavier)
    np.testing.assert_array_equal(other.mid, fresh.mid)
    np.testing.assert_array_equal(other.rad, fresh.rad)
    equal = _mixed()                                    # an equal arm, another object
    sums(robot, some, False)
    sums(equal, some, True)
    assert asked and all(a is equal for a, _ in asked)


def test_joint_sums_on_one_tree_evaluate_each_column_once_and_give_the_same_sums(monkeypatch):
    """Joint sums of two sets of pairs on one certification's tree (as two budgets ask): the
    second evaluates only the columns the first did not, and every sum equals the one
    evaluated afresh, column by column, with nothing kept; another arm is evaluated anew."""
    from gd_analyze.certify import certify as cert

    robot = _mixed()
    base = base_parameters(robot)
    region = joint_region(robot, np.asarray(robot.qdd_max, float))
    pb = cert.certify(robot, base, region, samples=100, max_boxes=64)
    live = np.flatnonzero((~pb.zero).any(axis=1))
    assert live.size >= 6
    few, more = np.zeros(pb.zero.shape, bool), np.zeros(pb.zero.shape, bool)
    few[live[::3]] = True                               # a set inside the other
    more[live[::3]] = more[live[1::3]] = True
    cols = np.flatnonzero(base.independent.reshape(-1))
    asked = []
    evaluate = cert.channel_enclosures

    def counted(robot, lo, hi, columns, *a, **k):
        asked.append((robot, set(np.asarray(columns, int).tolist())))
        return evaluate(robot, lo, hi, columns, *a, **k)

    monkeypatch.setattr(cert, "channel_enclosures", counted)

    def sums(arm, pairs, keep):
        if not keep:
            cert._LEAF_CHANNELS.clear()
            cert._JOINT_SUMS.clear()
        asked.clear()
        out = cert.joint_sums(arm, base, region, pb.split_joint, pb.split_at, pairs, pb.zero)
        return out, set().union(*(c for _, c in asked))

    first, _ = sums(robot, few, False)
    second, evaluated = sums(robot, more, True)
    assert set(cols[second.columns]) - set(cols[first.columns])     # columns were added
    assert evaluated == set(cols[second.columns]) - set(cols[first.columns])
    again, evaluated = sums(robot, few, True)
    assert evaluated == set()                           # all kept: nothing evaluated
    for got, pairs in ((first, few), (second, more), (again, few)):
        fresh, evaluated = sums(robot, pairs, False)
        assert evaluated == set(cols[fresh.columns])
        np.testing.assert_array_equal(got.columns, fresh.columns)
        np.testing.assert_array_equal(got.pairs, fresh.pairs)
        np.testing.assert_array_equal(got.mid, fresh.mid)
        np.testing.assert_array_equal(got.rad, fresh.rad)
    other = _mixed()                                    # an equal arm, another object
    _, evaluated = sums(other, few, True)
    assert evaluated == set(cols[first.columns]) and all(a is other for a, _ in asked)


def test_leaf_channels_of_a_seven_joint_ladder_are_kept_across_its_budgets(monkeypatch):
    """The leaf enclosures a 7-joint arm's tolerance ladder asks for on one certification's
    tree (512 final boxes; 29 columns at EPS 0.01, 20 of them at 0.001, 36 at 0.05, as the
    TALOS arm's) are kept between the calls: the second evaluates nothing, the third only the
    columns the first did not hold; each call gives the columns asked, in order, as a
    fresh evaluation does. A 12-joint arm's 4 columns on 300 boxes (2.3 million numbers) are not kept."""
    import types

    from gd_analyze.certify import certify as cert

    n, leaves = 7, 512
    robot = types.SimpleNamespace(n=n)          # the arm keys what is kept, by identity
    asked = []

    def evaluated(arm, levels, count, cols):
        asked.append(list(np.asarray(cols, int)))
        value = np.asarray(cols, float)[None, None, None, :]
        shape = (count, 1 + n + n * n, n, len(cols))
        return np.broadcast_to(value, shape).copy(), np.broadcast_to(value + 0.5, shape).copy()

    monkeypatch.setattr(cert, "_tree_channels", evaluated)
    monkeypatch.setattr(cert, "_LEAF_CHANNELS", [])
    middle, few, more = np.arange(0, 58, 2), np.arange(0, 40, 2), np.arange(0, 72, 2)
    for cols, want in ((middle, [list(middle)]), (few, []),
                       (more, [list(np.setdiff1d(more, middle))])):
        asked.clear()
        lo, hi = cert._leaf_channels(robot, b"tree", None, leaves, cols)
        assert asked == want
        np.testing.assert_array_equal(lo[0, 0, 0], cols)
        np.testing.assert_array_equal(hi[-1, -1, -1], cols + 0.5)
        assert lo.shape == (leaves, 1 + n + n * n, n, cols.size) and lo.flags.writeable
    n, leaves = 12, 300                         # 2.3 million numbers: between the caps
    robot = types.SimpleNamespace(n=n)
    for _ in range(2):
        asked.clear()
        cert._leaf_channels(robot, b"tree", None, leaves, np.arange(4))
        assert asked == [list(range(4))]


def test_the_decomposed_bound_holds_at_every_sampled_state_and_is_below_the_final_boxes():
    """The Panda's region model at EPS 0.01 drops pairs of links on more than three joints:
    its bound on a joint is the decomposition's (the branch and bound on the first links'
    pairs plus the final boxes' bound of the rest), below the final boxes' bound of the whole
    set, never above it, and never below the error Pinocchio's rnea shows at 100,000 sampled
    states; the pair of trees kept with the model gives it again without search, and a tree
    of the pair cut short, with an extra box or a joint the arm does not have proves
    nothing."""
    from gd_analyze.certify.certify import (
        JOINT_DIMS,
        decomposed_bound,
        decomposed_pairs,
        decomposed_tree_bound,
        joint_sums,
        leaf_bound,
        split_joints,
        tilings_bound,
    )

    robot = load_robot("panda")
    region = joint_region(robot, acceleration_limits(robot)[0])
    base = base_parameters(robot)
    rec, guarantee = region_model(robot, base, region, 0.01)
    pb = certified(robot, base, region)
    dropped = np.asarray(rec.dropped, bool)
    assert split_joints(robot, base, dropped, pb.zero).sum() > JOINT_DIMS
    first = decomposed_pairs(robot, base, dropped, pb.zero)
    assert first is not None and first.any() and (dropped & ~pb.zero & ~first).any()
    budget = 0.01 * pb.scale
    sums = joint_sums(robot, base, region, pb.split_joint, pb.split_at, dropped, pb.zero)
    old = leaf_bound(pb, sums, dropped)                 # the bound before the decomposition
    split = decomposed_bound(robot, base, region, pb, dropped, budget, sums)
    again = region_bound(robot, base, region, pb, dropped, budget)
    slack = 1e-12 * pb.scale
    assert np.all(again <= old + slack) and np.all(again <= split + slack)
    assert np.allclose(guarantee.bound, again, rtol=1e-12, atol=1e-12 * pb.scale.max())
    over = old > budget                                 # the decomposition is needed there
    assert over.any() and np.all(again[over] <= budget[over] * (1 + 1e-12))
    assert np.all(guarantee.bound <= budget * (1 + 1e-12))
    # soundness against the oracle, of the decomposition alone and of the stored bound
    tau_s = python_function(pruned_program(robot, base, dropped))
    q, qd, qdd, ref = _sampled(robot, region, STATES, seed=7)
    err = np.abs(tau_s(q, qd, qdd) - ref).max(axis=0)
    round_off = 64 * np.finfo(float).eps * max(guarantee.scale.max(), np.abs(ref).max())
    assert np.all(np.isfinite(err))
    assert np.all(err <= split + round_off), (err, split)
    assert np.all(err <= guarantee.bound + round_off), (err, guarantee.bound)
    j = int(np.argmax(np.where(over, old / budget, 0.0)))
    assert err[j] > 0.1 * split[j]                      # not vacuous
    # the pair of trees kept with the model gives the bound again without search, and holds
    assert guarantee.decomposed, "no pair of trees kept: the reader would search again"
    again = tilings_bound(robot, base, region, dropped, guarantee.tilings,
                          guarantee.decomposed)
    assert np.all(again <= guarantee.bound + 1e-9 * pb.scale), (again, guarantee.bound)
    assert np.all(err <= again + round_off), (err, again)
    # a tree of the pair cut short, with an extra box, or a cut along a joint the arm does
    # not have: not a tiling, no bound from the pair
    first_tree, rest_tree = guarantee.decomposed[0]
    for forged in (first_tree[:-1], np.concatenate([first_tree, [-1]]),
                   np.where(first_tree >= 0, robot.n, first_tree)):
        for pair in ((forged, rest_tree), (rest_tree, forged)):
            assert np.all(tilings_bound(robot, base, region, dropped, (), (pair,)) == np.inf)
            with pytest.raises(ValueError):
                decomposed_tree_bound(robot, base, region, dropped, *pair)
    # the region as one box for the first links' pairs: a tiling, a sound bound far above
    whole = decomposed_tree_bound(robot, base, region, dropped, np.full(1, -1), rest_tree)
    assert np.all(whole >= again - 1e-9 * pb.scale) and np.any(whole > guarantee.bound)


def test_the_decomposed_limit_is_the_budget_left_rounded_down_on_a_grid():
    """The branch and bound on the first links' pairs seeks the budget left by the rest,
    rounded down on a grid of 1e-6 of the budget: never above it, never below 0, and the same
    for a rest that differs in its last bits (joint sums of other parameters)."""
    from gd_analyze.certify.certify import DECOMPOSED_GRID, decomposed_limit

    limit = np.array([2.0, 1.0, 0.0, 3.0, 1.0])
    rest = np.array([0.5123456789, 1.5, 0.0, 1.2345678901, np.inf])
    got = decomposed_limit(limit, rest)
    left = np.maximum(limit - rest, 0.0)
    assert np.all(got >= 0) and np.all(got <= left)
    assert np.all(got >= left - DECOMPOSED_GRID * limit)
    assert got[1] == 0 and got[2] == 0 and got[4] == 0
    np.testing.assert_array_equal(got, decomposed_limit(limit, rest * (1 + 4e-16)))


def test_the_compiled_joint_sum_is_the_scaled_enclosures_added():
    """summed_kernel (the branch and bound's joint sum in one pass) gives the sums of the
    array code (certify._scaled, then JointSums.sums' weighted sum over the columns) on
    random enclosures, weights of 0 and 1 and signed betas, to a few roundings; an infinite
    enclosure of a column weighted 0 is left out."""
    from gd_analyze.certify.ball_kernels import summed_kernel
    from gd_analyze.certify.certify import _scaled, _slack

    rng = np.random.default_rng(5)
    B, C, n, k = 9, 13, 3, 6
    a, b = rng.normal(size=(2, B, C, n, k))
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    beta = rng.normal(size=k)
    weight = (rng.random((C, n, k)) < 0.6).astype(float)
    slack = _slack(n, k)
    mid, rad = summed_kernel(lo, hi, beta, weight, slack)
    m_ref, r_ref = _scaled([lo.copy(), hi.copy()], beta, slack)
    np.testing.assert_allclose(mid, np.einsum("lcik,cik->lci", m_ref, weight),
                               rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(rad, np.einsum("lcik,cik->lci", r_ref, weight),
                               rtol=1e-13, atol=1e-15)
    assert np.all(rad >= 0)
    off = np.argwhere(weight == 0)[0]
    hi[:, off[0], off[1], off[2]] = np.inf
    again = summed_kernel(lo, hi, beta, weight, slack)
    assert np.all(np.isfinite(again[1])) and np.array_equal(again[0], mid)
