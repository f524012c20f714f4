"""The joint-limit region: its limits, the worst states over it, and the torque scale."""
import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.core.selection.region import (
    channel_values,
    joint_region,
    missing_limits,
    qd_vertices,
    region_scale,
    sample_positions,
    worst_states,
)
from gd_analyze.core.symbolic.base_parameters import base_parameters
from gd_analyze.formulations.pinocchio import pinocchio_model


def _rnea(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def test_region_of_the_robots_limits_and_the_missing_ones():
    robot = load_robot("ur5")                   # +-2 pi: more than a turn is the full circle
    region = joint_region(robot, np.full(6, 3.0))
    assert np.all(region.q_min[[0, 1, 3, 4, 5]] == -np.pi) and region.q_max[2] == np.pi
    assert missing_limits(load_robot("puma560")) == ""
    spec = load_robot("two-link")
    from dataclasses import replace
    assert missing_limits(replace(spec, qd_max=np.array([1.0, np.nan]))) == \
        "joint 2 has no velocity limit"
    with pytest.raises(ValueError, match="joint 2"):
        joint_region(replace(spec, qd_max=np.array([1.0, np.nan])), np.ones(2))
    q = sample_positions(region, 50)
    ok = region.contains(q, np.zeros_like(q), np.zeros_like(q))
    assert ok.all() and not region.contains(q + 10, q * 0, q * 0)[0].all()


def test_worst_states_are_states_of_the_region_and_the_largest_over_the_vertices():
    """At each sampled position, the torque at the state worst_states returns equals its value
    (Pinocchio's rnea), and no vertex of the velocity and acceleration limits gives more."""
    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = sample_positions(region, 20, seed=3)[:20]
    V = channel_values(robot, q, cols)
    value, qd, qdd = worst_states(V, np.tile(base.beta, (3, 1)), region.qd_max, region.qdd_max)
    n = robot.n
    for i in range(n):
        tau = _rnea(robot, q, qd[:, i], qdd[:, i])[:, i]
        np.testing.assert_allclose(np.abs(tau), value[:, i], rtol=1e-9)
    rng = np.random.default_rng(0)
    for _ in range(20):                     # every vertex, not only qd_vertices' half
        sd = rng.choice([-1.0, 1.0], n) * region.qd_max
        sdd = rng.choice([-1.0, 1.0], n) * region.qdd_max
        tau = _rnea(robot, q, np.tile(sd, (20, 1)), np.tile(sdd, (20, 1)))
        assert np.all(np.abs(tau) <= value * (1 + 1e-9))


def test_the_scale_is_reached_where_it_says():
    robot = load_robot("stanford")             # a prismatic joint
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    cols = np.flatnonzero(base.independent.reshape(-1))
    scale, state = region_scale(robot, region, cols, base.beta, samples=200)
    n = robot.n
    tau = _rnea(robot, state[:, :n], state[:, n:2 * n], state[:, 2 * n:])
    np.testing.assert_allclose(np.abs(tau[np.arange(n), np.arange(n)]), scale, rtol=1e-9)
    assert np.all(state[:, :n] >= region.q_min - 1e-12) and np.all(state[:, :n] <= region.q_max)
    assert np.all(np.abs(state[:, n:2 * n]) <= region.qd_max * (1 + 1e-12))
    floor = region_scale(robot, region, cols, base.beta, torque_floor=1e6, samples=20,
                         refine=0)[0]
    assert np.all(floor == 1e6)


def test_the_vertices_are_one_of_each_opposite_pair():
    """Half the box's vertices, one of each pair x, -x: together with their negatives, all."""
    qd_max = np.array([1.0, 2.0, 0.5, 3.0])
    verts = qd_vertices(qd_max)
    both = {tuple(v) for v in np.vstack([verts, -verts])}
    assert len(verts) == 8 and len(both) == 16
    assert both == {tuple(np.array(s) * qd_max) for s in
                    __import__("itertools").product([-1.0, 1.0], repeat=4)}


def test_one_joint_has_one_vertex():
    """One joint: the pair (qd_max, -qd_max) is one vertex, qd_max itself."""
    assert qd_vertices(np.array([1.5])).tolist() == [[1.5]]


@pytest.mark.parametrize("name", ("puma560", "stanford"))
def test_channel_values_engines_agree_and_rebuild_rnea(name):
    """The array code (each part at the states it is read at) and the compiled kernel (every
    part at every state) give the same channels, within 1e-12 of their scale, over several
    chunks; the channels rebuild Pinocchio's rnea at a random state (tau = A qdd + qd^T C qd
    + G)."""
    robot = load_robot(name)
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = sample_positions(region, 30, seed=5)
    V = {e: channel_values(robot, q, cols, chunk=7, engine=e) for e in ("numpy", "compiled")}
    scale = np.abs(V["compiled"]).max()
    assert np.abs(V["numpy"] - V["compiled"]).max() <= 1e-12 * scale
    n = robot.n
    rng = np.random.default_rng(2)
    qd, qdd = rng.uniform(-1, 1, (q.shape[0], n)), rng.uniform(-1, 1, (q.shape[0], n))
    Y = V["numpy"] @ base.beta                                   # (B, C, n)
    tau = Y[:, 0] + np.einsum("bji,bj->bi", Y[:, 1:1 + n], qdd) + np.einsum(
        "bjli,bj,bl->bi", Y[:, 1 + n:].reshape(-1, n, n, n), qd, qd)
    ref = _rnea(robot, q, qd, qdd)
    assert np.abs(tau - ref).max() <= 1e-10 * np.abs(ref).max()
    with pytest.raises(ValueError, match="engine"):
        channel_values(robot, q, cols, engine="fortran")


def _pinocchio_parts(robot, q, qd):
    """Pinocchio's mass matrix M(q), velocity torque h(q, qd) (no gravity) and gravity g(q)."""
    model = pinocchio_model(robot)
    data = model.createData()
    M = np.triu(pin.crba(model, data, q))
    g = pin.computeGeneralizedGravity(model, data, q).copy()
    model.gravity.linear = np.zeros(3)
    h = pin.rnea(model, model.createData(), q, qd, np.zeros(robot.n)).copy()
    return M + np.triu(M, 1).T, h, g


@pytest.mark.parametrize("parts", [(0, 0, 1), (0, 1, 1), (1, 0, 0), (1, 1, 0), (1, 1, 1)])
def test_the_sampled_error_of_dropped_parts_is_pinocchios_largest(parts):
    """Issue 32: a trajectory model's ``region_sampled_error`` by sampling only. Dropping
    whole parts (inertial, velocity, gravity) of every base parameter, the error at a
    position is, by Pinocchio, sum_j |M_ij| qdd_max_j + the largest |h_i + g_i| over every
    vertex of the velocity box; the function gives its largest value over the sampled
    positions relative to s_i, and the state where it says it found it gives that error."""
    import itertools

    from gd_analyze.core.selection.region import region_samples, sampled_error

    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    values = region_samples(robot, base, region, samples=40, seed=5)
    dropped = np.tile(np.array(parts, bool), (base.beta.size, 1))
    error, state = sampled_error(base, region, dropped, values)
    q, scale, n = values[0], values[2], robot.n
    inertial, velocity, gravity = parts
    verts = np.array(list(itertools.product([-1.0, 1.0], repeat=n))) * region.qd_max
    worst = np.zeros(n)
    for x in q:
        M, _, g = _pinocchio_parts(robot, x, np.zeros(n))
        quad = np.array([velocity * _pinocchio_parts(robot, x, v)[1] for v in verts]) + gravity * g
        worst = np.maximum(worst, inertial * np.abs(M) @ region.qdd_max
                           + np.abs(quad).max(axis=0))
    np.testing.assert_allclose(error, worst / scale, rtol=1e-9, atol=1e-12)   # 0: round-off
    for i in range(n):                       # the witness state gives the error it reports
        x, xd, xdd = state[i, :n], state[i, n:2 * n], state[i, 2 * n:]
        M, h, g = _pinocchio_parts(robot, x, xd)
        tau = inertial * M @ xdd + velocity * h + gravity * g
        np.testing.assert_allclose(abs(tau[i]), error[i] * scale[i], rtol=1e-9,
                                   atol=1e-12 * scale[i])
        assert np.all(np.abs(xdd) <= region.qdd_max * (1 + 1e-12))
    full = _rnea(robot, values[3][:, :n], values[3][:, n:2 * n], values[3][:, 2 * n:])
    np.testing.assert_allclose(np.abs(full[np.arange(n), np.arange(n)]), scale, rtol=1e-9)


def test_the_samples_are_those_a_certification_draws():
    """A certification made in the process is read in place of the samples
    (:func:`gd_analyze.workflows.region_memo.region_values`): the same positions, values and
    scale for the same count and seed."""
    from gd_analyze.core.selection.certify import certify
    from gd_analyze.core.selection.region import region_samples

    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    q, V, scale, state = region_samples(robot, base, region, samples=30)
    pb = certify(robot, base, region, max_boxes=2, samples=30)
    assert np.array_equal(pb.positions, q) and np.array_equal(pb.values, V)
    assert np.array_equal(pb.scale, scale) and np.array_equal(pb.scale_state, state)
