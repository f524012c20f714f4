"""Planning: the quintic plan within the limits, and the shipped trajectory as the default plan."""

import math

import numpy as np

from conftest import SHIPPED
from gd_analyze.io.planning import DEFAULT_GOAL_DEG, DEFAULT_START_DEG, plan_quintic, quintic_duration
from gd_analyze.io.trajectory import read_trajectory
import pytest
from gd_analyze.io.planning import random_trajectories


def _default_plan(puma, n=31):
    return plan_quintic(puma, np.radians(DEFAULT_START_DEG), np.radians(DEFAULT_GOAL_DEG), n)


def test_plan_respects_limits_and_one_is_active(puma):
    traj = _default_plan(puma, n=20001)      # dense, to find the peaks
    assert traj.t.shape == (20001,)
    peak_v = np.abs(traj.qd).max(axis=0) / puma.qd_max
    peak_a = np.abs(traj.qdd).max(axis=0) / puma.qdd_max
    assert peak_v.max() <= 1 + 1e-9 and peak_a.max() <= 1 + 1e-9
    assert max(peak_v.max(), peak_a.max()) > 1 - 1e-6      # shortest duration: a limit binds
    np.testing.assert_allclose(traj.q[0], np.radians(DEFAULT_START_DEG))
    np.testing.assert_allclose(traj.q[-1], np.radians(DEFAULT_GOAL_DEG))
    np.testing.assert_allclose(traj.qd[[0, -1]], 0, atol=1e-15)
    np.testing.assert_allclose(traj.qdd[[0, -1]], 0, atol=1e-12)


def test_plan_derivatives_are_consistent(puma):
    traj = _default_plan(puma, n=4001)
    dt = traj.t[1] - traj.t[0]
    np.testing.assert_allclose(np.gradient(traj.q, dt, axis=0)[1:-1], traj.qd[1:-1], atol=1e-5)
    np.testing.assert_allclose(np.gradient(traj.qd, dt, axis=0)[1:-1], traj.qdd[1:-1], atol=1e-5)


def test_duration_formula_binding_joint(puma):
    # Joint 6 moves 240 deg with qdd_max 80 deg/s^2: T = sqrt(10 * 240 / (sqrt(3) * 80)) s
    T = quintic_duration(puma, np.radians(DEFAULT_START_DEG), np.radians(DEFAULT_GOAL_DEG))
    assert math.isclose(T, math.sqrt(10 * 240 / (math.sqrt(3) * 80)), rel_tol=1e-12)


def test_shipped_trajectory_is_the_default_plan(puma):
    shipped = read_trajectory(SHIPPED, 6)
    plan = _default_plan(puma)
    assert shipped.derivatives == "file" and shipped.t.shape == (31,)
    for name in ("t", "q", "qd", "qdd"):
        np.testing.assert_allclose(getattr(shipped, name), getattr(plan, name), rtol=0,
                                   atol=1e-14)


@pytest.mark.parametrize("name", ["puma", "two_link"])
def test_random_trajectories_respect_the_limits(name, request):
    robot = request.getfixturevalue(name)
    trajs = random_trajectories(robot, 25, seed=11)
    assert len(trajs) == 25
    tol = 1 + 1e-12
    for k, tr in enumerate(trajs):
        assert tr.source == f"random-11-{k}"
        assert tr.q.shape == tr.qd.shape == tr.qdd.shape == (31, robot.n)
        assert np.all(tr.q >= robot.q_min) and np.all(tr.q <= robot.q_max)
        assert np.all(np.abs(tr.qd) <= robot.qd_max * tol)
        assert np.all(np.abs(tr.qdd) <= robot.qdd_max * tol)
        np.testing.assert_array_equal(tr.qd[[0, -1]], 0.0)
        # the shortest such motion: densely sampled, one joint reaches a limit
        dense = plan_quintic(robot, tr.q[0], tr.q[-1], n_setpoints=4001, duration=tr.t[-1])
        use = max(np.max(np.abs(dense.qd) / robot.qd_max),
                  np.max(np.abs(dense.qdd) / robot.qdd_max))
        assert use == pytest.approx(1.0, abs=1e-5)
    again = random_trajectories(robot, 25, seed=11)
    other = random_trajectories(robot, 25, seed=12)
    assert all(np.array_equal(a.q, b.q) for a, b in zip(trajs, again))
    assert not any(np.array_equal(a.q, b.q) for a, b in zip(trajs, other))
    # starts and goals spread over the whole range of every joint
    starts = np.array([tr.q[0] for tr in trajs])
    span = robot.q_max - robot.q_min
    assert np.all(starts.max(axis=0) - starts.min(axis=0) > 0.4 * span)


def test_random_trajectories_bad_arguments(puma):
    with pytest.raises(ValueError):
        random_trajectories(puma, 0)
    with pytest.raises(ValueError):
        random_trajectories(puma, 3, seed=-1)
    with pytest.raises(ValueError):
        random_trajectories(puma, 3, n_setpoints=1)
