"""Planning: the quintic plan within the limits, and the shipped trajectory as the default plan."""

import math

import numpy as np
import pytest
from conftest import SHIPPED

from gd_analyze.trajectory.planning import (
    DEFAULT_GOAL_DEG,
    DEFAULT_START_DEG,
    plan_quintic,
    quintic_duration,
    quintic_plan,
    random_trajectories,
)
from gd_analyze.trajectory.trajectory import read_trajectory


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


def test_default_motion_moves_joints_with_equal_limits_differently():
    """Stanford's joints 1, 2, 4 and 6 share their limits: the default plan still moves them
    differently, so no difference q_i - q_j of two revolute joints stays constant (a plain
    quarter-to-three-quarters plan made joints 2 and 4 move alike, and sin(q2 - q4) vanish)."""
    from gd_analyze import load_robot
    from gd_analyze.trajectory.planning import default_motion

    # (the PUMA 560 has its own default, DEFAULT_START_DEG -> DEFAULT_GOAL_DEG, whose joints
    # 1 and 5 move alike; q1 appears nowhere in its D, h or c)
    for name in ("stanford", "two-link"):
        robot = load_robot(name)
        start, goal = default_motion(robot)
        assert (start >= robot.q_min).all() and (start <= robot.q_max).all()
        assert (goal >= robot.q_min).all() and (goal <= robot.q_max).all()
        traj = plan_quintic(robot, start, goal, 31)
        rev = np.flatnonzero(~np.asarray(robot.prismatic, bool))
        for a in rev:
            for b in rev[rev > a]:
                diff = traj.q[:, a] - traj.q[:, b]
                assert np.ptp(diff) > 0.05, (name, a + 1, b + 1)


def test_default_motion_rule_and_infinite_limits():
    import dataclasses

    from gd_analyze import load_robot
    from gd_analyze.trajectory.planning import default_motion

    robot = load_robot("stanford")
    lo, hi = robot.q_min, robot.q_max
    start, goal = default_motion(robot)
    np.testing.assert_allclose((start - lo) / (hi - lo), [0.20, 0.64, 0.28, 0.80, 0.36, 0.76])
    np.testing.assert_allclose((goal - lo) / (hi - lo), [0.76, 0.24, 0.72, 0.32, 0.68, 0.20])
    free = dataclasses.replace(robot, q_min=np.full(6, -np.inf), q_max=np.full(6, np.inf))
    s, g = default_motion(free)
    # revolute joint 1: 0.20 -> 0.76 of [-120, 120] deg; prismatic joint 3: 0.28 -> 0.72 of
    # [-0.1, 0.3] m
    np.testing.assert_allclose(np.degrees([s[0], g[0]]), [-72.0, 62.4])
    np.testing.assert_allclose([s[2], g[2]], [0.012, 0.188])


_READ_SIDECAR = """
import resource, sys
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))   # old code: MemoryError, not a
from gd_analyze.trajectory.planning import read_provenance           # full machine
print(read_provenance(sys.argv[1]))
"""


@pytest.mark.parametrize("kind", ["fifo", "link_to_fifo", "dev_zero", "large"])
def test_a_sidecar_is_read_only_if_a_small_regular_file(tmp_path, kind):
    """A FIFO sidecar would hang evaluate and control; /dev/zero would fill the memory."""
    import os
    import subprocess
    import sys

    side = tmp_path / "t.provenance.json"
    if kind == "fifo":
        os.mkfifo(side)
    elif kind == "link_to_fifo":
        os.mkfifo(tmp_path / "pipe")
        side.symlink_to(tmp_path / "pipe")
    elif kind == "dev_zero":
        side.symlink_to("/dev/zero")
    else:
        side.write_text('{"robot": "' + "x" * (2 << 20) + '"}')
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), OPENBLAS_NUM_THREADS="1")
    run = subprocess.run([sys.executable, "-c", _READ_SIDECAR, str(tmp_path / "t.csv")],
                         capture_output=True, text=True, env=env, timeout=300)  # a safety net
    assert (run.returncode, run.stdout) == (0, "None\n"), run.stderr[-500:]


def _oracle_quintic(q0, q1, T, N):
    """The quintic sampled at once, written out from its definition: s(u) = 10 u^3 - 15 u^4
    + 6 u^5, u = t / T, t = linspace(0, T, N), and its first two time derivatives."""
    t = np.linspace(0.0, T, N)
    u = (t / T)[:, None]
    dq = q1 - q0
    return (t, q0 + u**3 * (10 - 15 * u + 6 * u**2) * dq,
            30 * u**2 * (1 - u) ** 2 / T * dq, 60 * u * (1 - u) * (1 - 2 * u) / T**2 * dq)


@pytest.mark.parametrize("N, size", [(2, 1), (3, 2), (1000, 7), (1001, 1000), (5000, 4999)])
def test_chunks_are_the_whole_plan_bit_for_bit(puma, N, size):
    """Sampled piece by piece, the plan gives exactly the set points of the whole motion."""
    q0, q1 = np.radians(DEFAULT_START_DEG), np.radians(DEFAULT_GOAL_DEG)
    plan = quintic_plan(puma, q0, q1, N)
    pieces = list(plan.chunks(size))
    assert max(p.t.size for p in pieces) <= size and sum(p.t.size for p in pieces) == N
    want = _oracle_quintic(q0, q1, plan.duration, N)
    for name, expected in zip(("t", "q", "qd", "qdd"), want):
        got = np.concatenate([getattr(p, name) for p in pieces])
        assert np.array_equal(got, expected), name
        assert np.array_equal(getattr(plan_quintic(puma, q0, q1, N), name), expected), name
    assert plan.duration == pytest.approx(quintic_duration(puma, q0, q1), rel=0)
